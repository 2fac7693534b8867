// Bundles the client into dist/: one ES module per page (shared code split into chunks), the
// pages' HTML and CSS, and a .gz beside every file for aiohttp to serve precompressed.
// Run by `bash dev.sh serve|test` through `npm run build`; the output is not committed.
import { build } from "esbuild";
import { cpSync, mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { gzipSync } from "node:zlib";

const here = new URL(".", import.meta.url).pathname;
const out = join(here, "dist");
const pages = ["home", "play", "replay", "leaderboard", "diagrams"];

rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
await build({
  entryPoints: pages.map((p) => join(here, "src", "pages", `${p}.js`)),
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
console.log(`web/dist: ${pages.length} pages, ${(total / 1024).toFixed(1)} KiB gzipped in all`);
