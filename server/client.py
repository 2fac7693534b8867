"""A client of the public API (docs/protocol.md): what `billiards play` and the load benchmark
use, and what a bot or a test can use. It knows HTTP, the relay's WebSocket and the message
models, nothing of the server's insides.

The table feed follows the protocol's resync rule: messages are applied in version order, a
repeat is ignored, and a gap (a version skipped, or the relay's gap notice) fetches the full
state with `GET /api/tables/{id}` instead of guessing.
"""

from __future__ import annotations

import json
import uuid
from collections.abc import AsyncIterator
from typing import Annotated, Any, TypeVar

import aiohttp
from pydantic import BaseModel, Field, TypeAdapter, ValidationError

from server.api_models import (
    IntentAccepted,
    IntentDuplicate,
    OutcomeMessage,
    PlayerInfo,
    PlayerToken,
    QuickStatus,
    TableMessage,
    TableView,
)
from server.relay.frames import GAP_TYPE

META = "ws+meta.nchan"
M = TypeVar("M", bound=BaseModel)
_ACK = TypeAdapter(IntentAccepted | IntentDuplicate)
_FEED = TypeAdapter(Annotated[OutcomeMessage | TableMessage, Field(discriminator="kind")])


class Refused(Exception):
    """The server refused a request: its status, code and reason."""

    def __init__(self, status: int, code: str, reason: str) -> None:
        super().__init__(f"{code}: {reason}")
        self.status, self.code, self.reason = status, code, reason


def from_json(model: type[M], value: Any) -> M:
    """`value` (decoded JSON) as `model`, validated as JSON: arrays are tuples where the model
    says so, as strict models need."""
    return model.model_validate_json(json.dumps(value))


def table_id_of(link: str) -> str:
    """A table id from a private link (`.../t/<id>`) or the id itself."""
    return link.rstrip("/").rsplit("/", 1)[-1]


class GameClient:
    """One player's session with a server at `base` (e.g. `http://127.0.0.1:8080`)."""

    def __init__(self, base: str, session: aiohttp.ClientSession) -> None:
        self.base = base.rstrip("/")
        self.session = session
        self.token: str | None = None
        self.player: PlayerInfo | None = None

    async def fetch(self, method: str, path: str, body: Any = None) -> bytes:
        """The answer's body (JSON) to one request; Refused if the server refuses it."""
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        async with self.session.request(
            method, self.base + path, json=body, headers=headers
        ) as response:
            data = await response.read()
            if response.status >= 400:
                payload = json.loads(data)
                raise Refused(response.status, payload.get("code", "?"), payload.get("reason", ""))
            return data

    async def register(self, name: str) -> PlayerInfo:
        token = PlayerToken.model_validate_json(
            await self.fetch("POST", "/api/players", {"name": name})
        )
        self.token, self.player = token.token, token.player
        return token.player

    async def create(self, game: str, **options: Any) -> TableView:
        body = {"game": game, **options}
        return TableView.model_validate_json(await self.fetch("POST", "/api/tables", body))

    async def join(self, table_id: str) -> TableView:
        return TableView.model_validate_json(
            await self.fetch("POST", f"/api/tables/{table_id}/join")
        )

    async def table(self, table_id: str) -> TableView:
        return TableView.model_validate_json(await self.fetch("GET", f"/api/tables/{table_id}"))

    async def quick(self, game: str) -> QuickStatus:
        body = {"game": game}
        return QuickStatus.model_validate_json(await self.fetch("POST", "/api/quick", body))

    async def send(
        self, table_id: str, version: int, action: Any
    ) -> IntentAccepted | IntentDuplicate:
        """Send one intent (a fresh shot id); Refused if the server refuses it."""
        body = {"version": version, "shot_id": uuid.uuid4().hex, "input": action}
        return _ACK.validate_json(await self.fetch("POST", f"/api/tables/{table_id}/intents", body))

    async def wait_paired(self) -> str:
        """The table id of a quick match, once the server has paired this player."""
        assert self.player is not None
        async for data in self.messages(f"player-{self.player.id}"):
            message = {} if data is None else json.loads(data)
            if message.get("kind") == "paired":
                return message["table"]
            status = QuickStatus.model_validate_json(await self.fetch("GET", "/api/quick"))
            if status.status == "paired" and status.table is not None:
                return status.table
        raise Refused(0, "closed", "the player channel closed before pairing")

    async def messages(self, channel: str) -> AsyncIterator[bytes | None]:
        """The data (JSON) of each message of a relay channel; None for the relay's gap
        notice. Left undecoded: a reader validates what it needs straight from the bytes."""
        async with self.session.ws_connect(f"{self.base}/sub/{channel}", protocols=(META,)) as ws:
            async for frame in ws:
                if frame.type not in (aiohttp.WSMsgType.TEXT, aiohttp.WSMsgType.BINARY):
                    break
                raw = frame.data if isinstance(frame.data, bytes) else frame.data.encode()
                header, _, data = raw.partition(b"\n\n")
                yield None if f"content-type: {GAP_TYPE}".encode() in header else data

    async def follow(self, view: TableView) -> AsyncIterator[TableView | OutcomeMessage]:
        """The table's changes in version order from `view`: each outcome (or a fresh view on
        a `table` message or a resync), until the channel closes."""
        version = view.version
        async for data in self.messages(view.channel):
            message = None if data is None else _feed_message(data)
            if data is not None and (message is None or message.version <= version):
                continue  # not a change of the table, or already applied
            if message is None or message.version > version + 1:
                fresh = await self.table(view.id)
                version = fresh.version
                yield fresh
            else:
                version = message.version
                yield message if isinstance(message, OutcomeMessage) else message.view


def _feed_message(data: bytes) -> OutcomeMessage | TableMessage | None:
    """A table channel's outcome or table message, validated from its JSON in one pass; None
    for the messages that change no version (presence, chat) and kinds this client does not
    know."""
    try:
        return _FEED.validate_json(data)
    except ValidationError as error:
        if error.errors()[0]["type"] in ("union_tag_invalid", "union_tag_not_found"):
            return None
        raise
