"""The coloured manifolds solved side by side: gather, a vectorised lane loop, scatter.

One pass (``solve_coloured``, the biased solve or the relax of a substep) takes the
colours of ``colouring.py`` in order. For each colour the two bodies of every manifold
are gathered into its lane (``lanes[field, m]``: velocities and the position and
rotation deltas since the step start), every lane is solved, and the moving bodies'
velocities are scattered back; no two lanes of a colour share a moving body, so the
lanes are independent and the loop over them is what LLVM's loop vectoriser packs into
vector instructions (8 float64 lanes with AVX-512, 4 with AVX2).

A lane solves what ``solver.solve_pairs`` does for a two-point pair: both normal
impulses at once (the 2x2 complementarity problem of the soft rows,
``solver.solve_pair_normals``), or one after the other where the block has no solution,
then each point's friction within its cone. To vectorise, it is written without
branches: every case is computed and the first that holds is selected (a select is a
blend; a branch would split the block the vectoriser packs), on values only (numbers in,
numbers out: a helper that takes an array leaves numba's reference counting in the loop,
which stops the vectoriser), with an unsigned lane index (no negative-index
wrap-around). Lane arithmetic is elementwise IEEE arithmetic, so the vectorised loop is
bitwise the scalar loop, with or without the compiler (``NUMBA_DISABLE_JIT=1``).

LLVM's vectoriser also needs run-time checks that the stored rows do not overlap the
loaded ones (their distance is a run-time shape), more than its default limit of 8: the
options below raise it. They are process-wide and only let more loops vectorise; they
change no result (no fast-math).

The soft row of a point at separation ``s`` (``solver.soft_row``): a gap (``s > 0``) is
hard, ``v_n + s / h >= 0`` (arrive, no more); an overlap in the biased pass asks
``m_s v_n + max(m_s rate s, -push) + i_s K lambda = 0``, in the relax pass ``v_n = 0``.
The separation is ``s0 + n . (dB - dA) + (rB x n) qB - (rA x n) qA`` (rotation
linearised, ``solver.current_separation``).
"""

from __future__ import annotations

import math

import llvmlite.binding
import numpy as np

from ._jit import JIT_DISABLED, inline, kernel
from .colouring import colour_arrays, follow_base, point_base
from .state import ANGLE, OMEGA, VX, VY, X, Y
from .workspace import (
    ANGLE0,
    CBIAS_RATE,
    CFRICTION,
    CIIA,
    CIIB,
    CIMA,
    CIMB,
    CIMPULSE_SCALE,
    CMASS_SCALE,
    CNX,
    CNY,
    COLOURS,
    FOLLOW0,
    LDQA,
    LDQB,
    LDXA,
    LDXB,
    LDYA,
    LDYB,
    LVAX,
    LVAY,
    LVBX,
    LVBY,
    LWA,
    LWB,
    MOVABLE,
    PBOUNCES,
    PDRIFT,
    PER_FOLLOW,
    PER_POINT,
    PGROSS_J,
    PKEEP,
    PMAX_J,
    PNORMAL_J,
    PNORMAL_MASS,
    POINT0,
    PRAX,
    PRAY,
    PRBX,
    PRBY,
    PRNA,
    PRNB,
    PRTA,
    PRTB,
    PSEP0,
    PSTEP_J,
    PTANGENT_J,
    PTANGENT_MASS,
    SDQ,
    SDX,
    SDY,
    SMOVABLE,
    SVX,
    SVY,
    SW,
    X0,
    Y0,
)

if not JIT_DISABLED:
    for _option in ("-runtime-memory-check-threshold=512",
                    "-vectorize-memory-check-threshold=4096",
                    "-memory-check-merge-threshold=4096"):  # fmt: skip
        llvmlite.binding.set_option("", _option)


# A colour is gathered, solved and scattered this many lanes at a time, so that its lanes
# are still in the L1 cache when the lane loop reads them and when the scatter does
# (12 rows of 256 float64: 24 KiB), however many manifolds the colour has. The lanes of
# a colour are independent (they share no body that moves), so chunks change no result.
LANE_CHUNK = 256


@inline
def _row(c, p, v):
    """Point ``p``'s separation now and its normal relative velocity ``J . V``."""
    base = POINT0 + p * PER_POINT
    nx, ny, rna, rnb = c[CNX], c[CNY], c[base + PRNA], c[base + PRNB]
    s = c[base + PSEP0] + nx * (v[9] - v[3]) + ny * (v[10] - v[4]) + rnb * v[11] - rna * v[5]
    return s, nx * (v[6] - v[0]) + ny * (v[7] - v[1]) + rnb * v[8] - rna * v[2]


@inline
def _soft(c, s, consts):
    """``(mass_scale, bias, impulse_scale)`` of a point at separation ``s``, by selects;
    ``consts`` is ``(1/h, push speed, biased pass?)``."""
    inv_h, push, biased = consts
    gap = s > 0.0
    mass_scale = c[CMASS_SCALE] if biased else 1.0
    soft_bias = max(mass_scale * c[CBIAS_RATE] * s, -push) if biased else 0.0
    return (
        1.0 if gap else mass_scale,
        s * inv_h if gap else soft_bias,
        0.0 if gap else (c[CIMPULSE_SCALE] if biased else 0.0),
    )


@inline
def _push_normal(c, p, v, d):
    """``v`` after an impulse ``d`` along the normal at point ``p`` (on B; minus on A)."""
    base = POINT0 + p * PER_POINT
    nx, ny, rna, rnb = c[CNX], c[CNY], c[base + PRNA], c[base + PRNB]
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    return (v[0] - ima * d * nx, v[1] - ima * d * ny, v[2] - iia * rna * d, v[3], v[4], v[5],
            v[6] + imb * d * nx, v[7] + imb * d * ny, v[8] + iib * rnb * d, v[9], v[10],
            v[11])  # fmt: skip


@inline
def _point_normal(c, p, v, consts):
    """Point ``p`` alone (``solver.solve_normal``): ``(v, increment)``."""
    s, vn = _row(c, p, v)
    mass_scale, bias, impulse_scale = _soft(c, s, consts)
    base = POINT0 + p * PER_POINT
    acc = c[base + PNORMAL_J]
    impulse = -c[base + PNORMAL_MASS] * (mass_scale * vn + bias) - impulse_scale * acc
    change = max(acc + impulse, 0.0) - acc
    return _push_normal(c, p, v, change), change


@inline
def _block(c, v, consts):
    """Both normal increments at once, every case of the complementarity problem computed
    and the first that holds selected (``solver.solve_pair_normals``, whose order of
    cases this keeps): ``(found, d0, d1)``. Divisions that a case cannot use (a zero
    determinant or pivot) divide by 1 and are not selected."""
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    b0, b1 = POINT0, POINT0 + PER_POINT
    rna0, rnb0, rna1, rnb1 = c[b0 + PRNA], c[b0 + PRNB], c[b1 + PRNA], c[b1 + PRNB]
    k11 = ima + imb + iia * rna0 * rna0 + iib * rnb0 * rnb0
    k22 = ima + imb + iia * rna1 * rna1 + iib * rnb1 * rnb1
    k12 = ima + imb + iia * rna0 * rna1 + iib * rnb0 * rnb1
    solvable = k11 * k22 - k12 * k12 > 1e-3 * k11 * k22
    (s0, vn0), (s1, vn1) = _row(c, 0, v), _row(c, 1, v)
    ms0, bias0, is0 = _soft(c, s0, consts)
    ms1, bias1, is1 = _soft(c, s1, consts)
    acc0, acc1 = c[b0 + PNORMAL_J], c[b1 + PNORMAL_J]
    a11, a12, r1 = ms0 * k11 + is0 * k11, ms0 * k12, -(ms0 * vn0 + bias0 + is0 * k11 * acc0)
    a21, a22, r2 = ms1 * k12, ms1 * k22 + is1 * k22, -(ms1 * vn1 + bias1 + is1 * k22 * acc1)
    det = a11 * a22 - a12 * a21
    safe_det = det if det != 0.0 else 1.0
    both0, both1 = (r1 * a22 - a12 * r2) / safe_det, (a11 * r2 - a21 * r1) / safe_det
    ok_both = det != 0.0 and acc0 + both0 >= 0.0 and acc1 + both1 >= 0.0
    first0 = (r1 + a12 * acc1) / (a11 if a11 != 0.0 else 1.0)  # only the first pushes
    ok_first = acc0 + first0 >= 0.0 and a21 * first0 - a22 * acc1 - r2 >= 0.0
    second1 = (r2 + a21 * acc0) / (a22 if a22 != 0.0 else 1.0)  # only the second
    ok_second = acc1 + second1 >= 0.0 and -a11 * acc0 + a12 * second1 - r1 >= 0.0
    ok_neither = -a11 * acc0 - a12 * acc1 - r1 >= 0.0 and -a21 * acc0 - a22 * acc1 - r2 >= 0.0
    d0 = both0 if ok_both else (first0 if ok_first else -acc0)
    d1 = both1 if ok_both else (-acc1 if ok_first else (second1 if ok_second else -acc1))
    return solvable and (ok_both or ok_first or ok_second or ok_neither), d0, d1


@inline
def _friction(c, p, v, normal):
    """Point ``p``'s friction within ``friction * normal`` (``solver.solve_friction``):
    ``(v, new impulse, increment)``; nothing without friction."""
    base = POINT0 + p * PER_POINT
    nx, ny = c[CNX], c[CNY]
    rta, rtb = c[base + PRTA], c[base + PRTB]
    vt = ny * (v[6] - v[0]) - nx * (v[7] - v[1]) + rtb * v[8] - rta * v[2]  # t = (n_y, -n_x)
    limit = c[CFRICTION] * normal
    old = c[base + PTANGENT_J]
    clamped = min(max(old - c[base + PTANGENT_MASS] * vt, -limit), limit)
    new = clamped if c[CFRICTION] > 0.0 else old
    d = new - old
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    v = (v[0] - ima * d * ny, v[1] + ima * d * nx, v[2] - iia * rta * d, v[3], v[4], v[5],
         v[6] + imb * d * ny, v[7] - imb * d * nx, v[8] + iib * rtb * d, v[9], v[10],
         v[11])  # fmt: skip
    return v, new, d


@inline
def solve_manifold(c, v, consts):
    """One manifold from its constraint values ``c`` (CON_F) and lane values ``v``
    (LANE_F): the block solve or, where it has no solution, one point after the other,
    then both frictions. Returns ``(v, (normal, tangent, d_normal, d_tangent) of point
    0, the same of point 1)``."""
    found, d0, d1 = _block(c, v, consts)
    v_seq, e0 = _point_normal(c, 0, v, consts)
    v_seq, e1 = _point_normal(c, 1, v_seq, consts)
    v_block = _push_normal(c, 1, _push_normal(c, 0, v, d0), d1)
    d0, d1 = (d0, d1) if found else (e0, e1)
    v = (v_block[0] if found else v_seq[0], v_block[1] if found else v_seq[1],
         v_block[2] if found else v_seq[2], v[3], v[4], v[5],
         v_block[6] if found else v_seq[6], v_block[7] if found else v_seq[7],
         v_block[8] if found else v_seq[8], v[9], v[10], v[11])  # fmt: skip
    n0, n1 = c[POINT0 + PNORMAL_J] + d0, c[POINT0 + PER_POINT + PNORMAL_J] + d1
    v, t0, dt0 = _friction(c, 0, v, n0)
    v, t1, dt1 = _friction(c, 1, v, n1)
    return v, (n0, t0, d0, dt0), (n1, t1, d1, dt1)


@inline
def _accumulate(step, largest, gross, d_normal, d_tangent):
    """``solver.push``'s bookkeeping of a point: the impulse over the step, the largest
    increment, the sizes of the pushes."""
    return step + d_normal, max(largest, d_normal), gross + abs(d_normal) + abs(d_tangent)


@kernel
def solve_lanes(con, lanes, start, end, consts) -> None:
    """Lanes ``start:end`` of one colour, in the loop form the vectoriser takes (module
    docstring): every load and store in the loop itself."""
    first, second = POINT0, POINT0 + PER_POINT
    for m in range(np.uint64(start), np.uint64(end)):
        v = (lanes[0, m], lanes[1, m], lanes[2, m], lanes[3, m], lanes[4, m], lanes[5, m],
             lanes[6, m], lanes[7, m], lanes[8, m], lanes[9, m], lanes[10, m],
             lanes[11, m])  # fmt: skip
        c = (con[0, m], con[1, m], con[2, m], con[3, m], con[4, m], con[5, m], con[6, m],
             con[7, m], con[8, m], con[9, m], con[10, m], con[11, m], con[12, m],
             con[13, m], con[14, m], con[15, m], con[16, m], con[17, m], con[18, m],
             con[19, m], con[20, m], con[21, m], con[22, m], con[23, m], con[24, m],
             con[25, m], con[26, m], con[27, m], con[28, m], con[29, m], con[30, m],
             con[31, m], con[32, m], con[33, m])  # fmt: skip
        v, j0, j1 = solve_manifold(c, v, consts)
        lanes[LVAX, m], lanes[LVAY, m], lanes[LWA, m] = v[0], v[1], v[2]
        lanes[LVBX, m], lanes[LVBY, m], lanes[LWB, m] = v[6], v[7], v[8]
        con[first + PNORMAL_J, m], con[first + PTANGENT_J, m] = j0[0], j0[1]
        (con[first + PSTEP_J, m], con[first + PMAX_J, m],
         con[first + PGROSS_J, m]) = _accumulate(c[first + PSTEP_J], c[first + PMAX_J],
                                                 c[first + PGROSS_J], j0[2], j0[3])  # fmt: skip
        con[second + PNORMAL_J, m], con[second + PTANGENT_J, m] = j1[0], j1[1]
        (con[second + PSTEP_J, m], con[second + PMAX_J, m],
         con[second + PGROSS_J, m]) = _accumulate(c[second + PSTEP_J], c[second + PMAX_J],
                                                  c[second + PGROSS_J], j1[2], j1[3])  # fmt: skip


@inline
def _load_state(body, w, terms, states, i) -> None:
    states[i, SVX], states[i, SVY] = body[w, i, VX], body[w, i, VY]
    states[i, SW] = body[w, i, OMEGA]
    states[i, SDX] = body[w, i, X] - terms[i, X0]
    states[i, SDY] = body[w, i, Y] - terms[i, Y0]
    states[i, SDQ] = body[w, i, ANGLE] - terms[i, ANGLE0]
    states[i, SMOVABLE] = terms[i, MOVABLE]


@kernel
def load_states(body, w, terms, states) -> None:
    """Every body's velocity, motion since the step start and whether it moves into its
    state row (``workspace.STATE_F``), once a step: a body that does not move keeps that
    row over the step (``load_moving``)."""
    for i in range(terms.shape[0]):
        _load_state(body, w, terms, states, i)


@kernel
def load_moving(body, w, terms, states, moving, count) -> None:
    """``load_states`` for the ``count`` moving bodies only (``integrate.list_moving``),
    before each coloured pass: nothing changes the others' rows within a step."""
    for k in range(count):
        _load_state(body, w, terms, states, moving[k])


@kernel
def store_states(body, w, states, moving, count) -> None:
    """The velocities of the ``count`` moving bodies that contacts move back from their
    state rows (the passes wrote no other)."""
    for k in range(count):
        i = moving[k]
        if states[i, SMOVABLE] != 0.0:
            body[w, i, VX], body[w, i, VY] = states[i, SVX], states[i, SVY]
            body[w, i, OMEGA] = states[i, SW]


@kernel
def gather(states, body_a, body_b, lanes, start, end) -> None:
    """The two bodies of manifolds ``start:end`` into their lanes."""
    for m in range(start, end):
        a, b = body_a[m], body_b[m]
        lanes[LVAX, m], lanes[LVAY, m] = states[a, SVX], states[a, SVY]
        lanes[LWA, m], lanes[LDXA, m] = states[a, SW], states[a, SDX]
        lanes[LDYA, m], lanes[LDQA, m] = states[a, SDY], states[a, SDQ]
        lanes[LVBX, m], lanes[LVBY, m] = states[b, SVX], states[b, SVY]
        lanes[LWB, m], lanes[LDXB, m] = states[b, SW], states[b, SDX]
        lanes[LDYB, m], lanes[LDQB, m] = states[b, SDY], states[b, SDQ]


@kernel
def scatter(states, body_a, body_b, lanes, start, end) -> None:
    """The lanes' velocities back to the bodies that move (a colour holds each once; a
    body that cannot move is never written: its lanes did not change it)."""
    for m in range(start, end):
        a, b = body_a[m], body_b[m]
        if states[a, SMOVABLE] != 0.0:
            states[a, SVX], states[a, SVY] = lanes[LVAX, m], lanes[LVAY, m]
            states[a, SW] = lanes[LWA, m]
        if states[b, SMOVABLE] != 0.0:
            states[b, SVX], states[b, SVY] = lanes[LVBX, m], lanes[LVBY, m]
            states[b, SW] = lanes[LWB, m]


@kernel
def solve_coloured(states, ctx_values, colour_floats, colour_ints) -> None:
    """One pass over the coloured manifolds, colour after colour, on the body ``states``
    (``load_states``). ``ctx_values`` is ``(1/h, push speed, biased pass?)``;
    ``colour_floats``, ``colour_ints`` the scratch ``colouring.colour_arrays`` cuts."""
    c = colour_arrays(colour_floats, colour_ints)
    con, lanes, body_a, body_b, starts = c.con, c.lanes, c.body_a, c.body_b, c.starts
    for colour in range(COLOURS):
        for start in range(starts[colour], starts[colour + 1], LANE_CHUNK):
            end = min(start + LANE_CHUNK, starts[colour + 1])
            gather(states, body_a, body_b, lanes, start, end)
            solve_lanes(con, lanes, start, end, ctx_values)
            scatter(states, body_a, body_b, lanes, start, end)


@kernel
def warm_start_coloured(states, colour_floats, colour_ints, count) -> None:
    """``solver.warm_start`` for the coloured manifolds: each point's accumulated
    impulses applied again, from ``con``, to the body ``states`` (one manifold after
    another: a sum of pushes, in the order of the colours)."""
    c = colour_arrays(colour_floats, colour_ints)
    con, body_a, body_b = c.con, c.body_a, c.body_b
    for m in range(count):
        a, b = body_a[m], body_b[m]
        nx, ny = con[CNX, m], con[CNY, m]
        ima, imb, iia, iib = con[CIMA, m], con[CIMB, m], con[CIIA, m], con[CIIB, m]
        for p in range(2):
            base = point_base(p)
            normal, tangent = con[base + PNORMAL_J, m], con[base + PTANGENT_J, m]
            if normal != 0.0 or tangent != 0.0:
                con[base + PSTEP_J, m] += normal
                con[base + PGROSS_J, m] += abs(normal) + abs(tangent)
                px, py = normal * nx + tangent * ny, normal * ny - tangent * nx
                angular_a = con[base + PRNA, m] * normal + con[base + PRTA, m] * tangent
                angular_b = con[base + PRNB, m] * normal + con[base + PRTB, m] * tangent
                states[a, SVX] -= ima * px
                states[a, SVY] -= ima * py
                states[a, SW] -= iia * angular_a
                states[b, SVX] += imb * px
                states[b, SVY] += imb * py
                states[b, SW] += iib * angular_b


@inline
def _jacobian(nx, ny, ima, imb, iia, iib, rax, ray, rbx, rby):
    """``contacts.set_jacobian``'s arithmetic on values: the cross terms and masses of a
    point with the anchors ``(rax, ray)`` on A and ``(rbx, rby)`` on B, ``(rA x n, rB x n,
    rA x t, rB x t, normal mass, tangent mass)`` (so a coloured point's Jacobian is its
    point row's)."""
    tx, ty = ny, -nx
    rna, rnb = rax * ny - ray * nx, rbx * ny - rby * nx
    rta, rtb = rax * ty - ray * tx, rbx * ty - rby * tx
    k_normal = ima + imb + iia * rna * rna + iib * rnb * rnb
    k_tangent = ima + imb + iia * rta * rta + iib * rtb * rtb
    # Divided by 1 where the mass is not taken (a division under a branch does not
    # vectorise; the result is the same).
    normal_mass = 1.0 / (k_normal if k_normal > 0.0 else 1.0)
    tangent_mass = 1.0 / (k_tangent if k_tangent > 0.0 else 1.0)
    return (rna, rnb, rta, rtb, normal_mass if k_normal > 0.0 else 0.0,
            tangent_mass if k_tangent > 0.0 else 0.0)  # fmt: skip


@inline
def _followed(nx, ny, ima, imb, iia, iib, rax, ray, rbx, rby, xa, ya, xb, yb, on_a):
    """A point's Jacobian (``_jacobian``) with one anchor moved to the other: B's to A's
    if ``on_a`` (A's is the material point), else A's to B's; ``x``, ``y`` the bodies'
    positions now, ``r`` the anchors as the narrowphase made them."""
    mx = (xb + rbx) - (xa + rax)
    my = (yb + rby) - (ya + ray)
    return _jacobian(nx, ny, ima, imb, iia, iib, rax if on_a else rax + mx,
                     ray if on_a else ray + my, rbx - mx if on_a else rbx,
                     rby - my if on_a else rby)  # fmt: skip


@kernel
def follow_coloured(body, w, colour_floats, colour_ints, count) -> None:
    """``contacts.follow_bodies`` for the coloured manifolds (two boxes: never two
    discs): after the positions moved, the anchor that is not a material point of its
    body goes to the one that is, so both push at one world point; a point that may
    bounce keeps its Jacobian and records how far its anchors drifted apart
    (``_record_drift``). A point against an immovable body keeps its Jacobian too: it
    takes any torque, there is nothing to keep.

    Written as the lane loop is (``solve_lanes``), so that it vectorises: the bodies'
    positions gathered into the lanes first (their velocity rows, free between passes),
    then every point's new Jacobian computed and stored where it is taken, its old one
    stored back where it is kept (a select, not a branch)."""
    c = colour_arrays(colour_floats, colour_ints)
    con, lanes, body_a, body_b = c.con, c.lanes, c.body_a, c.body_b
    for m in range(count):
        a, b = body_a[m], body_b[m]
        lanes[LVAX, m], lanes[LVAY, m] = body[w, a, X], body[w, a, Y]
        lanes[LVBX, m], lanes[LVBY, m] = body[w, b, X], body[w, b, Y]
    for m in range(np.uint64(0), np.uint64(count)):
        xa, ya, xb, yb = lanes[LVAX, m], lanes[LVAY, m], lanes[LVBX, m], lanes[LVBY, m]
        nx, ny = con[CNX, m], con[CNY, m]
        ima, imb, iia, iib = con[CIMA, m], con[CIMB, m], con[CIIA, m], con[CIIB, m]
        moves = (ima != 0.0) & (imb != 0.0)
        # Point 0, then point 1, written out: a loop over them would stop the
        # vectoriser, which takes innermost loops only.
        f, base = FOLLOW0, POINT0
        rax, ray, rbx, rby = con[f + PRAX, m], con[f + PRAY, m], con[f + PRBX, m], con[f + PRBY, m]
        old = (con[base + PRNA, m], con[base + PRNB, m], con[base + PRTA, m],
               con[base + PRTB, m], con[base + PNORMAL_MASS, m],
               con[base + PTANGENT_MASS, m])  # fmt: skip
        j = _followed(nx, ny, ima, imb, iia, iib, rax, ray, rbx, rby, xa, ya, xb, yb,
                      con[f + PKEEP, m] == 0.0)  # fmt: skip
        follows = moves & (con[f + PBOUNCES, m] == 0.0)
        con[base + PRNA, m] = j[0] if follows else old[0]
        con[base + PRNB, m] = j[1] if follows else old[1]
        con[base + PRTA, m] = j[2] if follows else old[2]
        con[base + PRTB, m] = j[3] if follows else old[3]
        con[base + PNORMAL_MASS, m] = j[4] if follows else old[4]
        con[base + PTANGENT_MASS, m] = j[5] if follows else old[5]
        f, base = FOLLOW0 + PER_FOLLOW, POINT0 + PER_POINT
        rax, ray, rbx, rby = con[f + PRAX, m], con[f + PRAY, m], con[f + PRBX, m], con[f + PRBY, m]
        old = (con[base + PRNA, m], con[base + PRNB, m], con[base + PRTA, m],
               con[base + PRTB, m], con[base + PNORMAL_MASS, m],
               con[base + PTANGENT_MASS, m])  # fmt: skip
        j = _followed(nx, ny, ima, imb, iia, iib, rax, ray, rbx, rby, xa, ya, xb, yb,
                      con[f + PKEEP, m] == 0.0)  # fmt: skip
        follows = moves & (con[f + PBOUNCES, m] == 0.0)
        con[base + PRNA, m] = j[0] if follows else old[0]
        con[base + PRNB, m] = j[1] if follows else old[1]
        con[base + PRTA, m] = j[2] if follows else old[2]
        con[base + PRTB, m] = j[3] if follows else old[3]
        con[base + PNORMAL_MASS, m] = j[4] if follows else old[4]
        con[base + PTANGENT_MASS, m] = j[5] if follows else old[5]
    _record_drift(body, w, con, body_a, body_b, count)


@kernel
def _record_drift(body, w, con, body_a, body_b, count) -> None:
    """The points that may bounce (between two moving bodies): the farthest their
    anchors have drifted apart this step (``contacts.follow_bodies``)."""
    for m in range(count):
        if con[CIMA, m] == 0.0 or con[CIMB, m] == 0.0:
            continue
        a, b = body_a[m], body_b[m]
        for p in range(2):
            follow = follow_base(p)
            if con[follow + PBOUNCES, m] != 0.0:
                mx = (body[w, b, X] + con[follow + PRBX, m]) - (
                    body[w, a, X] + con[follow + PRAX, m]
                )
                my = (body[w, b, Y] + con[follow + PRBY, m]) - (
                    body[w, a, Y] + con[follow + PRAY, m]
                )
                con[follow + PDRIFT, m] = max(con[follow + PDRIFT, m], math.hypot(mx, my))
