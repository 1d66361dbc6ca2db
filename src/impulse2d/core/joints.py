"""Stage: the joints, solved in the soft step beside the contacts (Box2D v3's joint solver,
read, not copied: ``joint.c``, ``revolute_joint.c``, ``prismatic_joint.c``,
``weld_joint.c``, ``distance_joint.c``, ``mouse_joint.c``).

A joint is a row of the spring table (``state``: ``LINK`` says which kind; springs stay
explicit forces, ``integrate.apply_springs``), so it joins its bodies' island, wakes them
and is saved and restored as springs are. Every substep it is warm started with its
accumulated impulses, solved with the soft bias (``use_bias``), and after the positions
move, relaxed without it, before the contacts in each pass (``pipeline.substeps``). The
accumulated impulses are per substep and kept from step to step (the warm start).

Each constraint ``C(x) = 0`` with Jacobian ``J`` and effective mass ``m = 1 / (J M^-1
J^T)`` takes, in a pass, the impulse

    lambda = -m massScale (J v + biasRate C) - impulseScale lambda_acc

with the soft coefficients of a spring-damper integrated implicitly over the substep
(``context.soft_constraint``): a rigid joint uses the world's joint softness (twice the
contact stiffness, damping ratio 2, as Box2D), a joint spring its own hertz and damping
ratio, and the relax pass ``biasRate = 0, massScale = 1, impulseScale = 0`` (the
velocity error alone). A limit is a one-sided constraint: speculative while it is not
reached (its gap over the substep as the bias, rigidly), soft once it is passed; its
accumulated impulse is kept >= 0. A motor drives the relative speed to its target with
an accumulated impulse clamped to the motor's limit times the substep.

Anchors are recomputed from the bodies' current poses in every pass (``rA = R(angle_A)
local_A``), so the position error ``C`` is exact at each substep. Relative angles are
taken from the rotations, in (-pi, pi] (``relative_angle``), so angle limits lie within
half a turn either way, as Box2D's.
"""

from __future__ import annotations

import math

from . import context
from ._jit import inline, kernel
from .state import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    ANGLE,
    AXIS_X,
    AXIS_Y,
    BREAK_FORCE,
    COLLIDE,
    DAMPING_RATIO,
    DISTANCE,
    ENABLED,
    FORCE_X,
    FORCE_Y,
    HERTZ,
    IMPULSE_ANGLE,
    IMPULSE_LOWER,
    IMPULSE_MOTOR,
    IMPULSE_SPRING,
    IMPULSE_UPPER,
    IMPULSE_X,
    IMPULSE_Y,
    JOINT_LIST,
    JOINT_TORQUE,
    LIMITED,
    LINK,
    LOWER,
    MAX_MOTOR,
    MOTOR_SPEED,
    MOUSE,
    NEXT_AT_A,
    NEXT_AT_B,
    OMEGA,
    PRISMATIC,
    REFERENCE_ANGLE,
    REST_LENGTH,
    REVOLUTE,
    SPRING,
    SPRING_ON,
    UPPER,
    VX,
    VY,
    WELD,
    X,
    Y,
)
from .workspace import STEP_INV_MASS, STEP_INV_MOMENT


@kernel
def joint_acts(body_i, spring, ends, w, k) -> bool:
    """Row ``k`` is a joint (not a spring), on, between enabled bodies."""
    a, b = ends[k, 0], ends[k, 1]
    return (
        (a >= 0)
        & (spring[w, k, LINK] != SPRING)
        & (spring[w, k, SPRING_ON] == 1.0)
        & (body_i[w, a, ENABLED] == 1)
        & (body_i[w, b, ENABLED] == 1)
    )


@inline
def _soft(hertz, damping_ratio, h):
    """``context.soft_constraint`` in compiled code: (bias rate, mass scale, impulse scale).
    The frequency is capped at a quarter of the substep rate, as the contacts' is
    (``Settings.step_context``): a spring stiffer than that is not resolved within a
    substep (and its coefficients would overflow)."""
    omega = 2.0 * math.pi * min(hertz, 0.25 / h)
    a1 = 2.0 * damping_ratio + h * omega
    if a1 == 0.0:  # a frequency so low that h omega underflows: no spring at all
        return 0.0, 0.0, 1.0
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@inline
def relative_angle(body, spring, w, k, a, b) -> float:
    """B's angle less A's less the reference, in (-pi, pi]: from the relative rotation
    ``R_A^T R_B R_ref^T`` (as Box2D's ``b2RelativeAngle``), not from the difference of
    the angles, which no longer resolves a turn once an angle is large (a body spun
    for long, or set to 1e300)."""
    ta, tb, ref = body[w, a, ANGLE], body[w, b, ANGLE], spring[w, k, REFERENCE_ANGLE]
    ca, sa, cb, sb = math.cos(ta), math.sin(ta), math.cos(tb), math.sin(tb)
    c, s = ca * cb + sa * sb, ca * sb - sa * cb
    cr, sr = math.cos(ref), math.sin(ref)
    return math.atan2(s * cr - c * sr, c * cr + s * sr)


@inline
def _coefficients(ctx, hertz, damping_ratio, h, use_bias):
    """The soft coefficients of a pass: a soft joint's own (``hertz > 0``) in both passes,
    as Box2D's (it is a spring, not an error to remove); a rigid joint's the world's
    joint softness, or in the relax pass the rigid velocity solve."""
    if hertz > 0.0:
        return _soft(hertz, damping_ratio, h)
    if not use_bias:
        return 0.0, 1.0, 0.0
    return ctx[context.JOINT_RATE], ctx[context.JOINT_MASS], ctx[context.JOINT_IMPULSE]


@inline
def _frame(body, spring, w, k, a, b):
    """World offsets of the anchors from the centres, ``rA``, ``rB``, and ``d = (pB + rB) -
    (pA + rA)`` the anchors' separation. A mouse joint's first anchor is a world point."""
    cb, sb = math.cos(body[w, b, ANGLE]), math.sin(body[w, b, ANGLE])
    lbx, lby = spring[w, k, ANCHOR_BX], spring[w, k, ANCHOR_BY]
    rbx, rby = cb * lbx - sb * lby, sb * lbx + cb * lby
    if spring[w, k, LINK] == MOUSE:
        dx = body[w, b, X] + rbx - spring[w, k, ANCHOR_AX]
        dy = body[w, b, Y] + rby - spring[w, k, ANCHOR_AY]
        return 0.0, 0.0, rbx, rby, dx, dy
    ca, sa = math.cos(body[w, a, ANGLE]), math.sin(body[w, a, ANGLE])
    lax, lay = spring[w, k, ANCHOR_AX], spring[w, k, ANCHOR_AY]
    rax, ray = ca * lax - sa * lay, sa * lax + ca * lay
    dx = body[w, b, X] + rbx - body[w, a, X] - rax
    dy = body[w, b, Y] + rby - body[w, a, Y] - ray
    return rax, ray, rbx, rby, dx, dy


@inline
def _apply(body, w, a, b, ma, ia, mb, ib, px, py, la, lb) -> None:
    """Linear impulse ``P`` on B and ``-P`` on A, angular ``lb`` on B and ``-la`` on A."""
    body[w, a, VX] -= ma * px
    body[w, a, VY] -= ma * py
    body[w, a, OMEGA] -= ia * la
    body[w, b, VX] += mb * px
    body[w, b, VY] += mb * py
    body[w, b, OMEGA] += ib * lb


@inline
def _masses(terms, spring, w, k, a, b):
    """Step inverse masses and moments (0 for what does not move); a mouse joint's first
    body is its target, which nothing moves."""
    if spring[w, k, LINK] == MOUSE:
        return 0.0, 0.0, terms[b, STEP_INV_MASS], terms[b, STEP_INV_MOMENT]
    return (terms[a, STEP_INV_MASS], terms[a, STEP_INV_MOMENT], terms[b, STEP_INV_MASS],
            terms[b, STEP_INV_MOMENT])  # fmt: skip


@inline
def _relative_point_velocity(body, w, a, b, rax, ray, rbx, rby, mouse):
    """``vB + wB x rB - vA - wA x rA`` (a mouse joint's target is still)."""
    vx = body[w, b, VX] - body[w, b, OMEGA] * rby
    vy = body[w, b, VY] + body[w, b, OMEGA] * rbx
    if not mouse:
        vx -= body[w, a, VX] - body[w, a, OMEGA] * ray
        vy -= body[w, a, VY] + body[w, a, OMEGA] * rax
    return vx, vy


@inline
def _point(body, spring, w, k, a, b, masses, frame, soft, mouse, most) -> None:
    """The two-row point constraint ``pB + rB = pA + rA`` (revolute, weld, mouse): the 2x2
    effective mass ``K = (mA + mB) I + iA [rA]^2 + iB [rB]^2`` inverted in closed form.
    ``most``: a limit on the accumulated impulse's length (a mouse joint's force times
    the substep; inf: none)."""
    ma, ia, mb, ib = masses
    rax, ray, rbx, rby, dx, dy = frame
    rate, mass_scale, impulse_scale = soft
    k11 = ma + mb + ia * ray * ray + ib * rby * rby
    k12 = -ia * rax * ray - ib * rbx * rby
    k22 = ma + mb + ia * rax * rax + ib * rbx * rbx
    det = k11 * k22 - k12 * k12
    if det <= 0.0:
        return
    vx, vy = _relative_point_velocity(body, w, a, b, rax, ray, rbx, rby, mouse)
    bx, by = vx + rate * dx, vy + rate * dy
    old_x, old_y = spring[w, k, IMPULSE_X], spring[w, k, IMPULSE_Y]
    total_x = old_x - mass_scale * (k22 * bx - k12 * by) / det - impulse_scale * old_x
    total_y = old_y - mass_scale * (k11 * by - k12 * bx) / det - impulse_scale * old_y
    length = math.sqrt(total_x * total_x + total_y * total_y)
    if length > most:
        total_x, total_y = total_x * most / length, total_y * most / length
    ix, iy = total_x - old_x, total_y - old_y
    spring[w, k, IMPULSE_X], spring[w, k, IMPULSE_Y] = total_x, total_y
    _apply(body, w, a, b, ma, ia, mb, ib, ix, iy, rax * iy - ray * ix, rbx * iy - rby * ix)


@inline
def _one_sided(spring, w, k, column, gap, speed, mass, ctx, inv_h, use_bias) -> float:
    """A limit's impulse increment (>= 0 in total): ``gap`` >= 0 is to be kept, ``speed``
    its rate of change. Not reached (``gap > 0``): speculative, rigid, the gap closing
    over the substep at most; passed: the world's joint softness (none when relaxing)."""
    if gap > 0.0:
        bias, mass_scale, impulse_scale = gap * inv_h, 1.0, 0.0
    elif use_bias:
        bias = ctx[context.JOINT_RATE] * gap
        mass_scale, impulse_scale = ctx[context.JOINT_MASS], ctx[context.JOINT_IMPULSE]
    else:
        bias, mass_scale, impulse_scale = 0.0, 1.0, 0.0
    old = spring[w, k, column]
    increment = -mass * mass_scale * (speed + bias) - impulse_scale * old
    total = max(old + increment, 0.0)
    spring[w, k, column] = total
    return total - old


@inline
def _revolute(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias) -> None:
    """Spring, motor and limits on the relative angle, then the point constraint."""
    ma, ia, mb, ib = masses
    axial = 1.0 / (ia + ib) if ia + ib > 0.0 else 0.0
    angle = relative_angle(body, spring, w, k, a, b)
    if spring[w, k, HERTZ] > 0.0:
        rate, mass_scale, impulse_scale = _soft(spring[w, k, HERTZ], spring[w, k, DAMPING_RATIO], h)
        turn = body[w, b, OMEGA] - body[w, a, OMEGA]
        impulse = (
            -mass_scale * axial * (turn + rate * angle)
            - impulse_scale * spring[w, k, IMPULSE_SPRING]
        )
        spring[w, k, IMPULSE_SPRING] += impulse
        _apply(body, w, a, b, ma, ia, mb, ib, 0.0, 0.0, impulse, impulse)
    if spring[w, k, MAX_MOTOR] > 0.0:
        turn = body[w, b, OMEGA] - body[w, a, OMEGA]
        old, most = spring[w, k, IMPULSE_MOTOR], spring[w, k, MAX_MOTOR] * h
        total = min(max(old - axial * (turn - spring[w, k, MOTOR_SPEED]), -most), most)
        spring[w, k, IMPULSE_MOTOR] = total
        _apply(body, w, a, b, ma, ia, mb, ib, 0.0, 0.0, total - old, total - old)
    if spring[w, k, LIMITED] == 1.0:
        inv_h = 1.0 / h
        turn = body[w, b, OMEGA] - body[w, a, OMEGA]
        low = _one_sided(spring, w, k, IMPULSE_LOWER, angle - spring[w, k, LOWER], turn, axial,
                         ctx, inv_h, use_bias)  # fmt: skip
        _apply(body, w, a, b, ma, ia, mb, ib, 0.0, 0.0, low, low)
        turn = body[w, b, OMEGA] - body[w, a, OMEGA]
        high = _one_sided(spring, w, k, IMPULSE_UPPER, spring[w, k, UPPER] - angle, -turn, axial,
                          ctx, inv_h, use_bias)  # fmt: skip
        _apply(body, w, a, b, ma, ia, mb, ib, 0.0, 0.0, -high, -high)
    soft = _coefficients(ctx, 0.0, 0.0, h, use_bias)
    _point(body, spring, w, k, a, b, masses, frame, soft, False, math.inf)


@inline
def _weld(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias) -> None:
    """The relative angle held at its reference, then the point constraint, both soft by
    the joint's own hertz when it has one (a weld that bends), else rigid."""
    ma, ia, mb, ib = masses
    soft = _coefficients(ctx, spring[w, k, HERTZ], spring[w, k, DAMPING_RATIO], h, use_bias)
    rate, mass_scale, impulse_scale = soft
    if ia + ib > 0.0:
        angle = relative_angle(body, spring, w, k, a, b)
        turn = body[w, b, OMEGA] - body[w, a, OMEGA]
        impulse = -mass_scale * (turn + rate * angle) / (ia + ib)
        impulse -= impulse_scale * spring[w, k, IMPULSE_ANGLE]
        spring[w, k, IMPULSE_ANGLE] += impulse
        _apply(body, w, a, b, ma, ia, mb, ib, 0.0, 0.0, impulse, impulse)
    _point(body, spring, w, k, a, b, masses, frame, soft, False, math.inf)


@inline
def _along(body, w, a, b, frame, masses, ux, uy):
    """The anchors' relative speed along the unit ``u``, and the effective mass along it."""
    ma, ia, mb, ib = masses
    rax, ray, rbx, rby, _, _ = frame
    vx, vy = _relative_point_velocity(body, w, a, b, rax, ray, rbx, rby, False)
    cross_a, cross_b = rax * uy - ray * ux, rbx * uy - rby * ux
    inverse = ma + mb + ia * cross_a * cross_a + ib * cross_b * cross_b
    return vx * ux + vy * uy, 1.0 / inverse if inverse > 0.0 else 0.0


@inline
def _push_along(body, w, a, b, masses, frame, ux, uy, impulse) -> None:
    ma, ia, mb, ib = masses
    rax, ray, rbx, rby, _, _ = frame
    px, py = impulse * ux, impulse * uy
    _apply(body, w, a, b, ma, ia, mb, ib, px, py, rax * py - ray * px, rbx * py - rby * px)


@inline
def _distance(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias) -> None:
    """The anchors' distance: held at the rest length (a rod, ``LOWER == UPPER``), or free
    between ``LOWER`` and ``UPPER`` (a rope: 0 to its length) with an optional spring
    towards the rest length."""
    dx, dy = frame[4], frame[5]
    length = math.sqrt(dx * dx + dy * dy)
    if length < 1e-12:
        return
    ux, uy = dx / length, dy / length
    rest, lower, upper = spring[w, k, REST_LENGTH], spring[w, k, LOWER], spring[w, k, UPPER]
    if lower >= upper:  # rigid
        speed, mass = _along(body, w, a, b, frame, masses, ux, uy)
        rate, mass_scale, impulse_scale = _coefficients(ctx, 0.0, 0.0, h, use_bias)
        impulse = -mass_scale * mass * (speed + rate * (length - rest))
        impulse -= impulse_scale * spring[w, k, IMPULSE_X]
        spring[w, k, IMPULSE_X] += impulse
        _push_along(body, w, a, b, masses, frame, ux, uy, impulse)
        return
    if spring[w, k, HERTZ] > 0.0:
        speed, mass = _along(body, w, a, b, frame, masses, ux, uy)
        rate, mass_scale, impulse_scale = _soft(spring[w, k, HERTZ], spring[w, k, DAMPING_RATIO], h)
        impulse = -mass_scale * mass * (speed + rate * (length - rest))
        impulse -= impulse_scale * spring[w, k, IMPULSE_SPRING]
        spring[w, k, IMPULSE_SPRING] += impulse
        _push_along(body, w, a, b, masses, frame, ux, uy, impulse)
    inv_h = 1.0 / h
    speed, mass = _along(body, w, a, b, frame, masses, ux, uy)
    low = _one_sided(spring, w, k, IMPULSE_LOWER, length - lower, speed, mass, ctx, inv_h, use_bias)
    _push_along(body, w, a, b, masses, frame, ux, uy, low)
    speed, mass = _along(body, w, a, b, frame, masses, ux, uy)
    high = _one_sided(spring, w, k, IMPULSE_UPPER, upper - length, -speed, mass, ctx, inv_h,
                      use_bias)  # fmt: skip
    _push_along(body, w, a, b, masses, frame, ux, uy, -high)


@inline
def _slider_frame(body, spring, w, k, a, frame):
    """A prismatic joint's axis and its normal in the world (the axis turns with A), the
    translation along it, and the lever terms ``(d + rA) x axis``, ``rB x axis`` and the
    same for the normal."""
    ca, sa = math.cos(body[w, a, ANGLE]), math.sin(body[w, a, ANGLE])
    lx, ly = spring[w, k, AXIS_X], spring[w, k, AXIS_Y]
    ax, ay = ca * lx - sa * ly, sa * lx + ca * ly
    nx, ny = -ay, ax
    rax, ray, rbx, rby, dx, dy = frame
    ox, oy = dx + rax, dy + ray
    return (ax, ay, nx, ny, ax * dx + ay * dy, ox * ay - oy * ax, rbx * ay - rby * ax,
            ox * ny - oy * nx, rbx * ny - rby * nx)  # fmt: skip


@inline
def _slide(body, w, a, b, masses, ux, uy, lever_a, lever_b, impulse, turn) -> None:
    """An impulse along ``u`` with the levers of a slider, plus a torque ``turn``."""
    ma, ia, mb, ib = masses
    _apply(body, w, a, b, ma, ia, mb, ib, impulse * ux, impulse * uy,
           impulse * lever_a + turn, impulse * lever_b + turn)  # fmt: skip


@inline
def _slide_speed(body, w, a, b, ux, uy, lever_a, lever_b) -> float:
    return (ux * (body[w, b, VX] - body[w, a, VX]) + uy * (body[w, b, VY] - body[w, a, VY])
            + lever_b * body[w, b, OMEGA] - lever_a * body[w, a, OMEGA])  # fmt: skip


@inline
def _prismatic(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias) -> None:
    """Spring, motor and limits along the axis, then the normal and the relative angle
    held together (a 2x2 block)."""
    ma, ia, mb, ib = masses
    ax, ay, nx, ny, translation, a1, a2, s1, s2 = _slider_frame(body, spring, w, k, a, frame)
    inverse = ma + mb + ia * a1 * a1 + ib * a2 * a2
    axial = 1.0 / inverse if inverse > 0.0 else 0.0
    if spring[w, k, HERTZ] > 0.0:
        rate, mass_scale, impulse_scale = _soft(spring[w, k, HERTZ], spring[w, k, DAMPING_RATIO], h)
        speed = _slide_speed(body, w, a, b, ax, ay, a1, a2)
        impulse = -mass_scale * axial * (speed + rate * translation)
        impulse -= impulse_scale * spring[w, k, IMPULSE_SPRING]
        spring[w, k, IMPULSE_SPRING] += impulse
        _slide(body, w, a, b, masses, ax, ay, a1, a2, impulse, 0.0)
    if spring[w, k, MAX_MOTOR] > 0.0:
        speed = _slide_speed(body, w, a, b, ax, ay, a1, a2)
        old, most = spring[w, k, IMPULSE_MOTOR], spring[w, k, MAX_MOTOR] * h
        total = min(max(old - axial * (speed - spring[w, k, MOTOR_SPEED]), -most), most)
        spring[w, k, IMPULSE_MOTOR] = total
        _slide(body, w, a, b, masses, ax, ay, a1, a2, total - old, 0.0)
    if spring[w, k, LIMITED] == 1.0:
        inv_h = 1.0 / h
        speed = _slide_speed(body, w, a, b, ax, ay, a1, a2)
        low = _one_sided(spring, w, k, IMPULSE_LOWER, translation - spring[w, k, LOWER], speed,
                         axial, ctx, inv_h, use_bias)  # fmt: skip
        _slide(body, w, a, b, masses, ax, ay, a1, a2, low, 0.0)
        speed = _slide_speed(body, w, a, b, ax, ay, a1, a2)
        high = _one_sided(spring, w, k, IMPULSE_UPPER, spring[w, k, UPPER] - translation, -speed,
                          axial, ctx, inv_h, use_bias)  # fmt: skip
        _slide(body, w, a, b, masses, ax, ay, a1, a2, -high, 0.0)
    _slider_block(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias, nx, ny, s1, s2)


@inline
def _slider_block(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias, nx, ny, s1, s2):
    """``n . d = 0`` and ``angle_B - angle_A = reference`` solved together: ``K = [[mA + mB
    + iA s1^2 + iB s2^2, iA s1 + iB s2], [iA s1 + iB s2, iA + iB]]``."""
    ma, ia, mb, ib = masses
    dx, dy = frame[4], frame[5]
    k11 = ma + mb + ia * s1 * s1 + ib * s2 * s2
    k12 = ia * s1 + ib * s2
    k22 = ia + ib if ia + ib > 0.0 else 1.0
    det = k11 * k22 - k12 * k12
    if det <= 0.0:
        return
    rate, mass_scale, impulse_scale = _coefficients(ctx, 0.0, 0.0, h, use_bias)
    c1 = rate * (nx * dx + ny * dy)
    c2 = rate * relative_angle(body, spring, w, k, a, b)
    b1 = _slide_speed(body, w, a, b, nx, ny, s1, s2) + c1
    b2 = body[w, b, OMEGA] - body[w, a, OMEGA] + c2
    i1 = -mass_scale * (k22 * b1 - k12 * b2) / det - impulse_scale * spring[w, k, IMPULSE_X]
    i2 = -mass_scale * (k11 * b2 - k12 * b1) / det - impulse_scale * spring[w, k, IMPULSE_Y]
    spring[w, k, IMPULSE_X] += i1
    spring[w, k, IMPULSE_Y] += i2
    _slide(body, w, a, b, masses, nx, ny, s1, s2, i1, i2)


@inline
def _mouse(body, spring, w, k, b, masses, frame, h) -> None:
    """Body B's anchor pulled to the target (the first anchor, a world point) by a soft
    point constraint of the joint's own hertz and damping ratio, its force at most
    ``MAX_MOTOR`` (Box2D's mouse joint), in both passes alike."""
    soft = _soft(spring[w, k, HERTZ], spring[w, k, DAMPING_RATIO], h)
    most = spring[w, k, MAX_MOTOR] * h
    _point(body, spring, w, k, b, b, masses, frame, soft, True, most)


@kernel
def solve_joints(body, body_i, spring, ends, w, ctx, terms, use_bias) -> None:
    """One pass over the joints (the soft pass with ``use_bias``, else the relax pass)."""
    h = ctx[context.H]
    for k in range(ends.shape[0]):
        if not joint_acts(body_i, spring, ends, w, k):
            continue
        a, b = ends[k, 0], ends[k, 1]
        masses = _masses(terms, spring, w, k, a, b)
        if masses[0] + masses[1] + masses[2] + masses[3] == 0.0:
            continue  # nothing it joins moves
        frame = _frame(body, spring, w, k, a, b)
        kind = spring[w, k, LINK]
        if kind == REVOLUTE:
            _revolute(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias)
        elif kind == PRISMATIC:
            _prismatic(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias)
        elif kind == WELD:
            _weld(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias)
        elif kind == DISTANCE:
            _distance(body, spring, w, k, a, b, masses, frame, ctx, h, use_bias)
        elif kind == MOUSE:
            _mouse(body, spring, w, k, b, masses, frame, h)


@inline
def _axial_total(spring, w, k) -> float:
    """The accumulated impulse along a joint's own axis (angle, distance or slide)."""
    return (spring[w, k, IMPULSE_SPRING] + spring[w, k, IMPULSE_MOTOR]
            + spring[w, k, IMPULSE_LOWER] - spring[w, k, IMPULSE_UPPER])  # fmt: skip


@inline
def _reaction(body, spring, w, k, a, b):
    """The impulse a joint applies to B over a substep: linear ``(px, py)`` and the
    angular impulse about B's centre beyond ``rB x P`` (A gets the opposite)."""
    kind = spring[w, k, LINK]
    frame = _frame(body, spring, w, k, a, b)
    axial = _axial_total(spring, w, k)
    if kind == DISTANCE:
        dx, dy = frame[4], frame[5]
        length = max(math.sqrt(dx * dx + dy * dy), 1e-12)
        total = spring[w, k, IMPULSE_X] + axial
        return total * dx / length, total * dy / length, 0.0, frame
    if kind == PRISMATIC:
        ax, ay, nx, ny = _slider_frame(body, spring, w, k, a, frame)[:4]
        normal = spring[w, k, IMPULSE_X]
        return axial * ax + normal * nx, axial * ay + normal * ny, spring[w, k, IMPULSE_Y], frame
    turn = spring[w, k, IMPULSE_ANGLE] if kind == WELD else axial if kind == REVOLUTE else 0.0
    return spring[w, k, IMPULSE_X], spring[w, k, IMPULSE_Y], turn, frame


@kernel
def warm_start_joints(body, body_i, spring, ends, w, terms) -> None:
    """Every joint's accumulated impulses applied again at the start of a substep."""
    for k in range(ends.shape[0]):
        if not joint_acts(body_i, spring, ends, w, k):
            continue
        a, b = ends[k, 0], ends[k, 1]
        masses = _masses(terms, spring, w, k, a, b)
        ma, ia, mb, ib = masses
        px, py, turn, frame = _reaction(body, spring, w, k, a, b)
        rax, ray, rbx, rby, _, _ = frame
        if spring[w, k, LINK] == PRISMATIC:  # its levers are (d + rA) x u, not rA x u
            _, _, _, _, _, a1, a2, s1, s2 = _slider_frame(body, spring, w, k, a, frame)
            axial, normal = _axial_total(spring, w, k), spring[w, k, IMPULSE_X]
            la, lb = axial * a1 + normal * s1 + turn, axial * a2 + normal * s2 + turn
        else:
            la, lb = rax * py - ray * px + turn, rbx * py - rby * px + turn
        _apply(body, w, a, b, ma, ia, mb, ib, px, py, la, lb)


@kernel
def finish_joints(body, body_i, spring, ends, w, ctx) -> None:
    """After the substeps: each joint's force and torque on B over the step (N, N m: the
    accumulated impulse of a substep over the substep), and the joints whose force went
    past their ``BREAK_FORCE`` switched off, their impulses cleared."""
    inv_h = ctx[context.INV_H]
    for k in range(ends.shape[0]):
        if not joint_acts(body_i, spring, ends, w, k):
            continue
        a, b = ends[k, 0], ends[k, 1]
        px, py, turn, _ = _reaction(body, spring, w, k, a, b)
        fx, fy = px * inv_h, py * inv_h
        spring[w, k, FORCE_X], spring[w, k, FORCE_Y] = fx, fy
        spring[w, k, JOINT_TORQUE] = turn * inv_h
        most = spring[w, k, BREAK_FORCE]  # 0: it never breaks
        if most > 0.0 and fx * fx + fy * fy > most * most:
            spring[w, k, SPRING_ON] = 0.0
            for column in range(IMPULSE_X, IMPULSE_SPRING + 1):
                spring[w, k, column] = 0.0


@kernel
def joined(body_i, spring, ends, w, a, b) -> bool:
    """Whether a joint that keeps its bodies from colliding joins ``a`` and ``b``: a walk
    along ``a``'s list of joints (``JOINT_LIST``, ``NEXT_AT_A``, ``NEXT_AT_B``), as long
    as ``a`` has joints (Box2D walks a body's joint edges so)."""
    k = body_i[w, a, JOINT_LIST]
    for _ in range(ends.shape[0]):  # at most every row: a broken list cannot loop
        if k < 0:
            return False
        first = ends[k, 0] == a
        other = ends[k, 1] if first else ends[k, 0]
        if other == b and spring[w, k, COLLIDE] == 0.0 and spring[w, k, SPRING_ON] == 1.0:
            return True
        k = int(spring[w, k, NEXT_AT_A] if first else spring[w, k, NEXT_AT_B])
    return False


@kernel
def drop_joined_pairs(body_i, spring, ends, w, pairs, n_pairs) -> int:
    """The broadphase's candidate pairs less those a joint keeps apart, in their order;
    returns how many are left."""
    kept = 0
    for p in range(n_pairs):
        a, b = pairs[p, 0], pairs[p, 1]
        if body_i[w, a, JOINT_LIST] >= 0 and body_i[w, b, JOINT_LIST] >= 0:
            if joined(body_i, spring, ends, w, a, b):
                continue
        pairs[kept, 0], pairs[kept, 1] = a, b
        kept += 1
    return kept
