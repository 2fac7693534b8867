"""The publisher endpoint: nchan's status codes, channel info formats, ids, delete."""

from __future__ import annotations

import json

import aiohttp
import msgpack

from server.relay.ids import parse_message_id
from tests.relay.conftest import RelayHarness, receive, receive_meta, wait_subscribers


async def test_publish_answers_202_without_subscribers_and_201_with(relay: RelayHarness) -> None:
    response = await relay.publish("game1", {"move": 1})
    assert response.status == 202
    ws = await relay.ws("/sub/game1")
    await receive_meta(ws)  # the buffered message: the subscription is live
    response = await relay.publish("game1", {"move": 2})
    assert response.status == 201
    await ws.close()


async def test_publish_answers_channel_info_as_text_or_json(relay: RelayHarness) -> None:
    response = await relay.publish("game1", {"n": 1})
    text = await response.text()
    assert response.headers["Content-Type"] == "text/plain"  # no charset, as nchan
    lines = text.split("\r\n")  # CRLF line ends, no final one
    assert lines[0] == "queued messages: 1"
    assert lines[2] == "active subscribers: 0"
    assert lines[3].startswith("last message id: ") and not text.endswith("\n")
    response = await relay.client.post(
        "/pub/game1",
        data=b"[2]",
        headers={
            "Content-Type": "application/json",
            "Accept": "text/json",
            **relay.auth("game1"),
        },
    )
    assert response.headers["Content-Type"] == "text/json"
    info = json.loads(await response.text())
    assert info["messages"] == 2
    assert info["subscribers"] == 0
    assert parse_message_id(info["last_message_id"])


async def test_get_info_of_unknown_channel_is_404(relay: RelayHarness) -> None:
    response = await relay.client.get("/pub/never_published")
    assert response.status == 404
    assert "never_published" in (await response.json())["error"]


async def test_get_info_counts_messages_and_subscribers(relay: RelayHarness) -> None:
    for n in range(3):
        await relay.publish_ok("game1", n)
    ws = await relay.ws("/sub/game1")
    await wait_subscribers(relay, "game1", 1)
    info = await relay.info("game1")
    assert info is not None
    assert info["messages"] == 3
    assert info["subscribers"] == 1
    response = await relay.client.get("/pub/game1", headers={"Accept": "text/plain"})
    text = await response.text()
    assert text.endswith(f"\r\nlast message id: {info['last_message_id']}")
    await ws.close()


async def test_ids_increase_within_a_channel(relay: RelayHarness) -> None:
    ids = [await relay.publish_ok("game1", n) for n in range(20)]
    keys = [parse_message_id(message_id) for message_id in ids]
    assert keys == sorted(keys)
    assert len(set(keys)) == len(keys)


async def test_msgpack_body_is_accepted_and_kept_as_msgpack(relay: RelayHarness) -> None:
    response = await relay.publish("game1", {"shot": [1.5, 2]}, as_msgpack=True)
    assert response.status == 202
    ws = await relay.ws("/sub/game1")
    _, content_type, data = await receive_meta(ws)
    assert content_type == "application/msgpack"
    assert msgpack.unpackb(data) == {"shot": [1.5, 2]}
    await ws.close()


async def test_delete_closes_subscribers_and_forgets_the_channel(relay: RelayHarness) -> None:
    await relay.publish_ok("game1", "hello")
    ws = await relay.ws("/sub/game1")
    await receive_meta(ws)
    response = await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
    assert response.status == 200
    closing = await receive(ws)
    assert closing.type == aiohttp.WSMsgType.CLOSE
    assert closing.data == aiohttp.WSCloseCode.GOING_AWAY  # 1001, as nchan
    assert closing.extra == "410 Gone"
    assert await relay.info("game1") is None
    again = await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
    assert again.status == 404


async def test_delete_needs_a_token_for_the_channel(relay: RelayHarness) -> None:
    await relay.publish_ok("game1", "hello")
    response = await relay.client.delete("/pub/game1")
    assert response.status == 401
    response = await relay.client.delete("/pub/game1", headers=relay.auth("game2"))
    assert response.status == 403
    assert await relay.info("game1") is not None


async def test_websocket_publisher_gets_channel_info_per_message(relay: RelayHarness) -> None:
    token = relay.token("game1")
    publisher = await relay.client.ws_connect(
        f"/pub/game1?token={token}", headers={"Accept": "application/json"}
    )
    await publisher.send_str('{"move": 1}')
    info = json.loads((await receive(publisher)).data)
    assert (info["messages"], info["subscribers"]) == (1, 0)
    subscriber = await relay.ws("/sub/game1")
    await receive_meta(subscriber)
    await publisher.send_bytes(msgpack.packb({"move": 2}))
    info = json.loads((await receive(publisher)).data)
    assert (info["messages"], info["subscribers"]) == (2, 1)
    _, content_type, data = await receive_meta(subscriber)
    assert (content_type, msgpack.unpackb(data)) == ("application/msgpack", {"move": 2})
    await publisher.send_str("{not json")
    refusal = json.loads((await receive(publisher)).data)
    assert refusal["status"] == 400
    await publisher.send_str('{"move": 3}')  # the socket stays usable after a refusal
    assert json.loads((await receive(publisher)).data)["messages"] == 3
    await publisher.close()
    await subscriber.close()


async def test_websocket_publisher_without_token_publishes_nothing(relay: RelayHarness) -> None:
    publisher = await relay.client.ws_connect("/pub/game1")
    await publisher.send_str('{"move": 1}')
    refusal = json.loads((await receive(publisher)).data)
    assert refusal["status"] == 401
    assert await relay.info("game1") is None
    await publisher.close()
