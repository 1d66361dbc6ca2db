"""``Column``: the one descriptor through which every view of a slot reads and writes it.

A ``Circle``'s ``position``, a ``Spring``'s ``stiffness`` and a ``Sensor``'s ``width`` are
all the same thing: one per-world value stored in some columns of the slot's row of one
of the state's tables (``state.body``, ``state.spring``, ``state.sensor``), checked on
every assignment (shape, finiteness, a sign rule, the envelope), kept by the object itself
while it is in no world. ``Column`` says that once; what differs is only what a write
does besides writing (``Part._write``: a body wakes what it touches and may rebuild its
mass, a spring wakes its two bodies, a sensor just writes).

(World-wide settings are not columns of a row: ``Settings`` keeps them, one value for
every world, and folds them into the step context.)

In a batch of ``B`` worlds a column reads as one value per world (shape ``(B,)`` or
``(B, 2)``) and is written with one value for every world or one per world; in a single
world it reads as a float or a ``(2,)`` array (``per_world``).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks, envelope

if TYPE_CHECKING:
    from .world import World

# Checks against the envelope (``impulse2d.envelope``), shared by the columns.
SIZE = partial(_checks.within, low=envelope.SIZE[0], high=envelope.SIZE[1], unit=" m")
COORDINATE = partial(_checks.within, low=-envelope.COORDINATE, high=envelope.COORDINATE, unit=" m")
LENGTH = partial(_checks.within, low=0.0, high=2.0 * envelope.COORDINATE, unit=" m")
SPEED = partial(_checks.magnitude_at_most, high=envelope.SPEED, unit=" m/s")
ANGULAR_SPEED = partial(
    _checks.within, low=-envelope.ANGULAR_SPEED, high=envelope.ANGULAR_SPEED, unit=" rad/s"
)
RESTITUTION_RANGE = partial(_checks.within, low=0.0, high=envelope.RESTITUTION)
FRICTION_RANGE = partial(_checks.within, low=0.0, high=envelope.FRICTION)
RATE = partial(_checks.within, low=0.0, high=envelope.RATE, unit=" 1/s")
DECELERATION = partial(_checks.within, low=0.0, high=envelope.ACCELERATION, unit=" m/s^2")


def per_world(values: np.ndarray, batch: int) -> Any:
    """A (B, ...) readout as the user sees it: as is in a batch, a float or a (2,) array
    in a single world."""
    if batch == 1:
        single = values[0]
        return single.item() if single.ndim == 0 else single
    return values


class Part:
    """What every view of a slot has (bodies, planes, springs, sensors): the world it is
    in and its slot there, and, while it is in none, the values it keeps itself.

    A subclass says what a write of one of its columns does (``_write``) and may refuse
    a name (``_check_readable``, ``_check_settable``) or a value that depends on other
    values (``_check_value``)."""

    def __init__(self) -> None:
        self._world: World | None = None
        self._slot = -1
        self._values: dict[str, Any] = {}

    @property
    def world(self) -> World | None:
        """The world this object is in, or None."""
        return self._world

    @property
    def slot(self) -> int:
        """Index of this object's slot in its world's arrays (-1 when not in a world)."""
        return self._slot

    def _check_readable(self, name: str) -> None:
        """Raise AttributeError if this object has no column ``name`` (a circular
        sensor's width)."""

    def _check_settable(self, name: str) -> None:
        """Raise AttributeError if column ``name`` is fixed at construction."""
        self._check_readable(name)

    def _check_value(self, name: str, array: np.ndarray) -> None:
        """Hook for rules that depend on more than one value (mass of a dynamic body)."""

    def _write(self, column: Column, stored: np.ndarray) -> None:
        """Write ``stored`` (B, len(column.columns)) into the slot's row, and what follows."""
        raise NotImplementedError


class Column:
    """Descriptor for one per-world value of a slot: a scalar column or a 2-vector.

    ``columns``: the columns of ``state.<table>``; ``rule``: ``'> 0'``, ``'>= 0'`` or
    None (any finite number; ``finite=False`` also admits +inf); ``limit(name, array)``
    checks the value against ``impulse2d.envelope``; ``scale``: stored = value * scale (a
    box stores half its width); ``rebuild``: a body's mass properties follow from it;
    ``moves``: a write teleports or resizes the body (what rested on it wakes).
    """

    def __init__(
        self,
        columns: tuple[int, ...],
        table: str = "body",
        *,
        rule: str | None = None,
        limit: Callable[[str, np.ndarray], None] | None = None,
        scale: float = 1.0,
        finite: bool = True,
        rebuild: bool = False,
        moves: bool = False,
        doc: str = "",
    ) -> None:
        if list(columns) != list(range(columns[0], columns[0] + len(columns))):
            raise ValueError(f"a Column's columns must be adjacent, got {columns}")
        self.columns, self.table, self.rule, self.limit = list(columns), table, rule, limit
        self.scale, self.finite, self.rebuild, self.moves = scale, finite, rebuild, moves
        self.__doc__ = doc

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @property
    def tail(self) -> tuple[int, ...]:
        """The shape of one world's value: () or (2,)."""
        return (2,) if len(self.columns) == 2 else ()

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        if obj is None:
            return self
        obj._check_readable(self.name)
        if obj._world is None:
            value = obj._values[self.name]
            return value.copy() if isinstance(value, np.ndarray) else value
        world = obj._world
        values = getattr(world.state, self.table)[:, obj._slot, self.columns]
        if not self.tail:
            values = values[:, 0]
        values = values / self.scale if self.scale != 1.0 else values.copy()
        return per_world(values, world.batch_size)

    def validate(self, obj: Any, value: Any, batch: int | None) -> np.ndarray:
        """The value checked against the column's rules; (B, *tail) when ``batch`` is
        given, else as a detached object keeps it (one value, or one per world)."""
        if batch is None:
            array = np.asarray(_checks.detached(self.name, value, self.tail, finite=self.finite))
        else:
            array = _checks.batched(self.name, value, batch, self.tail, finite=self.finite)
        if self.rule:
            _checks.batched_rule(self.name, array, self.rule)
        if self.limit:
            self.limit(self.name, array)
        obj._check_value(self.name, array)
        return array

    def __set__(self, obj: Any, value: Any) -> None:
        obj._check_settable(self.name)
        world = obj._world
        if world is None:
            array = self.validate(obj, value, None)
            obj._values[self.name] = float(array) if array.shape == () else array
            return
        array = self.validate(obj, value, world.batch_size)
        obj._write(self, (array * self.scale).reshape(world.batch_size, len(self.columns)))
