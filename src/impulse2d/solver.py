"""The contact solver: Box2D v3's soft step, vectorised over colours.

One step of ``dt`` is split into ``substeps`` of ``h = dt / substeps``; each substep:

1. integrate velocities (gravity, forces, springs, drag) -- in ``world.py``;
2. ``warm_start``: apply the impulses accumulated so far;
3. ``solve(use_bias=True)``: non-penetration with a *soft* position correction (a
   spring-damper of ``contact_hertz``) plus Coulomb friction, Gauss-Seidel by colour;
4. integrate positions -- in ``world.py``;
5. ``solve(use_bias=False)`` (the *relax* pass): the same without the position bias,
   which removes the velocity the bias added, so pushing bodies apart does not make
   them bounce.

After the substeps, ``restitution`` applies the bounce once, against the normal
velocity the point had at the start of the step (``relative_velocity``), so resting
contacts never bounce and a falling ball rebounds at ``e`` times its impact speed.

Speculative contacts (``separation > 0``) are hard: the closing speed is limited to
``separation / h``, so a body arrives at the surface and no further. The current
separation of a point is ``base + J . dq``, where ``dq`` is how far each body has moved
since the step began (the Jacobian is the same one that gives the normal velocity);
``contacts.base_separation`` folds the starting poses in, so it is ``base + J . pose``.

Sign conventions are in ``contacts.py``. The tutorial resolves each collision once with
an impulse and then pushes the bodies apart by the penetration ("contact forces"); here
both are the same constraint, iterated, which is what lets boxes stack.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .contacts import Contacts
from .narrowphase import FEATURES

_SHARED_SWEEPS = 8  # restitution sweeps for pairs that strike at two points (see restitution)


@dataclass
class Block:
    """One colour's points, ready for the solver: only the velocity rows its Jacobians use
    (a frictionless disc contact touches no angular velocity), gathered as one array."""

    lo: int
    hi: int
    index: np.ndarray  # flat (3, T) indices of the used rows, row-major: (rows * k,)
    jac_n: np.ndarray  # (rows, k)
    inv_n: np.ndarray
    jac_t: np.ndarray | None  # None: no friction in this colour
    inv_t: np.ndarray | None
    write: np.ndarray  # which of the used rows can change (their inverse mass is not 0)
    write_index: np.ndarray  # their flat indices


def blocks(contacts: Contacts) -> list[Block]:
    """Split the contacts into per-colour blocks (see ``Block``), once per step."""
    out = []
    for lo, hi in itertools.pairwise(contacts.bounds):
        if lo == hi:  # persistent colours can leave a colour empty
            continue
        jac_n, inv_n = contacts.jac_n[:, lo:hi], contacts.inv_n[:, lo:hi]
        friction = bool(contacts.friction[lo:hi].any())
        used = (jac_n != 0.0).any(axis=1)
        moved = (inv_n != 0.0).any(axis=1)
        if friction:
            used |= (contacts.jac_t[:, lo:hi] != 0.0).any(axis=1)
            moved |= (contacts.inv_t[:, lo:hi] != 0.0).any(axis=1)
        rows = np.flatnonzero(used | moved)
        index = contacts.index6[rows, lo:hi]
        write = np.flatnonzero(moved[rows])
        out.append(
            Block(
                lo=int(lo),
                hi=int(hi),
                index=index.ravel(),
                jac_n=jac_n[rows],
                inv_n=inv_n[rows],
                jac_t=contacts.jac_t[rows, lo:hi] if friction else None,
                inv_t=contacts.inv_t[rows, lo:hi] if friction else None,
                write=write,
                write_index=index[write].ravel(),
            )
        )
    return out


def separation(contacts: Contacts, pose: np.ndarray) -> np.ndarray:
    """Current separation of every point, ``base + J . pose`` (``pose`` is ``(3, T)``).

    This is the separation at the start of the step plus ``J . dq``, the motion of the
    two bodies along the normal since then (rotation linearised: ``dq`` is small)."""
    return contacts.base_separation + (contacts.jac_n * pose.reshape(-1)[contacts.index6]).sum(
        axis=0
    )


def warm_start(contacts: Contacts, velocity: np.ndarray) -> None:
    """Apply the accumulated normal and friction impulses to the ``(3, T)`` velocities."""
    if not (contacts.normal_impulse.any() or contacts.tangent_impulse.any()):
        return  # fresh or speculative contacts carry nothing yet
    contacts.step_impulse += contacts.normal_impulse
    change = contacts.inv_n * contacts.normal_impulse + contacts.inv_t * contacts.tangent_impulse
    np.add.at(velocity.reshape(-1), contacts.index6.ravel(), change.ravel())


def solve(
    contacts: Contacts,
    colour_blocks: list[Block],
    velocity: np.ndarray,
    current_separation: np.ndarray,
    inv_h: float,
    use_bias: bool,
    push_speed: float,
) -> None:
    """One Gauss-Seidel sweep over the colours: normal, then friction, for every point.

    The normal impulse solves ``J v + bias = 0`` softly and is clamped so the accumulated
    impulse stays >= 0 (contacts push, never pull); friction is clamped to the Coulomb
    cone ``|lambda_t| <= mu lambda_n``.
    """
    s = current_separation
    speculative = s > 0.0
    if use_bias:
        bias = np.where(
            speculative,
            s * inv_h,
            np.maximum(contacts.mass_scale * contacts.bias_rate * s, -push_speed),
        )
        mass_scale = np.where(speculative, 1.0, contacts.mass_scale)
        impulse_scale = np.where(speculative, 0.0, contacts.impulse_scale)
    else:
        bias = np.where(speculative, s * inv_h, 0.0)
        mass_scale = impulse_scale = None
    flat = velocity.reshape(-1)
    # The normal velocity of every point before this sweep, kept for restitution as the
    # velocity at which a point first pushes (taken before the sweep, so the order in which
    # a box's two corners are solved does not change it).
    watched = contacts.watched
    if watched is not None:
        before = np.zeros(contacts.size)
        before[watched] = (contacts.jac_n[:, watched] * flat[contacts.index6[:, watched]]).sum(
            axis=0
        )
        fresh = (contacts.impact_velocity == 0.0)[watched]
    for block in colour_blocks:
        lo, hi = block.lo, block.hi
        v = flat[block.index].reshape(-1, hi - lo)
        # Non-penetration.
        vn = (block.jac_n * v).sum(axis=0)
        accumulated = contacts.normal_impulse[lo:hi]  # a view: read before writing back
        if mass_scale is None:
            impulse = -contacts.normal_mass[lo:hi] * (vn + bias[lo:hi])
        else:
            impulse = (
                -contacts.normal_mass[lo:hi] * (mass_scale[lo:hi] * vn + bias[lo:hi])
                - impulse_scale[lo:hi] * accumulated
            )
        total = np.maximum(accumulated + impulse, 0.0)
        impulse = total - accumulated
        contacts.normal_impulse[lo:hi] = total
        contacts.step_impulse[lo:hi] += impulse
        np.maximum(
            contacts.max_normal_impulse[lo:hi], impulse, out=contacts.max_normal_impulse[lo:hi]
        )
        v += impulse * block.inv_n
        if block.jac_t is not None:
            # Friction, within the cone of the normal impulse just found.
            vt = (block.jac_t * v).sum(axis=0)
            accumulated = contacts.tangent_impulse[lo:hi]  # a view: take the change first
            limit = contacts.friction[lo:hi] * total
            friction = np.minimum(
                np.maximum(accumulated - contacts.tangent_mass[lo:hi] * vt, -limit), limit
            )
            v += (friction - accumulated) * block.inv_t
            contacts.tangent_impulse[lo:hi] = friction
        flat[block.write_index] = v[block.write].ravel()
    if watched is not None:
        # Points that pushed for the first time in this sweep keep their velocity before it.
        touched = fresh & (contacts.max_normal_impulse[watched] > 0.0)
        contacts.impact_velocity[watched[touched]] = before[watched[touched]]


def restitution(contacts: Contacts, velocity: np.ndarray, threshold: float, h: float) -> None:
    """Bounce: send each impacting point apart at ``e`` times its impact speed.

    Only points that approached faster than ``threshold`` at the start of the step, and
    pushed during it, take part, so resting contacts stay at rest and a ball at rest in
    a rack that is hit does not "bounce" off its neighbours (which would create energy).

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
    the step are not their speeds at impact (a spinning corner turns within the step), and
    Newton's law on them can give the pair a quarter more kinetic energy than it had. Its
    points use the normal velocity they had when they first pushed, in the substep they
    touched, and a few Gauss-Seidel sweeps share the bounce between them as a simultaneous
    impact would (solved one after the other, the first point would take it all and set a
    flat-landing box spinning).
    """
    eligible = (
        (contacts.relative_velocity < -threshold)
        & (contacts.max_normal_impulse > 0.0)
        & (contacts.restitution > 0.0)
    )
    if not eligible.any():
        return
    flat = velocity.reshape(-1)
    half_kick = 0.5 * h * contacts.relative_acceleration
    approach = -(contacts.relative_velocity + half_kick)
    gap = np.maximum(contacts.separation, 0.0)
    impact = np.sqrt(
        np.maximum(approach * approach - 2.0 * contacts.relative_acceleration * gap, 0.0)
    )
    outgoing = contacts.restitution * impact - half_kick
    # Which eligible points share their pair with another. (This depends only on each
    # point's own world, so a batch still steps exactly like single worlds.)
    rows = np.flatnonzero(eligible)
    _, inverse, counts = np.unique(
        contacts.key[rows] // FEATURES, return_inverse=True, return_counts=True
    )
    shared = np.zeros(eligible.size, dtype=bool)
    shared[rows[counts[inverse] > 1]] = True
    targets = np.where(
        shared, contacts.restitution * np.minimum(contacts.impact_velocity, 0.0), -outgoing
    )
    for sweep in range(_SHARED_SWEEPS if shared.any() else 1):
        _restitution_sweep(contacts, flat, eligible if sweep == 0 else shared, targets)


def _restitution_sweep(
    contacts: Contacts, flat: np.ndarray, chosen_mask: np.ndarray, targets: np.ndarray
) -> None:
    """One Gauss-Seidel sweep driving each chosen point's normal velocity to ``-target``
    (the normal impulse stays >= 0)."""
    bounds = contacts.bounds
    for k in range(bounds.size - 1):
        chosen = np.flatnonzero(chosen_mask[bounds[k] : bounds[k + 1]]) + bounds[k]
        if chosen.size == 0:
            continue
        index = contacts.index6[:, chosen].ravel()
        v = flat[index].reshape(6, chosen.size)
        vn = (contacts.jac_n[:, chosen] * v).sum(axis=0)
        accumulated = contacts.normal_impulse[chosen]
        total = np.maximum(accumulated - contacts.normal_mass[chosen] * (vn + targets[chosen]), 0.0)
        impulse = total - accumulated
        contacts.normal_impulse[chosen] = total
        contacts.step_impulse[chosen] += impulse
        v += impulse * contacts.inv_n[:, chosen]
        flat[index] = v.ravel()
