"""The browser client's side of the server: its pages, its bundled files and the tables it draws.

The page URLs are fixed so that links can be shared; each answers the same HTML page for every
id (the page's script reads the id from its address and asks the game API for the rest), after
checking what can be checked here: a game's name. Files come from `web/dist`, which
`npm run build` (run by `bash dev.sh serve|test`) fills; aiohttp serves a precompressed `.gz`
beside a file when the browser accepts gzip. A server started without the build still serves
the API and answers every page with a 503 that says how to build it.

`GET /web/tables` gives the geometry of each game's table (cushion noses, jaws, pockets, the
ball radius and the marked spots) from `physics.tables` and `rules.spots`, so the client draws
exactly the table the engine simulates.
"""

from __future__ import annotations

import mimetypes
from pathlib import Path

from aiohttp import web
from pydantic import BaseModel, ConfigDict

from rules.racks import Game
from rules.racks import table as rules_table
from rules.spots import BAULK_Y, D_RADIUS, SNOOKER_SPOTS, STANDARD_SIZE, Point, Table
from server.protocol.ids import GAMES, TABLE_SIZES

#: Where `npm run build` writes the client.
DIST = Path(__file__).resolve().parents[2] / "web" / "dist"  # server/http/ -> the root


#: Each page URL and the HTML file that answers it.
PAGES: dict[str, str] = {
    "/": "home.html",
    "/practice/{game}": "play.html",
    "/table/{id}": "play.html",
    "/replay/{id}": "replay.html",
    "/leaderboard/{game}": "leaderboard.html",
    "/player/{name}": "player.html",
    "/diagrams": "diagrams.html",
}

mimetypes.add_type("application/manifest+json", ".webmanifest")

#: Files are rebuilt in place, so browsers revalidate (Last-Modified) instead of guessing.
NO_CACHE = {"Cache-Control": "no-cache"}


class Cushion(BaseModel):
    """A straight cushion nose from p1 to p2; `normal` points into the table."""

    model_config = ConfigDict(frozen=True)

    name: str
    p1: Point
    p2: Point
    normal: Point


class Circle(BaseModel):
    """A jaw (rounded rail end) or a pocket's capture circle."""

    model_config = ConfigDict(frozen=True)

    name: str
    center: Point
    radius: float


class TableGeometry(BaseModel):
    """What the client needs to draw one game's table, in the engine's coordinates (metres).

    spots: the marked spots by name (pool's head and foot spots, snooker's colour spots, the
    carom spots). baulk_y / d_radius: snooker's baulk line and D, None on the other tables.
    head_string_y: pool's head string (the kitchen's edge), None elsewhere. size: the table's
    size in feet (pool; the others are at the standard 9). sizes: pool's other table sizes,
    each drawn as its own table (the client picks a table's by its `options.size`).
    """

    model_config = ConfigDict(frozen=True)

    game: str
    w: float
    l: float
    R: float
    cushion_height: float
    cushions: tuple[Cushion, ...]
    jaws: tuple[Circle, ...]
    pockets: tuple[Circle, ...]
    spots: dict[str, Point]
    baulk_y: float | None = None
    d_radius: float | None = None
    head_string_y: float | None = None
    size: int = STANDARD_SIZE
    sizes: dict[int, TableGeometry] = {}


def table_geometry(game: str, size: int = STANDARD_SIZE) -> TableGeometry:
    """The drawable table of `game` at `size`, built from the rules' table and the engine's
    geometry; at the standard size with the game's other sizes beside it."""
    table: Table = rules_table(Game(game), size)
    geometry = table.spec.geometry()
    snooker = table.preset == "snooker"
    pool = game in ("nineball", "eightball")
    spots = dict(SNOOKER_SPOTS) if snooker else {"head": table.head_spot, "foot": table.foot_spot}
    return TableGeometry(
        game=game,
        w=table.width,
        l=table.length,
        R=table.R,
        cushion_height=table.spec.cushion_height,
        cushions=tuple(
            Cushion(name=s.name, p1=s.p1, p2=s.p2, normal=s.normal) for s in geometry.segments
        ),
        jaws=tuple(Circle(name=j.name, center=j.center, radius=j.radius) for j in geometry.jaws),
        pockets=tuple(
            Circle(name=p.name, center=p.center, radius=p.radius) for p in geometry.pockets
        ),
        spots=spots,
        baulk_y=BAULK_Y if snooker else None,
        d_radius=D_RADIUS if snooker else None,
        head_string_y=table.head_string if pool else None,
        size=size,
        sizes={
            other: table_geometry(game, other)
            for other in (TABLE_SIZES if pool and size == STANDARD_SIZE else ())
            if other != size
        },
    )


#: The tables never change while the server runs: built once, at import.
TABLES_JSON = "{" + ",".join(f'"{g}":{table_geometry(g).model_dump_json()}' for g in GAMES) + "}"


async def tables(_: web.Request) -> web.Response:
    return web.Response(text=TABLES_JSON, content_type="application/json", headers=NO_CACHE)


def page_handler(filename: str):
    """The handler of one page URL: its HTML file, once the game in the URL (if any) is known."""

    async def handler(request: web.Request) -> web.StreamResponse:
        game = request.match_info.get("game")
        if game is not None and game not in GAMES:
            raise web.HTTPNotFound(
                text=f"unknown game {game!r}; the games are {', '.join(GAMES)}",
            )
        path = DIST / filename
        if not path.is_file():
            raise web.HTTPServiceUnavailable(
                text="the web client is not built: run `bash dev.sh serve` (or `npm ci && "
                "npm run build` in web/)",
            )
        return web.FileResponse(path, headers=NO_CACHE)

    return handler


async def static_file(request: web.Request) -> web.StreamResponse:
    """A built file under /static/ (never outside DIST; .gz siblings are served, not listed)."""
    name = request.match_info["path"]
    try:  # a NUL byte or an over-long name is no file either, not a server error
        path = (DIST / name).resolve()
        found = path.is_relative_to(DIST) and path.is_file() and path.suffix != ".gz"
    except (ValueError, OSError):
        found = False
    if not found:
        raise web.HTTPNotFound()
    return web.FileResponse(path, headers=NO_CACHE)


async def service_worker(_: web.Request) -> web.StreamResponse:
    """`/sw.js`, from the root so that its scope is the whole site (web/src/sw.js)."""
    path = DIST / "sw.js"
    if not path.is_file():
        raise web.HTTPNotFound()
    return web.FileResponse(path, headers=NO_CACHE)


async def short_link(request: web.Request) -> web.StreamResponse:
    """`/t/{id}`, the short private link of docs/protocol.md: the table's page."""
    raise web.HTTPFound(f"/table/{request.match_info['id']}")


def mount_web(app: web.Application) -> None:
    """Add the client's pages, files and table geometry to the app (and the diagrams' data)."""
    from server.http.diagrams import mount_diagrams

    for url, filename in PAGES.items():
        app.router.add_get(url, page_handler(filename))
    app.router.add_get("/t/{id:[0-9a-f]{1,64}}", short_link)
    app.router.add_get("/static/{path:.+}", static_file)
    app.router.add_get("/sw.js", service_worker)
    app.router.add_get("/web/tables", tables)
    mount_diagrams(app)
