"""BILLIARDS_PURE_PYTHON: read when `physics` is first imported, it picks the engine."""

import subprocess
import sys

import pytest

from physics import kernel

#: Prints whether the engine is compiled, then for each kernel module whether it is the .py.
PROBE = """
import sys
import physics
from physics import kernel
print(kernel.compiled(), *(sys.modules[m].__file__.endswith(".py") for m in kernel.MODULES))
"""


@pytest.mark.parametrize(("value", "pure"), [("1", True), ("yes", True), ("0", False), ("", False)])
def test_the_variable_picks_the_engine(value, pure):
    env = {"PATH": "/usr/bin:/bin", kernel.PURE_ENV: value}
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    assert out == [str(not pure)] + [str(pure)] * len(kernel.MODULES)


def test_too_late_once_a_kernel_module_is_imported():
    import physics.engine  # noqa: F401

    with pytest.raises(RuntimeError, match="already imported"):
        kernel.use_source()
