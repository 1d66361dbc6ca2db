"""``Spring``: a damped spring between anchor points on two bodies, a view of one spring slot.

The physics (Hooke's law along the unit direction, damping along it only, applied in every
substep, and the stability limit) is in ``integrate.py``. Two fixes to the tutorial's
version: it multiplied by the *unnormalised* separation (a force growing as
``L (L0 - L)``, not Hooke's law) and damped the whole relative velocity, which also brakes
sideways motion a spring cannot resist.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from . import edit
from .columns import COORDINATE, LENGTH, Column, Part
from .core.state import ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, DAMPING, REST_LENGTH, STIFFNESS

if TYPE_CHECKING:
    from .shapes import Body


class Spring(Part):
    """A damped spring joining ``anchor1`` on ``body1`` to ``anchor2`` on ``body2``.

    ``rest_length`` (m, >= 0; default: the anchors' distance when the spring is added),
    ``stiffness`` k (N/m, >= 0), ``damping`` c (N s/m, >= 0, acting on the relative
    velocity along the spring: a mass m on a spring decays as ``exp(-c t / (2 m))``),
    anchors in body-local coordinates (m). Both bodies must be in the world first. A
    spring too stiff for the substep (``h^2 k w + 2 h c w >= 4``, ``w`` the inverse
    effective mass along it) makes ``World.step`` raise instead of exploding.
    """

    # Anchors and lengths within the envelope's coordinates; the stiffness and damping
    # are bounded by the stability check of every step instead.
    rest_length = Column((REST_LENGTH,), "spring", limit=LENGTH, doc="Rest length L0 (m).")
    stiffness = Column((STIFFNESS,), "spring", rule=">= 0", doc="Stiffness k (N/m).")
    damping = Column(
        (DAMPING,),
        "spring",
        rule=">= 0",
        doc="Damping c (N s/m) on the relative velocity along the spring.",
    )
    anchor1 = Column(
        (ANCHOR_AX, ANCHOR_AY), "spring", limit=COORDINATE, doc="Anchor on body1, body-local (m)."
    )
    anchor2 = Column(
        (ANCHOR_BX, ANCHOR_BY), "spring", limit=COORDINATE, doc="Anchor on body2, body-local (m)."
    )

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
                raise ValueError(
                    f"{name} must be a body (a Circle, Box, Polygon, ...), "
                    f"got {type(body).__name__}"
                )
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

    def _write(self, column: Column, stored: np.ndarray) -> None:
        """A spring's write wakes both its bodies in every world."""
        world = self._world
        state, layout = world.state, world.layout
        edit.write_rows(state, "spring", self._slot, column.columns, stored)
        everywhere = np.arange(world.batch_size)
        edit.wake(state, layout, everywhere, self.body1.slot)
        edit.wake(state, layout, everywhere, self.body2.slot)

    @property
    def length(self) -> Any:
        """Current distance between the two anchors (m)."""
        return np.linalg.norm(
            self.body2.to_world(self.anchor2) - self.body1.to_world(self.anchor1), axis=-1
        )

    def __repr__(self) -> str:
        return f"<Spring {'slot ' + str(self._slot) if self._world else 'not in a world'}>"
