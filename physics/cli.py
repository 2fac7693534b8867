"""`billiards simulate [SCENE.json|-]`: simulate one scene and print the result as JSON."""

from __future__ import annotations

import argparse
import json
import sys


def register(sub: argparse._SubParsersAction) -> None:
    cmd = sub.add_parser("simulate", help="simulate one shot from a scene file and print JSON")
    cmd.add_argument("scene", nargs="?", default="-", help="scene JSON file, or - for stdin")
    cmd.add_argument(
        "--example",
        choices=["nineball_break", "snooker_break_off", "fifteen_ball_break"],
        help="simulate a built-in example scene instead of reading one",
    )
    cmd.add_argument("--indent", type=int, default=None, help="pretty-print with this indent")
    cmd.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from physics import SceneError, simulate_scene
    from physics.examples import BREAKS

    try:
        if args.example:
            scene = BREAKS[args.example]()
        elif args.scene == "-":
            scene = json.load(sys.stdin)
        else:
            with open(args.scene, encoding="utf-8") as fh:
                scene = json.load(fh)
        result = simulate_scene(scene)
    except (OSError, json.JSONDecodeError, SceneError) as exc:
        print(f"billiards simulate: {exc}", file=sys.stderr)
        return 2
    json.dump(result, sys.stdout, indent=args.indent)
    sys.stdout.write("\n")
    return 0
