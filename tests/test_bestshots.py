"""The best-shots call (``impulse2d.envs.bestshots``, ``Pool2DRackBestShots-v0``): every
ball into every pocket, ranked as the ghost-ball player ranks them, a blocked path
refused, the best-ranked shot the scripted player's own, and the call played on its
ghost-ball line."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import impulse2d  # noqa: F401  (registers the env ids)
from impulse2d.envs import baselines, bestshots, pool
from impulse2d.envs.pool import BALL_RADIUS, TABLE_LENGTH, TABLE_WIDTH, pockets


def _obs(*balls: tuple[float, float, float]) -> np.ndarray:
    """One Pool2D observation from (x m, y m, potted) per ball, cue ball first."""
    rows = [(x / (TABLE_LENGTH / 2), y / (TABLE_WIDTH / 2), potted) for x, y, potted in balls]
    return np.array([np.ravel(rows)], np.float32)


def test_a_straight_shot_at_a_corner_pocket_ranks_first_with_its_score():
    """Cue ball and ball on the diagonal to a corner pocket: cut 0, score 1 / (1 + reach
    + run), both paths clear; a ball in the way of another's path makes that shot blocked."""
    corner = pockets()[0][np.argmax(pockets()[0].sum(axis=1))]  # the (+x, +y) corner
    direction = corner / np.linalg.norm(corner)
    ball = 0.3 * direction
    obs = _obs((0.0, 0.0, 0), (*ball, 0))
    shot = bestshots.best_shots(obs)
    assert shot["valid"][0, 0] and shot["sin"][0, 0] == pytest.approx(0.0, abs=1e-5)
    run = np.linalg.norm(corner - ball)
    reach = np.linalg.norm(ball) - 2 * BALL_RADIUS
    assert shot["score"][0, 0] == pytest.approx(1 / (1 + reach + run), rel=1e-5)
    assert shot["ball"][0, 0] == 1 and np.allclose(shot["pocket_xy"][0, 0], corner)
    # a second ball halfway along the first one's run blocks that shot
    blocker = ball + 0.5 * (corner - ball)
    blocked = bestshots.table_shots(_obs((0.0, 0.0, 0), (*ball, 0), (*blocker, 0)))
    k = list(pockets()[0][:, 0] * 10 + pockets()[0][:, 1]).index(corner[0] * 10 + corner[1])
    assert blocked["clear_ball"][0, k] < 1.0 and not blocked["valid"][0, k]


def test_potted_balls_are_never_offered_before_balls_on_the_table():
    obs = _obs((-0.5, 0.0, 0), (0.2, 0.1, 1), (0.4, -0.2, 0))
    shot = bestshots.best_shots(obs)
    assert (shot["ball"][0] == 2).all()  # six pockets of ball 2, the one on the table


@pytest.mark.parametrize("seed", range(12))
def test_the_best_ranked_clear_shot_is_the_ghost_ball_players(seed):
    """On random tables (and the racks of the game's own resets), rank 1, when clear, is
    the shot the scripted player takes: the same ball, and the same aim."""
    game = pool.PoolGame(1, num_balls=int(np.random.default_rng(seed).integers(1, 16)),
                         layout="random")  # fmt: skip
    game.seed([0], [seed])
    game.reset([0])
    row = game.observe()
    scripted = baselines.pool_shots(row[0])
    shot = bestshots.best_shots(row)
    assert bool(shot["valid"][0, 0]) == bool(scripted)
    if scripted:
        score, aim, _, ball = max(scripted, key=lambda s: s[0])
        assert shot["ball"][0, 0] == ball and shot["score"][0, 0] == pytest.approx(score, rel=1e-9)
        call = np.zeros((1, 8))
        call[0, 0] = 1.0
        angle = bestshots.best_shot_actions(call, row)[0, 0] * np.pi
        assert angle == pytest.approx(np.arctan2(aim[1], aim[0]), abs=1e-9)
        # the clear shots come first, best first
        valid, score_row = shot["valid"][0], shot["score"][0]
        assert (np.diff(valid.astype(int)) <= 0).all()
        assert (np.diff(score_row[valid]) <= 1e-12).all()
        assert valid.sum() == min(len(scripted), bestshots.SHOTS)


def test_the_id_offers_the_best_shots_and_plays_the_rack():
    env = gym.make("Pool2DRackBestShots-v0")
    obs, _ = env.reset(seed=4)
    assert obs.shape == (48 + bestshots.FEATURES,) and env.observation_space.contains(obs)
    expected = bestshots.best_shot_features(obs[None, :48])[0]
    np.testing.assert_array_equal(obs[48:], expected)


def _potted_per_shot(rank: int) -> float:
    """Eight racks played to the end calling the shot of ``rank`` (0 best) softly."""
    venv = gym.make_vec("Pool2DRackBestShots-v0", 8, vectorization_mode="vector_entry_point")
    venv.reset(seed=10)
    call = np.zeros((8, 8), np.float32)  # the others' preferences 0, no trim
    call[:, rank], call[:, 7] = 1.0, -0.6
    done, potted, shots = np.zeros(8, bool), 0, 0
    while not done.all():
        _, _, terminated, truncated, info = venv.step(call)
        potted += int(info["potted"][~done].sum())
        shots += int((~done).sum())
        done |= terminated | truncated
    return potted / shots


def test_calling_the_best_shot_pots_more_than_calling_the_sixth():
    best, sixth = _potted_per_shot(0), _potted_per_shot(5)
    assert best > 0.65 and best > sixth + 0.1  # 0.74 and 0.57 on these racks
