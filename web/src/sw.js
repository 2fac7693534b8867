// The service worker, served from the site's root (/sw.js) so that its scope is every page.
// Pages and their files load from the network when it answers (the server rebuilds them in
// place) and from the cache when it does not, so an installed game opens offline; the game
// itself needs the server, which the pages say when their requests fail. The API, the relay
// and the diagrams' data are never cached: they are the game, not its files.
const CACHE = "billiards-v1";
const SHELL = ["/", "/static/style.css", "/static/home.js", "/static/manifest.webmanifest"];
const OFFLINE = `<!doctype html><meta charset="utf-8"><meta name="viewport" content="width=device-width">
<title>billiards: offline</title><link rel="stylesheet" href="/static/style.css">
<main class="page"><div class="card"><h2>The server cannot be reached</h2>
<p>billiards needs its server to play: every shot is refereed there. Check the connection and reload.</p></div></main>`;

self.addEventListener("install", (event) => {
  event.waitUntil(caches.open(CACHE).then((cache) => cache.addAll(SHELL)).then(() => self.skipWaiting()));
});

self.addEventListener("activate", (event) => {
  event.waitUntil(
    caches
      .keys()
      .then((names) => Promise.all(names.filter((name) => name !== CACHE).map((name) => caches.delete(name))))
      .then(() => self.clients.claim()),
  );
});

/** Only the site's own pages and files: never the API, the relay or other origins. */
function cacheable(request) {
  const url = new URL(request.url);
  if (request.method !== "GET" || url.origin !== self.location.origin) return false;
  return !/^\/(api|sub|pub|diagrams\/|web\/)/.test(url.pathname);
}

async function networkFirst(request) {
  const cache = await caches.open(CACHE);
  try {
    const response = await fetch(request);
    if (response.ok) cache.put(request, response.clone());
    return response;
  } catch (error) {
    const cached = await cache.match(request, { ignoreSearch: true });
    if (cached) return cached;
    if (request.mode === "navigate") {
      return new Response(OFFLINE, { status: 503, headers: { "Content-Type": "text/html; charset=utf-8" } });
    }
    throw error;
  }
}

self.addEventListener("fetch", (event) => {
  if (cacheable(event.request)) event.respondWith(networkFirst(event.request));
});
