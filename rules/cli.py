"""`billiards selfplay GAME [--seed N]` and `billiards replay RECORD`.

Both print the same thing, one line per input: the referee's decision on each shot and each
choice made, then the final scores. selfplay can save its record (--record FILE, JSON; --link
prints the compact share-link form), and replaying that file prints exactly the lines selfplay
printed. replay reads a JSON record or a share link, and refuses (exit status 2, one line on
stderr naming the input) a record that does not replay to the game it states. The only module
of `rules` that does I/O.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rules.record import GameRecord, Replay

from rules.racks import Game


def register(sub: argparse._SubParsersAction) -> None:
    play = sub.add_parser("selfplay", help="play a whole game between two simple shot pickers")
    play.add_argument("game", choices=[g.value for g in Game])
    play.add_argument("--seed", type=int, default=0, help="rack seed (default 0)")
    play.add_argument("--gap", type=float, default=0.0002, help="largest gap in the rack (m)")
    play.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    play.add_argument("--max-inputs", type=int, default=400, help="stop after this many inputs")
    play.add_argument("--record", help="write the game record (JSON) to this file")
    play.add_argument("--link", action="store_true", help="print the record as a share link")
    play.set_defaults(func=run_selfplay)
    rep = sub.add_parser("replay", help="replay a game record and print every decision")
    rep.add_argument("record", help="game record (JSON or share link) file, or - for stdin")
    rep.set_defaults(func=run_replay)


def describe(replay: Replay) -> Iterator[str]:
    """The lines both commands print for a replayed or self-played game."""
    state = replay.start
    yield f"{state.game}: P{state.turn + 1} to break"
    for n, step in enumerate(replay.steps, 1):
        if step.decision is None:
            yield f"#{n} P{state.turn + 1} chooses {step.action.option}"
        else:
            yield f"#{n} {step.decision.line()}"
        state = step.state
    result = f"winner P{state.winner + 1}" if state.over else "not finished"
    scores, best = state.scores, state.best
    yield f"scores {scores[0]}-{scores[1]}, best {best[0]}/{best[1]}; {result}"


def run_selfplay(args: argparse.Namespace) -> int:
    from pydantic import ValidationError

    from rules.game import Setup
    from rules.selfplay import selfplay

    try:
        setup = Setup(game=args.game, seed=args.seed, gap=args.gap, target=args.target)
    except ValidationError as exc:
        print(f"billiards selfplay: {exc.errors()[0]['msg']}", file=sys.stderr)
        return 2
    from physics import SimulationError

    try:
        record, replay = selfplay(setup, max_inputs=args.max_inputs)
    except SimulationError as exc:
        print(f"billiards selfplay: the engine failed: {exc}", file=sys.stderr)
        return 1
    for line in describe(replay):
        print(line)
    if args.link:
        from rules.compact import encode

        print(encode(record))
    if args.record:
        with open(args.record, "w", encoding="utf-8") as fh:
            fh.write(record.to_json())
    return 0


def read_record(text: str) -> GameRecord:
    """A JSON record, or a share link (anything not starting with '{')."""
    from rules.compact import decode
    from rules.record import GameRecord

    if text.lstrip().startswith("{"):
        return GameRecord.from_json(text)
    return decode(text)


def run_replay(args: argparse.Namespace) -> int:
    from pydantic import ValidationError

    from physics import SceneError, SimulationError
    from rules.codes import RuleError
    from rules.record import replay

    try:
        if args.record == "-":
            text = sys.stdin.read()
        else:
            with open(args.record, encoding="utf-8") as fh:
                text = fh.read()
        result = replay(read_record(text))
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(x) for x in first["loc"])
        print(f"billiards replay: invalid record: {where}: {first['msg']}", file=sys.stderr)
        return 2
    except (OSError, UnicodeDecodeError, RuleError, SceneError, SimulationError) as exc:
        print(f"billiards replay: {exc}", file=sys.stderr)
        return 2
    for line in describe(result):
        print(line)
    return 0
