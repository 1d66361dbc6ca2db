"""Slingshot2DBlocks-v0's level templates: v0's ten (``_templates``) and six built with
triangles and round stones, with the blocks game's own fixed split.

The new templates are puzzles the new blocks make (Phy-Q's roofs, boulders and ramps):

* train: ``roofed_tower`` (a pig under a gable roof on a tower), ``boulder_column`` (a
  stone on a column, a pig on the ground behind it: topple the stone onto it),
  ``rampart`` (a wedge whose slope faces the sling, a pig behind it and a boulder
  behind the pig; one or two of them), ``rolling_stone`` (a stone on a tower's roof
  plank, a pig on the ground beyond the tower);
* held out: ``village`` (two roofed huts, a pig inside each) and ``fort`` (a wedge in
  front of a roofed tower, a pig inside, a boulder behind it): new arrangements of the
  train templates' pieces.

The split joins v0's: the blocks game trains on v0's seven train templates and the four
new ones, and holds out v0's three and the two new ones. Slingshot2D-v0's own templates
and split are unchanged, so its held-out results stand. Level seed ``k`` plays template
``names[k % len(names)]`` (``_templates.template_level``). Every generator keeps to the
blocks game's slots (20 boxes, ``MAX_TRIANGLES``, ``MAX_STONES``, 4 pigs) and to v0's
span (structures between x = 7.5 and 15 m).
"""

from __future__ import annotations

import numpy as np

from . import _templates
from ._blocks import STONE_RADII, TRIANGLE_LEG, roof, stone, wedge
from ._levels import MATERIALS, PIG_RADIUS, POST, SQUARE, STONE, Level
from ._templates import Template

_STONE = MATERIALS.index(STONE)
_HALF_ROOF = TRIANGLE_LEG  # a roof reaches this far either side of its tower's centre


def _material(rng: np.random.Generator) -> int:
    return int(rng.integers(3))


def _roofed_tower(rng: np.random.Generator) -> Level:
    """A tower of one to three storeys under a gable roof, a pig inside; half the time a
    second pig on the ground behind it."""
    level = Level("roofed_tower")
    x, span = float(rng.uniform(8.5, 12.0)), float(rng.uniform(0.8, 1.4))
    storeys = [_material(rng) for _ in range(int(rng.integers(1, 4)))]
    roof(level, x, level.tower(x, 0.0, span, storeys), _material(rng))
    level.pig(x, 0.0)
    if rng.random() < 0.5:
        level.pig(x + _HALF_ROOF + 0.1 + PIG_RADIUS + float(rng.uniform(0.2, 1.2)), 0.0)
    return level


def _boulder_column(rng: np.random.Generator) -> Level:
    """A column of two to four squares with a stone on top, a pig on the ground behind
    it: the stone falls the way the column is pushed."""
    level = Level("boulder_column")
    x = float(rng.uniform(8.5, 12.5))
    top = level.column(x, int(rng.integers(2, 5)), _material(rng))
    stone(level, x, top, float(rng.uniform(0.2, 0.3)), _STONE)
    level.pig(x + SQUARE / 2 + 0.1 + PIG_RADIUS + float(rng.uniform(0.0, 0.8)), 0.0)
    return level


def _rampart_at(level: Level, rng: np.random.Generator, x: float) -> float:
    """A wedge from ``x`` (its slope facing the sling), a pig behind it, a boulder behind
    the pig; returns the boulder's right edge."""
    wedge(level, x + TRIANGLE_LEG, _material(rng))
    behind = x + TRIANGLE_LEG + 0.1 + PIG_RADIUS
    level.pig(behind, 0.0)
    radius = float(rng.uniform(*STONE_RADII))
    stone(level, behind + PIG_RADIUS + 0.1 + radius, 0.0, radius, _STONE)
    return behind + PIG_RADIUS + 0.1 + 2 * radius


def _rampart(rng: np.random.Generator) -> Level:
    """One or two ramparts: a wedge, a pig behind it, a boulder behind the pig."""
    level = Level("rampart")
    x = float(rng.uniform(8.0, 9.0))
    for _ in range(int(rng.integers(1, 3))):
        x = _rampart_at(level, rng, x) + float(rng.uniform(0.6, 1.0))
    return level


def _rolling_stone(rng: np.random.Generator) -> Level:
    """A stone on the roof plank of a tower of one or two storeys, a pig on the ground
    beyond the tower and, half the time, one inside it."""
    level = Level("rolling_stone")
    x, span = float(rng.uniform(8.5, 12.0)), float(rng.uniform(0.8, 1.2))
    top = level.tower(x, 0.0, span, [_material(rng) for _ in range(int(rng.integers(1, 3)))])
    stone(level, x, top, float(rng.uniform(0.25, 0.4)), _STONE)
    level.pig(x + span / 2 + POST[0] / 2 + 0.1 + PIG_RADIUS + float(rng.uniform(0.2, 1.0)), 0.0)
    if rng.random() < 0.5:
        level.pig(x, 0.0)
    return level


def _village(rng: np.random.Generator) -> Level:
    """Held out. Two one-storey huts under gable roofs, 0.8-2 m apart, a pig in each."""
    level = Level("village")
    x = float(rng.uniform(8.5, 9.5))
    for _ in range(2):
        span = float(rng.uniform(0.8, 1.2))
        roof(level, x, level.tower(x, 0.0, span, [_material(rng)]), _material(rng))
        level.pig(x, 0.0)
        x += 2 * _HALF_ROOF + float(rng.uniform(0.8, 2.0))
    return level


def _fort(rng: np.random.Generator) -> Level:
    """Held out. A wedge in front of a roofed tower of one or two storeys, a pig inside
    the tower and a boulder on the ground behind it."""
    level = Level("fort")
    x = float(rng.uniform(8.0, 9.5))
    wedge(level, x + TRIANGLE_LEG, _material(rng))
    tower = x + TRIANGLE_LEG + 0.05 + _HALF_ROOF + float(rng.uniform(0.0, 0.5))
    span = float(rng.uniform(0.8, 1.2))
    storeys = [_material(rng) for _ in range(int(rng.integers(1, 3)))]
    roof(level, tower, level.tower(tower, 0.0, span, storeys), _material(rng))
    level.pig(tower, 0.0)
    radius = float(rng.uniform(0.25, 0.4))
    stone(level, tower + _HALF_ROOF + 0.1 + radius, 0.0, radius, _STONE)
    return level


NEW: dict[str, Template] = {
    "roofed_tower": _roofed_tower,
    "boulder_column": _boulder_column,
    "rampart": _rampart,
    "rolling_stone": _rolling_stone,
    "village": _village,
    "fort": _fort,
}
"""The six templates with the new blocks: four to train on, then two held out."""

TEMPLATES: dict[str, Template] = {**_templates.TEMPLATES, **NEW}
"""Every template of the blocks game by name: v0's ten, then the six new ones."""

SPLITS: dict[str, tuple[str, ...]] = {
    "train": (*_templates.SPLITS["train"], "roofed_tower", "boulder_column", "rampart",
              "rolling_stone"),
    "held-out": (*_templates.SPLITS["held-out"], "village", "fort"),
    "all": tuple(TEMPLATES),
}  # fmt: skip
"""The blocks game's fixed split: v0's train templates and four new ones to train on;
v0's held-out templates and two new ones held out; all of them."""
