# The C types of physics/roots.py for the compiled kernel (setup.py); the .py is the source.
cimport cython
cimport physics.pymath as math
cimport physics.pymath as pymath

cdef int _NEWTON_ITERS

# A polynomial (roots.Poly, of degree up to four) as a C struct of five doubles.
ctypedef (double, double, double, double, double) Quartic

@cython.locals(c0=cython.double, c1=cython.double, c2=cython.double, c3=cython.double,
               c4=cython.double)
cdef double _horner(Quartic c, double t) noexcept
cdef Quartic _derivative(Quartic c) noexcept
cdef int _degree(Quartic c) noexcept
@cython.locals(disc=cython.double, q=cython.double, r1=cython.double, r2=cython.double)
cdef (double, double) _quadratic_roots(double c0, double c1, double c2) except *

@cython.locals(t=cython.double, f=cython.double, d=cython.double, step=cython.double,
               _=cython.int)
cdef double _refine(Quartic c, Quartic dc, double lo, double hi) except? -1.0
@cython.locals(knots=list, degree=cython.int, turn=cython.double, r1=cython.double,
               r2=cython.double)
cdef list _knots(Quartic dc, double lo, double hi)
@cython.locals(f_prev=cython.double, f_b=cython.double, a=cython.double, b=cython.double,
               k=Py_ssize_t, dc=Quartic, knots=list, roots=list)
cpdef list all_roots(Quartic c, double hi)
@cython.locals(c0=cython.double, c1=cython.double, c2=cython.double, c3=cython.double,
               c4=cython.double)
cdef Quartic _negated(Quartic c) noexcept
cdef double _refine_neg(Quartic c, Quartic dc, double lo, double hi) except? -1.0

@cython.locals(cx=cython.double, cy=cython.double, chord2=cython.double, s=cython.double)
cpdef bint path_misses(double px, double py, double vx, double vy, double ax, double ay,
                       double h, double clearance) except -1
@cython.locals(r1=cython.double, r2=cython.double)
cpdef double first_entry_quadratic(double c0, double c1, double c2, double hi,
                                   double skip=*) except? -1.0
@cython.locals(a=cython.double, b=cython.double, k=Py_ssize_t, dc=Quartic, knots=list)
cpdef double first_entry(Quartic c, double hi, double skip=*) except? -1.0
@cython.locals(c0=cython.double, c1=cython.double, c2=cython.double, c3=cython.double,
               c4=cython.double, floor=cython.double, f_b=cython.double, apart=cython.bint,
               a=cython.double, b=cython.double, k=Py_ssize_t, dc=Quartic, knots=list)
cpdef double first_return(Quartic c, double hi, double depth) except? -1.0
