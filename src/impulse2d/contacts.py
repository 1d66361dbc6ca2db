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

from dataclasses import dataclass

import numpy as np

from .narrowphase import FEATURES

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
    prio: np.ndarray,
    total: int,
) -> np.ndarray:
    """Colour constraints so that no dynamic body appears twice in a colour.

    ``free_a``/``free_b`` mark ends on bodies that cannot move (fixed, kinematic): they
    never conflict. Returns the colour of each constraint (0, 1, ...).
    """
    count = body_a.size
    result = np.full(count, -1, np.int64)
    if count == 0:
        return result
    sentinel = total  # every immovable end points here; it constrains nothing
    ends_a = np.where(free_a, sentinel, body_a)
    ends_b = np.where(free_b, sentinel, body_b)
    used = np.zeros(total + 1, np.uint64)
    best = np.full(total + 1, _ALL_BITS, np.uint64)
    remaining = np.arange(count)
    deferred: list[np.ndarray] = []
    base = 0
    while remaining.size or deferred:
        if remaining.size == 0:  # this palette is full for some bodies: start another
            remaining = np.concatenate(deferred)
            deferred = []
            used[:] = 0
            base += _PALETTE
        ra, rb, rp = ends_a[remaining], ends_b[remaining], prio[remaining]
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


@dataclass
class Cache:
    """Accumulated impulses by point key, sorted by key, for warm starting."""

    keys: np.ndarray
    normal_impulse: np.ndarray
    tangent_impulse: np.ndarray

    @staticmethod
    def empty() -> Cache:
        return Cache(np.zeros(0, np.int64), np.zeros(0), np.zeros(0))

    def take(self, rows: np.ndarray) -> Cache:
        return Cache(self.keys[rows], self.normal_impulse[rows], self.tangent_impulse[rows])

    def lookup(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Impulses stored for ``keys`` (0 where a key is new)."""
        if self.keys.size == 0:
            return np.zeros(keys.size), np.zeros(keys.size)
        where = np.minimum(np.searchsorted(self.keys, keys), self.keys.size - 1)
        found = self.keys[where] == keys
        return (
            np.where(found, self.normal_impulse[where], 0.0),
            np.where(found, self.tangent_impulse[where], 0.0),
        )

    @staticmethod
    def merge(first: Cache, second: Cache) -> Cache:
        """Union of two caches with disjoint keys, sorted."""
        keys = np.concatenate([first.keys, second.keys])
        order = np.argsort(keys, kind="stable")
        return Cache(
            keys[order],
            np.concatenate([first.normal_impulse, second.normal_impulse])[order],
            np.concatenate([first.tangent_impulse, second.tangent_impulse])[order],
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
    base_separation: np.ndarray
    relative_velocity: np.ndarray
    relative_acceleration: np.ndarray  # normal, from gravity and applied forces
    restitution: np.ndarray
    friction: np.ndarray
    bias_rate: np.ndarray
    mass_scale: np.ndarray
    impulse_scale: np.ndarray
    normal_impulse: np.ndarray
    tangent_impulse: np.ndarray
    max_normal_impulse: np.ndarray
    anchor_ax: np.ndarray
    anchor_ay: np.ndarray
    bounds: np.ndarray

    @property
    def size(self) -> int:
        return int(self.key.size)

    def cache(self) -> Cache:
        order = np.argsort(self.key, kind="stable")
        return Cache(self.key[order], self.normal_impulse[order], self.tangent_impulse[order])


def build(
    point_key: np.ndarray,
    local_key: np.ndarray,
    body_a: np.ndarray,
    body_b: np.ndarray,
    normal_x: np.ndarray,
    normal_y: np.ndarray,
    anchor_a: tuple[np.ndarray, np.ndarray],
    anchor_b: tuple[np.ndarray, np.ndarray],
    separation: np.ndarray,
    bodies: dict[str, np.ndarray],
    cache: Cache,
    rules: tuple[str, str],
    softness: tuple[tuple[float, float, float], tuple[float, float, float]],
) -> Contacts:
    """Turn narrowphase points into colour-sorted constraints.

    ``bodies`` holds flat per-body arrays: ``inv_mass``, ``inv_moment``, ``restitution``,
    ``friction``, ``movable`` (bool: dynamic and awake), and the ``(3, T)`` ``vel`` and
    ``accel`` (acceleration from gravity and applied forces).
    ``softness`` is ``(dynamic pair, pair with an immovable body)``.
    """
    total = bodies["inv_mass"].size
    rax, ray = anchor_a
    rbx, rby = anchor_b
    nx, ny = normal_x, normal_y
    tx, ty = ny, -nx
    movable_a, movable_b = bodies["movable"][body_a], bodies["movable"][body_b]
    ima = np.where(movable_a, bodies["inv_mass"][body_a], 0.0)
    imb = np.where(movable_b, bodies["inv_mass"][body_b], 0.0)
    iia = np.where(movable_a, bodies["inv_moment"][body_a], 0.0)
    iib = np.where(movable_b, bodies["inv_moment"][body_b], 0.0)
    rna, rnb = rax * ny - ray * nx, rbx * ny - rby * nx
    rta, rtb = rax * ty - ray * tx, rbx * ty - rby * tx
    k_normal = ima + imb + iia * rna * rna + iib * rnb * rnb
    k_tangent = ima + imb + iia * rta * rta + iib * rtb * rtb
    jac_n = np.stack([-nx, -ny, -rna, nx, ny, rnb])
    inv_n = np.stack([-ima * nx, -ima * ny, -iia * rna, imb * nx, imb * ny, iib * rnb])
    jac_t = np.stack([-tx, -ty, -rta, tx, ty, rtb])
    inv_t = np.stack([-ima * tx, -ima * ty, -iia * rta, imb * tx, imb * ty, iib * rtb])
    index6 = np.stack(
        [body_a, body_a + total, body_a + 2 * total, body_b, body_b + total, body_b + 2 * total]
    )
    velocity = bodies["vel"].reshape(-1)[index6]
    relative_velocity = (jac_n * velocity).sum(axis=0)
    relative_acceleration = (jac_n * bodies["accel"].reshape(-1)[index6]).sum(axis=0)
    normal_impulse, tangent_impulse = cache.lookup(point_key)
    restitution = mix(rules[0], bodies["restitution"][body_a], bodies["restitution"][body_b])
    friction = mix(rules[1], bodies["friction"][body_a], bodies["friction"][body_b])
    both = movable_a & movable_b
    soft = [np.where(both, softness[0][i], softness[1][i]) for i in range(3)]

    colours = colour(body_a, body_b, ~movable_a, ~movable_b, priority(local_key), total)
    order = np.argsort(colours, kind="stable")
    counts = np.bincount(colours, minlength=1) if colours.size else np.zeros(0, np.int64)
    bounds = np.concatenate([[0], np.cumsum(counts)])

    def by_colour(array: np.ndarray) -> np.ndarray:
        return array[..., order]

    return Contacts(
        key=by_colour(point_key),
        body_a=by_colour(body_a),
        body_b=by_colour(body_b),
        index6=by_colour(index6),
        normal_x=by_colour(nx),
        normal_y=by_colour(ny),
        jac_n=by_colour(jac_n),
        inv_n=by_colour(inv_n),
        jac_t=by_colour(jac_t),
        inv_t=by_colour(inv_t),
        normal_mass=by_colour(_inverse(k_normal)),
        tangent_mass=by_colour(_inverse(k_tangent)),
        base_separation=by_colour(separation),
        relative_velocity=by_colour(relative_velocity),
        relative_acceleration=by_colour(relative_acceleration),
        restitution=by_colour(restitution),
        friction=by_colour(friction),
        bias_rate=by_colour(soft[0]),
        mass_scale=by_colour(soft[1]),
        impulse_scale=by_colour(soft[2]),
        normal_impulse=by_colour(normal_impulse),
        tangent_impulse=by_colour(tangent_impulse),
        max_normal_impulse=np.zeros(point_key.size),
        anchor_ax=by_colour(rax),
        anchor_ay=by_colour(ray),
        bounds=bounds,
    )


def _inverse(k: np.ndarray) -> np.ndarray:
    """1 / k, and 0 where k is 0 (a constraint between two immovable bodies)."""
    return np.divide(1.0, k, out=np.zeros_like(k), where=k > 0.0)


def point_keys(pair_key: np.ndarray, feature: np.ndarray) -> np.ndarray:
    """A point's key: its pair's key and its feature id."""
    return pair_key * FEATURES + feature
