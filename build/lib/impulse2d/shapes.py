"""The friendly objects: ``Circle``, ``Box`` and ``Plane``, views of one body slot.

As in pymunk, an object holds no physics state of its own once it is in a world: every
attribute is a ``Column`` (``columns.py``, the descriptor springs and sensors use too)
that reads a fresh copy from the world's arrays (``world.state.body[:, slot, ...]``), and
every assignment validates its input and writes through ``edit``, which keeps derived
values consistent and wakes the body. Before ``World.add`` (and after ``World.remove``)
the object keeps its values itself, so nothing a user set up is lost by removing and
adding again.

In a batch of ``B`` worlds a property returns one value per world (shape ``(B,)`` or
``(B, 2)``) and a setter accepts either one value for every world or one per world. In
a single world (``B == 1``) values are plain floats and arrays of shape ``(2,)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks, edit, envelope
from .columns import (
    ANGULAR_SPEED,
    COORDINATE,
    DECELERATION,
    FRICTION_RANGE,
    RATE,
    RESTITUTION_RANGE,
    SIZE,
    SPEED,
    Column,
    Part,
    per_world,
)
from .core.state import (
    ANGLE,
    ANGULAR_DRAG,
    AWAKE,
    BOX,
    CIRCLE,
    DYNAMIC,
    ENABLED,
    FIRST_CONTACT,
    FIXED,
    FRICTION,
    HALF_H,
    HALF_W,
    HEALTH,
    KINEMATIC,
    LINEAR_DRAG,
    MASS,
    MOMENT,
    OMEGA,
    PLANE,
    RESTITUTION,
    ROLLING,
    SENSED,
    VX,
    VY,
    X,
    Y,
)

if TYPE_CHECKING:
    pass


class _Slot(Part):
    """What Circle, Box and Plane share: a body slot, validation."""

    _kind: int = -1
    _motion: int = FIXED
    _fixed_names: tuple[str, ...] = ()
    _saved: tuple[str, ...] = ()  # what a detached object keeps (see World.remove)

    def _check_settable(self, name: str) -> None:
        if name in self._fixed_names:
            raise AttributeError(f"{name} cannot be changed after construction")

    def _write(self, column: Column, stored: np.ndarray) -> None:
        """A body's write goes through ``edit``: it wakes what the change touches and
        rebuilds the mass properties that follow from it."""
        world = self._world
        state, layout = world.state, world.layout
        edit.write_body(state, layout, self._slot, column.columns, stored, moves=column.moves)
        if column.rebuild:
            edit.rebuild_mass(state, layout, self._slot)

    def _read(self, column: int, integer: bool = False) -> Any:
        world = self._world
        array = world.state.body_i if integer else world.state.body
        return per_world(array[:, self._slot, column].copy(), world.batch_size)

    def __repr__(self) -> str:
        where = f"slot {self._slot}" if self._world is not None else "not in a world"
        return f"<{type(self).__name__} {where}>"


class Body(_Slot):
    """A rigid body: the common part of ``Circle`` and ``Box``.

    Keyword arguments (SI units): ``position`` (m), ``velocity`` (m/s), ``angle`` (rad),
    ``angular_velocity`` (rad/s), ``mass`` (kg), ``restitution`` (>= 0; 1 is perfectly
    elastic; above 1 adds energy), ``friction`` (Coulomb coefficient >= 0),
    ``linear_drag`` and ``angular_drag`` (1/s: speeds decay as ``exp(-drag t)``),
    ``rolling_resistance`` (m/s^2: the speed falls by this much per second until the body
    stops, as a ball rolling on cloth in a top-down scene: 0.1 for a pool ball),
    ``health`` (N s, > 0; default inf, unbreakable: impacts closing faster than the
    world's ``damage_speed`` drain it by their impulse, and at 0 the body is switched
    off), ``fixed`` (never moves: infinite mass) and ``kinematic`` (moves with the
    velocity you give it, pushes dynamic bodies, is not pushed back: infinite mass).

    The tutorial gives fixed bodies "a high mass"; here they have infinite mass (zero
    inverse mass), so nothing can move them and no energy leaks into them.
    """

    position = Column((X, Y), moves=True, limit=COORDINATE, doc="Centre of mass (m), settable.")
    velocity = Column((VX, VY), limit=SPEED, doc="Linear velocity (m/s), settable.")
    angle = Column((ANGLE,), moves=True, doc="Rotation (rad, counter-clockwise), settable.")
    angular_velocity = Column((OMEGA,), limit=ANGULAR_SPEED, doc="Angular velocity (rad/s, CCW).")
    mass = Column((MASS,), rule=">= 0", rebuild=True, doc="Mass (kg, > 0 if dynamic), settable.")
    restitution = Column((RESTITUTION,), limit=RESTITUTION_RANGE, doc="Restitution coefficient.")
    friction = Column((FRICTION,), limit=FRICTION_RANGE, doc="Coulomb friction coefficient.")
    linear_drag = Column((LINEAR_DRAG,), limit=RATE, doc="Linear drag (1/s).")
    angular_drag = Column((ANGULAR_DRAG,), limit=RATE, doc="Angular drag (1/s).")
    rolling_resistance = Column(
        (ROLLING,), limit=DECELERATION, doc="Constant deceleration of the speed (m/s^2)."
    )
    health = Column(
        (HEALTH,), rule="> 0", finite=False, doc="Left before impacts break it (N s); inf: never."
    )

    _saved = (
        "position",
        "velocity",
        "angle",
        "angular_velocity",
        "mass",
        "restitution",
        "friction",
        "linear_drag",
        "angular_drag",
        "rolling_resistance",
        "health",
    )

    def __init__(
        self,
        *,
        position: Any = (0.0, 0.0),
        velocity: Any = (0.0, 0.0),
        angle: float = 0.0,
        angular_velocity: float = 0.0,
        mass: Any = 1.0,
        restitution: Any = 0.0,
        friction: Any = 0.6,
        linear_drag: Any = 0.0,
        angular_drag: Any = 0.0,
        rolling_resistance: Any = 0.0,
        health: Any = np.inf,
        fixed: bool = False,
        kinematic: bool = False,
    ) -> None:
        super().__init__()
        if not isinstance(fixed, (bool, np.bool_)) or not isinstance(kinematic, (bool, np.bool_)):
            raise ValueError(f"fixed and kinematic must be bools, got {fixed!r}, {kinematic!r}")
        if fixed and kinematic:
            raise ValueError("fixed and kinematic cannot both be True")
        self._motion = FIXED if fixed else KINEMATIC if kinematic else DYNAMIC
        if self._motion == FIXED:
            for name, value in (("velocity", velocity), ("angular_velocity", angular_velocity)):
                if np.any(_checks.real_array(name, value) != 0.0):
                    raise ValueError(f"{name} of a fixed body must be 0; use kinematic=True")
        values = {
            "position": position,
            "velocity": velocity,
            "angle": angle,
            "angular_velocity": angular_velocity,
            "restitution": restitution,
            "friction": friction,
            "linear_drag": linear_drag,
            "angular_drag": angular_drag,
            "rolling_resistance": rolling_resistance,
            "health": health,
        }
        for name, value in values.items():
            setattr(self, name, value)
        self.mass = mass

    def _check_value(self, name: str, array: np.ndarray) -> None:
        if name != "mass":
            return
        if self._motion == DYNAMIC and np.any(array <= 0.0):
            raise ValueError(f"mass of a dynamic body must be > 0, got {array[array <= 0].flat[0]}")
        # A fixed or kinematic body may keep mass 0 (it is never used); any other mass
        # must be in the envelope.
        _checks.within("mass", array[array != 0.0], *envelope.MASS, unit=" kg")

    # -- kind of body ----------------------------------------------------------------------
    @property
    def fixed(self) -> bool:
        """True if the body never moves."""
        return self._motion == FIXED

    @property
    def kinematic(self) -> bool:
        """True if the body moves only with the velocity it is given."""
        return self._motion == KINEMATIC

    @property
    def moment(self) -> Any:
        """Moment of inertia about the centre (kg m^2), derived from mass and size."""
        if self._world is None:
            return self._moment_of(self._values["mass"])
        return self._read(MOMENT)

    def _moment_of(self, mass: Any) -> Any:  # pragma: no cover - overridden
        raise NotImplementedError

    @property
    def awake(self) -> Any:
        """False while the body sleeps (bool per world). Fixed bodies are never awake."""
        if self._world is None:
            return self._motion != FIXED
        return per_world(
            self._world.state.body_i[:, self._slot, AWAKE] == 1, self._world.batch_size
        )

    @property
    def enabled(self) -> Any:
        """Whether the body takes part in each world; settable per world (shape (B,))."""
        if self._world is None:
            return True
        return per_world(
            self._world.state.body_i[:, self._slot, ENABLED] == 1, self._world.batch_size
        )

    @enabled.setter
    def enabled(self, value: Any) -> None:
        if self._world is None:
            raise ValueError("enabled can only be set on a body in a world; use World.add")
        batch = self._world.batch_size
        flags = np.asarray(value)
        if flags.dtype != np.bool_ or flags.shape not in ((), (batch,)):
            raise ValueError(f"enabled must be a bool or {batch} bools, got {value!r}")
        edit.set_enabled(
            self._world.state, self._world.layout, self._slot, np.broadcast_to(flags, (batch,))
        )

    @property
    def sensed(self) -> Any:
        """The slot (in ``world.sensors``) of the last sensor whose region this body's
        centre entered, -1 if none since ``World.reset_events`` (int per world)."""
        return self._read(SENSED, integer=True) if self._world is not None else -1

    @property
    def first_contact(self) -> Any:
        """The slot of the first body this one pushed against since
        ``World.reset_events``, -1 if none (int per world)."""
        return self._read(FIRST_CONTACT, integer=True) if self._world is not None else -1

    def wake(self) -> None:
        """Wake the body (and, at the next step, everything touching it)."""
        if self._world is not None:
            edit.wake(
                self._world.state, self._world.layout, np.arange(self._world.batch_size), self._slot
            )

    # -- forces ------------------------------------------------------------------------------
    def apply_force(self, force: Any, point: Any = None) -> None:
        """Add a force (N) acting over the next step at a world point (default: the centre).

        A force off the centre also applies the torque ``r x F``. Forces are cleared
        after every step. Fixed and kinematic bodies are not affected.
        """
        self._apply(force, point, "force")

    def apply_impulse(self, impulse: Any, point: Any = None) -> None:
        """Change momentum at once by ``impulse`` (N s) at a world point; wakes the body.

        This is what the tutorial's mouse cue does (its ``ApplyForce`` in collisions
        and for the cue is really an impulse: it changes velocity by ``J / m`` at once).
        """
        self._apply(impulse, point, "impulse")

    def _apply(self, vector: Any, point: Any, name: str) -> None:
        if self._world is None:
            raise ValueError(f"apply_{name} needs the body to be in a world; use World.add first")
        batch = self._world.batch_size
        push = _checks.batched(name, vector, batch, (2,))
        where = None if point is None else _checks.batched("point", point, batch, (2,))
        if where is not None:
            COORDINATE("point", where)
        edit.apply(self._world.state, self._world.layout, self._slot, name == "force", push, where)

    # -- geometry --------------------------------------------------------------------------
    def to_world(self, local_point: Any) -> np.ndarray:
        """A body-local point (m) in world coordinates: shape (2,), or (B, 2) in a batch.

        ``local_point`` is one point, or (in a batch) one point per world."""
        local = self._point("local_point", local_point)
        position, angle = np.asarray(self.position), np.asarray(self.angle)
        c, s = np.cos(angle), np.sin(angle)
        x = c * local[..., 0] - s * local[..., 1]
        y = s * local[..., 0] + c * local[..., 1]
        return position + np.stack([x, y], axis=-1)

    def to_local(self, world_point: Any) -> np.ndarray:
        """A world point (m) in this body's coordinates: shape (2,), or (B, 2) in a batch."""
        return self._to_local(self._point("world_point", world_point))

    def _to_local(self, point: np.ndarray) -> np.ndarray:
        d = point - np.asarray(self.position)
        angle = np.asarray(self.angle)
        c, s = np.cos(angle), np.sin(angle)
        return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)

    def _point(self, name: str, value: Any) -> np.ndarray:
        """A finite point (2,), or one per world (B, 2) when the body is in a batch."""
        batch = self._world.batch_size if self._world is not None else 1
        if batch == 1:
            return _checks.vector2(name, value)
        array = _checks.real_array(name, value)
        if array.shape not in ((2,), (batch, 2)):
            raise ValueError(f"{name} must have shape (2,) or ({batch}, 2), got {array.shape}")
        return array

    def is_inside(self, point: Any) -> Any:
        """True if the world point lies inside the shape (bool, or one per world)."""
        return self._contains_local(self._to_local(self._point("point", point)))

    def _contains_local(self, local: np.ndarray) -> Any:  # pragma: no cover - overridden
        raise NotImplementedError


class Circle(Body):
    """A solid disc of ``radius`` (m); moment of inertia ``m r^2 / 2``.

    All other keywords as in :class:`Body`. Example::

        ball = world.add(Circle(position=(0, 5), radius=0.5, mass=1.0, restitution=0.5))
    """

    _kind = CIRCLE
    _saved = (*Body._saved, "radius")
    radius = Column((HALF_W,), limit=SIZE, rebuild=True, moves=True, doc="Radius (m).")

    def __init__(self, *, radius: Any = 0.5, **body: Any) -> None:
        super().__init__(**body)
        self.radius = radius

    def _moment_of(self, mass: Any) -> Any:
        return 0.5 * mass * self.radius * self.radius

    def _contains_local(self, local: np.ndarray) -> Any:
        inside = local[..., 0] ** 2 + local[..., 1] ** 2 <= np.asarray(self.radius) ** 2
        return bool(inside) if inside.ndim == 0 else inside


class Box(Body):
    """A solid rectangle ``width`` x ``height`` (m) centred on ``position``.

    Moment of inertia ``m (w^2 + h^2) / 12`` (the tutorial's ``m w h / 12`` is wrong: it
    is not even dimensionally a moment for a non-square box). ``angle`` rotates it
    counter-clockwise. All other keywords as in :class:`Body`.
    """

    _kind = BOX
    _saved = (*Body._saved, "width", "height")
    width = Column((HALF_W,), limit=SIZE, rebuild=True, moves=True, scale=0.5, doc="Width (m).")
    height = Column((HALF_H,), limit=SIZE, rebuild=True, moves=True, scale=0.5, doc="Height (m).")

    def __init__(self, *, width: Any = 1.0, height: Any = 1.0, **body: Any) -> None:
        super().__init__(**body)
        self.width = width
        self.height = height

    def _moment_of(self, mass: Any) -> Any:
        return mass * (self.width * self.width + self.height * self.height) / 12.0

    def _contains_local(self, local: np.ndarray) -> Any:
        inside = (np.abs(local[..., 0]) <= 0.5 * np.asarray(self.width)) & (
            np.abs(local[..., 1]) <= 0.5 * np.asarray(self.height)
        )
        return bool(inside) if inside.ndim == 0 else inside


class Plane(_Slot):
    """An infinite fixed half-space: the points ``p`` with ``(p - point) . normal <= 0``.

    ``normal`` (any non-zero length; stored normalised) points out of the solid side,
    so a ground is ``Plane(normal=(0, 1), point=(0, 0))``. Unlike the tutorial's
    two-sided line, the solid side is a whole half-space, so nothing can tunnel
    through a plane however fast it moves.
    """

    _kind = PLANE
    _fixed_names = ("normal",)
    _saved = ("point", "restitution", "friction")
    point = Column((X, Y), moves=True, limit=COORDINATE, doc="A point on the surface (m).")
    restitution = Column((RESTITUTION,), limit=RESTITUTION_RANGE, doc="Restitution coefficient.")
    friction = Column((FRICTION,), limit=FRICTION_RANGE, doc="Coulomb friction coefficient.")

    def __init__(
        self,
        *,
        normal: Any = (0.0, 1.0),
        point: Any = (0.0, 0.0),
        restitution: Any = 0.0,
        friction: Any = 0.6,
    ) -> None:
        super().__init__()
        n = _checks.vector2("normal", normal)
        # A normal too short to normalise accurately (its square underflows) is refused.
        length = float(np.hypot(n[0], n[1]))
        if not length > 1e-150:
            raise ValueError(f"normal must be a non-zero vector (length > 1e-150), got {normal!r}")
        self._normal = n / length
        self.point = point
        self.restitution = restitution
        self.friction = friction

    @property
    def normal(self) -> np.ndarray:
        """Unit normal pointing out of the solid side."""
        return self._normal.copy()

    def is_inside(self, point: Any) -> Any:
        """True if the world point is in the solid half-space (on or behind the surface)."""
        p = _checks.vector2("point", point)
        depth = (p - np.asarray(self.point)) @ self._normal
        return bool(depth <= 0.0) if np.ndim(depth) == 0 else depth <= 0.0
