# The C types of physics/cushion.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.pymath as math
cimport physics.motion as motion  # motion.V2, motion.V3: vectors as C structs of doubles

cdef double _ZERO_SLIP, _SNAP_SLIP, _LAND, _STIFF, _TURN
cdef int _MAX_STEPS

ctypedef (double, double, double, double, double, double) State


cdef class _Impact:
    cdef public double s, c, eps, eps2, snap2, grip_i, grip_c, mu_w, mu_s, det_both

    @cython.locals(s=cython.double, c=cython.double, eps=cython.double, mu_w=cython.double,
                   mu_s=cython.double, slip_i=cython.double, slip_c=cython.double,
                   fix=cython.double, fiy=cython.double, fcx=cython.double, fcy=cython.double,
                   ux=cython.double, uy=cython.double, k=cython.double, n_c=cython.double,
                   ax=cython.double, ay=cython.double, drive=cython.double)
    cdef (double, double, double, double) forces(self, double x_i, double y_i, double x_c,
                                                 double y_c)
    @cython.locals(s=cython.double, c=cython.double, mu_s=cython.double, n_c=cython.double,
                   ax=cython.double, ay=cython.double, drive=cython.double)
    cdef (double, double) _cloth(self, double fix, double fiy, double x_c, double y_c,
                                 double slip_c)

    @cython.locals(s=cython.double, c=cython.double, eps=cython.double, mu_w=cython.double,
                   mu_s=cython.double, x_i=cython.double, y_i=cython.double,
                   x_c=cython.double, y_c=cython.double, slip_i=cython.double,
                   slip_c=cython.double, k=cython.double, fix=cython.double, fiy=cython.double,
                   fcx=cython.double, fcy=cython.double)
    cdef State rate(self, double vx, double vy, double Wx, double Wy, double Wz)
    @cython.locals(y0=cython.double, y1=cython.double, y2=cython.double, y3=cython.double,
                   y4=cython.double, y5=cython.double, a0=cython.double, a1=cython.double,
                   a2=cython.double, a3=cython.double, a4=cython.double, a5=cython.double,
                   b0=cython.double, b1=cython.double, b2=cython.double, b3=cython.double,
                   b4=cython.double, b5=cython.double, c0=cython.double, c1=cython.double,
                   c2=cython.double, c3=cython.double, c4=cython.double, c5=cython.double,
                   d0=cython.double, d1=cython.double, d2=cython.double, d3=cython.double,
                   d4=cython.double, d5=cython.double, h2=cython.double, h6=cython.double)
    cdef State rk4(self, State y, State k1, double h)
    @cython.locals(s=cython.double, c=cython.double)
    cdef (double, double, double, double) slips(self, State y)
    @cython.locals(s=cython.double, c=cython.double, best=cython.double, y0=cython.double,
                   y1=cython.double, y2=cython.double, y3=cython.double, y4=cython.double,
                   d0=cython.double, d1=cython.double, d2=cython.double, d3=cython.double,
                   d4=cython.double)
    cdef (double, int) step_limit(self, State y, State d)
    @cython.locals(size=cython.double, closing=cython.double, turning=cython.double)
    cdef double _limit(self, double best, double sx, double sy, double dx, double dy,
                       double grip) except? -1.0
    @cython.locals(s=cython.double, c=cython.double, x_i=cython.double, y_i=cython.double,
                   x_c=cython.double, y_c=cython.double, fix=cython.double, fiy=cython.double,
                   fcx=cython.double, fcy=cython.double)
    cdef State zero_slip(self, State y, int contact)


@cython.locals(impact=_Impact, R=cython.double, s=cython.double, c=cython.double,
               vx=cython.double, vy=cython.double, Wx=cython.double, Wy=cython.double,
               Wz=cython.double, h=cython.double, target=cython.double, step=cython.double,
               lo=cython.double, m0=cython.double, m1=cython.double, u=cython.double,
               y=State, d=State, y1=State, d1=State, end=State, contact=cython.int,
               taken=cython.int)
cpdef tuple mathavan(object v, object w, object normal, object p, double sin_theta,
                     object work=*)
@cython.locals(u2=cython.double, u3=cython.double)
cpdef double _hermite(double f0, double f1, double m0, double m1, double u) except? -1.0
@cython.locals(a=cython.double, b=cython.double, disc=cython.double, q=cython.double,
               best=cython.double, peak=cython.double, u=cython.double, value=cython.double,
               r1=cython.double, r2=cython.double)
cpdef double _hermite_peak(double f0, double f1, double m0, double m1) except? -1.0
@cython.locals(nx=cython.double, ny=cython.double)
cdef (double, double, double, double, double) _to_cushion(motion.V2 v, motion.V3 w,
                                                          motion.V2 normal, double R)
@cython.locals(nx=cython.double, ny=cython.double)
cdef tuple _to_table(double vx, double vy, double Wx, double Wy, double Wz, motion.V2 normal,
                     double R)
cdef bint _leaving(motion.V2 v, motion.V2 normal) except -1
@cython.locals(tol=cython.double, g=cython.double, slope=cython.double, newton=cython.double,
               u2=cython.double)
cpdef double _hermite_root(double f0, double f1, double m0, double m1, double lo) except? -1.0
