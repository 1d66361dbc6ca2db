"""``Sensor``: a region that notices bodies, a view of one sensor slot (see ``events.py``).

A sensor is a circle or a box that takes no part in collisions. After every step, each
dynamic body that moved and whose centre is in the region (or, with ``outside=True``, out
of it) records the sensor's slot in ``body.sensed``; with ``disables=True`` it is also
switched off, in that world only. Pool pockets are circles that disable; "left the table"
is a box with ``outside=True``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import edit
from .columns import COORDINATE, SIZE, Column, Part, per_world
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


class Sensor(Part):
    """A circle of ``radius`` or a ``width`` x ``height`` box (m) at ``position``, rotated
    by ``angle`` (rad), that reports the bodies whose centre enters it (see the module
    docstring). Give either ``radius`` or both ``width`` and ``height``. ``outside`` and
    ``disables`` are fixed at construction; the region can move and be resized, and
    ``enabled`` switches the sensor per world."""

    position = Column(
        (SENSOR_X, SENSOR_Y), "sensor", limit=COORDINATE, doc="Centre of the region (m)."
    )
    angle = Column((SENSOR_ANGLE,), "sensor", doc="Rotation of a box region (rad).")
    radius = Column((SENSOR_HW,), "sensor", limit=SIZE, doc="Radius of a circular region (m).")
    width = Column((SENSOR_HW,), "sensor", limit=SIZE, scale=0.5, doc="Width of a box region (m).")
    height = Column(
        (SENSOR_HH,), "sensor", limit=SIZE, scale=0.5, doc="Height of a box region (m)."
    )

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

    def _check_readable(self, name: str) -> None:
        circle_only, box_only = name == "radius", name in ("width", "height")
        if (circle_only and self.kind == BOX) or (box_only and self.kind == CIRCLE):
            shape = "box" if self.kind == BOX else "circle"
            raise AttributeError(f"a {shape} sensor has no {name}")

    def _write(self, column: Column, stored: np.ndarray) -> None:
        edit.write_rows(self._world.state, "sensor", self._slot, column.columns, stored)

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
