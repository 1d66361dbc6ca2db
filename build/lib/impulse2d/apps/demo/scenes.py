"""One builder per demo scene: each returns a fresh ``World`` set up and ready to step.

The scenes follow the tutorial "Making a 2D Physics Engine" milestone by milestone (``m01``
to ``m12``), then its extras and games. Every builder is deterministic: scenes with
randomness draw from a seeded ``numpy`` generator, so a scene built twice steps bitwise
the same. Sizes are in metres, masses in kilograms, times in seconds.

The registry with names, descriptions, time steps and camera views is in
``impulse2d.apps.demo`` (``__init__.py``); ``python -m impulse2d.apps.demo --list`` prints it.
"""

from __future__ import annotations

import math

import numpy as np

import impulse2d as p2

# -- helpers ---------------------------------------------------------------------------------


def _ground(world: p2.World, y: float = 0.0, **material: float) -> p2.Plane:
    """Add a horizontal ground plane (solid below ``y``)."""
    return world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, y), **material))


def _slope_point(
    origin: tuple[float, float], direction: tuple[float, float], s: float
) -> tuple[float, float]:
    """The point ``s`` metres from ``origin`` along the unit vector ``direction``."""
    return (origin[0] + s * direction[0], origin[1] + s * direction[1])


# -- milestones 1-2: motion ------------------------------------------------------------------


def constant_velocity() -> p2.World:
    """Milestone 1: three circles in zero gravity, each at its own constant velocity.

    Nothing acts on them, so ``x = x0 + v t`` exactly: after 5 s they are 5, 7.5 and 10 m
    from the start line.
    """
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    for lane, speed in ((1.5, 1.0), (0.0, 1.5), (-1.5, 2.0)):
        world.add(p2.Circle(position=(0.0, lane), radius=0.3, velocity=(speed, 0.0)))
    return world


def gravity() -> p2.World:
    """Milestone 2: two balls launched upwards at 8 m/s, one also moving sideways at 2.5 m/s.

    Gravity acts only vertically, so both rise and fall together (``y = v t - g t^2 / 2``)
    while the sideways one traces a parabola. A ground at y = -1 catches them.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world, -1.0)
    world.add(p2.Circle(position=(0.0, 0.0), radius=0.2, velocity=(0.0, 8.0)))
    world.add(p2.Circle(position=(1.0, 0.0), radius=0.2, velocity=(2.5, 8.0)))
    return world


# -- milestones 3-5: planes, all pairs, circle-plane ----------------------------------------

SLOPE_LEFT = math.radians(35.0)
SLOPE_RIGHT = math.radians(20.0)


def planes() -> p2.World:
    """Milestone 3: a valley of three planes (a 35 degree slope, a floor, a 20 degree slope).

    A ball released on the steep slope rolls (friction turns it) down, across the floor and
    up the gentle slope; at each kink it loses the speed that points into the next plane.
    Boxes rest on both slopes, held by static friction (0.9 > tan 35 degrees).
    """
    world = p2.World(gravity=(0.0, -9.81))
    left_origin, right_origin = (-2.0, 0.0), (2.0, 0.0)
    cl, sl = math.cos(SLOPE_LEFT), math.sin(SLOPE_LEFT)
    cr, sr = math.cos(SLOPE_RIGHT), math.sin(SLOPE_RIGHT)
    world.add(p2.Plane(normal=(sl, cl), point=left_origin, friction=0.9))  # rises to the left
    _ground(world, 0.0, friction=0.9)
    world.add(p2.Plane(normal=(-sr, cr), point=right_origin, friction=0.9))  # rises right
    up_left, up_right = (-cl, sl), (cr, sr)
    r = 0.3
    surface = _slope_point(left_origin, up_left, 3.5)
    world.add(
        p2.Circle(position=(surface[0] + r * sl, surface[1] + r * cl), radius=r, friction=0.9)
    )
    half = 0.3
    surface = _slope_point(left_origin, up_left, 5.5)
    world.add(
        p2.Box(
            position=(surface[0] + half * sl, surface[1] + half * cl),
            width=2 * half,
            height=2 * half,
            angle=-SLOPE_LEFT,
            friction=0.9,
        )
    )
    surface = _slope_point(right_origin, up_right, 7.0)
    world.add(
        p2.Box(
            position=(surface[0] - half * sr, surface[1] + half * cr),
            width=2 * half,
            height=2 * half,
            angle=SLOPE_RIGHT,
            friction=0.9,
        )
    )
    return world


ARENA = (4.0, 2.25)  # half width, half height of the m04 arena (m)


def all_pairs() -> p2.World:
    """Milestone 4: ten circles and boxes in a walled arena in zero gravity, all elastic.

    Every pair of bodies (and every body against every wall) is tested each step; the
    bodies keep colliding like a gas, and their kinetic energy stays within 4 % of the
    start over 8 s (3.9 % measured). Seeded: the same every run.
    """
    rng = np.random.default_rng(4)
    world = p2.World(gravity=(0.0, 0.0), restitution_threshold=0.0, sleeping=False)
    hx, hy = ARENA
    for normal, point in (((0, 1), (0, -hy)), ((0, -1), (0, hy)), ((1, 0), (-hx, 0))):
        world.add(p2.Plane(normal=normal, point=point, restitution=1.0, friction=0.0))
    world.add(p2.Plane(normal=(-1, 0), point=(hx, 0), restitution=1.0, friction=0.0))
    cells = [(x, y) for y in (-1.1, 0.0, 1.1) for x in (-3.0, -1.5, 0.0, 1.5, 3.0)]
    picks = rng.choice(len(cells), size=10, replace=False)
    for k, cell in enumerate(picks):
        x, y = cells[cell]
        position = (x + rng.uniform(-0.15, 0.15), y + rng.uniform(-0.15, 0.15))
        speed, heading = rng.uniform(1.5, 3.0), rng.uniform(0.0, 2.0 * math.pi)
        velocity = (speed * math.cos(heading), speed * math.sin(heading))
        material = {"restitution": 1.0, "friction": 0.0, "velocity": velocity}
        if k % 2:
            size = rng.uniform(0.4, 0.7, size=2)
            world.add(
                p2.Box(
                    position=position,
                    width=float(size[0]),
                    height=float(size[1]),
                    angle=float(rng.uniform(0.0, math.pi)),
                    **material,
                )
            )
        else:
            world.add(p2.Circle(position=position, radius=float(rng.uniform(0.2, 0.4)), **material))
    return world


RESTITUTIONS = (0.2, 0.5, 0.8)
DROP_HEIGHT = 3.0  # m, bottom of each ball above the plane in m05


def circle_plane() -> p2.World:
    """Milestone 5: three balls dropped from 3 m onto a plane, restitution 0.2, 0.5 and 0.8.

    Each bounce rises to ``e^2`` of the height before it: 0.12, 0.75 and 1.92 m.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    r = 0.3
    for x, e in zip((-1.5, 0.0, 1.5), RESTITUTIONS, strict=True):
        world.add(p2.Circle(position=(x, DROP_HEIGHT + r), radius=r, restitution=e))
    return world


# -- milestones 6-8: boxes and rotation -------------------------------------------------------


def circle_and_box() -> p2.World:
    """Milestone 6: twelve circles and boxes of random size and angle falling onto a plane.

    They land and pile up. Seeded: the same every run.
    """
    rng = np.random.default_rng(6)
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    k = 0
    for y in (2.0, 4.0, 6.0):
        for x in (-2.25, -0.75, 0.75, 2.25):
            position = (x + rng.uniform(-0.2, 0.2), y + rng.uniform(-0.2, 0.2))
            material = {"restitution": 0.2, "friction": 0.5}
            if (k + int(y)) % 2:
                world.add(
                    p2.Circle(position=position, radius=float(rng.uniform(0.2, 0.4)), **material)
                )
            else:
                size = rng.uniform(0.3, 0.6, size=2)
                world.add(
                    p2.Box(
                        position=position,
                        width=float(size[0]),
                        height=float(size[1]),
                        angle=float(rng.uniform(0.0, math.pi)),
                        mass=float(size[0] * size[1] * 4.0),
                        **material,
                    )
                )
            k += 1
    return world


SPINS = (1.0, 2.0, -3.0)  # rad/s of the three spinning boxes in m07
PUSH_FORCE = (3.0, 0.0)  # N, applied at the top edge of the pushed box
PUSH_POINT = (0.0, 0.25)  # body-local point where the push acts (m)
PUSH_STEPS = 10  # steps the push lasts


def rotation() -> p2.World:
    """Milestone 7: three boxes spinning at 1, 2 and -3 rad/s in zero gravity, and one pushed.

    The spinning boxes keep their angular velocity exactly. The fourth box (slot 3) is
    pushed by a 3 N force at the middle of its top edge for the first 10 steps (see
    ``push_rotation``): the off-centre force moves it right and spins it clockwise.
    """
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    for x, spin in zip((-3.0, 0.0, 3.0), SPINS, strict=True):
        world.add(p2.Box(position=(x, 1.0), width=1.2, height=0.6, angular_velocity=spin))
    world.add(p2.Box(position=(-4.0, -1.5), width=1.0, height=0.5))
    return world


def push_rotation(world: p2.World) -> None:
    """Before each of the first ``PUSH_STEPS`` steps of m07, push its fourth box off centre.

    ``apply_force`` acts over the next step only, so it is applied again every step; the
    force stays horizontal while its point of action turns with the box.
    """
    if world.steps < PUSH_STEPS:
        box = world.bodies[3]
        box.apply_force(PUSH_FORCE, point=box.to_world(PUSH_POINT))


def box_plane() -> p2.World:
    """Milestone 8: four boxes of different shapes dropped at an angle onto a plane.

    The corner that lands first takes the impact off centre, so each box rotates as it
    falls over, then settles flat on a face.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    shapes = ((1.0, 0.5, 0.3), (1.0, 1.0, 0.6), (2.0, 0.4, -0.9), (0.6, 1.2, 1.2))
    for x, (w, h, angle) in zip((-4.5, -1.5, 1.5, 4.5), shapes, strict=True):
        world.add(p2.Box(position=(x, 2.5), width=w, height=h, angle=angle, restitution=0.2))
    return world


# -- milestones 9-11: collisions between bodies ----------------------------------------------


OBLIQUE_OFFSET = 0.2  # m between the lines of motion of the bottom pair in m09


def circle_circle() -> p2.World:
    """Milestone 9: elastic billiard collisions in zero gravity, in three lanes.

    Top: equal balls head on, the moving one stops dead and the other leaves at 2 m/s.
    Middle: a 4 kg ball hits a 1 kg ball: 1.2 and 3.2 m/s afterwards. Bottom: equal balls
    off centre (0.2 m between their lines): they leave at right angles.
    """
    world = p2.World(gravity=(0.0, 0.0), restitution_threshold=0.0, sleeping=False)
    ball = {"restitution": 1.0, "friction": 0.0}
    world.add(p2.Circle(position=(-3.0, 2.5), radius=0.3, velocity=(2.0, 0.0), **ball))
    world.add(p2.Circle(position=(0.0, 2.5), radius=0.3, **ball))
    world.add(p2.Circle(position=(-3.0, 0.0), radius=0.5, mass=4.0, velocity=(2.0, 0.0), **ball))
    world.add(p2.Circle(position=(0.0, 0.0), radius=0.3, mass=1.0, **ball))
    world.add(p2.Circle(position=(-3.0, -2.5), radius=0.3, velocity=(2.0, 0.0), **ball))
    world.add(p2.Circle(position=(0.0, -2.5 - OBLIQUE_OFFSET), radius=0.3, **ball))
    return world


def circle_box() -> p2.World:
    """Milestone 10: balls hit free standing boxes in zero gravity, one centrally, one off centre.

    The top box is hit on its centre line and slides without turning; the bottom one is
    hit 0.7 m above its centre, so the impulse's torque sets it spinning clockwise.
    """
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    for y, offset in ((1.5, 0.0), (-1.5, 0.7)):
        world.add(p2.Box(position=(0.0, y), width=0.4, height=2.0, restitution=0.5))
        world.add(
            p2.Circle(
                position=(-3.0, y + offset),
                radius=0.2,
                mass=0.5,
                velocity=(3.0, 0.0),
                restitution=0.5,
            )
        )
    return world


LEAN = 0.3  # m each box of the leaning tower in m11 sticks out past the one below


def box_box() -> p2.World:
    """Milestone 11: two towers of five boxes: a straight column stands, a leaning one falls.

    In the leaning tower each box sticks out 0.3 m past the one below: the four upper
    boxes' centre of mass is 0.75 m past the bottom box's centre, beyond its edge, so they
    pivot about that edge and the tower topples.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    for row in range(5):
        world.add(p2.Box(position=(-3.0, 0.5 + row)))
    for row in range(5):
        world.add(p2.Box(position=(1.0 + LEAN * row, 0.5 + row)))
    return world


# -- milestone 12: drag and friction ----------------------------------------------------------

SLIDE_SPEED = 4.0  # m/s
SLIDE_FRICTIONS = (0.1, 0.3, 0.6)
DRAGS = (0.0, 1.0, 3.0)  # 1/s


def drag_friction() -> p2.World:
    """Milestone 12: boxes sliding at 4 m/s on shelves with friction 0.1, 0.3 and 0.6, and
    balls falling with linear drag 0, 1 and 3 per second.

    Each box stops after ``v^2 / (2 mu g)``: 8.2, 2.7 and 1.4 m. Drag slows a ball as
    ``exp(-d t)``; the draggy balls reach terminal speeds ``g / d`` of 9.8 and 3.3 m/s.
    The shelves have friction 1 and the world mixes friction by ``min``, so each contact
    has the box's own coefficient.
    """
    world = p2.World(gravity=(0.0, -9.81), friction_mixing="min")
    _ground(world, -1.0, friction=1.0)
    for level, mu in enumerate(SLIDE_FRICTIONS):
        y = 1.2 * level
        world.add(p2.Box(position=(4.5, y), width=11.0, height=0.2, fixed=True, friction=1.0))
        world.add(
            p2.Box(
                position=(0.0, y + 0.35),
                width=0.5,
                height=0.5,
                velocity=(SLIDE_SPEED, 0.0),
                friction=mu,
            )
        )
    for x, drag in zip((12.0, 13.0, 14.0), DRAGS, strict=True):
        world.add(p2.Circle(position=(x, 6.0), radius=0.25, linear_drag=drag))
    return world


# -- extras ------------------------------------------------------------------------------------


def springs() -> p2.World:
    """Springs extra: a chain of five masses on springs, and two oscillators side by side.

    The chain hangs from a fixed anchor; released straight out sideways, it swings down
    like a rope. On the right, 1 kg masses on 40 N/m springs start 0.8 m below their rest
    point: the undamped one keeps its amplitude, the damped one (c = 0.8 N s/m) shrinks as
    ``exp(-c t / 2m)``.
    """
    world = p2.World(gravity=(0.0, -9.81))
    previous = world.add(p2.Circle(position=(-2.0, 4.0), radius=0.08, fixed=True))
    for i in range(1, 6):
        bead = world.add(p2.Circle(position=(-2.0 + 0.5 * i, 4.0), radius=0.12, mass=0.3))
        world.add(p2.Spring(previous, bead, rest_length=0.5, stiffness=150.0, damping=0.05))
        previous = bead
    k, mass, rest = 40.0, 1.0, 1.5
    sag = mass * 9.81 / k
    for x, damping in ((3.0, 0.0), (5.0, 0.8)):
        anchor = world.add(p2.Circle(position=(x, 4.5), radius=0.08, fixed=True))
        bob = world.add(p2.Circle(position=(x, 4.5 - rest - sag - 0.8), radius=0.2, mass=mass))
        world.add(p2.Spring(anchor, bob, rest_length=rest, stiffness=k, damping=damping))
    return world


SHELF_TOP = 5.0  # m, the top of the shelf the ball rolls along in the sleeping scene


def sleeping() -> p2.World:
    """Sleeping extra: a stack of four boxes falls asleep, then a ball arrives and wakes it.

    The stack settles at once and sleeps after 0.5 s at rest (draw it with the ``sleeping``
    overlay to see it dim). A ball rolls along a high shelf at 3 m/s, drops off its end
    at about 3 s and lands on the top box: the whole stack's island wakes.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    for row in range(4):
        world.add(p2.Box(position=(0.0, 0.5 + row)))
    world.add(p2.Box(position=(-6.0, SHELF_TOP - 0.1), width=10.0, height=0.2, fixed=True))
    r, speed = 0.3, 3.0
    world.add(
        p2.Circle(
            position=(-10.0, SHELF_TOP + r),
            radius=r,
            mass=2.0,
            velocity=(speed, 0.0),
            angular_velocity=-speed / r,
        )
    )
    return world


def contact_forces() -> p2.World:
    """Contact forces extra: 30 circles spawned overlapping at one spot in a walled pit.

    Nothing is moving at first; the soft contact correction pushes the overlapping circles
    apart (no faster than ``contact_push_speed``, 3 m/s) and they settle into a heap.
    Seeded: the same every run.
    """
    rng = np.random.default_rng(30)
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    world.add(p2.Plane(normal=(1.0, 0.0), point=(-3.0, 0.0)))
    world.add(p2.Plane(normal=(-1.0, 0.0), point=(3.0, 0.0)))
    for _ in range(30):
        offset = rng.uniform(-0.05, 0.05, size=2)
        world.add(
            p2.Circle(
                position=(float(offset[0]), 1.5 + float(offset[1])),
                radius=float(rng.uniform(0.2, 0.3)),
            )
        )
    return world


def energy() -> p2.World:
    """Energy extra: a box swinging and bouncing on a spring, and an elastic ball bouncing.

    On the left a box hangs from a spring fixed to the middle of its top edge: released
    level with the anchor it swings, stretches and wobbles, trading potential, elastic,
    linear and rotational kinetic energy. On the right a ball with
    restitution 1 trades potential for kinetic energy at every bounce. The total stays
    (nearly) constant: the CLI plots all five over time.
    """
    world = p2.World(gravity=(0.0, -9.81), sleeping=False)
    _ground(world, restitution=1.0)
    anchor = world.add(p2.Circle(position=(-2.0, 5.0), radius=0.08, fixed=True))
    bob = world.add(p2.Box(position=(-0.5, 5.0), width=0.5, height=0.3, mass=1.0))
    world.add(
        p2.Spring(anchor, bob, rest_length=1.5, stiffness=60.0, anchor2=(0.0, 0.15), damping=0.0)
    )
    world.add(p2.Circle(position=(3.0, 4.0), radius=0.3, restitution=1.0))
    return world


CRADLE_RADIUS = 0.1
CRADLE_GAP = 0.005  # m between neighbouring balls; why: see newtons_cradle
CRADLE_LENGTH = 1.0  # m from anchor to ball centre
CRADLE_ANGLE = 0.5  # rad the first ball is pulled back


def newtons_cradle() -> p2.World:
    """Newton's cradle: five elastic balls, 5 mm apart, each hung on a stiff spring.

    The end ball swings in, the far ball swings out to the same height and the three in
    the middle barely move; then back again. The balls hang 5 mm apart rather than
    touching: with a row of touching balls every contact is solved at once and the
    impulse spreads over all of them (as in Box2D); with a gap wider than a ball moves in
    one step (6.5 mm at 1.55 m/s and 1/240 s) the collisions happen one after another.
    """
    world = p2.World(gravity=(0.0, -9.81), restitution_threshold=0.0, sleeping=False)
    r, length = CRADLE_RADIUS, CRADLE_LENGTH
    for i in range(5):
        x = i * (2.0 * r + CRADLE_GAP)
        anchor = world.add(p2.Circle(position=(x, length), radius=0.02, fixed=True))
        if i == 0:
            position = (
                x - length * math.sin(CRADLE_ANGLE),
                length - length * math.cos(CRADLE_ANGLE),
            )
        else:
            position = (x, 0.0)
        ball = world.add(
            p2.Circle(position=position, radius=r, mass=0.2, restitution=1.0, friction=0.0)
        )
        world.add(p2.Spring(anchor, ball, rest_length=length, stiffness=2000.0))
    return world


def pyramid() -> p2.World:
    """Stacking: the 10-row, 55-box pyramid of 1 m boxes on a plane, 5 cm apart in a row.

    It stands still: the contact solver with friction holds every box in place, and the
    whole pyramid falls asleep.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world)
    for row in range(10):
        for i in range(10 - row):
            world.add(p2.Box(position=((i - (10 - row - 1) / 2) * 1.05, 0.5 + row)))
    return world


POOL_RADIUS = 0.028575  # m
POOL_TABLE = (2.54, 1.27)  # m, play area


def pool_break() -> p2.World:
    """Game (pool): the 16-ball break on a 2.54 x 1.27 m table, top down (no gravity).

    The cue ball hits the rack at 8 m/s; balls (0.17 kg, restitution 0.95) scatter, bounce
    off the cushions (fixed boxes, restitution 0.75: the world mixes restitution by
    ``min``) and roll to a stop under a linear drag of 0.7 per second. Step with dt 1/120.
    """
    world = p2.World(
        gravity=(0.0, 0.0), substeps=2, restitution_mixing="min", restitution_threshold=0.05
    )
    length, width = POOL_TABLE
    t = 0.1  # cushion thickness
    for x, y, w, h in (
        (0.0, (width + t) / 2, length + 2 * t, t),
        (0.0, -(width + t) / 2, length + 2 * t, t),
        ((length + t) / 2, 0.0, t, width),
        (-(length + t) / 2, 0.0, t, width),
    ):
        world.add(p2.Box(position=(x, y), width=w, height=h, fixed=True, restitution=0.75))
    r = POOL_RADIUS
    ball = {"radius": r, "mass": 0.17, "restitution": 0.95, "friction": 0.0, "linear_drag": 0.7}
    world.add(p2.Circle(position=(-length / 4, 0.0), velocity=(8.0, 0.0), **ball))
    spacing = 2.0001 * r
    for row in range(5):
        for k in range(row + 1):
            x = length / 4 + row * spacing * math.sqrt(3) / 2
            world.add(p2.Circle(position=(x, (k - row / 2) * spacing), **ball))
    return world


def slingshot() -> p2.World:
    """Game (Angry Birds): a heavy ball flung at a two-storey tower with a "pig" on top.

    The tower is two pairs of posts under two planks; the pig is the small circle on the
    top plank. The 3 kg ball is launched at (11, 5) m/s and smashes the top storey.
    """
    world = p2.World(gravity=(0.0, -9.81))
    _ground(world, friction=0.8)
    world.add(p2.Box(position=(0.0, 0.6), width=0.2, height=1.2, fixed=True))  # the sling post
    block = {"friction": 0.7, "mass": 0.8}
    for x in (7.4, 8.6):
        world.add(p2.Box(position=(x, 0.6), width=0.3, height=1.2, **block))
    world.add(p2.Box(position=(8.0, 1.325), width=1.8, height=0.25, **block))
    for x in (7.6, 8.4):
        world.add(p2.Box(position=(x, 1.85), width=0.25, height=0.8, **block))
    world.add(p2.Box(position=(8.0, 2.35), width=1.4, height=0.2, **block))
    world.add(p2.Circle(position=(8.0, 2.75), radius=0.3, mass=0.5, friction=0.7))  # the pig
    world.add(
        p2.Circle(position=(0.0, 1.45), radius=0.25, mass=3.0, velocity=(11.0, 5.0), friction=0.5)
    )
    return world
