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

Bodies can still leave the envelope by themselves (a body falling for a day, a spring
set spinning): the guarantee is about scenes whose values stay inside it, and such a run
still gives finite numbers for far longer than any episode.
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
