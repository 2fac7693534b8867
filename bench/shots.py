"""Time the event engine on the breaks: events, median wall time, and the first call.

    .venv/bin/python bench/shots.py [--repeat N] [--pooltool-python PY]

With --pooltool-python (e.g. a venv made by `python3 -m venv /tmp/pt && /tmp/pt/bin/pip
install pooltool-billiards`) it also times pooltool's own nine-ball break in the same run.

The first-call time is measured in a fresh interpreter (import, then one shot), so it shows
any warm-up or JIT cost a server would pay on its first request. Also shown: what the cheaper
model choices save ("models" key of the scene format) and how much the trajectory output
weighs in msgpack.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from physics import parse_scene, simulate
from physics.engine import Simulation
from physics.examples import BREAKS

FIRST_CALL = """
import time, sys
t0 = time.perf_counter()
from physics import simulate
from physics.examples import BREAKS
t1 = time.perf_counter()
simulate(BREAKS[sys.argv[1]]())
t2 = time.perf_counter()
print(t1 - t0, t2 - t1)
"""

#: The same kind of shot in pooltool (ekiefl/pooltool, a numba event engine), run with another
#: interpreter that has it installed: its own nine-ball rack and table, cue ball at 8 m/s into
#: the 1 with a little follow. Prints: first call (s), median (s), events.
POOLTOOL = """
import statistics, sys, time
import pooltool as pt

def shot():
    table = pt.Table.from_game_type(pt.GameType.NINEBALL)
    system = pt.System(
        table=table, balls=pt.get_rack(pt.GameType.NINEBALL, table), cue=pt.Cue(cue_ball_id="cue")
    )
    system.strike(V0=float(sys.argv[1]), phi=pt.aim.at_ball(system, "1"), b=0.1)
    return system

times = []
for _ in range(int(sys.argv[2]) + 1):
    system = shot()
    t0 = time.perf_counter()
    pt.simulate(system, inplace=True)
    times.append(time.perf_counter() - t0)
print(times[0], statistics.median(times[1:]), len(system.events))
"""

VARIANTS = {
    "default": {},
    "frictionless balls": {"ball_ball": "frictionless"},
    "han cushion": {"cushion": "han"},
    "no spin": {"spin": False},
}


def median_ms(scene, repeat: int) -> float:
    parsed = parse_scene(scene)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        simulate(parsed)
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def first_call(name: str) -> tuple[float, float]:
    out = subprocess.run(
        [sys.executable, "-c", FIRST_CALL, name],
        capture_output=True,
        text=True,
        check=True,
        cwd=Path(__file__).resolve().parent.parent,
    ).stdout.split()
    return 1e3 * float(out[0]), 1e3 * float(out[1])


def savings(repeat: int) -> None:
    """What modelling only what a scene needs saves, on scenes built to isolate each point."""
    R = 0.028575
    roll = {"cue": {"v": [0.0, 2.0], "w": [-2.0 / R, 0.0, 0.0]}}
    alone = {"table": "nineball", "balls": {"cue": [0.3, 0.3]}, "initial": roll}
    parked = {f"p{k}": [1.0, 0.3 + 0.15 * k] for k in range(14)}  # in a row, off its path
    crowd = alone | {"balls": alone["balls"] | parked}
    carom_dims = {"w": 1.27, "l": 2.54, "pockets": False, "cushion_height": 0.0363}
    rows = [
        ("1 ball rolling, table empty", alone),
        ("... with 14 balls parked", crowd),
        ("... same table, no pockets", alone | {"table": carom_dims}),
        ("... no spin model", alone | {"models": {"spin": False}}),
    ]
    print(f"\n{'what the engine skips':<32} {'events':>6} {'median ms':>10}")
    for label, scene in rows:
        shot = simulate(scene)
        print(f"{label:<32} {len(shot.events):>6} {median_ms(scene, repeat):>10.3f}")
    print(f"\n{'break':<20} {'contacts checked':>16} {'quartics solved':>15} {'culled':>7}")
    for name, make in BREAKS.items():
        sim = Simulation(parse_scene(make()))
        sim.run()
        culled = 1 - sim.quartics_solved / sim.contacts_checked
        print(f"{name:<20} {sim.contacts_checked:>16} {sim.quartics_solved:>15} {culled:>7.0%}")


def pooltool(python: str, speed: float, repeat: int) -> None:
    """pooltool's nine-ball break beside ours, in the same run."""
    out = subprocess.run(
        [python, "-c", POOLTOOL, str(speed), str(repeat)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    first, median, events = float(out[0]), float(out[1]), int(out[2])
    ours = median_ms(BREAKS["nineball_break"](speed=speed), repeat)
    print(f"\n{'nine-ball break':<20} {'events':>6} {'median ms':>10} {'1st call ms':>11}")
    print(f"{'pooltool':<20} {events:>6} {1e3 * median:>10.1f} {1e3 * first:>11.0f}")
    ratio = 1e3 * median / ours
    print(f"{'this engine':<20} {'':>6} {ours:>10.1f}   (pooltool / this engine: {ratio:.0f}x)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=30)
    parser.add_argument(
        "--pooltool-python",
        help="an interpreter with pooltool-billiards installed, to time it beside this engine",
    )
    parser.add_argument("--speed", type=float, default=8.0, help="break speed (m/s)")
    args = parser.parse_args()
    print(f"break speed {args.speed} m/s, median of {args.repeat} runs per row\n")
    header = f"{'scene':<20} {'models':<19} {'events':>6} {'median ms':>10} {'vs default':>10}"
    header += f" {'msgpack B':>9} {'import ms':>9} {'1st call ms':>11}"
    print(header)
    print("-" * len(header))
    for name, make in BREAKS.items():
        base = None
        for label, models in VARIANTS.items():
            scene = make(speed=args.speed) | {"models": models}
            shot = simulate(scene)
            ms = median_ms(scene, args.repeat)
            base = base or ms
            row = f"{name:<20} {label:<19} {len(shot.events):>6} {ms:>10.2f} {ms / base:>10.2f}"
            if label == "default":
                imp, first = first_call(name)
                row += f" {len(shot.to_msgpack()):>9} {imp:>9.1f} {first:>11.1f}"
            print(row)
    savings(args.repeat)
    if args.pooltool_python:
        pooltool(args.pooltool_python, args.speed, args.repeat)


if __name__ == "__main__":
    main()
