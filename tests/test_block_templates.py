"""Slingshot2DBlocks-v0's level templates (``envs/_block_templates.py``): the six new
templates' levels fit the blocks game's slots without overlap and stand as built, the
game plays them by its own split (v0's templates and split unchanged), and a template
of the blocks game is refused by name in v0."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from impulse2d.envs import _block_templates, _blocks, _templates
from impulse2d.envs.slingshot import MAX_BLOCKS, MAX_PIGS
from test_slingshot_blocks import _extents, _game, _stands

NEW = list(_block_templates.NEW)


@pytest.mark.parametrize("name", NEW)
def test_every_new_template_fits_the_slots_without_overlap(name):
    uses_triangles = uses_stones = 0
    for seed in range(200):
        level = _block_templates.TEMPLATES[name](np.random.default_rng(seed))
        assert level.name == name
        assert 1 <= len(level.pigs) <= MAX_PIGS and len(level.blocks) <= MAX_BLOCKS
        assert len(level.triangles) <= _blocks.MAX_TRIANGLES
        assert len(level.stones) <= _blocks.MAX_STONES
        uses_triangles += bool(level.triangles)
        uses_stones += bool(level.stones)
        boxes = _extents(level)
        for i, a in enumerate(boxes):
            assert a[2] >= -1e-9 and 7.5 < a[0] and a[1] < 15.0, (seed, a)  # v0's span
            for b in boxes[:i]:
                apart = a[1] <= b[0] + 1e-9 or b[1] <= a[0] + 1e-9
                assert apart or a[3] <= b[2] + 1e-9 or b[3] <= a[2] + 1e-9, (seed, a, b)
    assert uses_triangles + uses_stones >= 200  # every level has a new block


@pytest.mark.parametrize("name", NEW)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_new_template_levels_stand_as_built(name, seed):
    """Woken and left 3 s without a bird: no damage, no body drifts 3 cm (stones on
    columns and roof planks, roofs on towers, boulders behind wedges)."""
    level = _block_templates.TEMPLATES[name](np.random.default_rng(seed))
    assert _stands(_game(level)) < 0.03


def test_the_blocks_split_extends_v0s_which_is_unchanged():
    assert _templates.SPLITS["train"] == (
        "tower", "bunker", "pyramid", "shelter", "perch", "twin", "pyramids",
    )  # fmt: skip
    assert _templates.SPLITS["held-out"] == ("wall", "castle", "stairs")
    train, held_out = _block_templates.SPLITS["train"], _block_templates.SPLITS["held-out"]
    assert train[:7] == _templates.SPLITS["train"] and held_out[:3] == _templates.SPLITS["held-out"]
    assert set(train[7:]) | set(held_out[3:]) == set(NEW)
    assert not set(train) & set(held_out)
    assert set(train) | set(held_out) == set(_block_templates.TEMPLATES)
    assert _block_templates.SPLITS["all"] == tuple(_block_templates.TEMPLATES)


def test_the_blocks_game_deals_its_held_out_templates_by_level_seed():
    env = gym.make("Slingshot2DBlocks-v0", level="templates", templates="held-out", num_birds=1)
    game = env.unwrapped.game
    dealt = []
    picked = game._pick_level
    game._pick_level = lambda rng: dealt.append(picked(rng)) or dealt[-1]
    for seed in range(40):
        env.reset(seed=seed)
    names = {level.name for level in dealt}
    assert names == {"wall", "castle", "stairs", "village", "fort"}
    level = _templates.template_level(_block_templates.SPLITS["held-out"], 4,
                                      _block_templates.TEMPLATES)  # fmt: skip
    expected = _block_templates.TEMPLATES["fort"](np.random.default_rng(4))
    assert level.name == "fort" and level.triangles == expected.triangles
    assert level.stones == expected.stones and level.pigs == expected.pigs


def test_a_blocks_template_in_v0_is_refused_by_name():
    with pytest.raises(ValueError, match=r"templates must be a split .* 'village'"):
        gym.make("Slingshot2D-v0", level="templates", templates=["tower", "village"])
    env = gym.make("Slingshot2DBlocks-v0", level="templates", templates=["village"])
    assert env.unwrapped.game.templates == ("village",)
