# The C types of physics/motion.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.pymath as math


cdef class Constants:
    cdef readonly double R, g, spin_decel, u_r, u_s


# A velocity and a spin, which these functions only read, as C structs of doubles.
ctypedef (double, double) V2
ctypedef (double, double, double) V3


cpdef (double, double) slip(V2 v, V3 w, double R)
@cython.locals(ux=cython.double, uy=cython.double, eps=cython.double, wz=cython.double)
cpdef str classify(V2 v, V3 w, Constants consts)
cpdef tuple rolling_spin(V2 v, double wz, double R)
@cython.locals(wz_rate=cython.double, ux=cython.double, uy=cython.double, s=cython.double,
               f=cython.double, kw=cython.double, ax=cython.double, ay=cython.double,
               wz=cython.double, eps=cython.double, R=cython.double, g=cython.double,
               vx=cython.double, vy=cython.double)
cpdef (double, double, double, double, double) accelerations(str state, V2 v, V3 w,
                                                              Constants consts)
@cython.locals(ux=cython.double, uy=cython.double, wz=cython.double)
cpdef double transition_time(str state, V2 v, V3 w, Constants consts) except? -1.0
@cython.locals(wz=cython.double, eps=cython.double)
cpdef double spin_stop_time(V3 w, Constants consts) except? -1.0
