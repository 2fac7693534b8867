"""Bounded memory for a long-running server: expired tables leave the storage and the relay,
and a table channel's backlog is bounded in bytes, not only in messages."""

from __future__ import annotations

import time

from aiohttp.test_utils import TestClient

from server.game.expiry import sweep
from server.game.identity import GUEST_KEPT
from server.game.tables import KEEP_IDLE
from server.http.app import SERVICE_BUFFER
from server.protocol.ids import table_channel as channel_of
from server.relay.payloads import JSON
from tests.service.conftest import a_table, register, service_of


async def test_a_sweep_drops_expired_tables_and_their_channels(server: TestClient) -> None:
    service = service_of(server)
    old, fresh = a_table("1" * 20), a_table("2" * 20)
    for record in (old.model_copy(update={"created": time.time() - KEEP_IDLE - 1}), fresh):
        await service.storage.create_table(record)
        await service.publisher.relay.backend.publish(channel_of(record.id), b"{}", JSON)
    assert await sweep(service.storage, service.publisher, time.time()) == [old.id]
    backend = service.publisher.relay.backend
    assert await service.storage.get_table(old.id) is None
    assert await backend.info(channel_of(old.id)) is None  # the channel and its buffer: gone
    assert (await backend.info(channel_of(fresh.id))).messages == 1
    response = await server.get(f"/api/tables/{old.id}")
    assert response.status == 404


async def test_a_table_channels_backlog_is_bounded_in_bytes(server: TestClient) -> None:
    """Outcomes with large trajectories: the backlog stays within the service's byte bound
    however many are published, far below the message count bound times their size."""
    backend = service_of(server).publisher.relay.backend
    channel = channel_of("3" * 20)
    outcome = b'{"trajectory": "' + b"x" * (SERVICE_BUFFER.buffer_bytes // 5) + b'"}'
    for _ in range(20):
        await backend.publish(channel, outcome, JSON)
    backlog = await backend.read_since(channel, None, SERVICE_BUFFER.buffer_length)
    kept = sum(len(m.data) for m in backlog.messages)
    assert 0 < kept <= SERVICE_BUFFER.buffer_bytes and len(backlog.messages) < 20


async def test_a_sweep_drops_guests_unused_for_a_day(server: TestClient) -> None:
    """Before: every registered guest stayed in storage for good."""
    service = service_of(server)
    ada = await register(server, "Ada")
    now = time.time()
    await sweep(service.storage, service.publisher, now + GUEST_KEPT - 60)
    assert await service.storage.get_player(ada.info["id"]) is not None  # seen a day ago
    await sweep(service.storage, service.publisher, now + GUEST_KEPT + 60)
    assert await service.storage.get_player(ada.info["id"]) is None
