# The C types of physics/ball_ball.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.pymath as math
cimport physics.motion as motion  # motion.V2, motion.V3: vectors as C structs of doubles

@cython.locals(nx=cython.double, ny=cython.double, vn=cython.double, dv=cython.double)
cpdef tuple frictionless(motion.V2 va, motion.V3 wa, motion.V2 vb, motion.V3 wb, motion.V2 n,
                         object p)
@cython.locals(nx=cython.double, ny=cython.double, vn=cython.double, R=cython.double,
               m=cython.double, rx=cython.double, ry=cython.double, rz=cython.double,
               rn=cython.double, tx=cython.double, ty=cython.double, tz=cython.double,
               slip=cython.double, jn=cython.double, mu=cython.double, jt=cython.double,
               jx=cython.double, jy=cython.double, jz=cython.double, ax=cython.double,
               ay=cython.double, k=cython.double, ca=motion.V3, cb=motion.V3,
               dw=motion.V3)
cpdef tuple alciatore(motion.V2 va, motion.V3 wa, motion.V2 vb, motion.V3 wb, motion.V2 n,
                      object p)
