"""Struct-of-arrays storage for every body and spring slot of every world.

Layout (the reason the engine can step a thousand worlds in one pass):

* ``B`` worlds (the batch) share one set of ``N`` body *slots*. A slot has the same shape
  kind (circle, box, plane) and motion type (dynamic, kinematic, fixed) in every world;
  its size, mass, material and state may differ per world.
* Per-world fields have shape ``(B, N)``; vector state has a leading component axis,
  ``(3, B, N)`` for ``(x, y, angle)``, ``(vx, vy, angular_velocity)`` and
  ``(fx, fy, torque)``. Rows first means one component of every body is contiguous, so
  a gather of three components is one flat ``take`` and the integrator is one
  elementwise expression over ``3 * B * N`` numbers.
* The flat body index used by the pipeline is ``world * N + slot``; ``flat(name)`` gives
  the ``(T,)`` or ``(3, T)`` view with ``T = B * N``.
* A slot that is switched off in one world (a potted ball, a destroyed block) has
  ``enabled[w, slot] = False``: arrays keep their shapes, the pipeline skips it.

Units are SI throughout: metres, kilograms, seconds, radians.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Shape kinds, ordered so that a contact pair (A, B) always has kind(A) <= kind(B).
CIRCLE, BOX, PLANE = 0, 1, 2
FREE = -1  # an unused slot

# Motion types.
DYNAMIC, KINEMATIC, FIXED = 0, 1, 2


@dataclass(frozen=True)
class Field:
    """One stored array: its name, dtype, fill value and number of component rows."""

    name: str
    dtype: type
    default: float | bool | int
    rows: int = 0  # 0: shape (B, N); 3: shape (3, B, N)
    doc: str = ""


BODY_FIELDS: tuple[Field, ...] = (
    # state
    Field("pose", np.float64, 0.0, 3, "x (m), y (m), angle (rad)"),
    Field("vel", np.float64, 0.0, 3, "vx (m/s), vy (m/s), angular velocity (rad/s)"),
    Field("force", np.float64, 0.0, 3, "fx (N), fy (N), torque (N m), cleared every step"),
    Field("enabled", np.bool_, False, 0, "the body exists in this world"),
    Field("awake", np.bool_, False, 0, "dynamic or kinematic and not sleeping"),
    Field("sleep_time", np.float64, 0.0, 0, "seconds the body has been slow (s)"),
    Field("island", np.int64, -1, 0, "island id while asleep (flat index of a member)"),
    # parameters
    Field("mass", np.float64, 1.0, 0, "kg, as given"),
    Field("inv_mass", np.float64, 0.0, 0, "1/kg; 0 for fixed and kinematic bodies"),
    Field("moment", np.float64, 1.0, 0, "kg m^2 about the centre"),
    Field("inv_moment", np.float64, 0.0, 0, "1/(kg m^2); 0 for fixed and kinematic"),
    Field("half_width", np.float64, 0.0, 0, "m; the radius for circles"),
    Field("half_height", np.float64, 0.0, 0, "m; the radius for circles"),
    Field("bound", np.float64, 0.0, 0, "bounding radius (m): circle radius, box half-diagonal"),
    Field("normal_x", np.float64, 0.0, 0, "plane normal, pointing out of the solid side"),
    Field("normal_y", np.float64, 1.0, 0, ""),
    Field("restitution", np.float64, 0.0, 0, "coefficient of restitution"),
    Field("friction", np.float64, 0.0, 0, "Coulomb friction coefficient"),
    Field("linear_drag", np.float64, 0.0, 0, "1/s: velocity decays as exp(-d t)"),
    Field("angular_drag", np.float64, 0.0, 0, "1/s: angular velocity decays as exp(-d t)"),
    Field("rolling_resistance", np.float64, 0.0, 0, "m/s^2: constant deceleration of speed"),
)

SPRING_FIELDS: tuple[Field, ...] = (
    Field("enabled", np.bool_, False, 0, "the spring exists in this world"),
    Field("anchor_a", np.float64, 0.0, 2, "anchor on body 1, body-local (m)"),
    Field("anchor_b", np.float64, 0.0, 2, "anchor on body 2, body-local (m)"),
    Field("rest_length", np.float64, 0.0, 0, "m"),
    Field("stiffness", np.float64, 0.0, 0, "N/m"),
    Field("damping", np.float64, 0.0, 0, "N s/m, on the relative velocity along the spring"),
)


class Table:
    """Arrays for ``capacity`` slots in each of ``batch_size`` worlds; grows by doubling."""

    def __init__(self, fields: tuple[Field, ...], batch_size: int, capacity: int) -> None:
        self.fields = fields
        self.batch_size = batch_size
        self.capacity = capacity
        self.arrays: dict[str, np.ndarray] = {}
        for field in fields:
            self.arrays[field.name] = self._new(field, capacity)

    def _new(self, field: Field, capacity: int) -> np.ndarray:
        shape = (self.batch_size, capacity)
        if field.rows:
            shape = (field.rows, *shape)
        return np.full(shape, field.default, dtype=field.dtype)

    def grow(self, capacity: int) -> None:
        """Reallocate every array for ``capacity`` slots, keeping the existing ones."""
        for field in self.fields:
            old = self.arrays[field.name]
            new = self._new(field, capacity)
            new[..., : self.capacity] = old
            self.arrays[field.name] = new
        self.capacity = capacity

    def __getitem__(self, name: str) -> np.ndarray:
        return self.arrays[name]

    def flat(self, name: str) -> np.ndarray:
        """The ``(T,)`` or ``(rows, T)`` view of a field, ``T = batch_size * capacity``."""
        array = self.arrays[name]
        total = self.batch_size * self.capacity
        return array.reshape(total) if array.ndim == 2 else array.reshape(array.shape[0], total)

    def copy_arrays(self) -> dict[str, np.ndarray]:
        return {name: array.copy() for name, array in self.arrays.items()}


def grown(capacity: int, needed: int) -> int:
    """The next capacity: doubling, so adding n bodies costs O(n) copies in total."""
    while capacity < needed:
        capacity *= 2
    return capacity
