"""What computing a long replay's shots costs a worker: time and peak memory per computation.

    .venv/bin/python bench/replay_pages.py [--inputs 2000] [--pages 2]

A replay's shots (`GET /api/replays/{id}/shots?page=N`) are computed in the background worker
by replaying the record (server/game/replays.py). This builds a long, legal three-cushion
record (bench/long_record.py: a claimant may send one of up to `MAX_INPUTS` inputs), then, each
in a fresh process, computes its pages as the server does (`--pages` at a time: the first two,
the last two) and, for comparison, all of them at once, as the server did before; it prints
each computation's seconds, the bytes of the pages made and the process's peak RSS (the
process's own baseline, with the engine loaded and nothing computed, is the first row).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from long_record import long_record

from server.game.refereeing import GameRecord
from server.game.replays import PAGES_AT_ONCE, page_count, shots_pages


def measure(path: str, first: int, count: int | None) -> dict:
    """One computation in this process (a fresh one): seconds, bytes, peak RSS (MB)."""
    record = GameRecord.model_validate_json(Path(path).read_text())
    began = time.perf_counter()
    pages = shots_pages("a" * 24, record, first, count) if count != 0 else []
    seconds = time.perf_counter() - began
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"pages": len(pages), "bytes": sum(map(len, pages)), "s": seconds, "rss": peak}


def run(path: str, first: int, count: int | None) -> dict:
    args = [sys.executable, __file__, "--measure", path, str(first), str(count)]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--inputs", type=int, default=2000, help="soft shots in the record")
    ap.add_argument("--pages", type=int, default=PAGES_AT_ONCE, help="pages a computation")
    ap.add_argument("--measure", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.measure:
        path, first, count = args.measure
        print(json.dumps(measure(path, int(first), None if count == "None" else int(count))))
        return
    print(f"building a three-cushion record of {args.inputs} soft shots...", flush=True)
    record = long_record(args.inputs)
    pages = page_count(len(record.inputs))
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as out:
        out.write(record.to_json())
    print(f"{len(record.inputs)} inputs, {pages} pages of shots\n")
    rows = [
        ("nothing computed (baseline)", 0, 0),
        (f"pages 0-{args.pages - 1}", 0, args.pages),
        (f"pages {pages - args.pages}-{pages - 1}", pages - args.pages, args.pages),
        (f"all {pages} pages at once (before)", 0, None),
    ]
    print(f"{'computation':<34}{'pages':>6}{'MB made':>9}{'seconds':>9}{'peak RSS MB':>13}")
    for label, first, count in rows:
        r = run(out.name, first, count)
        print(f"{label:<34}{r['pages']:>6}{r['bytes'] / 1e6:>9.1f}{r['s']:>9.2f}{r['rss']:>13.0f}")
    Path(out.name).unlink()


if __name__ == "__main__":
    main()
