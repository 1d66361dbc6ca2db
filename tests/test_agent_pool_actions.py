"""The agents' Pool2D features and action transforms against the geometry they claim:
offsets and pocket directions, the ghost-ball contact point each action names, the
target ball, the clearance of a path, and shots played through the transforms."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch

import impulse2d  # noqa: F401  (registers the env ids)
from impulse2d.envs.pool import BALL_RADIUS, pockets


def test_pool_relative_features_are_the_offsets_to_each_ball() -> None:
    from agents._features import PoolRelativeFeatures

    space = gym.spaces.Box(-1.0, 1.0, (9,), np.float32)  # cue ball and two object balls
    extractor = PoolRelativeFeatures(space)
    # Cue at (-0.635, 0) m; ball 1 at (0.635, 0.3175) m; ball 2 potted.
    obs = torch.tensor([[-0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0, 1.0]])
    out = extractor(obs)[0].numpy()
    assert out.shape == (9 + 12,) == (extractor.features_dim,)
    assert np.allclose(out[:9], obs[0].numpy())  # the observation itself comes first
    dx, dy = 1.27, 0.3175
    dist = np.hypot(dx, dy)
    ball1 = [dx, dy, dist, dx / dist, dy / dist, np.arctan2(dy, dx) / np.pi]
    assert np.allclose(out[9:15], ball1, atol=1e-6)
    assert np.all(out[15:] == 0.0)  # a potted ball reads as zeros


def test_pool_pocket_features_give_each_ball_the_way_to_each_pocket() -> None:
    from agents._features import PoolPocketFeatures, PoolRelativeFeatures

    space = gym.spaces.Box(-1.0, 1.0, (9,), np.float32)
    extractor = PoolPocketFeatures(space)
    obs = torch.tensor([[-0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0, 1.0]])
    out = extractor(obs)[0].numpy()
    relative = PoolRelativeFeatures(space)(obs)[0].numpy()
    assert out.shape == (21 + 2 * 6 * 3,) == (extractor.features_dim,)
    assert np.array_equal(out[:21], relative)  # pool_relative's features come first
    centres = pockets()[0]
    assert centres.shape == (6, 2)
    ball1 = np.array([0.635, 0.3175])  # the observation's (0.5, 0.5) on the 2.54 x 1.27 m bed
    to_pocket = centres - ball1
    dist = np.linalg.norm(to_pocket, axis=1)
    per_pocket = out[21:39].reshape(6, 3)
    assert np.allclose(per_pocket[:, :2], to_pocket / dist[:, None], atol=1e-5)
    assert np.allclose(per_pocket[:, 2], dist, atol=1e-5)
    assert np.all(out[39:] == 0.0)  # the potted ball reads as zeros


def test_direction_vector_transform_maps_vectors_to_angles() -> None:
    from agents._wrappers import direction_vector

    out = direction_vector(np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 5.0], [-1.0, -1e-9, -5.0]]))
    assert out.dtype == np.float32 and out.shape == (3, 2)
    assert np.allclose(out[:, 0], [0.0, 0.5, -1.0], atol=1e-6)  # +x, +y, just under -x
    assert np.allclose(out[:, 1], np.tanh([0.0, 5.0, -5.0]))


def test_ball_contact_aims_past_the_nearest_ball_on_the_table() -> None:
    from agents._wrappers import ball_contact

    # cue at the origin; ball 1 potted (nearest if it counted), ball 2 at (0.5 m, 0),
    # ball 3 farther at (-0.6 m, 0.3 m).
    obs = np.array([[0, 0, 0, 0.05, 0, 1, 0.5 / 1.27, 0, 0, -0.6 / 1.27, 0.3 / 0.635, 0]])
    r, d = 0.028575, 0.5
    for b, expected in [(0.0, 0.0), (np.arctanh(0.5), np.arcsin(r / d)), (-5.0, None)]:
        angle, speed = ball_contact(np.array([[b, 0.3]]), obs)[0]
        if expected is None:  # the thinnest cut on the right: the line passes at 2r
            expected = -np.arcsin(2 * r * np.tanh(5.0) / d)
        assert angle == pytest.approx(expected / np.pi, abs=1e-6)
        assert speed == pytest.approx(np.tanh(0.3), abs=1e-6)
    # the line at the output angle passes ball 2's centre at 2 r tanh(b) (signed, left +)
    angle = ball_contact(np.array([[0.7, 0.0]]), obs)[0, 0] * np.pi
    assert d * np.sin(angle) == pytest.approx(2 * r * np.tanh(0.7), rel=1e-5)
    # every ball potted: a defined action, no NaN
    empty = np.array([[0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1]], np.float32)
    assert np.all(np.isfinite(ball_contact(np.array([[1.0, 1.0]]), empty)))


def test_ball_contact_reaches_every_ghost_ball_shot_and_cuts_the_right_way() -> None:
    """The ghost-ball player's shots are all in the transform's range (b = atanh of the
    offset at which its line passes the ball, over 2r), and a positive b (aim left of
    the ball) sends the object ball to the right of the cue ball's line, as a cut does."""
    from agents._wrappers import ball_contact

    from impulse2d.envs.baselines import pool_ghost_ball

    env = gym.make("Pool2D-v0", num_balls=1, layout="random")
    r = 0.028575
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        want = pool_ghost_ball(obs)
        xy = obs.reshape(-1, 3)[:, :2] * (1.27, 0.635)
        dx, dy = xy[1] - xy[0]
        offset = np.hypot(dx, dy) * np.sin(np.pi * want[0] - np.arctan2(dy, dx))
        assert abs(offset) < 2 * r
        got = ball_contact(np.array([[np.arctanh(offset / (2 * r)), np.arctanh(want[1])]]), obs)
        turn = (got[0, 0] - want[0] + 1) % 2 - 1
        assert abs(turn) < 1e-5 and got[0, 1] == pytest.approx(want[1], abs=1e-5)
    obs, _ = env.reset(seed=3)
    xy = obs.reshape(-1, 3)[:, :2] * (1.27, 0.635)
    line = np.arctan2(*(xy[1] - xy[0])[::-1])
    # stop the shot just after the contact (a 4.4 m/s stroke), to read the ball's heading
    seconds = (np.hypot(*(xy[1] - xy[0])) - 2 * r) / 4.4 + 0.1
    env = gym.make("Pool2D-v0", num_balls=1, layout="random", max_shot_seconds=seconds)
    assert np.array_equal(env.reset(seed=3)[0], obs)
    after, *_ = env.step(ball_contact(np.array([[0.8, 0.5]]), obs)[0])
    moved = (after.reshape(-1, 3)[1, :2] - obs.reshape(-1, 3)[1, :2]) * (1.27, 0.635)
    assert np.hypot(*moved) > 0.05
    turn = (np.arctan2(moved[1], moved[0]) - line + np.pi) % (2 * np.pi) - np.pi
    assert -np.pi / 2 < turn < -0.2  # to the right, by a real cut (tanh 0.8 = 0.66)


def test_pool_cut_features_are_the_ball_contact_actions_of_the_ghost_ball_shots() -> None:
    """For each pocket, ``ball_contact`` with ``tanh(b)`` = the feature's sine sends the cue
    ball through that pocket's ghost point, and the cosine is that of the cut angle."""
    from agents._features import PoolCutFeatures, PoolPocketFeatures
    from agents._wrappers import ball_contact

    space = gym.spaces.Box(-1.0, 1.0, (9,), np.float32)
    extractor = PoolCutFeatures(space)
    obs = np.array([[-0.5, -0.2, 0.0, 0.3, 0.4, 0.0, 0.0, 0.0, 1.0]], np.float32)
    out = extractor(torch.as_tensor(obs))[0].numpy()
    before = PoolPocketFeatures(space)(torch.as_tensor(obs))[0].numpy()
    assert out.shape == (before.size + 2 * 6 * 2,) == (extractor.features_dim,)
    assert np.array_equal(out[: before.size], before)
    cuts = out[before.size :].reshape(2, 6, 2)
    assert np.all(cuts[1] == 0.0)  # the potted ball
    xy = obs[0].reshape(3, 3)[:, :2].astype(np.float64) * (1.27, 0.635)
    cue, ball = xy[0], xy[1]
    for pocket, (sine, cosine) in zip(pockets()[0], cuts[0], strict=True):
        u_bp = (pocket - ball) / np.linalg.norm(pocket - ball)
        ghost = ball - 2 * BALL_RADIUS * u_bp
        u = (ghost - cue) / np.linalg.norm(ghost - cue)
        assert cosine == pytest.approx(u @ u_bp, abs=1e-5)
        assert sine**2 + cosine**2 == pytest.approx(1.0, abs=1e-5)
        angle = ball_contact(np.array([[np.arctanh(sine), 0.0]]), obs)[0, 0] * np.pi
        direction = np.array([np.cos(angle), np.sin(angle)])
        off = ghost - cue
        miss = (
            direction[0] * off[1] - direction[1] * off[0]
        )  # the ghost point's distance off the path
        assert abs(miss) < 1e-5


# -- pocket_choice and pool_target: the shot at the nearest ball, into a called pocket --------
def _obs(*balls: tuple[float, float, float]) -> np.ndarray:
    """One Pool2D observation from (x m, y m, potted) per ball, cue ball first."""
    rows = [(x / 1.27, y / 0.635, potted) for x, y, potted in balls]
    return np.array([np.ravel(rows)], np.float32)


def _path_miss(angle: float, start: np.ndarray, point: np.ndarray) -> float:
    """Signed distance of ``point`` from the line leaving ``start`` at ``angle``."""
    off = point - start
    return float(np.cos(angle) * off[1] - np.sin(angle) * off[0])


def _called(pocket: int, correction: float = 0.0, speed: float = 0.0) -> np.ndarray:
    action = np.full((1, 8), -1.0)
    action[0, pocket], action[0, 6], action[0, 7] = 1.0, correction, speed
    return action


def test_pocket_choice_plays_the_ghost_ball_line_into_the_called_pocket() -> None:
    from agents._wrappers import pocket_choice

    # cue ball, a potted ball nearer than anything, the target (nearest on the table), a far ball
    obs = _obs((-0.4, -0.1, 0), (-0.35, -0.1, 1), (0.3, 0.2, 0), (0.9, -0.4, 0))
    cue, ball = np.array([-0.4, -0.1]), np.array([0.3, 0.2])
    for pocket, centre in enumerate(pockets()[0]):
        u_bp = (centre - ball) / np.linalg.norm(centre - ball)
        ghost = ball - 2 * BALL_RADIUS * u_bp
        angle, speed = pocket_choice(_called(pocket, 0.0, 0.4), obs)[0]
        assert abs(_path_miss(angle * np.pi, cue, ghost)) < 2e-6  # float32 angle
        assert speed == pytest.approx(np.tanh(0.4), abs=1e-6)
    # the correction moves the contact left by 0.25 tanh(c) of a ball diameter (on the
    # pocket with the thinnest cut, so that nothing reaches the clip at +-1)
    from agents._pool_geometry import target_shots

    thin = int(target_shots(torch.as_tensor(obs, dtype=torch.float64))["sin"][0].abs().argmin())
    base = pocket_choice(_called(thin), obs)[0, 0] * np.pi
    trimmed = pocket_choice(_called(thin, correction=0.5), obs)[0, 0] * np.pi
    moved = _path_miss(base, cue, ball) - _path_miss(trimmed, cue, ball)
    assert moved == pytest.approx(2 * BALL_RADIUS * 0.25 * np.tanh(0.5), abs=2e-6)


def test_pocket_choice_takes_the_highest_preference_and_survives_an_empty_table() -> None:
    from agents._wrappers import pocket_choice

    obs = _obs((-0.4, -0.1, 0), (0.3, 0.2, 0))
    prefs = np.array([[0.1, -2.0, 0.7, 0.69, -1.0, 0.0, 0.0, 0.0]])
    assert np.array_equal(pocket_choice(prefs, obs), pocket_choice(_called(2), obs))
    empty = _obs((-0.4, -0.1, 0), (0.3, 0.2, 1))
    assert np.allclose(pocket_choice(_called(3, 0.0, 5.0), empty)[0], [0.0, np.tanh(5.0)])


def test_clearance_is_the_nearest_obstacle_from_a_path_in_ball_diameters() -> None:
    from agents._pool_geometry import CLEARANCE_CAP, clearance

    start = torch.tensor([[[0.0, 0.0], [0.0, 0.0]]], dtype=torch.float64)
    end = torch.tensor([[[1.0, 0.0], [0.0, 1.0]]], dtype=torch.float64)
    d = 2 * BALL_RADIUS
    xy = torch.tensor([[[0.5, 0.5 * d], [2.0, 0.0], [0.1, 5.0]]], dtype=torch.float64)
    on = torch.tensor([[True, True, False]])
    got = clearance(start, end, xy, on)[0].numpy()
    # along x, ball 0 is half a diameter off the path: a ball rolling there hits it;
    # along y, ball 0 is 0.5 m off (capped), ball 1 beyond the end is 2 m from (0, 1)
    assert got[0] == pytest.approx(0.5)
    assert got[1] == CLEARANCE_CAP
    nothing = clearance(start, end, xy, torch.zeros((1, 3), dtype=torch.bool))
    assert torch.all(nothing == CLEARANCE_CAP)


def test_pool_target_features_describe_the_shots_pocket_choice_plays() -> None:
    from agents._features import PoolTargetFeatures
    from agents._pool_geometry import target_shots

    space = gym.spaces.Box(-1.0, 1.0, (12,), np.float32)
    extractor = PoolTargetFeatures(space)
    # cue ball; ball 1 on the way from the target to the (+x, +y) corner pocket (index 3);
    # the target ball 2, nearest the cue ball; ball 3 far off every path
    obs = _obs((-0.5, 0.0, 0), (0.6, 0.3, 0), (0.0, 0.0, 0), (-1.1, 0.2, 0))
    out = extractor(torch.as_tensor(obs))[0].numpy().astype(np.float64)
    assert out.shape == (12 + 4 + 36,) == (extractor.features_dim,)
    assert np.array_equal(out[:12], obs[0])
    shot = target_shots(torch.as_tensor(obs, dtype=torch.float64))
    assert out[12] == 1.0 and np.allclose(out[13:16], [0.5, 0.0, 0.5], atol=1e-5)
    per_pocket = out[16:].reshape(6, 6)
    for column, key in enumerate(("sin", "cos", "run", "reach", "clear_cue", "clear_ball")):
        assert np.allclose(per_pocket[:, column], shot[key][0].numpy(), atol=1e-5), key
    assert per_pocket[3, 5] < 1.0  # the object ball's path to pocket 3 is blocked
    assert np.all(per_pocket[[0, 1, 4], 5] == 3.0)  # the left corners and a side: clear
    assert np.all(per_pocket[:, 4] == 3.0)  # nothing between the cue ball and the target
    cleared = _obs((-0.5, 0.0, 0), (0.6, 0.3, 1), (0.0, 0.0, 1), (-1.1, 0.2, 1))
    assert np.all(extractor(torch.as_tensor(cleared))[0, 12:].numpy() == 0.0)


@pytest.mark.parametrize(("num_balls", "least"), [(1, 0.95), (15, 11.0)])
def test_calling_the_ghost_ball_players_pocket_pots_as_it_does(num_balls, least) -> None:
    """A policy that calls the clear pocket with the smallest cut (the ghost-ball rule) at
    a firm speed, through pocket_choice, pots the one ball nearly always and most of the
    rack (random play: 0.12 and 7.5): the transform plays the shots its geometry
    describes."""
    from agents._pool_geometry import target_shots
    from agents._tasks import play_episodes
    from agents._wrappers import pocket_choice

    def caller(obs: np.ndarray) -> np.ndarray:
        shot = target_shots(torch.as_tensor(obs, dtype=torch.float64))
        clear = (shot["clear_cue"] > 1) & (shot["clear_ball"] > 1)
        score = shot["cos"] ** 2 / (1 + shot["reach"] + shot["run"]) + clear.double()
        action = np.zeros((len(obs), 8))
        action[np.arange(len(obs)), score.argmax(dim=1).numpy()] = 1.0
        action[:, 7] = -0.5  # about 1.7 m/s
        return pocket_choice(action, obs)

    kwargs = {"num_balls": num_balls, "max_episode_steps": 5 if num_balls == 1 else 30}
    if num_balls == 1:
        kwargs["layout"] = "random"
    record = play_episodes("Pool2D-v0", kwargs, caller, 20, 1000)
    assert record["potted"].mean() >= least
