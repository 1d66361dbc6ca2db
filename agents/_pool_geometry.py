"""Pool shot geometry for the agents' features and actions, batched, in torch.

One implementation for both sides of a policy: the ``pool_target`` features extractor
(torch, inside the network) and the ``pocket_choice`` action transform (numpy actions,
converted) read the same numbers, so the shot a policy's action names is the shot its
features describe.

Positions are in metres on the bed, from Pool2D observations (per ball ``x / (L/2)``,
``y / (W/2)``, potted flag). For an object ball at ``b``, a pocket at ``q`` and the cue
ball at ``c`` (the "ghost ball" method):

    u_bp = (q - b) / |q - b|               the object ball's path to the pocket
    g = b - 2 r u_bp                       where the cue ball must be at contact
    u = (g - c) / |g - c|                  the cue ball's path
    sin(cut) = u_bp x u,  cos(cut) = u . u_bp

The cue ball's path passes the object ball's centre at the signed distance
``(b - c) x u = 2 r (u_bp x u) = 2 r sin(cut)`` (left of the ball positive), which is
how an action names a contact point.
"""

from __future__ import annotations

import torch

from impulse2d.envs.pool import BALL_RADIUS, TABLE_LENGTH, TABLE_WIDTH, pockets

POCKETS = torch.as_tensor(pockets()[0], dtype=torch.float64)  # (6, 2) m
HALF_SIZE = (TABLE_LENGTH / 2, TABLE_WIDTH / 2)
CLEARANCE_CAP = 3.0  # clearances are in ball diameters, capped here (nothing in the way)


def balls(obs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """``(n, 3 (k + 1))`` observations -> positions ``(n, k + 1, 2)`` (m) and on-table
    flags ``(n, k + 1)``; ball 0 is the cue ball."""
    rows = obs.reshape(obs.shape[0], -1, 3)
    return rows[..., :2] * rows.new_tensor(HALF_SIZE), rows[..., 2] < 0.5


def target_ball(xy: torch.Tensor, on_table: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """The nearest object ball on the table to the cue ball: its index ``(n,)`` (1..k)
    and whether there is one ``(n,)`` (a cleared table has none; index 1 then)."""
    distance = torch.linalg.vector_norm(xy[:, 1:] - xy[:, :1], dim=-1)
    distance = torch.where(on_table[:, 1:], distance, torch.inf)
    nearest = torch.argmin(distance, dim=1)
    return nearest + 1, torch.isfinite(distance.min(dim=1).values)


def _unit(v: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    length = torch.linalg.vector_norm(v, dim=-1, keepdim=True)
    return v / length.clamp_min(1e-9), length[..., 0]


def shots(cue: torch.Tensor, ball: torch.Tensor) -> dict[str, torch.Tensor]:
    """The ghost-ball shot into each pocket, for cue ball and object ball ``(n, 2)``:
    ``ghost`` ``(n, 6, 2)``, ``run`` (ball to pocket, m), ``reach`` (cue ball to ghost
    point, m), ``sin`` and ``cos`` of the cut, all ``(n, 6)``."""
    pocket = POCKETS.to(cue.dtype)
    u_bp, run = _unit(pocket - ball[:, None, :])
    ghost = ball[:, None, :] - 2 * BALL_RADIUS * u_bp
    u, reach = _unit(ghost - cue[:, None, :])
    sin = u_bp[..., 0] * u[..., 1] - u_bp[..., 1] * u[..., 0]
    cos = (u_bp * u).sum(dim=-1)
    return {"ghost": ghost, "run": run, "reach": reach, "sin": sin, "cos": cos}


def clearance(
    start: torch.Tensor, end: torch.Tensor, xy: torch.Tensor, obstacle: torch.Tensor
) -> torch.Tensor:
    """How far the nearest obstacle ball's centre is from each segment ``start -> end``
    (``(n, s, 2)`` each; ``xy`` ``(n, m, 2)``, ``obstacle`` ``(n, m)`` bool), in ball
    diameters, capped at ``CLEARANCE_CAP``. Below 1, a ball rolling along the segment
    touches that obstacle."""
    d = end - start  # (n, s, 2)
    rel = xy[:, None, :, :] - start[:, :, None, :]  # (n, s, m, 2)
    length2 = (d * d).sum(dim=-1).clamp_min(1e-18)[..., None]  # (n, s, 1)
    t = ((rel * d[:, :, None, :]).sum(dim=-1) / length2).clamp(0.0, 1.0)
    gap = torch.linalg.vector_norm(rel - t[..., None] * d[:, :, None, :], dim=-1)
    gap = torch.where(obstacle[:, None, :], gap / (2 * BALL_RADIUS), CLEARANCE_CAP)
    if gap.shape[-1] == 0:
        return gap.new_full(d.shape[:2], CLEARANCE_CAP)
    return gap.min(dim=-1).values.clamp(max=CLEARANCE_CAP)


def target_shots(obs: torch.Tensor) -> dict[str, torch.Tensor]:
    """Everything about the shots at the target ball (the nearest on the table):
    ``shots(...)``'s entries, plus ``cue``, ``ball`` ``(n, 2)``, ``has_target`` ``(n,)``
    and the clearances ``(n, 6)`` of the cue ball's path to each ghost point
    (``clear_cue``) and of the object ball's path to each pocket (``clear_ball``)."""
    xy, on_table = balls(obs)
    index, has_target = target_ball(xy, on_table)
    rows = torch.arange(xy.shape[0])
    cue, ball = xy[:, 0], xy[rows, index]
    out = shots(cue, ball)
    obstacle = on_table.clone()
    obstacle[:, 0] = False
    obstacle[rows, index] = False  # neither the cue ball nor the target is in the way
    pocket = POCKETS.to(xy.dtype).expand(xy.shape[0], -1, -1)
    out["clear_cue"] = clearance(cue[:, None, :].expand(-1, 6, -1), out["ghost"], xy, obstacle)
    out["clear_ball"] = clearance(ball[:, None, :].expand(-1, 6, -1), pocket, xy, obstacle)
    out.update(cue=cue, ball=ball, has_target=has_target)
    return out
