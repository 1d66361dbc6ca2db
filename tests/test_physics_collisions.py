"""Physics laws of impacts: restitution, momentum, impulse on a free body, fixed and
kinematic bodies, and a box settling on the ground."""

from __future__ import annotations

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, G, contact_count, run

ZERO_G = (0.0, 0.0)


# -- a ball bouncing on the ground -----------------------------------------------------------
def _bounce(drop: float, e: float, radius: float = 0.5) -> tuple[float, float]:
    """Drop a ball (centre at ``drop``) on the ground; return (rebound speed, impact speed).

    The impact speed is the analytic one, sqrt(2 g (drop - radius)).
    """
    world = p2.World()
    ball = world.add(p2.Circle(position=(0.0, drop), radius=radius, restitution=e))
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), restitution=e))
    previous = 0.0
    for _ in range(600):
        world.step(DT)
        vy = ball.velocity[1]
        if previous < 0.0 <= vy:
            return vy, np.sqrt(2.0 * G * (drop - radius))
        previous = vy
    raise AssertionError("the ball never bounced")


@pytest.mark.parametrize("drop", [3.0, 5.0])
@pytest.mark.parametrize("e", [0.2, 0.4, 0.6, 0.8, 1.0])
def test_bounce_rebounds_at_restitution_times_impact_speed(e, drop):
    """Newton's law of restitution on a plane: v_out = e v_in (ratio within +-0.03)."""
    rebound, impact = _bounce(drop, e)
    assert rebound / impact == pytest.approx(e, abs=0.03)


def test_bounce_ratio_from_short_drops():
    """v_out = e v_in (+-0.03) also for short drops (impact speed 3-5 m/s), whatever the
    phase of the impact within a step (the ball gains g dt of speed during the step)."""
    ratios = {
        (drop, e): _bounce(drop, e)[0] / _bounce(drop, e)[1]
        for drop in (1.0, 1.25, 1.5, 1.75, 2.0)
        for e in (0.5, 0.8, 1.0)
    }
    bad = {key: round(r, 4) for key, r in ratios.items() if abs(r - key[1]) > 0.03}
    assert not bad, f"(drop, e): rebound/impact ratio {bad}"


def test_slow_impact_does_not_bounce():
    """Impacts slower than restitution_threshold (1 m/s) do not bounce, even with e = 1."""
    world = p2.World(sleeping=False)
    ball = world.add(p2.Circle(position=(0.0, 0.53), radius=0.5, restitution=1.0))
    world.add(p2.Plane(restitution=1.0))
    top = []
    for _ in range(60):
        world.step(DT)
        top.append(ball.position[1])
    assert max(top[10:]) < 0.505  # impact at ~0.77 m/s: it stays down
    assert ball.velocity[1] == pytest.approx(0.0, abs=0.02)


def _elastic_bounces(drop: float, bounces: int = 5) -> np.ndarray:
    """Total energy after every step of an e = 1 ball until it has bounced ``bounces`` times,
    relative to the start."""
    world = p2.World()
    ball = world.add(p2.Circle(position=(0.0, drop), radius=0.5, restitution=1.0))
    world.add(p2.Plane(restitution=1.0))
    start = world.energy().total
    energy, count, previous = [], 0, 0.0
    while count < bounces:
        world.step(DT)
        energy.append(world.energy().total / start - 1.0)
        vy = ball.velocity[1]
        count += previous < 0.0 <= vy
        previous = vy
        assert world.steps < 2000
    return np.array(energy)


def test_elastic_bouncing_keeps_energy():
    """e = 1: total energy (m v^2/2 + m g y) stays within 3% over 5 bounces, no drift."""
    energy = _elastic_bounces(3.0)
    assert np.abs(energy).max() < 0.03
    # No trend after the first bounce: the last second of bouncing has the same energy.
    half = energy.size // 2
    assert abs(energy[half:].mean() - energy[-half // 2 :].mean()) < 0.005


def test_elastic_bouncing_keeps_energy_any_drop_height():
    """e = 1: total energy within 3% over 5 bounces for drop heights from 1 to 4 m."""
    worst = {drop: float(np.abs(_elastic_bounces(drop)).max()) for drop in np.arange(1, 4.1, 0.5)}
    assert max(worst.values()) < 0.03, f"drop height: worst relative energy change {worst}"


# -- head-on collisions of free bodies (zero gravity, no friction) ------------------------------
def _head_on(shape: str, m1: float, m2: float, v1: float, v2: float, e: float):
    world = p2.World(gravity=ZERO_G, sleeping=False)
    make = p2.Circle if shape == "circle" else p2.Box
    a = world.add(
        make(position=(-1.5, 0.0), mass=m1, velocity=(v1, 0.0), restitution=e, friction=0.0)
    )
    b = world.add(
        make(position=(1.5, 0.0), mass=m2, velocity=(v2, 0.0), restitution=e, friction=0.0)
    )
    run(world, 1.5)
    return a, b


def _one_d(m1: float, m2: float, v1: float, v2: float, e: float) -> tuple[float, float]:
    u1 = ((m1 - e * m2) * v1 + (1 + e) * m2 * v2) / (m1 + m2)
    u2 = ((m2 - e * m1) * v2 + (1 + e) * m1 * v1) / (m1 + m2)
    return u1, u2


HEAD_ON = [
    (1.0, 1.0, 3.0, -3.0, 1.0),  # equal masses, elastic: swap
    (1.0, 1.0, 3.0, 0.0, 1.0),  # Newton's cradle: the mover stops
    (1.0, 3.0, 4.0, -1.0, 1.0),
    (2.0, 1.0, 4.0, -1.0, 0.5),
    (1.0, 2.0, 5.0, -2.0, 0.3),
    (1.0, 4.0, 5.0, 0.0, 0.0),  # perfectly inelastic: move together
    (3.0, 1.0, 2.0, -4.0, 0.0),
]


@pytest.mark.parametrize(("m1", "m2", "v1", "v2", "e"), HEAD_ON)
def test_head_on_circles_follow_1d_formula(m1, m2, v1, v2, e):
    """v1' = ((m1 - e m2) v1 + (1+e) m2 v2)/(m1+m2), v2' = ((m2 - e m1) v2 + (1+e) m1 v1)/(...)."""
    a, b = _head_on("circle", m1, m2, v1, v2, e)
    u1, u2 = _one_d(m1, m2, v1, v2, e)
    np.testing.assert_allclose(a.velocity, [u1, 0.0], atol=1e-6)
    np.testing.assert_allclose(b.velocity, [u2, 0.0], atol=1e-6)
    assert a.angular_velocity == b.angular_velocity == 0.0


@pytest.mark.parametrize(("m1", "m2", "v1", "v2"), [(1.0, 4.0, 5.0, 0.0), (3.0, 1.0, 2.0, -4.0)])
def test_head_on_boxes_perfectly_inelastic_move_together(m1, m2, v1, v2):
    """e = 0: both move at (m1 v1 + m2 v2) / (m1 + m2) after the impact."""
    a, b = _head_on("box", m1, m2, v1, v2, 0.0)
    common = (m1 * v1 + m2 * v2) / (m1 + m2)
    np.testing.assert_allclose(a.velocity, [common, 0.0], atol=1e-4)
    np.testing.assert_allclose(b.velocity, [common, 0.0], atol=1e-4)


@pytest.mark.parametrize(("m1", "m2", "v1", "v2", "e"), [HEAD_ON[0], HEAD_ON[2], HEAD_ON[4]])
def test_head_on_boxes_follow_1d_formula(m1, m2, v1, v2, e):
    """Aligned boxes hitting face to face obey the 1D formula and do not spin (symmetry)."""
    a, b = _head_on("box", m1, m2, v1, v2, e)
    u1, u2 = _one_d(m1, m2, v1, v2, e)
    np.testing.assert_allclose([a.velocity[0], b.velocity[0]], [u1, u2], atol=0.02 * abs(v1 - v2))
    assert abs(a.angular_velocity) < 0.01 and abs(b.angular_velocity) < 0.01


@pytest.mark.parametrize("offset", [0.1, 0.3, 0.5, 0.7, 0.9])
def test_oblique_elastic_equal_masses_leave_at_right_angles(offset):
    """Equal masses, e = 1, no friction: outgoing velocities are perpendicular and kinetic
    energy is kept (v1' . v2' = 0, |v1'|^2 + |v2'|^2 = |v1|^2)."""
    world = p2.World(gravity=ZERO_G, sleeping=False)
    a = world.add(
        p2.Circle(
            position=(-2.0, 0.0), radius=0.5, velocity=(4.0, 0.0), restitution=1.0, friction=0.0
        )
    )
    b = world.add(p2.Circle(position=(0.0, offset), radius=0.5, restitution=1.0, friction=0.0))
    run(world, 1.5)
    va, vb = a.velocity, b.velocity
    assert np.linalg.norm(vb) > 0.5  # they did collide
    angle = np.degrees(np.arccos(va @ vb / np.linalg.norm(va) / np.linalg.norm(vb)))
    assert angle == pytest.approx(90.0, abs=0.5)
    assert va @ va + vb @ vb == pytest.approx(16.0, rel=1e-6)
    np.testing.assert_allclose(va + vb, [4.0, 0.0], atol=1e-9)


def test_oblique_cut_angle_is_the_line_of_centres_at_impact():
    """The struck ball leaves along the line of centres at impact, at asin(b / 2r) from the
    path, whatever phase of a step the impact falls in (the contact normal is taken at the
    time of impact, not at the start of the step)."""
    offset, speed = 0.7, 4.0
    expected = np.degrees(np.arcsin(offset / 1.0))
    worst = []
    for dt in (DT, DT / 2, DT / 4):
        errors = []
        # Start positions spanning one step of travel: every phase of the impact in a step.
        for start in np.linspace(-3.0, -3.0 + speed * dt, 8, endpoint=False):
            world = p2.World(gravity=ZERO_G, sleeping=False)
            world.add(
                p2.Circle(
                    position=(start, 0.0),
                    radius=0.5,
                    velocity=(speed, 0.0),
                    restitution=1.0,
                    friction=0.0,
                )
            )
            b = world.add(
                p2.Circle(position=(0.0, offset), radius=0.5, restitution=1.0, friction=0.0)
            )
            run(world, 0.8, dt)
            errors.append(abs(np.degrees(np.arctan2(b.velocity[1], b.velocity[0])) - expected))
        worst.append(max(errors))
    assert max(worst) < 0.05  # degrees


@pytest.mark.parametrize("kinds", [("circle", "circle"), ("circle", "box"), ("box", "box")])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_momentum_conserved_in_collisions(kinds, seed):
    """Free bodies, g = 0: sum m v is conserved to 1e-6 relative, whatever the shapes,
    spins, restitution and friction."""
    rng = np.random.default_rng(seed)
    world = p2.World(gravity=ZERO_G, sleeping=False)
    bodies = []
    for kind, x in zip(kinds, (-1.5, 1.5), strict=True):
        kwargs = dict(
            position=(x, rng.uniform(-0.3, 0.3)),
            mass=rng.uniform(0.5, 3.0),
            velocity=(-x * rng.uniform(1.5, 3.0), rng.uniform(-0.5, 0.5)),
            angle=rng.uniform(0.0, 3.0),
            angular_velocity=rng.uniform(-3.0, 3.0),
            restitution=rng.uniform(0.0, 1.0),
            friction=rng.uniform(0.0, 1.0),
        )
        if kind == "circle":
            bodies.append(world.add(p2.Circle(radius=rng.uniform(0.4, 0.7), **kwargs)))
        else:
            size = dict(width=rng.uniform(0.6, 1.2), height=rng.uniform(0.6, 1.2))
            bodies.append(world.add(p2.Box(**size, **kwargs)))
    before = sum(body.mass * body.velocity for body in bodies)
    start = [body.velocity for body in bodies]
    contacts = 0
    for _ in range(90):
        world.step(DT)
        contacts += contact_count(world)
    after = sum(body.mass * body.velocity for body in bodies)
    assert contacts > 0
    assert np.linalg.norm(after - before) <= 1e-6 * np.linalg.norm(before)
    # The collision did something (the bodies are not just passing each other).
    assert np.linalg.norm(bodies[0].velocity - start[0]) > 0.1


# -- a ball striking a free box off-centre ------------------------------------------------------
@pytest.mark.parametrize("offset", [0.0, 0.4, -0.7])
@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_ball_strikes_free_box_off_centre(e, offset):
    """J = (1+e) v / (1/m1 + 1/m2 + (r x n)^2 / I); v_box = J n / m2, w_box = (r x J n) / I,
    v_ball = v - J / m1 (within 5%), just after the impact."""
    m_ball, m_box, speed = 1.0, 2.0, 3.0
    world = p2.World(gravity=ZERO_G, sleeping=False)
    ball = world.add(
        p2.Circle(
            position=(-2.0, offset),
            radius=0.25,
            mass=m_ball,
            velocity=(speed, 0.0),
            restitution=e,
            friction=0.0,
        )
    )
    box = world.add(p2.Box(width=1.0, height=2.0, mass=m_box, restitution=e, friction=0.0))
    moment = m_box * (1.0**2 + 2.0**2) / 12.0
    r = np.array([-0.5, offset])  # contact point from the box centre; n = (1, 0)
    r_cross_n = r[0] * 0.0 - r[1] * 1.0
    impulse = (1 + e) * speed / (1 / m_ball + 1 / m_box + r_cross_n**2 / moment)
    for _ in range(120):
        world.step(DT)
        if np.any(box.velocity != 0.0):
            break
    else:
        raise AssertionError("the ball never reached the box")
    tol = 0.05 * impulse / m_box
    assert box.velocity[0] == pytest.approx(impulse / m_box, abs=tol)
    assert box.velocity[1] == pytest.approx(0.0, abs=tol)
    w_expected = r_cross_n * impulse / moment
    assert box.angular_velocity == pytest.approx(w_expected, abs=0.05 * abs(w_expected) + 1e-6)
    assert ball.velocity[0] == pytest.approx(speed - impulse / m_ball, abs=0.05 * speed)


# -- fixed and kinematic bodies -----------------------------------------------------------------
def test_fixed_body_never_moves_when_hit():
    """A fixed body has infinite mass: position, angle and velocity stay exactly put."""
    world = p2.World()
    world.add(p2.Plane())
    post = world.add(p2.Box(position=(0.0, 0.5), width=1.0, height=1.0, fixed=True))
    hitters = [
        world.add(
            p2.Circle(
                position=(-3.0, 0.5), radius=0.3, velocity=(20.0, 0.0), mass=50.0, restitution=0.5
            )
        ),
        world.add(p2.Box(position=(0.0, 4.0), velocity=(0.0, -10.0), mass=100.0, angle=0.3)),
        world.add(p2.Circle(position=(3.0, 0.6), velocity=(-30.0, 0.0), mass=10.0)),
    ]
    touched = 0
    for _ in range(120):
        world.step(DT)
        touched += contact_count(world)
        assert np.array_equal(post.position, [0.0, 0.5])
        assert post.angle == 0.0 and post.angular_velocity == 0.0
        assert np.array_equal(post.velocity, [0.0, 0.0])
    assert touched > 0
    assert hitters[0].velocity[0] <= 0.0  # the heavy ball bounced back (or stopped)
    for hitter in hitters:  # nobody went through it
        assert not post.is_inside(hitter.position)


def test_kinematic_body_pushes_and_is_not_deflected():
    """A kinematic body keeps x = x0 + v t whatever hits it, and pushes dynamic bodies."""
    world = p2.World()
    world.add(p2.Plane(friction=0.5))
    pusher = world.add(
        p2.Box(position=(-3.0, 0.6), width=0.6, height=1.0, velocity=(2.0, 0.0), kinematic=True)
    )
    pushed = [
        world.add(p2.Box(position=(0.0, 0.25), width=0.5, height=0.5, mass=1.0)),
        world.add(p2.Box(position=(1.5, 0.25), width=0.5, height=0.5, mass=50.0)),
        world.add(p2.Circle(position=(3.5, 0.3), radius=0.3, mass=2.0)),
    ]
    # A heavy box lands on its top and a heavy fast ball hits its back face.
    falling = world.add(p2.Box(position=(-2.0, 3.0), mass=20.0))
    bullet = world.add(p2.Circle(position=(-7.0, 0.6), radius=0.2, mass=30.0, velocity=(25.0, 0.0)))
    for _ in range(300):
        world.step(DT)
        np.testing.assert_allclose(pusher.velocity, [2.0, 0.0], atol=0.0)
        assert pusher.angular_velocity == 0.0 and pusher.angle == 0.0
        assert pusher.position[1] == 0.6
    assert pusher.position[0] == pytest.approx(-3.0 + 2.0 * world.time, abs=1e-9)
    # Everything in its way now sits ahead of its front face (x = pusher.x + 0.3).
    front = pusher.position[0] + 0.3
    for body in pushed:
        assert body.position[0] > front
        assert body.position[0] > 3.0  # they were moved along
    assert bullet.position[0] < pusher.position[0] - 0.3 - 0.2 + 0.01  # still behind it
    assert np.all(np.isfinite(falling.position))


# -- a box dropped at an angle ------------------------------------------------------------------
@pytest.mark.parametrize("size", [(1.0, 1.0), (2.0, 0.5)])
@pytest.mark.parametrize("angle", [0.2, 0.5, 1.0, 1.3, -0.6, 2.5])
def test_box_dropped_at_angle_settles_flat(angle, size):
    """A box landing on a corner rotates and comes to rest on a face: angle = k pi/2 and
    centre height = the matching half side."""
    width, height = size
    world = p2.World()
    world.add(p2.Plane())
    box = world.add(p2.Box(position=(0.0, 2.0), width=width, height=height, angle=angle))
    spin = 0.0
    for _ in range(360):
        world.step(DT)
        spin = max(spin, abs(box.angular_velocity))
    assert spin > 0.5  # it tipped over onto a face
    quarter_turns = box.angle / (np.pi / 2)
    k = round(quarter_turns)
    assert abs(box.angle - k * np.pi / 2) < 0.01
    rest_height = (height if k % 2 == 0 else width) / 2
    assert box.position[1] == pytest.approx(rest_height, abs=0.01)
    assert np.linalg.norm(box.velocity) < 0.05
