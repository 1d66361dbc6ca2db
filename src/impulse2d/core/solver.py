"""The contact solver: Box2D v3's soft step, Gauss-Seidel over one world's points in order.

One step of ``dt`` is split into ``substeps`` of ``h = dt / substeps``; each substep:

1. integrate velocities (gravity, forces, springs, drag) -- ``integrate.py``;
2. ``warm_start``: apply the impulses accumulated so far;
3. ``solve``: non-penetration with a *soft* position correction (a spring-damper of
   ``contact_hertz``) plus Coulomb friction, point after point;
4. integrate positions -- ``integrate.py``;
5. ``relax``: the same sweep without the position bias, which removes the velocity the
   bias added, so pushing bodies apart does not make them bounce.

Both are one sweep, ``sweep(..., use_bias, last)``, named by what they are for.

After the substeps, ``restitution`` applies the bounce (all bouncing points at once).

Speculative contacts (``separation > 0``) are hard: the closing speed is limited to
``separation / h``, so a body arrives at the surface and no further (in the last relax
pass of a step they are left to the next step, see ``solve_normal``). The separation of a
point during the step is its separation at the start plus ``J . dq``, the motion of the
two bodies along the normal since then (rotation linearised: ``dq`` is small).

The tutorial resolves each collision once with an impulse and then pushes the bodies
apart by the penetration ("contact forces"); here both are the same constraint, iterated,
which is what lets boxes stack. Sign conventions are in ``contacts.py``.
"""

from __future__ import annotations

import math

from . import context
from ._jit import inline, kernel
from .colouring import manifold_end, pair_at
from .state import ANGLE, OMEGA, VX, VY, X, Y
from .workspace import (
    AGAINST_PLANE,
    ANGLE0,
    APPROACH_SPEED,
    BIAS_RATE,
    BOUNCE,
    GROSS_J,
    HALF_SPEC,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPULSE_SCALE,
    MASS_SCALE,
    MAX_J,
    MIXED_FRICTION,
    MIXED_RESTITUTION,
    NORMAL_ACCEL,
    NORMAL_J,
    NORMAL_MASS,
    NX,
    NY,
    RNA,
    RNB,
    RTA,
    RTB,
    SEP0,
    SHARED,
    STEP_J,
    TANGENT_J,
    TANGENT_MASS,
    TARGET,
    X0,
    Y0,
)

_BOUNCE_SWEEPS = 64  # at most this many restitution sweeps when several points bounce
_BOUNCE_TOLERANCE = 1e-9  # ... until no point's speed changes by more than this (relative)
_PLANE_SWEEPS = 4  # sweeps of the points against planes in each pass (see solve)


@inline
def velocities(body, w, a, b):
    """Bodies ``a`` and ``b``'s velocities as values ``(vxA, vyA, wA, vxB, vyB, wB)``.

    The sweeps work on these values, loaded once a pair and stored after it: stored and
    loaded again at every push, LLVM must assume a store to ``body`` may have changed the
    point's row (it cannot tell the arrays apart) and reloads both. The arithmetic is the
    same, in the same order, so the results are bitwise those of pushing in place."""
    return (body[w, a, VX], body[w, a, VY], body[w, a, OMEGA],
            body[w, b, VX], body[w, b, VY], body[w, b, OMEGA])  # fmt: skip


@inline
def store_velocities(body, w, a, b, v) -> None:
    """``velocities``' values written back."""
    body[w, a, VX], body[w, a, VY], body[w, a, OMEGA] = v[0], v[1], v[2]
    body[w, b, VX], body[w, b, VY], body[w, b, OMEGA] = v[3], v[4], v[5]


@inline
def pushed(v, points, k, normal, tangent):
    """``v`` after ``normal`` along n and ``tangent`` along t at point ``k``: to B, and
    the opposite to A. ``GROSS_J`` sums the pushes' sizes: what a point that keeps the
    step start's Jacobian may exert as torque is bounded by it (see
    ``contacts.follow_bodies``). (Kernels index ``array[w, i, COLUMN]`` throughout: row
    views inside loops cost numba reference counting and make a sweep four times
    slower.)"""
    points[k, GROSS_J] += abs(normal) + abs(tangent)
    nx, ny = points[k, NX], points[k, NY]
    px = normal * nx + tangent * ny  # t = (n_y, -n_x)
    py = normal * ny - tangent * nx
    ima, imb = points[k, IMA], points[k, IMB]
    return (
        v[0] - ima * px,
        v[1] - ima * py,
        v[2] - points[k, IIA] * (points[k, RNA] * normal + points[k, RTA] * tangent),
        v[3] + imb * px,
        v[4] + imb * py,
        v[5] + points[k, IIB] * (points[k, RNB] * normal + points[k, RTB] * tangent),
    )


@inline
def push(body, w, a, b, points, k, normal, tangent) -> None:
    """``pushed`` on the bodies themselves."""
    v = pushed(velocities(body, w, a, b), points, k, normal, tangent)
    store_velocities(body, w, a, b, v)


@inline
def along(v, dx, dy, cross_a, cross_b) -> float:
    """``J . V`` for the direction ``(dx, dy)`` with the Jacobian's cross terms
    ``rA x d`` and ``rB x d``: the relative velocity of the point along it."""
    return -(dx * v[0] + dy * v[1]) - cross_a * v[2] + dx * v[3] + dy * v[4] + cross_b * v[5]


@inline
def normal_speed(v, points, k) -> float:
    """The relative velocity of point ``k`` along the normal (< 0: closing)."""
    return along(v, points[k, NX], points[k, NY], points[k, RNA], points[k, RNB])


@inline
def normal_velocity(body, w, a, b, points, k) -> float:
    """``normal_speed`` of the bodies themselves."""
    return normal_speed(velocities(body, w, a, b), points, k)


@inline
def tangent_speed(v, points, k) -> float:
    """... and along the tangent ``t = (n_y, -n_x)``."""
    return along(v, points[k, NY], -points[k, NX], points[k, RTA], points[k, RTB])


@inline
def moved(body, w, terms, a, b):
    """How far bodies ``a`` and ``b`` moved since the step start, as values ``(dxA, dyA,
    dqA, dxB, dyB, dqB)`` (m, rad): positions do not change within a sweep, so a pair
    computes them once."""
    return (body[w, a, X] - terms[a, X0], body[w, a, Y] - terms[a, Y0],
            body[w, a, ANGLE] - terms[a, ANGLE0], body[w, b, X] - terms[b, X0],
            body[w, b, Y] - terms[b, Y0], body[w, b, ANGLE] - terms[b, ANGLE0])  # fmt: skip


@inline
def separation(points, k, d) -> float:
    """The separation of point ``k`` at the step start plus ``J_n . dq`` since then, for
    the bodies' motion ``d`` (``moved``)."""
    nx, ny = points[k, NX], points[k, NY]
    return (
        points[k, SEP0]
        - (nx * d[0] + ny * d[1])
        - points[k, RNA] * d[2]
        + nx * d[3]
        + ny * d[4]
        + points[k, RNB] * d[5]
    )


@inline
def current_separation(body, w, a, b, points, k, terms) -> float:
    """``separation`` of the bodies themselves."""
    return separation(points, k, moved(body, w, terms, a, b))


@kernel
def warm_start(body, w, points, ids, n, others) -> None:
    """Apply every point's accumulated normal and friction impulses, but in a coloured
    world only those of the pairs ``others`` lists (``lanes.warm_start_coloured`` warm
    starts the rest; ``pair_at``)."""
    p, start = 0, pair_at(others, 0, 0)
    while start < n:
        end = manifold_end(ids, n, start)
        for k in range(start, end):
            normal, tangent = points[k, NORMAL_J], points[k, TANGENT_J]
            if normal != 0.0 or tangent != 0.0:
                points[k, STEP_J] += normal
                push(body, w, ids[k, 0], ids[k, 1], points, k, normal, tangent)
        p += 1
        start = pair_at(others, p, end)


@inline
def solve_normal(ctx, points, k, use_bias, last, v, d):
    """Non-penetration at point ``k`` (see ``sweep``): ``v`` (``velocities``) after it,
    its bodies having moved ``d`` (``moved``)."""
    inv_h, push_speed = ctx[context.INV_H], ctx[context.PUSH_SPEED]
    s = separation(points, k, d)
    if s > 0.0:
        untouched = points[k, MAX_J] == 0.0 and points[k, NORMAL_J] == 0.0
        if last and untouched and points[k, SHARED] == 0.0:
            # The last relax pass, for a lone point that has not touched: limiting the
            # approach here would be for the next step's first substep, which limits
            # it itself before anything moves. Done here it slowed a ball before it
            # arrived and counted as an impact, which restitution bounced in mid-air.
            # (A pair's several points are coupled through its bodies' turning: their
            # one sweep per pass needs this second one, or a box landing fast on a
            # face can sink a corner; Box2D keeps it for every point.)
            return v
        bias, mass_scale, impulse_scale = s * inv_h, 1.0, 0.0  # speculative: arrive, no more
    elif use_bias:
        mass_scale, impulse_scale = points[k, MASS_SCALE], points[k, IMPULSE_SCALE]
        bias = max(mass_scale * points[k, BIAS_RATE] * s, -push_speed)
    else:
        bias, mass_scale, impulse_scale = 0.0, 1.0, 0.0
    vn = normal_speed(v, points, k)
    accumulated = points[k, NORMAL_J]
    impulse = -points[k, NORMAL_MASS] * (mass_scale * vn + bias) - impulse_scale * accumulated
    total = max(accumulated + impulse, 0.0)
    change = total - accumulated
    points[k, NORMAL_J] = total
    points[k, STEP_J] += change
    points[k, MAX_J] = max(points[k, MAX_J], change)
    return pushed(v, points, k, change, 0.0)


@inline
def solve_friction(points, k, v):
    """Coulomb friction at point ``k``, within the cone of its normal impulse: ``v``
    after it."""
    friction = points[k, MIXED_FRICTION]
    if friction > 0.0:
        vt = tangent_speed(v, points, k)
        limit = friction * points[k, NORMAL_J]
        old = points[k, TANGENT_J]
        new = min(max(old - points[k, TANGENT_MASS] * vt, -limit), limit)
        v = pushed(v, points, k, 0.0, new - old)
        points[k, TANGENT_J] = new
    return v


@inline
def soft_row(ctx, points, k, use_bias, d):
    """The soft constraint of point ``k`` as ``(mass_scale, bias, impulse_scale)``: its
    impulse solves ``mass_scale v_n + bias + impulse_scale K lambda = 0`` (``K`` its
    effective inverse mass, ``lambda`` its accumulated impulse), as in ``solve_normal``."""
    s = separation(points, k, d)
    if s > 0.0:
        return 1.0, s * ctx[context.INV_H], 0.0
    if use_bias:
        mass_scale = points[k, MASS_SCALE]
        bias = max(mass_scale * points[k, BIAS_RATE] * s, -ctx[context.PUSH_SPEED])
        return mass_scale, bias, points[k, IMPULSE_SCALE]
    return 1.0, 0.0, 0.0


@inline
def solve_pair_normals(ctx, points, k, use_bias, v, d):
    """Both normal impulses of a two-point pair at once (Box2D v2's block solver, here
    for soft rows), from and to the pair's ``velocities`` ``v``; returns ``(solved,
    v)``: not solved, having changed nothing, if the two rows are too nearly parallel
    to solve together (then they are solved one after the other).

    Every two-point pair is solved so, resting or striking. Solved one after the other,
    the point solved first takes more than its share each sweep, and the order of a
    pair's points is fixed by the winding of the reference face: in Box2D's
    ``large_pyramid`` (5,050 boxes) that bias pushed the upper half 0.25-0.33 m to one
    side in 500 steps, the same way when the scene was mirrored and the other way when
    the points were taken in reverse (Box2D v3, one after the other too: 0.08 m). Solved
    together the largest shift is 0.13 m and follows the scene's mirror image; it costs
    about a tenth more solver time on that scene. Inlined at one call site (``sweep``
    loops over its passes rather than calling ``solve_pairs`` three times), which costs
    a few seconds of the first compile.

    With ``d`` the two increments and ``x = lambda + d`` the totals, row ``i`` asks
    ``ms_i (v_i + sum_j K_ij d_j) + bias_i + is_i K_ii x_i = 0`` for ``x_i > 0``, or that
    left side ``>= 0`` for ``x_i = 0`` (a contact pushes, never pulls): a 2x2 linear
    complementarity problem, solved by trying its four cases, both pushing first.
    Solved one after the other instead, the first point takes the whole impact and
    turns the body, which the second then undoes: a box landing flat would be left
    turning, and friction would turn that turning into sliding (more energy than it
    came with)."""
    j = k + 1
    ima, imb, iia, iib = points[k, IMA], points[k, IMB], points[k, IIA], points[k, IIB]
    k11 = ima + imb + iia * points[k, RNA] * points[k, RNA] + iib * points[k, RNB] * points[k, RNB]
    k22 = ima + imb + iia * points[j, RNA] * points[j, RNA] + iib * points[j, RNB] * points[j, RNB]
    k12 = ima + imb + iia * points[k, RNA] * points[j, RNA] + iib * points[k, RNB] * points[j, RNB]
    if not k11 * k22 - k12 * k12 > 1e-3 * k11 * k22:
        return False, v
    ms1, bias1, is1 = soft_row(ctx, points, k, use_bias, d)
    ms2, bias2, is2 = soft_row(ctx, points, j, use_bias, d)
    acc1, acc2 = points[k, NORMAL_J], points[j, NORMAL_J]
    # Row i: A_i1 d_1 + A_i2 d_2 = r_i.
    a11, a12, r1 = (
        ms1 * k11 + is1 * k11,
        ms1 * k12,
        -(ms1 * normal_speed(v, points, k) + bias1 + is1 * k11 * acc1),
    )
    a21, a22, r2 = (
        ms2 * k12,
        ms2 * k22 + is2 * k22,
        -(ms2 * normal_speed(v, points, j) + bias2 + is2 * k22 * acc2),
    )
    det = a11 * a22 - a12 * a21
    d1 = d2 = 0.0
    found = False
    if det != 0.0:  # both push
        d1, d2 = (r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det
        found = acc1 + d1 >= 0.0 and acc2 + d2 >= 0.0
    if not found:  # only the first pushes
        d2 = -acc2
        d1 = (r1 - a12 * d2) / a11
        found = acc1 + d1 >= 0.0 and a21 * d1 + a22 * d2 - r2 >= 0.0
    if not found:  # only the second
        d1 = -acc1
        d2 = (r2 - a21 * d1) / a22
        found = acc2 + d2 >= 0.0 and a11 * d1 + a12 * d2 - r1 >= 0.0
    if not found:  # neither
        d1, d2 = -acc1, -acc2
        found = a11 * d1 + a12 * d2 - r1 >= 0.0 and a21 * d1 + a22 * d2 - r2 >= 0.0
    if not found:
        return False, v
    points[k, NORMAL_J] += d1
    points[k, STEP_J] += d1
    points[k, MAX_J] = max(points[k, MAX_J], d1)
    v = pushed(v, points, k, d1, 0.0)
    points[j, NORMAL_J] += d2
    points[j, STEP_J] += d2
    points[j, MAX_J] = max(points[j, MAX_J], d2)
    return True, pushed(v, points, j, d2, 0.0)


@inline
def solve_pairs(body, w, ctx, terms, points, ids, n, use_bias, last, boundary, repeats,
                others) -> bool:  # fmt: skip
    """One sweep over the pairs (those ``others`` lists in a coloured world,
    ``pair_at``) against a plane (``boundary`` 1.0) or the others (0.0); returns whether
    a pair of them has more than two points (coupled by its body's turning, which one
    sweep does not settle). A pair of two points has its normals solved at once
    (``solve_pair_normals``); others one point after the other, and such a pair is
    solved ``repeats`` times over before the sweep moves on."""
    coupled = False
    p, start = 0, pair_at(others, 0, 0)
    while start < n:  # a pair's points are neighbours
        end = manifold_end(ids, n, start)
        if points[start, AGAINST_PLANE] == boundary:  # never a coloured one's IN_COLOUR
            coupled |= end - start > 2
            a, b = ids[start, 0], ids[start, 1]
            v = velocities(body, w, a, b)  # the pair's bodies, as values until it is done
            d = moved(body, w, terms, a, b)
            for _ in range(repeats if end - start > 2 else 1):
                solved = False
                if end - start == 2:
                    solved, v = solve_pair_normals(ctx, points, start, use_bias, v, d)
                if not solved:
                    for k in range(start, end):
                        v = solve_normal(ctx, points, k, use_bias, last, v, d)
                for k in range(start, end):
                    v = solve_friction(points, k, v)
            store_velocities(body, w, a, b, v)
        p += 1
        start = pair_at(others, p, end)
    return coupled


@inline
def solve(body, w, ctx, terms, points, ids, n, rest, others) -> None:
    """The biased sweep of a substep: contacts pushed apart softly (``sweep``)."""
    sweep(body, w, ctx, terms, points, ids, n, True, False, rest, others)


@inline
def relax(body, w, ctx, terms, points, ids, n, last_substep, rest, others) -> None:
    """The relax sweep of a substep, without the position bias (``sweep``);
    ``last_substep``: the step's last, which leaves lone untouched points alone."""
    sweep(body, w, ctx, terms, points, ids, n, False, last_substep, rest, others)


@kernel
def sweep(body, w, ctx, terms, points, ids, n, use_bias, last, rest, others) -> None:
    """One Gauss-Seidel sweep over the pairs in order, but those of coloured manifolds
    (``lanes.solve_coloured`` solves them first; in a coloured world it walks the pairs
    ``others`` lists, ``pair_at``): ``rest`` is how many points are left, and with none
    left there is nothing to do. At each pair: non-penetration at each of
    its points, then friction at each, within the cone of the normal impulse.

    The normal impulse solves ``J v + bias = 0`` softly and is clamped so the accumulated
    impulse stays >= 0 (contacts push, never pull); friction is clamped to the Coulomb
    cone ``|lambda_t| <= mu lambda_n``. Friction comes after all of a pair's normals (as
    in Box2D): a box landing flat on a face gets uneven normal impulses from its two
    points solved one after the other, the first one turning it, and friction solved in
    between would meet the sliding that turning makes at the second point, push against
    it and leave the box moving sideways with more energy than it had. A pair of two
    points has both normals solved at once (``solve_pair_normals``).

    Points against a plane are solved after all others, in ``_PLANE_SWEEPS`` sweeps when
    a pair has more than two (one otherwise; a pair of two is solved exactly): in
    Gauss-Seidel the last constraint solved holds exactly, and a plane, the world's
    boundary, must win over a body squeezing another against it (a kinematic pusher, or a
    heavy ball landing on a light plank, whose push it then undoes). A plank has up to
    four points against the plane, coupled through its turning; one sweep leaves it
    tipping into the ground, four converge (a 1 kg ball at 9 m/s on a 0.1 kg plank at
    32 Hz pushed the plank's centre 8 mm behind the plane with one). In a small world
    planes have few points, so the sweeps cost little. A large one (``ctx[COLOUR_FROM]``
    points or more, the worlds ``colouring.py`` colours) can have a thousand, most of
    them pairs of one or two points that one sweep settles: there each pair of more
    than two is solved ``_PLANE_SWEEPS`` times over where it stands, and the plane pairs
    are swept once (a rain of 1,000 bodies had 21 such pairs among 1,054 plane points,
    and sweeping all of them four more times cost half its solver time)."""
    if rest == 0:
        return
    large = n >= ctx[context.COLOUR_FROM]
    repeats = _PLANE_SWEEPS if large else 1
    # One call site for the inlined solve_pairs (each site compiles its own copy): pass 0
    # the pairs between bodies, then the plane pairs, once or _PLANE_SWEEPS times.
    sweeps = 2
    done = 0
    while done < sweeps:
        boundary = 0.0 if done == 0 else 1.0
        coupled = solve_pairs(body, w, ctx, terms, points, ids, n, use_bias, last, boundary,
                              repeats if done == 1 else 1, others)  # fmt: skip
        if done == 1 and coupled and not large:
            sweeps += _PLANE_SWEEPS - 1
        done += 1


@inline
def bounce_target(points, k, h) -> float:
    """The normal velocity at which point ``k`` must leave: ``e`` times its impact speed.

    The impact speed is the approach speed at the step start, ``u``, carried over the
    remaining gap ``s`` under the constant closing acceleration ``c = -a_n`` (gravity and
    applied forces): ``u_impact = sqrt(u^2 + 2 c s)``. Without it a ball dropped 2 m at
    60 Hz loses 2.6 % of its energy per bounce on average. And the semi-implicit Euler
    integrator (``v += h a; x += h v``) stores, under a constant acceleration, the
    velocity of half a substep *earlier*; the velocity in step with the position is
    ``v + h a / 2``. So ``u = -(v_n + h a_n / 2)`` and the stored outgoing velocity is
    ``e u_impact - h a_n / 2``. Without it a bounce loses ``m g h v`` (1 % per bounce at
    60 Hz with 4 substeps). The returned target is minus that (``v_n + target = 0``)."""
    e, accel = points[k, MIXED_RESTITUTION], points[k, NORMAL_ACCEL]
    half_kick = 0.5 * h * accel
    approach = -(points[k, APPROACH_SPEED] + half_kick)
    gap = max(points[k, SEP0], 0.0)
    impact = math.sqrt(max(approach * approach - 2.0 * accel * gap, 0.0))
    return -(e * impact - half_kick)


@kernel
def bounce_targets(body, w, ctx, terms, points, ids, n) -> tuple[int, int]:
    """Which points bounce and the normal velocity each must reach; returns how many,
    and the first of them: each bouncing point's ``BOUNCE`` is the next one's index plus
    one (``n + 1`` after the last; 0 at points that do not bounce), so the sweeps of
    ``restitution`` visit those points alone, in order (a large world's 40 m/s impact
    had 22 of 92,531 points bouncing, and up to 64 sweeps over every point row to find
    them cost a third of its step).

    A point bounces if it closed faster than the threshold at the step start and pushed.
    With ``e = 0`` it must also touch at the end of the step (within a tenth of the pair's
    speculative distance): the points of a pair can push before its bodies meet, to limit
    how fast they may close (see ``solve``), and bringing those to rest along the normal
    would stop the bodies in mid-air. (With ``e > 0`` that early bounce keeps the speed
    right, at the price of a position up to the gap off.) A lone bouncing point of its
    pair with ``e = 0`` is left as the solver stopped it; several points of a pair bounce
    together, ``e = 0`` included: the sweeps bring them all to rest along the normal,
    which the solver's own passes leave a few per cent short of for an impact that
    happens within one step (two boxes meeting face to face would part again instead of
    moving on together)."""
    threshold, h = ctx[context.RESTITUTION_THRESHOLD], ctx[context.H]
    for k in range(n):
        a, b = ids[k, 0], ids[k, 1]
        eligible = points[k, APPROACH_SPEED] < -threshold and points[k, MAX_J] > 0.0
        if eligible and points[k, MIXED_RESTITUTION] == 0.0:
            reach = 0.1 * (terms[a, HALF_SPEC] + terms[b, HALF_SPEC])
            eligible = current_separation(body, w, a, b, points, k, terms) <= reach
        points[k, BOUNCE] = 1.0 if eligible else 0.0
    count, first, last = 0, n, -1
    start = 0
    while start < n:  # a pair's points are neighbours
        end = manifold_end(ids, n, start)
        bouncing = 0
        for k in range(start, end):
            bouncing += 1 if points[k, BOUNCE] > 0.0 else 0
        for k in range(start, end):
            if points[k, BOUNCE] == 0.0:
                continue
            if bouncing == 1 and points[k, MIXED_RESTITUTION] == 0.0:
                points[k, BOUNCE] = 0.0  # the solver already stopped it
            else:
                points[k, TARGET] = bounce_target(points, k, h)
                count += 1
                if last >= 0:
                    points[last, BOUNCE] = k + 1.0
                else:
                    first = k
                last = k
        start = end
    if last >= 0:
        points[last, BOUNCE] = n + 1.0
    return count, first


@inline
def bounce(body, w, points, ids, k) -> float:
    """Point ``k`` sent to its target velocity; returns the impulse applied.

    What the bounce may take back is what the point pushed over the step: a contact never
    pulls, over the step (not only over the last substep)."""
    a, b = ids[k, 0], ids[k, 1]
    vn = normal_velocity(body, w, a, b, points, k)
    pushed = points[k, STEP_J]
    total = max(pushed - points[k, NORMAL_MASS] * (vn + points[k, TARGET]), 0.0)
    change = total - pushed
    points[k, STEP_J] = total
    points[k, NORMAL_J] = max(points[k, NORMAL_J] + change, 0.0)
    push(body, w, a, b, points, k, change, 0.0)
    return change


@kernel
def restitution(body, w, ctx, terms, points, ids, n) -> None:
    """Bounce: send each impacting point apart at ``e`` times its impact speed.

    Only points that approached faster than ``restitution_threshold`` at the start of the
    step, and pushed during it, take part, so resting contacts stay at rest and a ball at
    rest in a rack that is hit does not "bounce" off its neighbours. Each gets Newton's
    law, ``v_n' = -e u``, ``u`` its approach speed at the step start (as in Box2D; for
    gravity's corrections see ``bounce_target``).

    Why the step start, for every point: over a step the contacts change the velocities
    ``V`` by impulses ``lambda_i`` along their Jacobians ``J_i`` (those of bouncing points
    are kept for the whole step, ``contacts.follow_bodies``), so the kinetic energy
    changes by ``sum_i lambda_i (u_i + v_i') / 2``, ``u_i = J_i V_start`` and ``v_i' =
    J_i V_end`` (the work of an impulse is the impulse times the mean of the velocities
    before and after). Where a point pushed, ``v_i' = -e_i u_i`` makes its term
    ``lambda_i (1 - e_i) u_i / 2 <= 0``: the bounce never adds energy. That holds only
    for approach speeds measured on one state of the bodies: a box whose corner strikes
    first and sets it turning brings its other corner in faster than it started, and
    bouncing that corner at ``e`` times its speed when it first pushed (the velocity
    after the first corner had been stopped, not bounced) gave a box 8 % more energy.

    And it holds only when every bouncing point reaches its target: sent apart one
    after the other, a later point's impulse changes the speed of an earlier one that
    shares a body with it (a box hit by a ball while striking the ground, a box whose
    corners arrive one after the other), which then leaves faster than ``e u`` (the box
    between ball and plane gained 1.5 %), or, solved once each, the first of a box's
    points would take a flat landing all alone and set it spinning. So when several
    points bounce, Gauss-Seidel sweeps over them until no point's speed changes by more
    than ``_BOUNCE_TOLERANCE`` of its approach: the simultaneous impact, in which every
    point that pushes leaves at its target and the others at least as fast.
    """
    count, first = bounce_targets(body, w, ctx, terms, points, ids, n)
    for _ in range(_BOUNCE_SWEEPS if count > 1 else 1):
        settled = True
        k = first
        while k < n:  # the bouncing points, in order (``bounce_targets``)
            change = bounce(body, w, points, ids, k)
            scale = _BOUNCE_TOLERANCE * points[k, NORMAL_MASS] * -points[k, APPROACH_SPEED]
            settled &= abs(change) <= scale
            k = int(points[k, BOUNCE]) - 1
        if settled:
            return
