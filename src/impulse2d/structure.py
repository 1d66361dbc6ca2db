"""Adding and removing objects: which slot an object takes, and what its slot starts as.

An object added to a world is added to every world of the batch, in the same slot; its
values (validated all at once, before anything is written) fill that slot in each world.
Removing it frees the slot and hands the object its values back, so it can be added again
unchanged. Arrays grow by doubling when every slot is taken.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from . import edit
from .core.state import (
    ANGLE,
    AWAKE,
    BODY_I,
    BREAK_FORCE,
    CIRCLE,
    COLLIDE,
    DYNAMIC,
    ENABLED,
    FIXED,
    FREE,
    HALF_H,
    HALF_W,
    JOINT_LIST,
    LIMITED,
    LINEAR_DRAG,
    LINK,
    NEXT_AT_A,
    NEXT_AT_B,
    NORMAL_X,
    NORMAL_Y,
    PLANE,
    POLYGON,
    REST_LENGTH,
    SAP_ORDER,
    SENSOR_ON,
    SPRING_ON,
    body_defaults,
    grown,
)
from .joints import Joint
from .polygons import inner_radius
from .sensors import Sensor
from .shapes import Body, Plane, _Slot
from .springs import Spring

if TYPE_CHECKING:
    from .world import World


def _free(objects: list) -> int:
    """The first free slot, or -1."""
    for slot, obj in enumerate(objects):
        if obj is None:
            return slot
    return -1


def _take_slot(world: World, kind: str) -> int:
    objects = world.objects[kind]
    slot = _free(objects)
    if slot >= 0:
        return slot
    old = len(objects)
    capacity = grown(old, old + 1)
    if kind == "bodies":
        world.state.grow_bodies(capacity)
        world.layout.grow("shapes", capacity)
    else:
        world.state.grow_rows("spring" if kind == "springs" else "sensor", capacity)
        world.layout.grow(kind, capacity)
    objects.extend([None] * (capacity - old))
    return old


def add(world: World, obj: Any) -> Any:
    """Put ``obj`` in a free slot of every world (see ``World.add``)."""
    if isinstance(obj, Spring):
        return _add_spring(world, obj)
    if isinstance(obj, Joint):
        return _add_joint(world, obj)
    if isinstance(obj, Sensor):
        return _add_sensor(world, obj)
    if not isinstance(obj, (Body, Plane)):
        raise ValueError(
            "obj must be a body (Circle, Box, Polygon, Capsule, Segment), Plane, Spring or "
            f"Sensor, got {type(obj).__name__}"
        )
    if obj._world is not None:
        raise ValueError(f"{obj!r} is already in a world; remove it first")
    batch, cls = world.batch_size, type(obj)
    staged = [
        (getattr(cls, name), getattr(cls, name).validate(obj, value, batch))
        for name, value in obj._values.items()
    ]
    slot = _take_slot(world, "bodies")
    state = world.state
    row, row_i = body_defaults()
    state.body[:, slot] = row
    keep = [i for i in range(BODY_I) if i != SAP_ORDER]
    state.body_i[:, slot, keep] = row_i[keep]
    world.layout.shapes[slot] = obj._kind, obj._motion
    for field, array in staged:
        state.body[:, slot, field.columns] = (array * field.scale).reshape(batch, -1)
    edit.refresh_derived(world.state, slot, [ANGLE, LINEAR_DRAG])
    if obj._kind == CIRCLE:
        state.body[:, slot, HALF_H] = state.body[:, slot, HALF_W]
    if obj._kind == PLANE:
        state.body[:, slot, NORMAL_X], state.body[:, slot, NORMAL_Y] = obj._normal
    if obj._kind == POLYGON:
        state.make_hulls()
        state.hull[:, slot] = obj._outline
        # Both half sizes are the inner radius: what "its smallest half size" means for
        # the projection out of planes and the envelope.
        state.body[:, slot, HALF_W] = state.body[:, slot, HALF_H] = inner_radius(obj._outline)
    state.body_i[:, slot, ENABLED] = 1
    state.body_i[:, slot, AWAKE] = 0 if obj._motion == FIXED else 1
    world.objects["bodies"][slot] = obj
    obj._world, obj._slot, obj._values = world, slot, {}
    edit.rebuild_mass(world.state, world.layout, slot)
    edit.forget(world.state, slot)
    return obj


def remove(world: World, obj: Any) -> None:
    """Take ``obj`` out of every world; it keeps its values (see ``World.remove``)."""
    if not isinstance(obj, (_Slot, Spring, Joint, Sensor)) or obj._world is not world:
        raise ValueError(f"obj must be an object in this world, got {obj!r}")
    if isinstance(obj, Spring):
        _remove_spring(world, obj)
        return
    if isinstance(obj, Joint):
        _remove_joint(world, obj)
        return
    if isinstance(obj, Sensor):
        values = {name: getattr(obj, name) for name in _sensor_names(obj)}
        world.state.sensor[:, obj._slot, SENSOR_ON] = 0.0
        world.layout.sensors[obj._slot] = -1
        world.objects["sensors"][obj._slot] = None
        obj._world, obj._slot, obj._values = None, -1, values
        return
    links = [s for s in world.objects["springs"] if s is not None]
    attached = [s for s in links if obj in (s.body1, s.body2)]
    if attached:
        raise ValueError(
            f"{obj!r} is attached to {len(attached)} spring(s) or joint(s); remove them first"
        )
    values = {name: getattr(obj, name) for name in obj._saved}
    slot = obj._slot
    everywhere = np.arange(world.batch_size)
    edit.wake(world.state, world.layout, everywhere, slot, neighbours=True)
    edit.forget(world.state, slot)
    world.state.body_i[:, slot, ENABLED] = 0
    world.state.body_i[:, slot, AWAKE] = 0
    world.layout.shapes[slot] = FREE, DYNAMIC
    world.objects["bodies"][slot] = None
    obj._world, obj._slot, obj._values = None, -1, values


def _add_spring(world: World, spring: Spring) -> Spring:
    if spring._world is not None:
        raise ValueError(f"{spring!r} is already in a world; remove it first")
    for name, body in (("body1", spring.body1), ("body2", spring.body2)):
        if body._world is not world:
            raise ValueError(f"{name} of the spring must be in this world; add it first")
    values = spring._values
    slot = _take_slot(world, "springs")
    world.state.spring[:, slot] = 0.0
    world.objects["springs"][slot] = spring
    spring._world, spring._slot = world, slot
    try:
        for name in ("stiffness", "damping", "anchor1", "anchor2"):
            setattr(spring, name, values[name])
        if values["rest_length"] is None:
            world.state.spring[:, slot, REST_LENGTH] = np.atleast_1d(spring.length)
        else:
            spring.rest_length = values["rest_length"]
    except ValueError:
        world.objects["springs"][slot] = None
        world.layout.springs[slot] = -1
        spring._world, spring._slot = None, -1
        raise
    world.layout.springs[slot] = spring.body1.slot, spring.body2.slot
    world.state.spring[:, slot, SPRING_ON] = 1.0
    spring._values = {}
    everywhere = np.arange(world.batch_size)
    edit.wake(world.state, world.layout, everywhere, spring.body1.slot)
    edit.wake(world.state, world.layout, everywhere, spring.body2.slot)
    return spring


def _remove_spring(world: World, spring: Spring) -> None:
    names = ("rest_length", "stiffness", "damping", "anchor1", "anchor2")
    values = {name: getattr(spring, name) for name in names}
    world.state.spring[:, spring._slot, SPRING_ON] = 0.0
    world.layout.springs[spring._slot] = -1
    world.objects["springs"][spring._slot] = None
    edit.wake(world.state, world.layout, np.arange(world.batch_size), spring.body1.slot)
    spring._world, spring._slot, spring._values = None, -1, values


def _add_joint(world: World, joint: Joint) -> Joint:
    """A joint in a row of the spring table: its columns validated and written, the
    anchors and reference angles its bodies' poses give in each world, and, unless the
    joined bodies may collide, the row put at the head of both bodies' joint lists
    (``core.joints.joined`` walks them)."""
    if joint._world is not None:
        raise ValueError(f"{joint!r} is already in a world; remove it first")
    for name, body in (("body1", joint.body1), ("body2", joint.body2)):
        if body._world is not world:
            raise ValueError(f"{name} of the joint must be in this world; add it first")
    values = joint._values
    slot = _take_slot(world, "springs")
    state = world.state
    state.spring[:, slot] = 0.0
    world.objects["springs"][slot] = joint
    joint._world, joint._slot = world, slot
    try:
        for name in joint._names:
            setattr(joint, name, values[name])
    except ValueError:
        world.objects["springs"][slot] = None
        joint._world, joint._slot = None, -1
        raise
    row = state.spring[:, slot]
    for column, array in joint._attach(world).items():
        row[:, column : column + (array.shape[1] if array.ndim == 2 else 1)] = array.reshape(
            world.batch_size, -1
        )
    row[:, LINK], row[:, SPRING_ON] = joint._link, 1.0
    row[:, LIMITED] = 1.0 if getattr(joint, "_limited", False) else 0.0
    row[:, BREAK_FORCE] = 0.0 if np.isinf(joint.break_force) else joint.break_force
    row[:, COLLIDE] = 1.0 if joint.collide_connected else 0.0
    a, b = joint.body1.slot, joint.body2.slot
    world.layout.springs[slot] = a, b
    row[:, NEXT_AT_A] = row[:, NEXT_AT_B] = -1.0
    if not joint.collide_connected and a != b:
        heads = state.body_i[:, :, JOINT_LIST]
        row[:, NEXT_AT_A], row[:, NEXT_AT_B] = heads[:, a], heads[:, b]
        heads[:, a] = heads[:, b] = slot
    joint._values = {}
    joint._wake()
    return joint


def _next_at(state: Any, layout: Any, row: int, body: int) -> np.ndarray:
    column = NEXT_AT_A if layout.springs[row, 0] == body else NEXT_AT_B
    return state.spring[:, row, column]


def _unlink(world: World, slot: int) -> None:
    """Take row ``slot`` out of both its bodies' joint lists (the same in every world)."""
    state, layout = world.state, world.layout
    for body in set(layout.springs[slot].tolist()):
        previous, current = -1, int(state.body_i[0, body, JOINT_LIST])
        while current != slot:
            if current < 0:
                return  # not linked (it lets its bodies collide)
            previous, current = current, int(_next_at(state, layout, current, body)[0])
        following = _next_at(state, layout, slot, body).copy()
        if previous < 0:
            state.body_i[:, body, JOINT_LIST] = following
        else:
            _next_at(state, layout, previous, body)[:] = following


def _remove_joint(world: World, joint: Joint) -> None:
    values = {name: getattr(joint, name) for name in joint._names}
    joint._wake()
    _unlink(world, joint._slot)
    world.state.spring[:, joint._slot] = 0.0
    world.layout.springs[joint._slot] = -1
    world.objects["springs"][joint._slot] = None
    joint._world, joint._slot, joint._values = None, -1, values


def _sensor_names(sensor: Sensor) -> tuple[str, ...]:
    size = ("width", "height") if sensor.kind != CIRCLE else ("radius",)
    return ("position", "angle", *size)


def _add_sensor(world: World, sensor: Sensor) -> Sensor:
    if sensor._world is not None:
        raise ValueError(f"{sensor!r} is already in a world; remove it first")
    values = {name: sensor._values[name] for name in _sensor_names(sensor)}
    slot = _take_slot(world, "sensors")
    world.state.sensor[:, slot] = 0.0
    world.objects["sensors"][slot] = sensor
    sensor._world, sensor._slot = world, slot
    try:
        for name, value in values.items():
            setattr(sensor, name, value)
    except ValueError:
        world.objects["sensors"][slot] = None
        sensor._world, sensor._slot = None, -1
        raise
    world.layout.sensors[slot] = sensor.kind, sensor.flags
    world.state.sensor[:, slot, SENSOR_ON] = 1.0
    sensor._values = {}
    return sensor
