# Python's `object`, as the kernel sees it: a kernel module's .pxd that says
# `cimport physics.cobject as object` makes its `object.__new__(cls)` and
# `object.__setattr__(o, name, value)` the C functions these call (object's tp_new and the C
# API's PyObject_GenericSetAttr), without the Python calls.
from cpython.object cimport PyObject, PyObject_GenericSetAttr, PyTypeObject


cdef extern from "Python.h":
    PyTypeObject PyBaseObject_Type


cdef inline __new__(cls):
    return PyBaseObject_Type.tp_new(<type>cls, <PyObject *>(), NULL)


cdef inline int __setattr__(o, name, value) except -1:
    return PyObject_GenericSetAttr(o, name, value)
