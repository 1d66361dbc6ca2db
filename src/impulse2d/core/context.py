"""The step context: one float64 row (``CONTEXT_SIZE``) that carries ``dt`` and what
follows from it into every kernel (Box2D v3's ``b2StepContext``): its column indices,
and the soft-constraint coefficients it holds. ``Settings.step_context`` fills it."""

from __future__ import annotations

import math

MIXING_RULES = ("max", "min", "mean", "product", "sqrt")

# Indices into the step context.
DT, H, INV_H, SUBSTEPS = 0, 1, 2, 3
GRAVITY_X, GRAVITY_Y = 4, 5
SOFT_RATE, SOFT_MASS, SOFT_IMPULSE = 6, 7, 8  # between two dynamic bodies
HARD_RATE, HARD_MASS, HARD_IMPULSE = 9, 10, 11  # against an immovable body: twice as stiff
PUSH_SPEED = 12
RESTITUTION_THRESHOLD = 13
SPECULATIVE = 14
SLEEPING, TIME_TO_SLEEP, SLEEP_SPEED = 15, 16, 17
DAMAGE_SPEED = 18
RESTITUTION_RULE, FRICTION_RULE = 19, 20
COLOUR_FROM = 21  # a world of this many points a step or more is coloured (colouring.py)
JOINT_RATE, JOINT_MASS, JOINT_IMPULSE = 22, 23, 24  # a rigid joint's softness (joints.py)
CONTEXT_SIZE = 25
# A rigid joint is as soft as a spring of twice the contact frequency with this damping
# ratio (Box2D v3's joint softness): stiff enough to hold, soft enough not to ring.
JOINT_DAMPING_RATIO = 2.0


def soft_constraint(hertz: float, damping_ratio: float, h: float) -> tuple[float, float, float]:
    """Bias rate, mass scale and impulse scale of a soft contact (Box2D v3's soft step).

    A penetration ``C < 0`` is treated as a spring-damper of natural frequency
    ``omega = 2 pi hertz`` and damping ratio ``zeta`` integrated implicitly over the
    substep ``h``. Solving ``J v + (beta / h) C + gamma lambda = 0`` for the impulse gives
    ``lambda = -m massScale (J v + biasRate C) - impulseScale lambda_acc`` with::

        a1 = 2 zeta + h omega,  a2 = h omega a1,  a3 = 1 / (1 + a2)
        biasRate = omega / a1,  massScale = a2 a3,  impulseScale = a3
    """
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * damping_ratio + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3
