"""Game records: how small the share-link form is, and how many tampered records replay catches.

    .venv/bin/python bench/records.py [--racks N] [--frames N] [--per-kind K] [--seed S]

Self-plays N nine-ball racks and N snooker frames (and as many eight-ball racks and
three-cushion games, to 3 points, for the tamper table), then prints:

1. Size per shot of each record's forms, medians over the games: the compact msgpack (the
   whole record, and its inputs with their digests alone: the issue's goal is at most 12
   bytes per shot), deflated, the base64url share link, and the JSON record.
2. Tamper detection: up to K distinct alterations of each kind (rules.tamper) on every record
   (the last shot's heading has one), each replayed;
   how many were refused, and how: by the digests (REPLAY_DIFFERS) or at an input that became
   illegal; "legal" counts the altered records whose inputs all stay legal, which replay to
   the end as a different game when the record's claims are not checked (as before the
   digests): only the digests can refuse those.

Progress goes to stderr. Timings are not the point here; nothing is timed.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import zlib
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rules.codes import Refusal, RuleError
from rules.compact import encode, pack
from rules.game import Setup, play, start
from rules.inputs import Shot
from rules.record import GameRecord, replay
from rules.selfplay import selfplay
from rules.tamper import ALTERATIONS


def play_games(game: str, n: int, seed: int) -> list[GameRecord]:
    records = []
    for k in range(n):
        setup = Setup(game=game, seed=seed + k, gap=0.0002, target=3)
        records.append(selfplay(setup, max_inputs=400)[0])
        print(f"  {game}: {k + 1}/{n} played", file=sys.stderr, end="\r")
    print(file=sys.stderr)
    return records


def sizes(record: GameRecord) -> dict[str, float]:
    shots = sum(isinstance(a, Shot) for a in record.inputs)
    packed = pack(record)
    empty = pack(record.model_copy(update={"inputs": (), "digests": ()}))
    return {
        "shots": shots,
        "msgpack": len(packed) / shots,
        "inputs+digests": (len(packed) - len(empty)) / shots,
        "deflated": len(zlib.compress(packed, 9)) / shots,
        "link chars": len(encode(record)) / shots,
        "JSON chars": len(record.to_json()) / shots,
    }


def size_table(games: dict[str, list[GameRecord]]) -> None:
    columns = ["shots", "msgpack", "inputs+digests", "deflated", "link chars", "JSON chars"]
    print("\nBytes per shot (median over games)")
    print(f"{'game':<10} {'games':>5} " + " ".join(f"{c:>15}" for c in columns))
    for game, records in games.items():
        rows = [sizes(r) for r in records]
        medians = [statistics.median(row[c] for row in rows) for c in columns]
        print(f"{game:<10} {len(rows):>5} " + " ".join(f"{m:>15.1f}" for m in medians))


def all_legal(record: GameRecord) -> bool:
    """Whether every input of the record is legal in turn (its claims left unchecked)."""
    state = start(record.setup)
    try:
        for action in record.inputs:
            state = play(state, action).state
    except RuleError:
        return False
    return True


def tamper_table(records: list[GameRecord], per_kind: int, rng: random.Random) -> None:
    tried, by_digest, by_rule, missed, legal = Counter(), Counter(), Counter(), Counter(), Counter()
    for n, record in enumerate(records, 1):
        for kind, alter in ALTERATIONS.items():
            seen = [record]
            for _ in range(per_kind):
                altered = alter(record, rng)
                if altered is None or altered in seen:
                    continue
                seen.append(altered)
                tried[kind] += 1
                legal[kind] += all_legal(altered)
                try:
                    replay(altered)
                    missed[kind] += 1
                except RuleError as exc:
                    counter = by_digest if exc.code == Refusal.REPLAY_DIFFERS else by_rule
                    counter[kind] += 1
        print(f"  tampering: {n}/{len(records)} records", file=sys.stderr, end="\r")
    print(file=sys.stderr)
    print(f"\nTamper detection over {len(records)} self-played records")
    columns = {"tried": tried, "legal": legal, "by digest": by_digest, "illegal": by_rule}
    columns["accepted"] = missed
    print(f"{'alteration':<38}" + "".join(f" {c:>10}" for c in columns))
    for kind in [*ALTERATIONS, None]:
        counts = [c[kind] if kind else sum(c.values()) for c in columns.values()]
        print(f"{kind or 'all':<38}" + "".join(f" {n:>10}" for n in counts))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--racks", type=int, default=20, help="games of each kind (default 20)")
    parser.add_argument("--frames", type=int, default=4, help="snooker frames (default 4)")
    parser.add_argument("--per-kind", type=int, default=4, help="alterations of each kind")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    games = {
        "nineball": play_games("nineball", args.racks, args.seed),
        "snooker": play_games("snooker", args.frames, args.seed),
        "eightball": play_games("eightball", args.racks, args.seed),
        "carom": play_games("three_cushion", max(1, args.racks // 4), args.seed),
    }
    size_table(games)
    every = [r for records in games.values() for r in records]
    tamper_table(every, args.per_kind, random.Random(args.seed))


if __name__ == "__main__":
    main()
