"""The `billiards` command: one subcommand per capability, each registered by its own package.

Each module in REGISTRARS has `register(subparsers)`, which adds its subcommands and sets
`func` on them; heavy imports happen inside the handlers so that `billiards simulate` does not
pay for the web server.
"""

from __future__ import annotations

import argparse
import importlib
import sys

REGISTRARS = (
    "physics.cli",
    "server.http.serve",
    "server.client.play",
    "rules.cli",
    "physics.diagrams_cli",
    "physics.fit_cli",
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="billiards", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name in REGISTRARS:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return int(args.func(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
