"""Validation contract, structure: adding, removing and connecting objects, flags and world
settings raise ValueError (naming the parameter where there is one) at the call that made
the mistake, and leave everything the user set up as it was.

Also a spring too stiff for the substep, which raises at the step instead of giving NaN.
Bad numbers and shapes, and rejected setters: ``test_validation_values.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

import impulse2d as p2
from conftest import names, two_circles


# -- structure: adding, removing, springs ----------------------------------------------------------
@pytest.mark.parametrize("make", [lambda: p2.Circle(), lambda: p2.Box(), lambda: p2.Plane()])
def test_adding_an_object_twice_rejected(make):
    """Adding an object already in this world or in another world raises ValueError."""
    world, other = p2.World(), p2.World()
    obj = world.add(make())
    with pytest.raises(ValueError, match="already"):
        world.add(obj)
    with pytest.raises(ValueError, match="already"):
        other.add(obj)
    assert world.bodies == [obj] and other.bodies == []
    assert obj.world is world


def test_adding_a_spring_twice_rejected():
    """Adding a spring already in a world, to it or to another world, raises ValueError."""
    world, a, b = two_circles()
    s = world.add(p2.Spring(a, b))
    with pytest.raises(ValueError, match="already"):
        world.add(s)
    with pytest.raises(ValueError):
        p2.World().add(s)
    assert world.springs == [s]


def test_spring_from_a_body_to_itself_rejected():
    """A spring whose two bodies are the same raises ValueError naming the bodies."""
    _, a, _ = two_circles()
    with pytest.raises(ValueError, match=r"body1|body2"):
        p2.Spring(a, a)
    with pytest.raises(ValueError):
        p2.Spring(a, a, rest_length=1.0, stiffness=2.0)


def test_spring_between_distinct_detached_bodies_is_constructible():
    """Two different bodies make a valid spring even before they are added."""
    s = p2.Spring(p2.Box(), p2.Circle(), stiffness=2.0)
    assert s.world is None and s.stiffness == 2.0


@pytest.mark.parametrize("missing", ["body1", "body2"])
def test_spring_whose_body_is_not_in_the_world_rejected(missing):
    """Adding a spring whose body is not in the world raises naming that body; adds nothing."""
    world, a, _ = two_circles()
    stranger = p2.Circle(position=(5.0, 0.0))
    bodies = (stranger, a) if missing == "body1" else (a, stranger)
    spring = p2.Spring(*bodies)
    with names(missing):
        world.add(spring)
    assert world.springs == [] and spring.world is None
    elsewhere = p2.World().add(p2.Circle())
    with pytest.raises(ValueError):
        world.add(p2.Spring(a, elsewhere))
    assert world.springs == []


def test_removing_what_is_not_in_the_world_rejected():
    """remove of an object that is not in this world raises ValueError."""
    world, a, _ = two_circles()
    with pytest.raises(ValueError):
        world.remove(p2.Circle())
    with pytest.raises(ValueError):
        p2.World().remove(a)
    world.remove(a)
    with pytest.raises(ValueError):
        world.remove(a)


def test_add_rejects_non_objects():
    """add of something that is not a Circle, Box, Plane or Spring raises."""
    world = p2.World()
    with pytest.raises((TypeError, ValueError)):
        world.add((0.0, 0.0))
    assert world.bodies == []


# -- flags and settings ----------------------------------------------------------------------------
@pytest.mark.parametrize("cls", [p2.Circle, p2.Box])
def test_fixed_and_kinematic_together_rejected(cls):
    """fixed=True with kinematic=True raises ValueError naming both."""
    with pytest.raises(ValueError, match=r"(?s)(fixed.*kinematic|kinematic.*fixed)"):
        cls(fixed=True, kinematic=True)


@pytest.mark.parametrize("batch_size", [0, -1])
def test_batch_size_below_one_rejected(batch_size):
    """batch_size below 1, in World or replicate, raises ValueError naming batch_size."""
    with names("batch_size"):
        p2.World(batch_size=batch_size)
    with names("batch_size"):
        p2.World().replicate(batch_size)


@pytest.mark.parametrize("name", ["restitution_mixing", "friction_mixing"])
@pytest.mark.parametrize("rule", ["average", "MAX", "", None])
def test_unknown_mixing_rule_rejected(name, rule):
    """An unknown mixing rule raises ValueError naming the parameter."""
    with names(name):
        p2.World(**{name: rule})


def test_every_documented_mixing_rule_accepted():
    """Each documented rule (max, min, mean, product, sqrt) is accepted for both mixings."""
    for rule in ("max", "min", "mean", "product", "sqrt"):
        world = p2.World(restitution_mixing=rule, friction_mixing=rule)
        assert world.restitution_mixing == rule and world.friction_mixing == rule


def test_restore_of_mismatched_snapshot_rejected():
    """Restoring a snapshot of another scene, or into bad world indices, raises ValueError."""
    world, _, _ = two_circles()
    other = p2.World()
    other.add(p2.Circle())
    with pytest.raises(ValueError):
        other.restore(world.snapshot())
    with pytest.raises(ValueError):
        world.restore(object())
    batch = world.replicate(3)
    with names("worlds"):
        batch.restore(world.snapshot(), worlds=[3])
    with names("worlds"):
        batch.restore(world.snapshot(), worlds=[-1])


# -- stiff springs ---------------------------------------------------------------------------------
def test_too_stiff_spring_raises_at_step_instead_of_nan():
    """A spring too stiff for the substep raises at step time; nothing integrates; recoverable."""
    world, a, b = two_circles(gravity=(0.0, -9.81))
    s = world.add(p2.Spring(a, b, rest_length=1.0, stiffness=1e9))
    with pytest.raises(ValueError, match="stiffness"):
        world.step(1.0 / 60.0)
    assert world.steps == 0 and world.time == 0.0
    np.testing.assert_array_equal(a.position, [0.0, 0.0])
    np.testing.assert_array_equal(b.position, [3.0, 0.0])
    np.testing.assert_array_equal(a.velocity, [0.0, 0.0])
    s.stiffness = 10.0
    for _ in range(10):
        world.step(1.0 / 60.0)
    assert np.all(np.isfinite(a.position)) and np.all(np.isfinite(b.position))
    assert a.position[0] > 0.0


def test_spring_made_too_stiff_later_raises_at_step():
    """Raising a spring's stiffness past the stable limit makes the next step raise, not NaN."""
    world, a, b = two_circles(gravity=(0.0, 0.0))
    s = world.add(p2.Spring(a, b, rest_length=1.0, stiffness=10.0))
    world.step(1.0 / 60.0)
    s.stiffness = 1e9
    positions = (a.position, b.position)
    with pytest.raises(ValueError, match="stiffness"):
        world.step(1.0 / 60.0)
    np.testing.assert_array_equal(a.position, positions[0])
    np.testing.assert_array_equal(b.position, positions[1])
