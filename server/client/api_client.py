"""A client of the public API (docs/protocol.md): what `billiards play` and the load benchmark
use, and what a bot or a test can use. It knows HTTP, the relay's WebSocket and the message
models, nothing of the server's insides.

The table feed follows the protocol's resync rule: messages are applied in version order, a
repeat is ignored, and a gap (a version skipped, or the relay's gap notice) fetches the full
state with `GET /api/tables/{id}` instead of guessing.

It is written for an unreliable connection (a load balancer whose replica dies, a link that
drops): the feed reconnects and resumes from the last relay message id it saw, and a request
that got no answer (a transport failure, or a proxy's 502/503/504 page) is sent again where
that is safe, each method saying why it is. Both wait with bounded, jittered backoff and give
up with `Unreachable` once the server has been out of reach for `Patience.give_up` seconds.
Until the server has answered once, nothing is retried: an address that never answered is a
mistake to report at once, not an outage to wait out.
"""

from __future__ import annotations

import asyncio
import json
import random
import time
import uuid
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager, suppress
from dataclasses import dataclass
from typing import Annotated, Any, TypeVar
from urllib.parse import quote

import aiohttp
from pydantic import BaseModel, Field, TypeAdapter, ValidationError

from server.protocol.feed import CLOSE_GOING_AWAY, DELETED_REASON, GAP_TYPE, META_PROTOCOL
from server.protocol.ids import HEARTBEAT_INTERVAL, QUICK_POLL, MessageKind, player_channel
from server.protocol.models import (
    ChatMessage,
    IntentAccepted,
    IntentDuplicate,
    OutcomeMessage,
    PlayerInfo,
    PlayerToken,
    PresenceMessage,
    QuickStatus,
    SharedPosition,
    Status,
    TableList,
    TableMessage,
    TableView,
)

M = TypeVar("M", bound=BaseModel)
T = TypeVar("T")
_ACK = TypeAdapter(IntentAccepted | IntentDuplicate)
_FEED = TypeAdapter(
    Annotated[
        OutcomeMessage | TableMessage | PresenceMessage | ChatMessage, Field(discriminator="kind")
    ]
)
Change = TableView | OutcomeMessage

#: Statuses a proxy answers, with its own page, when it could not get an answer from the
#: server behind it (nginx: 502 the replica failed, 503 none available, 504 it timed out).
#: The request may or may not have been carried out, as after a transport failure.
NO_ANSWER = frozenset({502, 503, 504})
#: Bounds on one request: connecting (a host that does not answer at all) and each read (a
#: connection that went silent). A resent intent may wait for the lease of an input a dead
#: replica accepted (match.LEASE, 15 s) before it is answered, well within the read bound.
REQUEST_TIMEOUT = aiohttp.ClientTimeout(total=None, sock_connect=10.0, sock_read=60.0)
#: Seconds to open the feed's WebSocket (the handshake, before any message).
HANDSHAKE_TIMEOUT = 10.0
#: Seconds between the feed's WebSocket pings: a connection that stops answering them (a
#: link that died without closing) is dropped and reopened within 1.5 times this.
FEED_PING = 10.0


class Refused(Exception):
    """The server refused a request: its status, code and reason."""

    def __init__(self, status: int, code: str, reason: str) -> None:
        super().__init__(f"{code}: {reason}")
        self.status, self.code, self.reason = status, code, reason


class Unreachable(Exception):
    """No answer came: the connection failed, or a proxy could not reach the server (after
    retrying, where the request may be retried, until the client's patience ran out)."""


@dataclass(frozen=True)
class Patience:
    """How the client waits for a server out of reach: delays double from `first` to `most`
    seconds (each shortened by a random part, so that clients dropped together do not all
    come back together), and after `give_up` seconds without an answer it gives up."""

    first: float = 0.1
    most: float = 2.0
    give_up: float = 60.0


class Backoff:
    """One spell of retries under a `Patience`: how long to wait, and when to stop trying."""

    def __init__(self, patience: Patience) -> None:
        self._patience = patience
        self._delay = patience.first
        self._since: float | None = None

    def reached(self) -> None:
        """The server answered: a later failure starts a new count towards giving up."""
        self._since = None

    def served(self) -> None:
        """The connection delivered: the next wait starts again from the shortest. (Until
        then waits keep growing, so a server that accepts and drops at once is not hammered.)"""
        self._delay = self._patience.first

    async def pause(self, failure: Unreachable) -> None:
        """Wait before the next attempt; Unreachable once the server has been out of reach
        for longer than the patience allows."""
        now = time.monotonic()
        if self._since is None:
            self._since = now
        if now - self._since >= self._patience.give_up:
            give_up = self._patience.give_up
            raise Unreachable(f"no answer for {give_up:g} s ({failure})") from failure
        await asyncio.sleep(self._delay * random.uniform(0.5, 1.0))
        self._delay = min(2 * self._delay, self._patience.most)


def from_json(model: type[M], value: Any) -> M:
    """`value` (decoded JSON) as `model`, validated as JSON: arrays are tuples where the model
    says so, as strict models need."""
    return model.model_validate_json(json.dumps(value))


def table_id_of(link: str) -> str:
    """A table id from a private link (`.../t/<id>`) or the id itself."""
    return link.rstrip("/").rsplit("/", 1)[-1]


def finished(change: Change) -> bool:
    """Whether a table has reached its end: nothing more will be played there."""
    return change.status in (Status.OVER, Status.CANCELLED)


def one_line(error: BaseException) -> str:
    """An error as one line of text (the CLI's contract is one line on failure)."""
    return " ".join(str(error).split()) or type(error).__name__


def refusal(status: int, phrase: str, data: bytes, is_json: bool) -> Refused:
    """The refusal an answer carries: the API's JSON error, or for any other body (a proxy's
    HTML page, say) its HTTP status line. Only a JSON answer is parsed as JSON."""
    try:
        payload = json.loads(data) if is_json else None
    except ValueError:
        payload = None
    if isinstance(payload, dict) and isinstance(payload.get("code"), str):
        return Refused(status, payload["code"], str(payload.get("reason", "")))
    return Refused(status, f"http_{status}", f"the server answered {status} {phrase}".strip())


class GameClient:
    """One player's session with a server at `base` (e.g. `http://127.0.0.1:8080`)."""

    def __init__(
        self, base: str, session: aiohttp.ClientSession, patience: Patience | None = None
    ) -> None:
        self.base = base.rstrip("/")
        self.session = session
        self.patience = patience or Patience()
        self.token: str | None = None
        self.player: PlayerInfo | None = None
        #: Whether the server has answered anything yet (see the module docstring).
        self.reached = False
        #: Tables this client has created, joined or read (see `create`).
        self._known: set[str] = set()
        #: The inbox and version of each table this client follows (see `follow`).
        self._following: dict[str, tuple[asyncio.Queue[Any], list[int]]] = {}

    # ----- requests ---------------------------------------------------------------------------
    async def fetch(
        self, method: str, path: str, body: Any = None, *, retry: bool | None = None
    ) -> bytes:
        """The answer's body (JSON) to a request; Refused if the server refuses it,
        Unreachable if no answer comes. `retry` (by default for GET only, which changes
        nothing) sends it again after a failure that left its fate unknown."""
        if retry is None:
            retry = method == "GET"
        if retry:
            return await self._retrying(lambda _first: self._attempt(method, path, body))
        return await self._attempt(method, path, body)

    async def _attempt(self, method: str, path: str, body: Any = None) -> bytes:
        """One request, once (see `fetch`)."""
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        url = self.base + path
        try:
            async with self.session.request(
                method, url, json=body, headers=headers, timeout=REQUEST_TIMEOUT
            ) as response:
                data = await response.read()
        except aiohttp.InvalidURL as error:
            raise Refused(0, "bad_url", one_line(error)) from None
        except (aiohttp.ClientError, TimeoutError) as error:
            raise Unreachable(f"{method} {path}: {one_line(error)}") from error
        self.reached = True
        status, is_json = response.status, response.content_type == "application/json"
        if status < 400:
            return data
        if status in NO_ANSWER and not is_json:  # the proxy's page, not the server's refusal
            raise Unreachable(f"{method} {path}: {status} {response.reason}")
        raise refusal(status, response.reason or "", data, is_json)

    async def _retrying(self, attempt: Callable[[bool], Awaitable[T]]) -> T:
        """`attempt(first)` until it is answered (or refused), with backoff after each
        attempt that got no answer. `first` tells a resend from the first sending."""
        backoff = Backoff(self.patience)
        first = True
        while True:
            try:
                return await attempt(first)
            except Unreachable as failure:
                if not self.reached:
                    raise
                await backoff.pause(failure)
            first = False

    # ----- identity and tables --------------------------------------------------------------
    async def register(self, name: str) -> PlayerInfo:
        """A guest identity under `name`. Resent after a lost answer: a registration that did
        land is an identity nobody will use, whose claim on the name lapses within five
        minutes (identity.ONLINE); it makes the resend `name_taken`, which then says so."""

        async def attempt(first: bool) -> PlayerToken:
            try:
                data = await self._attempt("POST", "/api/players", {"name": name})
            except Refused as refused:
                if first or refused.code != "name_taken":
                    raise
                lost = " (perhaps by this client's own request whose answer was lost)"
                raise Refused(refused.status, refused.code, refused.reason + lost) from None
            return PlayerToken.model_validate_json(data)

        token = await self._retrying(attempt)
        self.token, self.player = token.token, token.player
        return token.player

    async def create(self, game: str, **options: Any) -> TableView:
        """A new table with this player in seat 0. After a lost answer the table may exist
        already: a public one would then be listed in the lobby with nobody coming, so the
        lobby is searched for it (`_lost_table`) before the request is sent again. A private
        one is listed nowhere and its id is known to nobody: sending again leaves only a
        table no one sees, which expires (tables.KEEP_IDLE)."""
        body = {"game": game, **options}

        async def attempt(first: bool) -> TableView:
            lost = None if first else await self._lost_table(game)
            if lost is not None:
                return lost
            return TableView.model_validate_json(await self._attempt("POST", "/api/tables", body))

        return self._seen(await self._retrying(attempt))

    async def _lost_table(self, game: str) -> TableView | None:
        """A listed table of `game` in whose seat 0 this player sits and that this client has
        never heard of: its own creation, whose answer was lost."""
        assert self.player is not None
        listing = TableList.model_validate_json(await self._attempt("GET", "/api/tables"))
        for summary in listing.tables:
            host = summary.seats[0]
            mine = host is not None and host.id == self.player.id
            if mine and summary.game == game and summary.id not in self._known:
                return TableView.model_validate_json(
                    await self._attempt("GET", f"/api/tables/{summary.id}")
                )
        return None

    async def join(self, table_id: str) -> TableView:
        """Take the free seat. Resent after a lost answer: if the first request did seat this
        player, the resend is refused `already_seated`, which means the seat is ours, so it
        is answered with the table as it stands."""
        try:
            data = await self.fetch("POST", f"/api/tables/{table_id}/join", retry=True)
        except Refused as refused:
            if refused.code != "already_seated":
                raise
            return await self.table(table_id)
        return self._seen(TableView.model_validate_json(data))

    async def table(self, table_id: str) -> TableView:
        return self._seen(
            TableView.model_validate_json(await self.fetch("GET", f"/api/tables/{table_id}"))
        )

    def _seen(self, view: TableView) -> TableView:
        self._known.add(view.id)
        return view

    async def quick(self, game: str, **options: Any) -> QuickStatus:
        """Ask for a quick match. Never sent blindly twice: the server would queue a player
        whom the first request had paired (and might pair it again). After a lost answer the
        client asks where it stands (`GET /api/quick`) and sends again only if the first
        request never arrived (`idle`)."""

        async def attempt(first: bool) -> QuickStatus:
            if not first:
                status = QuickStatus.model_validate_json(await self._attempt("GET", "/api/quick"))
                if status.status != "idle":
                    return status
            data = await self._attempt("POST", "/api/quick", {"game": game, **options})
            return QuickStatus.model_validate_json(data)

        return await self._retrying(attempt)

    async def shared_position(self, code: str) -> SharedPosition:
        """What a practice position's link code sets up (checked by the server)."""
        data = await self.fetch("GET", f"/api/positions/{quote(code, safe='')}")
        return SharedPosition.model_validate_json(data)

    # ----- playing ----------------------------------------------------------------------------
    async def send(
        self, table_id: str, version: int, action: Any
    ) -> IntentAccepted | IntentDuplicate:
        """Send one intent; Refused if the server refuses it. Its shot id is chosen once and
        kept across resends: the server answers a shot id it has seen with that input's first
        outcome (`IntentDuplicate`) and never plays it twice (docs/protocol.md), so an intent
        whose answer was lost is sent again without risk."""
        body = {"version": version, "shot_id": uuid.uuid4().hex, "input": action}
        path = f"/api/tables/{table_id}/intents"
        return _ACK.validate_json(await self.fetch("POST", path, body, retry=True))

    async def heartbeat(self, table_id: str) -> PresenceMessage:
        """Tell the server this seated player is here (once: the next heartbeat is the retry)."""
        data = await self.fetch("POST", f"/api/tables/{table_id}/heartbeat", retry=False)
        presence = PresenceMessage.model_validate_json(data)
        followed = self._following.get(table_id)
        if followed is not None and presence.version > followed[1][0]:
            followed[0].put_nowait(_RESYNC)  # the feed missed a change: the follower resyncs
        return presence

    async def claim(self, table_id: str) -> TableView:
        """Claim the win from an opponent gone past the grace period (once: a resend of a
        claim that landed is refused, the match being over)."""
        data = await self.fetch("POST", f"/api/tables/{table_id}/claim", retry=False)
        return TableView.model_validate_json(data)

    def heartbeats(self, table_id: str) -> AbstractAsyncContextManager[None]:
        """Send heartbeats every HEARTBEAT_INTERVAL while the context is open. They keep the
        player shown present and make the server look at the table, which is what plays an
        input that a replica accepted and then died with (server/game/actor.py, LEASE). Each
        answer says until when an absent player is waited for: past that, this player claims
        the win (the
        server decides by its own clock; a claim it refuses waits for the next heartbeat)."""

        async def beat() -> None:
            while True:
                # Best effort: the feed and the intents are what report real trouble.
                with suppress(Refused, Unreachable):
                    presence = await self.heartbeat(table_id)
                    if any(t is not None and t <= time.time() for t in presence.grace_until):
                        await self.claim(table_id)
                await asyncio.sleep(HEARTBEAT_INTERVAL)

        return _running(beat)

    async def wait_paired(self) -> str:
        """The table id of a quick match, once the server has paired this player: from the
        player channel's `paired` message, or from polling `GET /api/quick` every
        `QUICK_POLL` seconds, which also keeps the request from lapsing."""
        listen = asyncio.ensure_future(self._paired_message())
        try:
            while not listen.done():
                status = QuickStatus.model_validate_json(await self.fetch("GET", "/api/quick"))
                if status.status == "paired" and status.table is not None:
                    return status.table
                if status.status != "waiting":
                    raise Refused(0, "lapsed", f"the quick-match request is {status.status}")
                await asyncio.wait([listen], timeout=QUICK_POLL)
            return listen.result()
        finally:
            listen.cancel()

    async def _paired_message(self) -> str:
        """The table of the player channel's first `paired` message."""
        assert self.player is not None
        async for data in self.messages(player_channel(self.player.id)):
            message = {} if data is None else json.loads(data)
            if message.get("kind") == MessageKind.PAIRED:
                return message["table"]
        raise Refused(0, "closed", "the player channel closed before pairing")

    # ----- the relay ------------------------------------------------------------------------
    async def messages(self, channel: str) -> AsyncIterator[bytes | None]:
        """The data (JSON) of each message of a relay channel; None for the relay's gap
        notice. Left undecoded: a reader validates what it needs straight from the bytes.

        Ends only when the channel is deleted. A connection that drops is opened again, with
        backoff, resuming after the last message id it delivered (the relay then sends what
        was missed, exactly once, or a gap notice); Unreachable once it cannot be reopened
        within the client's patience."""
        backoff = Backoff(self.patience)
        last_id: str | None = None
        while True:
            try:
                async with await self._subscribe(channel, last_id) as ws:
                    backoff.reached()
                    while (frame := await ws.receive()).type in (
                        aiohttp.WSMsgType.TEXT,
                        aiohttp.WSMsgType.BINARY,
                    ):
                        message_id, data = _meta_frame(frame.data)
                        last_id = message_id or last_id
                        backoff.served()
                        yield data
                    if _deleted(frame):
                        return
                    failure = Unreachable(f"{channel}: the feed closed ({_close_reason(frame)})")
            except Unreachable as error:
                if not self.reached:
                    raise
                failure = error
            await backoff.pause(failure)

    async def _subscribe(
        self, channel: str, last_id: str | None
    ) -> aiohttp.ClientWebSocketResponse:
        """The channel's WebSocket (`ws+meta.nchan`, for message ids), resuming after
        `last_id` if given; Unreachable if it cannot be opened now, Refused if the relay
        refuses it for good."""
        params = {} if last_id is None else {"last_event_id": last_id}
        url = f"{self.base}/sub/{channel}"
        try:
            async with asyncio.timeout(HANDSHAKE_TIMEOUT):
                ws = await self.session.ws_connect(
                    url, params=params, protocols=(META_PROTOCOL,), heartbeat=FEED_PING
                )
        except aiohttp.WSServerHandshakeError as error:
            self.reached = True
            if error.status in NO_ANSWER or error.status == 429:  # 429: too many, try later
                raise Unreachable(f"{channel}: {error.status} {error.message}") from error
            raise Refused(error.status, f"http_{error.status}", one_line(error)) from None
        except aiohttp.InvalidURL as error:
            raise Refused(0, "bad_url", one_line(error)) from None
        except (aiohttp.ClientError, TimeoutError) as error:
            raise Unreachable(f"{channel}: {one_line(error)}") from error
        self.reached = True
        return ws

    async def follow(self, view: TableView) -> AsyncIterator[Change]:
        """The table's changes in version order from `view`: each outcome (or a fresh view on
        a `table` message or a resync). Ends once the table is finished (the change that
        finishes it included), or if its channel is deleted (first yielding the stored
        state, if it is newer: it says how the table ended, or that it did not)."""
        if finished(view):
            return
        inbox: asyncio.Queue[Any] = asyncio.Queue()
        version = [view.version]  # shared with `heartbeat`, whose answers carry the version
        self._following[view.id] = (inbox, version)
        pump = asyncio.ensure_future(self._pump(view.channel, inbox))
        try:
            while (item := await inbox.get()) is not _END:
                if isinstance(item, BaseException):
                    raise item
                change = await self._change(view.id, version[0], None if item is _RESYNC else item)
                if change is None:
                    continue
                version[0] = change.version
                yield change
                if finished(change):
                    return
        finally:
            pump.cancel()
            self._following.pop(view.id, None)
        fresh = await self.table(view.id)
        if fresh.version > version[0]:
            yield fresh

    async def _pump(self, channel: str, inbox: asyncio.Queue[Any]) -> None:
        """Hand the feed's messages to `follow`'s inbox (the gap notice as `_RESYNC`), then
        `_END`, or the error that ended it."""
        try:
            async for data in self.messages(channel):
                inbox.put_nowait(_RESYNC if data is None else data)
            inbox.put_nowait(_END)
        except Exception as error:  # the follower raises it: a feed that failed never hangs
            inbox.put_nowait(error)

    async def _change(self, table_id: str, version: int, data: bytes | None) -> Change | None:
        """What one feed message (None: the relay's gap notice, or a heartbeat's answer that
        carried a newer version) changes for a client at `version`, by the resync rule: None
        for a repeat or a message that changes no version; the message if it is the next
        version; the fetched state after a gap."""
        message = None if data is None else _feed_message(data)
        if data is not None and (message is None or message.version <= version):
            return None  # not a message of the table, or nothing newer than what was applied
        if isinstance(message, OutcomeMessage | TableMessage) and message.version == version + 1:
            return message if isinstance(message, OutcomeMessage) else message.view
        # A gap notice, a version skipped, or a presence or chat message sent at a version
        # this client has not seen (it missed a change, as after a server restart).
        fresh = await self.table(table_id)
        return fresh if fresh.version > version else None


@asynccontextmanager
async def _running(loop: Callable[[], Awaitable[None]]) -> AsyncIterator[None]:
    """Run `loop()` as a task while the context is open."""
    task = asyncio.create_task(loop())
    try:
        yield
    finally:
        task.cancel()
        with suppress(asyncio.CancelledError):
            await task


# What `follow`'s inbox holds besides a message's data: fetch the table; the feed ended.
_RESYNC, _END = object(), object()


def _meta_frame(raw: str | bytes) -> tuple[str | None, bytes | None]:
    """A `ws+meta.nchan` frame's message id (None if it has none) and data (None for the
    relay's gap notice)."""
    raw = raw.encode() if isinstance(raw, str) else raw
    header, _, data = raw.partition(b"\n\n")
    fields = dict(line.partition(b": ")[::2] for line in header.split(b"\n"))
    message_id = fields.get(b"id", b"").decode() or None
    return message_id, None if fields.get(b"content-type") == GAP_TYPE.encode() else data


def _deleted(frame: aiohttp.WSMessage) -> bool:
    """Whether the relay closed the feed because the channel was deleted (nchan's 410)."""
    return (
        frame.type is aiohttp.WSMsgType.CLOSE
        and frame.data == CLOSE_GOING_AWAY
        and frame.extra == DELETED_REASON
    )


def _close_reason(frame: aiohttp.WSMessage) -> str:
    """Why a feed ended, in words, for the message of a client that gives up."""
    if frame.type is aiohttp.WSMsgType.CLOSE:
        return f"code {frame.data} {frame.extra or ''}".strip()
    if frame.type is aiohttp.WSMsgType.ERROR:
        return one_line(frame.data)
    return "connection lost"


def _feed_message(
    data: bytes,
) -> OutcomeMessage | TableMessage | PresenceMessage | ChatMessage | None:
    """A table channel's message, validated from its JSON in one pass; None for kinds this
    client does not know."""
    try:
        return _FEED.validate_json(data)
    except ValidationError as error:
        if error.errors()[0]["type"] in ("union_tag_invalid", "union_tag_not_found"):
            return None
        raise
