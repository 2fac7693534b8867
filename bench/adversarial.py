"""The adversarial corpus: hostile and extreme scenes, what the engine does with each, and what
the worst of them cost.

    .venv/bin/python bench/adversarial.py [--seed N] [--malformed N] [--valid N] [--check]

Scenes are generated deterministically from the seed. Malformed ones (wrong types, absurd
numbers, broken tables, bytes that are not a scene) must each be refused with SceneError. Valid
ones sit at the edges of what the scene format accepts (parameters at or near their bounds, up
to 32 balls frozen in clusters, flush with the rails or by the pockets, the hardest strikes)
and must each end as a shot or as the engine's BudgetExceeded. Anything else is a bug and is
printed. The table gives the count of each outcome and the CPU time per document (p50, p99,
max in ms, from the raw bytes to the end of the shot; CPU time of this process, so that other
work on a shared machine inflates it less than wall time).

--check also asserts, for every finished valid shot, that the balls left on the table make a
valid next scene and that no two balls overlap by more than 1e-9 m at any event (slower).
"""

from __future__ import annotations

import argparse
import json
import math
import random
import statistics
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from physics import BudgetExceeded, SceneError, parse_scene, scene_from_json, simulate
from physics.cue import MAX_ELEVATION, MAX_SPEED, MISCUE_LIMIT
from physics.scene import CONTACT_TOLERANCE, MAX_BALL_SPEED, MAX_SCENE_BYTES, MAX_SPIN, ParamsIn
from physics.tables import PRESETS, position_problem

BALL_COUNTS = (1, 2, 5, 16, 32)


def bounds(model: type, name: str) -> tuple[float, float]:
    """The (low, high) bounds of a field of a scene model, read from its JSON schema."""
    branch = model.model_json_schema()["properties"][name]["anyOf"][0]
    return branch.get("minimum", branch.get("exclusiveMinimum")), branch["maximum"]


def near_bound(rng: random.Random, low: float, high: float) -> float:
    """A value at a bound or anywhere between (bounds are where the costs are)."""
    return rng.choice([low, high, rng.uniform(low, high)])


# -- valid scenes ----------------------------------------------------------------------------


def valid_scene(rng: random.Random) -> dict[str, Any]:
    """A scene the format accepts, built at the edges of what it accepts."""
    preset = rng.choice(sorted(PRESETS))
    scene: dict[str, Any] = {"table": preset}
    params = {}
    for name in rng.sample(sorted(ParamsIn.model_fields), rng.randint(0, 6)):
        low, high = bounds(ParamsIn, name)
        value = near_bound(rng, low, high)
        params[name] = round(value) if name == "mathavan_steps" else value
    if params:
        scene["params"] = params
    if rng.random() < 0.3:
        side = rng.choice([0.5, 0.8, 1.27])
        scene["table"] = {"preset": preset, "w": side, "l": rng.choice([side, 2 * side])}
    try:
        parsed = parse_scene(scene | {"balls": {"probe": [0.25, 0.25]}})
    except SceneError:  # the mix made a table that does not close its pockets: no overrides
        scene = {"table": preset}
        parsed = parse_scene(scene | {"balls": {"probe": [0.25, 0.25]}})
    scene["balls"] = balls(rng, parsed.geometry, parsed.params.R)
    if rng.random() < 0.3:
        scene["models"] = {
            "ball_ball": rng.choice(["alciatore", "frictionless"]),
            "cushion": rng.choice(["mathavan", "han"]),
            "spin": rng.random() < 0.8,
        }
    names = list(scene["balls"])
    # Mostly one or two balls set moving; now and then all of them (the costliest kind).
    movers = names[: rng.choice([1, 1, 2, 3, len(names) if rng.random() < 0.1 else 1])]
    if rng.random() < 0.6:
        offset = rng.choice([0.0, MISCUE_LIMIT, rng.uniform(0, MISCUE_LIMIT)])
        angle = rng.uniform(0, 2 * math.pi)
        scene["strike"] = {
            "ball": names[0],
            "speed": rng.choice([MAX_SPEED, 1e-3, rng.uniform(1e-3, MAX_SPEED)]),
            "heading": rng.uniform(0, 360),
            "elevation": rng.choice([0.0, MAX_ELEVATION, rng.uniform(0, MAX_ELEVATION)]),
            "a": offset * math.cos(angle),
            "b": offset * math.sin(angle),
        }
        movers = movers[1:3]
    scene["initial"] = {name: motion(rng) for name in movers}
    return scene


def motion(rng: random.Random) -> dict[str, list[float]]:
    speed = rng.choice([0.999 * MAX_BALL_SPEED, rng.uniform(0, MAX_BALL_SPEED)])
    heading = rng.uniform(0, 2 * math.pi)
    axis = [rng.uniform(-1, 1) for _ in range(3)]
    spin = rng.choice([0.0, 0.999 * MAX_SPIN, rng.uniform(0, MAX_SPIN)]) / math.hypot(*axis)
    return {
        "v": [speed * math.cos(heading), speed * math.sin(heading)],
        "w": [spin * c for c in axis],
    }


def balls(rng: random.Random, g, R: float) -> dict[str, list[float]]:
    """Up to 32 balls: frozen clusters, flush with the rails, by the pockets, anywhere."""
    w, l = g.spec.w, g.spec.l
    pts: list[tuple[float, float]] = []
    for _ in range(rng.choice(BALL_COUNTS) * 3):
        kind = rng.random()
        if pts and kind < 0.4:
            bx, by = rng.choice(pts)
            ang = rng.uniform(0, 2 * math.pi)
            p = (bx + 2 * R * math.cos(ang), by + 2 * R * math.sin(ang))
        elif g.pockets and kind < 0.6:
            pocket = rng.choice(g.pockets)
            ang = rng.uniform(0, 2 * math.pi)
            d = pocket.radius + rng.uniform(0, 3 * R)
            p = (pocket.center[0] + d * math.cos(ang), pocket.center[1] + d * math.sin(ang))
        elif kind < 0.8:
            along_x, along_y = rng.uniform(R, w - R), rng.uniform(R, l - R)
            p = rng.choice([(R, along_y), (w - R, along_y), (along_x, R), (along_x, l - R)])
        else:
            p = (rng.uniform(R, w - R), rng.uniform(R, l - R))
        clear = all(math.dist(p, q) >= 2 * R for q in pts)
        if clear and position_problem(g, R, *p, CONTACT_TOLERANCE) is None:
            pts.append(p)
        if len(pts) == 32:
            break
    return {f"b{k}": list(p) for k, p in enumerate(pts)} or {"b0": [w / 2, l / 2]}


# -- malformed documents ---------------------------------------------------------------------


def _set(scene: dict, path: tuple, value: Any) -> dict:
    """A deep copy of scene with the value at path replaced."""
    out = json.loads(json.dumps(scene))
    node = out
    for key in path[:-1]:
        node = node.setdefault(key, {})
    node[path[-1]] = value
    return out


#: Values that are never a valid number of a scene.
BAD_VALUES = ("x", "3.0", True, None, [], {}, 1e308, -1e308)


def malformed(rng: random.Random) -> bytes:
    """The bytes of a document that is not a valid scene."""
    base = {
        "table": "nineball",
        "balls": {"cue": [0.5, 0.5], "1": [0.5, 1.5]},
        "strike": {"ball": "cue", "speed": 2.0, "heading": 90.0},
    }
    kind = rng.randrange(10)
    if kind == 0:  # a bad value anywhere a number belongs
        path = rng.choice(
            [("balls", "cue", 0), ("strike", "speed"), ("strike", "heading"), ("strike", "a")]
            + [("params", n) for n in sorted(ParamsIn.model_fields)]
            + [("table", n) for n in ("w", "l", "corner_depth", "jaw_radius", "cushion_height")]
        )
        if path[0] == "balls":
            value = [rng.choice(BAD_VALUES), 0.5]
            return json.dumps(_set(base, path[:2], value)).encode()
        value = rng.choice(BAD_VALUES)
        if path[0] == "table":
            base["table"] = {}
        return json.dumps(_set(base, path, value)).encode()
    if kind == 1:  # a parameter past its bound
        name = rng.choice(sorted(ParamsIn.model_fields))
        low, high = bounds(ParamsIn, name)
        value = rng.choice([low - abs(low) * 0.5 - 1e-3, high * 2 + 1])
        if name == "mathavan_steps":
            value = rng.choice([0, 33, 100_000, 4.5])
        return json.dumps(_set(base, ("params", name), value)).encode()
    if kind == 2:  # a table that is broken
        table = rng.choice(
            [
                {"corner_radius": rng.uniform(1e-4, 0.02)},
                {"side_radius": rng.uniform(1e-4, 0.01)},
                {"side_depth": rng.uniform(0.1, 0.2)},
                {"corner_mouth": rng.uniform(1e-3, 0.05)},
                {"cushion_height": rng.uniform(1e-3, 0.02)},
                {"cushion_height": rng.uniform(0.06, 0.1)},
                {"l": 0.5, "side_mouth": 0.3, "corner_mouth": 0.3},
                {"w": rng.choice([0.0, -1.0, 1e9])},
                {"pockets": rng.choice([1, "yes", None])},
                {"preset": "pool"},
                {"lenght": 2.0},
            ]
        )
        return json.dumps(base | {"table": table}).encode()
    if kind == 3:  # balls where no ball may be
        where = rng.choice(
            [[0.01, 0.5], [5.0, 0.5], [0.03, 0.05], [0.5, 0.5 + rng.uniform(0, 0.05)], [-1, -1]]
        )
        return json.dumps(_set(base, ("balls", "1"), where)).encode()
    if kind == 4:  # strikes out of range
        key, value = rng.choice(
            [
                *[("speed", 0.0), ("speed", 50.0), ("elevation", 89.5), ("elevation", -1.0)],
                *[("a", 0.6), ("b", -0.51), ("ball", "ghost"), ("ball", "bad id!")],
                *[("heading", 1e6), ("heading", -400.0)],
            ]
        )
        return json.dumps(_set(base, ("strike", key), value)).encode()
    if kind == 5:  # initial motion out of range, or for a ball that is not there
        m = rng.choice([{"v": [20.0, 0.0]}, {"w": [0.0, 0.0, 1e4]}, {"v": [1.0]}, {"x": 1}])
        return json.dumps(base | {"initial": {rng.choice(["1", "9"]): m}}).encode()
    if kind == 6:  # structure: too many balls, unknown keys, wrong shapes
        return json.dumps(
            rng.choice(
                [
                    base
                    | {
                        "balls": {
                            f"b{k}": [0.1 + 0.06 * (k % 15), 0.2 + 0.06 * (k // 15)]
                            for k in range(40)
                        }
                    },
                    base | {"extra": 1},
                    base | {"balls": {}},
                    base | {"balls": [[0.5, 0.5]]},
                    base | {"models": {"cushion": "bogus"}},
                    [base],
                    "scene",
                ]
            )
        ).encode()
    if kind == 7:  # nesting past the parser's limit, and documents too long
        depth = rng.choice([2_000, 30_000])
        return rng.choice(
            [
                b"[" * depth + b"]" * depth,
                b'{"balls": ' + b"[" * depth,
                b" " * (MAX_SCENE_BYTES + 1),
            ]
        )
    if kind == 8:  # integers too long for Python to convert, or for a float
        digits = rng.choice([400, 5_000])
        return b'{"balls": {"cue": [' + b"9" * digits + b", 0.5]}}"
    # Bytes that are not UTF-8 JSON: binary noise, other encodings, truncation.
    text = json.dumps(base)
    return rng.choice(
        [
            bytes(rng.randrange(256) for _ in range(rng.randint(1, 64))),
            text.encode("utf-16"),
            text.replace("nineball", "n\u00efneball").encode("latin-1"),
            text[: rng.randint(0, len(text) - 1)].encode(),
        ]
    )


# -- running ---------------------------------------------------------------------------------


def run_one(document: bytes) -> tuple[str, float, Any]:
    """(outcome, seconds, shot or None) of one document from its bytes."""
    t0 = time.process_time()
    try:
        shot = simulate(scene_from_json(document))
    except SceneError:
        return "refused", time.process_time() - t0, None
    except BudgetExceeded:
        return "budget", time.process_time() - t0, None
    except Exception as exc:
        return f"BUG {type(exc).__name__}: {exc}", time.process_time() - t0, None
    return "shot", time.process_time() - t0, shot


def check(scene: dict[str, Any], shot) -> str | None:
    """What a finished shot broke of the invariants, or None."""
    left = {k: list(f.pos) for k, f in shot.final.items() if f.pos is not None}
    if left:
        try:
            parse_scene(
                {k: v for k, v in scene.items() if k in ("table", "params")} | {"balls": left}
            )
        except SceneError as exc:
            return f"next scene refused: {exc}"
    R = parse_scene(scene).params.R
    for event in shot.events:
        at = [p for p in (shot.position(b, event.t) for b in shot.final) if p is not None]
        for k, p in enumerate(at):
            for q in at[k + 1 :]:
                if 2 * R - math.dist(p, q) > 1e-9:
                    return f"overlap {2 * R - math.dist(p, q):.3g} m at t={event.t}"
    return None


def family(scene: dict[str, Any]) -> str:
    """A valid scene's row in the breakdown: how many balls, and how many set moving."""
    n = len(scene["balls"])
    moving = len(scene["initial"]) + ("strike" in scene)
    size = next(f"{k:>2} balls or fewer" for k in (2, 5, 16, 32) if n <= k)
    return f"  {size}, {'all' if moving == n and n > 2 else 'some'} moving"


def corpus(seed: int, n_malformed: int, n_valid: int):
    """(kind, document bytes, scene or None) in a fixed order for the seed."""
    rng = random.Random(seed)
    for _ in range(n_malformed):
        yield "malformed", malformed(rng), None
    for _ in range(n_valid):
        scene = valid_scene(rng)
        yield "valid", json.dumps(scene).encode(), scene


def percentile(sorted_ms: list[float], q: float) -> float:
    return sorted_ms[min(len(sorted_ms) - 1, int(q * len(sorted_ms)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--malformed", type=int, default=1500)
    parser.add_argument("--valid", type=int, default=7000)
    parser.add_argument("--check", action="store_true", help="check invariants of valid shots")
    args = parser.parse_args()
    total = args.malformed + args.valid
    outcomes: dict[str, Counter] = defaultdict(Counter)
    times: dict[str, list[float]] = defaultdict(list)
    problems = []
    worst = (0.0, b"")
    for k, (kind, document, scene) in enumerate(corpus(args.seed, args.malformed, args.valid)):
        outcome, seconds, shot = run_one(document)
        outcomes[kind][outcome.split(":")[0]] += 1
        times[kind].append(1e3 * seconds)
        if scene is not None:
            times[family(scene)].append(1e3 * seconds)
        if seconds > worst[0]:
            worst = (seconds, document)
        expected = {"malformed": ("refused",), "valid": ("shot", "budget")}[kind]
        if outcome not in expected:
            problems.append(f"{kind} #{k}: {outcome}: {document[:200]!r}")
        elif args.check and shot is not None:
            broken = check(scene, shot)
            if broken:
                problems.append(f"{kind} #{k}: {broken}: {document[:300]!r}")
        if (k + 1) % 500 == 0 or k + 1 == total:
            print(f"  {k + 1}/{total} documents, {len(problems)} problems", file=sys.stderr)
    print(f"\nseed {args.seed}: {args.malformed} malformed, {args.valid} valid documents")
    print(f"{'corpus':<10} {'outcome':<16} {'count':>6} {'p50 ms':>8} {'p99 ms':>8} {'max ms':>8}")
    for kind in ("malformed", "valid"):
        ms = sorted(times[kind])
        if not ms:
            continue
        for outcome, count in sorted(outcomes[kind].items()):
            print(f"{kind:<10} {outcome:<16} {count:>6}")
        p50, p99 = statistics.median(ms), percentile(ms, 0.99)
        print(f"{kind:<10} {'(all)':<16} {len(ms):>6} {p50:>8.2f} {p99:>8.2f} {ms[-1]:>8.1f}")
    print("valid, by family:")
    for name in sorted(k for k in times if k.startswith("  ")):
        ms = sorted(times[name])
        p50, p99 = statistics.median(ms), percentile(ms, 0.99)
        print(f"{name:<27} {len(ms):>6} {p50:>8.2f} {p99:>8.2f} {ms[-1]:>8.1f}")
    print(f"\nslowest document ({1e3 * worst[0]:.1f} ms): {worst[1][:160]!r}...")
    for line in problems[:20]:
        print(line)
    print(f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
