"""A player's profile: ratings, recent matches (server/game/history.py) and best breaks, as the
profile page and `GET /api/players/{id}/profile` show them."""

from __future__ import annotations

from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import bot_player
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import BOT_LEVELS, GAMES
from server.protocol.models import BotInfo, BotList, PlayerProfile, ProfileMatch, RatingView
from server.storage import Storage

#: Matches a profile lists.
RECENT = 50


def rating_view(rating: Rating) -> RatingView:
    return RatingView(**rating.model_dump(), provisional=rating.provisional)


def seen_from(result: MatchResult, player_id: str) -> ProfileMatch:
    """A match result from one of its players' side."""
    me = result.seat_of(player_id)
    them = 1 - me
    return ProfileMatch(
        table=result.table,
        game=result.game,
        at=result.at,
        opponent=result.seats[them],
        won=result.winner == me,
        ended=result.ended,
        score=(result.racks_won[me], result.racks_won[them]),
        rating_before=result.before[me].rating,
        rating_after=result.after[me].rating,
        replays=list(result.replays),
    )


async def bots(storage: Storage) -> BotList:
    """The bots, weakest first, each with its ratings (bots are rated like anyone)."""
    listed = []
    for bot, (level, name) in sorted(BOT_LEVELS.items(), key=lambda item: item[1][0]):
        rated = await storage.ratings(bot_player(bot).id)
        ratings = {game: rating_view(r) for game, r in rated.items()}
        listed.append(BotInfo(id=bot, level=level, name=name, ratings=ratings))
    return BotList(bots=listed)


async def profile(storage: Storage, player_id: str) -> PlayerProfile:
    """The profile of a player; NOT_FOUND if there is no such player."""
    player = await storage.get_player(player_id)
    if player is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such player")
    ratings = {game: rating_view(r) for game, r in (await storage.ratings(player.id)).items()}
    results = await storage.results(player.id, RECENT)
    breaks = {game: await storage.best_break(game, player.name) for game in GAMES}
    return PlayerProfile(
        player=player,
        ratings=ratings,
        matches=[seen_from(result, player.id) for result in results],
        best_breaks={game: entry for game, entry in breaks.items() if entry is not None},
    )
