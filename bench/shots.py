"""Time the engine, compiled kernel and pure Python side by side, beside pooltool.

    .venv/bin/python bench/shots.py [--repeat N] [--batch N] [--pooltool-python PY]

Each path runs in its own interpreter (BILLIARDS_PURE_PYTHON=1 for the pure-Python engine, the
compiled kernel otherwise), and the two take turns, a few shots at a time, so that both see the
same load on a shared machine. For each scene: events, the median CPU time of a shot (from the
parsed scene to the Shot; CPU time of the worker, which other work on the machine inflates less
than wall time), events per second, and the ratio of the two paths. Then the
first shot in a fresh interpreter (import, then one shot: any warm-up a server pays on its
first request), the batch throughput of simulate_many over every core for the bot's kind of
shot (the single shot at random headings and speeds; the Shots it returns are built when first
read, which this does not do), and, with --pooltool-python (an interpreter with
pooltool-billiards installed), pooltool's own nine-ball break in the same run. A machine shared
with other sessions shows little of what a second worker adds: Linux's scheduler (autogroup)
gives each session an equal share of the CPU however many processes it runs.
Last, on the compiled path: what the cheaper model choices save and what the culling skips.

pooltool-billiards 0.6.0 pins a development build of panda3d (its 3D front end) that PyPI does
not carry; its physics runs on the released panda3d 1.10:

    python3 -m venv /tmp/pt && /tmp/pt/bin/pip install --no-deps pooltool-billiards==0.6.0
    /tmp/pt/bin/pip install 'panda3d>=1.10.13,<1.11' panda3d-gltf panda3d-simplepbr numba \
        'llvmlite>=0.44,<0.46' scipy attrs cattrs msgpack msgpack-numpy pyyaml click pillow \
        h5py 'h11>=0.16' 'rich>=14,<15' 'numpy-quaternion>=2024.0.12'
"""

from __future__ import annotations

import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from physics import kernel, parse_scene, simulate, simulate_many  # noqa: E402
from physics.engine import Simulation  # noqa: E402
from physics.examples import BREAKS, single_shot  # noqa: E402

PATHS = {"compiled": "0", "python": "1"}  # the value of BILLIARDS_PURE_PYTHON for each

FIRST_CALL = """
import time, sys
t0 = time.perf_counter()
from physics import simulate, kernel
from physics.examples import single_shot
t1 = time.perf_counter()
simulate(single_shot())
t2 = time.perf_counter()
print(t1 - t0, t2 - t1, kernel.compiled())
"""

#: The same kind of shot in pooltool (ekiefl/pooltool, a numba event engine), run with another
#: interpreter that has it installed: its own nine-ball rack and table, cue ball at 8 m/s into
#: the 1 with a little follow. Prints: first call (s), median (s), events, version (CPU time,
#: as for this engine).
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
    t0 = time.process_time()
    pt.simulate(system, inplace=True)
    times.append(time.process_time() - t0)
print(times[0], statistics.median(times[1:]), len(system.events), pt.__version__)
"""

VARIANTS = {
    "frictionless balls": {"ball_ball": "frictionless"},
    "han cushion": {"cushion": "han"},
    "no spin": {"spin": False},
}


def scenes(speed: float) -> dict[str, dict]:
    rows = {name: make(speed=speed) for name, make in BREAKS.items()}
    rows["single shot"] = single_shot()
    return rows


def bot_shots(n: int) -> list[dict]:
    """The bot's kind of shot: the single shot at random headings and speeds."""
    rng = random.Random(14)
    return [single_shot(rng.uniform(0.5, 4.0), rng.uniform(0.0, 360.0)) for _ in range(n)]


def batch_rate(n: int, workers: int) -> float:
    """Shots per second of simulate_many on `workers` processes (pool already started)."""
    shots = [parse_scene(s) for s in bot_shots(n)]
    simulate_many(shots[: 4 * workers], workers=workers)  # start the pool, warm the workers
    t0 = time.perf_counter()
    simulate_many(shots, workers=workers)
    return n / (time.perf_counter() - t0)


def cpu_ms(scene: dict, repeat: int) -> list[float]:
    """CPU times (ms) of `repeat` shots of a parsed scene, after one to warm up."""
    parsed = parse_scene(scene)
    simulate(parsed)
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        simulate(parsed)
        times.append(1e3 * (time.process_time() - t0))
    return times


def worker(args: argparse.Namespace) -> None:
    """One path's timings, on request: reads `SCENE REPEAT` lines, answers each with a JSON
    line (run by main with the path's environment); `batch` answers the batch throughput."""
    rows = scenes(args.speed)
    print(json.dumps({"compiled": kernel.compiled()}), flush=True)
    for line in sys.stdin:
        name, repeat = line.rsplit(" ", 1)
        if name == "batch":
            cores = os.cpu_count() or 1
            answer = {str(w): batch_rate(int(repeat), w) for w in sorted({1, cores})}
        else:
            scene = rows[name]
            answer = {"events": len(simulate(scene).events), "ms": cpu_ms(scene, int(repeat))}
        print(json.dumps(answer), flush=True)


class Path:
    """A worker interpreter running one path of the engine."""

    def __init__(self, path: str, args: argparse.Namespace) -> None:
        env = os.environ | {kernel.PURE_ENV: PATHS[path]}
        command = [sys.executable, __file__, "--worker", "--speed", str(args.speed)]
        self.process = subprocess.Popen(
            command, env=env, cwd=ROOT, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
        )
        if json.loads(self.process.stdout.readline())["compiled"] != (path == "compiled"):
            raise SystemExit(f"the {path} path is not available (is the kernel built?)")

    def ask(self, name: str, repeat: int) -> dict:
        self.process.stdin.write(f"{name} {repeat}\n")
        self.process.stdin.flush()
        return json.loads(self.process.stdout.readline())

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()


def measure(args: argparse.Namespace) -> dict[str, dict]:
    """Both paths' figures, the paths taking turns five shots at a time."""
    paths = {path: Path(path, args) for path in PATHS}
    results: dict[str, dict] = {path: {"rows": {}} for path in PATHS}
    for name in scenes(args.speed):
        print(f"timing {name} ...", file=sys.stderr, flush=True)
        for path in PATHS:
            results[path]["rows"][name] = {"ms": []}
        for _ in range(max(1, args.repeat // 5)):
            for path, worker_ in paths.items():
                answer = worker_.ask(name, 5)
                row = results[path]["rows"][name]
                row["events"] = answer["events"]
                row["ms"] += answer["ms"]
        for path in PATHS:
            row = results[path]["rows"][name]
            row["ms"] = statistics.median(row["ms"])
    print("timing the batches ...", file=sys.stderr, flush=True)
    for path, worker_ in paths.items():
        results[path]["batch"] = worker_.ask("batch", args.batch)
        worker_.close()
    return results


def first_call(path: str) -> tuple[float, float]:
    env = os.environ | {kernel.PURE_ENV: PATHS[path]}
    out = subprocess.run(
        [sys.executable, "-c", FIRST_CALL],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    ).stdout.split()
    return 1e3 * float(out[0]), 1e3 * float(out[1])


def side_by_side(results: dict[str, dict]) -> None:
    c, p = results["compiled"]["rows"], results["python"]["rows"]
    header = f"{'scene':<20} {'events':>6} {'compiled ms':>11} {'python ms':>10} {'speed-up':>8}"
    header += f" {'compiled ev/s':>13} {'python ev/s':>11}"
    print(header)
    print("-" * len(header))
    for name in c:
        n, mc, mp = c[name]["events"], c[name]["ms"], p[name]["ms"]
        assert n == p[name]["events"], "the two paths disagree"  # tests/physics_kernel checks more
        row = f"{name:<20} {n:>6} {mc:>11.3f} {mp:>10.3f} {mp / mc:>7.1f}x"
        print(row + f" {1e3 * n / mc:>13,.0f} {1e3 * n / mp:>11,.0f}")


def first_calls() -> None:
    print(f"\n{'first shot, fresh interpreter':<30} {'import ms':>9} {'1st shot ms':>11}")
    for path in PATHS:
        imp, first = first_call(path)
        print(f"{path:<30} {imp:>9.1f} {first:>11.2f}")


def batches(results: dict[str, dict], n: int) -> None:
    print(f"\n{'batch of ' + str(n) + ' single shots':<30} {'workers':>7} {'shots/s':>9}")
    for path, result in results.items():
        for workers, rate in result["batch"].items():
            print(f"{path:<30} {workers:>7} {rate:>9,.0f}")


def pooltool(python: str, results: dict[str, dict], speed: float, repeat: int) -> None:
    """pooltool's nine-ball break beside ours, in the same run."""
    out = subprocess.run(
        [python, "-c", POOLTOOL, str(speed), str(repeat)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    first, median, events, version = float(out[0]), float(out[1]), int(out[2]), out[3]
    print(f"\n{'nine-ball break':<24} {'events':>6} {'median ms':>10} {'pooltool / this':>15}")
    label = f"pooltool {version}"
    print(f"{label:<24} {events:>6} {1e3 * median:>10.2f}   (1st call {1e3 * first:.0f} ms)")
    for path, result in results.items():
        row = result["rows"]["nineball_break"]
        ratio = 1e3 * median / row["ms"]
        print(f"{'this engine, ' + path:<24} {row['events']:>6} {row['ms']:>10.3f} {ratio:>14.0f}x")


def savings(speed: float, repeat: int) -> None:
    """What the cheaper models save, and what the culling skips (this process's path)."""
    print(f"\n{'model choice (compiled)':<20} {'models':<19} {'events':>6} {'median ms':>10}")
    for name, make in BREAKS.items():
        for label, models in VARIANTS.items():
            scene = make(speed=speed) | {"models": models}
            events = len(simulate(scene).events)
            ms = statistics.median(cpu_ms(scene, repeat))
            print(f"{name:<20} {label:<19} {events:>6} {ms:>10.3f}")
    print(f"\n{'break':<20} {'contacts checked':>16} {'quartics solved':>15} {'culled':>7}")
    for name, make in BREAKS.items():
        sim = Simulation(parse_scene(make(speed=speed)))
        sim.run()
        culled = 1 - sim.quartics_solved / sim.contacts_checked
        print(f"{name:<20} {sim.contacts_checked:>16} {sim.quartics_solved:>15} {culled:>7.0%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=30, help="runs per row (median)")
    parser.add_argument("--batch", type=int, default=2000, help="shots per batch")
    parser.add_argument("--speed", type=float, default=8.0, help="break speed (m/s)")
    parser.add_argument(
        "--pooltool-python",
        help="an interpreter with pooltool-billiards installed, to time it beside this engine",
    )
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        return worker(args)
    print(
        f"break speed {args.speed} m/s, median of {args.repeat} runs per row, "
        f"{os.cpu_count()} cores\n"
    )
    results = measure(args)
    side_by_side(results)
    first_calls()
    batches(results, args.batch)
    if args.pooltool_python:
        pooltool(args.pooltool_python, results, args.speed, args.repeat)
    if kernel.compiled():
        savings(args.speed, args.repeat)


if __name__ == "__main__":
    main()
