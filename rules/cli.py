"""`billiards selfplay GAME [--seed N]` and `billiards replay RECORD.json`.

Both print the same thing, one line per input: the referee's decision on each shot and each
choice made, then the final scores. selfplay can save its record (--record FILE), and replaying
that file prints exactly the lines selfplay printed. The only module of `rules` that does I/O.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rules.record import Replay

GAMES = ("nineball", "eightball", "snooker", "three_cushion")


def register(sub: argparse._SubParsersAction) -> None:
    play = sub.add_parser("selfplay", help="play a whole game between two simple shot pickers")
    play.add_argument("game", choices=GAMES)
    play.add_argument("--seed", type=int, default=0, help="rack seed (default 0)")
    play.add_argument("--gap", type=float, default=0.0002, help="largest gap in the rack (m)")
    play.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    play.add_argument("--max-inputs", type=int, default=400, help="stop after this many inputs")
    play.add_argument("--record", help="write the game record (JSON) to this file")
    play.set_defaults(func=run_selfplay)
    rep = sub.add_parser("replay", help="replay a game record and print every decision")
    rep.add_argument("record", help="game record JSON file, or - for stdin")
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
    if args.record:
        with open(args.record, "w", encoding="utf-8") as fh:
            fh.write(record.to_json())
    return 0


def run_replay(args: argparse.Namespace) -> int:
    from pydantic import ValidationError

    from physics import SceneError, SimulationError
    from rules.record import GameRecord, replay
    from rules.state import RuleError

    try:
        if args.record == "-":
            text = sys.stdin.read()
        else:
            with open(args.record, encoding="utf-8") as fh:
                text = fh.read()
        result = replay(GameRecord.from_json(text))
    except (OSError, ValidationError, RuleError, SceneError, SimulationError) as exc:
        print(f"billiards replay: {exc}", file=sys.stderr)
        return 2
    for line in describe(result):
        print(line)
    return 0
