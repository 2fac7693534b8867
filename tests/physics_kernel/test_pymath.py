"""physics/pymath.pxd, the kernel's `math`, against Python's own (and its `clears` against
physics/pymath.py's), on many random arguments.

Its functions are C inline functions, so a probe extension that runs them is compiled here,
with the kernel's flags (Cython and a C compiler, which dev.sh installs).
"""

import importlib.util
import math
import random
import subprocess
import sys
from array import array
from pathlib import Path

import pytest

from physics import pymath

ROOT = Path(__file__).resolve().parents[2]
PROBE = """
cimport physics.pymath as m

def hypot(double[:] x, double[:] y, double[:] out):
    for i in range(x.shape[0]):
        out[i] = m.hypot(x[i], y[i])

def sqrt(double x):
    return m.sqrt(x)

def clears(double x, double y, double ax, double ay, double h, double clearance):
    return m.clears(x, y, ax, ay, h, clearance)

def exp(double x):
    return m.exp(x)
"""
BUILD = """
import sys
from setuptools import Extension, setup
from Cython.Build import cythonize
from physics import kernel
ext = Extension("pymath_probe", ["pymath_probe.pyx"], extra_compile_args=kernel.C_FLAGS)
setup(
    ext_modules=cythonize([ext], include_path=[sys.argv[1]], quiet=True,
                          compiler_directives=kernel.DIRECTIVES),
    script_args=["-q", "build_ext", "--inplace"],
)
"""


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    where = tmp_path_factory.mktemp("pymath")
    (where / "pymath_probe.pyx").write_text(PROBE)
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}
    subprocess.run(
        [sys.executable, "-c", BUILD, str(ROOT)],
        cwd=where,
        env=env,
        check=True,
        capture_output=True,
    )
    (built,) = where.glob("pymath_probe*.so")
    spec = importlib.util.spec_from_file_location("pymath_probe", built)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def arguments(n, rng):
    """Pairs over the ranges the engine sees and far beyond, and every pair of edge cases."""
    xs, ys = [], []
    for _ in range(n):
        e = rng.uniform(-40.0, 8.0)
        xs.append(rng.uniform(-1.0, 1.0) * 10.0**e)
        ys.append(rng.uniform(-1.0, 1.0) * 10.0 ** (e + rng.choice([0.0, rng.uniform(-20, 20)])))
    edges = [0.0, -0.0, 1.0, 3.0, 5e-324, 1e-310, 2.2250738585072014e-308, 1.7976931348623157e308]
    edges += [1e300, 2e307, 4.5e307, 9e307, -1e-300, math.inf, -math.inf, math.nan]
    for a in edges:
        for b in edges:
            xs.append(a)
            ys.append(b)
    return array("d", xs), array("d", ys)


def test_hypot_is_pythons_to_the_bit(probe):
    rng = random.Random(14)
    for _ in range(10):
        xs, ys = arguments(200_000, rng)
        out = array("d", bytes(8 * len(xs)))
        probe.hypot(xs, ys, out)
        for x, y, h in zip(xs, ys, out, strict=True):
            expected = math.hypot(x, y)
            assert h == expected or (math.isnan(h) and math.isnan(expected)), (x, y)


@pytest.mark.parametrize("x", [0.0, -0.0, 2.0, 1e-300, math.inf, math.nan])
def test_sqrt_and_exp_as_python(probe, x):
    for ours, theirs in ((probe.sqrt, math.sqrt), (probe.exp, math.exp)):
        a, b = ours(x), theirs(x)
        assert a == b or (math.isnan(a) and math.isnan(b))
        assert math.copysign(1.0, a) == math.copysign(1.0, b)


@pytest.mark.parametrize(("x", "error"), [(-1.0, ValueError), (-math.inf, ValueError)])
def test_sqrt_domain_error(probe, x, error):
    with pytest.raises(error):
        probe.sqrt(x)


def test_exp_range_error(probe):
    with pytest.raises(OverflowError):
        probe.exp(1000.0)
    assert probe.exp(-1000.0) == 0.0


def clears_arguments(n, rng):
    """(x, y, ax, ay, h, clearance) as path_misses passes them, and far beyond; each with
    clearances at the exact boundary, an ulp either side, and about the fast path's margin.
    """
    edges = [0.0, -0.0, 1e-300, 1e-160, 1e160, math.inf, -math.inf, math.nan]
    for k in range(n):
        if k % 10 == 0:
            x, y, ax, ay, h = (rng.choice([*edges, rng.uniform(-1, 1)]) for _ in range(5))
        else:
            e = rng.uniform(-30.0, 3.0)
            x, y = (rng.uniform(-1.0, 1.0) * 10.0 ** (e + rng.uniform(-3, 3)) for _ in range(2))
            ax, ay = (rng.choice([0.0, rng.uniform(-20.0, 20.0)]) for _ in range(2))
            h = rng.choice([0.0, rng.uniform(0.0, 10.0), 10.0 ** rng.uniform(-12, 2)])
        with_sag = math.hypot(x, y) - 0.125 * math.hypot(ax, ay) * h * h
        for c in (with_sag, 0.05 * rng.random(), -with_sag, 0.0):
            if not math.isfinite(c):
                yield x, y, ax, ay, h, c
                continue
            yield x, y, ax, ay, h, c
            yield x, y, ax, ay, h, math.nextafter(c, math.inf)
            yield x, y, ax, ay, h, math.nextafter(c, -math.inf)
            for scale in (1e-13, 1e-12, 1e-11):  # inside the margin, at it, beyond it
                yield x, y, ax, ay, h, c * (1.0 + scale * rng.uniform(-1.0, 1.0))


def test_clears_gives_pythons_answer(probe):
    rng = random.Random(14)
    for args in clears_arguments(100_000, rng):
        assert probe.clears(*args) == pymath.clears(*args), args
