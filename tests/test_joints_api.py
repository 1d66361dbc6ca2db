"""Joints as users meet them: refusals by name, anchors and readouts, removing and adding
again, the joint lists that keep joined bodies apart, batches equal to single worlds,
snapshots, and a refused step that leaves the joints as they were."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from impulse2d import envelope
from impulse2d.core.state import JOINT_LIST

DT = 1 / 60


def _pair(world: p2.World | None = None):
    world = world or p2.World()
    a = world.add(p2.Box(width=1.0, height=0.2, position=(0.0, 1.0)))
    b = world.add(p2.Box(width=1.0, height=0.2, position=(0.9, 1.0)))
    return world, a, b


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda a, b: p2.RevoluteJoint(a, a), "different bodies"),
        (lambda a, b: p2.RevoluteJoint(a, "b"), "body2 must be a body"),
        (lambda a, b: p2.RevoluteJoint(a, b, lower_angle=1.0, upper_angle=0.0), "lower_angle"),
        (lambda a, b: p2.RevoluteJoint(a, b, lower_angle=0.0), "must be given together"),
        (lambda a, b: p2.RevoluteJoint(a, b, max_motor_torque=-1.0), "max_motor_torque must"),
        (lambda a, b: p2.RevoluteJoint(a, b, anchor=(math.nan, 0.0)), "anchor must be finite"),
        (lambda a, b: p2.RevoluteJoint(a, b, break_force=0.0), "break_force must be"),
        (lambda a, b: p2.RevoluteJoint(a, b, collide_connected=1), "collide_connected"),
        (lambda a, b: p2.PrismaticJoint(a, b, axis=(0.0, 0.0)), "axis must be a non-zero"),
        (lambda a, b: p2.DistanceJoint(a, b, min_length=2.0, max_length=1.0), "min_length"),
        (lambda a, b: p2.WeldJoint(a, b, hertz=-1.0), "hertz must be >= 0"),
        (lambda a, b: p2.MouseJoint(a, target=(0.0, 0.0), max_force=0.0), "max_force must"),
    ],
)
def test_bad_joints_are_refused_by_name(make, message):
    _, a, b = _pair()
    with pytest.raises(ValueError, match=message):
        make(a, b)


def test_a_joint_needs_both_bodies_in_its_world():
    world, a, _ = _pair()
    elsewhere = p2.World().add(p2.Circle())
    with pytest.raises(ValueError, match="body2 of the joint must be in this world"):
        world.add(p2.RevoluteJoint(a, elsewhere))
    assert world.joints == []


def test_a_body_with_a_joint_cannot_be_removed_until_the_joint_is():
    world, a, b = _pair()
    joint = world.add(p2.RevoluteJoint(a, b, anchor=(0.45, 1.0)))
    with pytest.raises(ValueError, match="spring\\(s\\) or joint\\(s\\)"):
        world.remove(a)
    world.remove(joint)
    world.remove(a)
    assert world.joints == [] and a.world is None


def test_a_bad_setting_is_refused_and_changes_nothing():
    world, a, b = _pair()
    joint = world.add(p2.RevoluteJoint(a, b, lower_angle=-0.5, upper_angle=0.5))
    before = world.state.copy()
    for name, value in (("lower_angle", 0.8), ("motor_speed", math.inf), ("spring_hertz", -2.0)):
        with pytest.raises(ValueError, match=name):
            setattr(joint, name, value)
    for array_name, array in before.arrays().items():
        assert array.tobytes() == getattr(world.state, array_name).tobytes(), array_name


def test_a_removed_joint_comes_back_with_its_settings():
    world, a, b = _pair()
    joint = p2.RevoluteJoint(
        a, b, anchor=(0.45, 1.0), motor_speed=2.0, max_motor_torque=3.0, lower_angle=-1.0,
        upper_angle=1.0,
    )  # fmt: skip
    world.add(joint)
    world.step(DT, 5)
    world.remove(joint)
    assert joint.world is None and joint.motor_speed == 2.0 and joint.lower_angle == -1.0
    world.add(joint)
    assert joint.max_motor_torque == 3.0 and joint.upper_angle == 1.0 and joint.limited


def test_joint_lists_stay_right_as_joints_come_and_go():
    """Three joints at one body, the middle one removed: the other two still keep their
    pairs from colliding, the freed pair collides again, and every body's list (walked
    from ``JOINT_LIST``) holds exactly the joints that keep bodies apart."""
    world = p2.World(gravity=(0.0, 0.0))
    hub = world.add(p2.Box(width=1.0, height=1.0))
    spokes = [
        world.add(p2.Box(width=0.6, height=0.3, position=p))
        for p in ((0.6, 0), (-0.6, 0), (0, 0.6))
    ]
    joints = [world.add(p2.WeldJoint(hub, spoke)) for spoke in spokes]
    world.remove(joints[1])
    world.step(DT)
    contacts = world.contacts()
    pairs = {
        frozenset(p) for p in zip(contacts.slot_a.tolist(), contacts.slot_b.tolist(), strict=True)
    }
    assert frozenset((hub.slot, spokes[1].slot)) in pairs
    assert frozenset((hub.slot, spokes[0].slot)) not in pairs
    assert frozenset((hub.slot, spokes[2].slot)) not in pairs
    state, ends = world.state, world.layout.springs
    for body in (hub, *spokes):
        walked, k = [], int(state.body_i[0, body.slot, JOINT_LIST])
        while k >= 0:
            walked.append(k)
            column = 31 if ends[k, 0] == body.slot else 32  # NEXT_AT_A, NEXT_AT_B
            k = int(state.spring[0, k, column])
        expected = [j.slot for j in (joints[0], joints[2]) if body in (j.body1, j.body2)]
        assert sorted(walked) == sorted(expected)


def _scene(batch_size: int = 1) -> p2.World:
    world = p2.World(batch_size=batch_size, substeps=4)
    world.add(p2.Plane())
    hook = world.add(p2.Circle(radius=0.05, position=(0.0, 3.0), fixed=True))
    previous = hook
    for k in range(4):
        link = world.add(p2.Capsule(length=0.5, radius=0.08, position=(0.3 + 0.6 * k, 3.0)))
        world.add(p2.RevoluteJoint(previous, link, anchor=(0.6 * k, 3.0)))
        previous = link
    box = world.add(p2.Box(width=0.5, height=0.5, position=(-1.0, 0.25)))
    world.add(p2.PrismaticJoint(hook, box, axis=(1.0, 0.0), motor_speed=-1.0, max_motor_force=5.0))
    world.add(p2.MouseJoint(previous, target=(2.0, 1.0)))
    return world


def test_a_batch_steps_each_world_as_the_single_world_and_snapshots_replay():
    single, batch = _scene(), _scene().replicate(3)
    assert len(batch.joints) == 6 and batch.joints[0].body1 is batch.bodies[1]
    for _ in range(60):
        single.step(DT)
        batch.step(DT)
    for name in ("body", "body_i", "spring"):
        for w in range(3):
            assert (
                getattr(single.state, name)[0].tobytes() == getattr(batch.state, name)[w].tobytes()
            )
    snap = single.snapshot()
    single.step(DT, 30)
    after = single.state.copy()
    single.restore(snap)
    single.step(DT, 30)
    for name, array in after.arrays().items():
        assert array.tobytes() == getattr(single.state, name).tobytes(), name


def test_a_refused_step_leaves_the_joints_as_they_were():
    """A world of joints in motion where one body is pushed past the envelope's speed
    within a step: the step is refused and every array, the joints' impulses and forces
    included, is bitwise as before it."""
    world = _scene()
    world.step(DT, 20)
    ball = world.add(
        p2.Circle(radius=0.1, position=(5.0, 5.0), velocity=(0.999 * envelope.SPEED, 0.0))
    )
    ball.apply_force((1e5 * ball.mass, 0.0))
    before = world.state.copy()
    with pytest.raises(p2.EnvelopeError):
        world.step(DT)
    for name, array in before.arrays().items():
        assert np.array_equal(array, getattr(world.state, name), equal_nan=True), name


def test_readouts_before_and_after_adding():
    world, a, b = _pair(p2.World(gravity=(0.0, 0.0)))
    joint = p2.RevoluteJoint(a, b, anchor=(0.45, 1.0))
    assert joint.enabled is True and np.all(joint.force == 0.0) and joint.angle == 0.0
    world.add(joint)
    b.angular_velocity = 1.0
    world.step(DT, 10)
    assert joint.angle == pytest.approx(float(b.angle) - float(a.angle))
    joint.enabled = False
    assert joint.enabled is False
    with pytest.raises(ValueError, match="enabled must be a bool"):
        joint.enabled = 1
