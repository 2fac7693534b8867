"""Fan-out: one feed per channel per process however many subscribe, every one delivered."""

from __future__ import annotations

import json

from tests.relay.conftest import RelayHarness, receive_meta, wait_subscribers


async def test_many_subscribers_share_one_feed_per_channel(relay: RelayHarness) -> None:
    backend = relay.relay.backend
    sockets = [await relay.ws("/sub/game1") for _ in range(5)]
    sockets.append(await relay.ws("/sub/game2,game1"))
    await wait_subscribers(relay, "game1", 6)
    await wait_subscribers(relay, "game2", 1)
    assert backend.open_feeds == 2
    for n in range(3):
        assert (await relay.publish("game1", n)).status == 201
    for ws in sockets:
        assert [json.loads((await receive_meta(ws))[2]) for _ in range(3)] == [0, 1, 2]
    for ws in sockets:
        await ws.close()
    await wait_subscribers(relay, "game1", 0)
    assert backend.open_feeds == 0  # the last subscriber gone, the feed stops
