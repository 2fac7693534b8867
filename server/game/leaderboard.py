"""The leaderboard of the highest breaks per game, and the verification of claimed breaks.

Breaks enter two ways, and every entry says which (`source`, docs/protocol.md):

- **played on this server** (`match`, `practice`): at the end of every rack played here
  (finished, or the rack being played when a match ended by a resignation or a claim), each
  seated person's best break of the rack, with the rack's replay;
- **submitted** (`claim`): a player (a token) claims a break from a game record played
  anywhere, perhaps by a program (`billiards selfplay`). The server replays the record through
  its own engine and referees and accepts the claim only if the record replays (every input
  legal and in bounds, the engine version this server runs) and its best break is exactly the
  claimed score. The entry carries the claiming player's name and id: nobody enters a break
  under another's name. A refused claim stores nothing and says why.

The default board lists both kinds, each entry marked with its source: a submitted break was
verified shot by shot like a played one, and the mark lets a reader weigh it.

One break, one entry: a break is identified by what was played, the position its visit
started from and the visit's inputs (`server.game.visits`), not by the record it came in, so
a record cut after the best visit, extended by an input, or (three-cushion) replayed under
another seed is the same break and refused as a duplicate; only the game's standard rack
counts (a claim whose setup has a rack gap, another three-cushion target, fewer reds or a
smaller pool table is refused, and one from a set-up position with its own code,
`set_up_position`: a practice position is never ranked).

Claims cost a worker seconds, so the cheap refusals come first (server/http/api.py,
`claim_break`, then here): the token; the claim's rate per player (`LIMITS["claim"]`,
server/game/service.py); the worker time left to the player and to its address (at most
`CLAIM_SECONDS` per minute each, `WorkBudget`, charged with the replays and with the time
parsing the claims took) and the event loop's share for parsing all claims (`PARSE_SECONDS`),
before the body is read and again once it is in; a body whose very
bytes were refused before as a duplicate or a mismatch (`refused_before`), before it is
parsed; the setup; the verdict of a record replayed here before (remembered by its digest:
a repeated claim, duplicate or wrong, costs no replay); and only then a replay, in the
background worker (server/game/workers.py), at most `MAX_VERIFYING` at once per process.

What a break is: snooker's points in one visit and three-cushion's run as the referees count
them, and in nine-ball and eight-ball the balls pocketed in one visit without a foul: each
player's `State.best`, which the referees keep. After each new entry that enters the game's
top breaks, they are published on the `public-leaderboard` channel. Breaks are never removed,
so the lowest score of a full top can only rise: an entry below the lowest this process last
read cannot be in the top, and its rack's end neither reads the top nor publishes it.
"""

from __future__ import annotations

import hashlib
import time
from collections import OrderedDict

from pydantic import ValidationError

from server.game import refereeing, tables
from server.game.budget import WorkBudget
from server.game.identity import name_key
from server.game.publisher import Publisher
from server.game.replays import rack_replay, record_refused, replay_url
from server.game.tables import TableRecord
from server.game.workers import WorkerPool
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import LEADERBOARD, SIZED_GAMES, new_replay_id
from server.protocol.models import (
    BreakEntry,
    ClaimRequest,
    ClaimVerdict,
    Leaderboard,
    LeaderboardMessage,
    Mode,
    PlayerInfo,
    RankedOptions,
    ReplayView,
    Source,
    TableOptions,
)
from server.storage import Storage

#: Claims replayed at once per process (a long record keeps a worker busy for seconds); more
#: are refused with 429 so that claims cannot starve the matches of workers.
MAX_VERIFYING = 1
#: Seconds of worker time per minute the claims of one player, or of one address, may take.
CLAIM_SECONDS = 10.0
#: Seconds per minute that parsing claims may hold this process's event loop, all claimants
#: together: a 1 MiB record takes about 80 ms to parse, and the holders' own buckets bound each
#: of them, not how many there are. Past it every claim waits (429) and the matches do not.
PARSE_SECONDS = 3.0
#: The one holder of `PARSE_SECONDS`.
EVERYONE = "everyone"
#: Verdicts of replayed records remembered per process (a repeated claim is refused from here).
KNOWN_RECORDS = 4096
#: Breaks a leaderboard answer or message lists by default, and at most.
TOP, MOST = 20, 100


def ranked(options: TableOptions, position: refereeing.Position | None = None) -> bool:
    """Whether a table's breaks are ranked: the boards rank each game as the rules set it out
    (snooker with 15 reds, three-cushion to 15 points, pool on the 9 ft table) from the game's
    own rack; a break at other options or from a set-up `position` (practice) keeps its replay
    but is not compared with those."""
    standard = (
        options.reds == refereeing.REDS_FULL
        and options.target in (0, refereeing.DEFAULT_TARGET)
        and options.size == refereeing.STANDARD_SIZE
    )
    return standard and position is None


def ranked_options(game: str) -> RankedOptions:
    """The options a game's board ranks (`ranked`): the standard ones, from the game's rack."""
    return RankedOptions(
        reds=refereeing.REDS_FULL if game == "snooker" else None,
        target=refereeing.DEFAULT_TARGET if game == "three_cushion" else None,
        size=refereeing.STANDARD_SIZE if game in SIZED_GAMES else None,
    )


class Breaks:
    def __init__(self, storage: Storage, pool: WorkerPool, publisher: Publisher) -> None:
        self._storage = storage
        self._pool = pool
        self._publisher = publisher
        self._verifying = 0
        #: Worker seconds each player and address may spend on claims per minute.
        self.budget = WorkBudget(CLAIM_SECONDS, "your claims")
        #: The event loop's time all claims may spend parsing per minute.
        self.parsing = WorkBudget(PARSE_SECONDS, "claims from everyone")
        #: Records replayed for claims by this process (what the cheap refusals save).
        self.replayed = 0
        #: Refusals any claimant gets, by the digest of the claim's bytes (`refused_before`).
        self._refused: OrderedDict[bytes, ServiceError] = OrderedDict()
        #: The verdicts of the last records replayed (by the digest of their JSON).
        self._known: OrderedDict[bytes, refereeing.Verified | ServiceError] = OrderedDict()
        #: Each game's lowest score of a full top, as this process last read it (module
        #: docstring: the true one is at least as high).
        self._floor: dict[str, int] = {}

    async def top(self, game: str, limit: int = TOP) -> Leaderboard:
        breaks = await self._storage.top_breaks(game, min(limit, MOST))
        return Leaderboard(game=game, ranks=ranked_options(game), breaks=breaks)

    async def _announce(self, game: str, scores: list[int]) -> None:
        """Publish the game's top breaks after new entries of these `scores`, unless every one
        is below the top's lowest score (it cannot have entered it, module docstring)."""
        floor = self._floor.get(game)
        if not scores or (floor is not None and max(scores) < floor):
            return
        top = await self._storage.top_breaks(game, TOP)
        if len(top) == TOP:
            self._floor[game] = top[-1].score
        await self._publisher.publish(LEADERBOARD, LeaderboardMessage(game=game, breaks=top))

    async def rack_played(self, record: TableRecord, archive: refereeing.RackArchive) -> ReplayView:
        """Store the replay of the table's current rack and its players' best breaks (each
        break once: the same visit from the same position, played or claimed before, is not
        entered again). The rack may be unfinished (a match ended off the table): its record
        then replays to the position it stopped at, with no winner.

        archive: the rack's record, best breaks and their keys (`refereeing.rack_archive`, of
        at least one input played, made by the table's worker pool)."""
        replay = rack_replay(record, archive.record, archive.best)
        best, keys = archive.best, archive.keys
        await self._storage.add_replay(replay)
        if not ranked(record.options, record.position):
            return replay
        source = Source.PRACTICE if record.mode is Mode.PRACTICE else Source.MATCH
        if record.mode is Mode.PRACTICE:  # one person played every visit
            seat = 0 if best[0] >= best[1] else 1
            best, keys = (best[seat], 0), (keys[seat], None)
        added: list[int] = []
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
            key = keys[seat]
            assert key is not None  # a break above zero was scored in some visit
            if await self._storage.add_break(entry, break_storage_key(key)):
                added.append(entry.score)
        await self._announce(record.game, added)
        return replay

    def may_parse(self, *holders: str) -> None:
        """RATE_LIMITED if `holders` (a player, an address) have spent their claims' time, or
        all claims the event loop's share for parsing them."""
        self.budget.check(*holders)
        self.parsing.check(EVERYONE)

    def parsed(self, seconds: float, *holders: str) -> None:
        """Charge a parse that took `seconds` to `holders` and to the event loop's share."""
        self.budget.charge(seconds, *holders)
        self.parsing.charge(seconds, EVERYONE)

    def refused_before(self, body: bytes) -> None:
        """Refuse at once a claim whose very bytes were refused as a duplicate or a mismatch
        (refusals that do not depend on who claims): no parsing, no replay."""
        known = self._refused.get(hashlib.sha256(body).digest())
        if known is not None:
            raise known

    async def claim(
        self, player: PlayerInfo, address: str, claim: ClaimRequest, body: bytes = b""
    ) -> ClaimVerdict:
        """Verify a break `player` claims (from `address`); ServiceError says why it is refused.

        Cheap refusals come first (module docstring): a setup that is not the game's standard,
        a holder out of worker time, a record already verified here; only then a replay.
        `body`: the request's bytes, remembered with a refusal that any claimant would get."""
        try:
            return await self._claim(player, address, claim)
        except ServiceError as error:
            if error.code in (ErrorCode.DUPLICATE, ErrorCode.CLAIM_MISMATCH) and body:
                self._refused[hashlib.sha256(body).digest()] = error
                if len(self._refused) > KNOWN_RECORDS:
                    self._refused.popitem(last=False)
            raise

    async def _claim(self, player: PlayerInfo, address: str, claim: ClaimRequest) -> ClaimVerdict:
        if claim.name is not None and name_key(claim.name) != name_key(player.name):
            raise ServiceError(
                ErrorCode.FORBIDDEN, f"a claim is entered under your own name, {player.name!r}"
            )
        setup = claim.record.setup
        if setup.game != claim.game:
            raise ServiceError(
                ErrorCode.CLAIM_MISMATCH, f"the record is a {setup.game} game, not {claim.game}"
            )
        if setup.set_up:
            raise ServiceError(
                ErrorCode.SET_UP_POSITION,
                "the record starts from a set-up position: its breaks are not ranked",
            )
        standard = setup.reds == refereeing.REDS_FULL and setup.size == refereeing.STANDARD_SIZE
        if setup.gap != 0.0 or setup.target != 0 or not standard:
            raise ServiceError(
                ErrorCode.CLAIM_MISMATCH,
                "only the game's standard rack counts (no gap, the default target, 15 reds, "
                "the 9 ft table)",
            )
        await self._beats_own_best(player, claim)
        record_json = claim.record.model_dump_json().encode()
        verified = await self._verified(record_json, player.id, address)
        best = max(verified.best)
        if claim.score != best:
            raise ServiceError(
                ErrorCode.CLAIM_MISMATCH,
                f"the record's best break is {best}, not {claim.score}",
            )
        return await self._enter(player, claim, verified)

    async def _beats_own_best(self, player: PlayerInfo, claim: ClaimRequest) -> None:
        """DUPLICATE unless the claim beats the player's best break on the game's board: a
        player's claims climb (before, one break whose last shot was turned by 0.0001 degree
        again and again, a new break each time by its inputs, filled the board)."""
        own = await self._storage.best_break(claim.game, player.name)
        if own is not None and own.player == player.id and own.score >= claim.score:
            raise ServiceError(
                ErrorCode.DUPLICATE,
                f"your best {claim.game} break here is {own.score}: a claim must beat it",
            )

    async def _verified(self, record_json: bytes, *holders: str) -> refereeing.Verified:
        """The record's replay verdict: remembered if this process replayed the same record
        before (so a repeated claim costs a look-up), else replayed in the background pool and
        charged to `holders`' worker time."""
        digest = hashlib.sha256(record_json).digest()
        if (known := self._known.get(digest)) is not None:
            self._known.move_to_end(digest)
            if isinstance(known, ServiceError):
                raise known
            return known
        self.budget.check(*holders)
        if self._verifying >= MAX_VERIFYING:
            raise ServiceError(ErrorCode.RATE_LIMITED, "claims are being verified: retry soon")
        self._verifying += 1
        self.replayed += 1
        began = self.budget.clock()
        try:
            verdict: refereeing.Verified | ServiceError = await self._pool.verify(record_json)
        except refereeing.NOT_REPLAYED as error:
            verdict = record_refused(error)
        except (ValueError, ValidationError) as error:
            verdict = ServiceError(ErrorCode.BAD_REQUEST, f"unreadable record: {error}")
        finally:
            self._verifying -= 1
            self.budget.charge(self.budget.clock() - began, *holders)
        self._known[digest] = verdict
        if len(self._known) > KNOWN_RECORDS:
            self._known.popitem(last=False)
        if isinstance(verdict, ServiceError):
            raise verdict
        return verdict

    async def _enter(
        self, player: PlayerInfo, claim: ClaimRequest, verified: refereeing.Verified
    ) -> ClaimVerdict:
        """Store a verified claim's break under its identity, unless that break is stored."""
        seat = 0 if verified.best[0] >= verified.best[1] else 1
        key = verified.keys[seat]
        assert key is not None  # a break above zero was scored in some visit
        replay_id = new_replay_id()
        replay = ReplayView(
            id=replay_id,
            url=replay_url(replay_id),
            table=None,
            rack=1,
            game=verified.game,
            players=[player, None] if seat == 0 else [None, player],
            best=verified.best,
            record=claim.record,
            created=time.time(),
        )
        entry = BreakEntry(
            game=verified.game,
            score=verified.best[seat],
            name=player.name,
            player=player.id,
            replay=replay_id,
            source=Source.CLAIM,
            at=time.time(),
        )
        if not await self._storage.add_break(entry, break_storage_key(key)):
            raise ServiceError(ErrorCode.DUPLICATE, "this break is on the leaderboard already")
        await self._storage.add_replay(replay)
        await self._announce(verified.game, [entry.score])
        return ClaimVerdict(accepted=True, entry=entry, replay=replay)


def break_storage_key(key: str) -> str:
    """The storage key of a break (`server.game.visits.break_key`): one entry per break,
    however it entered."""
    return f"break:{key}"
