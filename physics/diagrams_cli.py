"""`billiards diagrams OUTDIR`: write the PNG figures of the physics models."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


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
    from physics.diagrams import write_all

    rows = json.loads(args.accuracy.read_text()) if args.accuracy else None
    for path in write_all(args.outdir, rows):
        print(path)
    return 0
