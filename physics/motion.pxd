# The C types of physics/motion.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.pymath as math

@cython.locals(u_sp=cython.double, g=cython.double, R=cython.double)
cpdef double spin_decel(object p) except? -1.0
cpdef tuple slip(tuple v, tuple w, double R)
@cython.locals(ux=cython.double, uy=cython.double, eps=cython.double, wz=cython.double)
cpdef str classify(tuple v, tuple w, object p)
cpdef tuple rolling_spin(tuple v, double wz, double R)
@cython.locals(wz_rate=cython.double, ux=cython.double, uy=cython.double, s=cython.double,
               f=cython.double, k=cython.double, ax=cython.double, ay=cython.double,
               wz=cython.double, eps=cython.double, R=cython.double, g=cython.double,
               u_s=cython.double, u_r=cython.double, vx=cython.double, vy=cython.double)
cpdef tuple accelerations(str state, tuple v, tuple w, object p)
@cython.locals(ux=cython.double, uy=cython.double, u_s=cython.double, u_r=cython.double,
               g=cython.double, wz=cython.double)
cpdef double transition_time(str state, tuple v, tuple w, object p) except? -1.0
@cython.locals(wz=cython.double, eps=cython.double)
cpdef double spin_stop_time(tuple w, object p) except? -1.0
