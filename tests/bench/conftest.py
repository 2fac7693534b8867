"""The relay fixtures (on both backends), for the tests of the benchmark's own clients."""

from tests.relay.conftest import redis_url_or_none, start_relay

__all__ = ["redis_url_or_none", "start_relay"]
