# The C types of physics/motion.py for the compiled kernel (setup.py); the .py is the source.
cimport physics.pymath as math
