# The C types of physics/roots.py for the compiled kernel (setup.py); the .py is the source.
cimport cython
cimport physics.pymath as math
cimport physics.pymath as pymath

cdef int _NEWTON_ITERS

@cython.locals(acc=cython.double, coef=cython.double)
cpdef double _horner(tuple c, double t) except? -1.0
@cython.locals(k=Py_ssize_t)
cpdef tuple _derivative(tuple c)
@cython.locals(disc=cython.double, q=cython.double, r1=cython.double, r2=cython.double)
cpdef list _quadratic_roots(double c0, double c1, double c2)

@cython.locals(t=cython.double, f=cython.double, d=cython.double, step=cython.double,
               _=cython.int)
cpdef double _refine(tuple c, tuple dc, double lo, double hi) except? -1.0
@cython.locals(p=cython.double)
cpdef list critical_points(tuple dc, double hi)
@cython.locals(f_prev=cython.double, f_b=cython.double, a=cython.double, b=cython.double,
               k=Py_ssize_t)
cpdef list all_roots(tuple c, double hi)
@cython.locals(x=cython.double)
cpdef double _refine_neg(tuple c, tuple dc, double lo, double hi) except? -1.0

@cython.locals(cx=cython.double, cy=cython.double, chord2=cython.double, s=cython.double)
cpdef bint path_misses(double px, double py, double vx, double vy, double ax, double ay,
                       double h, double clearance) except -1
@cython.locals(r=cython.double)
cpdef object first_entry_quadratic(double c0, double c1, double c2, double hi, double skip=*)
@cython.locals(a=cython.double, b=cython.double, k=Py_ssize_t, p=cython.double)
cpdef object first_entry(tuple c, double hi, double skip=*)
@cython.locals(floor=cython.double, f_b=cython.double, apart=cython.bint, a=cython.double,
               b=cython.double, k=Py_ssize_t)
cpdef object first_return(tuple c, double hi, double depth)
