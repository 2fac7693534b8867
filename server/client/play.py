"""`billiards play`, `watch` and `submit`: a match, a table's outcomes, a claimed break.

Both talk to a server only through its public API (server/client/api_client.py). `play`
registers a guest, gets a table (quick match, a new table, a private link, practice or the
bot; with the lobby's options: race, reds, target, table size, shot clock, a shared practice
position, the bot's level), then plays every shot its seat is to play with a shot chooser
(`--bot picker`, the rules' shot pickers, by default; `--bot bot:N` the searching bot at level
N, `--bot bot` its strongest) and prints each outcome as it arrives, one line each, until the
match is over, sending the heartbeats a seated player owes meanwhile. `watch` prints a table's
outcomes until it is over. Both ride out a connection that drops (server/client/api_client.py
reconnects, resumes and resends what is safe to resend) and give up after `--patience` seconds
without an answer.
`submit` sends a game record (as `billiards selfplay --record` writes it) and the claimed
score to the leaderboard as a player: the one a token names (`--token` or BILLIARDS_TOKEN),
or a guest it registers under `--name` (a claim is entered under its player's name, never a
free one), and prints the verdict. Exit status 0 on success (for
`play` and `watch`: the match is over), 2 with one line when the server refused something (a
claim that does not hold says why) or could not be reached.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import secrets
import sys
from collections.abc import Awaitable, Callable
from functools import partial
from typing import TYPE_CHECKING

from server.protocol.models import OutcomeMessage, Status, TableCreate, TableView

#: Each table option in words, as the first line prints those that are not the defaults.
OPTION_WORDS = {
    "race_to": "race to {}",
    "shot_clock": "{} s shot clock",
    "reds": "{} reds",
    "target": "{} points",
    "size": "{} ft table",
}
#: The server's bot a `--vs-bot` table gets unless `--level` says another (the API's default).
DEFAULT_LEVEL = TableCreate.model_fields["bot"].default.value

if TYPE_CHECKING:
    import aiohttp

    from rules.bot.chooser import Chooser
    from server.client.api_client import GameClient


def outcome_line(change: TableView | OutcomeMessage, names: list[str]) -> str:
    """One line per change: the version, who acted and what the referee ruled."""
    if isinstance(change, TableView):
        line = f"v{change.version:<4} table {change.status.value}: " + " vs ".join(names)
    elif change.void:
        line = f"v{change.version:<4} {names[change.seat]}: not played ({change.void})"
    elif change.decision is None:
        option = change.input.option  # type: ignore[union-attr]
        line = f"v{change.version:<4} {names[change.seat]}: chose {option}"
    else:
        line = f"v{change.version:<4} {names[change.seat]}: {change.decision.line()}"
    if change.status is Status.OVER and change.winner is not None:
        line += f" -- match over, {names[change.winner]} wins"
    return line


def names_of(view: TableView) -> list[str]:
    return [seat.name if seat else "(empty)" for seat in view.seats]


def misplaced(args: argparse.Namespace) -> list[tuple[str, str]]:
    """Options given where they mean nothing (each with what it goes with): refused before
    anything is sent, rather than silently dropped."""
    found = []
    if args.position and not args.practice:
        found.append(("--position", "--practice"))
    if args.shot_clock is not None and not (args.create or args.practice or args.vs_bot):
        found.append(("--shot-clock", "--create, --practice or --vs-bot"))
    if args.level != DEFAULT_LEVEL and not args.vs_bot:
        found.append(("--level", "--vs-bot"))
    if args.join and game_options(args):
        found.append(("a table option", "a new table (a joined table has its own)"))
    return found


def table_words(view: TableView) -> str:
    """The game and the options it is played with that are not the defaults."""
    options = view.options.model_dump(exclude_defaults=True, exclude={"private"})
    said = [OPTION_WORDS[key].format(value) for key, value in options.items()]
    if view.position is not None:
        said.append("from a set-up position")
    return view.game + (f" ({', '.join(said)})" if said else "")


def game_options(args: argparse.Namespace) -> dict[str, int]:
    """The options asked for on the command line that shape the game (a quick match pairs
    players who chose the same); the server checks them and refuses what it does not offer."""
    asked = {"race_to": args.race_to, "reds": args.reds, "target": args.target, "size": args.size}
    return {key: value for key, value in asked.items() if value is not None}


async def _open_table(client: GameClient, args: argparse.Namespace) -> TableView:
    if args.join:
        from server.client.api_client import table_id_of

        return await client.join(table_id_of(args.join))
    game = game_options(args)
    options: dict[str, object] = dict(game)
    if args.shot_clock is not None:
        options["shot_clock"] = args.shot_clock
    if args.position:
        shared = await client.shared_position(args.position)
        options.update(position=shared.position, size=shared.size, reds=shared.reds)
    if args.practice:
        return await client.create(args.game, mode="practice", **options)
    if args.vs_bot:
        return await client.create(args.game, mode="bot", bot=args.level, **options)
    if args.create:
        view = await client.create(args.game, private=args.private, **options)
        print(f"waiting for an opponent: {client.base}/t/{view.id}", flush=True)
        return view
    status = await client.quick(args.game, **game)
    table_id = status.table if status.status == "paired" else await client.wait_paired()
    return await client.table(table_id)


async def _shoot_if_mine(
    chooser: Chooser, client: GameClient, view_id: str, change: TableView | OutcomeMessage
) -> None:
    from server.client.api_client import Refused

    nxt = change.next
    if nxt is None or nxt.player != client.player.id:
        return
    # The search runs in the client's own process, on a thread so that the heartbeats and the
    # feed's pings go on meanwhile (a long search would otherwise look like a dead client).
    action = await asyncio.to_thread(chooser.choose, change.state)
    try:
        await client.send(view_id, change.version, action.model_dump(mode="json"))
    except Refused as refusal:
        if refusal.code != "stale_version":  # stale: the feed will bring the newer state
            raise


React = Callable[["GameClient", str, TableView | OutcomeMessage], Awaitable[None]]


async def _print_changes(client: GameClient, view: TableView, react: React | None = None) -> int:
    """Print each change of the table until the match is over, reacting to each (0: over).
    The feed rides out dropped connections; if it ends before the match does (the table's
    channel was deleted), that is a failure, never a success."""
    from server.client.api_client import Refused, finished

    names = names_of(view)
    async for change in client.follow(view):
        if isinstance(change, TableView):
            names = names_of(change)
        print(outcome_line(change, names), flush=True)
        if finished(change):
            return 0
        if react is not None:
            await react(client, view.id, change)
    raise Refused(0, "closed", "the table's channel closed before the match was over")


async def play(args: argparse.Namespace) -> int:
    import aiohttp

    from rules.bot.chooser import chooser
    from server.client.api_client import Refused

    try:
        shoot = partial(_shoot_if_mine, chooser(args.bot, secrets.randbits(32)))
    except ValueError as error:
        raise Refused(0, "unknown_chooser", str(error)) from None
    if wrong := misplaced(args):
        flag, needs = wrong[0]
        raise Refused(0, "bad_arguments", f"{flag} goes with {needs}")
    async with aiohttp.ClientSession() as session:
        client = _client(args, session)
        await client.register(args.name or f"cli-{secrets.token_hex(3)}")
        view = await _open_table(client, args)
        print(f"table {view.id}: {table_words(view)}, you are {client.player.name}", flush=True)
        async with client.heartbeats(view.id):
            await shoot(client, view.id, view)
            return await _print_changes(client, view, shoot)


async def watch(args: argparse.Namespace) -> int:
    import aiohttp

    from server.client.api_client import finished, table_id_of

    # No heartbeats: they are a seated player's (the API refuses a spectator's); a spectator
    # is counted by its feed, which the client keeps open.
    async with aiohttp.ClientSession() as session:
        client = _client(args, session)
        view = await client.table(table_id_of(args.table))
        print(outcome_line(view, names_of(view)), flush=True)
        if finished(view):
            return 0
        return await _print_changes(client, view)


async def submit(args: argparse.Namespace) -> int:
    """Claim a break from a game record file; print the server's verdict."""
    import json
    from pathlib import Path

    import aiohttp

    from server.client.api_client import GameClient, Refused
    from server.protocol.models import ClaimVerdict

    try:
        record = json.loads(Path(args.record).read_text())
        game = args.game or record["setup"]["game"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise Refused(0, "unreadable_record", f"{args.record}: {error}") from None
    async with aiohttp.ClientSession() as session:
        client = GameClient(args.url, session)
        if args.token:
            client.token = args.token
        elif args.name:
            await client.register(args.name)
        else:
            raise Refused(0, "no_player", "give --name (a guest) or --token (BILLIARDS_TOKEN)")
        body = {"game": game, "record": record, "score": args.score}
        answer = await client.fetch("POST", "/api/leaderboard/claims", body)
    verdict = ClaimVerdict.model_validate_json(answer)
    entry = verdict.entry
    print(
        f"accepted: {entry.game} break of {entry.score} by {entry.name}, "
        f"replay {client.base}{verdict.replay.url}"
    )
    return 0


def _run(
    command: Callable[[argparse.Namespace], Awaitable[int]],
) -> Callable[[argparse.Namespace], int]:
    from server.client.api_client import Refused, Unreachable, one_line

    def handler(args: argparse.Namespace) -> int:
        try:
            return asyncio.run(command(args))
        except Refused as refusal:
            print(f"refused: {refusal.code}: {refusal.reason}", file=sys.stderr)
            return 2
        except (Unreachable, OSError) as error:
            print(f"cannot reach {args.url}: {one_line(error)}", file=sys.stderr)
            return 2

    return handler


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("play", help="play a whole match against a server")
    parser.add_argument("url", help="the server, e.g. http://127.0.0.1:8080")
    parser.add_argument("game", choices=("nineball", "eightball", "snooker", "three_cushion"))
    how = parser.add_mutually_exclusive_group()
    how.add_argument("--quick", action="store_true", help="quick match (the default)")
    how.add_argument("--create", action="store_true", help="open a table and wait")
    how.add_argument("--join", metavar="LINK", help="join a table by its link or id")
    how.add_argument("--practice", action="store_true", help="a solo practice table")
    how.add_argument("--vs-bot", action="store_true", help="a table against the server's bot")
    parser.add_argument("--private", action="store_true", help="with --create: not listed")
    _option_arguments(parser)
    parser.add_argument(
        "--bot", default="picker", help="shot chooser: picker (default), bot:N (level N), bot"
    )
    parser.add_argument("--name", help="display name (default: cli-<random>)")
    _patience_option(parser)
    parser.set_defaults(func=_run(play))

    parser = subparsers.add_parser("submit", help="claim a leaderboard break from a record")
    parser.add_argument("url", help="the server, e.g. http://127.0.0.1:8080")
    parser.add_argument("record", help="a game record file (billiards selfplay --record)")
    parser.add_argument("--name", help="claim as a new guest of this name")
    parser.add_argument(
        "--token",
        default=os.environ.get("BILLIARDS_TOKEN"),
        help="claim as the player of this token (default: $BILLIARDS_TOKEN)",
    )
    parser.add_argument("--score", type=int, required=True, help="the claimed best break")
    parser.add_argument("--game", help="the leaderboard (default: the record's game)")
    parser.set_defaults(func=_run(submit))

    parser = subparsers.add_parser("watch", help="print a table's outcomes as they come")
    parser.add_argument("url", help="the server, e.g. http://127.0.0.1:8080")
    parser.add_argument("table", help="the table's id or link")
    _patience_option(parser)
    parser.set_defaults(func=_run(watch))


def _option_arguments(parser: argparse.ArgumentParser) -> None:
    """The table's options, as the lobby offers them (server.protocol.ids)."""
    from server.protocol.ids import RACE_TO_MAX, SNOOKER_REDS, TABLE_SIZES, TARGET_MAX, BotName

    parser.add_argument(
        "--race-to", type=int, metavar="N", help=f"racks (frames, games) to win, 1-{RACE_TO_MAX}"
    )
    parser.add_argument("--reds", type=int, choices=SNOOKER_REDS, help="snooker's reds")
    parser.add_argument(
        "--target", type=int, metavar="N", help=f"three-cushion's points to win, 1-{TARGET_MAX}"
    )
    parser.add_argument("--size", type=int, choices=TABLE_SIZES, help="pool table size in feet")
    parser.add_argument(
        "--shot-clock", type=int, metavar="S", help="a new table's seconds per shot (0: none)"
    )
    parser.add_argument(
        "--position",
        metavar="CODE",
        help="with --practice: start from a shared position (its link's code)",
    )
    parser.add_argument(
        "--level",
        choices=[b.value for b in BotName],
        default=DEFAULT_LEVEL,
        help=f"with --vs-bot: the server's bot (picker, bot:1 ... bot:5; default {DEFAULT_LEVEL})",
    )


def _patience_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--patience",
        type=float,
        metavar="SECONDS",
        help="how long to keep trying while the server cannot be reached before exiting with "
        "status 2 (default: a minute)",
    )


def _client(args: argparse.Namespace, session: aiohttp.ClientSession) -> GameClient:
    """The API client of a command, as patient as `--patience` asks."""
    from server.client.api_client import GameClient, Patience

    patience = Patience() if args.patience is None else Patience(give_up=args.patience)
    return GameClient(args.url, session, patience)
