"""`billiards simulate [SCENE.json|-]`: simulate one scene and print the result as JSON.

Every input that is not a valid scene, and every shot the engine abandons (its budget,
physics.engine), ends with one line on stderr and exit status 2; never a traceback.
"""

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


def _read(path: str) -> bytes:
    """The document's bytes, at most one more than a scene may have (so too long is seen)."""
    from physics.scene import MAX_SCENE_BYTES

    if path == "-":
        return sys.stdin.buffer.read(MAX_SCENE_BYTES + 1)
    with open(path, "rb") as fh:
        return fh.read(MAX_SCENE_BYTES + 1)


def run(args: argparse.Namespace) -> int:
    from physics import SceneError, SimulationError, scene_from_json, simulate_scene
    from physics.examples import BREAKS

    try:
        scene = BREAKS[args.example]() if args.example else scene_from_json(_read(args.scene))
        result = simulate_scene(scene)
    except OSError as exc:
        print(f"billiards simulate: {exc.strerror or exc}: {args.scene}", file=sys.stderr)
        return 2
    except (SceneError, SimulationError) as exc:
        print(f"billiards simulate: {exc}", file=sys.stderr)
        return 2
    json.dump(result, sys.stdout, indent=args.indent)
    sys.stdout.write("\n")
    return 0
