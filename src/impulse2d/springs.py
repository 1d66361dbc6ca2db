"""``Spring``: a damped spring between anchor points on two bodies, a view of one spring slot.

The physics (Hooke's law along the unit direction, damping along it only, applied in every
substep, and the stability limit) is in ``integrate.py``. Two fixes to the tutorial's
version: it multiplied by the *unnormalised* separation (a force growing as
``L (L0 - L)``, not Hooke's law) and damped the whole relative velocity, which also brakes
sideways motion a spring cannot resist.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks, edit, envelope
from .core.state import ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, DAMPING, REST_LENGTH, STIFFNESS
from .shapes import Part, per_world

if TYPE_CHECKING:
    from .shapes import Body

# Anchors and lengths within the envelope's coordinates (``impulse2d.envelope``); the
# stiffness and damping are bounded by the stability check of every step instead.
_LENGTH = partial(_checks.within, low=0.0, high=2.0 * envelope.COORDINATE, unit=" m")
_ANCHOR = partial(_checks.within, low=-envelope.COORDINATE, high=envelope.COORDINATE, unit=" m")
_NON_NEGATIVE = partial(_checks.batched_rule, rule=">= 0")

# name -> (columns of state.spring, shape of one value, check(name, array))
_COLUMNS: dict[str, tuple[list[int], tuple[int, ...], Callable[[str, Any], None]]] = {
    "rest_length": ([REST_LENGTH], (), _LENGTH),
    "stiffness": ([STIFFNESS], (), _NON_NEGATIVE),
    "damping": ([DAMPING], (), _NON_NEGATIVE),
    "anchor1": ([ANCHOR_AX, ANCHOR_AY], (2,), _ANCHOR),
    "anchor2": ([ANCHOR_BX, ANCHOR_BY], (2,), _ANCHOR),
}


def _property(name: str, doc: str) -> property:
    return property(lambda self: self._get(name), lambda self, v: self._set(name, v), doc=doc)


class Spring(Part):
    """A damped spring joining ``anchor1`` on ``body1`` to ``anchor2`` on ``body2``.

    ``rest_length`` (m, >= 0; default: the anchors' distance when the spring is added),
    ``stiffness`` k (N/m, >= 0), ``damping`` c (N s/m, >= 0, acting on the relative
    velocity along the spring: a mass m on a spring decays as ``exp(-c t / (2 m))``),
    anchors in body-local coordinates (m). Both bodies must be in the world first. A
    spring too stiff for the substep (``h^2 k w + 2 h c w >= 4``, ``w`` the inverse
    effective mass along it) makes ``World.step`` raise instead of exploding.
    """

    rest_length = _property("rest_length", "Rest length L0 (m).")
    stiffness = _property("stiffness", "Stiffness k (N/m).")
    damping = _property("damping", "Damping c (N s/m) on the relative velocity along the spring.")
    anchor1 = _property("anchor1", "Anchor on body1, body-local (m).")
    anchor2 = _property("anchor2", "Anchor on body2, body-local (m).")

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
        super().__init__()
        self.body1, self.body2 = body1, body2
        self._values["rest_length"] = None
        if rest_length is not None:
            self.rest_length = rest_length
        self.stiffness, self.damping = stiffness, damping
        self.anchor1, self.anchor2 = anchor1, anchor2

    def _get(self, name: str) -> Any:
        if self._world is None:
            value = self._values[name]
            return value.copy() if isinstance(value, np.ndarray) else value
        columns, tail, _ = _COLUMNS[name]
        values = self._world.state.spring[:, self._slot, columns]
        return per_world(values if tail else values[:, 0], self._world.batch_size)

    def _set(self, name: str, value: Any) -> None:
        columns, tail, check = _COLUMNS[name]
        if self._world is None:
            kept = _checks.detached(name, value, tail)
            check(name, np.asarray(kept))
            self._values[name] = kept
            return
        world = self._world
        array = _checks.batched(name, value, world.batch_size, tail)
        check(name, array)
        world.state.spring[:, self._slot, columns] = array.reshape(world.batch_size, -1)
        everywhere = np.arange(world.batch_size)
        edit.wake(world.state, world.layout, everywhere, self.body1.slot)
        edit.wake(world.state, world.layout, everywhere, self.body2.slot)

    @property
    def length(self) -> Any:
        """Current distance between the two anchors (m)."""
        return np.linalg.norm(
            self.body2.to_world(self.anchor2) - self.body1.to_world(self.anchor1), axis=-1
        )

    def __repr__(self) -> str:
        return f"<Spring {'slot ' + str(self._slot) if self._world else 'not in a world'}>"
