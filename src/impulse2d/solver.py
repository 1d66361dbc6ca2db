"""The contact solver: Box2D v3's soft step, Gauss-Seidel over one world's points in order.

One step of ``dt`` is split into ``substeps`` of ``h = dt / substeps``; each substep:

1. integrate velocities (gravity, forces, springs, drag) -- ``integrate.py``;
2. ``warm_start``: apply the impulses accumulated so far;
3. ``solve(use_bias=True)``: non-penetration with a *soft* position correction (a
   spring-damper of ``contact_hertz``) plus Coulomb friction, point after point;
4. integrate positions -- ``integrate.py``;
5. ``solve(use_bias=False)`` (the *relax* pass): the same without the position bias,
   which removes the velocity the bias added, so pushing bodies apart does not make them
   bounce.

After the substeps, ``restitution`` applies the bounce once.

Speculative contacts (``separation > 0``) are hard: the closing speed is limited to
``separation / h``, so a body arrives at the surface and no further (in the last relax
pass of a step they are left to the next step, see ``solve``). The separation of a
point during the step is its separation at the start plus ``J . dq``, the motion of the
two bodies along the normal since then (rotation linearised: ``dq`` is small).

The tutorial resolves each collision once with an impulse and then pushes the bodies
apart by the penetration ("contact forces"); here both are the same constraint, iterated,
which is what lets boxes stack. Sign conventions are in ``contacts.py``.
"""

from __future__ import annotations

import math

from . import settings as ctx_
from ._jit import inline, kernel
from .state import ANGLE, VX, VY, W, X, Y
from .workspace import (
    AGAINST_PLANE,
    ANGLE0,
    APPROACH_SPEED,
    BEFORE_V,
    BIAS_RATE,
    BOUNCE,
    HALF_SPEC,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPACT_V,
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

_SHARED_SWEEPS = 8  # restitution sweeps for pairs that strike at two points (see restitution)


@inline
def push(body, w, a, b, points, k, normal, tangent) -> None:
    """Apply ``normal`` along n and ``tangent`` along t at point ``k``: to B, and the
    opposite to A. (Kernels index ``array[w, i, COLUMN]`` throughout: row views inside
    loops cost numba reference counting and make a solver sweep four times slower.)"""
    nx, ny = points[k, NX], points[k, NY]
    px = normal * nx + tangent * ny  # t = (n_y, -n_x)
    py = normal * ny - tangent * nx
    body[w, a, VX] -= points[k, IMA] * px
    body[w, a, VY] -= points[k, IMA] * py
    body[w, a, W] -= points[k, IIA] * (points[k, RNA] * normal + points[k, RTA] * tangent)
    body[w, b, VX] += points[k, IMB] * px
    body[w, b, VY] += points[k, IMB] * py
    body[w, b, W] += points[k, IIB] * (points[k, RNB] * normal + points[k, RTB] * tangent)


@inline
def _along(body, w, a, b, dx, dy, cross_a, cross_b) -> float:
    """``J . V`` for the direction ``(dx, dy)`` with the Jacobian's cross terms
    ``rA x d`` and ``rB x d``: the relative velocity of the point along it."""
    return (
        -(dx * body[w, a, VX] + dy * body[w, a, VY])
        - cross_a * body[w, a, W]
        + dx * body[w, b, VX]
        + dy * body[w, b, VY]
        + cross_b * body[w, b, W]
    )


@inline
def normal_velocity(body, w, a, b, points, k) -> float:
    """The relative velocity of point ``k`` along the normal (< 0: closing)."""
    return _along(body, w, a, b, points[k, NX], points[k, NY], points[k, RNA], points[k, RNB])


@inline
def tangent_velocity(body, w, a, b, points, k) -> float:
    """... and along the tangent ``t = (n_y, -n_x)``."""
    return _along(body, w, a, b, points[k, NY], -points[k, NX], points[k, RTA], points[k, RTB])


@inline
def current_separation(body, w, a, b, points, k, terms) -> float:
    """The separation at the step start plus ``J_n . dq`` since then."""
    nx, ny = points[k, NX], points[k, NY]
    return (
        points[k, SEP0]
        - (nx * (body[w, a, X] - terms[a, X0]) + ny * (body[w, a, Y] - terms[a, Y0]))
        - points[k, RNA] * (body[w, a, ANGLE] - terms[a, ANGLE0])
        + nx * (body[w, b, X] - terms[b, X0])
        + ny * (body[w, b, Y] - terms[b, Y0])
        + points[k, RNB] * (body[w, b, ANGLE] - terms[b, ANGLE0])
    )


@kernel
def warm_start(body, w, points, ids, n) -> None:
    """Apply every point's accumulated normal and friction impulses."""
    for k in range(n):
        normal, tangent = points[k, NORMAL_J], points[k, TANGENT_J]
        if normal != 0.0 or tangent != 0.0:
            points[k, STEP_J] += normal
            push(body, w, ids[k, 0], ids[k, 1], points, k, normal, tangent)


@inline
def watched(points, k) -> bool:
    """Points whose velocity at first touch restitution will need (see ``restitution``)."""
    return (
        (points[k, SHARED] == 1.0)
        & (points[k, APPROACH_SPEED] < 0.0)
        & (points[k, MIXED_RESTITUTION] > 0.0)
    )


@inline
def solve_point(body, w, ctx, terms, points, ids, k, use_bias, last) -> None:
    """Non-penetration, then friction, at point ``k`` (see ``solve``)."""
    inv_h, push_speed = ctx[ctx_.INV_H], ctx[ctx_.PUSH_SPEED]
    a, b = ids[k, 0], ids[k, 1]
    s = current_separation(body, w, a, b, points, k, terms)
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
            return
        bias, mass_scale, impulse_scale = s * inv_h, 1.0, 0.0  # speculative: arrive, no more
    elif use_bias:
        mass_scale, impulse_scale = points[k, MASS_SCALE], points[k, IMPULSE_SCALE]
        bias = max(mass_scale * points[k, BIAS_RATE] * s, -push_speed)
    else:
        bias, mass_scale, impulse_scale = 0.0, 1.0, 0.0
    vn = normal_velocity(body, w, a, b, points, k)
    accumulated = points[k, NORMAL_J]
    impulse = -points[k, NORMAL_MASS] * (mass_scale * vn + bias) - impulse_scale * accumulated
    total = max(accumulated + impulse, 0.0)
    change = total - accumulated
    points[k, NORMAL_J] = total
    points[k, STEP_J] += change
    points[k, MAX_J] = max(points[k, MAX_J], change)
    push(body, w, a, b, points, k, change, 0.0)
    friction = points[k, MIXED_FRICTION]
    if friction > 0.0:
        vt = tangent_velocity(body, w, a, b, points, k)
        limit = friction * total
        old = points[k, TANGENT_J]
        new = min(max(old - points[k, TANGENT_MASS] * vt, -limit), limit)
        push(body, w, a, b, points, k, 0.0, new - old)
        points[k, TANGENT_J] = new


@kernel
def solve(body, w, ctx, terms, points, ids, n, use_bias, last=False) -> None:
    """One Gauss-Seidel sweep over the points, in order: non-penetration, then friction
    within the cone of the normal impulse just found.

    The normal impulse solves ``J v + bias = 0`` softly and is clamped so the accumulated
    impulse stays >= 0 (contacts push, never pull); friction is clamped to the Coulomb
    cone ``|lambda_t| <= mu lambda_n``. Restitution needs, for points that share their
    pair, the normal velocity at which a point first pushes; it is read before the sweep,
    so the order in which a box's two corners are solved does not change it.

    Points against a plane are solved after all others: in Gauss-Seidel the last
    constraint solved holds exactly, and a plane, the world's boundary, must win over a
    kinematic body squeezing a body against it (whose push it then undoes)."""
    for k in range(n):
        if watched(points, k) and points[k, IMPACT_V] == 0.0:
            points[k, BEFORE_V] = normal_velocity(body, w, ids[k, 0], ids[k, 1], points, k)
    for boundary in range(2):
        for k in range(n):
            if points[k, AGAINST_PLANE] == boundary:
                solve_point(body, w, ctx, terms, points, ids, k, use_bias, last)
    for k in range(n):
        if watched(points, k) and points[k, IMPACT_V] == 0.0 and points[k, MAX_J] > 0.0:
            points[k, IMPACT_V] = points[k, BEFORE_V]


@kernel
def bounce_targets(body, w, ctx, terms, points, ids, n) -> bool:
    """Which points bounce and the normal velocity each must reach; returns whether any
    pair shares its bounce between points (see ``restitution``).

    A point bounces if it closed faster than the threshold at the step start and pushed.
    With ``e = 0`` it must also touch at the end of the step (within a tenth of the pair's
    speculative distance): the points of a pair can push before its bodies meet, to limit
    how fast they may close (see ``solve``), and bringing those to rest along the normal
    would stop the bodies in mid-air. (With ``e > 0`` that early bounce keeps the speed
    right, at the price of a position up to the gap off.)"""
    threshold, h = ctx[ctx_.RESTITUTION_THRESHOLD], ctx[ctx_.H]
    for k in range(n):
        a, b = ids[k, 0], ids[k, 1]
        eligible = points[k, APPROACH_SPEED] < -threshold and points[k, MAX_J] > 0.0
        if eligible and points[k, MIXED_RESTITUTION] == 0.0:
            reach = 0.1 * (terms[a, HALF_SPEC] + terms[b, HALF_SPEC])
            eligible = current_separation(body, w, a, b, points, k, terms) <= reach
        points[k, BOUNCE] = 1.0 if eligible else 0.0
    shared_any = False
    start = 0
    while start < n:  # a pair's points are neighbours
        end = start + 1
        while end < n and ids[end, 0] == ids[start, 0] and ids[end, 1] == ids[start, 1]:
            end += 1
        bouncing = 0
        for k in range(start, end):
            bouncing += 1 if points[k, BOUNCE] > 0.0 else 0
        for k in range(start, end):
            if points[k, BOUNCE] == 0.0:
                continue
            e, accel = points[k, MIXED_RESTITUTION], points[k, NORMAL_ACCEL]
            if bouncing == 1 and e == 0.0:  # the solver already stopped it
                points[k, BOUNCE] = 0.0
            elif bouncing > 1:
                points[k, BOUNCE] = 2.0
                points[k, TARGET] = e * min(points[k, IMPACT_V], 0.0)
                shared_any = True
            else:
                half_kick = 0.5 * h * accel
                approach = -(points[k, APPROACH_SPEED] + half_kick)
                gap = max(points[k, SEP0], 0.0)
                impact = math.sqrt(max(approach * approach - 2.0 * accel * gap, 0.0))
                points[k, TARGET] = -(e * impact - half_kick)
        start = end
    return shared_any


@kernel
def restitution(body, w, ctx, terms, points, ids, n) -> None:
    """Bounce: send each impacting point apart at ``e`` times its impact speed.

    Only points that approached faster than ``restitution_threshold`` at the start of the
    step, and pushed during it, take part, so resting contacts stay at rest and a ball at
    rest in a rack that is hit does not "bounce" off its neighbours.

    A pair that strikes at one point gets Newton's law, ``v_n' = -e v_n``, with two
    corrections to Box2D's form that make bounces under gravity keep energy:

    * The impact speed is the approach speed at the step start, ``u``, carried over the
      remaining gap ``s`` under the constant closing acceleration ``c = -a_n`` (gravity
      and applied forces): ``u_impact = sqrt(u^2 + 2 c s)``. Without it a ball dropped
      2 m at 60 Hz loses 2.6 % of its energy per bounce on average.
    * The semi-implicit Euler integrator (``v += h a; x += h v``) stores, under a constant
      acceleration, the velocity of half a substep *earlier*; the velocity in step with
      the position is ``v + h a / 2``. So ``u = -(v_n + h a_n / 2)`` and the stored
      outgoing velocity is ``e u_impact - h a_n / 2``. Without it a bounce loses
      ``m g h v`` (1 % per bounce at 60 Hz with 4 substeps).

    A pair that strikes at two points (a box landing on a face, a spinning box whose
    corners arrive one after the other) is different: its points' speeds at the start of
    the step are not their speeds at impact, and Newton's law on them can give the pair a
    quarter more kinetic energy than it had. Its points use the normal velocity they had
    when they first pushed, and a few Gauss-Seidel sweeps share the bounce between them
    as a simultaneous impact would (solved one after the other, the first point would take
    it all and set a flat-landing box spinning). That includes ``e = 0``: the sweeps bring
    both points to rest along the normal, which the solver's own passes leave a few per
    cent short of for an impact that happens within one step (two boxes meeting face to
    face would part again instead of moving on together).
    """
    shared_any = bounce_targets(body, w, ctx, terms, points, ids, n)
    for sweep in range(_SHARED_SWEEPS if shared_any else 1):
        for k in range(n):
            bounce = points[k, BOUNCE]
            if bounce == 0.0 or (sweep > 0 and bounce != 2.0):
                continue
            a, b = ids[k, 0], ids[k, 1]
            vn = normal_velocity(body, w, a, b, points, k)
            # What the bounce may take back is what the point pushed over the step: a
            # contact never pulls, over the step (not only over the last substep).
            pushed = points[k, STEP_J]
            total = max(pushed - points[k, NORMAL_MASS] * (vn + points[k, TARGET]), 0.0)
            change = total - pushed
            points[k, STEP_J] = total
            points[k, NORMAL_J] = max(points[k, NORMAL_J] + change, 0.0)
            push(body, w, a, b, points, k, change, 0.0)
