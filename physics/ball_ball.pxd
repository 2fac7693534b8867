# The C types of physics/ball_ball.py for the compiled kernel (setup.py); the .py is the source.
cimport physics.pymath as math
