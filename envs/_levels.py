"""Slingshot2D levels: materials, the hand-made levels and the procedural generator.

A level is a list of blocks (boxes of a material) and pigs (circles) standing on the ground
(y = 0) to the right of the sling (x = 0). Sizes are in metres and masses in kilograms, at a
human scale: a wooden post 0.2 x 1.0 m weighs 12 kg, a pig is 0.5 m across.

Blocks are placed 2 mm apart so that a level starts without overlaps; the game puts every
body to sleep at the start, so the structures stand exactly as built until something hits
them, and then settle by those 2 mm, too gently (about 0.2 m/s) to do damage.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Material:
    """A block material: ``density`` (kg/m^2 of the box's face), ``friction``,
    ``restitution`` and ``health`` (the impact impulse, N s, that destroys a block)."""

    name: str
    density: float
    friction: float
    restitution: float
    health: float


# Science Birds' three materials, in their order of strength. Health is in N s of impact
# impulse: a 4 kg bird at 15 m/s hitting a 12 kg wooden post head-on delivers
# (1 + e) m M / (m + M) v = 1.3 * 3 * 15 = 58 N s (e = 0.3, the larger of the two).
ICE = Material("ice", density=40.0, friction=0.3, restitution=0.1, health=12.0)
WOOD = Material("wood", density=60.0, friction=0.6, restitution=0.1, health=30.0)
STONE = Material("stone", density=150.0, friction=0.8, restitution=0.05, health=80.0)
MATERIALS = (ICE, WOOD, STONE)

PIG_RADIUS = 0.25  # m
PIG_MASS = 3.0  # kg
# A pig falling 0.5 m lands at v = sqrt(2 g h) = 3.13 m/s and takes m v (1 + e) = 11.3 N s
# (the bounce counts): just survivable.
PIG_HEALTH = 12.0  # N s
GAP = 0.002  # m between stacked blocks at the start
POST = (0.2, 1.0)  # width, height of a post (m)
PLANK_HEIGHT = 0.2  # m
SQUARE = 0.4  # m, side of a square block


@dataclass
class Level:
    """Blocks ``(x, y, width, height, material index)`` and pigs ``(x, y)``: the centres.
    Slingshot2DBlocks-v0 levels also hold ``triangles`` ``(x, y, angle, material index)`` (the
    centroid of a right triangle with ``TRIANGLE_LEG`` legs, turned by ``angle``) and
    round ``stones`` ``(x, y, radius, material index)``; v0 levels have none."""

    name: str
    blocks: list[tuple[float, float, float, float, int]] = field(default_factory=list)
    pigs: list[tuple[float, float]] = field(default_factory=list)
    triangles: list[tuple[float, float, float, int]] = field(default_factory=list)
    stones: list[tuple[float, float, float, int]] = field(default_factory=list)

    def tower(self, x: float, base: float, span: float, materials: list[int]) -> float:
        """Storeys of two posts under a plank, one per material, centred on ``x``, the first
        standing at height ``base``. Returns the height of the top plank's upper face."""
        width, height = POST
        y = base
        for material in materials:
            for side in (-1.0, 1.0):
                self.blocks.append((x + side * span / 2, y + height / 2, width, height, material))
            y += height + GAP
            self.blocks.append((x, y + PLANK_HEIGHT / 2, span + width, PLANK_HEIGHT, material))
            y += PLANK_HEIGHT + GAP
        return y

    def pyramid(self, x: float, rows: int, material: int) -> float:
        """A pyramid of square blocks, ``rows`` at the bottom, centred on ``x``; returns its
        top height."""
        y = 0.0
        for row in range(rows):
            count = rows - row
            for k in range(count):
                offset = (k - (count - 1) / 2) * (SQUARE + GAP)
                self.blocks.append((x + offset, y + SQUARE / 2, SQUARE, SQUARE, material))
            y += SQUARE + GAP
        return y

    def column(self, x: float, count: int, material: int) -> float:
        """Square blocks stacked ``count`` high on the ground at ``x``; returns the top."""
        for k in range(count):
            self.blocks.append((x, k * (SQUARE + GAP) + SQUARE / 2, SQUARE, SQUARE, material))
        return count * (SQUARE + GAP)

    def pig(self, x: float, floor: float) -> None:
        """A pig resting on a floor at height ``floor``."""
        self.pigs.append((x, floor + PIG_RADIUS + GAP))


def _table() -> Level:
    level = Level("table")
    top = level.tower(9.0, 0.0, 1.0, [1])
    level.pig(9.0, top)
    return level


def _tower() -> Level:
    level = Level("tower")
    top = level.tower(10.0, 0.0, 1.2, [1, 1, 0])
    level.pig(10.0, 0.0)
    level.pig(10.0, top)
    return level


def _fortress() -> Level:
    level = Level("fortress")
    level.column(9.0, 3, 2)
    top = level.tower(11.0, 0.0, 1.4, [2, 1])
    level.pig(11.0, 0.0)
    level.pig(11.0, top)
    level.column(13.0, 2, 0)
    level.pig(13.8, 0.0)
    return level


def _wall() -> Level:
    level = Level("wall")
    level.column(9.0, 4, 0)
    level.column(9.6, 4, 1)
    level.pig(11.0, 0.0)
    level.pig(12.0, 0.0)
    return level


def _twin_towers() -> Level:
    level = Level("twin-towers")
    for x in (9.0, 14.0):
        top = level.tower(x, 0.0, 0.8, [1, 0])
        level.pig(x, top)
    level.pyramid(11.5, 3, 2)
    return level


HANDMADE = {make().name: make for make in (_table, _tower, _fortress, _wall, _twin_towers)}
"""The hand-made levels by name, easiest first."""


def random_level(rng: np.random.Generator, max_blocks: int, max_pigs: int) -> Level:
    """A procedural level from ``rng``: one to three structures (towers of one to three
    storeys, pyramids, columns) left to right from x = 8-10 m, in random materials, with
    pigs on top of, inside or behind them; at least one pig, within the slot limits."""
    level = Level("random")
    x = float(rng.uniform(8.0, 10.0))
    for _ in range(int(rng.integers(1, 4))):
        kind = int(rng.integers(3))
        blocks = len(level.blocks)
        if kind == 0:  # a tower; its inside (span - post width >= 0.6 m) fits a pig
            storeys = int(rng.integers(1, 4))
            span = float(rng.uniform(0.8, 1.4))
            if blocks + 3 * storeys > max_blocks:
                break
            x += span / 2
            top = level.tower(x, 0.0, span, [int(m) for m in rng.integers(3, size=storeys)])
            spots = [(x, top), (x, 0.0)]
            right = x + span / 2 + POST[0]
        elif kind == 1:  # a pyramid with a pig on top
            rows = int(rng.integers(2, 4))
            if blocks + rows * (rows + 1) // 2 > max_blocks:
                break
            x += rows * SQUARE / 2
            spots = [(x, level.pyramid(x, rows, int(rng.integers(3))))]
            right = x + rows * SQUARE / 2
        else:  # a column, with a pig on it or sheltering behind it
            count = int(rng.integers(2, 5))
            if blocks + count > max_blocks:
                break
            top = level.column(x, count, int(rng.integers(3)))
            behind = x + SQUARE / 2 + 0.1 + PIG_RADIUS
            spots = [(behind, 0.0), (x, top)]
            right = behind + PIG_RADIUS
        if len(level.pigs) < max_pigs:
            level.pig(*spots[int(rng.integers(len(spots)))])
        x = right + float(rng.uniform(1.0, 2.5))
        if x > 13.0:  # the widest structure (1.6 m) then still ends before 15 m
            break
    if not level.pigs:
        level.pig(x, 0.0)
    return level
