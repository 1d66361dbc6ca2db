"""Slingshot2DBlocks-v0 (``envs/slingshot_blocks.py``, ``envs/_blocks.py``): triangles and round
stones among the boxes. Levels fit the slots without overlap and stand as built (a roof
on a tower, a stone on a column, a boulder behind a wedge); the new blocks take their
material's mass from their area; the observation reads them where the table says; a
bird breaks them; Slingshot2D-v0 is unchanged beside it. The Gymnasium and SB3 checkers,
determinism, vector = single and pixels run on it in ``test_envs.py`` and
``test_env_pixels.py``."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from impulse2d.envs import _blocks, _levels
from impulse2d.envs._levels import MATERIALS, PIG_RADIUS, Level
from impulse2d.envs.slingshot import DT, FEATURES, MAX_BLOCKS, MAX_PIGS, slot_positions
from impulse2d.envs.slingshot_blocks import STONES_FROM, TRIANGLES_FROM, SlingshotBlocksGame

LEG = _blocks.TRIANGLE_LEG


def _game(level: str | Level) -> SlingshotBlocksGame:
    """A one-world blocks game playing ``level`` (a name, or a level given through the
    ``_pick_level`` hook)."""
    game = SlingshotBlocksGame(1, level=level if isinstance(level, str) else "hut")
    if isinstance(level, Level):
        game._pick_level = lambda rng: level
    game.seed([0], [0])
    game.reset([0])
    return game


def _corners(x: float, y: float, angle: float) -> np.ndarray:
    """A triangle's corners (3, 2) in the world, from its centroid and turn."""
    local = np.array(_blocks.triangle_vertices()) - LEG / 3
    c, s = math.cos(angle), math.sin(angle)
    return np.array([x, y]) + local @ np.array([[c, s], [-s, c]])


def _extents(level: Level) -> list[tuple[float, float, float, float]]:
    """Every body's box (left, right, bottom, top), m: boxes, triangles, stones, pigs."""
    found = [(x - w / 2, x + w / 2, y - h / 2, y + h / 2) for x, y, w, h, _ in level.blocks]
    for x, y, angle, _ in level.triangles:
        (left, bottom), (right, top) = (ends := _corners(x, y, angle)).min(0), ends.max(0)
        found.append((left, right, bottom, top))
    round_ = [(x, y, r) for x, y, r, _ in level.stones] + [
        (x, y, PIG_RADIUS) for x, y in level.pigs
    ]
    return found + [(x - r, x + r, y - r, y + r) for x, y, r in round_]


def test_a_triangles_centroid_and_turns():
    """Turned by 0 the right angle is bottom left; by pi/2 bottom right, the slope facing
    the sling; a roof is two of them back to back, its peak LEG above its floor."""
    level = Level("roof")
    peak = _blocks.roof(level, 10.0, 1.0, 0)
    left, right = (_corners(x, y, a) for x, y, a, _ in level.triangles)
    np.testing.assert_allclose(left[0], (10.0 - _levels.GAP / 2, 1.0 + _levels.GAP), atol=1e-12)
    np.testing.assert_allclose(right[0], (10.0 + _levels.GAP / 2, 1.0 + _levels.GAP), atol=1e-12)
    assert left[:, 0].max() == pytest.approx(10.0 - _levels.GAP / 2)  # back to back
    assert right[:, 0].min() == pytest.approx(10.0 + _levels.GAP / 2)
    assert max(left[:, 1].max(), right[:, 1].max()) == pytest.approx(peak)
    assert peak == pytest.approx(1.0 + _levels.GAP + LEG)


@pytest.mark.parametrize("seed", range(0, 400, 50))
def test_generated_levels_fit_the_slots_without_overlap(seed):
    for k in range(seed, seed + 50):
        level = _blocks.random_blocks_level(np.random.default_rng(k), MAX_BLOCKS, MAX_PIGS)
        assert 1 <= len(level.pigs) <= MAX_PIGS and len(level.blocks) <= MAX_BLOCKS
        assert len(level.triangles) <= _blocks.MAX_TRIANGLES
        assert len(level.stones) <= _blocks.MAX_STONES
        boxes = _extents(level)
        for i, a in enumerate(boxes):
            assert a[2] >= -1e-9 and 7.0 < a[0] and a[1] < 16.0, (k, a)
            for b in boxes[:i]:
                apart = a[1] <= b[0] + 1e-9 or b[1] <= a[0] + 1e-9
                assert apart or a[3] <= b[2] + 1e-9 or b[3] <= a[2] + 1e-9, (k, a, b)


def test_the_generator_uses_every_new_block():
    levels = [_blocks.random_blocks_level(np.random.default_rng(k), MAX_BLOCKS, MAX_PIGS)
              for k in range(200)]  # fmt: skip
    assert sum(len(level.triangles) > 0 for level in levels) > 40
    assert sum(len(level.stones) > 0 for level in levels) > 40
    angles = {a for level in levels for _, _, a, _ in level.triangles}
    assert angles == {_blocks.FACING_LEFT, _blocks.FACING_RIGHT}


def _stands(game: SlingshotBlocksGame, seconds: float = 3.0) -> float:
    """Wake every body, leave it ``seconds`` without a bird, and check nothing is
    damaged or destroyed; returns the largest drift (m) of a body in the level."""
    health, alive = game.health.copy(), game.alive.copy()
    start = game.world.array("pose").copy()
    game.world.gravity = game.world.gravity  # setting gravity wakes every body
    for _ in range(round(seconds / DT)):
        game.world.step(DT)
    np.testing.assert_array_equal(game.alive, alive)
    np.testing.assert_array_equal(game.health, health)
    pose, slots = game.world.array("pose"), game._targets[alive[0]]
    return float(np.hypot(*(pose[:2, 0, slots] - start[:2, 0, slots])).max())


@pytest.mark.parametrize("name", ["hut", "boulder", "ramparts"])
def test_handmade_blocks_levels_stand_as_built(name):
    """Roofs on towers, a stone on a table, a boulder behind a wedge: woken and left 3 s,
    the 2 mm gaps close below the damage speed and nothing moves more than 3 cm."""
    assert _stands(_game(name)) < 0.03


@pytest.mark.parametrize("seed", [3, 11, 17, 29, 40, 57])
def test_generated_blocks_levels_stand_as_built(seed):
    level = _blocks.random_blocks_level(np.random.default_rng(seed), MAX_BLOCKS, MAX_PIGS)
    assert _stands(_game(level)) < 0.03


def test_new_blocks_take_their_materials_mass_and_health():
    level = Level("pieces")
    _blocks.wedge(level, 9.0, 0)
    _blocks.triangle(level, 10.0, _levels.GAP, _blocks.FACING_RIGHT, 2)
    _blocks.stone(level, 12.0, 0.0, 0.3, 1)
    level.pig(13.0, 0.0)
    game = _game(level)
    triangles = game.blocks[MAX_BLOCKS : MAX_BLOCKS + 2]
    stone = game.blocks[MAX_BLOCKS + _blocks.MAX_TRIANGLES]
    for body, (_, _, _, m) in zip(triangles, level.triangles, strict=True):
        assert body.mass == pytest.approx(MATERIALS[m].density * LEG * LEG / 2)
        assert body.friction == MATERIALS[m].friction and body.health == MATERIALS[m].health
    assert stone.radius == 0.3
    assert stone.mass == pytest.approx(MATERIALS[1].density * math.pi * 0.09)
    # The triangle's moment is the geometry's: a right triangle with legs L about its
    # centroid has I = m L^2 / 9 (the two legs' second moments, L^4 / 36 each, over L^2 / 2).
    assert triangles[0].moment == pytest.approx(triangles[0].mass * LEG * LEG / 9)
    in_level = game._in_level[0]
    assert in_level[TRIANGLES_FROM : TRIANGLES_FROM + 2].all()
    assert not in_level[TRIANGLES_FROM + 2 : STONES_FROM].any()
    assert in_level[STONES_FROM] and not in_level[STONES_FROM + 1 :].any()


def test_the_observation_reads_the_new_blocks_where_the_table_says():
    env = gym.make("Slingshot2DBlocks-v0", level="ramparts")
    obs, _ = env.reset(seed=0)
    level = _blocks.HANDMADE_BLOCKS["ramparts"]()
    assert obs.shape == ((MAX_PIGS + MAX_BLOCKS + 10) * FEATURES + 1,) == (307,)
    assert env.observation_space.contains(obs)
    slots = obs[:-1].reshape(-1, FEATURES)
    x, y = slot_positions(slots)
    for k, (tx, ty, angle, material) in enumerate(level.triangles):
        row = slots[TRIANGLES_FROM + k]
        assert row[0] == 1 and row[1] == 1 and row[2] == pytest.approx(material / 2)
        assert (x[TRIANGLES_FROM + k], y[TRIANGLES_FROM + k]) == pytest.approx((tx, ty), abs=1e-5)
        assert row[5] == pytest.approx(angle / math.pi, abs=1e-6)
    sx, sy, radius, material = level.stones[0]
    row = slots[STONES_FROM]
    assert row[2] == pytest.approx(material / 2) and row[6] == row[7] == pytest.approx(radius)
    assert (x[STONES_FROM], y[STONES_FROM]) == pytest.approx((sx, sy), abs=1e-5)
    assert not slots[TRIANGLES_FROM + len(level.triangles) : STONES_FROM].any()
    assert not slots[STONES_FROM + 1 :].any()


def test_a_bird_breaks_an_ice_roof():
    """A bird flung flat and fast at the hut (4 kg at 20 m/s, 0-14 degrees up) breaks
    its ice roof (12 N s of health a triangle) whichever of these angles it takes; a
    shot that falls short (the slowest) leaves the roof whole."""
    env = gym.make("Slingshot2DBlocks-v0", level="hut", num_birds=3)
    env.reset(seed=0)
    game = env.unwrapped.game
    roof = game._in_level[0, TRIANGLES_FROM:STONES_FROM]
    assert roof.sum() == 2
    broken = []
    for angle, speed in [(-1.0, 1.0), (-0.95, 1.0), (-0.9, 1.0), (-0.85, 1.0), (-1.0, -1.0)]:
        state = env.unwrapped.save_state()
        env.step(np.array([angle, speed], np.float32))
        broken.append(int((~game.alive[0, TRIANGLES_FROM:STONES_FROM] & roof).sum()))
        env.unwrapped.restore_state(state)
    assert min(broken[:4]) >= 1 and broken[4] == 0


def test_slingshot2d_v0_is_unchanged_beside_it():
    """v0's slots and observation are v0's, and it refuses the new blocks."""
    env = gym.make("Slingshot2D-v0", level="handmade")
    assert env.observation_space.shape == ((MAX_PIGS + MAX_BLOCKS) * FEATURES + 1,)
    level = Level("wedge")
    _blocks.wedge(level, 9.0, 0)
    level.pig(10.0, 0.0)
    game = env.unwrapped.game
    game._pick_level = lambda rng: level
    with pytest.raises(ValueError, match="triangles or stones: they need Slingshot2DBlocks"):
        game.reset([0])
    assert "hut" not in _levels.HANDMADE
    with pytest.raises(ValueError, match="level"):
        gym.make("Slingshot2D-v0", level="hut")
