"""The world's state as plain arrays, and the layout of slots they share.

``B`` worlds (a batch; a plain world is a batch of one) share one layout of ``N`` body
slots, ``S`` spring slots and ``Q`` sensor slots. A slot has the same shape kind and
motion type in every world (``Layout``); everything else may differ per world and lives
in ``WorldState``, in arrays whose leading axis is the world:

==============  =====================  ======================================================
array           shape, dtype           what (columns below; SI units: m, kg, s, rad)
==============  =====================  ======================================================
``body``        (B, N, BODY_F) f8      pose, velocity, forces, mass, size, material, sleep
``body_i``      (B, N, BODY_I) i8      enabled, awake, island, events, broadphase order
``spring``      (B, S, SPRING_F) f8    springs and joints: anchors, parameters, impulses
``sensor``      (B, Q, SENSOR_F) f8    region of a sensor, enabled
``contact``     (B, C, CONTACT_F) f8   the contact points of the last step (warm start)
``contact_i``   (B, C, CONTACT_I) i8   their two bodies and feature id
``world_i``     (B, WORLD_I) i8        contact count, steps taken
``time``        (B,) f8                simulated time (s)
``hull``        (B, H, HULL_F) f8      a polygon's or capsule's outline (columns below)
==============  =====================  ======================================================

Columns are module constants (``X``, ``VX``, ``ENABLED``, ...), so a kernel reads
``body[w, i, VX]`` and the names are documented here once. The few arrays keep a
compiled call cheap: its cost grows with the number of arrays passed.

``hull`` is indexed by body slot like ``body`` (``H == N``), but it has one spare row
(``H == 1``) until the first polygon or capsule is added, so the worlds of circles and
boxes (pool, the tutorial's scenes) carry none of its 36 columns a slot. (One row, not
none: a GPU cannot take an array of no elements.)

A snapshot is a copy of the ``WorldState``; ``replicate`` repeats it along the world
axis. Contacts are kept sorted by ``(body A, body B, feature)`` in every world, with
``contact_count`` valid rows and zeros after them; ``C`` grows when a world needs more.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

# Shape kinds, ordered: a contact pair (A, B) has kind(A) <= kind(B). A capsule is a
# polygon of two vertices with a rounding radius, so it has no kind of its own.
CIRCLE, BOX, POLYGON, PLANE = 0, 1, 2, 3
FREE = -1  # an unused slot
# Motion types.
DYNAMIC, KINEMATIC, FIXED = 0, 1, 2

# -- body: float columns ------------------------------------------------------------------
X, Y, ANGLE = 0, 1, 2  # centre of mass (m) and rotation (rad, counter-clockwise)
VX, VY, OMEGA = 3, 4, 5  # velocity (m/s) and angular velocity (rad/s)
FX, FY, TORQUE = 6, 7, 8  # applied force (N) and torque (N m), cleared after each step
MASS, INV_MASS = 9, 10  # kg as given; 1/kg, 0 for fixed and kinematic bodies
MOMENT, INV_MOMENT = 11, 12  # kg m^2 about the centre; its inverse, 0 if not dynamic
HALF_W, HALF_H = 13, 14  # half width and height (m); both the radius for a circle
BOUND = 15  # bounding radius (m): the radius, a box's half diagonal, a polygon's farthest
# surface point from its centre of mass (its hull's BOUND_RADIUS), 0 for planes
NORMAL_X, NORMAL_Y = 16, 17  # a plane's unit normal, out of its solid side
RESTITUTION, FRICTION = 18, 19  # coefficients (mixed per contact by the world's rules)
LINEAR_DRAG, ANGULAR_DRAG = 20, 21  # 1/s: velocity decays as exp(-drag t)
ROLLING = 22  # rolling resistance (m/s^2): a constant deceleration of the speed
SLEEP_TIME = 23  # s the body has been slower than the sleep speed
HEALTH = 24  # drained by impacts (N s); the body is switched off at 0; inf: unbreakable
# Derived, kept current so a step need not recompute them for every body:
# COS, SIN: of a box's or polygon's angle, between steps (the narrowphase, broadphase use them)
COS, SIN = 25, 26
DAMP_LINEAR, DAMP_ANGULAR = 27, 28  # exp(-drag h) for the substep h = DAMP_H
DAMP_H = 29  # the substep the factors are for (0: recompute them)
BODY_F = 30

# -- body: integer columns ----------------------------------------------------------------
ENABLED = 0  # 1: the body takes part in this world
AWAKE = 1  # 1: moves this step (dynamic and not sleeping, or kinematic and moving)
ISLAND = 2  # while asleep: the island's id (the smallest slot in it); else -1
SENSED = 3  # the last sensor whose region the centre entered (-1: none since cleared)
FIRST_CONTACT = 4  # the first body this one pushed against since cleared (-1: none)
SAP_ORDER = 5  # not state: the broadphase's sorted slot order, a cache (any order works)
JOINT_LIST = 6  # the first joint row at this body (-1: none); the rest by NEXT_AT_A, _B
BODY_I = 7

# -- springs and joints: one table, a row each (``LINK`` says which) ------------------------
ANCHOR_AX, ANCHOR_AY = 0, 1  # on body 1, body-local (m); a mouse joint's target, world (m)
ANCHOR_BX, ANCHOR_BY = 2, 3  # on body 2, body-local (m)
REST_LENGTH, STIFFNESS, DAMPING = 4, 5, 6  # m, N/m, N s/m (a spring, along it); a distance
SPRING_ON = 7  # 1.0: the spring or joint acts in this world (0 also once a joint broke)
LINK = 8  # SPRING (an explicit force, integrate.apply_springs) or a joint kind (joints.py)
REFERENCE_ANGLE = 9  # angle of body 2 less body 1's when the joint was made (rad)
AXIS_X, AXIS_Y = 10, 11  # a prismatic joint's axis, in body 1's frame (unit)
LOWER, UPPER = 12, 13  # limits: angle (rad), translation or length (m)
LIMITED = 14  # 1.0: the limits act (a distance joint's always do)
MOTOR_SPEED, MAX_MOTOR = 15, 16  # rad/s or m/s; N m or N (0: no motor); a mouse's force
HERTZ, DAMPING_RATIO = 17, 18  # a joint's spring or softness (0 Hz: none, or rigid)
BREAK_FORCE = 19  # N: the joint switches off past it (0: it never breaks)
IMPULSE_X, IMPULSE_Y = 20, 21  # accumulated a substep (N s): the point, or a slider's block
IMPULSE_ANGLE, IMPULSE_MOTOR = 22, 23  # a weld's angle (N m s); the motor's
IMPULSE_LOWER, IMPULSE_UPPER, IMPULSE_SPRING = 24, 25, 26  # the limits', the spring's
FORCE_X, FORCE_Y, JOINT_TORQUE = 27, 28, 29  # what the joint did to body 2 over the step
COLLIDE = 30  # 1.0: the joined bodies collide (a joint's collide_connected)
NEXT_AT_A, NEXT_AT_B = 31, 32  # the next joint row at body 1 and at body 2 (-1: none)
SPRING_F = 33
# LINK values: what a row of the spring table is.
SPRING, REVOLUTE, PRISMATIC, WELD, DISTANCE, MOUSE = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0

# -- sensors: a circle (radius in SENSOR_HW) or a box -----------------------------------------
SENSOR_X, SENSOR_Y, SENSOR_ANGLE = 0, 1, 2
SENSOR_HW, SENSOR_HH = 3, 4  # m
SENSOR_ON = 5  # 1.0: the sensor watches in this world
SENSOR_F = 6
# Sensor flags (Layout.sensors[:, 1]).
SENSE_OUTSIDE = 1  # trigger when the centre is outside the region instead of inside
SENSE_DISABLES = 2  # switch the body off when triggered

# -- contacts --------------------------------------------------------------------------------
NORMAL_IMPULSE, TANGENT_IMPULSE = 0, 1  # accumulated per substep (N s): the warm start
STEP_IMPULSE = 2  # normal impulse applied over the whole last step (N s)
APPROACH = 3  # normal relative velocity at the start of the step (m/s, < 0: closing)
POINT_X, POINT_Y = 4, 5  # the point, midway between the surfaces, at the step start (m)
CONTACT_NX, CONTACT_NY = 6, 7  # unit normal from A to B
SEPARATION = 8  # gap along the normal at the step start (m, < 0: overlap)
GROSS_IMPULSE = 9  # |normal| + |tangent| of every push over the last step, summed (N s)
# A bound on the angular impulse (N m s) the point exerted over the last step by keeping
# its anchors (contacts.follow_bodies): the farthest they moved apart times the gross.
KEPT_TORQUE = 10
CONTACT_F = 11
BODY_A, BODY_B, FEATURE = 0, 1, 2  # slots, and which vertex/face made the point
CONTACT_I = 3

# -- hulls: a polygon's outline in its body's frame, whose origin is the centre of mass ------
VERTEX_COUNT = 0  # 2 (a capsule or segment) to MAX_VERTICES, as a float
ROUNDING = 1  # radius (m) the outline is rounded by: every point within it is solid
UNIT_MOMENT = 2  # moment of inertia per kg about the centre of mass (m^2)
BOUND_RADIUS = 3  # farthest surface point from the centre of mass (m)
VERTEX0 = 4  # vertex k at (VERTEX0 + 2k, VERTEX0 + 2k + 1), counter-clockwise (m)
MAX_VERTICES = 8
EDGE_NORMAL0 = VERTEX0 + 2 * MAX_VERTICES  # unit outward normal of the edge from vertex k to k + 1
HULL_F = EDGE_NORMAL0 + 2 * MAX_VERTICES

# -- per world --------------------------------------------------------------------------------
CONTACT_COUNT, STEPS = 0, 1
WORLD_I = 2


def body_defaults() -> tuple[np.ndarray, np.ndarray]:
    """One free slot's float and integer row."""
    row = np.zeros(BODY_F)
    row[[MASS, MOMENT, NORMAL_Y, COS, DAMP_LINEAR, DAMP_ANGULAR]] = 1.0
    row[HEALTH] = np.inf
    row_i = np.zeros(BODY_I, np.int64)
    row_i[[ISLAND, SENSED, FIRST_CONTACT, JOINT_LIST]] = -1
    return row, row_i


@dataclass
class WorldState:
    """Everything that evolves, for every world of a batch (see the module docstring)."""

    body: np.ndarray
    body_i: np.ndarray
    spring: np.ndarray
    sensor: np.ndarray
    contact: np.ndarray
    contact_i: np.ndarray
    world_i: np.ndarray
    time: np.ndarray
    hull: np.ndarray

    def __setattr__(self, name: str, value: object) -> None:
        # Every replaced array (a grown one, a put-back one) counts up ``generation``, so a
        # caller that keeps the arrays of a call (the runner's fast path) knows when
        # they are stale without comparing eight of them.
        object.__setattr__(self, name, value)
        object.__setattr__(self, "generation", self.__dict__.get("generation", 0) + 1)

    @staticmethod
    def empty(batch: int, bodies: int, springs: int, sensors: int, contacts: int) -> WorldState:
        row, row_i = body_defaults()
        body_i = np.broadcast_to(row_i, (batch, bodies, BODY_I)).copy()
        body_i[:, :, SAP_ORDER] = np.arange(bodies)
        return WorldState(
            body=np.broadcast_to(row, (batch, bodies, BODY_F)).copy(),
            body_i=body_i,
            spring=np.zeros((batch, springs, SPRING_F)),
            sensor=np.zeros((batch, sensors, SENSOR_F)),
            contact=np.zeros((batch, contacts, CONTACT_F)),
            contact_i=np.zeros((batch, contacts, CONTACT_I), np.int64),
            world_i=np.zeros((batch, WORLD_I), np.int64),
            time=np.zeros(batch),
            hull=np.zeros((batch, 1, HULL_F)),
        )

    @property
    def batch_size(self) -> int:
        return self.time.size

    @property
    def contact_capacity(self) -> int:
        return self.contact.shape[1]

    def arrays(self) -> dict[str, np.ndarray]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def copy(self) -> WorldState:
        return WorldState(**{name: array.copy() for name, array in self.arrays().items()})

    def repeat(self, batch: int) -> WorldState:
        """This one-world state repeated ``batch`` times along the world axis."""
        return WorldState(
            **{name: np.repeat(array, batch, axis=0) for name, array in self.arrays().items()}
        )

    def grow_bodies(self, capacity: int) -> None:
        """Room for ``capacity`` body slots; new slots are free."""
        old = self.body.shape[1]
        row, row_i = body_defaults()
        body = np.broadcast_to(row, (self.batch_size, capacity, BODY_F)).copy()
        body_i = np.broadcast_to(row_i, (self.batch_size, capacity, BODY_I)).copy()
        body[:, :old], body_i[:, :old] = self.body, self.body_i
        body_i[:, :, SAP_ORDER] = np.arange(capacity)
        self.body, self.body_i = body, body_i
        if self.hull.shape[1] == old:  # a row a slot already (or one slot, one spare row)
            self.grow_rows("hull", capacity)

    def make_hulls(self) -> None:
        """Give ``hull`` a row for every body slot (the first polygon needs them)."""
        if self.hull.shape[1] < self.body.shape[1]:
            self.grow_rows("hull", self.body.shape[1])

    def grow_rows(self, name: str, capacity: int) -> None:
        """Room for ``capacity`` rows in ``spring``, ``sensor``, ``hull`` or the contact
        arrays."""
        names = ("contact", "contact_i") if name == "contact" else (name,)
        for array_name in names:
            old = getattr(self, array_name)
            new = np.zeros((old.shape[0], capacity, old.shape[2]), old.dtype)
            new[:, : old.shape[1]] = old
            setattr(self, array_name, new)

    def put(self, source: WorldState, targets: np.ndarray, sources: np.ndarray) -> None:
        """Copy worlds ``sources`` of ``source`` into worlds ``targets`` of this state."""
        if source.contact_capacity > self.contact_capacity:
            self.grow_rows("contact", source.contact_capacity)
        for name, array in self.arrays().items():
            saved = getattr(source, name)
            if name in ("contact", "contact_i"):
                array[targets] = 0
                array[targets, : saved.shape[1]] = saved[sources]
            else:
                array[targets] = saved[sources]


class Layout:
    """What every world shares: which kind of shape and motion each slot holds, which
    bodies each spring joins and what each sensor is. Changes only when objects are
    added or removed, so kernels may rely on it for a whole run.

    * ``shapes`` (N, 2) int64: shape kind (``CIRCLE``, ``BOX``, ``PLANE``, ``FREE``) and
      motion type (``DYNAMIC``, ``KINEMATIC``, ``FIXED``) of each body slot;
    * ``springs`` (S, 2) int64: the body slots a spring joins (-1: a free slot);
    * ``sensors`` (Q, 2) int64: region kind (``CIRCLE`` or ``BOX``, -1: free) and flags
      (``SENSE_OUTSIDE``, ``SENSE_DISABLES``).

    The three are views of one array, ``rows`` (N + S + Q, 2), so a kernel takes one
    argument for all of them (``pipeline.split_layout`` cuts it again).
    """

    def __init__(self, bodies: int, springs: int, sensors: int) -> None:
        self.rows = np.full((bodies + springs + sensors, 2), -1, np.int64)
        self.rows[:bodies, 1] = DYNAMIC
        self._sizes = (bodies, springs, sensors)

    @property
    def shapes(self) -> np.ndarray:
        return self.rows[: self._sizes[0]]

    @property
    def springs(self) -> np.ndarray:
        n, s, _ = self._sizes
        return self.rows[n : n + s]

    @property
    def sensors(self) -> np.ndarray:
        n, s, _ = self._sizes
        return self.rows[n + s :]

    @property
    def kind(self) -> np.ndarray:
        return self.shapes[:, 0]

    @property
    def motion(self) -> np.ndarray:
        return self.shapes[:, 1]

    def copy(self) -> Layout:
        twin = Layout(*self._sizes)
        twin.rows[:] = self.rows
        return twin

    def grow(self, name: str, capacity: int) -> None:
        """Room for ``capacity`` slots of ``'shapes'``, ``'springs'`` or ``'sensors'``."""
        parts = {"shapes": self.shapes, "springs": self.springs, "sensors": self.sensors}
        sizes = {key: part.shape[0] for key, part in parts.items()}
        sizes[name] = capacity
        grown_layout = Layout(sizes["shapes"], sizes["springs"], sizes["sensors"])
        for key, part in parts.items():
            getattr(grown_layout, key)[: part.shape[0]] = part
        self.rows, self._sizes = grown_layout.rows, grown_layout._sizes

    def same_as(self, other: Layout) -> bool:
        return self._sizes == other._sizes and np.array_equal(self.rows, other.rows)


def grown(capacity: int, needed: int) -> int:
    """The next capacity: doubling, so adding n objects costs O(n) copies in total."""
    capacity = max(capacity, 1)
    while capacity < needed:
        capacity *= 2
    return capacity
