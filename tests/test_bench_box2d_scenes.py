"""``bench/box2d_scenes.py`` builds Box2D's benchmark scenes in impulse2d as the scenes
say: checked at small sizes on what each scene is about (no timing here)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "bench"))
import box2d_scenes as b2s


def test_the_joint_grid_hangs_from_its_fixed_discs_with_its_joints_holding():
    world, _ = b2s.joint_grid_impulse2d(8)
    assert len(world.joints) == 2 * 8 * 7
    world.step(b2s.DT, 60)
    assert np.isfinite(world.state.body[..., :6]).all()
    worst = max(float(np.hypot(*_gap(j))) for j in world.joints)
    assert worst < 0.02


def _gap(joint) -> np.ndarray:
    row = joint.world.state.spring[0, joint.slot]
    return np.asarray(joint.body2.to_world(row[2:4])) - np.asarray(joint.body1.to_world(row[0:2]))


def test_the_tumbler_turns_its_walls_rigidly_at_25_degrees_a_second():
    world, turn = b2s.tumbler_impulse2d(4)
    walls = [b for b in world.bodies if b.kinematic]
    for _ in range(120):
        world.step(b2s.DT)
        turn(world)
    angle = math.radians(25.0) * 2.0
    for wall in walls:
        assert float(np.hypot(*(np.asarray(wall.position) - (0.0, 10.0)))) == pytest.approx(
            10.0, abs=1e-6
        )
        assert float(wall.angle) == pytest.approx(angle, abs=1e-6)


def test_the_spinner_paddle_turns_at_its_motor_speed_and_the_ring_holds_the_bodies():
    """The motor (unlimited torque) turns the paddle at 5 rad/s through the bodies, and the
    ring of segments keeps nine in ten inside (a body caught between the paddle's tip,
    which nothing stops, and the ring is squeezed through it)."""
    world, _ = b2s.spinner_impulse2d(60)
    world.step(b2s.DT, 90)
    paddle = next(b for b in world.bodies if getattr(b, "radius", 0.0) == 0.2 and not b.fixed)
    assert float(paddle.angular_velocity) == pytest.approx(5.0, rel=0.05)
    inside = [np.hypot(b.position[0], b.position[1] - 32.0) for b in world.bodies if not b.fixed]
    assert np.mean(np.array(inside) < 40.0) > 0.9
    assert np.isfinite(world.state.body[..., :6]).all()


def test_smash_starts_asleep_and_the_heavy_box_wakes_what_it_strikes():
    world, _ = b2s.smash_impulse2d(6, 4)
    small = [b for b in world.bodies if float(b.mass) < 1.0]
    assert not any(b.awake for b in small)
    world.step(b2s.DT, 90)
    assert any(float(np.hypot(*b.velocity)) > 1.0 for b in small)


def test_many_pyramids_stand_on_their_segments():
    world, _ = b2s.many_pyramids_impulse2d(2)
    boxes = [b for b in world.bodies if not b.fixed]
    assert len(boxes) == 4 * 55
    start = np.array([b.position for b in boxes])
    world.step(b2s.DT, 60)
    moved = np.abs(np.array([b.position for b in boxes]) - start).max()
    assert moved < 0.05
