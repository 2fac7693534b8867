"""Which engine runs: the compiled kernel or the pure-Python reference.

The kernel is the engine's own modules (MODULES) compiled by Cython from their .py source when
the package is built with a C compiler (setup.py); Python then imports the extension module in
place of the .py. Both give the same results to the last bit (docs/physics.md, "The compiled
kernel"). Setting BILLIARDS_PURE_PYTHON=1 in the environment runs the pure-Python engine even
where the kernel is built: the variable is read once, when `physics` is first imported, and
`use_source()` then makes every kernel module load from its .py file.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import os
import sys
from importlib.machinery import ModuleSpec
from pathlib import Path

#: The modules that make up the compiled kernel: the event loop, collision times and models.
MODULES = (
    "physics.roots",
    "physics.motion",
    "physics.ball_ball",
    "physics.cushion",
    "physics.engine",
    "physics.records",
)

#: IEEE arithmetic exactly as Python's floats do it: no fused multiply-add, no fast-math.
C_FLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math"]

#: Python's semantics where C's differ: division by zero raises, `**` and `%` as in Python.
DIRECTIVES = {
    "language_level": 3,
    "cdivision": False,
    "cpow": False,
    "binding": False,
    # The C types come from the .pxd files alone; the .py annotations stay for readers.
    "annotation_typing": False,
}

#: The environment variable that, set to anything but "" or "0", turns the kernel off.
PURE_ENV = "BILLIARDS_PURE_PYTHON"

_HERE = Path(__file__).resolve().parent


def pure_requested() -> bool:
    """True when the environment asks for the pure-Python engine."""
    return os.environ.get(PURE_ENV, "") not in ("", "0")


class _SourceFinder(importlib.abc.MetaPathFinder):
    """Finds the kernel's modules as their .py source, ahead of any compiled module."""

    def find_spec(self, name: str, path: object, target: object = None) -> ModuleSpec | None:
        if name not in MODULES:
            return None
        return importlib.util.spec_from_file_location(name, _HERE / f"{name[8:]}.py")


def use_source() -> None:
    """Load the kernel's modules from source from now on (before any of them is imported)."""
    loaded = [name for name in MODULES if name in sys.modules]
    if loaded:
        raise RuntimeError(f"{PURE_ENV}: kernel modules already imported: {', '.join(loaded)}")
    if not any(isinstance(f, _SourceFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, _SourceFinder())


def compiled() -> bool:
    """True when the engine in use is the compiled kernel."""
    from physics import engine

    return not engine.__file__.endswith(".py")
