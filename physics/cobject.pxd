# Python's `object`, as the kernel sees it: a kernel module's .pxd that says
# `cimport physics.cobject as object` makes its `object.__new__(cls)` and
# `object.__setattr__(o, name, value)` C calls, without the Python calls: the class's own
# allocation (tp_alloc, what object's tp_new calls) and the C API's PyObject_GenericSetAttr.
#
# object's tp_new also gives each new object of a class with an instance dict an empty dict of
# its own (Python 3.11's _PyObject_InitializeDict); the kernel's one caller, records.trusted,
# sets the object's __dict__ at once, so that dict would only be made to be freed again (a
# third of the cost of a Shot's models). Nothing else differs: a class that is no ABC, no
# arguments to check.
from cpython.object cimport PyObject_GenericSetAttr, PyTypeObject


cdef extern from *:
    """
    static PyObject *billiards_alloc(PyTypeObject *cls) { return cls->tp_alloc(cls, 0); }
    """
    object billiards_alloc(PyTypeObject *cls)


cdef inline __new__(cls):
    return billiards_alloc(<PyTypeObject *>cls)


cdef inline int __setattr__(o, name, value) except -1:
    return PyObject_GenericSetAttr(o, name, value)
