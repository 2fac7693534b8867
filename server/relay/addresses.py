"""Who is connecting: a client's address, and the subscriber connections each address holds.

Behind a load balancer every connection comes from the balancer, and the client's own address
is the one the balancer appended to `X-Forwarded-For` (nginx's `$proxy_add_x_forwarded_for`).
That header is believed only from the trusted proxies of the settings: from anyone else it is a
claim the client wrote itself, and could name any address. Walking the header from its right
end, past the entries that are themselves trusted proxies (a chain of balancers), the first
address left is the client's.

A cap on the connections one address holds stops one host from taking every file descriptor
of a replica; it is off by default, since the relay's byte bounds hold without it and the tests
and benchmarks here open thousands of connections from loopback (deploy/ sets one).
"""

from __future__ import annotations

import ipaddress

from aiohttp import web

from server.relay.errors import RelayError

Network = ipaddress.IPv4Network | ipaddress.IPv6Network


def networks(entries: list[str]) -> tuple[Network, ...]:
    """The trusted proxies' networks from addresses or CIDR blocks (ValueError if malformed)."""
    return tuple(ipaddress.ip_network(entry, strict=False) for entry in entries)


def _trusted(address: str, trusted: tuple[Network, ...]) -> bool:
    try:
        ip = ipaddress.ip_address(address)
    except ValueError:
        return False
    return any(ip in network for network in trusted)


def client_address(request: web.Request, trusted: tuple[Network, ...]) -> str:
    """The address of the client behind `request` (see the module docstring)."""
    address = request.remote or ""
    if not trusted or not _trusted(address, trusted):
        return address
    for hop in reversed(request.headers.getall("X-Forwarded-For", [])):
        for entry in reversed(hop.split(",")):
            address = entry.strip()
            if not _trusted(address, trusted):
                return address
    return address  # every hop a trusted proxy: the farthest one is the client


class ConnectionCounts:
    """Subscriber connections held per client address, at most `cap` each (None: no cap)."""

    def __init__(self, cap: int | None) -> None:
        self.cap = cap
        self._held: dict[str, int] = {}

    def held(self, address: str) -> int:
        return self._held.get(address, 0)

    def acquire(self, address: str) -> None:
        """Count one more connection of `address`; RelayError(429), counting nothing, if it
        already holds `cap`. Each acquire is matched by one `release` when the connection ends."""
        held = self._held.get(address, 0)
        if self.cap is not None and held >= self.cap:
            raise RelayError(429, f"too many connections from {address} (at most {self.cap})")
        self._held[address] = held + 1

    def release(self, address: str) -> None:
        left = self._held[address] - 1
        if left:
            self._held[address] = left
        else:
            del self._held[address]
