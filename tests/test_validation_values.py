"""Validation contract, values: a bad number or array shape raises ValueError naming the
parameter, at the call that made it, and a rejected call leaves everything as it was.

Sizes, masses and materials; NaN and inf anywhere a number goes; vectors and per-world
arrays of the wrong shape; and that a rejected setter keeps the previous value. Adding,
removing, springs, flags, settings and stiff springs: ``test_validation_structure.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import impulse2d as p2
from conftest import names, two_circles

NAN, INF = math.nan, math.inf
NON_FINITE = [NAN, INF, -INF]


# -- helpers ---------------------------------------------------------------------------------------
def body_values(body) -> dict:
    keys = [
        "position",
        "velocity",
        "angle",
        "angular_velocity",
        "mass",
        "moment",
        "restitution",
        "friction",
        "linear_drag",
        "angular_drag",
        "awake",
        "enabled",
    ]
    keys += ["radius"] if isinstance(body, p2.Circle) else ["width", "height"]
    return {k: np.array(getattr(body, k)) for k in keys}


def assert_same(before: dict, after: dict) -> None:
    for key, value in before.items():
        np.testing.assert_array_equal(after[key], value, err_msg=key)


# -- sizes, masses, materials ----------------------------------------------------------------------
@pytest.mark.parametrize("value", [0.0, -0.5, -INF])
@pytest.mark.parametrize(
    ("cls", "name"), [(p2.Circle, "radius"), (p2.Box, "width"), (p2.Box, "height")]
)
def test_non_positive_size_rejected(cls, name, value):
    """Zero or negative radius, width and height raise ValueError naming the parameter."""
    with names(name):
        cls(**{name: value})


@pytest.mark.parametrize("cls", [p2.Circle, p2.Box])
@pytest.mark.parametrize("mass", [0.0, -1.0])
def test_non_positive_mass_of_dynamic_body_rejected(cls, mass):
    """A dynamic body with zero or negative mass raises ValueError naming mass."""
    with names("mass"):
        cls(mass=mass)
    with names("mass"):
        cls(mass=mass, kinematic=False, fixed=False)


@pytest.mark.parametrize(
    ("cls", "name"),
    [
        (p2.Circle, "restitution"),
        (p2.Circle, "friction"),
        (p2.Circle, "linear_drag"),
        (p2.Circle, "angular_drag"),
        (p2.Box, "restitution"),
        (p2.Box, "friction"),
        (p2.Box, "linear_drag"),
        (p2.Box, "angular_drag"),
        (p2.Plane, "restitution"),
        (p2.Plane, "friction"),
    ],
)
def test_negative_material_rejected(cls, name):
    """Negative restitution, friction and drag raise ValueError naming the parameter."""
    with names(name):
        cls(**{name: -0.1})


def test_zero_plane_normal_rejected():
    """A zero plane normal raises ValueError naming normal."""
    with names("normal"):
        p2.Plane(normal=(0.0, 0.0))


@settings(max_examples=60, deadline=None)
@given(
    kind=st.sampled_from(["Circle.radius", "Box.width", "Box.height", "Circle.mass", "Box.mass"]),
    value=st.one_of(
        st.floats(max_value=0.0, allow_nan=False),
        st.sampled_from([NAN, INF, -INF]),
    ),
)
def test_random_bad_size_or_mass_rejected(kind, value):
    """Any non-positive or non-finite size or dynamic mass is refused, with the name."""
    cls_name, name = kind.split(".")
    with names(name):
        getattr(p2, cls_name)(**{name: value})


# -- non-finite numbers ----------------------------------------------------------------------------
VECTOR_KEYWORDS = [
    (p2.Circle, "position"),
    (p2.Circle, "velocity"),
    (p2.Box, "position"),
    (p2.Box, "velocity"),
    (p2.Plane, "point"),
    (p2.Plane, "normal"),
]
SCALAR_KEYWORDS = [
    (cls, name)
    for cls in (p2.Circle, p2.Box)
    for name in (
        "angle",
        "angular_velocity",
        "mass",
        "restitution",
        "friction",
        "linear_drag",
        "angular_drag",
    )
] + [
    (p2.Circle, "radius"),
    (p2.Box, "width"),
    (p2.Box, "height"),
    (p2.Plane, "restitution"),
    (p2.Plane, "friction"),
]


@pytest.mark.parametrize("bad", NON_FINITE)
@pytest.mark.parametrize(("cls", "name"), VECTOR_KEYWORDS)
def test_non_finite_vector_keyword_rejected(cls, name, bad):
    """NaN or inf in any vector keyword raises ValueError naming it."""
    with names(name):
        cls(**{name: (1.0, bad)})


@pytest.mark.parametrize("bad", NON_FINITE)
@pytest.mark.parametrize(("cls", "name"), SCALAR_KEYWORDS)
def test_non_finite_scalar_keyword_rejected(cls, name, bad):
    """NaN or inf in any scalar keyword raises ValueError naming it."""
    with names(name):
        cls(**{name: bad})


@settings(max_examples=60, deadline=None)
@given(
    field=st.sampled_from(
        [
            "position",
            "velocity",
            "angle",
            "angular_velocity",
            "radius",
            "mass",
            "restitution",
            "friction",
            "linear_drag",
            "angular_drag",
        ]
    ),
    bad=st.sampled_from(NON_FINITE),
    index=st.integers(0, 1),
)
def test_random_non_finite_setter_rejected_and_value_kept(field, bad, index):
    """Setting a body field to NaN/inf raises naming the field and changes nothing."""
    world = p2.World()
    c = world.add(p2.Circle(position=(1.0, 2.0), velocity=(0.5, 0.0), radius=0.4, mass=2.0))
    before = body_values(c)
    current = np.array(getattr(c, field), dtype=float)
    value = current.copy()
    value.flat[index % value.size] = bad
    with names(field):
        setattr(c, field, value)
    assert_same(before, body_values(c))


WORLD_FLOATS = [
    "restitution_threshold",
    "contact_hertz",
    "contact_damping_ratio",
    "contact_push_speed",
    "speculative_distance",
    "time_to_sleep",
    "sleep_speed",
]


@pytest.mark.parametrize("bad", NON_FINITE)
@pytest.mark.parametrize("name", WORLD_FLOATS)
def test_non_finite_world_setting_rejected(name, bad):
    """NaN or inf in any World setting raises ValueError naming it."""
    with names(name):
        p2.World(**{name: bad})


@pytest.mark.parametrize("bad", NON_FINITE)
def test_non_finite_gravity_rejected(bad):
    """NaN or inf gravity, in the constructor or the setter, raises and keeps the old gravity."""
    with names("gravity"):
        p2.World(gravity=(0.0, bad))
    world = p2.World(gravity=(0.0, -1.0))
    with names("gravity"):
        world.gravity = (bad, 0.0)
    np.testing.assert_array_equal(world.gravity, [0.0, -1.0])


@pytest.mark.parametrize("dt", [0.0, -0.01, -INF, NAN, INF])
def test_bad_dt_rejected(dt):
    """A zero, negative or non-finite dt raises ValueError naming dt, and nothing is stepped."""
    world, a, _ = two_circles()
    with names("dt"):
        world.step(dt)
    assert world.steps == 0 and world.time == 0.0
    np.testing.assert_array_equal(a.position, [0.0, 0.0])


@pytest.mark.parametrize("bad", NON_FINITE)
@pytest.mark.parametrize("method", ["apply_force", "apply_impulse"])
def test_non_finite_force_impulse_or_point_rejected(method, bad):
    """NaN or inf in a force, impulse or its point raises naming it and applies nothing."""
    world, a, _ = two_circles(gravity=(0.0, 0.0))
    vector = "force" if method == "apply_force" else "impulse"
    with names(vector):
        getattr(a, method)((1.0, bad))
    with names("point"):
        getattr(a, method)((1.0, 0.0), point=(bad, 0.0))
    world.step(1.0 / 60.0)
    np.testing.assert_array_equal(a.velocity, [0.0, 0.0])
    assert a.angular_velocity == 0.0


@pytest.mark.parametrize("bad", NON_FINITE)
def test_non_finite_query_points_rejected(bad):
    """NaN/inf points to query_point, Plane.is_inside, to_world, to_local raise naming them."""
    world = p2.World()
    c = world.add(p2.Circle())
    g = world.add(p2.Plane())
    with names("point"):
        world.query_point((bad, 0.0))
    with names("point"):
        g.is_inside((bad, 0.0))
    with names("local_point"):
        c.to_world((0.0, bad))
    with names("world_point"):
        c.to_local((0.0, bad))


@pytest.mark.parametrize("cls", [p2.Circle, p2.Box])
def test_non_finite_is_inside_point_rejected_naming_point(cls):
    """body.is_inside(point) with NaN or inf raises ValueError naming its parameter, point."""
    body = p2.World().add(cls())
    for bad in NON_FINITE:
        with names("point"):
            body.is_inside((bad, 0.0))


@pytest.mark.parametrize("bad", NON_FINITE)
@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("rest_length", None),
        ("stiffness", None),
        ("damping", None),
        ("anchor1", "vector"),
        ("anchor2", "vector"),
    ],
)
def test_non_finite_spring_parameter_rejected(name, value, bad):
    """NaN/inf spring parameters raise naming them, in constructor and setter; value is kept."""
    world, a, b = two_circles()
    given_value = (0.0, bad) if value == "vector" else bad
    with names(name):
        p2.Spring(a, b, **{name: given_value})
    s = world.add(
        p2.Spring(
            a,
            b,
            rest_length=2.0,
            stiffness=3.0,
            damping=0.1,
            anchor1=(0.1, 0.0),
            anchor2=(0.0, 0.1),
        )
    )
    before = np.array(getattr(s, name))
    with names(name):
        setattr(s, name, given_value)
    np.testing.assert_array_equal(getattr(s, name), before)


@pytest.mark.parametrize("name", ["rest_length", "stiffness", "damping"])
def test_negative_spring_parameter_rejected(name):
    """A negative spring rest_length, stiffness or damping raises naming it."""
    _, a, b = two_circles()
    with names(name):
        p2.Spring(a, b, **{name: -1.0})


# -- shapes ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["position", "velocity"])
@pytest.mark.parametrize("value", [(0.0, 0.0, 0.0), (1.0,), ()])
def test_wrong_vector_shape_in_constructor_rejected(name, value):
    """A position or velocity that is not a 2-vector raises ValueError naming it."""
    with names(name):
        p2.Circle(**{name: value})


def test_wrong_shapes_elsewhere_rejected():
    """Wrong shapes for gravity, points, forces, impulses, anchors, setters raise naming them."""
    with names("gravity"):
        p2.World(gravity=(0.0, -9.81, 0.0))
    with names("point"):
        p2.Plane(point=(0.0, 0.0, 0.0))
    with names("normal"):
        p2.Plane(normal=(0.0, 1.0, 0.0))
    world, a, b = two_circles()
    with names("anchor1"):
        p2.Spring(a, b, anchor1=(0.0, 0.0, 0.0))
    with names("force"):
        a.apply_force((1.0, 0.0, 0.0))
    with names("impulse"):
        a.apply_impulse((1.0,))
    with names("point"):
        a.apply_force((1.0, 0.0), point=(0.0, 0.0, 0.0))
    with names("point"):
        world.query_point((0.0, 0.0, 0.0))
    before = body_values(a)
    with names("position"):
        a.position = (0.0, 0.0, 0.0)
    with names("velocity"):
        a.velocity = [[1.0, 2.0], [3.0, 4.0]]
    with names("angle"):
        a.angle = [0.1, 0.2]
    assert_same(before, body_values(a))


def test_wrong_batch_shapes_rejected():
    """In a batch, a setter given the wrong number of worlds raises and changes nothing."""
    world = p2.World(batch_size=4)
    c = world.add(p2.Circle())
    before = body_values(c)
    with names("position"):
        c.position = np.zeros((3, 2))
    with names("radius"):
        c.radius = [0.1, 0.2, 0.3]
    with names("enabled"):
        c.enabled = np.array([True, False])
    with names("enabled"):
        c.enabled = np.array([1, 0, 1, 0])
    with names("impulse"):
        c.apply_impulse(np.zeros((2, 2)))
    assert_same(before, body_values(c))


def test_add_of_body_with_wrong_number_of_worlds_rejected():
    """Adding a body with values for another batch size raises naming the field; no change."""
    body = p2.Circle(angle=[0.1, 0.2])  # values for a batch of 2
    world = p2.World(batch_size=3)
    keep = world.add(p2.Circle(position=(5.0, 0.0)))
    with names("angle"):
        world.add(body)
    assert world.bodies == [keep] and body.world is None
    np.testing.assert_array_equal(body.angle, [0.1, 0.2])
    assert p2.World(batch_size=2).add(body) is body


# -- a rejected call loses nothing -----------------------------------------------------------------
@pytest.mark.parametrize(
    ("field", "bad"),
    [
        ("radius", 0.0),
        ("radius", -1.0),
        ("mass", 0.0),
        ("mass", -2.0),
        ("restitution", -0.5),
        ("friction", -0.5),
        ("linear_drag", -1.0),
        ("angular_drag", -1.0),
        ("position", (NAN, 0.0)),
        ("velocity", (0.0, INF)),
        ("angle", NAN),
        ("angular_velocity", -INF),
    ],
)
def test_rejected_setter_keeps_previous_value(field, bad):
    """After a rejected setter call every property of the body is what it was before."""
    world = p2.World()
    c = world.add(
        p2.Circle(
            position=(1.0, 2.0),
            velocity=(0.3, 0.0),
            radius=0.4,
            mass=2.0,
            restitution=0.5,
            friction=0.2,
            angle=0.1,
            angular_velocity=1.0,
        )
    )
    world.step(1.0 / 60.0)
    before = body_values(c)
    with names(field):
        setattr(c, field, bad)
    assert_same(before, body_values(c))
    detached = p2.Circle(position=(1.0, 2.0), radius=0.4, mass=2.0)
    detached_before = {k: np.array(getattr(detached, k)) for k in ("position", "radius", "mass")}
    with names(field):
        setattr(detached, field, bad)
    for key, value in detached_before.items():
        np.testing.assert_array_equal(getattr(detached, key), value, err_msg=key)


@pytest.mark.parametrize(("field", "bad"), [("width", 0.0), ("height", -1.0), ("mass", 0.0)])
def test_rejected_box_setter_keeps_previous_value(field, bad):
    """A rejected box size or mass leaves the box's size, mass and moment as they were."""
    world = p2.World()
    b = world.add(p2.Box(width=2.0, height=1.0, mass=3.0))
    before = body_values(b)
    with names(field):
        setattr(b, field, bad)
    assert_same(before, body_values(b))


def test_partly_bad_batch_setter_changes_no_world():
    """A per-world setter with one bad entry raises and leaves every world's value as it was."""
    world = p2.World(batch_size=4)
    c = world.add(p2.Circle(radius=0.5, mass=1.0))
    before = body_values(c)
    with names("radius"):
        c.radius = [0.5, 0.6, -0.1, 0.7]
    with names("mass"):
        c.mass = [1.0, 0.0, 2.0, 3.0]
    with names("position"):
        c.position = [[0.0, 0.0], [1.0, 1.0], [NAN, 0.0], [2.0, 2.0]]
    assert_same(before, body_values(c))


def test_fixed_body_velocity_setter_rejected_and_kept():
    """Giving a fixed body a velocity raises (it never moves) and leaves it at rest."""
    world = p2.World()
    post = world.add(p2.Box(fixed=True))
    with names("velocity"):
        post.velocity = (1.0, 0.0)
    with names("angular_velocity"):
        post.angular_velocity = 1.0
    with names("velocity"):
        p2.Box(fixed=True, velocity=(1.0, 0.0))
    np.testing.assert_array_equal(post.velocity, [0.0, 0.0])
    assert post.angular_velocity == 0.0


def test_rejected_mixing_or_bad_world_does_not_break_a_good_world():
    """A rejected World construction has no effect on an existing world's objects."""
    world, a, b = two_circles()
    with pytest.raises(ValueError):
        p2.World(restitution_mixing="bogus")
    world.step(1.0 / 60.0)
    assert world.steps == 1 and a.world is world and b.world is world


# -- the checks' two paths -------------------------------------------------------------------------
def _outcome(check, *args):
    """What a check does with ``args``: its return value, or its error's message."""
    try:
        return "ok", check(*args)
    except ValueError as error:
        return "refused", str(error)


_ENTRY = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, -1.0, 100.0, 100.0000001, 1e308]),
)


@settings(max_examples=300, deadline=None)
@given(st.integers(1, 4), st.booleans(), st.data())
def test_small_arrays_are_checked_as_the_numpy_path_checks_them(worlds, pairs, data):
    """A check of a few entries runs in plain Python (numpy's reductions cost more than
    the test); it returns or refuses, with the same message, exactly as the numpy path."""
    from impulse2d import _checks

    shape = (worlds, 2) if pairs else (worlds,)
    count = worlds * (2 if pairs else 1)
    values = np.array(data.draw(st.lists(_ENTRY, min_size=count, max_size=count)))
    values = values.reshape(shape)
    cases = [
        (_checks.real_array, "x", values),
        (_checks.real_array, "x", values, None, False),
        (_checks.batched, "x", values, worlds, shape[1:]),
        (_checks.batched_rule, "x", np.nan_to_num(values), "> 0"),
        (_checks.batched_rule, "x", np.nan_to_num(values), ">= 0"),
        (_checks.within, "x", values, 0.0, 100.0, " m"),
    ]
    if pairs:
        cases.append((_checks.magnitude_at_most, "x", values, 100.0, " m/s"))
    for check, *args in cases:
        with np.errstate(over="ignore"):  # hypot of 1e308s
            fast = _outcome(check, *args)
            few, _checks.FEW_ENTRIES = _checks.FEW_ENTRIES, -1  # every array through numpy
            try:
                slow = _outcome(check, *args)
            finally:
                _checks.FEW_ENTRIES = few
        assert fast[0] == slow[0], (check.__name__, fast, slow)
        if fast[0] == "refused":
            assert fast[1] == slow[1]
        elif isinstance(fast[1], np.ndarray):
            assert np.array_equal(fast[1], slow[1], equal_nan=True)
