import pytest

from tests.physics_kernel.engines import other_engine


@pytest.fixture(scope="session")
def other():
    """A worker process running the other engine (see engines.py)."""
    with other_engine() as pool:
        yield pool
