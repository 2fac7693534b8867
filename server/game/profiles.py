"""A player's profile: ratings and their history, recent matches (server/game/history.py), best
breaks and when it was last seen, as the profile page and `GET /api/players/{id}/profile` show
them; and what a display name stands for (`GET /api/players/named/{name}`).

A name is unique only among players online (server/game/identity.py): once a claim lapses,
another player may take the name. So a name stands for the player who holds it now, or, when
nobody does, the player who held it last; names that read the same (`name_key`: `alice`,
`AIice`) are one name. A player's other, older holders keep their profiles under their ids.
"""

from __future__ import annotations

import time

from server.game.history import MatchResult
from server.game.identity import name_key
from server.game.ratings import Rating
from server.game.tables import bot_player
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import BOT_LEVELS, GAMES, PROFILE_HISTORY
from server.protocol.models import (
    BotInfo,
    BotList,
    PlayerInfo,
    PlayerProfile,
    ProfileMatch,
    RatingPoint,
    RatingView,
)
from server.storage import Storage

#: Matches a profile lists.
RECENT = 50


def rating_view(rating: Rating) -> RatingView:
    return RatingView(**rating.model_dump(), provisional=rating.provisional)


def seen_from(result: MatchResult, player_id: str) -> ProfileMatch:
    """A match result from one of its players' side: a private match's without its table or
    replays (profiles are public: before, a private table's id on them led anyone to its
    rematch being played)."""
    me = result.seat_of(player_id)
    them = 1 - me
    return ProfileMatch(
        table=None if result.private else result.table,
        game=result.game,
        at=result.at,
        opponent=result.seats[them],
        won=result.winner == me,
        ended=result.ended,
        score=(result.racks_won[me], result.racks_won[them]),
        rating_before=result.before[me].rating,
        rating_after=result.after[me].rating,
        replays=[] if result.private else list(result.replays),
    )


def rating_history(results: list[MatchResult], player_id: str) -> list[RatingPoint]:
    """The player's rating after each of `results` (newest first), oldest first: the graph."""
    points = []
    for result in reversed(results):
        after = result.after[result.seat_of(player_id)]
        points.append(
            RatingPoint(
                game=result.game, at=result.at, rating=after.rating, deviation=after.deviation
            )
        )
    return points


async def bots(storage: Storage) -> BotList:
    """The bots, weakest first, each with its ratings (bots are rated like anyone)."""
    listed = []
    for bot, (level, name) in sorted(BOT_LEVELS.items(), key=lambda item: item[1][0]):
        rated = await storage.ratings(bot_player(bot).id)
        ratings = {game: rating_view(r) for game, r in rated.items()}
        listed.append(BotInfo(id=bot, level=level, name=name, ratings=ratings))
    return BotList(bots=listed)


async def named(storage: Storage, name: str) -> PlayerInfo:
    """The player a display name stands for (module docstring); NOT_FOUND if nobody holds or
    held it (or its last holder, a guest, has expired)."""
    holder = await storage.name_holder(name_key(name))
    player = await storage.get_player(holder[0]) if holder is not None else None
    if player is None:
        raise ServiceError(ErrorCode.NOT_FOUND, f"no player holds or last held the name {name!r}")
    return player


async def _online(storage: Storage, player: PlayerInfo) -> bool:
    holder = await storage.name_holder(name_key(player.name))
    return holder is not None and holder[0] == player.id and holder[1] >= time.time()


async def profile(storage: Storage, player_id: str) -> PlayerProfile:
    """The profile of a player; NOT_FOUND if there is no such player."""
    player = await storage.get_player(player_id)
    if player is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such player")
    ratings = {game: rating_view(r) for game, r in (await storage.ratings(player.id)).items()}
    results = await storage.results(player.id, PROFILE_HISTORY)
    breaks = {game: await storage.best_break(game, player.name) for game in GAMES}
    return PlayerProfile(
        player=player,
        ratings=ratings,
        matches=[seen_from(result, player.id) for result in results[:RECENT]],
        # The boards rank names; a name passes to whoever registers it once it lapses, so
        # only a break the player made is theirs (before, a name's next holder showed the
        # breaks of the one before).
        best_breaks={
            game: entry
            for game, entry in breaks.items()
            if entry is not None and entry.player == player.id
        },
        history=rating_history(results, player.id),
        online=await _online(storage, player),
        last_seen=await storage.last_seen(player.id),
    )
