# The C types of physics/engine.py for the compiled kernel (setup.py); the .py is the source.
cimport cython

cimport physics.motion as motion
cimport physics.pymath as math
cimport physics.records as records
cimport physics.roots as roots


cdef dict _TABLES, _MODELS_USED
cdef double FAR_MARGIN
cdef Py_ssize_t _TABLES_KEPT

cdef tuple _unpacked(object g, double R)
cdef object _models_used(str ball_ball, str cushion, bint spin, double cushion_height)
cdef double _first_contact(roots.Quartic c, double gap, double contact,
                          double horizon) except? -1.0
cdef object _approach(list v, tuple contact)
cdef object _coupling(tuple c, tuple e, list inv)
cdef object _solve(list A, list u, list push)


cdef class _Rail:
    cdef readonly object segment
    cdef readonly double px, py, nx, ny, tx, ty


cdef class _Circle:
    cdef readonly str kind
    cdef readonly object piece
    cdef readonly double cx, cy, radius


cdef class _Ball:
    cdef public str name, state
    cdef public object pocket
    cdef public double t0, x, y, vx, vy, ax, ay, t_own
    cdef public tuple w, dw
    cdef public Py_ssize_t version
    cdef public list segments

    @cython.locals(dt=cython.double)
    cpdef (double, double, double, double) at(self, double t)
    @cython.locals(dt=cython.double, w=motion.V3, dw=motion.V3)
    cpdef advance(self, double t)


cdef class Simulation:
    cdef public object scene, p, models, ball_ball, cushion, geometry
    cdef public motion.Constants consts
    cdef public bint spin
    cdef public double sin_theta, now, diameter
    cdef public list balls, heap, events, cushion_steps, rails, circles
    cdef public dict index
    cdef public Py_ssize_t seq, contacts_checked, quartics_solved

    cpdef Py_ssize_t work(self)
    cpdef tuple run_records(self)
    cdef _start(self)
    @cython.locals(b=_Ball, end=cython.double)
    cdef tuple _records(self)
    @cython.locals(state=str, consts=motion.Constants, dwx=cython.double, dwy=cython.double,
                   dwz=cython.double)
    cdef _set_motion(self, _Ball b, tuple v, tuple w)
    cdef _record(self, _Ball b)
    cdef _emit(self, str kind, tuple balls, object cushion=*, object pocket=*)
    @cython.locals(bi=_Ball, bj=_Ball, vj=Py_ssize_t)
    cdef _push(self, double t, str kind, Py_ssize_t i, Py_ssize_t j=*, object data=*)
    @cython.locals(k=Py_ssize_t, i=Py_ssize_t, j=Py_ssize_t, bi=_Ball, other=_Ball,
                   earlier=tuple)
    cdef _predict(self, tuple changed)
    @cython.locals(b=_Ball, now=cython.double, t=cython.double, t_spin=cython.double,
                   state=str, kind=str, contact=tuple, consts=motion.Constants)
    cdef _predict_own(self, Py_ssize_t i)
    @cython.locals(R=cython.double, now=cython.double, x=cython.double, y=cython.double,
                   vx=cython.double, vy=cython.double, ax=cython.double, ay=cython.double,
                   speed=cython.double, accel=cython.double, nx=cython.double,
                   ny=cython.double, g0=cython.double, g1=cython.double, c2=cython.double,
                   tx=cython.double, ty=cython.double, cx=cython.double, cy=cython.double,
                   px=cython.double, py=cython.double,
                   s=cython.double, t=cython.double, approaching=cython.bint,
                   rail=_Rail, circle=_Circle, reach=cython.double, dx=cython.double,
                   dy=cython.double, far=cython.double)
    cdef tuple _table_contact(self, _Ball b, double horizon)
    @cython.locals(now=cython.double, xj=cython.double, yj=cython.double, vxj=cython.double,
                   vyj=cython.double, t=cython.double, dx=cython.double, dy=cython.double,
                   dvx=cython.double, dvy=cython.double, dax=cython.double, day=cython.double,
                   horizon=cython.double, reach=cython.double, far=cython.double)
    cdef _predict_pair(self, Py_ssize_t i, Py_ssize_t j, _Ball bi, _Ball bj)
    @cython.locals(c=roots.Quartic)
    cdef double _contact_time(self, double dx, double dy, double vx, double vy, double ax,
                              double ay, double contact, double horizon) except? -1.0
    @cython.locals(bi=_Ball, bj=_Ball, dx=cython.double, dy=cython.double, d=cython.double,
                   nx=cython.double, ny=cython.double, vn=cython.double)
    cpdef _collide_balls(self, Py_ssize_t i, Py_ssize_t j)
    @cython.locals(b=_Ball, nx=cython.double, ny=cython.double, vx=cython.double,
                   vy=cython.double, vn_in=cython.double, vn=cython.double, k=cython.double,
                   vn_out=cython.double, ax=cython.double, ay=cython.double)
    cpdef _collide_cushion(self, Py_ssize_t i, tuple normal, str kind, object cushion,
                           object pocket)
    cdef object _settle(self, tuple seeds, tuple first)
    cdef tuple _cluster(self, tuple seeds, tuple first)
    cdef _take(self, Py_ssize_t i, list pos, list v, list w)
    @cython.locals(rail=_Rail, circle=_Circle, R=cython.double, x=cython.double,
                   y=cython.double, vx=cython.double, vy=cython.double, px=cython.double,
                   py=cython.double, nx=cython.double, ny=cython.double, tx=cython.double,
                   ty=cython.double, gap=cython.double, s=cython.double, cx=cython.double,
                   cy=cython.double, d=cython.double)
    cdef _touching(self, Py_ssize_t k, list members, list pos, list v, list w, list contacts)
    cdef _add_fixed(self, Py_ssize_t k, nx, ny, vx, vy, list fixed, list contacts)
    cdef tuple _project(self, list v, list w, list contacts)
    cdef list _pressed_slides(self, list v, list w, list contacts)
    cdef _spare(self, list v, list w, list contacts)
    @cython.locals(b=_Ball, before=str, v=tuple)
    cpdef _transition(self, Py_ssize_t i)
    @cython.locals(b=_Ball)
    cdef _spin_stop(self, Py_ssize_t i)
    @cython.locals(b=_Ball)
    cdef _pocket(self, Py_ssize_t i, object name)
    @cython.locals(t=cython.double, kind=str, i=Py_ssize_t, j=Py_ssize_t, vi=Py_ssize_t,
                   vj=Py_ssize_t, count=Py_ssize_t, b=_Ball, dx=cython.double,
                   dy=cython.double, d=cython.double, heap=list, balls=list)
    cdef _loop(self)
