"""Leaderboard claims under attack: what one hostile holder costs the server and the others.

    .venv/bin/python bench/claim_flood.py [--record FILE] [--seconds 30] [--matches 8]

Starts `billiards serve` as bench/match_load.py does (SQLite, 2 match workers and the
background worker) and prints three figures of the claim path:

1. **Refusing a duplicate** of a long record (2,000 inputs, bench/long_record.py): the record
   is claimed once (replayed), then claimed again `REPEATS` times by other players, in the
   same bytes (refused by the body's digest) and re-encoded (other bytes: parsed, then
   refused by the record's remembered verdict); each repeat's answer time (ms, p50 / p99).
3. **The other players' shot latency while one holder floods claims**: match_load's
   matches paced at `--rate` refereed shots per second, alone and then beside a flood: one
   token posting, back to back for `--seconds`, claims of distinct cuts of the record (each
   a new record that needs a replay; a refused one is sent again after 10 ms):
   accepted -> outcome delivered, p50 / p99 ms.
2. **Worker CPU one hostile holder can spend per minute**: the same flood by another token
   (from the same address, whose worker time the first flood spent part of), with no
   matches: the CPU of the processes under the server meanwhile, scaled to a minute.

The matches' clients run in this process, the flood in a process of its own, and all share
the machine's cores with the server: the figures are noisy; compare the two rows of (3) from
one run.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import multiprocessing
import multiprocessing.queues
import sys
import tempfile
import time
from pathlib import Path

import aiohttp
from long_record import long_record
from match_load import cpu_now, free_port, percentile, run, start_server, wait_ready

from rules.record import GameRecord, replay

REPEATS = 50


async def register(session: aiohttp.ClientSession, base: str, name: str) -> dict[str, str]:
    async with session.post(f"{base}/api/players", json={"name": name}) as response:
        token = (await response.json())["token"]
    return {"Authorization": f"Bearer {token}"}


async def claim(
    session: aiohttp.ClientSession, base: str, auth: dict[str, str], record: str, score: int
) -> int:
    body = f'{{"game":"three_cushion","record":{record},"score":{score}}}'
    headers = {**auth, "Content-Type": "application/json"}
    async with session.post(f"{base}/api/leaderboard/claims", data=body, headers=headers) as r:
        await r.read()
        return r.status


def cuts(record: GameRecord) -> list[str]:
    """Records of the game's first n inputs for n from the whole down: each a new record."""
    steps = replay(record).steps
    made, current = [], GameRecord.begin(record.setup)
    for step in steps:
        current = current.extend(step.action, step.state)
        made.append(current.to_json())
    return made[::-1]


async def duplicates(base: str, record: str, score: int) -> None:
    async with aiohttp.ClientSession() as session:
        began = time.perf_counter()
        first = await claim(session, base, await register(session, base, "First"), record, score)
        first_ms = (time.perf_counter() - began) * 1000
        print(f"1. first claim: {first} in {first_ms:.0f} ms (replayed)")
        for label, spaced in (("the same bytes", False), ("re-encoded", True)):
            times, statuses = [], collections.Counter()
            for n in range(REPEATS):
                if n % 10 == 0:  # a player may send 10 claims at once (LIMITS["claim"])
                    other = await register(session, base, f"{label[:3]} {n // 10}")
                text = record + " " * n if spaced else record  # other bytes, the same record
                began = time.perf_counter()
                statuses[await claim(session, base, other, text, score)] += 1
                times.append((time.perf_counter() - began) * 1000)
            p50, p99 = percentile(times, 0.5), percentile(times, 0.99)
            print(f"   {REPEATS} duplicates, {label}, by other players: {dict(statuses)}, "
                  f"p50 {p50:.1f} ms, p99 {p99:.1f} ms")  # fmt: skip


async def flood(base: str, records: list[str], seconds: float, name: str) -> collections.Counter:
    statuses: collections.Counter = collections.Counter()
    stop = time.perf_counter() + seconds
    async with aiohttp.ClientSession() as session:
        auth = await register(session, base, name)
        remaining = iter(records)
        record = next(remaining)
        while time.perf_counter() < stop:
            status = await claim(session, base, auth, record, 1)
            statuses[status] += 1
            if status == 429:  # refused unread: the same record again (not a spin: a pause)
                await asyncio.sleep(0.01)
            else:
                record = next(remaining)
    return statuses


def flood_process(
    base: str, records: list[str], seconds: float, name: str
) -> multiprocessing.queues.Queue:
    """`flood` in a process of its own (forked: the records are not copied), so that the
    hostile client's own work (encoding 100 KB bodies) does not slow the matches' clients
    in this process; its answers by status come on the returned queue."""
    context = multiprocessing.get_context("fork")
    answers = context.Queue()

    def work() -> None:
        answers.put(asyncio.run(flood(base, records, seconds, name)))

    context.Process(target=work, daemon=True).start()
    return answers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", help="a standard three-cushion record (default: made)")
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--matches", type=int, default=8)
    parser.add_argument("--rate", type=float, default=20.0, help="paced shots/s of the matches")
    args = parser.parse_args()
    made = long_record(2000) if args.record is None else None
    record = made or GameRecord.model_validate_json(Path(args.record).read_text())
    text, best = record.to_json(), max(replay(record).final.best)
    variants = cuts(record)
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory() as directory:
        server = start_server(port, 2, directory)
        try:
            asyncio.run(wait_ready(base))
            print(f"record: {len(record.inputs)} inputs, best break {best}")
            asyncio.run(duplicates(base, text, best))
            alone = asyncio.run(run(base, args.matches, args.seconds, args.rate, server.pid))

            hostile = flood_process(base, variants, args.seconds, "Hostile")
            flooded = asyncio.run(run(base, args.matches, args.seconds, args.rate, server.pid))
            statuses = hostile.get(timeout=args.seconds + 60)
            for label, samples in (("alone", alone), ("one holder flooding", flooded)):
                print(f"3. {label:<20} shots {samples.shots:4d}, player p50 / p99 "
                      f"{percentile(samples.player_ms, 0.5):6.1f} / "
                      f"{percentile(samples.player_ms, 0.99):6.1f} ms")  # fmt: skip
            print(f"   the flood's answers: {dict(statuses)}")
            before = cpu_now(server.pid)
            statuses = asyncio.run(flood(base, variants[300:], args.seconds, "Hostile2"))
            main, workers, _ = (b - a for a, b in zip(before, cpu_now(server.pid), strict=True))
            per_minute = 60 / args.seconds
            print(f"2. one holder for {args.seconds:g} s: answers {dict(statuses)}; worker CPU "
                  f"{workers:.1f} s = {workers * per_minute:.1f} s per minute (server process "
                  f"{main * per_minute:.1f} s per minute)")  # fmt: skip
        finally:
            server.terminate()
            server.wait(timeout=10)


if __name__ == "__main__":
    sys.exit(main())
