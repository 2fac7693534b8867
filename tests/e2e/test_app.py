"""The game as an app a phone can keep: every page links the web app manifest, whose icons
are there; the service worker registers from the site's root with the whole site as its
scope; and offline, a page that was opened before comes from the cache while a new one says
that the game needs its server, instead of a blank page."""

from __future__ import annotations

import json
import struct
import urllib.request

from tests.e2e.conftest import screenshot

PAGES = ("/", "/practice/nineball", "/leaderboard/snooker", "/diagrams")


def fetch(url: str) -> tuple[str, bytes]:
    with urllib.request.urlopen(url) as response:
        return response.headers["Content-Type"], response.read()


def test_every_page_links_the_manifest_and_its_icons_are_drawn(server, open_page) -> None:
    page = open_page("/")
    for path in PAGES:
        page.goto(server.url + path)
        assert page.get_attribute("link[rel=manifest]", "href") == "/static/manifest.webmanifest"
    kind, body = fetch(server.url + "/static/manifest.webmanifest")
    manifest = json.loads(body)
    assert kind.startswith("application/manifest+json")
    assert manifest["start_url"] == "/" and manifest["display"] == "standalone"
    purposes = {icon["purpose"] for icon in manifest["icons"]}
    assert purposes == {"any", "maskable"}
    for icon in manifest["icons"]:
        kind, png = fetch(server.url + icon["src"])
        width, height = struct.unpack(">II", png[16:24])
        assert kind == "image/png" and png[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"{width}x{height}" == icon["sizes"]


def test_the_service_worker_serves_the_site_and_says_when_the_server_is_gone(
    server, open_page, console
) -> None:
    page = open_page("/", service_workers="allow")
    scope = page.evaluate("async () => (await navigator.serviceWorker.ready).scope")
    assert scope == server.url + "/"
    page.wait_for_function("() => navigator.serviceWorker.controller !== null")
    page.reload()  # through the worker now: the home page and its files are cached
    page.wait_for_selector("#games .card")
    expected = len(console.errors)  # offline, every request to the server fails, as it should
    page.context.set_offline(True)
    try:
        page.reload()
        page.wait_for_selector("#games .card")  # the cached page, drawn offline
        page.goto(server.url + "/leaderboard/eightball")  # never opened: nothing cached
        assert "needs its server" in page.inner_text("main")
        screenshot(page, "offline")
    finally:
        page.context.set_offline(False)
        del console.errors[expected:]
