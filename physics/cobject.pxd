# Python's `object`, as the kernel sees it: a kernel module's .pxd that says
# `cimport physics.cobject as object` makes its `object.__new__(cls)` and
# `object.__setattr__(o, name, value)` C calls, without the Python calls.
#
# __new__ is the class's own allocation (tp_alloc, what object's tp_new calls first). object's
# tp_new then also gives each new object of a class with an instance dict an empty dict of its
# own (Python 3.11's _PyObject_InitializeDict); the kernel's one caller, records.trusted, sets
# the object's __dict__ at once, so that dict would only be made to be freed again (a third of
# the cost of a Shot's models). Nothing else differs for a class that is no ABC.
#
# __setattr__ is what the C API's PyObject_GenericSetAttr does for a name the class defines
# with a setter (__dict__ and the other slots records.trusted sets): the setter of the
# descriptor the type's lookup finds, called directly, and PyObject_GenericSetAttr itself for
# any other name.
from cpython.object cimport PyTypeObject


cdef extern from *:
    """
    static PyObject *billiards_new(PyTypeObject *cls) { return cls->tp_alloc(cls, 0); }

    static int billiards_setattr(PyObject *o, PyObject *name, PyObject *value) {
        PyObject *descr = _PyType_Lookup(Py_TYPE(o), name);
        descrsetfunc set = descr == NULL ? NULL : Py_TYPE(descr)->tp_descr_set;
        return set == NULL ? PyObject_GenericSetAttr(o, name, value) : set(descr, o, value);
    }
    """
    object billiards_new(PyTypeObject *cls)
    int billiards_setattr(object o, object name, object value) except -1


cdef inline __new__(cls):
    return billiards_new(<PyTypeObject *>cls)


cdef inline int __setattr__(o, name, value) except -1:
    return billiards_setattr(o, name, value)
