"""Direct challenges: one player asks another, present in the lobby, to a game with chosen
options; the other accepts (a table is made for both, through the ordinary table path) or
declines; the challenger may cancel; a challenge lapses when either player leaves. A player
may challenge another a few times, then once a minute (`PAIR_LIMIT`).

"Leaving" is seen the way quick match sees it: a page that shows challenges polls
`GET /api/challenges` every `QUICK_POLL` seconds, which keeps its player present in the lobby
for `QUICK_LAPSE` seconds; a pending challenge one of whose players is no longer present is
settled as lapsed the next time either side looks (storage invariant 14 makes every
settlement happen once). Every change goes to both players' channels as a `challenge`
message, and an accepted challenge also as `paired`, which the pages already follow.
"""

from __future__ import annotations

import time

from server.game import tables
from server.game.actor import take
from server.game.challenge_record import ChallengeRecord
from server.game.lobby import Lobby, new_seed
from server.game.publisher import Publisher
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import (
    CHALLENGES_PENDING,
    QUICK_LAPSE,
    derived_table_id,
    new_challenge_id,
    player_channel,
)
from server.protocol.models import (
    Challenge,
    ChallengeCreate,
    ChallengeList,
    ChallengeMessage,
    ChallengeStatus,
    GameChoice,
    PairedMessage,
    PlayerInfo,
    TableCreate,
)
from server.relay import RateLimiter
from server.storage import Storage

#: Challenges one player may send another: `PAIR_LIMIT[1]` at once, then one every
#: 1 / `PAIR_LIMIT[0]` seconds, whatever became of them. Each is an alert on the other's page;
#: before, creating and cancelling in a loop sent one player 29 alerts in 40 s.
PAIR_LIMIT = (1 / 60.0, 3)


def challenge_table_id(challenge_id: str) -> str:
    """The table of an accepted challenge: one, whoever and however often it is accepted."""
    return derived_table_id("challenge", challenge_id)


class Challenges:
    def __init__(self, storage: Storage, publisher: Publisher, lobby: Lobby) -> None:
        self._storage = storage
        self._publisher = publisher
        self._lobby = lobby
        #: Challenges from one player to another (this process): a few, then one a minute.
        self._pairs = RateLimiter(*PAIR_LIMIT)

    async def create(self, player: PlayerInfo, body: ChallengeCreate) -> Challenge:
        """A new challenge from `player`, announced to both players."""
        if body.to == player.id:
            raise ServiceError(ErrorCode.ILLEGAL_INPUT, "you cannot challenge yourself")
        challenged = await self._storage.get_player(body.to)
        if challenged is None:
            raise ServiceError(ErrorCode.NOT_FOUND, "no such player")
        if not await self._storage.in_lobby(challenged.id, time.time()):
            raise ServiceError(
                ErrorCode.WRONG_PHASE, f"{challenged.name} is not in the lobby: challenge later"
            )
        take(self._pairs, f"{player.id}>{challenged.id}")
        mine = await self.pending(player)
        if sum(c.challenger.id == player.id for c in mine.challenges) >= CHALLENGES_PENDING:
            raise ServiceError(
                ErrorCode.RATE_LIMITED, f"at most {CHALLENGES_PENDING} challenges wait at once"
            )
        choice = GameChoice(**body.model_dump(exclude={"to", "shot_clock"}))
        record = ChallengeRecord(
            id=new_challenge_id(),
            challenger=player,
            challenged=challenged,
            choice=choice,
            shot_clock=body.shot_clock,
            created=time.time(),
        )
        await self._storage.add_challenge(record)
        await self._announce(record)
        return record.wire()

    async def pending(self, player: PlayerInfo) -> ChallengeList:
        """The player's pending challenges (it is present in the lobby from now); those whose
        other player has left are settled as lapsed first."""
        now = time.time()
        await self._storage.touch_lobby(player.id, now + QUICK_LAPSE)
        still = []
        for record in await self._storage.pending_challenges(player.id):
            if await self._lapsed(record, now):
                await self._settle(record, ChallengeStatus.LAPSED)
            else:
                still.append(record.wire())
        return ChallengeList(challenges=still)

    async def answer(self, player: PlayerInfo, challenge_id: str, to: ChallengeStatus) -> Challenge:
        """Accept or decline (the challenged player) or cancel (the challenger)."""
        record = await self._storage.get_challenge(challenge_id)
        if record is None:
            raise ServiceError(ErrorCode.NOT_FOUND, "no such challenge")
        who = record.challenger if to is ChallengeStatus.CANCELLED else record.challenged
        if who.id != player.id:
            raise ServiceError(ErrorCode.FORBIDDEN, f"this challenge is not yours to {to.value}")
        if record.status is ChallengeStatus.PENDING and await self._lapsed(record, time.time()):
            await self._settle(record, ChallengeStatus.LAPSED)
            raise ServiceError(ErrorCode.WRONG_PHASE, "the challenge lapsed: a player left")
        if record.status is not ChallengeStatus.PENDING:
            raise ServiceError(ErrorCode.WRONG_PHASE, f"the challenge is {record.status.value}")
        settled = await self._settle(record, to)
        if settled is None:  # settled meanwhile by another request
            raise ServiceError(ErrorCode.WRONG_PHASE, "the challenge was settled meanwhile")
        return settled.wire()

    async def _lapsed(self, record: ChallengeRecord, now: float) -> bool:
        present = [
            await self._storage.in_lobby(p.id, now) for p in (record.challenger, record.challenged)
        ]
        return not all(present)

    async def _settle(self, record: ChallengeRecord, to: ChallengeStatus) -> ChallengeRecord | None:
        """Store the challenge settled (once: None if it was settled already); an accepted one
        gets its table, and both players hear of it."""
        table = challenge_table_id(record.id) if to is ChallengeStatus.ACCEPTED else None
        settled = record.model_copy(update={"status": to, "table": table})
        if not await self._storage.settle_challenge(settled):
            return None
        if table is not None:
            await self._make_table(settled)
        await self._announce(settled)
        return settled

    async def _make_table(self, record: ChallengeRecord) -> None:
        """The accepted challenge's match: the challenger breaks."""
        assert record.table is not None
        create = TableCreate(**record.choice.model_dump(), shot_clock=record.shot_clock)
        table = tables.new_table(record.table, create, record.challenger, new_seed())
        try:
            await self._storage.create_table(tables.join(table, record.challenged))
        except ValueError:
            return  # made already
        self._lobby.changed()

    async def _announce(self, record: ChallengeRecord) -> None:
        message = ChallengeMessage(challenge=record.wire())
        for player in (record.challenger, record.challenged):
            await self._publisher.publish(player_channel(player.id), message)
            if record.table is not None:
                paired = PairedMessage(table=record.table)
                await self._publisher.publish(player_channel(player.id), paired)
