"""`billiards serve`: run the server (relay and game service) until interrupted.

Tokens must outlive a restart (a player's token is its identity), so the signing key is read
from the environment variable `BILLIARDS_RELAY_SECRET` or, without Redis, kept in a key file
only the server's user can read (`--key-file`, by default the database path plus `.key`;
created 0600 on first run and checked at every start: server/storage/signing_key.py, which
also says how to rotate it). Replicas sharing one Redis must check each other's tokens, so
they share the key through the environment variable.

The server runs on asyncio's own event loop. (A `--uvloop` option ran it on uvloop's; measured
in bench/relay.py it saved nothing worth a second loop to test, docs/operations.md, so it went.)

The process's garbage collector follows `server.http.collector` (its docstring says why).
"""

from __future__ import annotations

import argparse
import ipaddress
import os
from pathlib import Path


def _serve(args: argparse.Namespace) -> int:
    from aiohttp import web

    from server.http import collector
    from server.http.app import AppSettings, create_app, relay_settings
    from server.storage.signing_key import signing_key

    secret = os.environ.get("BILLIARDS_RELAY_SECRET")
    if secret is None and args.redis is None:
        secret = signing_key(Path(args.key_file or f"{args.db}.key"), Path(args.db))
    relay = relay_settings(
        auth_secret=secret,
        trusted_proxies=args.trusted_proxy,
        max_connections_per_address=args.max_connections_per_address,
    )
    optional = {"grace": args.grace, "names_per_address": args.names_per_address}
    settings = AppSettings(
        relay=relay,
        redis_url=args.redis,
        database=args.db,
        workers=args.workers,
        **{name: value for name, value in optional.items() if value is not None},
    )
    app = create_app(settings)
    collector.install(app)
    web.run_app(app, host=args.host, port=args.port)
    return 0


def _network(text: str) -> str:
    try:
        ipaddress.ip_network(text, strict=False)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return text


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("serve", help="run the game server and its message relay")
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on")
    parser.add_argument("--port", type=int, default=8080, help="TCP port")
    parser.add_argument("--redis", metavar="URL", help="Redis URL (default: in-memory relay)")
    parser.add_argument(
        "--db", default="billiards.sqlite3", help="SQLite file of the game (without --redis)"
    )
    parser.add_argument(
        "--key-file", help="the token signing key, mode 0600 (default: the --db path + .key)"
    )
    parser.add_argument(
        "--workers",
        type=int,
        help="simulation processes, and as many for the bots (default: one per core)",
    )
    parser.add_argument(
        "--grace",
        type=float,
        metavar="SECONDS",
        help="how long a disconnected player may stay away before the opponent may claim the "
        "win (default: server.game.tables.GRACE)",
    )
    parser.add_argument(
        "--names-per-address",
        type=int,
        metavar="N",
        help="guest names one client address may hold (default: server.game.service."
        "NAMES_PER_ADDRESS)",
    )
    parser.add_argument(
        "--trusted-proxy",
        action="append",
        default=[],
        type=_network,
        metavar="CIDR",
        help="a load balancer whose X-Forwarded-For names the client (repeatable; an address "
        "or a block such as 172.28.0.0/16)",
    )
    parser.add_argument(
        "--max-connections-per-address",
        type=int,
        metavar="N",
        help="subscriber connections one client address may hold (default: no cap)",
    )
    parser.set_defaults(func=_serve)
