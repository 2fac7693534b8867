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
from typing import Any, TypeVar

import aiohttp
from pydantic import BaseModel, TypeAdapter

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

    async def request(self, method: str, path: str, body: Any = None) -> tuple[int, Any]:
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        async with self.session.request(
            method, self.base + path, json=body, headers=headers
        ) as response:
            payload = await response.json(content_type=None)
            if response.status >= 400:
                raise Refused(response.status, payload.get("code", "?"), payload.get("reason", ""))
            return response.status, payload

    async def register(self, name: str) -> PlayerInfo:
        _, body = await self.request("POST", "/api/players", {"name": name})
        token = from_json(PlayerToken, body)
        self.token, self.player = token.token, token.player
        return token.player

    async def create(self, game: str, **options: Any) -> TableView:
        _, body = await self.request("POST", "/api/tables", {"game": game, **options})
        return from_json(TableView, body)

    async def join(self, table_id: str) -> TableView:
        _, body = await self.request("POST", f"/api/tables/{table_id}/join")
        return from_json(TableView, body)

    async def table(self, table_id: str) -> TableView:
        _, body = await self.request("GET", f"/api/tables/{table_id}")
        return from_json(TableView, body)

    async def quick(self, game: str) -> QuickStatus:
        _, body = await self.request("POST", "/api/quick", {"game": game})
        return from_json(QuickStatus, body)

    async def send(
        self, table_id: str, version: int, action: Any
    ) -> IntentAccepted | IntentDuplicate:
        """Send one intent (a fresh shot id); Refused if the server refuses it."""
        body = {"version": version, "shot_id": uuid.uuid4().hex, "input": action}
        _, answer = await self.request("POST", f"/api/tables/{table_id}/intents", body)
        return _ACK.validate_json(json.dumps(answer))

    async def wait_paired(self) -> str:
        """The table id of a quick match, once the server has paired this player."""
        assert self.player is not None
        async for message in self.messages(f"player-{self.player.id}"):
            if message.get("kind") == "paired":
                return message["table"]
            status = await self.request("GET", "/api/quick")
            if status[1]["status"] == "paired":
                return status[1]["table"]
        raise Refused(0, "closed", "the player channel closed before pairing")

    async def messages(self, channel: str) -> AsyncIterator[dict[str, Any]]:
        """JSON messages of a relay channel (`{"kind": "gap"}` for the relay's gap notice)."""
        async with self.session.ws_connect(f"{self.base}/sub/{channel}", protocols=(META,)) as ws:
            async for frame in ws:
                if frame.type not in (aiohttp.WSMsgType.TEXT, aiohttp.WSMsgType.BINARY):
                    break
                raw = frame.data if isinstance(frame.data, bytes) else frame.data.encode()
                header, _, data = raw.partition(b"\n\n")
                if f"content-type: {GAP_TYPE}".encode() in header:
                    yield {"kind": "gap"}
                else:
                    yield json.loads(data)

    async def follow(self, view: TableView) -> AsyncIterator[TableView | OutcomeMessage]:
        """The table's changes in version order from `view`: each outcome (or a fresh view on
        a `table` message or a resync), until the channel closes."""
        version = view.version
        async for message in self.messages(view.channel):
            kind = message.get("kind")
            if kind not in ("outcome", "table", "gap"):
                continue
            if kind != "gap" and message["version"] <= version:
                continue  # already applied
            if kind == "gap" or message["version"] > version + 1:
                fresh = await self.table(view.id)
                version = fresh.version
                yield fresh
            elif kind == "outcome":
                outcome = from_json(OutcomeMessage, message)
                version = outcome.version
                yield outcome
            else:
                fresh = from_json(TableMessage, message).view
                version = fresh.version
                yield fresh
