"""Contact constraints of one step: materials, effective masses, warm start, the cache.

Each narrowphase point becomes one non-penetration constraint along the normal ``n`` and
one friction constraint along the tangent ``t = (n_y, -n_x)``. For a direction ``d`` and
anchors ``rA``, ``rB`` the Jacobian acting on the velocities ``(vA, wA, vB, wB)`` is::

    J = [-d, -(rA x d), d, (rB x d)]        (2D cross: r x d = r_x d_y - r_y d_x)

so the relative velocity along ``d`` is ``J . V`` and an impulse ``lambda`` changes ``V``
by ``M^-1 J^T lambda``. The effective mass is ``1 / (J M^-1 J^T)``::

    1 / (1/mA + (rA x d)^2 / IA + 1/mB + (rB x d)^2 / IB)

(the tutorial's "effective mass" ``1 / (1/m + r^2 / I)`` for both bodies at once). Bodies
that cannot move this step (fixed, kinematic, asleep) enter with zero inverse mass.

*Materials.* Restitution and friction are mixed per contact by the world's rules (Box2D:
``max`` for restitution, ``sqrt(a b)`` for friction).

*Warm start.* The impulses a point accumulated are stored by the point's key (body A,
body B, feature id) and carried to the next step, as in box2d-lite, to the points that
are within their pair's speculative distance (``carry_impulses``). Points and cache are
both sorted by key, so matching them is one merge walk. Pairs that sleep through a step
are not solved; their cached points are kept (*dormant*) so a stack that wakes up starts
from the impulses that held it.
"""

from __future__ import annotations

import math

from . import context
from ._jit import inline, kernel
from .colouring import manifold_end, pair_at
from .state import (
    APPROACH,
    BODY_A,
    BODY_B,
    CONTACT_COUNT,
    CONTACT_F,
    CONTACT_I,
    CONTACT_NX,
    CONTACT_NY,
    ENABLED,
    FEATURE,
    FRICTION,
    GROSS_IMPULSE,
    HALF_W,
    KEPT_TORQUE,
    NORMAL_IMPULSE,
    OMEGA,
    POINT_X,
    POINT_Y,
    RESTITUTION,
    SEPARATION,
    STEP_IMPULSE,
    TANGENT_IMPULSE,
    VX,
    VY,
    X,
    Y,
)
from .workspace import (
    ACCEL_W,
    ACCEL_X,
    ACCEL_Y,
    APPROACH_SPEED,
    BIAS_RATE,
    DRIFT,
    GROSS_J,
    HALF_SPEC,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPULSE_SCALE,
    KEEP,
    MASS_SCALE,
    MAX_J,
    MIXED_FRICTION,
    MIXED_RESTITUTION,
    MOVABLE,
    MOVING,
    NORMAL_ACCEL,
    NORMAL_J,
    NORMAL_MASS,
    NX,
    NY,
    RAX,
    RAY,
    RBX,
    RBY,
    RNA,
    RNB,
    RTA,
    RTB,
    SEP0,
    SHARED,
    STEP_INV_MASS,
    STEP_INV_MOMENT,
    STEP_J,
    TANGENT_J,
    TANGENT_MASS,
    X0,
    Y0,
)

_SLOT_RADIX = 1 << 26  # slots per world in a point key (far more than any world holds)
_FEATURE_RADIX = 32


@kernel
def point_key(a, b, feature) -> int:
    """A point's key: ordered as (body A, body B, feature)."""
    return (a * _SLOT_RADIX + b) * _FEATURE_RADIX + feature


@kernel
def mix(rule, a, b) -> float:
    """Combine two materials' coefficients by the rule with index ``rule`` in
    ``context.MIXING_RULES``: max, min, mean, product, sqrt."""
    if rule == 0:
        return max(a, b)
    if rule == 1:
        return min(a, b)
    if rule == 2:
        return 0.5 * (a + b)
    if rule == 3:
        return a * b
    return math.sqrt(a * b)


@kernel
def carry_impulses(contact, contact_i, world_i, w, terms, points, ids, n) -> None:
    """Warm start: each point takes the impulses its key had at the last step (or 0), if
    its separation at the step start is within the pair's speculative distance.

    The warm start guesses that a contact pushes as it did at the last step: right for a
    contact that lasts. A point further apart is one the narrowphase made only so a fast
    body cannot pass through (its margin is what the pair can close in the step): the
    bodies do not touch, what it pushes is an impact within the step, not a load that
    lasted, and its Jacobian is not the one the cached impulse was found on. The point
    lies midway across the gap ``s``, so the lever arms ``r x t`` of its tangent row are
    ``s / 2`` longer than at the surface, and an impulse ``lambda`` along it changes the
    tangent velocity by ``K lambda``, ``K = 1/mA + 1/mB + (rA x t)^2/IA + (rB x t)^2/IB``.
    A 2 mm x 19 mm box 2 m from a disc has a 1 m arm and ``K`` 2e4 times what it had
    touching: the friction impulse carried from then (13 N s) spun it at 4e5 rad/s
    (1 kJ became 2.7 MJ), the contacts after it in the Gauss-Seidel sweep pushed on that
    spin before the point took it back, and the energy grew every step until it
    overflowed (``tests/test_physics_tunnelling.py``). Within the speculative distance
    (at most a quarter of each body's size, ``integrate.body_terms``, and the world's
    against a plane) the arms grow by at most a sixteenth of the bodies' bounding radii
    plus a quarter of the world's speculative distance: Box2D's regime."""
    cached = world_i[w, CONTACT_COUNT]
    j = 0
    for k in range(n):
        key = point_key(ids[k, 0], ids[k, 1], ids[k, 2])
        while (
            j < cached
            and point_key(
                contact_i[w, j, BODY_A], contact_i[w, j, BODY_B], contact_i[w, j, FEATURE]
            )
            < key
        ):
            j += 1
        found = (
            j < cached
            and point_key(
                contact_i[w, j, BODY_A], contact_i[w, j, BODY_B], contact_i[w, j, FEATURE]
            )
            == key
        )
        a, b = ids[k, 0], ids[k, 1]
        found &= points[k, SEP0] < terms[a, HALF_SPEC] + terms[b, HALF_SPEC]  # see above
        points[k, NORMAL_J] = contact[w, j, NORMAL_IMPULSE] if found else 0.0
        points[k, TANGENT_J] = contact[w, j, TANGENT_IMPULSE] if found else 0.0


@inline
def set_jacobian(points, k, dax, day, dbx, dby) -> None:
    """The Jacobian's cross terms ``rA x n``, ``rB x n``, ``rA x t``, ``rB x t`` and the
    effective masses of point ``k``, for its anchors moved by ``(dax, day)`` on A and
    ``(dbx, dby)`` on B from where the narrowphase put them (see ``follow_bodies``)."""
    nx, ny = points[k, NX], points[k, NY]
    tx, ty = ny, -nx
    rax, ray = points[k, RAX] + dax, points[k, RAY] + day
    rbx, rby = points[k, RBX] + dbx, points[k, RBY] + dby
    rna, rnb = rax * ny - ray * nx, rbx * ny - rby * nx
    rta, rtb = rax * ty - ray * tx, rbx * ty - rby * tx
    points[k, RNA], points[k, RNB], points[k, RTA], points[k, RTB] = rna, rnb, rta, rtb
    ima, imb, iia, iib = points[k, IMA], points[k, IMB], points[k, IIA], points[k, IIB]
    k_normal = ima + imb + iia * rna * rna + iib * rnb * rnb
    k_tangent = ima + imb + iia * rta * rta + iib * rtb * rtb
    points[k, NORMAL_MASS] = 1.0 / k_normal if k_normal > 0.0 else 0.0
    points[k, TANGENT_MASS] = 1.0 / k_tangent if k_tangent > 0.0 else 0.0


@inline
def along_line_of_centres(body, w, terms, points, k, a, b) -> None:
    """Two discs are pushed along their line of centres now, at anchors through their
    centres: the impulse then lies on the line joining the centres and exerts no torque
    on the pair. While they do not touch, a point keeps its normal if it has not pushed
    yet, or if that normal is the line of centres at a predicted impact (not the one at
    the step start): the impact's direction. ``SEP0`` is re-based so the solver's
    separation, its value at the step start plus ``J . dq``, is the exact gap now."""
    dx, dy = body[w, b, X] - body[w, a, X], body[w, b, Y] - body[w, a, Y]
    dist = math.sqrt(dx * dx + dy * dy)
    ra, rb = body[w, a, HALF_W], body[w, b, HALF_W]
    gap = dist - ra - rb
    if dist < 1e-12 * (ra + rb):
        return
    if gap > 0.0:
        untouched = points[k, MAX_J] == 0.0 and points[k, NORMAL_J] == 0.0
        x0, y0 = terms[b, X0] - terms[a, X0], terms[b, Y0] - terms[a, Y0]
        predicted = abs(x0 * points[k, NY] - y0 * points[k, NX]) > 1e-9 * (ra + rb)
        if untouched or predicted:
            return
    nx, ny = dx / dist, dy / dist
    points[k, NX], points[k, NY] = nx, ny
    reach_a, reach_b = ra + 0.5 * gap, -(rb + 0.5 * gap)
    points[k, RAX], points[k, RAY] = nx * reach_a, ny * reach_a
    points[k, RBX], points[k, RBY] = nx * reach_b, ny * reach_b
    moved_x = (body[w, b, X] - terms[b, X0]) - (body[w, a, X] - terms[a, X0])
    moved_y = (body[w, b, Y] - terms[b, Y0]) - (body[w, a, Y] - terms[a, Y0])
    points[k, SEP0] = gap - (nx * moved_x + ny * moved_y)
    set_jacobian(points, k, 0.0, 0.0, 0.0, 0.0)


@kernel
def follow_bodies(body, w, ctx, terms, points, ids, n, others) -> None:
    """After the positions moved: both anchors of every point at one world point again.

    Equal and opposite impulses at one world point exert no net torque, so contacts keep
    angular momentum exactly. The narrowphase puts both anchors at one point, but the
    bodies then move during the step; with each anchor kept at its offset from its own
    centre, a pair that slid ``m`` past each other would be pushed at two points ``m``
    apart and gain ``m x impulse``. So the anchor that is a material point of its body
    (``narrowphase.anchor_kept``: a disc's surface below its centre, a box's vertex)
    stays, and the other one goes to it: the point slides along the other body's
    surface, as a real contact does. Two discs are the exception: both anchors stay on
    the normal through their centres, so a normal impulse never spins a disc, and once
    they touch that normal is their line of centres (``along_line_of_centres``). Before
    they touch it is the line of centres at the predicted impact
    (``narrowphase.circle_circle``), which gives the right departure angle; the price is
    a torque ``m x impulse`` from the speculative push that brings them together, ``m``
    at most the distance they slide past each other in the step (the one place where
    contacts do not keep angular momentum exactly, an error of first order in ``dt``,
    bounded in ``tests/scene_laws.py``).

    Two kinds of point stay as the narrowphase made them. Against a fixed or kinematic
    body (or one asleep) there is no angular momentum to keep. And a point that may
    bounce (restitution > 0, closing faster than the threshold) keeps one Jacobian for
    the whole step: restitution sends it apart at ``e`` times the speed it came in with,
    along the Jacobian that speed was measured on, and pushes spread over several
    Jacobians (the solver's passes as the anchors move, then the bounce) would not keep
    the energy of an elastic impact (a spinning box striking a pebble gained 1 %). Such
    an impact exerts the torque ``m x impulse`` of the discs above, summed over every push
    of the step: ``sum_i m(t_i) x P_i``, at most ``dt |relative velocity|`` times the sizes
    of the pushes summed (``GROSS_J``), which pushes taken back by the relax pass or the
    bounce add to (``+P`` at ``m_1``, then ``-P`` at ``m_2``, exerts ``(m_1 - m_2) x P``
    with no net impulse). Pushes happen only where the positions stand between two
    integrations (the step start, ``m = 0``, and after each of them, here), so the
    largest ``|m|`` seen here (``DRIFT``) times ``GROSS_J`` bounds that torque exactly;
    the contact cache keeps it (``state.KEPT_TORQUE``) for the tests of the law."""
    threshold = ctx[context.RESTITUTION_THRESHOLD]
    p, start = 0, pair_at(others, 0, 0)
    while start < n:
        end = manifold_end(ids, n, start)
        for k in range(start, end):
            follow_point(body, w, terms, points, ids, k, threshold)
        p += 1
        start = pair_at(others, p, end)


@inline
def follow_point(body, w, terms, points, ids, k, threshold) -> None:
    """``follow_bodies`` at point ``k``."""
    if points[k, IMA] == 0.0 or points[k, IMB] == 0.0:
        return  # against an immovable body: it takes any torque, nothing to keep
    a, b = ids[k, 0], ids[k, 1]
    bounces = points[k, MIXED_RESTITUTION] > 0.0 and points[k, APPROACH_SPEED] < -threshold
    keep = points[k, KEEP]
    if keep == 2.0 and not bounces:
        along_line_of_centres(body, w, terms, points, k, a, b)
        return
    mx = (body[w, b, X] + points[k, RBX]) - (body[w, a, X] + points[k, RAX])
    my = (body[w, b, Y] + points[k, RBY]) - (body[w, a, Y] + points[k, RAY])
    if bounces:  # may bounce (see follow_bodies): its pushes act ``m`` apart
        points[k, DRIFT] = max(points[k, DRIFT], math.hypot(mx, my))
        return
    if keep == 0.0:
        set_jacobian(points, k, 0.0, 0.0, -mx, -my)
    else:
        set_jacobian(points, k, mx, my, 0.0, 0.0)


@kernel
def prepare(body, w, ctx, terms, points, ids, n) -> None:
    """Effective masses, mixed materials, softness and the normal velocity and
    acceleration at the start of the step, for every point."""
    restitution_rule = int(ctx[context.RESTITUTION_RULE])
    friction_rule = int(ctx[context.FRICTION_RULE])
    inv_h = ctx[context.INV_H]
    for k in range(n):
        a, b = ids[k, 0], ids[k, 1]
        nx, ny = points[k, NX], points[k, NY]
        ima, iia = terms[a, STEP_INV_MASS], terms[a, STEP_INV_MOMENT]
        imb, iib = terms[b, STEP_INV_MASS], terms[b, STEP_INV_MOMENT]
        points[k, IMA], points[k, IIA], points[k, IMB], points[k, IIB] = ima, iia, imb, iib
        set_jacobian(points, k, 0.0, 0.0, 0.0, 0.0)
        rna, rnb = points[k, RNA], points[k, RNB]
        points[k, APPROACH_SPEED] = (
            -(nx * body[w, a, VX] + ny * body[w, a, VY])
            - rna * body[w, a, OMEGA]
            + nx * body[w, b, VX]
            + ny * body[w, b, VY]
            + rnb * body[w, b, OMEGA]
        )
        points[k, NORMAL_ACCEL] = (
            -(nx * terms[a, ACCEL_X] + ny * terms[a, ACCEL_Y])
            - rna * terms[a, ACCEL_W]
            + nx * terms[b, ACCEL_X]
            + ny * terms[b, ACCEL_Y]
            + rnb * terms[b, ACCEL_W]
        ) * inv_h
        points[k, MIXED_RESTITUTION] = mix(
            restitution_rule, body[w, a, RESTITUTION], body[w, b, RESTITUTION]
        )
        points[k, MIXED_FRICTION] = mix(friction_rule, body[w, a, FRICTION], body[w, b, FRICTION])
        # Against a body that cannot move, the contact is twice as stiff (Box2D).
        hard = terms[a, MOVABLE] == 0.0 or terms[b, MOVABLE] == 0.0
        base = context.HARD_RATE if hard else context.SOFT_RATE
        points[k, BIAS_RATE] = ctx[base]
        points[k, MASS_SCALE] = ctx[base + 1]
        points[k, IMPULSE_SCALE] = ctx[base + 2]
        same_before = k > 0 and ids[k - 1, 0] == a and ids[k - 1, 1] == b
        same_after = k + 1 < n and ids[k + 1, 0] == a and ids[k + 1, 1] == b
        points[k, SHARED] = 1.0 if same_before or same_after else 0.0
        points[k, STEP_J] = 0.0
        points[k, GROSS_J] = points[k, DRIFT] = 0.0
        points[k, MAX_J] = 0.0


@inline
def dormant(body_i, contact_i, world_i, w, terms, j) -> bool:
    """A cached point whose two bodies both rest this step (and exist): kept as it is."""
    a, b = contact_i[w, j, BODY_A], contact_i[w, j, BODY_B]
    return (
        (terms[a, MOVING] == 0.0)
        & (terms[b, MOVING] == 0.0)
        & (body_i[w, a, ENABLED] == 1)
        & (body_i[w, b, ENABLED] == 1)
    )


@kernel
def count_dormant(body_i, contact_i, world_i, w, terms) -> int:
    count = 0
    for j in range(world_i[w, CONTACT_COUNT]):
        if dormant(body_i, contact_i, world_i, w, terms, j):
            count += 1
    return count


@kernel
def _copy_point(merged, merged_ids, m, points, ids, k, terms) -> None:
    a = ids[k, 0]
    merged[m, NORMAL_IMPULSE] = points[k, NORMAL_J]
    merged[m, TANGENT_IMPULSE] = points[k, TANGENT_J]
    merged[m, STEP_IMPULSE] = points[k, STEP_J]
    merged[m, GROSS_IMPULSE] = points[k, GROSS_J]
    merged[m, KEPT_TORQUE] = points[k, DRIFT] * points[k, GROSS_J]
    merged[m, APPROACH] = points[k, APPROACH_SPEED]
    merged[m, POINT_X] = terms[a, X0] + points[k, RAX]
    merged[m, POINT_Y] = terms[a, Y0] + points[k, RAY]
    merged[m, CONTACT_NX] = points[k, NX]
    merged[m, CONTACT_NY] = points[k, NY]
    merged[m, SEPARATION] = points[k, SEP0]
    merged_ids[m, 0], merged_ids[m, 1], merged_ids[m, 2] = ids[k, 0], ids[k, 1], ids[k, 2]


@kernel
def store(body_i, contact, contact_i, world_i, w, terms, points, ids, n, merged, merged_ids):
    """The new cache: this step's points merged, in key order, with the dormant ones."""
    cached, m, j = world_i[w, CONTACT_COUNT], 0, 0
    for k in range(n + 1):
        key = point_key(ids[k, 0], ids[k, 1], ids[k, 2]) if k < n else -1
        while j < cached:
            old = point_key(
                contact_i[w, j, BODY_A], contact_i[w, j, BODY_B], contact_i[w, j, FEATURE]
            )
            if k < n and old > key:
                break
            j += 1
            if k < n and old == key:
                break  # this step's point replaces it
            if dormant(body_i, contact_i, world_i, w, terms, j - 1):
                for column in range(CONTACT_F):
                    merged[m, column] = contact[w, j - 1, column]
                merged[m, STEP_IMPULSE] = merged[m, GROSS_IMPULSE] = 0.0
                merged[m, KEPT_TORQUE] = 0.0
                for column in range(CONTACT_I):
                    merged_ids[m, column] = contact_i[w, j - 1, column]
                m += 1
        if k < n:
            _copy_point(merged, merged_ids, m, points, ids, k, terms)
            m += 1
    for j in range(m):
        for column in range(CONTACT_F):
            contact[w, j, column] = merged[j, column]
        for column in range(CONTACT_I):
            contact_i[w, j, column] = merged_ids[j, column]
    # Rows past the count stay zero (state.py), so a world is its first rows alone: the
    # undo of a refused call (refusal.py) saves and puts back only those.
    contact[w, m:cached] = 0.0
    contact_i[w, m:cached] = 0
    world_i[w, CONTACT_COUNT] = m
