"""The service's own publishing on relay channels: in process, straight into the backend.

Clients publish through the relay's checks (tokens, rate, the 64 KiB client limit); the game
service is the relay's owner, so its messages skip the per-holder rate limit (a busy server
publishes far more than one player) and the client size limit (an eight-ball break's outcome,
trajectory included, is about 40 KB of JSON). Messages are the pydantic models of
server/protocol/models.py as JSON, which every transport (WebSocket, EventSource, long-poll)
carries.
"""

from __future__ import annotations

from pydantic import BaseModel

from server.relay import JSON, Published, Relay


class Publisher:
    def __init__(self, relay: Relay) -> None:
        self.relay = relay

    async def publish(self, channel: str, message: BaseModel) -> Published:
        """Publish `message` as JSON, encoded once: pydantic's serializer writes the bytes the
        relay keeps (`model_dump_json` would make a str of them, to be encoded back, two more
        copies of an outcome's tens of KB)."""
        data = type(message).__pydantic_serializer__.to_json(message)
        return await self.publish_json(channel, data)

    async def publish_json(self, channel: str, data: bytes) -> Published:
        """Publish a message already encoded as JSON (an outcome: `tables.outcome_json`)."""
        return await self.relay.backend.publish(channel, data, JSON)

    async def delete(self, channel: str) -> None:
        """Delete a channel and its buffer on every replica (its subscribers are closed)."""
        await self.relay.backend.delete(channel)

    async def subscribers(self, channel: str) -> int:
        """Subscribers of `channel` on every replica (the relay's global count)."""
        info = await self.relay.backend.info(channel)
        return info.subscribers if info else 0
