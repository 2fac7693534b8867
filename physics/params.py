"""Physical constants of one scene: balls, cloth, cushions.

A `Params` value is immutable and travels with the scene it belongs to; nothing in the engine
reads a module global, so two tables with different cloth can be simulated side by side.
The scene format's names are kept (`u_s`, `u_r`, ...); docs/physics.md says how each is used
and where it departs from the starting equations (its "Corrections").
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Params:
    """Ball and cloth constants (SI units).

    R, m: ball radius (m) and mass (kg).
    u_s: ball-cloth sliding friction; a sliding ball's slip point decelerates at 7/2 u_s g.
    u_r: rolling resistance as in Han 2005: a rolling ball decelerates at u_r g (docs/physics.md,
        correction 2).
    u_sp: spin (about the vertical) friction: dw_z/dt = -5/2 u_sp g / R in every state
        (correction 3).
    e_b: ball-ball coefficient of restitution.
    e_c: ball-cushion coefficient of restitution.
    f_c: ball-cushion sliding friction (mu_w of Mathavan 2010).
    g: gravity (m/s^2).
    throw_a, throw_b, throw_c: Alciatore's ball-ball friction fit mu(v) = a + b exp(-c v)
        where v is the contact-point slip speed (correction 4).
    m_cue: cue mass (kg) for the cue strike model.
    mathavan_steps: Runge-Kutta steps of the Mathavan cushion integration over the impulse a
        frictionless compression would take (shorter steps are taken where slips need them).
    """

    R: float = 0.028575
    m: float = 0.170097
    u_s: float = 0.2
    u_r: float = 0.01
    u_sp: float = 0.01
    e_b: float = 0.95
    e_c: float = 0.85
    f_c: float = 0.2
    g: float = 9.81
    throw_a: float = 9.951e-3
    throw_b: float = 0.108
    throw_c: float = 1.088
    m_cue: float = 0.567
    mathavan_steps: int = 4


#: Pool balls (2 1/4 in, 6 oz) on ordinary worsted cloth: the common values for pool.
POOL = Params()

#: Snooker balls (52.5 mm, about 141 g) on napped snooker cloth, which runs a little further.
SNOOKER = Params(R=0.02625, m=0.1406, u_r=0.008)

#: Carom balls (61.5 mm, 210 g) on heated three-cushion cloth, the fastest of the three. The
#: cloth, cushion and ball-ball constants (and the table's cushion height) are those fitted to
#: 91 shots recorded on a real table (`billiards fit --fit-constants`, docs/physics.md,
#: "Recorded shots"), to three figures.
CAROM = Params(
    R=0.03075, m=0.21, u_s=0.211, u_r=0.00547, u_sp=0.0112, e_b=0.953, e_c=0.9, f_c=0.212
)
