// Bundles the client into dist/: one ES module per page (shared code split into chunks), each
// page's HTML (pages/layout.html around pages/NAME.html), the CSS, and a .gz beside every file
// for aiohttp to serve precompressed.
// Run by `bash dev.sh serve|test` through `npm run build`; the output is not committed.
import { build } from "esbuild";
import { cpSync, mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { deflateSync, gzipSync } from "node:zlib";

const here = new URL(".", import.meta.url).pathname;
const out = join(here, "dist");
/** Each page: its title, body class and extra head lines. */
const pages = {
  home: { title: "billiards" },
  play: { title: "billiards: table", body: "play-page" },
  replay: { title: "billiards: replay", body: "play-page" },
  leaderboard: { title: "billiards: leaderboard" },
  diagrams: { title: "billiards: physics diagrams", head: '<link rel="stylesheet" href="/static/uPlot.min.css">' },
  player: { title: "billiards: player", head: '<link rel="stylesheet" href="/static/uPlot.min.css">' },
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
// The service worker is served from the root (its scope is the whole site), as written.
cpSync(join(here, "src", "sw.js"), join(out, "sw.js"));
for (const [name, size, bleed] of [["icon-192", 192, false], ["icon-512", 512, false], ["icon-maskable-512", 512, true]]) {
  writeFileSync(join(out, `${name}.png`), tableIcon(size, bleed));
}

/** The app's icon, drawn from the table: felt in its rail, the cue ball and a red. A maskable
 * icon fills its square (the system may cut any shape from the middle 80%). */
function tableIcon(size, bleed) {
  const rgb = new Uint8Array(size * size * 3);
  const paint = (inside, colour) => {
    for (let y = 0; y < size; y++) {
      for (let x = 0; x < size; x++) {
        if (inside((x + 0.5) / size, (y + 0.5) / size)) rgb.set(colour, (y * size + x) * 3);
      }
    }
  };
  const box = (m, r) => (u, v) => {
    const dx = Math.max(m + r - u, 0, u - (1 - m - r)), dy = Math.max(m + r - v, 0, v - (1 - m - r));
    return u >= m && u <= 1 - m && v >= m && v <= 1 - m && dx * dx + dy * dy <= r * r;
  };
  const ball = (cx, cy, r) => (u, v) => (u - cx) ** 2 + (v - cy) ** 2 <= r * r;
  const inset = bleed ? 0.1 : 0;
  paint(() => true, [11, 61, 42]);
  paint(box(inset + 0.04, 0.12), [92, 51, 23]);
  paint(box(inset + 0.12, 0.06), [23, 120, 66]);
  paint(ball(0.38, 0.6, 0.11 - inset / 4), [245, 243, 235]);
  paint(ball(0.64, 0.4, 0.11 - inset / 4), [200, 30, 35]);
  return png(size, rgb);
}

/** A PNG of 8-bit RGB pixels (one IDAT, deflated by zlib). */
function png(size, rgb) {
  const rows = Buffer.alloc(size * (size * 3 + 1));
  for (let y = 0; y < size; y++) Buffer.from(rgb.buffer, y * size * 3, size * 3).copy(rows, y * (size * 3 + 1) + 1);
  const chunk = (type, data) => {
    const head = Buffer.alloc(8);
    head.writeUInt32BE(data.length, 0);
    head.write(type, 4, "ascii");
    const tail = Buffer.alloc(4);
    tail.writeUInt32BE(crc32(Buffer.concat([head.subarray(4), data])), 0);
    return Buffer.concat([head, data, tail]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(size, 0);
  ihdr.writeUInt32BE(size, 4);
  ihdr.set([8, 2, 0, 0, 0], 8);
  const signature = Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]);
  return Buffer.concat([signature, chunk("IHDR", ihdr), chunk("IDAT", deflateSync(rows)), chunk("IEND", Buffer.alloc(0))]);
}

function crc32(bytes) {
  let crc = ~0;
  for (const byte of bytes) {
    crc ^= byte;
    for (let k = 0; k < 8; k++) crc = (crc >>> 1) ^ (0xedb88320 & -(crc & 1));
  }
  return ~crc >>> 0;
}

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
