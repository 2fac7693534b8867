"""Build the compiled kernel of the physics engine, when a C compiler is there.

Cython compiles the engine's hot modules (listed in KERNEL) from their own Python source into
extension modules beside them; the .pxd file next to each module gives the compiler the C
types, so the .py stays the one source of the engine and runs unchanged where nothing was
compiled. Without Cython or without a working C compiler the build warns and the package
installs as pure Python. docs/physics.md, "The compiled kernel", says why the flags below
keep every result bit-identical to the pure-Python engine.
"""

from __future__ import annotations

import runpy
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

#: The modules, C flags and Cython directives of the kernel, from physics/kernel.py (read
#: without importing the package, whose dependencies the build environment does not have).
KERNEL = runpy.run_path("physics/kernel.py")


class OptionalBuildExt(build_ext):
    """build_ext that warns instead of failing: the engine then runs as pure Python."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as exc:  # no compiler at all, or a broken toolchain
            _warn(exc)

    def build_extension(self, ext: Extension) -> None:
        try:
            super().build_extension(ext)
        except Exception as exc:
            _warn(exc)


def _warn(exc: BaseException) -> None:
    print(f"billiards: compiled kernel not built ({exc}); using pure Python", file=sys.stderr)


def _extensions() -> list[Extension]:
    try:
        from Cython.Build import cythonize
    except ImportError:
        _warn(ImportError("Cython is not installed"))
        return []
    modules = [
        Extension(name, [name.replace(".", "/") + ".py"], extra_compile_args=KERNEL["C_FLAGS"])
        for name in KERNEL["MODULES"]
    ]
    return cythonize(modules, compiler_directives=KERNEL["DIRECTIVES"], quiet=True)


setup(ext_modules=_extensions(), cmdclass={"build_ext": OptionalBuildExt})
