"""Suite-wide fixtures: a real redis-server (see tests/redis_server.py)."""

pytest_plugins = ["tests.redis_server"]
