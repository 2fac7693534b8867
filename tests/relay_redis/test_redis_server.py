"""The redis-server fixture itself: a restart replays every acknowledged write from the AOF."""

from __future__ import annotations

import pytest
import redis

from tests.redis_server import RedisServer


@pytest.mark.parametrize("kill", [False, True], ids=["clean-stop", "sigkill"])
def test_restart_keeps_acknowledged_writes(redis_server: RedisServer, kill: bool) -> None:
    client = redis.Redis.from_url(redis_server.url)
    for i in range(50):
        client.xadd("s", {"n": i})
    client.close()

    redis_server.restart(kill=kill)

    client = redis.Redis.from_url(redis_server.url)
    assert [int(fields[b"n"]) for _, fields in client.xrange("s")] == list(range(50))
    client.close()


def test_stopped_server_refuses_connections(redis_server: RedisServer) -> None:
    redis_server.stop()
    client = redis.Redis.from_url(redis_server.url, socket_connect_timeout=0.5)
    with pytest.raises(redis.ConnectionError):
        client.ping()
    redis_server.start()
    assert client.ping()
    client.close()
