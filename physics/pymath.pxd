"""Python's `math`, as the kernel sees it: C functions that give what `math` gives, to the bit.

A kernel module's .pxd says `cimport physics.pymath as math`: its `math.hypot(x, y)` then
calls the C function here instead of the Python one, with no change to the .py. Each function
returns what Python's does and raises where it raises (a domain or range error):
- sqrt, exp, copysign, nextafter, isfinite: Python's math module calls these same C library
  functions (and sqrt is correctly rounded by IEEE 754 in any case).
- hypot: Python computes it its own way (exact squares, a compensated sum and one correction
  step after the square root, the method of Borges, "An Improved Algorithm for hypot(a, b)",
  2019), which differs from the C library's hypot in about one result in three hundred. The
  function below takes the same steps in the same order; tests/physics_kernel/test_pymath.py
  checks it against math.hypot.
"""

cimport cython
from libc cimport math as libm
from libc.math cimport copysign, isfinite, nextafter
from libc.stdint cimport uint64_t


cdef extern from "<float.h>":
    const double DBL_MIN

cdef extern from "<math.h>":
    const double inf "INFINITY"
    const double nan "NAN"


cdef inline double sqrt(double x) except? -1.0:
    if x < 0.0:
        raise ValueError("math domain error")
    return libm.sqrt(x)


cdef inline double exp(double x) except? -1.0:
    cdef double r = libm.exp(x)
    if not isfinite(r) and isfinite(x):
        raise OverflowError("math range error")
    return r


cdef union _Bits:
    double d
    uint64_t u


cdef inline void _split(double x, double *hi, double *lo) noexcept nogil:
    """x = hi + lo, hi holding the upper half of x's bits (Veltkamp's split, at 2^27 + 1)."""
    cdef double t = x * 134217729.0
    hi[0] = t - (t - x)
    lo[0] = x - hi[0]


cdef inline void _exact(double xh, double xl, double yh, double yl, double *hi,
                        double *lo) noexcept nogil:
    """(xh + xl) (yh + yl) = hi + lo exactly, from split factors (Dekker's product)."""
    cdef double p = xh * yh
    cdef double q = xh * yl + xl * yh
    hi[0] = p + q
    lo[0] = p - hi[0] + q + xl * yl


cdef inline void _product(double x, double y, double *hi, double *lo) noexcept nogil:
    """x * y = hi + lo exactly."""
    cdef double xh, xl, yh, yl
    _split(x, &xh, &xl)
    _split(y, &yh, &yl)
    _exact(xh, xl, yh, yl, hi, lo)


cdef inline void _square(double x, double *hi, double *lo) noexcept nogil:
    """_product(x, x), splitting x once."""
    cdef double xh, xl
    _split(x, &xh, &xl)
    _exact(xh, xl, xh, xl, hi, lo)


cdef inline void _add(double hi, double lo, double *sums) noexcept nogil:
    """Add an exact product hi + lo to the sums: hi to sums[0] (its rounding error to sums[2]),
    lo to sums[1]."""
    cdef double s
    s = sums[0] + hi
    sums[2] += (sums[0] - s) + hi
    sums[0] = s
    sums[1] += lo


@cython.cdivision(True)  # by a power of two or by 2 h > 0: never by zero
cdef inline double _norm(double a, double b, double big) noexcept nogil:
    """sqrt(a^2 + b^2) for finite a, b >= 0 with big = max(a, b) > 0."""
    cdef int e
    cdef double scale, h, x, hi, lo
    cdef double sums[3]  # csum (starts at 1, so that its sums are exact), frac1, frac2
    cdef _Bits bits
    bits.d = big
    cdef int biased = <int>((bits.u >> 52) & 0x7ff)
    if 0 < biased <= 2044:
        # frexp and ldexp by the bits: big = m 2^e with m in [0.5, 1), and scale = 2^-e
        e = biased - 1022
        bits.u = (<uint64_t>(1023 - e)) << 52
        scale = bits.d
    else:
        libm.frexp(big, &e)
        if e < -1023:  # subnormal: 2^-e would overflow, so scale up by DBL_MIN first
            return DBL_MIN * _norm(a / DBL_MIN, b / DBL_MIN, big / DBL_MIN)
        scale = libm.ldexp(1.0, -e)
    sums[0], sums[1], sums[2] = 1.0, 0.0, 0.0
    _square(a * scale, &hi, &lo)
    _add(hi, lo, sums)
    _square(b * scale, &hi, &lo)
    _add(hi, lo, sums)
    h = libm.sqrt(sums[0] - 1.0 + (sums[1] + sums[2]))
    _product(-h, h, &hi, &lo)  # the residual a^2 + b^2 - h^2, nearly exact
    _add(hi, lo, sums)
    x = sums[0] - 1.0 + (sums[1] + sums[2])
    h += x / (2.0 * h)
    return h / scale


cdef inline double hypot(double x, double y) noexcept nogil:
    """math.hypot(x, y), to the last bit."""
    cdef double a = libm.fabs(x)
    cdef double b = libm.fabs(y)
    cdef double big = 0.0
    if a > big:
        big = a
    if b > big:
        big = b
    if big == inf:
        return big
    if a != a or b != b:
        return libm.NAN
    if big == 0.0:
        return big
    return _norm(a, b, big)


cdef inline bint clears(double x, double y, double ax, double ay, double h,
                        double clearance) noexcept nogil:
    """physics/pymath.py's clears, to the same answer: hypot(x, y) - sag > clearance, sag being
    0.125 hypot(ax, ay) h^2.

    Away from the boundary the answer follows from d = sqrt(x^2 + y^2) and g = sqrt(ax^2 +
    ay^2), each within 1e-15 of its hypot in relative terms when their squares neither
    underflow nor overflow (as here: the guards), so that d - sag' is within 3e-15 (d + sag')
    of the exact difference; a margin of 1e-12 (d + sag') around the clearance leaves only
    the cases within it to the exact computation. NaNs fail the guards and go there too.
    """
    cdef double q = x * x + y * y
    cdef double g2 = ax * ax + ay * ay
    cdef double d, sag, margin
    if 1e-150 < q < 1e150 and (1e-150 < g2 < 1e150 or (ax == 0.0 and ay == 0.0)) and (
        -1e50 < h < 1e50
    ):
        d = libm.sqrt(q)
        sag = 0.125 * libm.sqrt(g2) * h * h
        margin = 1e-12 * (d + sag)
        if d - sag > clearance + margin:
            return True
        if d - sag < clearance - margin:
            return False
    return hypot(x, y) - 0.125 * hypot(ax, ay) * h * h > clearance
