# Python's `object`, as the kernel sees it: a kernel module's .pxd that says
# `cimport physics.cobject as object` makes its `object.__setattr__(o, name, value)` the C API's
# PyObject_GenericSetAttr, which is what object.__setattr__ calls, without the Python call.
from cpython.object cimport PyObject_GenericSetAttr


cdef inline int __setattr__(o, name, value) except -1:
    return PyObject_GenericSetAttr(o, name, value)
