"""Slingshot2D's level templates (``envs/_templates.py``): every template's levels fit the
game's slots without overlaps and stand as built, level seeds map to templates as
documented, the split is fixed and disjoint, and bad template choices are refused by name."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from impulse2d.envs import _templates
from impulse2d.envs.planner import SlingshotPlanner
from impulse2d.envs.slingshot import MAX_BLOCKS, MAX_PIGS, PIG_RADIUS, SlingshotGame


def _boxes(level) -> list[tuple[float, float, float, float]]:
    """Every body's extent (left, right, bottom, top), m: blocks, then pigs as squares."""
    blocks = [(x - w / 2, x + w / 2, y - h / 2, y + h / 2) for x, y, w, h, _ in level.blocks]
    pigs = [(x - PIG_RADIUS, x + PIG_RADIUS, y - PIG_RADIUS, y + PIG_RADIUS) for x, y in level.pigs]
    return blocks + pigs


@pytest.mark.parametrize("name", list(_templates.TEMPLATES))
def test_every_level_fits_the_slots_without_overlap(name):
    for seed in range(300):
        level = _templates.TEMPLATES[name](np.random.default_rng(seed))
        assert 1 <= len(level.pigs) <= MAX_PIGS and len(level.blocks) <= MAX_BLOCKS
        boxes = _boxes(level)
        for i, a in enumerate(boxes):
            assert a[2] >= -1e-9 and 7.5 < a[0] and a[1] < 15.0  # on the ground, in range
            for b in boxes[:i]:
                apart = a[1] <= b[0] + 1e-9 or b[1] <= a[0] + 1e-9
                assert apart or a[3] <= b[2] + 1e-9 or b[3] <= a[2] + 1e-9, (seed, a, b)


@pytest.mark.parametrize("name", list(_templates.TEMPLATES))
def test_template_levels_stand_without_damage(name):
    """A harmless launch (the slowest, flat: it lands 3 m from the sling) destroys
    nothing: every level stands as built, whatever its draw."""
    env = gym.make("Slingshot2D-v0", level="templates", templates=[name], num_birds=1)
    for seed in range(4):
        env.reset(seed=seed)
        _, reward, _, _, info = env.step(np.array([-1.0, -1.0], np.float32))
        assert reward == 0 and info["pigs_left"] >= 1


def test_level_seed_k_plays_template_k_mod_n_from_its_own_generator():
    names = _templates.SPLITS["train"]
    for seed in (0, 6, 7, 1_000_003):
        level = _templates.template_level(names, seed)
        expected = _templates.TEMPLATES[names[seed % 7]](np.random.default_rng(seed))
        assert level.name == names[seed % 7] and level.blocks == expected.blocks
        assert level.pigs == expected.pigs
    game = SlingshotGame(1, level="templates", templates="held-out", num_levels=1, start_level=5)
    game.seed([0], [0])
    game.reset([0])  # level seed 5 of (wall, castle, stairs): 5 mod 3 = 2, the stairs
    level = _templates.template_level(("wall", "castle", "stairs"), 5)
    assert level.name == "stairs" and game.alive[0, :MAX_PIGS].sum() == len(level.pigs) == 2
    for pig, spot in zip(game.pigs, level.pigs, strict=False):
        np.testing.assert_allclose(pig.position, spot)


def test_the_split_is_fixed_and_disjoint():
    train, held_out = _templates.SPLITS["train"], _templates.SPLITS["held-out"]
    assert len(train) == 7 and len(held_out) == 3 and not set(train) & set(held_out)
    assert set(train) | set(held_out) == set(_templates.TEMPLATES) == set(_templates.SPLITS["all"])


def test_levels_deal_only_the_chosen_templates():
    env = gym.make_vec("Slingshot2D-v0", num_envs=12, vectorization_mode="vector_entry_point",
                       level="templates", templates="held-out")  # fmt: skip
    env.reset(seed=0)
    game = env.unwrapped.game
    dealt = []
    picked = game._pick_level
    game._pick_level = lambda rng: dealt.append(picked(rng)) or dealt[-1]
    env.reset(seed=1)
    assert len(dealt) == 12 and {level.name for level in dealt} == {"wall", "castle", "stairs"}


def test_the_planner_plays_template_levels():
    env = gym.make("Slingshot2D-v0", level="templates", templates=["tower"], num_birds=1)
    obs, _ = env.reset(seed=3)
    planner = SlingshotPlanner(env, candidates=32)
    assert planner.table.templates == ("tower",)
    _, _, _, _, info = env.step(planner(obs))
    assert info["cleared"]  # a lone tower falls to the best of 32 launches


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"templates": "easy"}, "templates must be a split .* got 'easy'"),
        ({"templates": []}, "templates must be a split .* got \\[\\]"),
        ({"templates": ["tower", "moon"]}, "templates must be a split .* 'moon'"),
        ({"templates": ["tower", "tower"]}, "templates must name each template once"),
        ({"templates": 3}, "templates must be a split .* got 3"),
        ({"level": "random", "templates": "train"}, "templates needs level='templates'"),
        ({"start_level": 4}, "start_level needs num_levels > 0"),
    ],
)
def test_bad_template_choices_are_refused_by_name(options, message):
    with pytest.raises(ValueError, match=message):
        gym.make("Slingshot2D-v0", **{"level": "templates", **options})
