"""Suite-wide fixtures: a real redis-server (see tests/redis_server.py), and hypothesis's CI
profile: in CI the property tests replay the same examples every run, so a landing never
hangs on a lucky draw; on a developer's machine they keep exploring."""

import os

from hypothesis import settings

pytest_plugins = ["tests.redis_server"]

settings.register_profile("ci", derandomize=True, deadline=None)
if os.environ.get("CI"):
    settings.load_profile("ci")
