// Bundles the client into dist/: one ES module per page (shared code split into chunks), each
// page's HTML (pages/layout.html around pages/NAME.html), the CSS, and a .gz beside every file
// for aiohttp to serve precompressed.
// Run by `bash dev.sh serve|test` through `npm run build`; the output is not committed.
import { build } from "esbuild";
import { cpSync, mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { gzipSync } from "node:zlib";

const here = new URL(".", import.meta.url).pathname;
const out = join(here, "dist");
/** Each page: its title, body class and extra head lines. */
const pages = {
  home: { title: "billiards" },
  play: { title: "billiards: table", body: "play-page" },
  replay: { title: "billiards: replay", body: "play-page" },
  leaderboard: { title: "billiards: leaderboard" },
  diagrams: { title: "billiards: physics diagrams", head: '<link rel="stylesheet" href="/static/uPlot.min.css">' },
};

rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
await build({
  entryPoints: Object.keys(pages).map((p) => join(here, "src", "pages", `${p}.js`)),
  bundle: true,
  splitting: true,
  format: "esm",
  minify: true,
  target: "es2020",
  outdir: out,
  chunkNames: "chunk-[hash]",
  legalComments: "none",
  logLevel: "warning",
});
cpSync(join(here, "static"), out, { recursive: true });
const layout = readFileSync(join(here, "pages", "layout.html"), "utf8");
for (const [page, { title, body = "", head = "" }] of Object.entries(pages)) {
  const fill = { title, body, head, page, main: readFileSync(join(here, "pages", `${page}.html`), "utf8").trim() };
  writeFileSync(join(out, `${page}.html`), layout.replace(/{{(\w+)}}/g, (_, key) => fill[key]));
}
cpSync(join(here, "node_modules", "uplot", "dist", "uPlot.min.css"), join(out, "uPlot.min.css"));

function walk(dir) {
  return readdirSync(dir).flatMap((name) => {
    const path = join(dir, name);
    return statSync(path).isDirectory() ? walk(path) : [path];
  });
}
let total = 0;
for (const file of walk(out)) {
  const gz = gzipSync(readFileSync(file), { level: 9 });
  writeFileSync(`${file}.gz`, gz);
  total += gz.length;
}
console.log(`web/dist: ${Object.keys(pages).length} pages, ${(total / 1024).toFixed(1)} KiB gzipped in all`);
