"""The stages of ``World.step``, one method each, in pipeline order.

Everything here works on the flat views of the body arrays (``(T,)`` and ``(3, T)``,
``T = worlds * slots``). Per-body terms that only change when something is woken, put
to sleep, switched on or off, or edited (which bodies move, gravity times ``h``, drag
factors) are cached in ``StepTerms`` and rebuilt only after such a change, so a step in
which nothing changed state does no work for them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import springs as spring_forces
from .contacts import Cache, Contacts, build, point_keys, soft_constraint
from .narrowphase import CIRCLE_CIRCLE, COLLIDE, FEATURES, PAIR_SHAPES, Points, Shapes
from .sleep import fall_asleep
from .state import BOX, CIRCLE, PLANE

_LOCAL_RADIX = 1 << 20  # slots per world in a capacity-independent local key


@dataclass
class StepTerms:
    """Per-body terms of a step, valid until the world's state version changes (bodies
    that wake, sleep or are switched on or off refresh only their own entries).

    ``index`` lists the bodies that move (awake dynamic or kinematic). When they are few
    (a batch whose worlds have mostly come to rest), per-body work runs on them only
    (``compact``); otherwise it runs on whole arrays, which is cheaper per body.
    """

    version: int
    h: float
    movable: np.ndarray  # (T,) bool: dynamic, enabled and awake (moved by forces, contacts)
    moving: np.ndarray  # (T,) bool: enabled and awake (dynamic or moving kinematic)
    present: np.ndarray  # (T,) bool: enabled circles and boxes (in the broadphase)
    index: np.ndarray  # (k,) flat indices of the moving bodies
    index3: np.ndarray  # (3k,) their entries in the flattened (3, T) arrays
    compact: bool  # integrate only the moving bodies
    travel: np.ndarray  # (T,) float: h where moving, else 0 (integrate positions)
    accel_h: np.ndarray  # (3, T): h * gravity on movable bodies
    damping: np.ndarray  # (3, T): exp(-drag h) on movable bodies, else 1
    inv_mass: np.ndarray  # (T,) 1/m on movable bodies, else 0
    inv_moment: np.ndarray  # (T,)
    rolling_h: np.ndarray  # (T,) h * rolling resistance on movable bodies, else 0
    rolling: np.ndarray  # flat indices of the bodies with rolling resistance


_COMPACT_FRACTION = 0.4  # below this fraction of moving bodies, integrate by index


class Integrator:
    """Semi-implicit Euler for one step's substeps: ``v = v exp(-drag h) + h a``, then
    ``x += h v`` with the solved velocity. Works on every body, or, when few move, only on
    the moving ones by index (``StepTerms.compact``)."""

    def __init__(
        self,
        vel: np.ndarray,
        pose: np.ndarray,
        terms: StepTerms,
        accel_h: np.ndarray,
        accelerated: bool,
    ) -> None:
        self.vel, self.pose, self.terms = vel, pose, terms
        self.accel_h = accel_h if accelerated else None  # None: no gravity, no forces
        if terms.compact:
            self.index3 = terms.index3
            self.damping = terms.damping.reshape(-1)[self.index3]
            self.accel = None if self.accel_h is None else accel_h.reshape(-1)[self.index3]
            self.step = terms.h
        else:
            self.travel = np.empty_like(vel)

    def velocities(self) -> None:
        if self.terms.compact:
            flat = self.vel.reshape(-1)
            moved = flat[self.index3] * self.damping
            flat[self.index3] = moved if self.accel is None else moved + self.accel
        else:
            self.vel *= self.terms.damping
            if self.accel_h is not None:
                self.vel += self.accel_h
        rolling = self.terms.rolling
        if rolling.size:
            # Rolling resistance takes a fixed amount off the speed each substep, never
            # turning the body around: v *= max(0, 1 - a h / |v|).
            vx, vy = self.vel[0, rolling], self.vel[1, rolling]
            speed = np.hypot(vx, vy)
            keep = np.maximum(1.0 - self.terms.rolling_h[rolling] / np.maximum(speed, 1e-300), 0.0)
            self.vel[0, rolling], self.vel[1, rolling] = vx * keep, vy * keep

    def positions(self) -> None:
        if self.terms.compact:
            self.pose.reshape(-1)[self.index3] += self.vel.reshape(-1)[self.index3] * self.step
            return
        np.multiply(self.vel, self.terms.travel, out=self.travel)
        self.pose += self.travel


def _empty_points() -> Points:
    empty = np.zeros(0)
    return Points(np.zeros(0, np.int64), *([empty] * 7), np.zeros(0, np.int64))


class StepStages:
    """Mixin of ``World``: the pipeline stages."""

    def _step_terms(self, h: float) -> StepTerms:
        """The step terms, rebuilt after a change (see ``_touch``): fully after an edit,
        or only for the bodies that woke up or fell asleep since the last step."""
        terms = self._terms
        if terms is None or terms.version != self._version or terms.h != h:
            self._woken = []
            self._terms = self._full_terms(h)
            return self._terms
        if self._woken:
            changed = np.unique(np.concatenate(self._woken))
            self._woken = []
            self._refresh_terms(terms, changed)
        return terms

    def _full_terms(self, h: float) -> StepTerms:
        flat = self._views
        total = flat["awake"].size
        # Per-body factors that do not depend on who is awake, kept so that an incremental
        # refresh selects exactly the same numbers a full rebuild would.
        # Drag multiplies velocity by exp(-drag h) per substep: exactly exp(-drag t) over
        # any number of steps (an explicit v -= drag v h would drift from it).
        self._drag_factors = (np.exp(-h * flat["linear_drag"]), np.exp(-h * flat["angular_drag"]))
        terms = StepTerms(
            version=self._version,
            h=h,
            movable=np.zeros(total, dtype=bool),
            moving=np.zeros(total, dtype=bool),
            present=np.zeros(total, dtype=bool),
            index=np.zeros(0, np.int64),
            index3=np.zeros(0, np.int64),
            compact=False,
            travel=np.zeros(total),
            accel_h=np.zeros((3, total)),
            damping=np.ones((3, total)),
            inv_mass=np.zeros(total),
            inv_moment=np.zeros(total),
            rolling_h=np.zeros(total),
            rolling=np.zeros(0, np.int64),
        )
        self._refresh_terms(terms, np.arange(total))
        return terms

    def _refresh_terms(self, terms: StepTerms, bodies: np.ndarray) -> None:
        """Recompute the awake-dependent terms of some bodies, in place."""
        flat, h = self._views, terms.h
        enabled = flat["enabled"][bodies]
        terms.present[bodies] = enabled & self._solid_flat[bodies]
        moving = flat["awake"][bodies] & enabled
        movable = moving & self._dynamic_flat[bodies]
        terms.moving[bodies] = moving
        terms.movable[bodies] = movable
        terms.travel[bodies] = np.where(moving, h, 0.0)
        terms.accel_h[0, bodies] = np.where(movable, h * self._gravity[0], 0.0)
        terms.accel_h[1, bodies] = np.where(movable, h * self._gravity[1], 0.0)
        linear, angular = self._drag_factors
        terms.damping[0, bodies] = np.where(movable, linear[bodies], 1.0)
        terms.damping[1, bodies] = terms.damping[0, bodies]
        terms.damping[2, bodies] = np.where(movable, angular[bodies], 1.0)
        terms.inv_mass[bodies] = np.where(movable, flat["inv_mass"][bodies], 0.0)
        terms.inv_moment[bodies] = np.where(movable, flat["inv_moment"][bodies], 0.0)
        terms.rolling_h[bodies] = np.where(movable, h * flat["rolling_resistance"][bodies], 0.0)
        terms.rolling = np.flatnonzero(terms.rolling_h)
        total = terms.moving.size
        terms.index = np.flatnonzero(terms.moving)
        terms.index3 = np.concatenate([terms.index, terms.index + total, terms.index + 2 * total])
        terms.compact = terms.index.size < _COMPACT_FRACTION * total

    def _speed_bound(self, terms: StepTerms) -> np.ndarray:
        """An upper bound on how fast any point of each body moves (m/s):
        ``|vx| + |vy| + R |w|`` (0 for bodies that do not move)."""
        vel, bound = self._views["vel"], self._views["bound"]
        if not terms.compact:
            speed = np.abs(vel[0]) + np.abs(vel[1]) + np.abs(vel[2]) * bound
            return np.where(terms.moving, speed, 0.0)
        index = terms.index
        v = np.abs(vel.reshape(-1)[terms.index3]).reshape(3, -1)
        speed = np.zeros(bound.size)
        speed[index] = v[0] + v[1] + v[2] * bound[index]
        return speed

    def _candidate_pairs(
        self, terms: StepTerms, speed: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pairs worth a narrowphase test: broadphase pairs whose *tight* boxes overlap (the
        fat boxes only say they might, soon) plus body-plane pairs, with something awake."""
        flat = self._views
        self._update_extents(terms)
        travel = speed * dt
        # Tight boxes: the shape's box grown on each side by how far the body can travel this
        # step and by half its speculative distance; fat boxes by two more steps of travel.
        grow = travel + self._half_spec
        margin = self._margin_base + 2.0 * travel
        x, y = flat["pose"][0], flat["pose"][1]
        keys, body_a, body_b = self._broadphase.update(
            x,
            y,
            self._extent_x,
            self._extent_y,
            grow,
            margin,
            terms.index,
            terms.present,
            self._allowed,
            self._kind,
        )
        awake = flat["awake"]
        worlds = np.unique(terms.index // self._bodies.capacity)
        if 2 * worlds.size < self._batch:  # few worlds move: look only at their pairs
            rows = self._broadphase.rows_of_worlds(worlds)
            rows = rows[awake[body_a[rows]] | awake[body_b[rows]]]
        else:
            rows = np.flatnonzero(awake[body_a] | awake[body_b])
        keys, body_a, body_b = keys[rows], body_a[rows], body_b[rows]
        grow_ab = grow[body_a] + grow[body_b]
        near = np.abs(x[body_a] - x[body_b]) < (
            self._extent_x[body_a] + self._extent_x[body_b] + grow_ab
        )
        near &= np.abs(y[body_a] - y[body_b]) < (
            self._extent_y[body_a] + self._extent_y[body_b] + grow_ab
        )
        if not near.all():
            keys, body_a, body_b = keys[near], body_a[near], body_b[near]
        if self._plane_keys.size:
            on = flat["enabled"][self._plane_a] & awake[self._plane_a]
            keys = np.concatenate([keys, self._plane_keys[on]])
            body_a = np.concatenate([body_a, self._plane_a[on]])
            body_b = np.concatenate([body_b, self._plane_b[on]])
        return keys, body_a, body_b

    def _update_extents(self, terms: StepTerms) -> None:
        """Axis-aligned half extents of boxes that can move or must be re-inserted:
        ``(|cos| w + |sin| h, |sin| w + |cos| h)`` for half sizes ``w, h``."""
        boxes = self._box_flat
        if boxes.size == 0:
            return
        boxes = boxes[terms.moving[boxes] | self._broadphase.stale[boxes]]
        if boxes.size == 0:
            return
        flat = self._views
        angle = flat["pose"][2, boxes]
        c, s = np.abs(np.cos(angle)), np.abs(np.sin(angle))
        hw, hh = flat["half_width"][boxes], flat["half_height"][boxes]
        self._extent_x[boxes] = c * hw + s * hh
        self._extent_y[boxes] = s * hw + c * hh

    def _narrowphase(
        self, keys: np.ndarray, body_a: np.ndarray, body_b: np.ndarray, speed: np.ndarray, dt: float
    ) -> Points:
        """Contact points of every candidate pair, by the table in ``narrowphase.COLLIDE``."""
        if keys.size == 0:
            return _empty_points()
        n = self._bodies.capacity
        kind_span = self._batch * n * n  # keys of one pair kind lie in [k span, (k+1) span)
        edges = np.searchsorted(keys, np.arange(6) * kind_span)
        # How close a pair must be for a (speculative) contact: what the two can close this
        # step plus their speculative distances (the same growth as their tight boxes).
        margin = (
            self._half_spec[body_a] + self._half_spec[body_b] + (speed[body_a] + speed[body_b]) * dt
        )
        parts = []
        for pair_kind, collide in COLLIDE.items():
            lo, hi = edges[pair_kind], edges[pair_kind + 1]
            if lo == hi:
                continue
            a, b = body_a[lo:hi], body_b[lo:hi]
            kind_a, kind_b = PAIR_SHAPES[pair_kind]
            moving = pair_kind == CIRCLE_CIRCLE  # the time of impact needs velocities
            # A number per pair for coincident discs (see circle_circle); others ignore it.
            tag = ((a % n) * 65537 + b % n).astype(np.float64) if moving else None
            found = collide(
                self._shapes(kind_a, a, moving),
                self._shapes(kind_b, b, moving),
                margin[lo:hi],
                tag,
                dt,
            )
            if found.pair.size:
                found.pair += lo
                parts.append(found)
        if not parts:
            return _empty_points()
        return parts[0] if len(parts) == 1 else Points.concatenate(parts)

    def _shapes(self, kind: int, index: np.ndarray, with_velocity: bool = False) -> Shapes:
        flat = self._views
        pose = flat["pose"]
        shapes = Shapes(pose[0, index], pose[1, index])
        if kind == CIRCLE:
            shapes.half_w = flat["half_width"][index]
            if with_velocity:
                vel = flat["vel"]
                shapes.vx, shapes.vy = vel[0, index], vel[1, index]
        elif kind == BOX:
            angle = pose[2, index]
            shapes.cos, shapes.sin = np.cos(angle), np.sin(angle)
            shapes.half_w, shapes.half_h = flat["half_width"][index], flat["half_height"][index]
        elif kind == PLANE:
            shapes.normal_x, shapes.normal_y = flat["normal_x"][index], flat["normal_y"][index]
        return shapes

    def _wake_touched(self, first: np.ndarray, second: np.ndarray, springs: tuple | None) -> bool:
        """Something awake touching a sleeping body (by a contact point or a spring) wakes
        the sleeper's whole island. Returns whether anything woke."""
        if springs is not None:
            first, second = (
                np.concatenate([first, springs[0]]),
                np.concatenate([second, springs[1]]),
            )
        if first.size == 0:
            return False
        awake, dynamic = self._views["awake"], self._dynamic_flat
        awake_a, awake_b = awake[first], awake[second]
        if (awake_a == awake_b).all():
            return False
        hit = np.concatenate(
            [
                first[~awake_a & awake_b & dynamic[first]],
                second[~awake_b & awake_a & dynamic[second]],
            ]
        )
        if hit.size == 0:
            return False
        self._wake_islands(np.unique(hit))
        return True

    def _accelerations(self, terms: StepTerms, h: float) -> np.ndarray:
        """``h`` times each body's acceleration: gravity (the force ``m g`` divided by
        ``m``) plus applied forces ``F / m`` and torques ``tau / I``."""
        if not self._forces_pending:
            return terms.accel_h
        force = self._views["force"]
        return terms.accel_h + h * np.stack(
            [force[0] * terms.inv_mass, force[1] * terms.inv_mass, force[2] * terms.inv_moment]
        )

    def _contacts(
        self,
        terms: StepTerms,
        accel_h: np.ndarray,
        points: Points,
        keys: np.ndarray,
        body_a: np.ndarray,
        body_b: np.ndarray,
        h: float,
    ) -> Contacts | None:
        """Constraints for the points: keys, materials, soft parameters, warm start."""
        flat = self._views
        pair_key = keys[points.pair]
        a, b = body_a[points.pair], body_b[points.pair]
        n = self._bodies.capacity
        key = point_keys(pair_key, points.feature)
        carried = self._cache.lookup(key)
        active = self._active_points(a, b, points.separation, carried, terms)
        if active is not None:
            if not active.any():
                return None
            rows = np.flatnonzero(active)
            points, pair_key, a, b, key = (
                points.take(rows),
                pair_key[rows],
                a[rows],
                b[rows],
                key[rows],
            )
            carried = tuple(array[rows] for array in carried)
        kind = pair_key // (self._batch * n * n)
        local = ((kind * _LOCAL_RADIX + a % n) * _LOCAL_RADIX + b % n) * FEATURES + points.feature
        hertz = min(self.contact_hertz, 0.25 / h)
        softness = (
            soft_constraint(hertz, self.contact_damping_ratio, h),
            soft_constraint(2.0 * hertz, self.contact_damping_ratio, h),
        )
        bodies = {
            "inv_mass": terms.inv_mass,
            "inv_moment": terms.inv_moment,
            "restitution": flat["restitution"],
            "friction": flat["friction"],
            "movable": terms.movable,
            "pose": flat["pose"],
            "vel": flat["vel"],
            "accel_h": accel_h if self._forces_pending or self._gravity.any() else None,
        }
        return build(key, local, a, b, points, bodies, carried, self._rules, softness, h)

    def _active_points(
        self,
        a: np.ndarray,
        b: np.ndarray,
        separation: np.ndarray,
        carried: tuple[np.ndarray, ...],
        terms: StepTerms,
    ) -> np.ndarray | None:
        """Which points can push this step (None: all of them).

        With no gravity, forces or springs, a point between two bodies at rest that do not
        overlap and carry no impulse stays at zero impulse unless a body it touches is set
        moving by another point; so activity spreads from the moving points through shared
        bodies and the rest (a freshly racked set of balls before the cue ball arrives)
        costs nothing. Skipping them changes no result: their impulses would be zero.
        """
        if self._gravity.any() or self._forces_pending or self._springs_used:
            return None
        vel = self._views["vel"]
        moving = (vel[0] != 0.0) | (vel[1] != 0.0) | (vel[2] != 0.0)
        active = moving[a] | moving[b] | (separation < 0.0) | (carried[0] != 0.0)
        active |= carried[1] != 0.0
        if active.all():
            return None
        hot = np.zeros(moving.size, dtype=bool)
        movable = terms.movable
        count = int(active.sum())
        while count:
            hot[a[active]] = True
            hot[b[active]] = True
            hot &= movable  # fixed bodies do not pass motion on
            active |= hot[a] | hot[b]
            now = int(active.sum())
            if now == count:
                break
            count = now
        return active

    def _active_springs(self) -> tuple | None:
        """Flat body indices and parameters of the springs that act this step, or None."""
        slots = np.flatnonzero(self._spring_a >= 0)
        if slots.size == 0:
            return None
        flat = self._views
        n, s = self._bodies.capacity, self._springs
        world = np.repeat(np.arange(self._batch), slots.size)
        slot = np.tile(slots, self._batch)
        a, b = world * n + self._spring_a[slot], world * n + self._spring_b[slot]
        on = s["enabled"][world, slot] & flat["enabled"][a] & flat["enabled"][b]
        if not on.any():
            return None
        world, slot, a, b = world[on], slot[on], a[on], b[on]
        params = {
            "anchor_a": s["anchor_a"][:, world, slot],
            "anchor_b": s["anchor_b"][:, world, slot],
            "rest_length": s["rest_length"][world, slot],
            "stiffness": s["stiffness"][world, slot],
            "damping": s["damping"][world, slot],
        }
        return a, b, params

    def _apply_springs(self, terms: StepTerms, springs: tuple, h: float) -> None:
        flat = self._views
        change = np.zeros_like(flat["vel"])
        spring_forces.add_forces(
            change,
            flat["pose"],
            flat["vel"],
            terms.inv_mass,
            terms.inv_moment,
            springs[0],
            springs[1],
            springs[2],
        )
        flat["vel"] += h * change

    def _finish(
        self,
        terms: StepTerms,
        contacts: Contacts | None,
        touching: tuple[np.ndarray, np.ndarray],
        speed: np.ndarray,
        springs: tuple | None,
        dt: float,
    ) -> None:
        """Store impulses for warm starting, clear forces, update sleep, advance time."""
        flat = self._views
        awake, enabled = flat["awake"], flat["enabled"]
        if self._cache.keys.size:
            # Keep the impulses of pairs that slept through this step (they were not solved).
            first, second = self._cached_bodies()
            dormant = ~awake[first] & ~awake[second] & enabled[first] & enabled[second]
            carried = self._cache.take(np.flatnonzero(dormant))
            self._cache = carried if contacts is None else Cache.merge(contacts.cache(), carried)
        elif contacts is not None:
            self._cache = contacts.cache()
        if self._forces_pending:
            flat["force"][...] = 0.0
            self._forces_pending = False
        kinematic = self._kinematic_flat
        if kinematic.size:  # a kinematic body is awake while it moves
            vel = flat["vel"]
            now = enabled[kinematic] & (
                (vel[0, kinematic] != 0) | (vel[1, kinematic] != 0) | (vel[2, kinematic] != 0)
            )
            if not np.array_equal(now, awake[kinematic]):
                awake[kinematic] = now
                self._touch(kinematic)
        if self.sleeping:
            self._update_sleep(terms, touching, speed, springs, dt)
        self._time += dt
        self.steps += 1
        self.last_contacts = contacts

    def _update_sleep(
        self,
        terms: StepTerms,
        touching: tuple[np.ndarray, np.ndarray],
        speed: np.ndarray,
        springs: tuple | None,
        dt: float,
    ) -> None:
        """Accumulate slow time; put islands that have been slow long enough to sleep.

        Slowness uses the step's speed bound ``|vx| + |vy| + R |w|`` (a little stricter
        than the speed itself). Islands join bodies by every narrowphase point (touching
        or about to), not only by the contacts that were solved: contacts between bodies
        at rest are skipped by the solver, and islands cut along them would sleep in
        pieces, each woken again by its awake neighbour, forever (an untouched rack next
        to a rolling ball never slept)."""
        flat = self._views
        sleep_time = flat["sleep_time"]
        index = terms.index  # only moving bodies can change their sleep time
        slow = terms.movable[index] & (speed[index] < self.sleep_speed)
        ready = np.where(slow, sleep_time[index] + dt, 0.0)
        sleep_time[index] = ready
        if not (ready >= self.time_to_sleep).any():
            return
        first, second = touching
        if springs is not None:
            first, second = (
                np.concatenate([first, springs[0]]),
                np.concatenate([second, springs[1]]),
            )
        movable = terms.movable
        joined = movable[first] & movable[second]
        ready = index[ready >= self.time_to_sleep]
        sleepy, label = fall_asleep(ready, (first[joined], second[joined]))
        if sleepy.size:
            flat["awake"][sleepy] = False
            flat["vel"][:, sleepy] = 0.0
            flat["island"][sleepy] = label
            self._touch(sleepy)
