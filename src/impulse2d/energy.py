"""Energy readouts: where the energy is, to watch it move between kinds (tutorial extra)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from . import springs as spring_forces


@dataclass(frozen=True)
class Energy:
    """Energy of a world (J); each field is a float, or one value per world of a batch.

    ``kinetic_linear`` = sum of ``m v^2 / 2``; ``kinetic_rotational`` = sum of
    ``I w^2 / 2``; ``potential`` = sum of ``-m g . position`` (zero at the origin; the
    tutorial writes "mass * gravity", which is a force: the height is missing);
    ``elastic`` = sum over springs of ``k (L - L0)^2 / 2``.
    """

    kinetic_linear: Any
    kinetic_rotational: Any
    potential: Any
    elastic: Any

    @property
    def kinetic(self) -> Any:
        """Linear plus rotational kinetic energy (J)."""
        return self.kinetic_linear + self.kinetic_rotational

    @property
    def total(self) -> Any:
        """Everything: kinetic, potential and elastic (J)."""
        return self.kinetic_linear + self.kinetic_rotational + self.potential + self.elastic


def energy_of(
    flat: dict[str, np.ndarray],
    dynamic: np.ndarray,
    gravity: np.ndarray,
    springs: tuple | None,
    batch: int,
) -> Energy:
    """Energy per world from the flat body arrays (see ``World.energy``)."""
    counted = dynamic & flat["enabled"]
    mass = np.where(counted, flat["mass"], 0.0).reshape(batch, -1)
    moment = np.where(counted, flat["moment"], 0.0).reshape(batch, -1)
    vel = flat["vel"].reshape(3, batch, -1)
    pose = flat["pose"].reshape(3, batch, -1)
    linear = 0.5 * (mass * (vel[0] ** 2 + vel[1] ** 2)).sum(axis=1)
    rotational = 0.5 * (moment * vel[2] ** 2).sum(axis=1)
    potential = -(mass * (gravity[0] * pose[0] + gravity[1] * pose[1])).sum(axis=1)
    elastic = np.zeros(batch)
    if springs is not None:
        a, b, params = springs
        _, _, _, length = spring_forces.geometry(
            flat["pose"], a, b, params["anchor_a"], params["anchor_b"]
        )
        stored = 0.5 * params["stiffness"] * (length - params["rest_length"]) ** 2
        slots = flat["enabled"].size // batch
        np.add.at(elastic, a // slots, stored)
    if batch == 1:
        return Energy(
            float(linear[0]), float(rotational[0]), float(potential[0]), float(elastic[0])
        )
    return Energy(linear, rotational, potential, elastic)
