"""Guest identity: a display name in, a signed token out; the token names the player after.

Tokens are the relay's (`TokenAuthority.issue` / `verify`: one token format for the whole app),
with the player's id as subject and no publish grants: players never publish on game channels,
they send intents over HTTP. The display name lives in storage beside the id, so a token stays
valid across reloads and restarts as long as the signing key does (kept in a file only the
server user reads, server/storage/signing_key.py, or given to every replica in
`BILLIARDS_RELAY_SECRET`).

Names are unique among players *online*: a claim on the name's skeleton (`name_key`: case,
look-alike characters and separators folded, so `AIice` and `Alice.` are `Alice`) lasts
`ONLINE` seconds and each sign of life renews it (a seated player's heartbeat, the lobby page's
poll of its challenges, a waiting player's poll of its quick match); once it lapses the name is
free for someone else.

Every request of a player carries its token, so the last `KNOWN_TOKENS` tokens that checked out
are remembered with their player and expiry: a player's next request costs a dictionary look-up
and an expiry check, not an HMAC, a JSON decode and a storage read (players never change, and a
token's signature stays genuine; only its expiry is checked again, every time). Players do go
away (unused guests expire, `GUEST_KEPT`), so a remembered token is checked in full again
`RECHECK` seconds after it was: a deleted player's token stops working within that time.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable

from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import new_player_id
from server.protocol.models import PlayerInfo, PlayerToken
from server.relay import AuthError, TokenAuthority
from server.storage import Storage

#: How long a player's token is valid (s): a month of coming back to the same name.
TOKEN_TTL = 30 * 24 * 3600
#: How long a name stays reserved after its player's last sign of life (s).
ONLINE = 300.0
#: How long a guest who never played a rated match is kept after its last sign of life (s):
#: then its player is deleted (storage invariant 15, server/game/expiry.py) and its token
#: names no player (401: the client registers again).
GUEST_KEPT = 24 * 3600.0
#: Seconds a remembered token is trusted before its player is read from storage again.
RECHECK = ONLINE
#: Genuine tokens remembered with their player (least recently used forgotten first).
KNOWN_TOKENS = 4096


#: What each allowed character may be read as once case is folded (`ids.NAME_CORE`: letters,
#: digits, `_-. `): i (capital I looks like l) and digit 1 as l, digit 0 as o, 5 as s, 2 as z,
#: 8 as b; `rn` reads as `m` and `vv` as `w`. Separators read as nothing: `Alice.` and
#: `A-lice` are `Alice`. (Folding i with l refuses `Ian` while `lan` is online: a rare
#: refusal, where the other way lets `AIice` pass for `Alice`.)
_LOOKALIKES = str.maketrans({"i": "l", "1": "l", "0": "o", "5": "s", "2": "z", "8": "b"})
_SEPARATORS = str.maketrans("", "", "_-. ")
_DIGRAPHS = (("rn", "m"), ("vv", "w"))


def name_key(name: str) -> str:
    """The skeleton of a display name: names with the same skeleton read the same, so only
    one of them may be online at a time (`AIice`, `A1ice`, `alice` and `Alice.` are `Alice`).

    A confusables skeleton in the spirit of Unicode TR39, for the few characters a name may
    hold: look-alike characters mapped to one, case folded, separators dropped."""
    skeleton = name.casefold().translate(_LOOKALIKES).translate(_SEPARATORS)
    for pair, single in _DIGRAPHS:
        skeleton = skeleton.replace(pair, single)
    return skeleton


class Identity:
    def __init__(
        self, authority: TokenAuthority, storage: Storage, clock: Callable[[], float] = time.time
    ) -> None:
        self._authority = authority
        self._storage = storage
        self._clock = clock
        #: token -> (its player, its expiry, when to read the player again)
        self._known: OrderedDict[str, tuple[PlayerInfo, int, float]] = OrderedDict()

    async def register(self, name: str) -> PlayerToken:
        """A new player with `name` and its token; NAME_TAKEN if a player online has it."""
        player = PlayerInfo(id=new_player_id(), name=name)
        now = time.time()
        if not await self._storage.claim_name(name_key(name), player.id, now + ONLINE, now):
            raise ServiceError(ErrorCode.NAME_TAKEN, f"the name {name!r} is in use")
        await self._storage.add_player(player, now)
        token = self._authority.issue(player.id, [], TOKEN_TTL, name=player.name)
        return PlayerToken(player=player, token=token, expires_at=int(now + TOKEN_TTL))

    async def authenticate(self, token: str | None) -> PlayerInfo:
        """The player a genuine, unexpired token names; UNAUTHORIZED otherwise."""
        known = self._known.get(token) if token else None
        now = self._clock()
        if known is not None:
            player, expires, recheck = known
            if expires < now:
                del self._known[token]
                raise ServiceError(ErrorCode.UNAUTHORIZED, "token has expired")
            if now < recheck:
                self._known.move_to_end(token)
                return player
            del self._known[token]  # checked in full below (the player may be gone)
        try:
            claims = self._authority.verify(token)
        except AuthError as error:
            raise ServiceError(ErrorCode.UNAUTHORIZED, error.reason) from None
        player = await self._storage.get_player(claims.sub)
        if player is None:
            raise ServiceError(ErrorCode.UNAUTHORIZED, "token names no player")
        self._known[token] = (player, claims.exp, now + RECHECK)
        if len(self._known) > KNOWN_TOKENS:
            self._known.popitem(last=False)
        return player

    async def seen(self, player: PlayerInfo) -> None:
        """Renew the player's name claim (it is online)."""
        now = time.time()
        await self._storage.claim_name(name_key(player.name), player.id, now + ONLINE, now)
