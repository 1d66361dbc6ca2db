"""Joints: ``RevoluteJoint``, ``PrismaticJoint``, ``WeldJoint``, ``DistanceJoint`` and
``MouseJoint``, views of one row of the spring table, as springs are.

A joint is a constraint solved in the soft step beside the contacts (``core.joints``):
warm started from its impulses of the last step, soft by the world's joint softness
when rigid or by its own hertz and damping ratio when it is a spring, relaxed without
bias after each substep (Box2D v3's scheme). Its anchors are given as *world* points
where it is made, as Box2D's samples make them, and kept in each body's frame (one per
world of a batch: the bodies may stand differently in each). By default the bodies it
joins do not collide with each other (``collide_connected=False``), so a ragdoll's
overlapping limbs or a chain's overlapping links do not push apart.

Readouts: ``force`` and ``torque`` are what the joint did to ``body2`` over the last
step (N, N m); past ``break_force`` the joint switches itself off in that world
(``enabled`` False) for Angry Birds-style structures. Parameters are settable and
validated by name, as every column, and a change wakes the two bodies.
"""

from __future__ import annotations

import math
from functools import partial
from typing import Any

import numpy as np

from . import _checks, edit, envelope
from .columns import ANGULAR_SPEED, COORDINATE, LENGTH, Column, Part, per_world
from .core.state import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANGLE,
    AXIS_X,
    BREAK_FORCE,
    DAMPING_RATIO,
    DISTANCE,
    FORCE_X,
    FORCE_Y,
    HERTZ,
    IMPULSE_SPRING,
    IMPULSE_X,
    JOINT_TORQUE,
    LOWER,
    MAX_MOTOR,
    MOTOR_SPEED,
    MOUSE,
    PRISMATIC,
    REFERENCE_ANGLE,
    REST_LENGTH,
    REVOLUTE,
    SPRING_ON,
    UPPER,
    WELD,
    X,
    Y,
)
from .shapes import Body

__all__ = [
    "DistanceJoint",
    "Joint",
    "MouseJoint",
    "PrismaticJoint",
    "RevoluteJoint",
    "WeldJoint",
]


# Angle limits lie within half a turn either way: the relative angle is taken so.
HALF_TURN = partial(_checks.within, low=-math.pi, high=math.pi, unit=" rad")
# A slider's speed is one number, within the envelope's speeds (SPEED checks 2-vectors).
SPEED_RANGE = partial(_checks.within, low=-envelope.SPEED, high=envelope.SPEED, unit=" m/s")


def _hertz() -> Column:
    """A joint spring's frequency (a Column a class: a descriptor learns its own name)."""
    return Column((HERTZ,), "spring", rule=">= 0", doc="Spring frequency (Hz, 0: none).")


def _ratio() -> Column:
    return Column((DAMPING_RATIO,), "spring", rule=">= 0", doc="Damping ratio (1: critical).")


class Joint(Part):
    """What every joint shares: its two bodies, being on per world, its force readouts,
    its break force. Not made directly: use one of the joint classes."""

    _link: float = REVOLUTE
    _names: tuple[str, ...] = ()  # the columns a detached joint keeps, written on add

    def __init__(self, body1: Body, body2: Body, break_force: Any, collide_connected: bool) -> None:
        for name, body in (("body1", body1), ("body2", body2)):
            if not isinstance(body, Body):
                raise ValueError(f"{name} must be a body, got {type(body).__name__}")
        if body1 is body2 and type(self) is not MouseJoint:
            raise ValueError("body1 and body2 must be different bodies (a joint to itself)")
        if not isinstance(collide_connected, (bool, np.bool_)):
            raise ValueError(f"collide_connected must be a bool, got {collide_connected!r}")
        super().__init__()
        self.body1, self.body2 = body1, body2
        self.collide_connected = bool(collide_connected)
        self._break_force = self._checked_break_force(break_force)

    # -- what structure.add calls --------------------------------------------------------
    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        """The columns that follow from the bodies' poses in ``world`` (B values each):
        anchors in the bodies' frames, reference angles. Overridden."""
        raise NotImplementedError

    def _write(self, column: Column, stored: np.ndarray) -> None:
        world = self._world
        edit.write_rows(world.state, "spring", self._slot, column.columns, stored)
        self._wake()

    def _wake(self) -> None:
        world = self._world
        everywhere = np.arange(world.batch_size)
        for body in {self.body1.slot, self.body2.slot}:
            edit.wake(world.state, world.layout, everywhere, body)

    def _row(self, column: int) -> np.ndarray:
        return self._world.state.spring[:, self._slot, column]

    # -- readouts and switches -----------------------------------------------------------
    @property
    def force(self) -> Any:
        """The force the joint applied to ``body2`` over the last step (N; ``body1`` got
        the opposite): shape (2,), or (B, 2) in a batch."""
        if self._world is None:
            return np.zeros(2)
        rows = self._world.state.spring[:, self._slot, FORCE_X : FORCE_Y + 1].copy()
        return per_world(rows, self._world.batch_size)

    @property
    def torque(self) -> Any:
        """The torque the joint applied to ``body2`` about its centre beyond that of
        ``force`` over the last step (N m): the motor, spring and limits of a revolute
        joint, the angle of a weld or slider."""
        if self._world is None:
            return 0.0
        return per_world(self._row(JOINT_TORQUE).copy(), self._world.batch_size)

    @property
    def enabled(self) -> Any:
        """Whether the joint acts in each world; False once it broke there. Settable
        (bool, or one per world): switching it on again starts it without impulses."""
        if self._world is None:
            return True
        return per_world(self._row(SPRING_ON) == 1.0, self._world.batch_size)

    @enabled.setter
    def enabled(self, value: Any) -> None:
        if self._world is None:
            raise ValueError("enabled can only be set on a joint in a world; use World.add")
        batch = self._world.batch_size
        flags = np.asarray(value)
        if flags.dtype != np.bool_ or flags.shape not in ((), (batch,)):
            raise ValueError(f"enabled must be a bool or {batch} bools, got {value!r}")
        flags = np.broadcast_to(flags, (batch,))
        rows = self._world.state.spring[:, self._slot]
        switched_on = flags & (rows[:, SPRING_ON] != 1.0)
        rows[switched_on, IMPULSE_X : IMPULSE_SPRING + 1] = 0.0
        rows[:, SPRING_ON] = np.where(flags, 1.0, 0.0)
        self._wake()

    @staticmethod
    def _checked_break_force(value: Any) -> float:
        number = _checks._real("break_force", value)
        if number.shape != () or math.isnan(float(number)) or float(number) <= 0.0:
            raise ValueError(f"break_force must be a number > 0 (inf: never), got {value!r}")
        return float(number)

    @property
    def break_force(self) -> float:
        """The force (N) past which the joint breaks (switches off); inf: never."""
        return self._break_force

    @break_force.setter
    def break_force(self, value: Any) -> None:
        self._break_force = self._checked_break_force(value)
        if self._world is not None:
            stored = 0.0 if math.isinf(self._break_force) else self._break_force
            self._world.state.spring[:, self._slot, BREAK_FORCE] = stored

    def __repr__(self) -> str:
        where = f"slot {self._slot}" if self._world is not None else "not in a world"
        return f"<{type(self).__name__} {where}>"


def _world_point(name: str, value: Any, default: Body) -> np.ndarray:
    """A world point given at construction (default: ``default``'s centre)."""
    if value is None:
        return np.asarray(default.position, float)
    point = _checks.vector2(name, value)
    COORDINATE(name, point)
    return point


def _limits(name: str, lower: Any, upper: Any, unit: str) -> tuple[float, float, bool]:
    """Lower and upper limits: both or neither, lower <= upper."""
    if (lower is None) != (upper is None):
        raise ValueError(f"lower_{name} and upper_{name} must be given together (or neither)")
    if lower is None:
        return 0.0, 0.0, False
    low, high = (
        _checks.finite_scalar(f"lower_{name}", lower),
        _checks.finite_scalar(f"upper_{name}", upper),
    )
    if low > high:
        raise ValueError(f"lower_{name} must be <= upper_{name}, got {low} > {high}{unit}")
    if name == "angle":
        HALF_TURN("lower_angle", low)
        HALF_TURN("upper_angle", high)
    return low, high, True


def _locals(body: Body, point: np.ndarray) -> np.ndarray:
    """``point`` (world) in ``body``'s frame, one row per world: (B, 2)."""
    return np.atleast_2d(body.to_local(point))


def _angle_of(body: Body) -> np.ndarray:
    return np.atleast_1d(np.asarray(body.angle, float))


class _Limited(Joint):
    """A joint with lower and upper limits on its own coordinate, kept ordered."""

    _lower: str = ""
    _upper: str = ""

    def _check_value(self, name: str, array: np.ndarray) -> None:
        if name not in (self._lower, self._upper):
            return
        other = self._upper if name == self._lower else self._lower
        if self._world is None and other not in self._values:
            return  # being made: the pair is checked as a pair (_limits)
        current = np.asarray(getattr(self, other), float)
        low, high = (array, current) if name == self._lower else (current, array)
        if np.any(low > high):
            raise ValueError(f"{self._lower} must be <= {self._upper}, got {low} > {high}")

    @property
    def limited(self) -> bool:
        """Whether the limits act (given at construction)."""
        return self._limited


class RevoluteJoint(_Limited):
    """A pin: ``body1`` and ``body2`` share the world point ``anchor`` (default:
    ``body2``'s centre) and turn about it freely, or within ``lower_angle`` to
    ``upper_angle`` (rad, in [-pi, pi], of ``body2``'s angle less ``body1``'s, from how
    they stand now; both or neither), driven by a motor towards ``motor_speed`` (rad/s) with at
    most ``max_motor_torque`` (N m; 0: no motor), pulled back to the angle they have
    now by a spring of ``spring_hertz`` and ``spring_damping_ratio`` (0 Hz: none).
    """

    _link = REVOLUTE
    _lower, _upper = "lower_angle", "upper_angle"
    _names = ("lower_angle", "upper_angle", "motor_speed", "max_motor_torque",
              "spring_hertz", "spring_damping_ratio")  # fmt: skip
    lower_angle = Column(
        (LOWER,), "spring", limit=HALF_TURN, doc="Lower limit of the relative angle (rad)."
    )
    upper_angle = Column(
        (UPPER,), "spring", limit=HALF_TURN, doc="Upper limit of the relative angle (rad)."
    )
    motor_speed = Column(
        (MOTOR_SPEED,), "spring", limit=ANGULAR_SPEED, doc="Motor's target speed (rad/s)."
    )
    max_motor_torque = Column((MAX_MOTOR,), "spring", rule=">= 0", doc="Motor's torque (N m).")
    spring_hertz, spring_damping_ratio = _hertz(), _ratio()

    def __init__(
        self,
        body1: Body,
        body2: Body,
        anchor: Any = None,
        *,
        lower_angle: Any = None,
        upper_angle: Any = None,
        motor_speed: Any = 0.0,
        max_motor_torque: Any = 0.0,
        spring_hertz: Any = 0.0,
        spring_damping_ratio: Any = 0.0,
        break_force: Any = math.inf,
        collide_connected: bool = False,
    ) -> None:
        super().__init__(body1, body2, break_force, collide_connected)
        self._anchor = _world_point("anchor", anchor, body2)
        low, high, self._limited = _limits("angle", lower_angle, upper_angle, " rad")
        self.lower_angle, self.upper_angle = low, high
        self.motor_speed, self.max_motor_torque = motor_speed, max_motor_torque
        self.spring_hertz, self.spring_damping_ratio = spring_hertz, spring_damping_ratio

    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        return _pinned(self.body1, self.body2, self._anchor)

    @property
    def angle(self) -> Any:
        """``body2``'s angle less ``body1``'s, from where they stood when joined (rad)."""
        return _relative_angle(self)


def _pinned(body1: Body, body2: Body, anchor: np.ndarray) -> dict[int, np.ndarray]:
    """Anchors of a shared world point in both frames, and the reference angle."""
    return {
        ANCHOR_AX: _locals(body1, anchor),
        ANCHOR_BX: _locals(body2, anchor),
        REFERENCE_ANGLE: _angle_of(body2) - _angle_of(body1),
    }


def _relative_angle(joint: Joint) -> Any:
    """``body2``'s angle less ``body1``'s less the reference, in (-pi, pi] (as the solver
    takes it, ``core.joints.relative_angle``)."""
    if joint._world is None:
        return 0.0
    turn = _angle_of(joint.body2) - _angle_of(joint.body1) - joint._row(REFERENCE_ANGLE)
    return per_world(np.angle(np.exp(1j * turn)), joint._world.batch_size)


class PrismaticJoint(_Limited):
    """A slider: ``body2`` moves along ``axis`` (a world direction when made, turning with
    ``body1``) through ``anchor``, without turning relative to ``body1``; within
    ``lower_translation`` to ``upper_translation`` (m, from where it stands now), driven
    towards ``motor_speed`` (m/s) with at most ``max_motor_force`` (N), pulled back by a
    spring of ``spring_hertz`` and ``spring_damping_ratio``.
    """

    _link = PRISMATIC
    _lower, _upper = "lower_translation", "upper_translation"
    _names = ("lower_translation", "upper_translation", "motor_speed", "max_motor_force",
              "spring_hertz", "spring_damping_ratio")  # fmt: skip
    lower_translation = Column((LOWER,), "spring", doc="Lower limit along the axis (m).")
    upper_translation = Column((UPPER,), "spring", doc="Upper limit along the axis (m).")
    motor_speed = Column(
        (MOTOR_SPEED,), "spring", limit=SPEED_RANGE, doc="Motor's target speed (m/s)."
    )
    max_motor_force = Column((MAX_MOTOR,), "spring", rule=">= 0", doc="Motor's force (N).")
    spring_hertz, spring_damping_ratio = _hertz(), _ratio()

    def __init__(
        self,
        body1: Body,
        body2: Body,
        anchor: Any = None,
        axis: Any = (1.0, 0.0),
        *,
        lower_translation: Any = None,
        upper_translation: Any = None,
        motor_speed: Any = 0.0,
        max_motor_force: Any = 0.0,
        spring_hertz: Any = 0.0,
        spring_damping_ratio: Any = 0.0,
        break_force: Any = math.inf,
        collide_connected: bool = False,
    ) -> None:
        super().__init__(body1, body2, break_force, collide_connected)
        self._anchor = _world_point("anchor", anchor, body2)
        direction = _checks.vector2("axis", axis)
        length = float(np.hypot(*direction))
        if not length > 1e-12:
            raise ValueError(f"axis must be a non-zero vector, got {axis!r}")
        self._axis = direction / length
        low, high, self._limited = _limits(
            "translation", lower_translation, upper_translation, " m"
        )
        self.lower_translation, self.upper_translation = low, high
        self.motor_speed, self.max_motor_force = motor_speed, max_motor_force
        self.spring_hertz, self.spring_damping_ratio = spring_hertz, spring_damping_ratio

    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        columns = _pinned(self.body1, self.body2, self._anchor)
        angle = _angle_of(self.body1)
        c, s = np.cos(angle), np.sin(angle)
        ax, ay = self._axis
        columns[AXIS_X] = np.column_stack([c * ax + s * ay, -s * ax + c * ay])
        return columns

    @property
    def translation(self) -> Any:
        """How far ``body2``'s anchor is along the axis from ``body1``'s (m)."""
        if self._world is None:
            return 0.0
        a = _world_anchor(self, self.body1, ANCHOR_AX)
        b = _world_anchor(self, self.body2, ANCHOR_BX)
        axis = _turned(self._world.state.body[:, self.body1.slot], self._pair(AXIS_X))
        return per_world(np.sum((b - a) * axis, axis=1), self._world.batch_size)

    def _pair(self, column: int) -> np.ndarray:
        return self._world.state.spring[:, self._slot, column : column + 2]


def _turned(rows: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Body-frame vectors ``local`` (B, 2) turned by the bodies' angles (``rows`` (B, F))."""
    c, s = np.cos(rows[:, ANGLE]), np.sin(rows[:, ANGLE])
    return np.column_stack([c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]])


def _world_anchor(joint: Joint, body: Body, column: int) -> np.ndarray:
    """A joint's anchor on ``body`` (its columns from ``column``) in the world, (B, 2)."""
    rows = joint._world.state.body[:, body.slot]
    local = joint._world.state.spring[:, joint._slot, column : column + 2]
    return rows[:, X : Y + 1] + _turned(rows, local)


class WeldJoint(Joint):
    """``body1`` and ``body2`` held together at ``anchor`` and at the angle they have now:
    rigid (``hertz`` 0, the world's joint softness), or as a soft weld that bends like a
    spring of ``hertz`` and ``damping_ratio`` (a cantilever of planks).
    """

    _link = WELD
    _names = ("hertz", "damping_ratio")
    hertz = Column((HERTZ,), "spring", rule=">= 0", doc="Softness frequency (Hz, 0: rigid).")
    damping_ratio = _ratio()

    def __init__(
        self,
        body1: Body,
        body2: Body,
        anchor: Any = None,
        *,
        hertz: Any = 0.0,
        damping_ratio: Any = 0.0,
        break_force: Any = math.inf,
        collide_connected: bool = False,
    ) -> None:
        super().__init__(body1, body2, break_force, collide_connected)
        self._anchor = _world_point("anchor", anchor, body2)
        self.hertz, self.damping_ratio = hertz, damping_ratio

    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        return _pinned(self.body1, self.body2, self._anchor)


class DistanceJoint(Joint):
    """The distance between ``anchor1`` on ``body1`` and ``anchor2`` on ``body2`` (world
    points when made; default the centres) held at ``length`` (default: as it is now):
    a rod. With ``min_length``/``max_length`` it is free between them (a rope:
    ``min_length=0``); with ``spring_hertz`` > 0 a spring pulls it towards ``length``
    (free between the limits, 0 to any length by default).
    """

    _link = DISTANCE
    _names = ("min_length", "max_length", "spring_hertz", "spring_damping_ratio")
    length = Column((REST_LENGTH,), "spring", limit=LENGTH, doc="Rest length (m).")
    min_length = Column((LOWER,), "spring", limit=LENGTH, doc="Shortest length (m).")
    max_length = Column((UPPER,), "spring", limit=LENGTH, doc="Longest length (m).")
    spring_hertz, spring_damping_ratio = _hertz(), _ratio()

    def __init__(
        self,
        body1: Body,
        body2: Body,
        anchor1: Any = None,
        anchor2: Any = None,
        *,
        length: Any = None,
        min_length: Any = None,
        max_length: Any = None,
        spring_hertz: Any = 0.0,
        spring_damping_ratio: Any = 0.0,
        break_force: Any = math.inf,
        collide_connected: bool = False,
    ) -> None:
        super().__init__(body1, body2, break_force, collide_connected)
        self._anchor1 = _world_point("anchor1", anchor1, body1)
        self._anchor2 = _world_point("anchor2", anchor2, body2)
        distance = float(np.hypot(*(self._anchor2 - self._anchor1)))
        self.length = distance if length is None else length
        springy = _checks.non_negative("spring_hertz", spring_hertz) > 0.0
        low_default = 0.0 if springy else self.length
        high_default = 2.0 * envelope.COORDINATE if springy else self.length
        self.min_length = low_default if min_length is None else min_length
        self.max_length = (
            (self.length if min_length is not None else high_default)
            if max_length is None
            else max_length
        )
        if np.any(np.asarray(self.min_length) > np.asarray(self.max_length)):
            raise ValueError(
                f"min_length must be <= max_length, got {self.min_length} > {self.max_length}"
            )
        self.spring_hertz, self.spring_damping_ratio = spring_hertz, spring_damping_ratio
        self._names = ("length", *DistanceJoint._names)

    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        return {
            ANCHOR_AX: _locals(self.body1, self._anchor1),
            ANCHOR_BX: _locals(self.body2, self._anchor2),
        }

    @property
    def current_length(self) -> Any:
        """The anchors' distance now (m)."""
        if self._world is None:
            return float(np.hypot(*(self._anchor2 - self._anchor1)))
        a = _world_anchor(self, self.body1, ANCHOR_AX)
        b = _world_anchor(self, self.body2, ANCHOR_BX)
        return per_world(np.hypot(*(b - a).T), self._world.batch_size)


class MouseJoint(Joint):
    """A drag: the point of ``body`` under ``target`` (a world point) when made is pulled
    towards ``target`` by a soft spring of ``hertz`` and ``damping_ratio`` with at most
    ``max_force`` (N; default 1000 times the body's weight at 9.81 m/s^2), Box2D's mouse
    joint. Move ``target`` to drag; remove the joint to let go.
    """

    _link = MOUSE
    _names = ("hertz", "damping_ratio", "max_force")
    target = Column((ANCHOR_AX, ANCHOR_AY), "spring", limit=COORDINATE, doc="Where to (m).")
    hertz = Column((HERTZ,), "spring", rule="> 0", doc="Spring frequency (Hz).")
    damping_ratio = _ratio()
    max_force = Column((MAX_MOTOR,), "spring", rule="> 0", doc="Largest pull (N).")

    def __init__(
        self,
        body: Body,
        target: Any,
        *,
        max_force: Any = None,
        hertz: Any = 5.0,
        damping_ratio: Any = 0.7,
        break_force: Any = math.inf,
    ) -> None:
        super().__init__(body, body, break_force, True)
        self._grab = _world_point("target", target, body)
        self.hertz, self.damping_ratio = hertz, damping_ratio
        if max_force is None:
            max_force = 1000.0 * float(np.max(body.mass)) * 9.81
        self.max_force = max_force
        self._values["target"] = self._grab.copy()
        self._names = ("target", *MouseJoint._names)

    @property
    def body(self) -> Body:
        """The body being dragged."""
        return self.body2

    def _attach(self, world: Any) -> dict[int, np.ndarray]:
        return {ANCHOR_BX: _locals(self.body2, self._grab)}
