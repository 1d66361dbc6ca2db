"""Validation contract over the whole public surface (``inputs_catalog.ENTRIES``).

Every constructor keyword, settable attribute and method argument refuses every wrong
value of its kind (NaN and inf, strings, None, complex numbers, bools where a number is
meant, wrong shapes, other objects) with a ``ValueError`` that names the parameter, and a
refused assignment leaves the world bitwise as it was. An extreme but finite number is
either refused the same way (outside ``impulse2d.envelope``) or accepted and then stepped
without a single non-finite number.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import impulse2d as p2
import inputs_catalog as cat


def refuses(entry: cat.Entry, value) -> str | None:
    """None if ``entry.give(value)`` raises a ValueError naming the parameter, else what
    happened instead."""
    try:
        entry.give(value)
    except ValueError as error:
        if re.search(rf"(?<![\w]){re.escape(entry.name)}(?![\w])", str(error)):
            return None
        return f"ValueError not naming {entry.name!r}: {error}"
    except Exception as error:
        return f"{type(error).__name__} instead of ValueError: {error}"
    return "accepted"


@pytest.mark.parametrize("entry", cat.ENTRIES, ids=lambda e: e.label)
def test_every_wrong_value_is_refused_naming_the_parameter(entry):
    failures = [
        f"{kind} {value!r}: {outcome}"
        for kind, values in cat.BAD[entry.shape].items()
        for value in values
        if not (value is None and entry.none_is_legal)
        and not (entry.inf_is_legal and isinstance(value, float) and value == np.inf)
        and (outcome := refuses(entry, value)) is not None
    ]
    assert not failures, f"{entry.label}:\n" + "\n".join(failures)


@pytest.mark.parametrize(
    "entry", [e for e in cat.ENTRIES if cat.extreme_values(e)], ids=lambda e: e.label
)
def test_an_extreme_number_is_refused_or_stays_finite(entry):
    failures = []
    for value in cat.extreme_values(entry):
        try:
            world = entry.give(value)
        except ValueError as error:
            if entry.name not in str(error):
                failures.append(f"{value!r}: ValueError not naming it: {error}")
            continue
        except Exception as error:
            failures.append(f"{value!r}: {type(error).__name__}: {error}")
            continue
        try:
            if isinstance(world, p2.World) and not cat.finite_after_steps(world):
                failures.append(f"{value!r}: accepted, then a non-finite number within 30 steps")
        except ValueError as error:
            # A spring's stability depends on the substep, so a spring too stiff for it
            # is refused by the step, naming stiffness and damping, before it moves.
            if entry.name not in str(error):
                failures.append(f"{value!r}: the step raised, not naming it: {error}")
    assert not failures, f"{entry.label}:\n" + "\n".join(failures)


SETTERS = [
    (p, n)
    for p, n in [
        ("world", "contact_hertz"),
        ("world", "gravity"),
        ("circle", "radius"),
        ("circle", "velocity"),
        ("box", "mass"),
        ("plane", "point"),
        ("spring", "stiffness"),
        ("spring", "anchor1"),
        ("sensor", "radius"),
    ]
]


@pytest.mark.parametrize(("part", "name"), SETTERS)
def test_a_refused_assignment_changes_nothing(part, name):
    """A refused value leaves the state bitwise as it was, and stepping still works."""
    world, parts = cat.scene()
    target = world if part == "world" else parts[part]
    before, kept = cat.state_bytes(world), np.array(getattr(target, name))
    for value in (np.nan, "x", np.complex128(1.0), True, [1.0, 2.0, 3.0]):
        with pytest.raises(ValueError, match=name):
            setattr(target, name, value)
    assert cat.state_bytes(world) == before
    np.testing.assert_array_equal(getattr(target, name), kept)
    assert cat.finite_after_steps(world)


@pytest.mark.parametrize(
    ("name", "value"),
    [("radius", np.ones(2)), ("velocity", np.ones((4, 2))), ("mass", np.ones((3, 1)))],
)
def test_a_per_world_value_of_the_wrong_shape_names_the_shapes_it_takes(name, value):
    """In a batch of 3, a per-world value must have shape () / (2,) or (3,) / (3, 2); the
    message gives both."""
    _, parts = cat.scene(batch_size=3)
    tail = "(2,)" if name == "velocity" else "()"
    batched = "(3, 2)" if name == "velocity" else "(3,)"
    with pytest.raises(ValueError, match=re.escape(tail) + ".*" + re.escape(batched)):
        setattr(parts["circle"], name, value)


def settable(cls: type) -> list[str]:
    """The public attributes of ``cls`` that can be assigned: properties with a setter
    and data descriptors (the body fields)."""
    names = []
    for name, attr in vars_of(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(attr, property):
            if attr.fset is not None:
                names.append(name)
        elif hasattr(type(attr), "__set__"):
            names.append(name)
    return names


def vars_of(cls: type) -> dict:
    merged: dict = {}
    for klass in reversed(cls.__mro__):
        merged.update(vars(klass))
    return merged


def test_the_catalog_covers_every_settable_attribute():
    """Each settable attribute of the public classes is in the catalog: a new one cannot
    slip past these tests."""
    covered = {(e.owner, e.name) for e in cat.ENTRIES}
    owners = {
        p2.World: "world",
        p2.Circle: "circle",
        p2.Box: "box",
        p2.Plane: "plane",
        p2.Spring: "spring",
        p2.Sensor: "sensor",
    }
    missing = [
        f"{owner}.{name}"
        for cls, owner in owners.items()
        for name in settable(cls)
        if (owner, name) not in covered
    ]
    assert not missing, missing
    assert len(covered) > 130
