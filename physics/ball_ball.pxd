# The C types of physics/ball_ball.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.pymath as math

@cython.locals(nx=cython.double, ny=cython.double, vn=cython.double, dv=cython.double)
cpdef tuple frictionless(tuple va, tuple wa, tuple vb, tuple wb, tuple n, object p)
@cython.locals(nx=cython.double, ny=cython.double, vn=cython.double, R=cython.double,
               m=cython.double, rx=cython.double, ry=cython.double, rz=cython.double,
               rn=cython.double, tx=cython.double, ty=cython.double, tz=cython.double,
               slip=cython.double, jn=cython.double, mu=cython.double, jt=cython.double,
               jx=cython.double, jy=cython.double, jz=cython.double, ax=cython.double,
               ay=cython.double, k=cython.double)
cpdef tuple alciatore(tuple va, tuple wa, tuple vb, tuple wb, tuple n, object p)
