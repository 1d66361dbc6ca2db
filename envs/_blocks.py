"""Slingshot2DBlocks-v0 levels: the v0 levels' boxes with triangles and round stones, as Angry
Birds and Phy-Q build (roofs, wedges, boulders), hand-made and generated.

A triangle is a right triangle with legs ``TRIANGLE_LEG``: turned by 0 its right angle is
at the bottom left and its slope faces right; turned by pi/2 the right angle is at the
bottom right and the slope faces left, towards the sling. Two side by side, back to back,
make a gable roof ``2 TRIANGLE_LEG`` wide and ``TRIANGLE_LEG`` high. Stones are discs of
any material (mostly stone). Materials are v0's: ice is Angry Birds' glass.

Blocks are placed ``GAP`` apart, as in v0, and everything starts asleep.
"""

from __future__ import annotations

import math

import numpy as np

from ._levels import GAP, HANDMADE, ICE, MATERIALS, PIG_RADIUS, SQUARE, STONE, WOOD, Level

TRIANGLE_LEG = 0.8  # m
STONE_RADII = (0.2, 0.45)  # m: the generator's range of stone radii
MAX_TRIANGLES = 6
MAX_STONES = 4
_ICE, _WOOD, _STONE = (MATERIALS.index(m) for m in (ICE, WOOD, STONE))
FACING_RIGHT, FACING_LEFT = 0.0, math.pi / 2  # a triangle's turns (rad)


def triangle_vertices() -> list[tuple[float, float]]:
    """The triangle's corners in its own frame, counter-clockwise, right angle first (the
    body centres them on their centroid)."""
    return [(0.0, 0.0), (TRIANGLE_LEG, 0.0), (0.0, TRIANGLE_LEG)]


def triangle(level: Level, corner_x: float, corner_y: float, angle: float, material: int) -> None:
    """A triangle with its right angle at ``(corner_x, corner_y)``, turned by ``angle``.
    Its centroid is a third of each leg from that corner: ``corner + R(angle) (L/3, L/3)``."""
    third = TRIANGLE_LEG / 3
    c, s = math.cos(angle), math.sin(angle)
    level.triangles.append(
        (corner_x + (c - s) * third, corner_y + (s + c) * third, angle, material)
    )


def roof(level: Level, x: float, base: float, material: int) -> float:
    """A gable of two triangles centred on ``x`` on a floor at height ``base``; returns
    its peak's height."""
    triangle(level, x - GAP / 2, base + GAP, FACING_LEFT, material)
    triangle(level, x + GAP / 2, base + GAP, FACING_RIGHT, material)
    return base + GAP + TRIANGLE_LEG


def wedge(level: Level, x: float, material: int) -> None:
    """A triangle on the ground whose slope faces the sling, its upright leg at ``x``."""
    triangle(level, x, GAP, FACING_LEFT, material)


def stone(level: Level, x: float, floor: float, radius: float, material: int) -> None:
    """A round stone resting on a floor at height ``floor``."""
    level.stones.append((x, floor + radius + GAP, radius, material))


def _hut() -> Level:
    level = Level("hut")
    top = level.tower(9.5, 0.0, 1.2, [_WOOD])
    roof(level, 9.5, top, _ICE)
    level.pig(9.5, 0.0)
    level.pig(11.2, 0.0)
    return level


def _boulder() -> Level:
    level = Level("boulder")
    top = level.tower(10.0, 0.0, 1.0, [_WOOD])
    stone(level, 10.0, top, 0.35, _STONE)
    level.pig(10.0, 0.0)
    level.pig(11.3, 0.0)
    return level


def _ramparts() -> Level:
    level = Level("ramparts")
    wedge(level, 8.9, _STONE)
    level.column(9.2, 3, _WOOD)
    level.pig(9.9, 0.0)
    stone(level, 10.7, 0.0, 0.3, _ICE)
    top = level.tower(12.5, 0.0, 1.2, [_ICE, _WOOD])
    roof(level, 12.5, top, _WOOD)
    level.pig(12.5, 0.0)
    return level


HANDMADE_BLOCKS = {**HANDMADE, **{make().name: make for make in (_hut, _boulder, _ramparts)}}
"""Slingshot2DBlocks' hand-made levels by name: v0's five, then three with the new blocks."""


def random_blocks_level(rng: np.random.Generator, max_blocks: int, max_pigs: int) -> Level:
    """A procedural Slingshot2DBlocks level from ``rng``: one to three structures left to
    right from x = 8-10 m, as ``_levels.random_level`` builds them, and with the new
    blocks: towers may take a roof (their pig then inside), columns a stone on top, and
    a fourth kind, a rampart, is a wedge with a pig behind it and a boulder behind it. Keeps to the
    slots (``max_blocks`` boxes, ``MAX_TRIANGLES``, ``MAX_STONES``, ``max_pigs``)."""
    level = Level("random")
    x = float(rng.uniform(8.0, 10.0))
    for _ in range(int(rng.integers(1, 4))):
        built = _structure(level, rng, x, max_blocks)
        if built is None:
            break
        spots, right = built
        if len(level.pigs) < max_pigs:
            level.pig(*spots[int(rng.integers(len(spots)))])
        x = right + float(rng.uniform(1.0, 2.5))
        if x > 13.0:  # the widest structure (1.8 m) then still ends before 15 m
            break
    if not level.pigs:
        level.pig(x, 0.0)
    return level


def _structure(level: Level, rng: np.random.Generator, x: float, max_blocks: int):
    """One structure with its left side at about ``x``: ``(pig spots, right edge)``, or
    None when the slots it needs are taken."""
    kind, blocks = int(rng.integers(4)), len(level.blocks)
    triangles, stones = len(level.triangles), len(level.stones)
    material = int(rng.integers(3))
    if kind == 0:  # a tower, roofed half the time (its inside fits a pig)
        storeys, span = int(rng.integers(1, 4)), float(rng.uniform(0.8, 1.4))
        if blocks + 3 * storeys > max_blocks:
            return None
        x += max(span / 2, TRIANGLE_LEG)
        top = level.tower(x, 0.0, span, [int(m) for m in rng.integers(3, size=storeys)])
        spots = [(x, top), (x, 0.0)]
        if triangles + 2 <= MAX_TRIANGLES and rng.random() < 0.5:
            roof(level, x, top, material)
            spots = [(x, 0.0)]
        return spots, x + TRIANGLE_LEG
    if kind == 1:  # a pyramid with a pig on top
        rows = int(rng.integers(2, 4))
        if blocks + rows * (rows + 1) // 2 > max_blocks:
            return None
        x += rows * SQUARE / 2
        return [(x, level.pyramid(x, rows, material))], x + rows * SQUARE / 2
    if kind == 2:  # a column, a stone on it half the time, a pig on it or behind it
        count = int(rng.integers(2, 5))
        if blocks + count > max_blocks:
            return None
        top = level.column(x, count, material)
        behind = x + SQUARE / 2 + 0.1 + PIG_RADIUS
        if stones < MAX_STONES and rng.random() < 0.5:
            stone(level, x, top, SQUARE / 2, _STONE)
            return [(behind, 0.0)], behind + PIG_RADIUS
        return [(behind, 0.0), (x, top)], behind + PIG_RADIUS
    # A rampart: a wedge, a pig behind it, a boulder behind the pig.
    if triangles + 1 > MAX_TRIANGLES or stones + 1 > MAX_STONES:
        return None
    x += TRIANGLE_LEG
    wedge(level, x, material)
    radius = float(rng.uniform(*STONE_RADII))
    behind = x + 0.1 + PIG_RADIUS
    stone(level, behind + PIG_RADIUS + 0.1 + radius, 0.0, radius, _STONE)
    return [(behind, 0.0)], behind + PIG_RADIUS + 0.1 + 2 * radius
