"""Damped springs between anchor points on two bodies (the tutorial's Spring).

The force on body 2 is ``F = -(k (L - L0) + c v_along) u`` and body 1 gets ``-F``, where
``u`` is the unit vector from anchor 1 to anchor 2, ``L`` their distance, ``L0`` the rest
length and ``v_along`` the relative velocity of the anchors along ``u``. Two fixes to the
tutorial's version: it multiplied by the *unnormalised* separation (a force growing as
``L (L0 - L)``, not Hooke's law) and damped the whole relative velocity, which also
brakes sideways motion a spring cannot resist. A force off a body's centre also
applies the torque ``r x F``.

Springs are applied as forces in every substep (symplectic Euler), which keeps the
period at ``2 pi sqrt(m / k)`` and does not pump energy in. That integrator is stable
only while ``h^2 k w + 2 h c w < 4`` (``w`` the inverse effective mass along the
spring, ``h`` the substep); ``check_stable`` raises a ValueError beyond it rather than
let the simulation explode.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks

if TYPE_CHECKING:
    from .shapes import Body
    from .world import World


class Spring:
    """A damped spring joining ``anchor1`` on ``body1`` to ``anchor2`` on ``body2``.

    ``rest_length`` (m, >= 0; default: the anchors' distance when the spring is added),
    ``stiffness`` k (N/m, >= 0), ``damping`` c (N s/m, >= 0, acting on the relative
    velocity along the spring: a mass m on a spring decays as ``exp(-c t / (2 m))``),
    anchors in body-local coordinates (m). Both bodies must be in the world first.
    """

    def __init__(
        self,
        body1: Body,
        body2: Body,
        rest_length: Any = None,
        stiffness: Any = 1.0,
        damping: Any = 0.0,
        anchor1: Any = (0.0, 0.0),
        anchor2: Any = (0.0, 0.0),
    ) -> None:
        from .shapes import Body

        for name, body in (("body1", body1), ("body2", body2)):
            if not isinstance(body, Body):
                raise ValueError(f"{name} must be a Circle or Box, got {type(body).__name__}")
        if body1 is body2:
            raise ValueError(
                "body1 and body2 must be different bodies (a spring from a body "
                "to itself does nothing)"
            )
        self.body1, self.body2 = body1, body2
        self._world: World | None = None
        self._slot = -1
        self._values: dict[str, Any] = {
            "rest_length": None
            if rest_length is None
            else _checks.non_negative("rest_length", rest_length),
            "stiffness": _checks.non_negative("stiffness", stiffness),
            "damping": _checks.non_negative("damping", damping),
            "anchor1": _checks.vector2("anchor1", anchor1),
            "anchor2": _checks.vector2("anchor2", anchor2),
        }

    @property
    def world(self) -> World | None:
        """The world this spring is in, or None."""
        return self._world

    def _get(self, name: str) -> Any:
        if self._world is None:
            value = self._values[name]
            return value.copy() if isinstance(value, np.ndarray) else value
        return self._world._read_spring(self._slot, name)

    def _set(self, name: str, value: Any, tail: tuple[int, ...], rule: str | None) -> None:
        if self._world is None:
            array = _checks.finite_array(name, value)
            if rule:
                _checks.batched_rule(name, array, rule)
            self._values[name] = float(array) if tail == () and array.shape == () else array
            return
        array = _checks.batched(name, value, self._world.batch_size, tail)
        if rule:
            _checks.batched_rule(name, array, rule)
        self._world._write_spring(self._slot, name, array)

    rest_length = property(
        lambda self: self._get("rest_length"),
        lambda self, v: self._set("rest_length", v, (), ">= 0"),
        doc="Rest length L0 (m).",
    )
    stiffness = property(
        lambda self: self._get("stiffness"),
        lambda self, v: self._set("stiffness", v, (), ">= 0"),
        doc="Stiffness k (N/m).",
    )
    damping = property(
        lambda self: self._get("damping"),
        lambda self, v: self._set("damping", v, (), ">= 0"),
        doc="Damping c (N s/m) on the relative velocity along the spring.",
    )
    anchor1 = property(
        lambda self: self._get("anchor1"),
        lambda self, v: self._set("anchor1", v, (2,), None),
        doc="Anchor on body1, body-local (m).",
    )
    anchor2 = property(
        lambda self: self._get("anchor2"),
        lambda self, v: self._set("anchor2", v, (2,), None),
        doc="Anchor on body2, body-local (m).",
    )

    @property
    def length(self) -> Any:
        """Current distance between the two anchors (m)."""
        return np.linalg.norm(
            self.body2.to_world(self.anchor2) - self.body1.to_world(self.anchor1), axis=-1
        )

    def __repr__(self) -> str:
        return f"<Spring {'slot ' + str(self._slot) if self._world else 'not in a world'}>"


def geometry(
    pose: np.ndarray, a: np.ndarray, b: np.ndarray, anchor_a: np.ndarray, anchor_b: np.ndarray
) -> tuple[np.ndarray, ...]:
    """World anchor offsets ``rA``, ``rB`` (2, S), separation ``d`` (2, S) and length (S,).

    ``pose`` is the flat ``(3, T)`` pose; ``a``, ``b`` flat body indices; anchors ``(2, S)``.
    """
    ca, sa = np.cos(pose[2, a]), np.sin(pose[2, a])
    cb, sb = np.cos(pose[2, b]), np.sin(pose[2, b])
    ra = np.stack([ca * anchor_a[0] - sa * anchor_a[1], sa * anchor_a[0] + ca * anchor_a[1]])
    rb = np.stack([cb * anchor_b[0] - sb * anchor_b[1], sb * anchor_b[0] + cb * anchor_b[1]])
    d = (pose[:2, b] + rb) - (pose[:2, a] + ra)
    return ra, rb, d, np.hypot(d[0], d[1])


def add_forces(
    accel: np.ndarray,
    pose: np.ndarray,
    vel: np.ndarray,
    inv_mass: np.ndarray,
    inv_moment: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    params: dict[str, np.ndarray],
) -> None:
    """Add every spring's acceleration to ``accel`` (3, T); see the module docstring."""
    ra, rb, d, length = geometry(pose, a, b, params["anchor_a"], params["anchor_b"])
    safe = np.where(length > 0.0, length, 1.0)
    ux, uy = np.where(length > 0.0, d[0] / safe, 0.0), np.where(length > 0.0, d[1] / safe, 0.0)
    # Relative velocity of the anchors: (vB + wB x rB) - (vA + wA x rA).
    rvx = (vel[0, b] - vel[2, b] * rb[1]) - (vel[0, a] - vel[2, a] * ra[1])
    rvy = (vel[1, b] + vel[2, b] * rb[0]) - (vel[1, a] + vel[2, a] * ra[0])
    tension = params["stiffness"] * (length - params["rest_length"]) + params["damping"] * (
        rvx * ux + rvy * uy
    )
    fx, fy = tension * ux, tension * uy  # force on A; B gets the opposite
    torque_a = ra[0] * fy - ra[1] * fx
    torque_b = -(rb[0] * fy - rb[1] * fx)
    total = inv_mass.size
    index = np.concatenate([a, a + total, a + 2 * total, b, b + total, b + 2 * total])
    change = np.concatenate(
        [
            fx * inv_mass[a],
            fy * inv_mass[a],
            torque_a * inv_moment[a],
            -fx * inv_mass[b],
            -fy * inv_mass[b],
            torque_b * inv_moment[b],
        ]
    )
    np.add.at(accel.reshape(-1), index, change)


def check_stable(
    pose: np.ndarray,
    inv_mass: np.ndarray,
    inv_moment: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    params: dict[str, np.ndarray],
    h: float,
) -> None:
    """Raise if a spring is too stiff or too damped for the substep ``h``."""
    ra, rb, d, length = geometry(pose, a, b, params["anchor_a"], params["anchor_b"])
    safe = np.where(length > 0.0, length, 1.0)
    ux, uy = d[0] / safe, d[1] / safe
    w = (
        inv_mass[a]
        + inv_mass[b]
        + inv_moment[a] * (ra[0] * uy - ra[1] * ux) ** 2
        + inv_moment[b] * (rb[0] * uy - rb[1] * ux) ** 2
    )
    measure = h * h * params["stiffness"] * w + 2.0 * h * params["damping"] * w
    if np.any(measure >= 4.0):
        worst = int(np.argmax(measure))
        raise ValueError(
            f"spring stiffness {params['stiffness'][worst]} N/m with damping "
            f"{params['damping'][worst]} N s/m is unstable at substep h = {h:.3g} s "
            f"(needs h^2 k w + 2 h c w < 4, got {measure[worst]:.3g}); lower stiffness or "
            "damping, use more substeps or a smaller dt"
        )
