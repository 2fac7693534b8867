"""Time the engine, compiled kernel and pure Python side by side, beside pooltool.

    .venv/bin/python bench/shots.py [--repeat N] [--batch N] [--pooltool-python PY]

Each path runs in its own interpreter (BILLIARDS_PURE_PYTHON=1 for the pure-Python engine, the
compiled kernel otherwise), and with --pooltool-python (an interpreter with pooltool-billiards
installed) pooltool runs in a third, timing its own nine-ball break. They take turns, five
shots at a time, so that all see the same load on a shared machine, and every figure is a CPU
time (of the worker, which other work on the machine inflates less than wall time). For each
scene: events, the median CPU time of a shot (from the parsed scene to the Shot), events per
second, and the ratio of the two paths; pooltool's ratio to each path is the median of the
ratios of each round's medians, so that a burst of load on the machine moves both sides of a
ratio alike. Then the first shot in a fresh interpreter (import, then one shot: any warm-up a
server pays on its first request), and the batch throughput of simulate_many on one worker (in
the process) and on every core, the two taking turns, for the bot's kind of shot (the single
shot at random headings and speeds): without trajectories (what a referee reads) and with
them, as shots per second of wall time and CPU time per shot of every process involved (the
caller and its workers). On a machine shared with other sessions the wall rate shows little
of what a second worker adds (Linux's scheduler, autogroup, gives each session an equal share
of the CPU however many processes it runs): the CPU time per shot says what a second core
would give, and "cores" how many the batch got. The machine's load average heads the table.
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
#: the 1 with a little follow. Prints its first call (JIT included) as a JSON line, then
#: answers each line N with the CPU times (ms) of N shots, as the engine's own paths do.
POOLTOOL = """
import json, sys, time
import pooltool as pt

def shot():
    table = pt.Table.from_game_type(pt.GameType.NINEBALL)
    system = pt.System(
        table=table, balls=pt.get_rack(pt.GameType.NINEBALL, table), cue=pt.Cue(cue_ball_id="cue")
    )
    system.strike(V0=float(sys.argv[1]), phi=pt.aim.at_ball(system, "1"), b=0.1)
    return system

def timed():
    system = shot()
    t0 = time.process_time()
    pt.simulate(system, inplace=True)
    return 1e3 * (time.process_time() - t0), len(system.events)

first, events = timed()
print(json.dumps({"first": first, "events": events, "version": pt.__version__}), flush=True)
for line in sys.stdin:
    print(json.dumps({"events": events, "ms": [timed()[0] for _ in range(int(line))]}), flush=True)
"""

#: Rounds of the batch figures, each setting timed once per round.
BATCH_ROUNDS = 3

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


def children_cpu() -> float | None:
    """CPU seconds of this process's live children so far (the batch's workers; Linux only)."""
    try:
        pids = []
        for task in Path("/proc/self/task").iterdir():
            pids += (task / "children").read_text().split()
        return sum(int(Path(f"/proc/{pid}/schedstat").read_text().split()[0]) for pid in pids) / 1e9
    except OSError:
        return None


def batch_rates(n: int, rounds: int) -> dict[str, dict[str, list[float]]]:
    """simulate_many on one worker and on every core, taking turns `rounds` times, with and
    without trajectories: per setting, the wall rates (shots/s), CPU per shot (us: this
    process and its workers) and cores used (CPU / wall) of each round."""
    shots = [parse_scene(s) for s in bot_shots(n)]
    counts = sorted({1, os.cpu_count() or 1})
    for workers in counts:
        simulate_many(shots[: 4 * workers], workers=workers)  # start the pool, warm the workers
    out: dict[str, dict[str, list[float]]] = {}
    for _ in range(rounds):
        for trajectories in (False, True):
            for workers in counts:
                c0, k0, t0 = time.process_time(), children_cpu(), time.perf_counter()
                simulate_many(shots, workers=workers, trajectories=trajectories)
                wall, k1 = time.perf_counter() - t0, children_cpu()
                own = time.process_time() - c0
                cpu = own + (k1 - k0 if k0 is not None and k1 is not None else 0.0)
                row = out.setdefault(f"{workers} {int(trajectories)}", {})
                row.setdefault("rate", []).append(n / wall)
                row.setdefault("cpu_us", []).append(1e6 * cpu / n)
                row.setdefault("cores", []).append(cpu / wall)
    return out


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
            answer = batch_rates(int(repeat), BATCH_ROUNDS)
        else:
            scene = rows[name]
            answer = {"events": len(simulate(scene).events), "ms": cpu_ms(scene, int(repeat))}
        print(json.dumps(answer), flush=True)


class Worker:
    """An interpreter answering timing requests: one path of the engine, or pooltool."""

    def __init__(self, command: list[str], env: dict[str, str] | None = None) -> None:
        self.process = subprocess.Popen(
            command, env=env, cwd=ROOT, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
        )
        self.hello = json.loads(self.process.stdout.readline())

    def ask(self, request: str) -> dict:
        self.process.stdin.write(request + "\n")
        self.process.stdin.flush()
        return json.loads(self.process.stdout.readline())

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()


def engine_worker(path: str, args: argparse.Namespace) -> Worker:
    env = os.environ | {kernel.PURE_ENV: PATHS[path]}
    command = [sys.executable, __file__, "--worker", "--speed", str(args.speed)]
    worker_ = Worker(command, env)
    if worker_.hello["compiled"] != (path == "compiled"):
        raise SystemExit(f"the {path} path is not available (is the kernel built?)")
    return worker_


def measure(args: argparse.Namespace) -> dict[str, dict]:
    """Every path's figures, the paths taking turns five shots at a time (pooltool too, on
    the nine-ball break): per scene the events and each round's five CPU times (ms)."""
    workers = {path: engine_worker(path, args) for path in PATHS}
    if args.pooltool_python:
        print("starting pooltool (its JIT takes a while) ...", file=sys.stderr, flush=True)
        command = [args.pooltool_python, "-c", POOLTOOL, str(args.speed)]
        workers["pooltool"] = Worker(command)
    results: dict[str, dict] = {path: {"rows": {}} for path in workers}
    for name in scenes(args.speed):
        print(f"timing {name} ...", file=sys.stderr, flush=True)
        taking = [p for p in workers if p != "pooltool" or name == "nineball_break"]
        for path in taking:
            results[path]["rows"][name] = {"rounds": []}
        for _ in range(max(1, args.repeat // 5)):
            for path in taking:
                request = "5" if path == "pooltool" else f"{name} 5"
                answer = workers[path].ask(request)
                row = results[path]["rows"][name]
                row["events"] = answer["events"]
                row["rounds"].append(answer["ms"])
    print("timing the batches ...", file=sys.stderr, flush=True)
    for path in PATHS:
        results[path]["batch"] = workers[path].ask(f"batch {args.batch}")
    for path, worker_ in workers.items():
        results[path]["hello"] = worker_.hello
        worker_.close()
    return results


def median_ms(row: dict) -> float:
    return statistics.median([ms for r in row["rounds"] for ms in r])


def ratio(slow: dict, fast: dict) -> float:
    """The median over the rounds of slow's median / fast's median (the two took turns)."""
    pairs = zip(slow["rounds"], fast["rounds"], strict=True)
    return statistics.median([statistics.median(a) / statistics.median(b) for a, b in pairs])


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
        n, mc, mp = c[name]["events"], median_ms(c[name]), median_ms(p[name])
        assert n == p[name]["events"], "the two paths disagree"  # tests/physics_kernel checks more
        row = f"{name:<20} {n:>6} {mc:>11.3f} {mp:>10.3f} {ratio(p[name], c[name]):>7.1f}x"
        print(row + f" {1e3 * n / mc:>13,.0f} {1e3 * n / mp:>11,.0f}")


def first_calls() -> None:
    print(f"\n{'first shot, fresh interpreter':<30} {'import ms':>9} {'1st shot ms':>11}")
    for path in PATHS:
        imp, first = first_call(path)
        print(f"{path:<30} {imp:>9.1f} {first:>11.2f}")


def batches(results: dict[str, dict], n: int) -> None:
    """Each setting's medians over the rounds; the speed-up is the median of the rounds'."""
    print(f"\n{'batch of ' + str(n) + ' single shots':<34} {'workers':>7} {'shots/s':>8}", end="")
    print(f" {'speed-up':>8} {'CPU us/shot':>11} {'cores':>5}")
    for path in PATHS:
        batch = results[path]["batch"]
        for trajectories, label in (("0", "no trajectories"), ("1", "with trajectories")):
            one = batch[f"1 {trajectories}"]
            for workers in sorted({int(key.split()[0]) for key in batch}):
                row = batch[f"{workers} {trajectories}"]
                pairs = zip(row["rate"], one["rate"], strict=True)
                gain = statistics.median([a / b for a, b in pairs])
                rate, cpu, cores = (statistics.median(row[k]) for k in ("rate", "cpu_us", "cores"))
                line = f"{path + ', ' + label:<34} {workers:>7} {rate:>8,.0f}"
                print(line + f" {gain:>7.2f}x {cpu:>11.1f} {cores:>5.2f}")


def pooltool(results: dict[str, dict]) -> None:
    """pooltool's nine-ball break beside ours, the three taking turns in the same run."""
    pt = results["pooltool"]
    row = pt["rows"]["nineball_break"]
    print(f"\n{'nine-ball break':<24} {'events':>6} {'median ms':>10} {'pooltool / this':>15}")
    label = f"pooltool {pt['hello']['version']}"
    first = pt["hello"]["first"]
    print(f"{label:<24} {row['events']:>6} {median_ms(row):>10.2f}   (1st call {first:.0f} ms)")
    for path in PATHS:
        ours = results[path]["rows"]["nineball_break"]
        line = f"{'this engine, ' + path:<24} {ours['events']:>6} {median_ms(ours):>10.3f}"
        print(line + f" {ratio(row, ours):>14.0f}x")


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
    parser.add_argument("--repeat", type=int, default=40, help="runs per row (median)")
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
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(
        f"break speed {args.speed} m/s, median of {args.repeat} runs per row, "
        f"{os.cpu_count()} cores, load average {load} (1, 5, 15 min)\n"
    )
    results = measure(args)
    side_by_side(results)
    first_calls()
    batches(results, args.batch)
    if args.pooltool_python:
        pooltool(results)
    if kernel.compiled():
        savings(args.speed, args.repeat)


if __name__ == "__main__":
    main()
