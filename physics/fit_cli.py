"""`billiards fit SHOTS.json`: fit each recorded shot's strike, report how well the engine
reproduces it; with `--fit-constants OUT.json`, fit the table's constants too.

scipy is an optional extra (`pip install 'billiards[fit]'`); without it this command says so
in one line and exits with status 2. Progress goes to standard error, the report (a table, or
one JSON object with `--json`) to standard output.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

#: What the command says when scipy is not installed.
MISSING = "billiards fit: needs scipy; install it with: pip install 'billiards[fit]'"

#: The models' choices as `--models` takes them (physics.scene.Models).
MODEL_CHOICES = {
    "cushion": ("mathavan", "han"),
    "ball_ball": ("alciatore", "frictionless"),
    "spin": ("on", "off"),
}


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "fit", help="fit recorded shots' strikes (and the table's constants) to the engine"
    )
    parser.add_argument("shots", type=Path, help="recorded shots (JSON, docs/physics.md)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--models",
        nargs="*",
        default=[],
        metavar="KEY=VALUE",
        help="model choices: cushion=mathavan|han ball_ball=alciatore|frictionless spin=on|off",
    )
    parser.add_argument(
        "--constants", type=Path, help="JSON of constants (Params fields, cushion_height)"
    )
    parser.add_argument(
        "--fit-constants",
        type=Path,
        metavar="OUT",
        help="fit the shared constants with cross-validation and write them to OUT",
    )
    parser.add_argument("--folds", type=int, default=2, help="cross-validation folds (2)")
    parser.add_argument("--workers", type=int, default=None, help="processes (every core)")
    parser.set_defaults(func=run)


def parse_models(items: list[str]) -> dict[str, Any]:
    """`--models` items as the scene's `models` object; ValueError names a bad one."""
    models: dict[str, Any] = {}
    for item in items:
        key, _, value = item.partition("=")
        if value not in MODEL_CHOICES.get(key, ()):
            raise ValueError(f"--models {item}: expected one of {_choices()}")
        models[key] = value == "on" if key == "spin" else value
    return models


def _choices() -> str:
    return " ".join(f"{k}={'|'.join(v)}" for k, v in MODEL_CHOICES.items())


def run(args: argparse.Namespace) -> int:
    try:
        import scipy  # noqa: F401
    except ModuleNotFoundError:
        print(MISSING, file=sys.stderr)
        return 2
    from physics import ENGINE_VERSION
    from physics.fit import Problem
    from physics.fit_batch import process_pool, stderr_progress, timed_fit
    from physics.recorded import load

    try:
        models = parse_models(args.models)
        recs = load(args.shots)
        constants = json.loads(args.constants.read_text()) if args.constants else {}
        if not recs:
            raise ValueError(f"no shots in {args.shots}")
        Problem.build(recs[0], constants, models)  # a bad constant or model fails here, once
    except (OSError, ValueError, KeyError, TypeError) as exc:
        print(f"billiards fit: {exc}", file=sys.stderr)
        return 2
    with process_pool(args.workers) as pool:
        if args.fit_constants:
            from physics.fit_constants import cross_validate

            report = cross_validate(recs, models, args.folds, pool, args.fit_constants)
        else:
            report = timed_fit(recs, constants, models, pool, stderr_progress)
            report["constants"] = constants
    report["models"] = models
    report["engine_version"] = ENGINE_VERSION
    if args.json:
        json.dump(report, sys.stdout)
        sys.stdout.write("\n")
    else:
        print_table(report)
    return 0


def print_table(report: dict[str, Any]) -> None:
    """The report as a table: one row per shot, then the figures."""
    print(f"{'shot':>5} {'cue cm':>7} {'all cm':>7} {'sims':>6} {'s':>5}  strike")
    for row in report["shots"]:
        s = row["strike"]
        strike = (
            f"heading {s['heading']:.2f} speed {s['speed']:.3f} a {s['a']:+.3f} "
            f"b {s['b']:+.3f} t0 {s['t0']:.3f}"
        )
        print(
            f"{row['id']:>5} {row['rmse_cm']:7.1f} {row['rmse_all_cm']:7.1f} "
            f"{row['simulations']:6d} {row['seconds']:5.1f}  {strike}"
        )
    for key, value in report.items():
        if key != "shots":
            print(f"{key}: {value}")
