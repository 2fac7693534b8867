"""The leaderboard of the highest breaks per game, and the verification of claimed breaks.

Breaks enter two ways:

- **automatically**, at the end of every rack played on this server (matches, the bot's
  tables, practice): each seated person's best break of the rack, with the rack's replay;
- **by claim**: a game record, a name and the claimed score. The server replays the record
  through its own engine and referees in a worker process and accepts the claim only if the
  record replays (every input legal and in bounds, the engine version this server runs) and
  its best break is exactly the claimed score; a record already claimed is a duplicate. A
  refused claim stores nothing and says why.

What a break is: snooker's points in one visit and three-cushion's run as the referees count
them, and in nine-ball and eight-ball the balls pocketed in one visit without a foul: each
player's `State.best`, which the referees keep. After each new entry the game's top breaks
are published on the `public-leaderboard` channel.
"""

from __future__ import annotations

import hashlib
import time

from pydantic import ValidationError

from server.game import refereeing, tables
from server.game.publisher import Publisher
from server.game.refereeing import PlayerInput, State
from server.game.replays import rack_replay, record_refused, replay_url
from server.game.tables import TableRecord
from server.game.workers import WorkerPool
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import new_replay_id
from server.protocol.models import (
    BreakEntry,
    ClaimRequest,
    ClaimVerdict,
    Leaderboard,
    LeaderboardMessage,
    Mode,
    ReplayView,
    Source,
)
from server.storage import Storage

LEADERBOARD = "public-leaderboard"
#: Claims replayed at once per process (a long record keeps a worker busy for seconds); more
#: are refused with 429 so that claims cannot starve the matches of workers.
MAX_VERIFYING = 1
#: Breaks a leaderboard answer or message lists by default, and at most.
TOP, MOST = 20, 100


class Breaks:
    def __init__(self, storage: Storage, pool: WorkerPool, publisher: Publisher) -> None:
        self._storage = storage
        self._pool = pool
        self._publisher = publisher
        self._verifying = 0

    async def top(self, game: str, limit: int = TOP) -> Leaderboard:
        breaks = await self._storage.top_breaks(game, min(limit, MOST))
        return Leaderboard(game=game, breaks=breaks)

    async def _announce(self, game: str) -> None:
        top = await self._storage.top_breaks(game, TOP)
        await self._publisher.publish(LEADERBOARD, LeaderboardMessage(game=game, breaks=top))

    async def rack_finished(
        self,
        record: TableRecord,
        played: list[tuple[PlayerInput, State]],
    ) -> ReplayView:
        """Store the rack's replay and its players' best breaks (once per rack and seat).

        played: each input of the rack that was played (void ones left out), with the state it
        led to (the last one's `best` is each player's best break of the rack)."""
        options = record.options
        setup = refereeing.rack_setup(
            record.game,
            record.seed + record.rack,
            record.breaker,
            reds=options.reds,
            target=options.target,
        )
        game_record = refereeing.rack_record(setup, played)
        replay, best = rack_replay(record, game_record, played[-1][1])
        await self._storage.add_replay(replay)
        source = Source.PRACTICE if record.mode is Mode.PRACTICE else Source.MATCH
        if record.mode is Mode.PRACTICE:  # one person played every visit
            best = (max(best), 0)
        added = False
        for seat, occupant in enumerate(record.seats):
            if occupant is None or tables.is_bot(occupant) or best[seat] <= 0:
                continue
            entry = BreakEntry(
                game=record.game,
                score=best[seat],
                name=occupant.name,
                player=occupant.id,
                replay=replay.id,
                source=source,
                at=time.time(),
            )
            added |= await self._storage.add_break(entry, f"{record.id}:{record.rack}:{seat}")
        if added:
            await self._announce(record.game)
        return replay

    async def claim(self, claim: ClaimRequest) -> ClaimVerdict:
        """Verify a claimed break by replaying its record; ServiceError says why it is refused."""
        if self._verifying >= MAX_VERIFYING:
            raise ServiceError(ErrorCode.RATE_LIMITED, "claims are being verified: retry soon")
        record_json = claim.record.model_dump_json()
        self._verifying += 1
        try:
            verified = await self._pool.verify(record_json.encode())
        except refereeing.NOT_REPLAYED as error:
            raise record_refused(error) from None
        except (ValueError, ValidationError) as error:
            raise ServiceError(ErrorCode.BAD_REQUEST, f"unreadable record: {error}") from None
        finally:
            self._verifying -= 1
        if verified.game != claim.game:
            raise ServiceError(
                ErrorCode.CLAIM_MISMATCH, f"the record is a {verified.game} game, not {claim.game}"
            )
        best = max(verified.best)
        if claim.score != best:
            raise ServiceError(
                ErrorCode.CLAIM_MISMATCH,
                f"the record's best break is {best}, not {claim.score}",
            )
        replay_id = new_replay_id()
        replay = ReplayView(
            id=replay_id,
            url=replay_url(replay_id),
            table=None,
            rack=1,
            game=verified.game,
            players=[None, None],
            best=verified.best,
            record=claim.record,
            created=time.time(),
        )
        entry = BreakEntry(
            game=verified.game,
            score=best,
            name=claim.name,
            replay=replay_id,
            source=Source.CLAIM,
            at=time.time(),
        )
        digest = hashlib.sha256(record_json.encode()).hexdigest()
        if not await self._storage.add_break(entry, f"claim:{digest}"):
            raise ServiceError(ErrorCode.DUPLICATE, "this record has been claimed already")
        await self._storage.add_replay(replay)
        await self._announce(verified.game)
        return ClaimVerdict(accepted=True, entry=entry, replay=replay)
