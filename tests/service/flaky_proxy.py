"""A real TCP proxy in front of a real server that fails the way networks and load balancers
do, on the test's command: every open connection cut at once (a link or a replica that died,
WebSocket feeds included), the address refusing connections for a while, or one request
carried out by the server whose answer never reaches the client (nginx's 502 page when the
replica died after doing the work, or the connection closing with no answer at all).

It reads just enough HTTP/1.1 to know where each request starts and ends (a request line,
headers, a Content-Length body; after a WebSocket upgrade, raw bytes both ways) and passes
answers through untouched, except the one it was told to lose.
"""

from __future__ import annotations

import asyncio
import contextlib
from dataclasses import dataclass, field

#: The page nginx answers when its upstream failed, in the shape nginx sends it.
PAGE = "<html>\r\n<head><title>{0}</title></head>\r\n<body>\r\n<center><h1>{0}</h1></center>\r\n"
PHRASES = {404: "Not Found", 413: "Request Entity Too Large", 502: "Bad Gateway",
           503: "Service Unavailable", 504: "Gateway Time-out"}  # fmt: skip


@dataclass
class Loss:
    """The answer to lose of the next request whose target starts with `prefix`: replaced by
    a proxy's HTML page of `status`, or with None by closing the connection."""

    prefix: str
    status: int | None


@dataclass(eq=False)  # kept in a set: each link is itself
class Link:
    """One client connection and its connection to the server."""

    client: asyncio.StreamWriter
    upstream: asyncio.StreamWriter
    websocket: bool = False
    lose: Loss | None = None  # set while the request whose answer is to be lost is out

    def abort(self) -> None:
        for writer in (self.client, self.upstream):
            writer.transport.abort()


@dataclass
class FlakyProxy:
    upstream_port: int
    #: "METHOD target" of every request passed on to the server, in order.
    requests: list[str] = field(default_factory=list)
    _losses: list[Loss] = field(default_factory=list)
    _links: set[Link] = field(default_factory=set)
    _server: asyncio.Server | None = None
    _port: int = 0

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self._port}"

    async def __aenter__(self) -> FlakyProxy:
        await self.up()
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.down()

    async def up(self) -> None:
        """Accept connections (again, on the same port)."""
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", self._port)
        self._port = self._server.sockets[0].getsockname()[1]

    async def down(self) -> int:
        """Cut every connection and refuse new ones until `up`; the feeds cut (see `cut`)."""
        if self._server is not None:
            self._server.close()
            self._server = None
        return self.cut()

    def cut(self) -> int:
        """Close every open connection at once, both ways; how many were WebSocket feeds."""
        links, self._links = self._links, set()
        for link in links:
            link.abort()
        return sum(link.websocket for link in links)

    def lose_answer(self, prefix: str, status: int | None) -> None:
        """Pass the next request for `prefix...` on to the server, but lose its answer (see
        `Loss`). Called several times, the losses apply to the next matching requests in turn."""
        self._losses.append(Loss(prefix, status))

    async def _serve(self, client_in: asyncio.StreamReader, client: asyncio.StreamWriter) -> None:
        upstream_in, upstream = await asyncio.open_connection("127.0.0.1", self.upstream_port)
        link = Link(client, upstream)
        self._links.add(link)
        ways = [
            asyncio.create_task(self._requests(client_in, link)),
            asyncio.create_task(self._answers(upstream_in, link)),
        ]
        await asyncio.wait(ways, return_when=asyncio.FIRST_COMPLETED)  # one side ended: both do
        for way in ways:
            way.cancel()
        await asyncio.gather(*ways, return_exceptions=True)
        link.abort()
        self._links.discard(link)

    async def _requests(self, client_in: asyncio.StreamReader, link: Link) -> None:
        """Pass the client's requests on one by one, noting each (and which answer to lose)."""
        while True:
            try:
                head = await client_in.readuntil(b"\r\n\r\n")
            except (asyncio.IncompleteReadError, ConnectionError):
                return
            method, target = head.decode("latin-1").split(" ", 2)[:2]
            headers = _headers(head)
            body = await client_in.readexactly(int(headers.get("content-length", "0")))
            self.requests.append(f"{method} {target}")
            link.lose = self._take_loss(target)
            link.upstream.write(head + body)
            await link.upstream.drain()
            if headers.get("upgrade", "").lower() == "websocket":
                link.websocket = True
                await _pipe(client_in, link.upstream)
                return

    async def _answers(self, upstream_in: asyncio.StreamReader, link: Link) -> None:
        """Pass the server's answers back, except one to lose: the server answered (so it
        did the work), and the client gets the loss instead."""
        while data := await upstream_in.read(65536):
            if link.lose is not None:
                await _lose(link.client, link.lose.status)
                return
            link.client.write(data)
            await link.client.drain()

    def _take_loss(self, target: str) -> Loss | None:
        for loss in self._losses:
            if target.startswith(loss.prefix):
                self._losses.remove(loss)
                return loss
        return None


def _headers(head: bytes) -> dict[str, str]:
    lines = head.decode("latin-1").split("\r\n")[1:]
    pairs = (line.split(":", 1) for line in lines if ":" in line)
    return {name.strip().lower(): value.strip() for name, value in pairs}


async def _pipe(source: asyncio.StreamReader, sink: asyncio.StreamWriter) -> None:
    while data := await source.read(65536):
        sink.write(data)
        await sink.drain()


async def _lose(client: asyncio.StreamWriter, status: int | None) -> None:
    """Answer with a proxy's page of `status` and close (None: close with no answer)."""
    if status is not None:
        title = f"{status} {PHRASES.get(status, 'Error')}"
        page = PAGE.format(title) + "<hr><center>nginx</center>\r\n</body>\r\n</html>\r\n"
        head = f"HTTP/1.1 {title}\r\nServer: nginx\r\nContent-Type: text/html\r\n"
        head += f"Content-Length: {len(page)}\r\nConnection: close\r\n\r\n"
        client.write((head + page).encode())
    client.close()
    with contextlib.suppress(ConnectionError):
        await client.wait_closed()  # the page is out before the link is torn down
