"""`billiards diagrams OUTDIR`: write the PNG figures of the physics models.

matplotlib is an optional extra (`pip install 'billiards[diagrams]'`) that nothing else needs;
without it this command says so in one line and exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

#: What the command says when matplotlib is not installed.
MISSING = "billiards diagrams: needs matplotlib; install it with: pip install 'billiards[diagrams]'"


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "diagrams",
        help="write PNG figures of the physics models (throw, cushion, motion, speed vs error)",
    )
    parser.add_argument("outdir", type=Path, help="directory for the PNG files")
    parser.add_argument(
        "--accuracy",
        type=Path,
        metavar="JSON",
        help="speed-vs-error rows saved by `bench/accuracy.py --json`; without it they are "
        "measured now with dt >= 5e-5 s (a minute or two)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from physics.diagrams import write_all
    except ModuleNotFoundError as exc:
        if exc.name != "matplotlib":
            raise
        print(MISSING, file=sys.stderr)
        return 2

    rows = json.loads(args.accuracy.read_text()) if args.accuracy else None
    for path in write_all(args.outdir, rows):
        print(path)
    return 0
