"""A small scene with every shape pair (the polygon ones too), a spring, a sensor and
breakable bodies, stepped (and once more with its manifolds coloured) and its final
state written to the file
named on the command line (``test_compiled.py`` runs it compiled and with
``NUMBA_DISABLE_JIT=1`` and compares the two; ``test_gpu.py``
runs it with ``--device cuda`` in numba's CUDA simulator against the CPU)."""

import sys

import numpy as np

import impulse2d as p2
from impulse2d.core import colouring


def build(device: str = "cpu") -> p2.World:
    world = p2.World(substeps=4, damage_speed=0.5, device=device)
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), friction=0.7))
    world.add(p2.Plane(normal=(1.0, 0.0), point=(-3.0, 0.0)))
    for i in range(3):
        world.add(p2.Box(position=(0.3 * i, 0.25 + 0.5 * i), width=0.9, height=0.5, angle=0.05 * i))
    ball = world.add(
        p2.Circle(position=(-1.5, 2.0), radius=0.3, velocity=(3.0, 0.0), restitution=0.6)
    )
    pig = world.add(p2.Circle(position=(1.5, 0.4), radius=0.25, health=2.0))
    world.add(p2.Box(position=(2.5, 0.2), width=0.3, height=0.3, fixed=True))
    kick = world.add(
        p2.Box(position=(-2.0, 0.2), width=0.3, height=0.3, kinematic=True, velocity=(0.5, 0.0))
    )
    world.add(p2.Spring(ball, pig, stiffness=20.0, damping=0.5, anchor1=(0.1, 0.0)))
    world.add(p2.Sensor(position=(2.0, 3.0), radius=0.5, disables=True))
    world.add(p2.Sensor(position=(0.0, 2.0), width=12.0, height=8.0, outside=True))
    # The outlines: a triangle dropped on the stack, a rounded hexagon on a fixed shelf
    # (a segment), a capsule rolled at the pig, a rod (a thin box-like polygon) on the
    # ground: every polygon pair (circle, box, polygon, plane) meets.
    world.add(p2.Polygon(vertices=[(0, 0), (0.6, 0), (0.2, 0.5)], position=(0.5, 2.2), angle=0.3))
    shelf = world.add(p2.Segment(start=(-2.9, 1.2), end=(-1.9, 1.0), radius=0.02))
    hexagon = [(0.25 * np.cos(t), 0.25 * np.sin(t)) for t in np.arange(6) * np.pi / 3]
    world.add(p2.Polygon(vertices=hexagon, radius=0.03, position=(-2.4, 1.6), angular_velocity=2.0))
    world.add(p2.Capsule(length=0.4, radius=0.12, position=(0.9, 0.4), velocity=(1.0, 0.0)))
    world.add(p2.Polygon(vertices=[(0, 0), (1.2, 0), (1.2, 0.1), (0, 0.1)], position=(-0.5, 1.8)))
    # Joints: a chain of capsules from a fixed hook, a breakable weld, a motor-driven
    # slider with limits, a rope and a mouse joint's drag.
    hook = world.add(p2.Circle(position=(4.0, 3.0), radius=0.05, fixed=True))
    links, previous = [], hook
    for k in range(3):
        link = world.add(p2.Capsule(length=0.4, radius=0.06, position=(4.25 + 0.5 * k, 3.0)))
        world.add(p2.RevoluteJoint(previous, link, anchor=(4.0 + 0.5 * k, 3.0)))
        links.append(link)
        previous = link
    world.add(p2.WeldJoint(world.bodies[3], world.bodies[4], anchor=(0.15, 0.5), break_force=30.0))
    rail = world.add(p2.Box(position=(6.0, 0.5), width=0.2, height=0.2, fixed=True))
    cart = world.add(p2.Box(position=(6.0, 1.0), width=0.4, height=0.2))
    world.add(
        p2.PrismaticJoint(
            rail,
            cart,
            axis=(1.0, 0.2),
            lower_translation=-0.5,
            upper_translation=0.5,
            motor_speed=1.0,
            max_motor_force=20.0,
        )
    )
    world.add(p2.DistanceJoint(hook, links[-1], min_length=0.0))
    world.add(p2.MouseJoint(cart, target=(6.0, 1.0)))
    del kick, shelf
    return world


def main(path: str, device: str = "cpu") -> None:
    world = build(device).replicate(3)
    world.bodies[5].velocity = np.array([[3.0, 0.0], [1.0, 4.0], [-2.0, 1.0]])
    for _ in range(40):
        world.step(1 / 60)
    steps = world.run_until_rest(1 / 60, 30, worlds=[0, 2])
    s = world.state
    print(world.device, s.contact_capacity, world._runner.pair_capacity)  # where it ran, room made
    # The same scene with its box-on-box manifolds solved in colour (a world is coloured
    # only from 128 points a step: this one has fewer), the boxes knocked about.
    colouring.COLOUR_FROM_POINTS = 0.0
    coloured = build(device).replicate(2)
    coloured.bodies[3].velocity = np.array([[0.0, -2.0], [1.5, 0.0]])
    for _ in range(40):
        coloured.step(1 / 60)
    np.savez(
        path,
        coloured_body=coloured.state.body,
        coloured_contact=coloured.state.contact,
        body=s.body,
        body_i=s.body_i,
        contact=s.contact,
        contact_i=s.contact_i,
        world_i=s.world_i,
        time=s.time,
        hull=s.hull,
        spring=s.spring,
        steps=steps,
    )


if __name__ == "__main__":
    main(sys.argv[1], *sys.argv[3:4] if sys.argv[2:3] == ["--device"] else ())
