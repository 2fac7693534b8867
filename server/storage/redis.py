"""Storage shared by replicas: Redis through redis-py's asyncio client.

Every compare-and-set is one Lua script, so it runs atomically on the Redis server whichever
replica sends it. Keys, all prefixed `game:`:

- `t:{id}` a hash of the table: `version`, `pending` (shot id or ""), `doc`;
- `i:{id}` a hash shot id -> input entry; `l:{id}` the resolved shot ids in order;
  `rs:{id}` a hash rack -> index in `l:{id}` of the rack's first input;
- `h:{id}` the heartbeats of its seats; `listed` a sorted set of listed tables by creation;
  `deadlines` a sorted set of tables by shot-clock deadline; `expiry` a sorted set of every
  table by the time it may be dropped (`TableRecord.expires`);
- `p:{id}` players and `seen` the unrated ones by their last sign of life (invariant 15),
  `lastseen` a hash player -> its last sign of life (every player's, kept while it is);
  `n:{key}` name claims (expiring), `online` the claims by expiry, and `holders` a hash
  name key -> `<player> <until>` of its last claim (kept after the claim lapses);
- `r:{player}` a hash game -> rating (its `games` count is the compare-and-set stamp),
  `rated` the set of tables whose result was rated;
- `rp:{id}` replays; `bk` the set of break keys, `be` a hash key -> break, `lb:{game}` a
  sorted set of a game's breaks by score, `lbn:{game}` a hash name -> key of its best break;
- `q:{game}` the quick-match queues and `qs:{player}` each player's quick-match status;
- `res:{table}` a decided match's result, `hist:{player}` a sorted set of its tables by time;
- `ch:{id}` a challenge (`status`, `doc`), `chp:{player}` the ids of a player's pending ones,
  `lobby:{player}` (expiring) while the player is present in the lobby.
"""

from __future__ import annotations

import math

import redis.asyncio as aioredis
from redis.exceptions import RedisError

from server.game.challenge_record import ChallengeRecord
from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import InputEntry, TableRecord
from server.protocol.models import BreakEntry, PlayerInfo, ReplayView
from server.storage import (
    Accepted,
    AcceptResult,
    RateResult,
    Storage,
    StorageError,
    last_without_motion,
    paired,
    waiting,
    without_motion,
)
from server.storage.records import dump, load

P = "game:"

# KEYS: table, listed, deadlines, expiry. ARGV: version, doc, table id, listed (0/1), created,
# deadline ("" for none), expires.
_CREATE = """
if redis.call('EXISTS', KEYS[1]) == 1 then return 0 end
redis.call('HSET', KEYS[1], 'version', ARGV[1], 'pending', '', 'doc', ARGV[2])
if ARGV[4] == '1' then redis.call('ZADD', KEYS[2], ARGV[5], ARGV[3]) end
if ARGV[6] ~= '' then redis.call('ZADD', KEYS[3], ARGV[6], ARGV[3]) end
redis.call('ZADD', KEYS[4], ARGV[7], ARGV[3])
return 1
"""

# KEYS: table, inputs. ARGV: version, shot id, doc, entry.
_ACCEPT = """
local old = redis.call('HGET', KEYS[2], ARGV[2])
if old then return {2, old} end
local stamp = redis.call('HMGET', KEYS[1], 'version', 'pending')
if stamp[1] ~= ARGV[1] or stamp[2] ~= '' then return {1} end
redis.call('HSET', KEYS[2], ARGV[2], ARGV[4])
redis.call('HSET', KEYS[1], 'pending', ARGV[2], 'doc', ARGV[3])
return {0}
"""

# KEYS: table, inputs, log, listed, deadlines, rack starts, expiry. ARGV: expected version,
# expected pending, new version, doc, table id, listed (0/1), created, shot id to log ("" for
# none), entry, deadline ("" for none), the entry's rack, expires.
_SWAP = """
local stamp = redis.call('HMGET', KEYS[1], 'version', 'pending')
if stamp[1] ~= ARGV[1] or stamp[2] ~= ARGV[2] then return 0 end
redis.call('HSET', KEYS[1], 'version', ARGV[3], 'pending', '', 'doc', ARGV[4])
if ARGV[8] ~= '' then
  redis.call('HSET', KEYS[2], ARGV[8], ARGV[9])
  redis.call('HSETNX', KEYS[6], ARGV[11], redis.call('LLEN', KEYS[3]))
  redis.call('RPUSH', KEYS[3], ARGV[8])
end
redis.call('ZADD', KEYS[7], ARGV[12], ARGV[5])
if ARGV[6] == '1' then redis.call('ZADD', KEYS[4], ARGV[7], ARGV[5])
else redis.call('ZREM', KEYS[4], ARGV[5]) end
if ARGV[10] ~= '' then redis.call('ZADD', KEYS[5], ARGV[10], ARGV[5])
else redis.call('ZREM', KEYS[5], ARGV[5]) end
return 1
"""

# KEYS: name key, online set, seen, holders, lastseen. ARGV: player, until (s), now (s),
# ttl (ms), the name key's field in holders.
_CLAIM = """
local holder = redis.call('GET', KEYS[1])
if holder and holder ~= ARGV[1] then return 0 end
if tonumber(ARGV[4]) > 0 then
  redis.call('SET', KEYS[1], ARGV[1], 'PX', ARGV[4])
else  -- a claim that has lapsed already holds nothing (not even for a millisecond)
  redis.call('DEL', KEYS[1])
end
redis.call('ZADD', KEYS[2], ARGV[2], KEYS[1])
redis.call('ZREMRANGEBYSCORE', KEYS[2], '-inf', '(' .. ARGV[3])
redis.call('ZADD', KEYS[3], ARGV[3], ARGV[1])
redis.call('HSET', KEYS[4], ARGV[5], ARGV[1] .. ' ' .. ARGV[2])
redis.call('HSET', KEYS[5], ARGV[1], ARGV[3])
return 1
"""

# KEYS: seen. ARGV: before, limit, key prefix. Unrated players last seen before `before`
# leave (invariant 15); rated ones leave the `seen` set alone, kept for good.
_EXPIRE_PLAYERS = """
local limit = tonumber(ARGV[2])
local gone = {}
while #gone < limit do
  local ids = redis.call('ZRANGEBYSCORE', KEYS[1], '-inf', '(' .. ARGV[1], 'LIMIT', 0,
                         limit - #gone)
  if #ids == 0 then break end
  for _, id in ipairs(ids) do
    redis.call('ZREM', KEYS[1], id)
    if redis.call('EXISTS', ARGV[3] .. 'r:' .. id) == 0 then
      redis.call('DEL', ARGV[3] .. 'p:' .. id)
      redis.call('HDEL', ARGV[3] .. 'lastseen', id)
      table.insert(gone, id)
    end
  end
end
return gone
"""

# KEYS: queue, caller's status. ARGV: player, waiting status, paired status (without its
# players), status key prefix, when the wait lapses (unix ms). A waiting status expires when
# its request lapses (invariant 11), so a lapsed partner is skipped like a cancelled one.
_PAIR = """
local status = redis.call('GET', KEYS[2])
if status == ARGV[2] then
  redis.call('PEXPIREAT', KEYS[2], ARGV[5])
  return false
end
if status and string.sub(status, 1, 8) == 'waiting:' then
  redis.call('LREM', 'game:q:' .. string.sub(status, 9), 0, ARGV[1])
end
while true do
  local partner = redis.call('LPOP', KEYS[1])
  if not partner then break end
  if partner ~= ARGV[1] and redis.call('GET', ARGV[4] .. partner) == ARGV[2] then
    local status = ARGV[3] .. partner .. ':' .. ARGV[1]  -- the players in seat order
    redis.call('SET', ARGV[4] .. partner, status)
    redis.call('SET', KEYS[2], status)
    return partner
  end
end
redis.call('RPUSH', KEYS[1], ARGV[1])
redis.call('SET', KEYS[2], ARGV[2], 'PXAT', ARGV[5])
return false
"""

# KEYS: the result's key, then each player's history. ARGV: the result, its time, table id.
_ADD_RESULT = """
if redis.call('SET', KEYS[1], ARGV[1], 'NX') == false then return 0 end
for i = 2, #KEYS do redis.call('ZADD', KEYS[i], ARGV[2], ARGV[3]) end
return 1
"""

#: Invariant 16: KEYS[1] the service's hash {since, alive}; ARGV now, outage (as text: a
#: float goes through Lua's number, but is stored and answered as the text it came as).
_SERVICE_SINCE = """
local alive = tonumber(redis.call('HGET', KEYS[1], 'alive'))
local since = redis.call('HGET', KEYS[1], 'since')
local now = tonumber(ARGV[1])
if not alive or not since or now - alive > tonumber(ARGV[2]) then since = ARGV[1] end
if not alive or now > alive then redis.call('HSET', KEYS[1], 'alive', ARGV[1]) end
redis.call('HSET', KEYS[1], 'since', since)
return since
"""
# KEYS: the challenge's hash, each player's pending set. ARGV: the settled document, status,
# challenge id.
_SETTLE_CHALLENGE = """
if redis.call('HGET', KEYS[1], 'status') ~= 'pending' then return 0 end
redis.call('HSET', KEYS[1], 'status', ARGV[2], 'doc', ARGV[1])
redis.call('SREM', KEYS[2], ARGV[3])
redis.call('SREM', KEYS[3], ARGV[3])
return 1
"""

# KEYS: caller's status. ARGV: when the wait lapses (unix ms).
_TOUCH_QUICK = """
local status = redis.call('GET', KEYS[1])
if status and string.sub(status, 1, 8) == 'waiting:' then
  redis.call('PEXPIREAT', KEYS[1], ARGV[1])
end
"""

# KEYS: rated set, then one ratings hash per player. ARGV: table id, game, one rating document
# per player, then each new rating's game count. Returns 0 rated, 1 already, 2 conflict.
_RATE = """
if redis.call('SISMEMBER', KEYS[1], ARGV[1]) == 1 then return 1 end
for i = 2, #KEYS do
  local doc = redis.call('HGET', KEYS[i], ARGV[2])
  local games = doc and cjson.decode(doc)['games'] or 0
  if games + 1 ~= tonumber(ARGV[#KEYS + i]) then return 2 end
end
redis.call('SADD', KEYS[1], ARGV[1])
for i = 2, #KEYS do redis.call('HSET', KEYS[i], ARGV[2], ARGV[i + 1]) end
return 0
"""

# KEYS: expiry, listed, deadlines. ARGV: now, limit, table key prefix. Every key of a table
# goes (the per-table key names as in `RedisStorage._keys`).
_EXPIRE = """
local ids = redis.call('ZRANGEBYSCORE', KEYS[1], '-inf', ARGV[1], 'LIMIT', 0, ARGV[2])
for _, id in ipairs(ids) do
  for _, part in ipairs({'t:', 'i:', 'l:', 'rs:', 'h:'}) do
    redis.call('DEL', ARGV[3] .. part .. id)
  end
  for i = 1, 3 do redis.call('ZREM', KEYS[i], id) end
end
return ids
"""

# KEYS: keys set, entries hash, game's ranking, game's best by name. ARGV: key, entry, score,
# name.
_ADD_BREAK = """
if redis.call('SADD', KEYS[1], ARGV[1]) == 0 then return 0 end
redis.call('HSET', KEYS[2], ARGV[1], ARGV[2])
redis.call('ZADD', KEYS[3], ARGV[3], ARGV[1])
local best = redis.call('HGET', KEYS[4], ARGV[4])
if not best or tonumber(redis.call('ZSCORE', KEYS[3], best)) < tonumber(ARGV[3]) then
  redis.call('HSET', KEYS[4], ARGV[4], ARGV[1])
end
return 1
"""

# KEYS: caller's status. ARGV: player.
_CANCEL = """
local status = redis.call('GET', KEYS[1])
if not status or string.sub(status, 1, 8) ~= 'waiting:' then return 0 end
redis.call('LREM', 'game:q:' .. string.sub(status, 9), 0, ARGV[1])
redis.call('DEL', KEYS[1])
return 1
"""


class RedisStorage(Storage):
    def __init__(self, url: str) -> None:
        self._redis = aioredis.Redis.from_url(url, decode_responses=True)
        self._create = self._redis.register_script(_CREATE)
        self._accept = self._redis.register_script(_ACCEPT)
        self._swap_script = self._redis.register_script(_SWAP)
        self._claim = self._redis.register_script(_CLAIM)
        self._expire_players = self._redis.register_script(_EXPIRE_PLAYERS)
        self._pair = self._redis.register_script(_PAIR)
        self._cancel = self._redis.register_script(_CANCEL)
        self._touch_quick = self._redis.register_script(_TOUCH_QUICK)
        self._add_result = self._redis.register_script(_ADD_RESULT)
        self._settle_challenge = self._redis.register_script(_SETTLE_CHALLENGE)
        self._service_since = self._redis.register_script(_SERVICE_SINCE)
        self._rate = self._redis.register_script(_RATE)
        self._expire = self._redis.register_script(_EXPIRE)
        self._add_break = self._redis.register_script(_ADD_BREAK)

    @classmethod
    async def open(cls, url: str) -> RedisStorage:
        storage = cls(url)
        try:
            await storage._redis.ping()
        except RedisError as error:
            await storage.close()
            raise StorageError(f"Redis at {url} does not answer: {error}") from error
        return storage

    async def close(self) -> None:
        await self._redis.aclose()

    # ----- players ----------------------------------------------------------------------
    async def add_player(self, player: PlayerInfo, now: float) -> None:
        async with self._redis.pipeline(transaction=True) as pipe:
            pipe.set(f"{P}p:{player.id}", dump(player))
            pipe.zadd(f"{P}seen", {player.id: now})
            pipe.hset(f"{P}lastseen", player.id, now)
            await pipe.execute()

    async def get_player(self, player_id: str) -> PlayerInfo | None:
        doc = await self._redis.get(f"{P}p:{player_id}")
        return load(PlayerInfo, doc) if doc else None

    async def claim_name(self, key: str, player_id: str, until: float, now: float) -> bool:
        ttl_ms = math.ceil((until - now) * 1000)  # a claim for under a millisecond lasts one
        keys = [f"{P}n:{key}", f"{P}online", f"{P}seen", f"{P}holders", f"{P}lastseen"]
        return bool(await self._claim(keys=keys, args=[player_id, until, now, ttl_ms, key]))

    async def name_holder(self, key: str) -> tuple[str, float] | None:
        value = await self._redis.hget(f"{P}holders", key)
        if not value:
            return None
        player, until = value.split(" ")
        return player, float(until)

    async def last_seen(self, player_id: str) -> float | None:
        if not await self._redis.exists(f"{P}p:{player_id}"):
            return None
        seen = await self._redis.hget(f"{P}lastseen", player_id)
        return float(seen) if seen is not None else None

    async def expire_players(self, before: float, limit: int) -> list[str]:
        gone = await self._expire_players(keys=[f"{P}seen"], args=[repr(before), limit, P])
        return [i.decode() if isinstance(i, bytes) else i for i in gone]

    async def online_players(self, now: float) -> int:
        return await self._redis.zcount(f"{P}online", now, "+inf")

    async def online(self, now: float, limit: int) -> list[str]:
        keys = await self._redis.zrevrangebyscore(f"{P}online", "+inf", now, start=0, num=limit)
        holders = await self._redis.mget(keys) if keys else []
        return [holder for holder in holders if holder]  # a claim may lapse meanwhile

    # ----- tables -----------------------------------------------------------------------
    def _keys(self, table_id: str) -> list[str]:
        return [
            f"{P}t:{table_id}",
            f"{P}i:{table_id}",
            f"{P}l:{table_id}",
            f"{P}listed",
            f"{P}deadlines",
            f"{P}rs:{table_id}",
            f"{P}expiry",
        ]

    async def create_table(self, record: TableRecord) -> None:
        keys = [f"{P}t:{record.id}", f"{P}listed", f"{P}deadlines", f"{P}expiry"]
        args = [record.version, dump(record), record.id, int(record.listed)]
        deadline = "" if record.deadline is None else repr(record.deadline)
        args += [record.created, deadline, repr(record.expires)]
        if not await self._create(keys=keys, args=args):
            raise ValueError(f"table {record.id} exists")

    async def get_table(self, table_id: str) -> TableRecord | None:
        doc = await self._redis.hget(f"{P}t:{table_id}", "doc")
        return last_without_motion(load(TableRecord, doc)) if doc else None

    async def accept(self, record: TableRecord) -> Accepted:
        entry = record.pending
        if entry is None:
            raise ValueError("accept needs a record with its pending input")
        args = [record.version, entry.shot_id, dump(record), dump(entry)]
        answer = await self._accept(keys=self._keys(record.id)[:2], args=args)
        if answer[0] == 2:
            return Accepted(AcceptResult.DUPLICATE, load(InputEntry, answer[1]))
        return Accepted(AcceptResult.ACCEPTED if answer[0] == 0 else AcceptResult.CONFLICT)

    async def _swap(
        self,
        record: TableRecord,
        pending: str,
        entry: InputEntry | None,
        outcome_json: bytes | None = None,
    ) -> bool:
        """`outcome_json`: the JSON of `entry`'s outcome (logged; the record's last outcome
        is stored without its motion, invariant 5)."""
        args = [
            record.version - 1,
            pending,
            record.version,
            dump(last_without_motion(record)),
            record.id,
            int(record.listed),
            record.created,
            entry.shot_id if entry else "",
            dump(entry, outcome_json and {"outcome": outcome_json}) if entry else "",
            "" if record.deadline is None else repr(record.deadline),
            entry.rack if entry else "",
            repr(record.expires),
        ]
        return bool(await self._swap_script(keys=self._keys(record.id), args=args))

    async def resolve(
        self, record: TableRecord, entry: InputEntry, outcome_json: bytes | None = None
    ) -> bool:
        return await self._swap(record, entry.shot_id, entry, outcome_json)

    async def update(self, record: TableRecord) -> bool:
        return await self._swap(record, "", None)

    async def find_input(self, table_id: str, shot_id: str) -> InputEntry | None:
        doc = await self._redis.hget(f"{P}i:{table_id}", shot_id)
        return load(InputEntry, doc) if doc else None

    async def _logged(self, table_id: str, start: int, stop: int) -> list[InputEntry]:
        """The played inputs from `start` to `stop` (inclusive, -1: the last) of the log."""
        shot_ids = await self._redis.lrange(f"{P}l:{table_id}", start, stop)
        if not shot_ids:
            return []
        docs = await self._redis.hmget(f"{P}i:{table_id}", shot_ids)
        return [load(InputEntry, doc) for doc in docs]

    async def inputs(self, table_id: str) -> list[InputEntry]:
        return await self._logged(table_id, 0, -1)

    async def rack_inputs(self, table_id: str, rack: int) -> list[InputEntry]:
        start, end = await self._redis.hmget(f"{P}rs:{table_id}", [str(rack), str(rack + 1)])
        if start is None:  # nothing logged in this rack, or logged before racks' starts were
            entries = [e for e in await self.inputs(table_id) if e.rack == rack]
        else:
            stop = -1 if end is None else int(end) - 1
            entries = await self._logged(table_id, int(start), stop)
        return [without_motion(entry) for entry in entries]

    async def expire_tables(self, now: float, limit: int) -> list[str]:
        keys = [f"{P}expiry", f"{P}listed", f"{P}deadlines"]
        return await self._expire(keys=keys, args=[repr(now), limit, P])

    async def heartbeat(self, table_id: str, seat: int, now: float) -> None:
        await self._redis.hset(f"{P}h:{table_id}", str(seat), repr(now))

    async def heartbeats(self, table_id: str) -> tuple[float | None, float | None]:
        seen = await self._redis.hmget(f"{P}h:{table_id}", ["0", "1"])
        return tuple(None if s is None else float(s) for s in seen)  # type: ignore[return-value]

    async def service_since(self, now: float, outage: float) -> float:
        since = await self._service_since(keys=[f"{P}service"], args=[repr(now), repr(outage)])
        return float(since)

    async def due_tables(self, now: float, limit: int) -> list[str]:
        return await self._redis.zrangebyscore(f"{P}deadlines", "-inf", now, start=0, num=limit)

    async def listed_tables(self, limit: int) -> list[TableRecord]:
        ids = await self._redis.zrevrange(f"{P}listed", 0, limit - 1)
        if not ids:
            return []
        async with self._redis.pipeline(transaction=False) as pipe:
            for table_id in ids:
                pipe.hget(f"{P}t:{table_id}", "doc")
            docs = await pipe.execute()
        return [load(TableRecord, doc) for doc in docs if doc]

    # ----- ratings ----------------------------------------------------------------------
    async def ratings(self, player_id: str) -> dict[str, Rating]:
        docs = await self._redis.hgetall(f"{P}r:{player_id}")
        return {game: load(Rating, doc) for game, doc in docs.items()}

    async def rate(self, table_id: str, game: str, ratings: dict[str, Rating]) -> RateResult:
        keys = [f"{P}rated", *(f"{P}r:{player}" for player in ratings)]
        args = [table_id, game, *(dump(rating) for rating in ratings.values())]
        args += [rating.games for rating in ratings.values()]
        answer = await self._rate(keys=keys, args=args)
        return (RateResult.RATED, RateResult.ALREADY, RateResult.CONFLICT)[answer]

    # ----- replays and the leaderboard ---------------------------------------------------
    async def add_result(self, result: MatchResult) -> bool:
        keys = [f"{P}res:{result.table}", *(f"{P}hist:{p.id}" for p in result.seats)]
        args = [dump(result), result.at, result.table]
        return bool(await self._add_result(keys=keys, args=args))

    async def results(self, player_id: str, limit: int) -> list[MatchResult]:
        tables = await self._redis.zrevrange(f"{P}hist:{player_id}", 0, limit - 1)
        docs = await self._redis.mget([f"{P}res:{table}" for table in tables]) if tables else []
        return [load(MatchResult, doc) for doc in docs if doc]

    async def add_challenge(self, challenge: ChallengeRecord) -> None:
        async with self._redis.pipeline(transaction=True) as pipe:
            document = {"status": "pending", "doc": dump(challenge)}
            pipe.hset(f"{P}ch:{challenge.id}", mapping=document)
            for player in (challenge.challenger, challenge.challenged):
                pipe.sadd(f"{P}chp:{player.id}", challenge.id)
            await pipe.execute()

    async def get_challenge(self, challenge_id: str) -> ChallengeRecord | None:
        doc = await self._redis.hget(f"{P}ch:{challenge_id}", "doc")
        return load(ChallengeRecord, doc) if doc else None

    async def settle_challenge(self, challenge: ChallengeRecord) -> bool:
        keys = [
            f"{P}ch:{challenge.id}",
            f"{P}chp:{challenge.challenger.id}",
            f"{P}chp:{challenge.challenged.id}",
        ]
        args = [dump(challenge), challenge.status.value, challenge.id]
        return bool(await self._settle_challenge(keys=keys, args=args))

    async def pending_challenges(self, player_id: str) -> list[ChallengeRecord]:
        ids = sorted(await self._redis.smembers(f"{P}chp:{player_id}"))
        docs = [await self._redis.hget(f"{P}ch:{i}", "doc") for i in ids]
        found = [load(ChallengeRecord, doc) for doc in docs if doc]
        return sorted(found, key=lambda c: c.created)

    async def touch_lobby(self, player_id: str, until: float) -> None:
        await self._redis.set(f"{P}lobby:{player_id}", "1", pxat=int(until * 1000))

    async def in_lobby(self, player_id: str, now: float) -> bool:
        return bool(await self._redis.exists(f"{P}lobby:{player_id}"))

    async def add_replay(self, replay: ReplayView) -> None:
        await self._redis.set(f"{P}rp:{replay.id}", dump(replay))

    async def get_replay(self, replay_id: str) -> ReplayView | None:
        doc = await self._redis.get(f"{P}rp:{replay_id}")
        return load(ReplayView, doc) if doc else None

    async def add_break(self, entry: BreakEntry, key: str) -> bool:
        keys = [f"{P}bk", f"{P}be", f"{P}lb:{entry.game}", f"{P}lbn:{entry.game}"]
        args = [key, dump(entry), entry.score, entry.name]
        return bool(await self._add_break(keys=keys, args=args))

    async def top_breaks(self, game: str, limit: int) -> list[BreakEntry]:
        ranked = await self._redis.zrevrange(f"{P}lb:{game}", 0, limit - 1)
        if not ranked:
            return []
        docs = await self._redis.hmget(f"{P}be", ranked)
        return [load(BreakEntry, doc) for doc in docs if doc]

    async def best_break(self, game: str, name: str) -> BreakEntry | None:
        key = await self._redis.hget(f"{P}lbn:{game}", name)
        doc = await self._redis.hget(f"{P}be", key) if key else None
        return load(BreakEntry, doc) if doc else None

    # ----- quick match ------------------------------------------------------------------
    async def pair(
        self, pool: str, player_id: str, table_id: str, now: float, until: float
    ) -> str | None:
        keys = [f"{P}q:{pool}", f"{P}qs:{player_id}"]
        status = paired(table_id, pool, now)
        args = [player_id, waiting(pool), status, f"{P}qs:", int(until * 1000)]
        return await self._pair(keys=keys, args=args)

    async def touch_quick(self, player_id: str, until: float) -> None:
        await self._touch_quick(keys=[f"{P}qs:{player_id}"], args=[int(until * 1000)])

    async def _quick_value(self, player_id: str) -> str | None:
        return await self._redis.get(f"{P}qs:{player_id}")

    async def cancel_quick(self, player_id: str) -> bool:
        return bool(await self._cancel(keys=[f"{P}qs:{player_id}"], args=[player_id]))
