"""Slingshot2DBlocks-v0: Slingshot2D with triangles and round stones among the boxes.

A game of its own id rather than a ``Slingshot2D-v1``: its slots, and so its observation,
grow, while Slingshot2D-v0 stays a current game, bit for bit as it was (its agents and
held-out results stand; Gymnasium would call a v0 beside a v1 out of date). The rules,
actions, rewards and materials are Slingshot2D-v0's; see ``Slingshot2DBlocksEnv``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import impulse2d as p2

from . import _block_templates, _blocks, _levels
from ._levels import MATERIALS
from .callshot import SlingshotCallShot, SlingshotCallShotVector
from .slingshot import (
    MAX_BLOCKS,
    MAX_PIGS,
    Slingshot2DEnv,
    Slingshot2DVectorEnv,
    SlingshotGame,
)

LEVELS = ("random", "handmade", "templates", *_blocks.HANDMADE_BLOCKS)
TRIANGLES_FROM = MAX_PIGS + MAX_BLOCKS  # the first triangle's observation slot
STONES_FROM = TRIANGLES_FROM + _blocks.MAX_TRIANGLES  # the first stone's


class SlingshotBlocksGame(SlingshotGame):
    """Slingshot with triangles and stones on ``batch_size`` worlds. Slots: the bird, ``MAX_PIGS``
    pigs, ``MAX_BLOCKS`` boxes, ``MAX_TRIANGLES`` triangles, ``MAX_STONES`` stones; a
    level uses the first of each kind and leaves the rest disabled (``SlingshotGame``).
    Every triangle slot has the same outline (an outline is the same in every world); a
    stone's radius is set per level."""

    level_names = LEVELS
    handmade = _blocks.HANDMADE_BLOCKS
    template_library, template_splits = _block_templates.TEMPLATES, _block_templates.SPLITS

    @staticmethod
    def _add_blocks(world: p2.World) -> list:
        boxes = SlingshotGame._add_blocks(world)
        vertices = _blocks.triangle_vertices()
        triangles = [world.add(p2.Polygon(vertices=vertices)) for _ in range(_blocks.MAX_TRIANGLES)]
        stones = [world.add(p2.Circle()) for _ in range(_blocks.MAX_STONES)]
        return [*boxes, *triangles, *stones]

    @staticmethod
    def _random_level(rng: np.random.Generator) -> _levels.Level:
        return _blocks.random_blocks_level(rng, MAX_BLOCKS, MAX_PIGS)

    def _place_blocks(self, level: _levels.Level, max_health, in_level, material) -> None:
        """The boxes as v0 places them, then the triangles (mass: density times the
        area ``L^2 / 2``) and the stones (density times ``pi r^2``)."""
        self._place_boxes(level, max_health, in_level, material)
        blocks = self._template_bodies[2]
        leg = _blocks.TRIANGLE_LEG
        for i, (x, y, angle, kind_index) in enumerate(level.triangles):
            block = blocks[MAX_BLOCKS + i]
            block.mass = MATERIALS[kind_index].density * leg * leg / 2
            block.angle = angle
            self._set_block(block, TRIANGLES_FROM + i, kind_index, (x, y), max_health,
                            in_level, material)  # fmt: skip
        for i, (x, y, radius, kind_index) in enumerate(level.stones):
            block = blocks[MAX_BLOCKS + _blocks.MAX_TRIANGLES + i]
            block.radius = radius
            block.mass = MATERIALS[kind_index].density * np.pi * radius * radius
            self._set_block(block, STONES_FROM + i, kind_index, (x, y), max_health,
                            in_level, material)  # fmt: skip


class Slingshot2DBlocksEnv(Slingshot2DEnv):
    """Slingshot2DBlocks-v0: Slingshot2D-v0 (``Slingshot2DEnv``: its rules, actions, rewards,
    materials, arguments and saving) with triangles and round stones among the boxes.

    ## Starting State
    As Slingshot2D-v0, with more blocks: triangles (right triangles with 0.8 m legs, as gable roofs
    and wedges) and round stones (radius 0.2-0.45 m), in v0's materials (ice is Angry
    Birds' glass). `level="handmade"` draws from v0's five hand-made levels and
    `"hut"`, `"boulder"` and `"ramparts"`; generated levels (`level="random"`) add
    roofs to towers, stones to columns, and ramparts (a wedge, a pig, a boulder):
    `impulse2d.envs._blocks`. `level="templates"` plays v0's ten templates and six with
    the new blocks (`impulse2d.envs._block_templates`: a roofed tower, a boulder on a
    column, ramparts, a rolling stone; held out, a village of roofed huts and a fort),
    split as v0's are: `templates="train"` (default) is v0's seven and four new ones,
    `"held-out"` v0's three and `village` and `fort`.

    ## Observation Space
    v0's nine numbers for each of 34 slots, then the birds left (307 numbers): 4 pigs
    (slots 0-3), 20 boxes (4-23), 6 triangles (24-29; their half width and height are
    the radius of the circle inside them, 0.117 m) and 4 stones (30-33; half sizes: the
    radius). Unused slots are zeros.

    ## Version History
    * v0: first version: Slingshot2D-v0 with triangles and round stones among the
      blocks (more slots, so a longer observation).
    """

    game_class = SlingshotBlocksGame


class Slingshot2DBlocksVectorEnv(Slingshot2DVectorEnv):
    """``num_envs`` Slingshot2DBlocks-v0 worlds stepped in one batched engine (see
    ``Slingshot2DBlocksEnv``)."""

    game_class = SlingshotBlocksGame


def make_call_shot(**kwargs: Any) -> SlingshotCallShot:
    """``Slingshot2DBlocksCallShot-v0``'s entry point: the blocks game with the
    call-shot action (``impulse2d.envs.callshot``)."""
    return SlingshotCallShot(Slingshot2DBlocksEnv(**kwargs))


def make_call_shot_vector(**kwargs: Any) -> SlingshotCallShotVector:
    return SlingshotCallShotVector(Slingshot2DBlocksVectorEnv(**kwargs))
