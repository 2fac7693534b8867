"""Connections per client address: the cap, and whose X-Forwarded-For is believed."""

from __future__ import annotations

import asyncio

import aiohttp
import pytest
from aiohttp.test_utils import make_mocked_request

from server.relay.addresses import client_address, networks
from tests.relay.conftest import WAIT_S, RelayHarness, StartRelay, wait_subscribers


async def _held_by(relay: RelayHarness, address: str, count: int) -> None:
    """Wait until `address` holds `count` subscriber connections (one closing ends later)."""
    while relay.relay.connections.held(address) != count:
        await asyncio.sleep(0.01)


async def _refused(response: aiohttp.ClientResponse) -> str:
    assert response.status == 429
    return (await response.json())["error"]


async def test_an_address_holds_at_most_its_cap_of_subscriber_connections(
    start_relay: StartRelay,
) -> None:
    relay = await start_relay(max_connections_per_address=2)
    first = await relay.ws("/sub/g")
    second = await relay.client.get("/sub/h", headers={"Accept": "text/event-stream"})
    await wait_subscribers(relay, "g", 1)
    await wait_subscribers(relay, "h", 1)
    with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
        await relay.ws("/sub/g")
    assert refused.value.status == 429
    error = await _refused(await relay.client.get("/sub/g", headers={"Accept": "text/json"}))
    assert "too many connections" in error
    assert relay.relay.backend.local_subscribers("g") == 1  # the refusals subscribed nothing

    await first.close()
    await asyncio.wait_for(_held_by(relay, "127.0.0.1", 1), WAIT_S)
    again = await relay.ws("/sub/g")  # a connection that ended frees its place
    await wait_subscribers(relay, "g", 1)
    await again.close()
    second.close()


async def test_forwarded_addresses_count_apart_only_behind_a_trusted_proxy(
    start_relay: StartRelay,
) -> None:
    def via(address: str) -> dict[str, str]:
        return {"X-Forwarded-For": f"203.0.113.9, {address}"}  # the client's own claim first

    trusted = await start_relay(max_connections_per_address=1, trusted_proxies=["127.0.0.0/8"])
    ada = await trusted.client.ws_connect("/sub/g", headers=via("198.51.100.1"))
    bob = await trusted.client.ws_connect("/sub/g", headers=via("198.51.100.2"))
    await wait_subscribers(trusted, "g", 2)
    with pytest.raises(aiohttp.WSServerHandshakeError):
        await trusted.client.ws_connect("/sub/g", headers=via("198.51.100.1"))

    untrusted = await start_relay(max_connections_per_address=1)  # the header is ignored
    carol = await untrusted.client.ws_connect("/sub/h", headers=via("198.51.100.1"))
    await wait_subscribers(untrusted, "h", 1)
    with pytest.raises(aiohttp.WSServerHandshakeError):
        await untrusted.client.ws_connect("/sub/h", headers=via("198.51.100.2"))
    await asyncio.gather(ada.close(), bob.close(), carol.close())


@pytest.mark.parametrize(
    ("peer", "header", "expected"),
    [
        ("10.0.0.2", None, "10.0.0.2"),  # no proxy in between
        ("10.0.0.2", "1.2.3.4", "1.2.3.4"),  # one trusted proxy
        ("10.0.0.2", "6.6.6.6, 1.2.3.4", "1.2.3.4"),  # a forged entry before the real one
        ("10.0.0.2", "1.2.3.4, 10.0.0.7", "1.2.3.4"),  # a chain of trusted proxies
        ("10.0.0.2", "10.0.0.8, 10.0.0.7", "10.0.0.8"),  # all trusted: the farthest
        ("192.0.2.1", "1.2.3.4", "192.0.2.1"),  # not from a trusted proxy: header ignored
        ("10.0.0.2", "not-an-address", "not-an-address"),  # kept apart, never trusted
    ],
)
def test_client_address(peer: str, header: str | None, expected: str) -> None:
    headers = {} if header is None else {"X-Forwarded-For": header}
    request = make_mocked_request("GET", "/", headers=headers)
    request = request.clone(remote=peer)
    assert client_address(request, networks(["10.0.0.0/8"])) == expected


def test_a_malformed_trusted_proxy_is_refused() -> None:
    with pytest.raises(ValueError):
        networks(["10.0.0.0/33"])
