"""Contact constraints for one step: materials, effective masses, warm start and colours.

Each narrowphase point becomes one non-penetration constraint (along the normal) and
one friction constraint (along the tangent ``t = (n_y, -n_x)``). For a constraint with
direction ``d`` and anchors ``rA``, ``rB`` the Jacobian acting on the six velocities
``(vA, wA, vB, wB)`` is::

    J = [-d, -(rA x d), d, (rB x d)]        (2D cross: r x d = r_x d_y - r_y d_x)

so the relative velocity along ``d`` is ``J . V`` and an impulse ``lambda`` changes
``V`` by ``M^-1 J^T lambda``. The effective mass is ``1 / (J M^-1 J^T)``::

    1 / (1/mA + (rA x d)^2 / IA + 1/mB + (rB x d)^2 / IB)

(this is the tutorial's "effective mass" ``1 / (1/m + r^2 / I)`` for both bodies at once).
``J`` and ``M^-1 J^T`` are stored as ``(6, P)`` arrays; ``index6`` holds, for each point,
the flat positions of ``(vxA, vyA, wA, vxB, vyB, wB)`` in the ``(3, T)`` velocity array,
so a gather is one ``take`` and a scatter one assignment.

*Colours.* Gauss-Seidel (solve one constraint, update the bodies, solve the next)
converges far better than Jacobi for stacks, but is sequential. Constraints are split
into colours in which no dynamic body appears twice, so a whole colour can be solved
at once with plain gathers and scatters and the sweep over colours is still
Gauss-Seidel (Box2D v3 does the same for SIMD lanes). Colouring is greedy first-fit
with a bit mask of used colours per body; conflicts inside a round are avoided by
letting only the points of highest priority at each body go (Luby's rule), so a round
is one vectorised pass. Priorities are a bijective hash of the point's key within its
world, so each world is coloured exactly as it would be on its own.

*Warm start.* Accumulated impulses are stored by point key (pair key and feature id)
and matched next step with a binary search, as in box2d-lite.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .narrowphase import FEATURES, Points

_HASH_1 = np.uint64(0x9E3779B97F4A7C15)
_HASH_2 = np.uint64(0xBF58476D1CE4E5B9)
_ALL_BITS = np.uint64(0xFFFFFFFFFFFFFFFF)
_PALETTE = 64  # colours per bit mask; more colours take further rounds of 64

MIXING_RULES = ("max", "min", "mean", "product", "sqrt")


def mix(rule: str, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Combine two materials' coefficients by a named rule (Box2D: max for restitution,
    sqrt(a * b) for friction)."""
    if rule == "max":
        return np.maximum(a, b)
    if rule == "min":
        return np.minimum(a, b)
    if rule == "mean":
        return 0.5 * (a + b)
    if rule == "product":
        return a * b
    return np.sqrt(a * b)


def soft_constraint(hertz: float, damping_ratio: float, h: float) -> tuple[float, float, float]:
    """Bias rate, mass scale and impulse scale of a soft contact (Box2D v3's soft step).

    A penetration ``C < 0`` is treated as a spring-damper of natural frequency
    ``omega = 2 pi hertz`` and damping ratio ``zeta`` integrated implicitly over the
    substep ``h``. Solving ``J v + (beta / h) C + gamma lambda = 0`` for the impulse gives
    ``lambda = -m massScale (J v + biasRate C) - impulseScale lambda_acc`` with::

        a1 = 2 zeta + h omega,  a2 = h omega a1,  a3 = 1 / (1 + a2)
        biasRate = omega / a1,  massScale = a2 a3,  impulseScale = a3
    """
    if hertz == 0.0:
        return 0.0, 1.0, 0.0
    omega = 2.0 * np.pi * hertz
    a1 = 2.0 * damping_ratio + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


def priority(local_key: np.ndarray) -> np.ndarray:
    """A bijective 64-bit hash (splitmix64's finaliser): unique priorities, no bias."""
    x = local_key.astype(np.uint64)
    x = (x ^ (x >> np.uint64(30))) * _HASH_1
    x = (x ^ (x >> np.uint64(27))) * _HASH_2
    return x ^ (x >> np.uint64(31))


def colour(
    body_a: np.ndarray,
    body_b: np.ndarray,
    free_a: np.ndarray,
    free_b: np.ndarray,
    local_key: np.ndarray,
    total: int,
    previous: np.ndarray,
) -> np.ndarray:
    """Colour constraints so that no dynamic body appears twice in a colour.

    ``free_a``/``free_b`` mark ends on bodies that cannot move (fixed, kinematic,
    asleep): they never conflict. ``previous`` is each point's colour at the last step
    (-1 for a new point): contacts persist, so keeping those colours while they are
    still valid makes colouring cost nothing in a steady scene; only new points go
    through the rounds. Returns the colour of each constraint (0, 1, ...).
    """
    count = body_a.size
    ends = np.concatenate([body_a[~free_a], body_b[~free_b]])
    ends.sort()
    if not (ends[1:] == ends[:-1]).any():  # no dynamic body twice: one colour (common)
        return np.zeros(count, np.int64)
    sentinel = total  # every immovable end points here; it constrains nothing
    ends_a = np.where(free_a, sentinel, body_a)
    ends_b = np.where(free_b, sentinel, body_b)
    result = np.where(previous < _PALETTE, previous, -1)
    used = _used_colours(result, ends_a, ends_b, total)
    remaining = np.flatnonzero(result < 0)
    by_point = np.zeros(count, np.uint64)
    by_point[remaining] = priority(local_key[remaining])
    best = np.full(total + 1, _ALL_BITS, np.uint64)
    deferred: list[np.ndarray] = []
    base = 0
    while remaining.size or deferred:
        if remaining.size == 0:  # this palette is full for some bodies: start another
            remaining = np.concatenate(deferred)
            deferred = []
            used[:] = 0
            base += _PALETTE
        ra, rb, rp = ends_a[remaining], ends_b[remaining], by_point[remaining]
        best[ra] = _ALL_BITS
        best[rb] = _ALL_BITS
        np.minimum.at(best, ra, rp)
        np.minimum.at(best, rb, rp)
        wins = ((ra == sentinel) | (best[ra] == rp)) & ((rb == sentinel) | (best[rb] == rp))
        winners, wa, wb = remaining[wins], ra[wins], rb[wins]
        free = ~(used[wa] | used[wb])
        bit = free & (~free + np.uint64(1))  # lowest free colour
        full = bit == 0
        ok = ~full
        result[winners[ok]] = base + np.log2(bit[ok].astype(np.float64)).astype(np.int64)
        used[wa[ok]] |= bit[ok]
        used[wb[ok]] |= bit[ok]
        used[sentinel] = 0
        if full.any():
            deferred.append(winners[full])
        remaining = remaining[~wins]
    return result


def _used_colours(
    result: np.ndarray, ends_a: np.ndarray, ends_b: np.ndarray, total: int
) -> np.ndarray:
    """Bit mask of the colours each body already has, after dropping (setting to -1 in
    ``result``) kept colours that now clash: a body that woke up, or that was asleep and
    is now movable, can meet two points of the same colour."""
    kept = np.flatnonzero(result >= 0)
    used = np.zeros(total + 1, np.uint64)
    if kept.size == 0:
        return used
    bits = np.left_shift(np.uint64(1), result[kept].astype(np.uint64))
    ea, eb = ends_a[kept], ends_b[kept]
    np.bitwise_or.at(used, ea, bits)
    np.bitwise_or.at(used, eb, bits)
    # Distinct powers of two add up to their OR; a repeated colour makes the sum differ.
    summed = np.zeros(total + 1, np.uint64)
    np.add.at(summed, ea, bits)
    np.add.at(summed, eb, bits)
    clash = summed != used
    clash[total] = False
    if clash.any():
        result[kept[clash[ea] | clash[eb]]] = -1
        return _used_colours(result, ends_a, ends_b, total)
    used[total] = 0
    return used


@dataclass
class Cache:
    """What a point carries to the next step, by point key (sorted): its two bodies (flat
    indices), its accumulated impulses (warm start) and its colour."""

    keys: np.ndarray
    body_a: np.ndarray
    body_b: np.ndarray
    normal_impulse: np.ndarray
    tangent_impulse: np.ndarray
    colour: np.ndarray

    @staticmethod
    def empty() -> Cache:
        index = np.zeros(0, np.int64)
        return Cache(index, index, index, np.zeros(0), np.zeros(0), index)

    def arrays(self) -> list[np.ndarray]:
        return [getattr(self, f.name) for f in fields(self)]

    def take(self, rows: np.ndarray) -> Cache:
        return Cache(*(array[rows] for array in self.arrays()))

    def copy(self) -> Cache:
        return Cache(*(array.copy() for array in self.arrays()))

    def lookup(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Impulses and colour stored for ``keys`` (0, 0 and -1 where a key is new)."""
        if self.keys.size == 0:
            return np.zeros(keys.size), np.zeros(keys.size), np.full(keys.size, -1)
        where = np.minimum(np.searchsorted(self.keys, keys), self.keys.size - 1)
        found = self.keys[where] == keys
        return (
            np.where(found, self.normal_impulse[where], 0.0),
            np.where(found, self.tangent_impulse[where], 0.0),
            np.where(found, self.colour[where], -1),
        )

    @staticmethod
    def merge(first: Cache, second: Cache) -> Cache:
        """Union of two caches with disjoint keys, sorted."""
        if second.keys.size == 0:
            return first
        if first.keys.size == 0:
            return second
        order = np.argsort(np.concatenate([first.keys, second.keys]), kind="stable")
        return Cache(
            *(
                np.concatenate([a, b])[order]
                for a, b in zip(first.arrays(), second.arrays(), strict=True)
            )
        )


@dataclass
class Contacts:
    """The contact constraints of one step, sorted by colour. Arrays have one entry per
    point (``(6, P)`` for Jacobians); ``bounds[c]:bounds[c + 1]`` is colour ``c``."""

    key: np.ndarray
    body_a: np.ndarray
    body_b: np.ndarray
    index6: np.ndarray
    normal_x: np.ndarray
    normal_y: np.ndarray
    jac_n: np.ndarray
    inv_n: np.ndarray  # M^-1 J^T for the normal
    jac_t: np.ndarray
    inv_t: np.ndarray
    normal_mass: np.ndarray
    tangent_mass: np.ndarray
    separation: np.ndarray  # at the start of the step
    base_separation: np.ndarray  # separation = base + J . pose during the step
    relative_velocity: np.ndarray
    relative_acceleration: np.ndarray  # normal, from gravity and applied forces
    restitution: np.ndarray
    friction: np.ndarray
    bias_rate: np.ndarray
    mass_scale: np.ndarray
    impulse_scale: np.ndarray
    normal_impulse: np.ndarray
    tangent_impulse: np.ndarray
    max_normal_impulse: np.ndarray  # largest solver increment this step (did it push?)
    impact_velocity: np.ndarray  # normal velocity when the point first pushed (0: not yet)
    step_impulse: np.ndarray  # normal impulse applied over the whole step (N s)
    watched: np.ndarray | None  # shared points that may bounce: whose impact_velocity to keep
    anchor_ax: np.ndarray
    anchor_ay: np.ndarray
    bounds: np.ndarray
    colour: np.ndarray  # of each point, in colour order
    order: np.ndarray | None  # colour order -> key order (None: already in key order)

    @property
    def size(self) -> int:
        return int(self.key.size)

    def cache(self) -> Cache:
        """The points' impulses and colours by key (the points arrived sorted by key)."""
        if self.order is None:
            return Cache(
                self.key,
                self.body_a,
                self.body_b,
                self.normal_impulse,
                self.tangent_impulse,
                self.colour,
            )
        back = np.empty_like(self.order)
        back[self.order] = np.arange(self.order.size)
        return Cache(
            self.key[back],
            self.body_a[back],
            self.body_b[back],
            self.normal_impulse[back],
            self.tangent_impulse[back],
            self.colour[back],
        )


def build(
    point_key: np.ndarray,
    local_key: np.ndarray,
    body_a: np.ndarray,
    body_b: np.ndarray,
    points: Points,
    bodies: dict[str, np.ndarray],
    carried: tuple[np.ndarray, np.ndarray, np.ndarray],
    rules: tuple[str, str],
    softness: tuple[tuple[float, float, float], tuple[float, float, float]],
    h: float,
) -> Contacts:
    """Turn narrowphase points into colour-sorted constraints.

    ``bodies`` holds flat per-body arrays: ``inv_mass`` and ``inv_moment`` (0 for bodies
    that cannot move this step), ``movable`` (bool), ``restitution``, ``friction``, and
    the ``(3, T)`` ``pose``, ``vel`` and ``accel_h`` (``h`` times the acceleration from
    gravity and applied forces, ``h`` the substep).
    ``carried`` is what the cache holds for the points (impulses and colour, see
    ``Cache.lookup``). ``softness`` is ``(between dynamic bodies, against an immovable
    body)``.
    """
    total = bodies["inv_mass"].size
    movable = bodies["movable"]
    normal_impulse, tangent_impulse, previous = carried
    colours = colour(body_a, body_b, ~movable[body_a], ~movable[body_b], local_key, total, previous)
    # Points that share their pair with another point (a face against a face): restitution
    # treats them differently (see solver.restitution). The points come sorted by key, so
    # a pair's points are neighbours.
    pair = point_key // FEATURES
    twin = pair[1:] == pair[:-1]
    shared = np.zeros(pair.size, dtype=bool)
    shared[1:] |= twin
    shared[:-1] |= twin
    fields = [
        shared,
        normal_impulse,
        tangent_impulse,
        colours,
        point_key,
        body_a,
        body_b,
        points.normal_x,
        points.normal_y,
        points.anchor_ax,
        points.anchor_ay,
        points.anchor_bx,
        points.anchor_by,
        points.separation,
    ]
    order = None
    if not colours.any():  # one colour: already in order
        bounds = np.array([0, colours.size])
    else:
        order = np.argsort(colours, kind="stable")
        fields = [array[order] for array in fields]
        bounds = np.concatenate([[0], np.cumsum(np.bincount(colours))])
    shared = fields[0]
    normal_impulse, tangent_impulse, colours, key, a, b, nx, ny, rax, ray, rbx, rby = fields[1:13]
    separation = fields[13]
    tx, ty = ny, -nx
    ima, imb = bodies["inv_mass"][a], bodies["inv_mass"][b]
    iia, iib = bodies["inv_moment"][a], bodies["inv_moment"][b]
    rna, rnb = rax * ny - ray * nx, rbx * ny - rby * nx
    rta, rtb = rax * ty - ray * tx, rbx * ty - rby * tx
    jac_n = np.stack([-nx, -ny, -rna, nx, ny, rnb])
    jac_t = np.stack([-tx, -ty, -rta, tx, ty, rtb])
    inverse = np.stack([ima, ima, iia, imb, imb, iib])  # the diagonal of M^-1, per end
    inv_n, inv_t = inverse * jac_n, inverse * jac_t
    k_normal = (jac_n * inv_n).sum(axis=0)  # J M^-1 J^T
    k_tangent = (jac_t * inv_t).sum(axis=0)
    index6 = np.stack([a, a + total, a + 2 * total, b, b + total, b + 2 * total])
    relative_velocity = (jac_n * bodies["vel"].reshape(-1)[index6]).sum(axis=0)
    if bodies["accel_h"] is None:  # no gravity, no applied forces
        relative_acceleration = np.zeros(key.size)
    else:
        relative_acceleration = (jac_n * bodies["accel_h"].reshape(-1)[index6]).sum(axis=0) / h
    # Separation as the solver tracks it: base + J . pose, with base fixed for the step.
    base = separation - (jac_n * bodies["pose"].reshape(-1)[index6]).sum(axis=0)
    restitution = mix(rules[0], bodies["restitution"][a], bodies["restitution"][b])
    both = movable[a] & movable[b]
    soft = [np.where(both, softness[0][i], softness[1][i]) for i in range(3)]
    return Contacts(
        key=key,
        body_a=a,
        body_b=b,
        index6=index6,
        normal_x=nx,
        normal_y=ny,
        jac_n=jac_n,
        inv_n=inv_n,
        jac_t=jac_t,
        inv_t=inv_t,
        normal_mass=_inverse(k_normal),
        tangent_mass=_inverse(k_tangent),
        separation=separation,
        base_separation=base,
        relative_velocity=relative_velocity,
        relative_acceleration=relative_acceleration,
        restitution=restitution,
        friction=mix(rules[1], bodies["friction"][a], bodies["friction"][b]),
        bias_rate=soft[0],
        mass_scale=soft[1],
        impulse_scale=soft[2],
        normal_impulse=normal_impulse,
        tangent_impulse=tangent_impulse,
        max_normal_impulse=np.zeros(key.size),
        impact_velocity=np.zeros(key.size),
        step_impulse=np.zeros(key.size),
        watched=_watched(shared, relative_velocity, restitution),
        anchor_ax=rax,
        anchor_ay=ray,
        bounds=bounds,
        colour=colours,
        order=order,
    )


def _watched(
    shared: np.ndarray, relative_velocity: np.ndarray, restitution: np.ndarray
) -> np.ndarray | None:
    """Indices of the points whose velocity at first touch restitution will need."""
    watched = np.flatnonzero(shared & (relative_velocity < 0.0) & (restitution > 0.0))
    return watched if watched.size else None


def _inverse(k: np.ndarray) -> np.ndarray:
    """1 / k, and 0 where k is 0 (a constraint between two immovable bodies)."""
    return np.divide(1.0, k, out=np.zeros_like(k), where=k > 0.0)


def point_keys(pair_key: np.ndarray, feature: np.ndarray) -> np.ndarray:
    """A point's key: its pair's key and its feature id."""
    return pair_key * FEATURES + feature
