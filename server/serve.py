"""`billiards serve`: run the server (relay included) until interrupted.

Replicas sharing one Redis must check each other's publish tokens, so they share the HMAC key,
read from the environment variable `BILLIARDS_RELAY_SECRET` (a random key per process if unset).
"""

from __future__ import annotations

import argparse
import os


def _serve(args: argparse.Namespace) -> int:
    from aiohttp import web

    from server.app import AppSettings, create_app
    from server.relay.settings import RelaySettings

    relay = RelaySettings(auth_secret=os.environ.get("BILLIARDS_RELAY_SECRET"))
    app = create_app(AppSettings(relay=relay, redis_url=args.redis))
    web.run_app(app, host=args.host, port=args.port)
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("serve", help="run the game server and its message relay")
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on")
    parser.add_argument("--port", type=int, default=8080, help="TCP port")
    parser.add_argument("--redis", metavar="URL", help="Redis URL (default: in-memory relay)")
    parser.set_defaults(func=_serve)
