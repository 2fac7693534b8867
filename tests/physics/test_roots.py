"""The collision-time solver: the earliest root, never a missed or a spurious one."""

import math
from itertools import pairwise

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from physics.roots import first_entry, first_entry_quadratic, path_misses


def brute_first(c, hi, n=400_001):
    ts = np.linspace(0.0, hi, n)
    f = np.polynomial.polynomial.polyval(ts, c)
    hit = np.nonzero(f <= 0)[0]
    return None if len(hit) == 0 else ts[hit[0]]


@settings(max_examples=300, deadline=None)
@given(
    roots=st.lists(st.floats(-1.0, 3.0), min_size=4, max_size=4),
    sign=st.sampled_from([1.0, -1.0]),
)
def test_first_entry_matches_dense_sampling(roots, sign):
    """Distinct roots (a triple or quadruple root is float noise wide: see the double-root
    test for the grazing case that matters)."""
    roots = sorted(roots)
    assume(min(b - a for a, b in pairwise(roots)) > 1e-3)
    c = tuple(float(x) * sign for x in np.polynomial.polynomial.polyfromroots(roots))
    got = first_entry(c, 2.0)
    ref = brute_first(c, 2.0)
    assert (got == math.inf) == (ref is None)
    if ref is not None:
        assert abs(got - ref) < 1e-5


def test_double_root_is_a_contact_not_a_miss():
    """A grazing contact: f touches zero at t = 1 without crossing."""
    c = tuple(np.polynomial.polynomial.polyfromroots([1.0, 1.0, -5.0, -6.0]))
    t = first_entry(c, 2.0)
    assert abs(t - 1.0) < 1e-6


def test_near_miss_reports_nothing():
    c = tuple(np.polynomial.polynomial.polyfromroots([1.0, 1.0, -5.0, -6.0]))
    c = (c[0] + 1e-9, *c[1:])
    assert first_entry(c, 2.0) == math.inf


def test_root_is_never_before_the_contact():
    """The reported time is at or just after the crossing, so no contact is resolved early."""
    c = (1.0, -3.0, 0.5, 0.1, 0.01)
    t = first_entry(c, 5.0)
    assert np.polynomial.polynomial.polyval(t, c) <= 0.0
    assert np.polynomial.polynomial.polyval(t - 1e-12, c) > 0.0


def test_quadratic_closed_form():
    assert first_entry_quadratic(1.0, -3.0, 2.0, 10.0) == 0.5
    assert first_entry_quadratic(1.0, 3.0, 2.0, 10.0) == math.inf
    assert first_entry_quadratic(1.0, -3.0, 2.0, 0.25) == math.inf


def test_path_misses_is_conservative():
    """Whenever the culling test says 'misses', the dense path really stays clear."""
    rng = np.random.default_rng(3)
    for _ in range(2000):
        p, v, a = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2) * 3
        h, clearance = rng.uniform(0.1, 2.0), rng.uniform(0.05, 1.0)
        if path_misses(*p, *v, *a, h, clearance):
            ts = np.linspace(0, h, 2001)[:, None]
            path = p + v * ts + 0.5 * a * ts**2
            assert np.min(np.linalg.norm(path, axis=1)) > clearance - 1e-12
    assert not path_misses(1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 2.0, 0.5)
    assert path_misses(1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.5)
