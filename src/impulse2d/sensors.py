"""``Sensor``: a region that notices bodies, a view of one sensor slot (see ``events.py``).

A sensor is a circle or a box that takes no part in collisions. After every step, each
dynamic body that moved and whose centre is in the region (or, with ``outside=True``, out
of it) records the sensor's slot in ``body.sensed``; with ``disables=True`` it is also
switched off, in that world only. Pool pockets are circles that disable; "left the table"
is a box with ``outside=True``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from . import _checks
from .core.state import (
    BOX,
    CIRCLE,
    SENSE_DISABLES,
    SENSE_OUTSIDE,
    SENSOR_ANGLE,
    SENSOR_HH,
    SENSOR_HW,
    SENSOR_ON,
    SENSOR_X,
    SENSOR_Y,
)
from .shapes import COORDINATE, SIZE, Part, per_world

# name -> (columns of state.sensor, shape of one value, check(name, array) against the
# envelope or None, stored = value * scale)
_COLUMNS: dict[str, tuple[list[int], tuple[int, ...], Callable[[str, Any], None] | None, float]] = {
    "position": ([SENSOR_X, SENSOR_Y], (2,), COORDINATE, 1.0),
    "angle": ([SENSOR_ANGLE], (), None, 1.0),
    "radius": ([SENSOR_HW], (), SIZE, 1.0),
    "width": ([SENSOR_HW], (), SIZE, 0.5),
    "height": ([SENSOR_HH], (), SIZE, 0.5),
}


def _property(name: str, doc: str) -> property:
    return property(lambda self: self._get(name), lambda self, v: self._set(name, v), doc=doc)


class Sensor(Part):
    """A circle of ``radius`` or a ``width`` x ``height`` box (m) at ``position``, rotated
    by ``angle`` (rad), that reports the bodies whose centre enters it (see the module
    docstring). Give either ``radius`` or both ``width`` and ``height``. ``outside`` and
    ``disables`` are fixed at construction; the region can move and be resized, and
    ``enabled`` switches the sensor per world."""

    position = _property("position", "Centre of the region (m).")
    angle = _property("angle", "Rotation of a box region (rad).")
    radius = _property("radius", "Radius of a circular region (m).")
    width = _property("width", "Width of a box region (m).")
    height = _property("height", "Height of a box region (m).")

    def __init__(
        self,
        *,
        position: Any = (0.0, 0.0),
        radius: Any = None,
        width: Any = None,
        height: Any = None,
        angle: Any = 0.0,
        outside: bool = False,
        disables: bool = False,
    ) -> None:
        box = width is not None or height is not None
        if (radius is not None) == box or (box and (width is None or height is None)):
            raise ValueError(
                "radius or width and height: give a radius for a circle, or both width and "
                f"height for a box, got radius={radius!r}, width={width!r}, height={height!r}"
            )
        for name, flag in (("outside", outside), ("disables", disables)):
            if not isinstance(flag, (bool, np.bool_)):
                raise ValueError(f"{name} must be a bool, got {flag!r}")
        super().__init__()
        self.kind = BOX if box else CIRCLE
        self.flags = (SENSE_OUTSIDE if outside else 0) | (SENSE_DISABLES if disables else 0)
        self.position, self.angle = position, angle
        if box:
            self.width, self.height = width, height
        else:
            self.radius = radius

    @property
    def outside(self) -> bool:
        """True if the sensor triggers outside its region instead of inside."""
        return bool(self.flags & SENSE_OUTSIDE)

    @property
    def disables(self) -> bool:
        """True if a body that triggers the sensor is switched off."""
        return bool(self.flags & SENSE_DISABLES)

    def _check_name(self, name: str) -> None:
        circle_only, box_only = name == "radius", name in ("width", "height")
        if (circle_only and self.kind == BOX) or (box_only and self.kind == CIRCLE):
            shape = "box" if self.kind == BOX else "circle"
            raise AttributeError(f"a {shape} sensor has no {name}")

    def _get(self, name: str) -> Any:
        self._check_name(name)
        if self._world is None:
            value = self._values[name]
            return value.copy() if isinstance(value, np.ndarray) else value
        columns, tail, _, scale = _COLUMNS[name]
        values = self._world.state.sensor[:, self._slot, columns] / scale
        return per_world(values if tail else values[:, 0], self._world.batch_size)

    def _set(self, name: str, value: Any) -> None:
        self._check_name(name)
        columns, tail, check, scale = _COLUMNS[name]
        if self._world is None:
            kept = _checks.detached(name, value, tail)
            if check:
                check(name, np.asarray(kept))
            self._values[name] = kept
            return
        batch = self._world.batch_size
        array = _checks.batched(name, value, batch, tail)
        if check:
            check(name, array)
        self._world.state.sensor[:, self._slot, columns] = (array * scale).reshape(batch, -1)

    @property
    def enabled(self) -> Any:
        """Whether the sensor watches in each world; settable per world (shape (B,))."""
        if self._world is None:
            return True
        state = self._world.state
        return per_world(state.sensor[:, self._slot, SENSOR_ON] == 1.0, self._world.batch_size)

    @enabled.setter
    def enabled(self, value: Any) -> None:
        if self._world is None:
            raise ValueError("enabled can only be set on a sensor in a world; use World.add")
        batch = self._world.batch_size
        flags = np.asarray(value)
        if flags.dtype != np.bool_ or flags.shape not in ((), (batch,)):
            raise ValueError(f"enabled must be a bool or {batch} bools, got {value!r}")
        self._world.state.sensor[:, self._slot, SENSOR_ON] = np.broadcast_to(flags, (batch,))

    def __repr__(self) -> str:
        where = f"slot {self._slot}" if self._world is not None else "not in a world"
        return f"<Sensor {where}>"
