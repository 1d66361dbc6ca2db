"""The envelope: the ranges of values inside which the engine holds to its contract.

Inside these ranges every step is to give finite numbers, no dynamic body's centre is to
end behind a plane, a scene with restitution <= 1 and no forces is to gain no kinetic
energy (beyond 1 % of solver error), free scenes are to keep their linear and angular
momentum, a world in a batch steps bitwise as it does alone, and a restored snapshot
replays bitwise. The property tests (``tests/test_random_scenes.py``) and the long fuzz
run (``bench/fuzz_scenes.py``, 10,000 scenes: no failure) draw their scenes from the
whole envelope.

Values outside it are refused where they are given, with the range in the message (a
radius of 1e-160 m would make the moment of inertia underflow to 0, a speed of 1e160 m/s
overflows its square), so a scene never turns to NaN later. The limits are wide enough
for anything from a marble to a building, and far inside what float64 can carry:

==============  ===================================  ======================================
quantity        range (constant)                     applies to
==============  ===================================  ======================================
size            1 mm to 10 km (``SIZE``)             radius, width, height (bodies, sensors)
coordinate      within 1e6 m on each axis            positions, plane points, the points
                (``COORDINATE``)                     forces and impulses act at, anchors
mass            1 mg to 1000 t (``MASS``)            dynamic bodies: mass ratios up to 1e12
speed           up to 10 km/s (``SPEED``)            velocities (kinematic too), the speed
                                                     an impulse leaves, ``contact_push_speed``
angular speed   up to 1e4 rad/s (``ANGULAR_SPEED``)  angular velocities, likewise
acceleration    up to 1e6 m/s^2 (``ACCELERATION``)   gravity; force / mass of a body's forces
time step       1 us to 1 s (``DT``)                 ``World.step``, ``run_until_rest``
==============  ===================================  ======================================

Rates (drags, contact stiffness, damping ratios) are bounded by ``RATE`` (1e6 per s, or
dimensionless): an exponential decay faster than that is already complete within the
shortest step. Restitution is at most ``RESTITUTION`` (2: above 1 adds energy, on purpose)
and friction at most ``FRICTION`` (100).

Bodies can still drive themselves out of it: restitution above 1 pumps energy into
every bounce, a kinematic body can squeeze a light one into a wedge of planes, a body can
fall for a day. Every step ends by checking the moving bodies of each world (their
position, speed and angular speed, ``refusal.leaves_envelope``); a world that left
refuses the step with ``EnvelopeError``, naming the world, the body and the quantity, and
the call changes nothing (every world of the batch is as it was before it). A scene
therefore never turns to NaN: it stops, with a reason, at the edge.
"""

from __future__ import annotations

SIZE = (1e-3, 1e4)  # m
COORDINATE = 1e6  # m, on each axis
MASS = (1e-6, 1e6)  # kg
SPEED = 1e4  # m/s
ANGULAR_SPEED = 1e4  # rad/s
ACCELERATION = 1e6  # m/s^2
DT = (1e-6, 1.0)  # s
RATE = 1e6  # 1/s (drags), Hz (contact stiffness), or dimensionless (damping ratio)
RESTITUTION = 2.0
FRICTION = 100.0


class EnvelopeError(ValueError):
    """A world left the envelope during a step; the step was refused and the call changed
    nothing. ``world`` and ``body`` are the world's index and the body's slot,
    ``quantity`` is ``"speed"``, ``"angular speed"``, ``"position"`` or ``"not finite"``."""

    def __init__(self, message: str, *, world: int, body: int, quantity: str) -> None:
        super().__init__(message)
        self.world, self.body, self.quantity = world, body, quantity
