"""`billiards selfplay GAME [--seed N]`, `billiards replay RECORD` and `billiards arena GAME`.

Both print the same thing, one line per input: the referee's decision on each shot and each
choice made, then the final scores. selfplay can save its record (--record FILE, JSON; --link
prints the compact share-link form), and replaying that file prints exactly the lines selfplay
printed. replay reads a JSON record or a share link, and refuses (exit status 2, one line on
stderr naming the input) a record that does not replay to the game it states. The only module
of `rules` that does I/O.

arena plays games between two choosers (rules.bot.chooser: picker, mcts, bot, bot:N) under one
execution noise and prints each side's results (rules.bot.arena), progress on stderr.
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
    play.add_argument(
        "--gap",
        type=float,
        default=0.0,
        help="largest gap in the rack (m; default 0, the server's racks: a claim needs it)",
    )
    play.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    play.add_argument("--max-inputs", type=int, default=400, help="stop after this many inputs")
    play.add_argument("--record", help="write the game record (JSON) to this file")
    play.add_argument("--link", action="store_true", help="print the record as a share link")
    play.set_defaults(func=run_selfplay)
    rep = sub.add_parser("replay", help="replay a game record and print every decision")
    rep.add_argument("record", help="game record (JSON or share link) file, or - for stdin")
    rep.set_defaults(func=run_replay)
    register_arena(sub)


def register_arena(sub: argparse._SubParsersAction) -> None:
    arena = sub.add_parser(
        "arena", help="play games between two choosers (picker, mcts, bot, bot:N)"
    )
    arena.add_argument("game", choices=[g.value for g in Game])
    arena.add_argument("--a", default="bot", help="first chooser (default: bot)")
    arena.add_argument("--b", default="picker", help="second chooser (default: picker)")
    arena.add_argument("--games", type=int, default=10, help="games to play (default 10)")
    arena.add_argument("--seed", type=int, default=0, help="arena seed (default 0)")
    arena.add_argument(
        "--noise", type=float, default=1.0, help="execution noise, factor of the tournament's"
    )
    arena.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    arena.add_argument("--max-inputs", type=int, default=400, help="inputs before a game stops")
    arena.add_argument("--workers", type=int, default=1, help="worker processes per bot")
    arena.add_argument("--json", action="store_true", help="print the result as one JSON object")
    arena.set_defaults(func=run_arena)


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


def arena_lines(result: dict) -> Iterator[str]:
    """The table `billiards arena` prints."""
    yield f"{result['game']}: {result['games']} games, {result['unfinished']} unfinished"
    yield (
        f"{'chooser':<10}{'wins':>6}  {'95% CI':<14}{'per visit':>10}{'run-outs':>10}"
        f"{'highest':>9}{'mean s':>9}{'p95 s':>8}{'sims':>7}"
    )
    for key in ("a", "b"):
        s = result[key]
        ci = f"[{s['ci95'][0]:.2f}, {s['ci95'][1]:.2f}]"
        yield (
            f"{s['name']:<10}{s['wins']:>6}  {ci:<14}{s['per_visit']:>10.2f}{s['run_outs']:>10}"
            f"{s['highest']:>9}{s['decision_mean_s']:>9.3f}{s['decision_p95_s']:>8.3f}"
            f"{s['simulations_mean']:>7.0f}"
        )
    for key in ("a", "b"):
        s = result[key]
        if s["losses"]:
            why = ", ".join(f"{k} {n}" for k, n in s["losses"].items())
            yield f"{s['name']} lost: {why}"


def run_arena(args: argparse.Namespace) -> int:
    import json

    from rules.bot.arena import arena
    from rules.bot.chooser import chooser
    from rules.bot.noise import tournament

    if args.games < 1 or args.max_inputs < 1 or args.workers < 1:
        print("billiards arena: --games, --max-inputs and --workers must be >= 1", file=sys.stderr)
        return 2
    try:
        noise = tournament(args.noise)
        a = chooser(args.a, 2 * args.seed + 1, expect=args.noise, workers=args.workers)
        b = chooser(args.b, 2 * args.seed + 2, expect=args.noise, workers=args.workers)
    except ValueError as exc:
        print(f"billiards arena: {exc}", file=sys.stderr)
        return 2

    def progress(i, game, sa, sb) -> None:
        won = "unfinished" if game.winner is None else f"won by seat {game.winner + 1}"
        print(
            f"game {i + 1}/{args.games}: {won} after {game.inputs} inputs; "
            f"{sa.name} {sa.wins} - {sb.wins} {sb.name}",
            file=sys.stderr,
            flush=True,
        )

    try:
        result = arena(
            Game(args.game),
            a,
            b,
            args.games,
            args.seed,
            noise,
            target=args.target,
            max_inputs=args.max_inputs,
            progress=progress,
        )
    finally:
        a.close()
        b.close()
    if args.json:
        print(json.dumps(result))
    else:
        for line in arena_lines(result):
            print(line)
    return 0
