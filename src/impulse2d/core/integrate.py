"""Integration: the step terms of each body, velocities, positions and springs.

Semi-implicit (symplectic) Euler per substep ``h``: velocities first,
``v <- v exp(-drag h) + h (g + F / m)``, then positions with the new velocity,
``x <- x + h v``. Drag is applied as the exact factor ``exp(-drag h)``, so a body's speed
decays as ``exp(-drag t)`` over any number of steps (an explicit ``v -= drag v h``
drifts from it). Rolling resistance takes a fixed amount ``a h`` off the speed each
substep, never turning the body around: ``v <- v max(0, 1 - a h / |v|)``.

Springs (the tutorial's Spring, corrected): the force on body 2 is
``F = -(k (L - L0) + c v_along) u`` and body 1 gets ``-F``, where ``u`` is the unit vector
from anchor 1 to anchor 2, ``L`` their distance, ``L0`` the rest length and ``v_along``
the relative velocity of the anchors along ``u``; off-centre anchors also get the torque
``r x F``. Applied in every substep, which keeps the period at ``2 pi sqrt(m / k)``. That
integrator is stable only while ``h^2 k w + 2 h c w < 4`` (``w`` the inverse effective
mass along the spring): ``spring_stability`` measures it so the world can refuse a
spring that would explode.
"""

from __future__ import annotations

import math

import numpy as np

from .. import envelope
from . import context
from ._jit import kernel
from .state import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    ANGLE,
    ANGULAR_DRAG,
    AWAKE,
    BOUND,
    BOX,
    COS,
    DAMP_ANGULAR,
    DAMP_H,
    DAMP_LINEAR,
    DAMPING,
    DYNAMIC,
    ENABLED,
    FREE,
    FX,
    FY,
    HALF_H,
    HALF_W,
    INV_MASS,
    INV_MOMENT,
    LINEAR_DRAG,
    LINK,
    OMEGA,
    PLANE,
    POLYGON,
    REST_LENGTH,
    ROLLING,
    ROUNDING,
    SIN,
    SPRING,
    SPRING_ON,
    STIFFNESS,
    TORQUE,
    VERTEX0,
    VERTEX_COUNT,
    VX,
    VY,
    X,
    Y,
)
from .workspace import (
    ACCEL_W,
    ACCEL_X,
    ACCEL_Y,
    ANGLE0,
    BOTTOM,
    HALF_SPEC,
    LEFT,
    MOVABLE,
    MOVING,
    REACH,
    RIGHT,
    ROLL_H,
    SPEED,
    STEP_INV_MASS,
    STEP_INV_MOMENT,
    TOP,
    X0,
    Y0,
)


@kernel
def step_terms(body, body_i, shapes, spring, ends, hull, w, ctx, terms) -> None:
    """Everything ``workspace`` lists per body for this step: ``body_terms``, then the
    springs' share of each body's reach and the broadphase boxes grown by it."""
    body_terms(body, body_i, shapes, w, ctx, terms)
    if ends.shape[0]:
        spring_reach(body, body_i, spring, ends, w, ctx, terms)
    broadphase_boxes(body, body_i, shapes, hull, w, ctx, terms)


@kernel
def body_terms(body, body_i, shapes, w, ctx, terms) -> None:
    """Fill the step terms of every body of world ``w`` (see ``workspace``). (The loop
    body is written out here rather than called: a compiled helper that branches costs
    numba's reference counting of every array it is handed, per call.)"""
    h, spec, substeps = ctx[context.H], ctx[context.SPECULATIVE], ctx[context.SUBSTEPS]
    for i in range(shapes.shape[0]):
        kind, motion = shapes[i, 0], shapes[i, 1]
        enabled = body_i[w, i, ENABLED] == 1
        moving = enabled and body_i[w, i, AWAKE] == 1 and kind != PLANE
        movable = moving and motion == DYNAMIC
        terms[i, MOVING] = 1.0 if moving else 0.0
        terms[i, MOVABLE] = 1.0 if movable else 0.0
        if movable:
            inv_mass = body[w, i, INV_MASS]
            terms[i, STEP_INV_MASS] = inv_mass
            terms[i, STEP_INV_MOMENT] = body[w, i, INV_MOMENT]
            terms[i, ACCEL_X] = h * (ctx[context.GRAVITY_X] + body[w, i, FX] * inv_mass)
            terms[i, ACCEL_Y] = h * (ctx[context.GRAVITY_Y] + body[w, i, FY] * inv_mass)
            terms[i, ACCEL_W] = h * body[w, i, TORQUE] * body[w, i, INV_MOMENT]
            terms[i, ROLL_H] = h * body[w, i, ROLLING]
            if body[w, i, DAMP_H] != h:  # exp(-drag h), recomputed only when h or drag change
                linear, angular = body[w, i, LINEAR_DRAG], body[w, i, ANGULAR_DRAG]
                body[w, i, DAMP_LINEAR] = math.exp(-h * linear) if linear != 0.0 else 1.0
                body[w, i, DAMP_ANGULAR] = math.exp(-h * angular) if angular != 0.0 else 1.0
                body[w, i, DAMP_H] = h
        else:
            terms[i, STEP_INV_MASS] = terms[i, STEP_INV_MOMENT] = 0.0
            terms[i, ACCEL_X] = terms[i, ACCEL_Y] = terms[i, ACCEL_W] = terms[i, ROLL_H] = 0.0
        vx, vy, turn, bound = body[w, i, VX], body[w, i, VY], body[w, i, OMEGA], body[w, i, BOUND]
        # What the velocity can reach within the step: now, plus gravity's and the applied
        # forces' gain over the substeps (springs: ``spring_reach``).
        gain = substeps * (abs(terms[i, ACCEL_X]) + abs(terms[i, ACCEL_Y]))
        gain += substeps * abs(terms[i, ACCEL_W]) * bound
        terms[i, SPEED] = abs(vx) + abs(vy) + abs(turn) * bound if moving else 0.0
        terms[i, REACH] = terms[i, SPEED] + gain if moving else 0.0
        # Half of the speculative distance: the world's, but at most a quarter of the body's
        # size, so small bodies (pool balls) are not given contacts whole radii away. Planes
        # have no size and take the world's.
        terms[i, HALF_SPEC] = 0.5 * (spec if kind == PLANE else min(spec, 0.25 * bound))
        terms[i, X0], terms[i, Y0] = body[w, i, X], body[w, i, Y]
        terms[i, ANGLE0] = body[w, i, ANGLE]


@kernel
def spring_reach(body, body_i, spring, ends, w, ctx, terms) -> None:
    """Add to each body's ``REACH`` what its springs can give it within the step.

    The impulse a spring can deliver over the step is at most its force at the step
    start over the step, ``|F| dt``, plus what its stretch turns into as it swings, the
    momentum ``|stretch| sqrt(k / w)`` (``w`` the inverse effective mass of the anchor
    along the spring: the amplitude of the velocity is ``sqrt(k w) |stretch|``). An
    impulse ``J`` at an anchor ``r`` speeds every point of the body up by at most
    ``J (1/m + |r x u| R / I)``. A stretched spring can fling a resting body across a
    plane in one step; the contacts are made from this reach, so the plane is there."""
    dt = ctx[context.DT]
    for k in range(ends.shape[0]):
        if not spring_acts(body_i, spring, ends, w, k) or spring[w, k, LINK] != SPRING:
            continue  # a joint is a constraint (joints.py), not a force
        a, b = ends[k, 0], ends[k, 1]
        rax, ray, rbx, rby, ux, uy, length = spring_geometry(body, spring, ends, w, k)
        along = spring_speed(body, w, a, b, rax, ray, rbx, rby, ux, uy)
        stretch = abs(length - spring[w, k, REST_LENGTH])
        stiffness = spring[w, k, STIFFNESS]
        force = stiffness * stretch + abs(spring[w, k, DAMPING] * along)
        for i, rx, ry in ((a, rax, ray), (b, rbx, rby)):
            if terms[i, MOVABLE] == 1.0:
                arm = abs(rx * uy - ry * ux)
                inv_mass, inv_moment = terms[i, STEP_INV_MASS], terms[i, STEP_INV_MOMENT]
                inverse = inv_mass + arm * arm * inv_moment
                impulse = force * dt + stretch * math.sqrt(stiffness / inverse)
                terms[i, REACH] += impulse * (inv_mass + arm * inv_moment * body[w, i, BOUND])


@kernel
def outline_extent(body, hull, w, i):
    """The box round body ``i``'s outline as it is turned now, about its centre of mass:
    ``(low_x, high_x, low_y, high_y)`` (m). Each vertex ``v`` is at ``R v`` with ``R`` the
    body's rotation; the rounding radius grows the box on every side."""
    c, s = body[w, i, COS], body[w, i, SIN]
    low_x = low_y = np.inf
    high_x = high_y = -np.inf
    for k in range(int(hull[w, i, VERTEX_COUNT])):
        vx, vy = hull[w, i, VERTEX0 + 2 * k], hull[w, i, VERTEX0 + 2 * k + 1]
        x, y = c * vx - s * vy, s * vx + c * vy
        low_x, high_x = min(low_x, x), max(high_x, x)
        low_y, high_y = min(low_y, y), max(high_y, y)
    r = hull[w, i, ROUNDING]
    return low_x - r, high_x + r, low_y - r, high_y + r


@kernel
def broadphase_boxes(body, body_i, shapes, hull, w, ctx, terms) -> None:
    """Each body's broadphase box (``LEFT`` ... ``TOP``, see ``workspace``)."""
    dt = ctx[context.DT]
    for i in range(shapes.shape[0]):
        kind = shapes[i, 0]
        enabled = body_i[w, i, ENABLED] == 1
        x, y = body[w, i, X], body[w, i, Y]
        hw, hh = body[w, i, HALF_W], body[w, i, HALF_H]
        if kind == BOX:
            c, s = abs(body[w, i, COS]), abs(body[w, i, SIN])
            extent_x, extent_y = c * hw + s * hh, s * hw + c * hh
            low_x, high_x, low_y, high_y = -extent_x, extent_x, -extent_y, extent_y
        elif kind == POLYGON:
            # The turned outline's own box, not the circle that holds it: a long segment
            # or plank would otherwise pair with everything within its length.
            low_x, high_x, low_y, high_y = outline_extent(body, hull, w, i)
        else:
            low_x, high_x, low_y, high_y = -hw, hw, -hw, hw
        # The broadphase box: the shape's box grown by how far the body can travel this
        # step and by half its speculative distance.
        grow = terms[i, REACH] * dt + terms[i, HALF_SPEC]
        in_broadphase = enabled and kind != PLANE and kind != FREE
        terms[i, LEFT] = x + low_x - grow if in_broadphase else np.inf
        terms[i, RIGHT] = x + high_x + grow
        terms[i, BOTTOM] = y + low_y - grow
        terms[i, TOP] = y + high_y + grow


@kernel
def list_moving(terms, moving) -> int:
    """The slots of the bodies that move this step (``MOVING``) into ``moving``, in slot
    order; returns how many. (Written without a branch: the slot is stored in every
    iteration and the count advanced by the flag.)"""
    count = 0
    for i in range(terms.shape[0]):
        moving[count] = i
        count += int(terms[i, MOVING] != 0.0)
    return count


@kernel
def integrate_velocities(body, w, terms, moving, count) -> None:
    """One substep of velocity: drag, gravity and forces, rolling resistance, for the
    ``count`` moving bodies (``list_moving``) that are dynamic."""
    for k in range(count):
        i = moving[k]
        if terms[i, MOVABLE] == 0.0:
            continue
        body[w, i, VX] = body[w, i, VX] * body[w, i, DAMP_LINEAR] + terms[i, ACCEL_X]
        body[w, i, VY] = body[w, i, VY] * body[w, i, DAMP_LINEAR] + terms[i, ACCEL_Y]
        body[w, i, OMEGA] = body[w, i, OMEGA] * body[w, i, DAMP_ANGULAR] + terms[i, ACCEL_W]
        roll = terms[i, ROLL_H]
        if roll > 0.0:
            vx, vy = body[w, i, VX], body[w, i, VY]
            keep = max(1.0 - roll / max(math.sqrt(vx * vx + vy * vy), 1e-300), 0.0)
            body[w, i, VX] = vx * keep
            body[w, i, VY] = vy * keep


@kernel
def integrate_positions(body, w, h, moving, count) -> None:
    """One substep of position, with the velocity just solved, for the ``count`` moving
    bodies (``list_moving``)."""
    for k in range(count):
        i = moving[k]
        body[w, i, X] += h * body[w, i, VX]
        body[w, i, Y] += h * body[w, i, VY]
        body[w, i, ANGLE] += h * body[w, i, OMEGA]


@kernel
def refresh_rotation(body, shapes, w, moving, count) -> None:
    """``COS``, ``SIN`` of the boxes and polygons that moved this step (``list_moving``),
    so they are current between steps for everyone who reads them."""
    for k in range(count):
        i = moving[k]
        if shapes[i, 0] == BOX or shapes[i, 0] == POLYGON:
            body[w, i, COS] = math.cos(body[w, i, ANGLE])
            body[w, i, SIN] = math.sin(body[w, i, ANGLE])


@kernel
def spring_geometry(body, spring, ends, w, k):
    """World anchor offsets ``(rax, ray, rbx, rby)``, unit direction and length of one
    spring."""
    a, b = ends[k, 0], ends[k, 1]
    ca, sa = math.cos(body[w, a, ANGLE]), math.sin(body[w, a, ANGLE])
    cb, sb = math.cos(body[w, b, ANGLE]), math.sin(body[w, b, ANGLE])
    rax = ca * spring[w, k, ANCHOR_AX] - sa * spring[w, k, ANCHOR_AY]
    ray = sa * spring[w, k, ANCHOR_AX] + ca * spring[w, k, ANCHOR_AY]
    rbx = cb * spring[w, k, ANCHOR_BX] - sb * spring[w, k, ANCHOR_BY]
    rby = sb * spring[w, k, ANCHOR_BX] + cb * spring[w, k, ANCHOR_BY]
    dx = (body[w, b, X] + rbx) - (body[w, a, X] + rax)
    dy = (body[w, b, Y] + rby) - (body[w, a, Y] + ray)
    length = math.sqrt(dx * dx + dy * dy)
    ux, uy = (dx / length, dy / length) if length > 0.0 else (0.0, 0.0)
    return rax, ray, rbx, rby, ux, uy, length


@kernel
def spring_speed(body, w, a, b, rax, ray, rbx, rby, ux, uy) -> float:
    """How fast a spring's anchors move apart along it (``u``): ``(vB + wB x rB) - (vA +
    wA x rA)``, projected on ``u``."""
    rvx = (body[w, b, VX] - body[w, b, OMEGA] * rby) - (body[w, a, VX] - body[w, a, OMEGA] * ray)
    rvy = (body[w, b, VY] + body[w, b, OMEGA] * rbx) - (body[w, a, VY] + body[w, a, OMEGA] * rax)
    return rvx * ux + rvy * uy


@kernel
def spring_acts(body_i, spring, ends, w, k) -> bool:
    """Spring slot ``k`` (a spring or a joint) is used, on, and joins two enabled bodies:
    it joins their islands. (Written with ``&``, without branches: a helper that
    branches costs numba reference counting per call.)"""
    a, b = ends[k, 0], ends[k, 1]
    return (
        (a >= 0)
        & (spring[w, k, SPRING_ON] == 1.0)
        & (body_i[w, a, ENABLED] == 1)
        & (body_i[w, b, ENABLED] == 1)
    )


@kernel
def apply_springs(body, body_i, spring, ends, w, terms, h) -> None:
    """Every spring's force over one substep, as a change of velocity."""
    for k in range(ends.shape[0]):
        if not spring_acts(body_i, spring, ends, w, k) or spring[w, k, LINK] != SPRING:
            continue  # a joint is a constraint (joints.py), not a force
        a, b = ends[k, 0], ends[k, 1]
        rax, ray, rbx, rby, ux, uy, length = spring_geometry(body, spring, ends, w, k)
        along = spring_speed(body, w, a, b, rax, ray, rbx, rby, ux, uy)
        stretch = length - spring[w, k, REST_LENGTH]
        tension = spring[w, k, STIFFNESS] * stretch + spring[w, k, DAMPING] * along
        fx, fy = tension * ux, tension * uy  # on A; B gets the opposite
        ima, iia = terms[a, STEP_INV_MASS], terms[a, STEP_INV_MOMENT]
        imb, iib = terms[b, STEP_INV_MASS], terms[b, STEP_INV_MOMENT]
        body[w, a, VX] += h * fx * ima
        body[w, a, VY] += h * fy * ima
        body[w, a, OMEGA] += h * (rax * fy - ray * fx) * iia
        body[w, b, VX] -= h * fx * imb
        body[w, b, VY] -= h * fy * imb
        body[w, b, OMEGA] -= h * (rbx * fy - rby * fx) * iib


@kernel
def spring_stability(body, body_i, spring, ends, w, terms, h):
    """``(slot, measure, too_fast)``: the first spring the step cannot take (slot -1 if
    none): the least stable one, by the measure ``h^2 k w + 2 h c w`` (unstable from 4;
    0.0 when none is); or, if every spring is stable, one whose pull accelerates its
    anchors apart faster than the envelope allows, ``(k |L - L0| + c |v_along|) w >
    envelope.ACCELERATION`` (as a force on a body may not), with ``too_fast`` True.
    Returned, not written to an array the caller allocates: a GPU kernel cannot
    allocate."""
    worst, measure, fast = -1, 0.0, -1
    for k in range(ends.shape[0]):
        if not spring_acts(body_i, spring, ends, w, k) or spring[w, k, LINK] != SPRING:
            continue  # a joint is a constraint (joints.py), not a force
        a, b = ends[k, 0], ends[k, 1]
        rax, ray, rbx, rby, ux, uy, length = spring_geometry(body, spring, ends, w, k)
        ca, cb = rax * uy - ray * ux, rbx * uy - rby * ux
        inverse = (
            terms[a, STEP_INV_MASS]
            + terms[b, STEP_INV_MASS]
            + terms[a, STEP_INV_MOMENT] * ca * ca
            + terms[b, STEP_INV_MOMENT] * cb * cb
        )
        stiffness, damping = spring[w, k, STIFFNESS], spring[w, k, DAMPING]
        value = h * h * stiffness * inverse + 2.0 * h * damping * inverse
        if value >= 4.0 and value > measure:
            worst, measure = k, value
        along = abs(spring_speed(body, w, a, b, rax, ray, rbx, rby, ux, uy))
        pull = (stiffness * abs(length - spring[w, k, REST_LENGTH]) + damping * along) * inverse
        if fast < 0 and pull > envelope.ACCELERATION:
            fast = k
    if worst < 0 and fast >= 0:
        return fast, measure, True
    return worst, measure, False
