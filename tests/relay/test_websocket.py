"""WebSocket subscribers: plain and ws+meta.nchan frames, publishing, multiplexing."""

from __future__ import annotations

import json

import aiohttp
import msgpack

from server.relay.ids import parse_message_id
from tests.relay.conftest import RelayHarness, StartRelay, receive, receive_meta, wait_subscribers


async def test_plain_frames_carry_only_the_data(relay: RelayHarness) -> None:
    ws = await relay.ws("/sub/game1", meta=False)
    assert ws.protocol is None
    await wait_subscribers(relay, "game1", 1)
    await relay.publish_ok("game1", {"a": 1})
    await relay.publish_ok("game1", {"b": 2}, as_msgpack=True)
    text = await receive(ws)
    assert text.type == aiohttp.WSMsgType.TEXT
    assert json.loads(text.data) == {"a": 1}
    binary = await receive(ws)
    assert binary.type == aiohttp.WSMsgType.BINARY
    assert msgpack.unpackb(binary.data) == {"b": 2}
    await ws.close()


async def test_meta_subprotocol_frames_carry_id_and_content_type(relay: RelayHarness) -> None:
    ws = await relay.ws("/sub/game1")
    assert ws.protocol == "ws+meta.nchan"
    await wait_subscribers(relay, "game1", 1)
    published = await relay.publish_ok("game1", {"a": 1})
    frame = await receive(ws)
    assert frame.type == aiohttp.WSMsgType.TEXT
    assert frame.data == f'id: {published}\ncontent-type: application/json\n\n{{"a": 1}}'
    await ws.close()


async def test_frames_sent_by_the_client_are_published(relay: RelayHarness) -> None:
    token = relay.token("game1")
    player = await relay.ws(f"/sub/game1?token={token}")
    watcher = await relay.ws("/sub/game1")
    await wait_subscribers(relay, "game1", 2)
    await player.send_str('{"shot": 1}')
    await player.send_bytes(msgpack.packb({"shot": 2}))
    for ws in (player, watcher):
        _, content_type, data = await receive_meta(ws)
        assert (content_type, json.loads(data)) == ("application/json", {"shot": 1})
        _, content_type, data = await receive_meta(ws)
        assert (content_type, msgpack.unpackb(data)) == ("application/msgpack", {"shot": 2})
    await player.close()
    await watcher.close()


async def test_websocket_publish_to_another_channel_with_pub(relay: RelayHarness) -> None:
    token = relay.token("moves")
    ws = await relay.ws(f"/sub/game1?pub=moves&token={token}")
    await wait_subscribers(relay, "game1", 1)
    await ws.send_str("[1]")
    mover = await relay.ws("/sub/moves")
    _, _, data = await receive_meta(mover)
    assert json.loads(data) == [1]
    await ws.close()
    await mover.close()


async def test_refused_websocket_publish_closes_with_the_reason(relay: RelayHarness) -> None:
    ws = await relay.ws("/sub/game1")  # no token
    await ws.send_str('{"cheat": true}')
    closing = await receive(ws)
    assert closing.type == aiohttp.WSMsgType.CLOSE
    assert closing.data == 4401
    assert "token" in closing.extra
    info = await relay.info("game1")
    assert info is None or info["messages"] == 0
    token = relay.token("game1")
    ws = await relay.ws(f"/sub/game1?token={token}")
    await ws.send_str('{"broken": ')
    closing = await receive(ws)
    assert closing.data == 4400
    assert "malformed JSON" in closing.extra
    info = await relay.info("game1")
    assert info is None or info["messages"] == 0


async def test_oversized_websocket_frame_is_refused(start_relay: StartRelay) -> None:
    relay = await start_relay(max_message_bytes=100)
    ws = await relay.ws(f"/sub/game1?token={relay.token('game1')}")
    await ws.send_str('"' + "x" * 200 + '"')
    closing = await receive(ws)
    assert closing.type == aiohttp.WSMsgType.CLOSE
    assert closing.data == aiohttp.WSCloseCode.MESSAGE_TOO_BIG
    info = await relay.info("game1")
    assert info is None or info["messages"] == 0


async def test_one_websocket_multiplexes_several_channels(relay: RelayHarness) -> None:
    ws = await relay.ws("/sub/table1,table2")
    await wait_subscribers(relay, "table1", 1)
    await wait_subscribers(relay, "table2", 1)
    a = await relay.publish_ok("table1", "a")
    b = await relay.publish_ok("table2", "b")
    c = await relay.publish_ok("table1", "c")
    cursors = [await receive_meta(ws) for _ in range(3)]
    assert [json.loads(data) for _, _, data in cursors] == ["a", "b", "c"]
    assert cursors[0][0] == f"table1/{a}"
    assert cursors[1][0] == f"table2/{b},table1/{a}"
    assert cursors[2][0] == f"table1/{c},table2/{b}"
    await ws.close()
    d = await relay.publish_ok("table2", "d")
    e = await relay.publish_ok("table1", "e")
    ws = await relay.ws(f"/sub/table1,table2?last_event_id={cursors[1][0]}")
    resumed = sorted([await receive_meta(ws) for _ in range(3)], key=lambda got: got[0])
    ids = {got[0].split(",")[0]: json.loads(got[2]) for got in resumed}
    assert ids == {f"table1/{c}": "c", f"table1/{e}": "e", f"table2/{d}": "d"}
    await ws.close()
    assert parse_message_id(e) > parse_message_id(c)


async def test_multiplexing_rejects_bad_channel_lists(relay: RelayHarness) -> None:
    for path in ("/sub/a,a", "/sub/" + ",".join(f"c{n}" for n in range(9)), "/sub/a,b.c"):
        response = await relay.client.get(path, headers={"Accept": "text/event-stream"})
        assert response.status == 400, path
    response = await relay.client.get("/sub/a,b?last_event_id=zzz/1:0")
    assert response.status == 400


async def test_one_message_reaches_plain_and_meta_subscribers_in_their_framing(
    start_relay: StartRelay,
) -> None:
    """Frames are built once per message and framing: sizes across all three length forms of
    RFC 6455 (7-bit, 16-bit, 64-bit) reach plain and `ws+meta.nchan` subscribers intact."""
    relay = await start_relay(max_message_bytes=100_000)
    plain = [await relay.ws("/sub/game1", meta=False) for _ in range(2)]
    meta = [await relay.ws("/sub/game1") for _ in range(2)]
    await wait_subscribers(relay, "game1", 4)
    for size in (10, 300, 70_000):
        value = "y" * size
        message_id = await relay.publish_ok("game1", value)
        for ws in plain:
            assert json.loads((await receive(ws)).data) == value
        for ws in meta:
            assert await receive_meta(ws) == (
                message_id,
                "application/json",
                json.dumps(value).encode(),
            )
    for ws in plain + meta:
        await ws.close()


async def test_compressing_subscribers_get_every_message_in_order(relay: RelayHarness) -> None:
    """permessage-deflate gives each connection its own compressor, so its frames cannot be
    shared: they go through the connection's queue, and arrive whole and in order."""
    compressed = await relay.client.ws_connect("/sub/game1", compress=15)
    assert compressed.compress == 15  # negotiated
    plain = await relay.ws("/sub/game1", meta=False)
    await wait_subscribers(relay, "game1", 2)
    for n in range(20):
        await relay.publish("game1", {"n": n, "pad": "z" * 200})
    for ws in (compressed, plain):
        assert [json.loads((await receive(ws)).data)["n"] for _ in range(20)] == list(range(20))
    await compressed.close()
    await plain.close()
