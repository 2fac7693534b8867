# The C types of physics/records.py for the compiled kernel (setup.py); the .py is the source.
cimport cython
cimport physics.cobject as object

cdef frozenset _EVENT_FIELDS, _SEGMENT_FIELDS
cdef dict _SEGMENT_DICT

cpdef trusted(cls, dict values, set given)
cpdef event(t, str kind, tuple balls, cushion, pocket)
@cython.locals(values=dict)
cpdef segment(tuple s)
@cython.locals(segs=list, s=tuple, f=tuple, e=tuple)
cpdef shot(list events, dict trajectories, dict final, duration, models)
