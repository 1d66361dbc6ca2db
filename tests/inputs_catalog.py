"""Every public entry that takes a value, and the kinds of wrong value to give it.

``ENTRIES`` lists each constructor keyword, settable attribute and method argument of
``World``, ``Circle``, ``Box``, ``Polygon``, ``Capsule``, ``Segment``, ``Plane``,
``Spring`` and ``Sensor`` as an ``Entry``: the
parameter's name, the shape of value it takes and a function that builds a fresh scene
and passes it one value. ``BAD[shape]`` are values that must be refused with a
``ValueError`` naming the parameter (NaN, inf, strings, None, complex numbers, bools
where a number is meant, wrong shapes: a per-world value of shape (1,) is a right shape
in a single world, which is a batch of one); ``EXTREME`` are finite but extreme numbers, which
must either be refused the same way or be stepped without a non-finite number.

``tests/test_validation_catalog.py`` runs every entry with every value of its kind;
``bench/fuzz_inputs.py`` runs the same and prints the counts by kind and outcome.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import impulse2d as p2
from impulse2d.core.state import HEALTH

DT = 1.0 / 60.0
NAN, INF = math.nan, math.inf


class Nonsense:
    """An object that is no number at all."""


BAD: dict[str, dict[str, list[Any]]] = {
    "real": {
        "non-finite": [NAN, INF, -INF, np.float64(NAN)],
        "string": ["1.0", ""],
        "None": [None],
        "complex": [1 + 0j, np.complex128(1.0), np.array(1.0 + 0j)],
        "bool": [True, np.bool_(False)],
        "shape": [(1.0, 2.0), np.ones((2, 2))],
        "object": [Nonsense(), {}],
    },
    "vector": {
        "non-finite": [(NAN, 0.0), (0.0, INF), np.array([-INF, 1.0])],
        "string": ["ab", ("1", "2")],
        "None": [None, (None, 1.0)],
        "complex": [(1 + 0j, 0.0), np.array([1.0, 2.0], np.complex128)],
        "bool": [(True, False), np.array([True, True])],
        "shape": [1.0, (1.0, 2.0, 3.0), [[1.0, 2.0], [3.0, 4.0]], [[1.0], [2.0, 3.0]]],
        "object": [Nonsense(), {"x": 1.0}],
    },
    "count": {
        "non-integer": [1.5, np.float64(2.0), "2", None, [2], 2 + 0j],
        "bool": [True, np.bool_(True)],
        "below 1": [0, -1],
    },
    "flag": {
        "non-bool": [1, 0, 1.0, "True", None, [True, False]],
    },
    "index": {
        "non-integer": ["0", None, [0], 1.5, True, np.float64(0.0)],
        "out of range": [-1, 5],
    },
    "worlds": {
        "non-integer": ["0", [0.5], [None], [True]],
        "out of range": [[-1], [5]],
    },
    "vertices": {
        "non-finite": [[(0.0, 0.0), (1.0, NAN), (0.0, 1.0)], [(0.0, 0.0), (INF, 0.0), (0.0, 1.0)]],
        "string": ["abc", [("0", "0"), ("1", "0"), ("0", "1")]],
        "None": [None, [(0.0, 0.0), None, (0.0, 1.0)]],
        "complex": [np.array([[0, 0], [1, 0], [0, 1]], np.complex128)],
        "bool": [np.ones((3, 2), bool)],
        "shape": [(1.0, 2.0), [(0.0, 0.0), (1.0, 0.0)], [(k, k * k) for k in range(9)]],
        "object": [Nonsense(), {"a": (0, 0)}],
        "degenerate": [
            [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)],  # collinear
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.8, 0.2)],  # not convex
            [(0.0, 0.0), (1.0, 0.0), (1.0, 0.001), (0.0, 1.0)],  # an edge under 5 mm
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (1.0, 1.0), (0.0, 1.0)],  # a repeated vertex
        ],
    },
    "body": {"not a body": [None, "x", 3, p2.Circle, p2.Plane()]},
    "object": {"not an object": [None, "x", 3, p2.Circle, p2.World]},
}

EXTREME = [1e300, -1e300, 1e155, 1e-154, 1e-300, 5e-324, 1e-160, 1e16]


@dataclass(frozen=True)
class Entry:
    """One parameter of one public entry: ``give(value)`` builds a scene, passes it
    ``value`` and returns the world (to be stepped) or None."""

    owner: str
    name: str
    shape: str  # a key of BAD
    give: Callable[[Any], p2.World | None]
    extremes: bool = True  # try EXTREME numbers (real and vector parameters)
    none_is_legal: bool = False  # None means a default (every thread, the centre)
    inf_is_legal: bool = False  # +inf means "never" (a body's health)

    @property
    def label(self) -> str:
        return f"{self.owner}.{self.name}"


def scene(batch_size: int = 1) -> tuple[p2.World, dict[str, Any]]:
    """A world with a ground, a ball on it, a box, a spring between them and a sensor."""
    world = p2.World(batch_size=batch_size)
    parts = {
        "plane": world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0))),
        "circle": world.add(p2.Circle(position=(0.0, 0.5), velocity=(1.0, 0.0))),
        "box": world.add(p2.Box(position=(2.0, 0.5))),
        "kinematic": world.add(p2.Box(position=(-3.0, 2.0), kinematic=True)),
        "sensor": world.add(p2.Sensor(position=(5.0, 5.0), radius=1.0)),
        "polygon": world.add(p2.Polygon(vertices=TRIANGLE, position=(4.0, 0.5))),
    }
    parts["revolute"] = world.add(
        p2.RevoluteJoint(parts["box"], parts["polygon"], lower_angle=-1.0, upper_angle=1.0)
    )
    parts["mouse"] = world.add(p2.MouseJoint(parts["polygon"], target=(4.0, 1.0)))
    parts["spring"] = world.add(p2.Spring(parts["circle"], parts["box"], stiffness=10.0))
    return world, parts


def _set(part: str, name: str, batch_size: int = 1) -> Callable[[Any], p2.World]:
    def give(value: Any) -> p2.World:
        world, parts = scene(batch_size)
        setattr(world if part == "world" else parts[part], name, value)
        return world

    return give


def _set_box_sensor(name: str) -> Callable[[Any], p2.World]:
    def give(value: Any) -> p2.World:
        world, _ = scene()
        sensor = world.add(p2.Sensor(position=(0.0, 3.0), width=1.0, height=2.0))
        setattr(sensor, name, value)
        return world

    return give


def _make(cls: type, name: str, **base: Any) -> Callable[[Any], p2.World]:
    def give(value: Any) -> p2.World:
        world, parts = scene()
        if cls is p2.Spring:
            obj = p2.Spring(parts["circle"], parts["box"], **{name: value})
        else:
            obj = cls(**{**base, name: value})
        world.add(obj)
        return world

    return give


def _joint(cls: type, name: str, **base: Any) -> Callable[[Any], p2.World]:
    """``cls(box, polygon, **{name: value})`` added to the scene (a mouse joint: on the
    polygon alone)."""

    def give(value: Any) -> p2.World:
        world, parts = scene()
        bodies = (parts["polygon"],) if cls is p2.MouseJoint else (parts["box"], parts["polygon"])
        world.add(cls(*bodies, **{**base, name: value}))
        return world

    return give


JOINT_ENTRIES = (
    (p2.RevoluteJoint, {"lower_angle": {"upper_angle": 1.0}, "upper_angle": {"lower_angle": -1.0},
                        "motor_speed": {}, "max_motor_torque": {}, "spring_hertz": {},
                        "spring_damping_ratio": {}}, ("anchor",)),
    (p2.PrismaticJoint, {"motor_speed": {}, "max_motor_force": {}, "spring_hertz": {},
                         "lower_translation": {"upper_translation": 1.0}}, ("anchor", "axis")),
    (p2.WeldJoint, {"hertz": {}, "damping_ratio": {}}, ("anchor",)),
    (p2.DistanceJoint, {"length": {}, "min_length": {"max_length": 5.0}, "spring_hertz": {}},
     ("anchor1", "anchor2")),
    (p2.MouseJoint, {"hertz": {}, "max_force": {}, "damping_ratio": {}}, ()),
)  # fmt: skip


def _joint_entries(e: list[Entry]) -> None:
    for cls, reals, vectors in JOINT_ENTRIES:
        base = {"target": (4.0, 1.0)} if cls is p2.MouseJoint else {}
        for name, more in reals.items():
            give = _joint(cls, name, **base, **more)
            default = name in ("length", "min_length", "max_force")  # None: the default
            e.append(Entry(f"{cls.__name__}()", name, "real", give, none_is_legal=default))
        for name in vectors:
            legal = name != "axis"  # None: a default point
            entry = Entry(
                f"{cls.__name__}()", name, "vector", _joint(cls, name), none_is_legal=legal
            )
            e.append(entry)
        e.append(Entry(f"{cls.__name__}()", "break_force", "real",
                       _joint(cls, "break_force", **base), inf_is_legal=True))  # fmt: skip
    grab = _joint(p2.MouseJoint, "target")  # None: the body's centre
    e.append(Entry("MouseJoint()", "target", "vector", grab, none_is_legal=True))
    for name in ("motor_speed", "max_motor_torque", "spring_hertz", "lower_angle", "upper_angle"):
        e.append(Entry("revolute", name, "real", _set("revolute", name)))
    e.append(Entry("mouse", "target", "vector", _set("mouse", "target")))
    e.append(Entry("mouse", "max_force", "real", _set("mouse", "max_force")))


def _placed(vertices: Any) -> p2.World:
    world, _ = scene()
    world.add(p2.Polygon.placed(vertices))
    return world


def _call(part: str, method: str, *before: Any, **kwargs: Any) -> Callable[[Any], Any]:
    """``part.method(*before, value, **kwargs)`` (``part`` 'world' or a scene part)."""

    def give(value: Any) -> p2.World:
        world, parts = scene()
        target = world if part == "world" else parts[part]
        getattr(target, method)(*before, value, **kwargs)
        return world

    return give


def _call_keyword(part: str, method: str, keyword: str, *args: Any) -> Callable[[Any], Any]:
    def give(value: Any) -> p2.World:
        world, parts = scene()
        target = world if part == "world" else parts[part]
        getattr(target, method)(*args, **{keyword: value})
        return world

    return give


def _world_kwarg(name: str) -> Callable[[Any], p2.World]:
    def give(value: Any) -> p2.World:
        world = p2.World(**{name: value})
        world.add(p2.Plane())
        world.add(p2.Circle(position=(0.0, 0.6), velocity=(1.0, -1.0)))
        return world

    return give


WORLD_REALS = [
    "restitution_threshold",
    "contact_hertz",
    "contact_damping_ratio",
    "contact_push_speed",
    "speculative_distance",
    "time_to_sleep",
    "sleep_speed",
    "damage_speed",
]
BODY_REALS = [
    "angle",
    "angular_velocity",
    "mass",
    "restitution",
    "friction",
    "linear_drag",
    "angular_drag",
    "rolling_resistance",
    "health",
]
BODY_VECTORS = ["position", "velocity"]
TRIANGLE = [(0.0, 0.0), (1.0, 0.0), (0.3, 0.8)]
OUTLINES = (
    (p2.Polygon, ["radius"], {"vertices": TRIANGLE}),
    (p2.Capsule, ["length", "radius"], {}),
)


def _entries() -> list[Entry]:
    e: list[Entry] = []
    # World: constructor and settable attributes.
    for name in WORLD_REALS:
        e.append(Entry("World()", name, "real", _world_kwarg(name)))
        e.append(Entry("world", name, "real", _set("world", name)))
    e.append(Entry("World()", "gravity", "vector", _world_kwarg("gravity")))
    e.append(Entry("world", "gravity", "vector", _set("world", "gravity")))
    for name in ("batch_size", "substeps", "threads"):
        e.append(
            Entry("World()", name, "count", _world_kwarg(name), none_is_legal=name == "threads")
        )
    for name in ("substeps", "threads"):
        e.append(
            Entry("world", name, "count", _set("world", name), none_is_legal=name == "threads")
        )
    e.append(Entry("World()", "sleeping", "flag", _world_kwarg("sleeping")))
    e.append(Entry("world", "sleeping", "flag", _set("world", "sleeping")))
    # World: methods.
    e.append(Entry("world.step", "dt", "real", _call("world", "step")))
    e.append(Entry("world.step", "steps", "count", _call("world", "step", DT)))
    e.append(Entry("world.run_until_rest", "dt", "real", _call("world", "run_until_rest", 10)))
    e.append(
        Entry("world.run_until_rest", "max_steps", "count", _call("world", "run_until_rest", DT))
    )
    e.append(
        Entry(
            "world.run_until_rest",
            "worlds",
            "worlds",
            _call_keyword("world", "run_until_rest", "worlds", DT, 10),
        )
    )
    e.append(Entry("world.stop", "worlds", "worlds", _call("world", "stop")))
    e.append(Entry("world.reset_events", "worlds", "worlds", _call("world", "reset_events")))
    e.append(Entry("world.impulses", "approach_speed", "real", _call("world", "impulses")))
    e.append(Entry("world.contacts", "world", "index", _call("world", "contacts")))
    e.append(Entry("world.query_point", "point", "vector", _call("world", "query_point")))
    e.append(
        Entry("world.query_point", "world", "index", _call("world", "query_point", (0.0, 0.5)))
    )
    e.append(Entry("world.replicate", "batch_size", "count", _call("world", "replicate")))
    e.append(Entry("world.add", "obj", "object", _call("world", "add")))
    e.append(Entry("world.remove", "obj", "object", _call("world", "remove")))
    # Bodies: constructors and attributes.
    for cls, sizes in ((p2.Circle, ["radius"]), (p2.Box, ["width", "height"])):
        kind = cls.__name__.lower()
        for name in BODY_REALS + sizes:
            inf = name == "health"
            make = _make(cls, name, position=(0.0, 3.0))
            e.append(Entry(f"{cls.__name__}()", name, "real", make, inf_is_legal=inf))
            e.append(Entry(kind, name, "real", _set(kind, name), inf_is_legal=inf))
        for name in BODY_VECTORS:
            e.append(Entry(f"{cls.__name__}()", name, "vector", _make(cls, name)))
            e.append(Entry(kind, name, "vector", _set(kind, name)))
        for name in ("fixed", "kinematic"):
            e.append(Entry(f"{cls.__name__}()", name, "flag", _make(cls, name), extremes=False))
    for cls, sizes, base in OUTLINES:
        for name in BODY_REALS + sizes:
            make = _make(cls, name, position=(0.0, 3.0), **base)
            e.append(Entry(f"{cls.__name__}()", name, "real", make, inf_is_legal=name == "health"))
        for name in BODY_VECTORS:
            e.append(Entry(f"{cls.__name__}()", name, "vector", _make(cls, name, **base)))
        for name in ("fixed", "kinematic"):
            flag = _make(cls, name, **base)
            e.append(Entry(f"{cls.__name__}()", name, "flag", flag, extremes=False))
    for name in BODY_REALS:
        e.append(
            Entry("polygon", name, "real", _set("polygon", name), inf_is_legal=name == "health")
        )
    for name in BODY_VECTORS:
        e.append(Entry("polygon", name, "vector", _set("polygon", name)))
    e.append(Entry("Polygon()", "vertices", "vertices", _make(p2.Polygon, "vertices")))
    e.append(Entry("Polygon.placed", "vertices", "vertices", lambda v: _placed(v)))
    segment = {"start": (-1.0, 0.2), "end": (1.0, 0.0)}
    for name in ("start", "end"):
        e.append(Entry("Segment()", name, "vector", _make(p2.Segment, name, **segment)))
    for name in ("radius", "restitution", "friction"):
        e.append(Entry("Segment()", name, "real", _make(p2.Segment, name, **segment)))
    _joint_entries(e)
    e.append(Entry("kinematic", "velocity", "vector", _set("kinematic", "velocity")))
    e.append(Entry("kinematic", "angular_velocity", "real", _set("kinematic", "angular_velocity")))
    for kind in ("circle", "box"):
        e.append(Entry(kind, "enabled", "flag", _set(kind, "enabled")))
    for method in ("apply_force", "apply_impulse"):
        e.append(Entry(f"circle.{method}", method.split("_")[1], "vector", _call("circle", method)))
        at = _call("circle", method, (1.0, 0.0))
        e.append(Entry(f"circle.{method}", "point", "vector", at, none_is_legal=True))
    for method, arg in (
        ("to_world", "local_point"),
        ("to_local", "world_point"),
        ("is_inside", "point"),
    ):
        e.append(Entry(f"box.{method}", arg, "vector", _call("box", method)))
    # Planes.
    for name in ("normal", "point"):
        e.append(Entry("Plane()", name, "vector", _make(p2.Plane, name)))
    for name in ("restitution", "friction"):
        e.append(Entry("Plane()", name, "real", _make(p2.Plane, name)))
        e.append(Entry("plane", name, "real", _set("plane", name)))
    e.append(Entry("plane", "point", "vector", _set("plane", "point")))
    e.append(Entry("plane.is_inside", "point", "vector", _call("plane", "is_inside")))
    # Springs.
    for name in ("rest_length", "stiffness", "damping"):
        default = name == "rest_length"  # None: the anchors' distance
        e.append(Entry("Spring()", name, "real", _make(p2.Spring, name), none_is_legal=default))
        e.append(Entry("spring", name, "real", _set("spring", name)))
    for name in ("anchor1", "anchor2"):
        e.append(Entry("Spring()", name, "vector", _make(p2.Spring, name)))
        e.append(Entry("spring", name, "vector", _set("spring", name)))
    e.append(Entry("Spring()", "body1", "body", lambda v: p2.Spring(v, p2.Circle())))
    e.append(Entry("Spring()", "body2", "body", lambda v: p2.Spring(p2.Circle(), v)))
    # Sensors.
    e.append(Entry("Sensor()", "radius", "real", _make(p2.Sensor, "radius")))
    e.append(Entry("Sensor()", "position", "vector", _make(p2.Sensor, "position", radius=1.0)))
    e.append(Entry("Sensor()", "angle", "real", _make(p2.Sensor, "angle", radius=1.0)))
    for name, shape in (("radius", "real"), ("angle", "real"), ("position", "vector")):
        e.append(Entry("sensor", name, shape, _set("sensor", name)))
    for name in ("width", "height"):
        box = _make(p2.Sensor, name, width=1.0, height=1.0)
        e.append(Entry("Sensor()", name, "real", box))
        e.append(Entry("sensor", name, "real", _set_box_sensor(name)))
    e.append(Entry("sensor", "enabled", "flag", _set("sensor", "enabled")))
    for name in ("outside", "disables"):
        e.append(Entry("Sensor()", name, "flag", _make(p2.Sensor, name, radius=1.0)))
    return e


ENTRIES = _entries()


def extreme_values(entry: Entry) -> list[Any]:
    """The EXTREME numbers, shaped for the entry (a vector gets them on one axis and on
    both), or none if the entry takes no number."""
    if not entry.extremes or entry.shape not in ("real", "vector"):
        return []
    if entry.shape == "real":
        return list(EXTREME)
    return [v for x in EXTREME for v in ((x, 0.0), (x, x))]


def state_bytes(world: p2.World) -> dict[str, bytes]:
    return {name: a.tobytes() for name, a in world.state.arrays().items()}


def finite_after_steps(world: p2.World, steps: int = 30) -> bool:
    """Step ``world`` and say whether every float of its state stayed finite (a body's
    health may be +inf: unbreakable) and its energy readout is finite."""
    for _ in range(steps):
        world.step(DT)
    arrays = world.state.arrays()
    body = np.delete(arrays.pop("body"), HEALTH, axis=-1)
    finite = all(np.isfinite(a).all() for a in arrays.values() if a.dtype.kind == "f")
    return finite and bool(np.isfinite(body).all()) and math.isfinite(world.energy().total)
