"""The integration stage alone: the step terms of each body (broadphase boxes, masses,
accelerations), semi-implicit Euler against its closed form, drag as an exact factor,
rolling resistance, springs (Hooke's law per substep, the period, the stability limit) and
the derived rotation columns kept current between steps.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from conftest import names, upward_crossings
from impulse2d.core import integrate, workspace
from impulse2d.core.state import ANGLE, AWAKE, BOX, COS, SIN
from impulse2d.core.workspace import (
    ACCEL_W,
    ACCEL_X,
    ACCEL_Y,
    BOTTOM,
    HALF_SPEC,
    LEFT,
    MOVABLE,
    MOVING,
    RIGHT,
    ROLL_H,
    SPEED,
    STEP_INV_MASS,
    STEP_INV_MOMENT,
    TOP,
)

DT = 1 / 60
ZERO_G = (0.0, 0.0)


def terms_of(world: p2.World, dt: float = DT, w: int = 0) -> np.ndarray:
    """``integrate.step_terms`` of world ``w`` as it stands."""
    state = world.state
    terms = np.zeros((state.body.shape[1], workspace.TERMS))
    ctx = world.settings.step_context(dt)
    integrate.step_terms(
        state.body,
        state.body_i,
        world.layout.shapes,
        state.spring,
        world.layout.springs,
        state.hull,
        w,
        ctx,
        terms,
    )
    return terms


def corners(x, y, angle, hw, hh) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    local = np.array([[hw, hh], [-hw, hh], [-hw, -hh], [hw, -hh]])
    return np.array([x, y]) + local @ np.array([[c, s], [-s, c]])


# -- body terms -------------------------------------------------------------------------------
@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 4, 2.0, -1.2, math.pi])
def test_resting_box_broadphase_box_is_tight(angle):
    """A box (0.8 x 0.3 half sizes) turned by theta, at rest: [LEFT, RIGHT] x [BOTTOM, TOP]
    contains its four corners and is tight: its half extents are |cos| hw + |sin| hh and
    |sin| hw + |cos| hh plus half the speculative distance, min(0.02, bound / 4) / 2 (1e-12)."""
    world = p2.World(gravity=ZERO_G)
    body = world.add(p2.Box(position=(1.5, -0.7), width=1.6, height=0.6, angle=angle))
    t = terms_of(world)[body.slot]
    hw, hh = 0.8, 0.3
    half_spec = 0.5 * min(0.02, 0.25 * math.hypot(hw, hh))
    assert t[HALF_SPEC] == pytest.approx(half_spec, abs=1e-15)
    assert t[SPEED] == 0.0
    ex = abs(math.cos(angle)) * hw + abs(math.sin(angle)) * hh + half_spec
    ey = abs(math.sin(angle)) * hw + abs(math.cos(angle)) * hh + half_spec
    np.testing.assert_allclose(
        t[[LEFT, RIGHT, BOTTOM, TOP]], [1.5 - ex, 1.5 + ex, -0.7 - ey, -0.7 + ey], atol=1e-12
    )
    c = corners(1.5, -0.7, angle, hw, hh)
    assert np.all((c[:, 0] >= t[LEFT]) & (c[:, 0] <= t[RIGHT]))
    assert np.all((c[:, 1] >= t[BOTTOM]) & (c[:, 1] <= t[TOP]))
    # Tight: some corner is within half the speculative distance of each side.
    assert c[:, 0].max() == pytest.approx(t[RIGHT] - half_spec, abs=1e-12)
    assert c[:, 1].min() == pytest.approx(t[BOTTOM] + half_spec, abs=1e-12)


@pytest.mark.parametrize(
    ("velocity", "spin"), [((3.0, -1.0), 0.0), ((0.0, 0.0), 8.0), ((-2, 5), -4)]
)
def test_moving_box_grows_by_speed_dt(velocity, spin):
    """A moving box's broadphase box grows on every side by SPEED dt, SPEED = |vx| + |vy| +
    |w| R (R the half diagonal) (1e-12), and contains every corner of the box over the whole
    step of free motion (sampled at 200 instants)."""
    world = p2.World(gravity=ZERO_G)
    body = world.add(
        p2.Box(position=(0, 0), width=1.2, height=0.4, angle=0.5, velocity=velocity,
               angular_velocity=spin)
    )  # fmt: skip
    t = terms_of(world)[body.slot]
    radius = math.hypot(0.6, 0.2)
    speed = abs(velocity[0]) + abs(velocity[1]) + abs(spin) * radius
    assert t[SPEED] == pytest.approx(speed, abs=1e-12)
    rest = world.snapshot()
    body.velocity, body.angular_velocity = (0.0, 0.0), 0.0
    still = terms_of(world)[body.slot]
    world.restore(rest)
    grow = speed * DT
    np.testing.assert_allclose(t[[RIGHT, TOP]] - still[[RIGHT, TOP]], [grow, grow], atol=1e-12)
    np.testing.assert_allclose(still[[LEFT, BOTTOM]] - t[[LEFT, BOTTOM]], [grow, grow], atol=1e-12)
    for tau in np.linspace(0.0, DT, 200):
        c = corners(velocity[0] * tau, velocity[1] * tau, 0.5 + spin * tau, 0.6, 0.2)
        assert np.all((c[:, 0] >= t[LEFT]) & (c[:, 0] <= t[RIGHT]))
        assert np.all((c[:, 1] >= t[BOTTOM]) & (c[:, 1] <= t[TOP]))


def test_motion_types_give_their_step_masses():
    """Step terms by motion type: dynamic MOVING = MOVABLE = 1 with 1/m, 1/I; fixed MOVING =
    MOVABLE = 0 and zero step inverse mass and moment; kinematic moving MOVING = 1 but
    MOVABLE = 0 and zero inverse mass; asleep MOVING = 0, SPEED = 0; a disabled body and a
    plane LEFT = +inf (out of the broadphase)."""
    world = p2.World(gravity=ZERO_G)
    dynamic = world.add(p2.Box(position=(0, 0), width=1.0, height=2.0, mass=3.0))
    fixed = world.add(p2.Box(position=(5, 0), fixed=True))
    kinematic = world.add(p2.Circle(position=(-5, 0), kinematic=True, velocity=(1, 0)))
    asleep = world.add(p2.Circle(position=(0, 5), velocity=(1, 0)))
    disabled = world.add(p2.Circle(position=(0, -5)))
    ground = world.add(p2.Plane())
    disabled.enabled = False
    world.state.body_i[0, asleep.slot, AWAKE] = 0  # put it to sleep by hand
    t = terms_of(world)
    assert t[dynamic.slot, [MOVING, MOVABLE]].tolist() == [1.0, 1.0]
    assert t[dynamic.slot, STEP_INV_MASS] == pytest.approx(1 / 3.0, rel=1e-15)
    assert t[dynamic.slot, STEP_INV_MOMENT] == pytest.approx(12 / (3.0 * 5.0), rel=1e-15)
    for body in (fixed, kinematic):
        assert t[body.slot, [MOVABLE, STEP_INV_MASS, STEP_INV_MOMENT]].tolist() == [0, 0, 0]
    assert t[fixed.slot, MOVING] == 0.0 and t[kinematic.slot, MOVING] == 1.0
    assert t[asleep.slot, [MOVING, MOVABLE, SPEED]].tolist() == [0, 0, 0]
    assert t[disabled.slot, LEFT] == np.inf and t[ground.slot, LEFT] == np.inf
    assert np.isfinite(t[[dynamic.slot, fixed.slot, kinematic.slot, asleep.slot], LEFT]).all()
    # The bodies the substeps' loops walk: the dynamic and the kinematic one, in slot order
    # (the list's slots after its count are left as the loop wrote them, unread).
    moving = np.full(t.shape[0], -1, np.int64)
    count = integrate.list_moving(t, moving)
    assert moving[:count].tolist() == sorted([dynamic.slot, kinematic.slot])


def test_acceleration_terms_are_h_times_g_plus_f_over_m():
    """ACCEL = h (g + F / m), ACCEL_W = h T / I, ROLL_H = h a for a dynamic body with an
    applied force, torque and rolling resistance (1e-15 relative); zero for a fixed one."""
    world = p2.World(gravity=(0.5, -9.81), substeps=3)
    body = world.add(p2.Box(position=(0, 0), width=1, height=1, mass=2.0, rolling_resistance=0.7))
    fixed = world.add(p2.Box(position=(4, 0), fixed=True))
    body.apply_force((4.0, 6.0), point=(0.0, 0.5))  # torque r x F = -0.5 * 4 = -2
    fixed.apply_force((1.0, 1.0))
    t = terms_of(world)
    h = DT / 3
    expected = [h * (0.5 + 4 / 2), h * (-9.81 + 6 / 2), h * -2.0 / body.moment, h * 0.7]
    np.testing.assert_allclose(
        t[body.slot, [ACCEL_X, ACCEL_Y, ACCEL_W, ROLL_H]], expected, rtol=1e-15
    )
    assert t[fixed.slot, [ACCEL_X, ACCEL_Y, ACCEL_W, ROLL_H]].tolist() == [0, 0, 0, 0]


# -- velocities and positions -----------------------------------------------------------------
@pytest.mark.parametrize("substeps", [1, 4, 7])
@pytest.mark.parametrize("drag", [0.3, 2.0])
def test_drag_decays_exactly_exponentially(drag, substeps):
    """Free flight, no gravity, linear and angular drag d: after t seconds v = v0 exp(-d t)
    and w = w0 exp(-d t) to 1e-12 relative, for any number of substeps (exact factor)."""
    world = p2.World(gravity=ZERO_G, substeps=substeps, sleeping=False)
    body = world.add(
        p2.Box(position=(0, 0), velocity=(3.0, -1.5), angular_velocity=2.0,
               linear_drag=drag, angular_drag=drag)
    )  # fmt: skip
    for _ in range(120):
        world.step(DT)
    factor = math.exp(-drag * world.time)
    np.testing.assert_allclose(body.velocity, np.array([3.0, -1.5]) * factor, rtol=1e-12)
    assert body.angular_velocity == pytest.approx(2.0 * factor, rel=1e-12)


@pytest.mark.parametrize("substeps", [1, 3, 4])
def test_gravity_follows_semi_implicit_euler_closed_form(substeps):
    """Under gravity g from (x0, v0), after N substeps of h = dt / substeps, semi-implicit
    Euler (v += h g, then x += h v) gives v_N = v0 + N h g and x_N = x0 + N h v0 +
    h^2 g N (N + 1) / 2 exactly (1e-12 relative): no contact, no drag."""
    g = np.array([0.7, -9.81])
    world = p2.World(gravity=g, substeps=substeps, sleeping=False)
    body = world.add(p2.Circle(position=(1.0, 50.0), velocity=(2.0, 3.0)))
    steps = 90
    for _ in range(steps):
        world.step(DT)
    h, n = DT / substeps, steps * substeps
    v0, x0 = np.array([2.0, 3.0]), np.array([1.0, 50.0])
    np.testing.assert_allclose(body.velocity, v0 + n * h * g, rtol=1e-12)
    np.testing.assert_allclose(
        body.position, x0 + n * h * v0 + h * h * g * n * (n + 1) / 2, rtol=1e-12
    )


def test_one_substep_of_the_kernels_by_hand():
    """``integrate_velocities`` then ``integrate_positions`` on one body: v' = v exp(-d h) +
    h (g + F / m), x' = x + h v', angle' = angle + h w' (1e-15 relative)."""
    world = p2.World(gravity=(0.0, -9.81), substeps=2)
    body = world.add(p2.Box(position=(1, 2), angle=0.3, velocity=(4, 1), angular_velocity=-2,
                            mass=2.0, linear_drag=0.5, angular_drag=0.25))  # fmt: skip
    body.apply_force((6.0, 0.0))
    terms = terms_of(world)
    state, h = world.state, DT / 2
    moving = np.zeros(terms.shape[0], np.int64)
    count = integrate.list_moving(terms, moving)
    assert count == 1 and moving[0] == 0  # the one body, in slot 0
    integrate.integrate_velocities(state.body, 0, terms, moving, count)
    v = np.array([4, 1]) * math.exp(-0.5 * h) + h * np.array([3.0, -9.81])
    w = -2 * math.exp(-0.25 * h)
    np.testing.assert_allclose(body.velocity, v, rtol=1e-15)
    assert body.angular_velocity == pytest.approx(w, rel=1e-15)
    integrate.integrate_positions(state.body, 0, h, moving, count)
    np.testing.assert_allclose(body.position, np.array([1, 2]) + h * v, rtol=1e-15)
    assert body.angle == pytest.approx(0.3 + h * w, rel=1e-15)


@pytest.mark.parametrize(("v0", "a"), [(2.0, 1.0), (1.3, 0.45)])
def test_rolling_resistance_stops_after_v0_over_a(v0, a):
    """A disc at speed v0 (direction (0.6, 0.8)) with rolling resistance a, no gravity:
    its speed is v0 - a t (1e-9) while it rolls, its direction never changes (it never
    reverses), and it stops within one step of t = v0 / a."""
    world = p2.World(gravity=ZERO_G, sleeping=False)
    direction = np.array([0.6, 0.8])
    body = world.add(p2.Circle(position=(0, 0), velocity=v0 * direction, rolling_resistance=a))
    stopped_at = None
    while world.time < v0 / a + 0.5:
        world.step(DT)
        v = body.velocity
        speed = float(np.linalg.norm(v))
        assert speed == pytest.approx(max(v0 - a * world.time, 0.0), abs=1e-9)
        assert v @ direction >= 0.0 and abs(v[0] * direction[1] - v[1] * direction[0]) < 1e-12
        if stopped_at is None and speed == 0.0:
            stopped_at = world.time
    assert stopped_at == pytest.approx(v0 / a, abs=DT)


# -- springs ------------------------------------------------------------------------------------
def _spring_world(m1, m2, k, c=0.0, anchors=((0.0, 0.0), (0.0, 0.0)), length=2.5, rest=2.0):
    world = p2.World(gravity=ZERO_G, sleeping=False)
    a = world.add(p2.Circle(position=(0.0, 0.0), radius=0.2, mass=m1))
    b = world.add(p2.Box(position=(length, 0.0), width=0.4, height=0.4, mass=m2))
    spring = world.add(
        p2.Spring(a, b, rest, stiffness=k, damping=c, anchor1=anchors[0], anchor2=anchors[1])
    )
    return world, a, b, spring


def test_spring_kernel_is_hookes_law_for_one_substep():
    """``apply_springs`` over one substep h: A gets h F / m1 with F = k (L - L0) u (u from
    A's anchor to B's), B the opposite; anchors off the centres turn A by h (rA x F) / IA
    and B by -h (rB x F) / IB (1e-12)."""
    m1, m2, k = 1.0, 2.0, 40.0
    ra, rb = np.array([0.1, -0.05]), np.array([-0.2, 0.1])
    world, a, b, _ = _spring_world(m1, m2, k, anchors=(ra, rb))
    terms = terms_of(world)
    state, h = world.state, DT / world.substeps
    ends = world.layout.springs
    integrate.apply_springs(state.body, state.body_i, state.spring, ends, 0, terms, h)
    d = b.position + rb - (a.position + ra)
    length = float(np.linalg.norm(d))
    force = k * (length - 2.0) * d / length  # on A
    np.testing.assert_allclose(a.velocity, h * force / m1, atol=1e-12)
    np.testing.assert_allclose(b.velocity, -h * force / m2, atol=1e-12)
    torque_a = ra[0] * force[1] - ra[1] * force[0]
    torque_b = rb[0] * -force[1] - rb[1] * -force[0]
    assert a.angular_velocity == pytest.approx(h * torque_a / a.moment, abs=1e-12)
    assert b.angular_velocity == pytest.approx(h * torque_b / b.moment, abs=1e-12)
    assert abs(torque_a) > 0.1 and abs(torque_b) > 0.1


@pytest.mark.parametrize(("m1", "m2", "k"), [(1.0, 1.0, 50.0), (1.0, 3.0, 30.0), (0.5, 4.0, 80.0)])
def test_two_bodies_on_a_spring_oscillate_with_the_reduced_mass(m1, m2, k):
    """Two free bodies on a spring (g = 0, stretched 0.5 m, released at rest): the stretch
    oscillates with period 2 pi sqrt(mu / k), mu = m1 m2 / (m1 + m2), within 1%."""
    world, _, _, spring = _spring_world(m1, m2, k)
    mu = m1 * m2 / (m1 + m2)
    period = 2 * math.pi * math.sqrt(mu / k)
    times, stretch = [], []
    while world.time < 4.5 * period:
        world.step(DT)
        times.append(world.time)
        stretch.append(float(spring.length) - 2.0)
    crossings = upward_crossings(np.array(times), np.array(stretch))
    assert crossings.size >= 3
    assert np.diff(crossings).mean() == pytest.approx(period, rel=0.01)


def test_spring_stability_measures_h2_k_w():
    """``spring_stability``: the measure is h^2 k w + 2 h c w with w = 1/m1 + 1/m2 for
    anchors at the centres (1e-12 relative); below 4 it reports no spring (-1) and writes
    0, from 4 up it names the spring's slot."""
    m1, m2, c = 1.0, 2.0, 3.0
    h = DT / 4
    w = 1 / m1 + 1 / m2
    for k, unstable in ((100.0, False), (4.0 / (h * h * w), True)):
        world, _, _, spring = _spring_world(m1, m2, k, c=c)
        state = world.state
        worst, measured, too_fast = integrate.spring_stability(
            state.body, state.body_i, state.spring, world.layout.springs, 0, terms_of(world), h
        )
        measure = h * h * k * w + 2 * h * c * w
        assert (worst == spring.slot) if unstable else (worst == -1)
        assert measured == (pytest.approx(measure, rel=1e-12) if unstable else 0.0)
        assert not too_fast


def test_unstable_spring_is_refused_and_the_world_does_not_step():
    """A spring of k = 1e7 N/m between 1 kg bodies at h = 1/240 s (h^2 k w = 347 >= 4):
    ``world.step`` raises ValueError naming stiffness, and the state is left bitwise as
    it was, the cached drag factors (DAMP_*) included."""
    world, _, _, _ = _spring_world(1.0, 1.0, 1e7)
    before = world.snapshot()
    with names("stiffness"):
        world.step(DT)
    for name, array in before.state.arrays().items():
        np.testing.assert_array_equal(getattr(world.state, name), array, err_msg=name)


# -- derived columns ------------------------------------------------------------------------------
def _check_rotation_columns(world: p2.World) -> int:
    """COS, SIN of every box equal cos, sin of its ANGLE bitwise, in every world; returns
    how many boxes were checked."""
    body, checked = world.state.body, 0
    for w in range(world.batch_size):
        for i in np.flatnonzero(world.layout.kind == BOX):
            assert body[w, i, COS] == math.cos(body[w, i, ANGLE]), (w, i)
            assert body[w, i, SIN] == math.sin(body[w, i, ANGLE]), (w, i)
            checked += 1
    return checked


def _tumbling_boxes() -> p2.World:
    world = p2.World()
    world.add(p2.Plane())
    for i in range(4):
        world.add(
            p2.Box(position=(1.1 * i, 0.6 + 0.3 * i), width=0.8, height=0.4, angle=0.4 * i,
                   angular_velocity=3.0 - 2.0 * i)
        )  # fmt: skip
    world.add(p2.Box(position=(-3, 1), kinematic=True, angular_velocity=1.5))
    return world


def test_rotation_columns_stay_current_while_stepping():
    """Boxes that spin, land, collide and settle, and a kinematic box turning: after every
    step, COS == cos(ANGLE) and SIN == sin(ANGLE) exactly for every box."""
    world = _tumbling_boxes()
    boxes = np.flatnonzero(world.layout.kind == BOX)
    start = world.state.body[0, boxes, ANGLE].copy()
    for _ in range(90):
        world.step(DT)
        assert _check_rotation_columns(world) == 5
    assert np.all(world.state.body[0, boxes, ANGLE] != start)  # they did turn


def test_rotation_columns_after_setting_angle_and_restoring():
    """COS, SIN equal cos, sin of the angle exactly after ``box.angle = ...`` (one value,
    and one per world of a batch), after ``restore`` of a snapshot into every world and into
    some worlds of a batch, and after stepping on from there."""
    world = _tumbling_boxes()
    boxes = [b for b in world.bodies if isinstance(b, p2.Box)]
    early = world.snapshot()
    for _ in range(20):
        world.step(DT)
    boxes[0].angle = 1.2345
    _check_rotation_columns(world)
    world.restore(early)
    _check_rotation_columns(world)
    batch = world.replicate(3)
    batch.bodies[2].angle = np.array([0.1, -2.0, 7.0])
    _check_rotation_columns(batch)
    for _ in range(10):
        batch.step(DT)
    batch.restore(early, worlds=[1])
    _check_rotation_columns(batch)
    batch.step(DT)
    assert _check_rotation_columns(batch) == 15
