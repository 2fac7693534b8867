"""server/http/pages.py: the page URLs, the built files and the tables' geometry."""

from __future__ import annotations

import gzip

import pytest

from physics.tables import PRESETS
from server.http import pages as web_module
from server.http.pages import GAMES, mount_web, table_geometry


@pytest.fixture
def dist(tmp_path, monkeypatch):
    """A stand-in build: one HTML file per page kind, a script and its .gz."""
    for name in ("home", "play", "replay", "leaderboard", "diagrams", "player"):
        (tmp_path / f"{name}.html").write_text(f"<!doctype html><title>{name}</title>")
    (tmp_path / "play.js").write_text("export const x = 1;")
    (tmp_path / "play.js.gz").write_bytes(gzip.compress(b"export const x = 1;"))
    monkeypatch.setattr(web_module, "DIST", tmp_path)
    return tmp_path


@pytest.fixture
async def client(serve):
    return await serve(mount_web)


@pytest.mark.parametrize(
    "path, page",
    [
        ("/", "home"),
        ("/practice/snooker", "play"),
        ("/table/0123456789abcdef0123", "play"),
        ("/t/0123456789abcdef0123", "play"),
        ("/replay/abc", "replay"),
        ("/leaderboard/three_cushion", "leaderboard"),
        ("/diagrams", "diagrams"),
        ("/player/Ada Lovelace", "player"),
    ],
)
async def test_each_page_url_answers_its_page(client, dist, path, page):
    response = await client.get(path)
    assert response.status == 200
    assert f"<title>{page}</title>" in await response.text()


@pytest.mark.parametrize("path", ["/practice/pyramid", "/leaderboard/darts"])
async def test_an_unknown_game_is_not_found(client, dist, path):
    response = await client.get(path)
    assert response.status == 404
    assert "nineball" in await response.text()


async def test_files_are_served_gzipped_when_accepted(client, dist):
    response = await client.get("/static/play.js", headers={"Accept-Encoding": "gzip"})
    assert response.status == 200
    assert response.headers["Content-Encoding"] == "gzip"
    assert await response.text() == "export const x = 1;"


@pytest.mark.parametrize(
    "path",
    [
        "/static/../pyproject.toml",
        "/static/%2e%2e/x",
        "/static/nothing.js",
        "/static/a%00b",  # no file name holds a NUL byte
        "/static/" + "x" * 300,  # nor is longer than the file system allows
    ],
)
async def test_nothing_outside_the_build_is_served(client, dist, path):
    assert (await client.get(path)).status == 404


async def test_without_a_build_pages_say_how_to_build(client, tmp_path, monkeypatch):
    monkeypatch.setattr(web_module, "DIST", tmp_path / "missing")
    response = await client.get("/")
    assert response.status == 503
    assert "dev.sh" in await response.text()


async def test_tables_are_the_engines_geometry(client):
    response = await client.get("/web/tables")
    tables = await response.json()
    assert set(tables) == set(GAMES)
    for game, t in tables.items():
        spec, params = PRESETS["nineball" if game == "eightball" else game]
        assert (t["w"], t["l"], t["R"]) == (spec.w, spec.l, params.R)
        geometry = spec.geometry()
        assert len(t["cushions"]) == len(geometry.segments)
        assert [p["center"] for p in t["pockets"]] == [list(p.center) for p in geometry.pockets]
    assert tables["three_cushion"]["pockets"] == []
    assert tables["snooker"]["baulk_y"] < tables["snooker"]["l"] / 2
    assert set(tables["snooker"]["spots"]) == {"yellow", "green", "brown", "blue", "pink", "black"}
    assert table_geometry("eightball").head_string_y == pytest.approx(tables["eightball"]["l"] / 4)
