"""Demo scenes beyond the tutorial's shapes: a pile of polygons, a pendulum chain, ragdolls
on stairs and a car climbing a hill. Deterministic, as every demo builder (a seeded
generator where there is randomness); metres, kilograms, seconds."""

from __future__ import annotations

import itertools
import math

import numpy as np

import impulse2d as p2


def polygon_pile() -> p2.World:
    """Forty convex polygons (triangles to octagons, some rounded) and capsules poured into
    a V of two segments above the ground: they tumble, slide and come to rest."""
    world = p2.World()
    world.add(p2.Plane())
    world.add(p2.Segment(start=(-6.0, 5.0), end=(-0.8, 1.0), friction=0.5))
    world.add(p2.Segment(start=(6.0, 5.0), end=(0.8, 1.0), friction=0.5))
    rng = np.random.default_rng(7)
    for k in range(40):
        x, y = rng.uniform(-4.0, 4.0), 6.0 + 0.8 * k
        if k % 5 == 4:
            world.add(p2.Capsule(length=rng.uniform(0.3, 0.8), radius=0.15, position=(x, y),
                                 angle=rng.uniform(0, math.pi)))  # fmt: skip
            continue
        sides = int(rng.integers(3, 9))
        turns = np.sort(rng.uniform(0.0, 2 * math.pi, sides)) if sides > 4 else None
        angles = turns if turns is not None else np.arange(sides) * 2 * math.pi / sides
        size = rng.uniform(0.25, 0.5)
        vertices = [(size * math.cos(t), size * math.sin(t)) for t in angles]
        try:
            shape = p2.Polygon(vertices=vertices, radius=0.04 * (k % 2), position=(x, y),
                               angle=rng.uniform(0, math.pi), friction=0.6)  # fmt: skip
        except ValueError:  # a random draw with two vertices too close: a regular one
            regular = [(size * math.cos(t), size * math.sin(t)) for t in np.arange(5) * 1.2566]
            shape = p2.Polygon(vertices=regular, position=(x, y))
        world.add(shape)
    return world


def pendulum_chain() -> p2.World:
    """A chain of twelve capsules pinned end to end, hanging from a hook, let go level: it
    falls, whips and swings (revolute joints; the links do not collide with their
    neighbours)."""
    world = p2.World(substeps=8)
    hook = world.add(p2.Circle(radius=0.08, position=(0.0, 6.0), fixed=True))
    previous, length = hook, 0.5
    for k in range(12):
        link = world.add(p2.Capsule(length=length, radius=0.06, position=(length * (k + 0.5), 6.0),
                                    mass=0.3))  # fmt: skip
        world.add(p2.RevoluteJoint(previous, link, anchor=(length * k, 6.0)))
        previous = link
    return world


def _limb(world: p2.World, start, end, radius: float, mass: float) -> p2.Capsule:
    """A capsule from ``start`` to ``end`` (its core), as a ragdoll's limb."""
    (x0, y0), (x1, y1) = start, end
    return world.add(p2.Capsule(length=math.hypot(x1 - x0, y1 - y0), radius=radius,
                                position=((x0 + x1) / 2, (y0 + y1) / 2),
                                angle=math.atan2(y1 - y0, x1 - x0), mass=mass))  # fmt: skip


def _ragdoll(world: p2.World, x: float, y: float) -> None:
    """A ragdoll standing at ``x`` with its feet at ``y``: head, torso, upper and lower
    arms and legs, pinned at the neck, shoulders, elbows, hips and knees within limits."""
    torso = _limb(world, (x, y + 1.0), (x, y + 1.5), 0.14, 8.0)
    head = world.add(p2.Circle(radius=0.13, position=(x, y + 1.8), mass=2.0))
    pin = p2.RevoluteJoint
    world.add(pin(torso, head, anchor=(x, y + 1.66), lower_angle=-0.4, upper_angle=0.4))
    for side in (-1.0, 1.0):
        upper_arm = _limb(
            world, (x + 0.05 * side, y + 1.55), (x + 0.05 * side, y + 1.25), 0.06, 1.5
        )
        lower_arm = _limb(world, (x + 0.05 * side, y + 1.2), (x + 0.05 * side, y + 0.95), 0.05, 1.0)
        thigh = _limb(world, (x + 0.08 * side, y + 0.85), (x + 0.08 * side, y + 0.5), 0.08, 4.0)
        shin = _limb(world, (x + 0.08 * side, y + 0.42), (x + 0.08 * side, y + 0.08), 0.07, 3.0)
        world.add(pin(torso, upper_arm, anchor=(x + 0.05 * side, y + 1.55), lower_angle=-2.5,
                      upper_angle=2.5))  # fmt: skip
        world.add(pin(upper_arm, lower_arm, anchor=(x + 0.05 * side, y + 1.22), lower_angle=-2.0,
                      upper_angle=0.0))  # fmt: skip
        world.add(pin(torso, thigh, anchor=(x + 0.08 * side, y + 0.92), lower_angle=-1.5,
                      upper_angle=0.8))  # fmt: skip
        world.add(pin(thigh, shin, anchor=(x + 0.08 * side, y + 0.46), lower_angle=0.0,
                      upper_angle=2.0))  # fmt: skip


def ragdolls() -> p2.World:
    """Three ragdolls tipped off the top of a flight of stairs: they tumble down limb over
    limb, their joints bending within their limits."""
    world = p2.World(substeps=8)
    world.add(p2.Plane())
    for k in range(8):
        world.add(
            p2.Box(width=1.0, height=0.4 * (8 - k), position=(0.5 + k, 0.2 * (8 - k)), fixed=True)
        )
    for k, x in enumerate((0.3, 0.6, 0.9)):
        _ragdoll(world, x, 3.2 + 2.2 * k)
    for body in world.bodies:
        if not getattr(body, "fixed", True):
            body.velocity = (1.5, 0.0)
    return world


def car_on_a_hill() -> p2.World:
    """A car (a polygon body on two wheels, each on a revolute motor) drives from the flat
    up a hill of segments, over its top and down the other side."""
    world = p2.World(substeps=8)
    hill = [(-10.0, 0.0), (2.0, 0.0), (6.0, 1.0), (9.0, 2.2), (11.0, 2.6), (13.0, 2.2),
            (16.0, 1.0), (20.0, 0.0), (40.0, 0.0)]  # fmt: skip
    for a, b in itertools.pairwise(hill):
        world.add(p2.Segment(start=a, end=b, friction=0.9))
    body = world.add(p2.Polygon(vertices=[(-1.2, -0.25), (1.2, -0.25), (1.0, 0.15), (0.2, 0.45),
                                          (-0.9, 0.45), (-1.2, 0.1)], position=(-6.0, 0.9),
                                mass=40.0))  # fmt: skip
    for x in (-0.8, 0.8):
        at = (float(body.position[0]) + x, 0.4)
        wheel = world.add(p2.Circle(radius=0.4, position=at, mass=4.0, friction=0.9))
        world.add(
            p2.RevoluteJoint(body, wheel, anchor=at, motor_speed=-8.0, max_motor_torque=200.0)
        )
    return world
