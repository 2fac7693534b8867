# The C types of physics/engine.py for the compiled kernel (setup.py); the .py is the source.
cimport physics.pymath as math
