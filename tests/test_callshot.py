"""The call-shot wrappers (impulse2d.envs.callshot) against the geometry they claim and the
game under them: the ghost-ball line into each called pocket, the trim, the clearance of a
path, the speed window, the parabola through each named pig; the wrapped env plays the
bare game's episodes; single, vector and registered ids agree; both checkers pass."""

from __future__ import annotations

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import impulse2d  # noqa: F401  (registers the env ids)
from impulse2d.envs import CALL_SHOT_IDS, base_game, callshot, slingshot
from impulse2d.envs.baselines import ballistic_angle, slingshot_ballistic
from impulse2d.envs.pool import BALL_RADIUS, TABLE_LENGTH, TABLE_WIDTH, pockets


# -- pool: the shots ----------------------------------------------------------------------------
def _obs(*balls: tuple[float, float, float]) -> np.ndarray:
    """One Pool2D observation from (x m, y m, potted) per ball, cue ball first."""
    rows = [(x / (TABLE_LENGTH / 2), y / (TABLE_WIDTH / 2), potted) for x, y, potted in balls]
    return np.array([np.ravel(rows)], np.float32)


def _path_miss(angle: float, start: np.ndarray, point: np.ndarray) -> float:
    """Signed distance of ``point`` from the line leaving ``start`` at ``angle``."""
    off = point - start
    return float(np.cos(angle) * off[1] - np.sin(angle) * off[0])


def _called(pocket: int, trim: float = 0.0, speed: float = 0.0) -> np.ndarray:
    action = np.full((1, 8), -1.0)
    action[0, pocket], action[0, 6], action[0, 7] = 1.0, trim, speed
    return action


def test_calling_a_pocket_plays_the_ghost_ball_line_into_it() -> None:
    # cue ball, a potted ball nearer than anything, the target (nearest on the table), a far ball
    obs = _obs((-0.4, -0.1, 0), (-0.35, -0.1, 1), (0.3, 0.2, 0), (0.9, -0.4, 0))
    cue, ball = np.array([-0.4, -0.1]), np.array([0.3, 0.2])
    for pocket, centre in enumerate(pockets()[0]):
        u_bp = (centre - ball) / np.linalg.norm(centre - ball)
        ghost = ball - 2 * BALL_RADIUS * u_bp
        angle = callshot.pool_call_shot_actions(_called(pocket, 0.0, 0.4), obs)[0, 0]
        assert abs(_path_miss(angle * np.pi, cue, ghost)) < 2e-6  # float32 observation
    # the trim moves the contact left by 0.25 t of a ball diameter (on the pocket with
    # the thinnest cut, so that nothing reaches the clip at +-1)
    thin = int(np.abs(callshot.pool_target_shots(obs)["sin"][0]).argmin())
    base = callshot.pool_call_shot_actions(_called(thin), obs)[0, 0] * np.pi
    trimmed = callshot.pool_call_shot_actions(_called(thin, trim=0.5), obs)[0, 0] * np.pi
    moved = _path_miss(base, cue, ball) - _path_miss(trimmed, cue, ball)
    assert moved == pytest.approx(2 * BALL_RADIUS * 0.25 * 0.5, abs=2e-6)


def test_the_highest_preference_is_called_and_an_empty_table_is_no_error() -> None:
    obs = _obs((-0.4, -0.1, 0), (0.3, 0.2, 0))
    prefs = np.array([[0.1, -0.9, 0.7, 0.69, -1.0, 0.0, 0.0, 0.0]])
    got = callshot.pool_call_shot_actions(prefs, obs)
    assert np.array_equal(got, callshot.pool_call_shot_actions(_called(2), obs))
    empty = _obs((-0.4, -0.1, 0), (0.3, 0.2, 1))
    assert callshot.pool_call_shot_actions(_called(3, 0.0, 0.7), empty)[0, 0] == 0.0
    assert np.all(callshot.pool_features(empty) == 0.0)


def test_the_speed_is_read_against_the_called_shots_window() -> None:
    obs = _obs((-0.9, 0.3, 0), (0.0, 0.1, 0))
    shot = callshot.pool_target_shots(obs)
    inside = (shot["pot_speed"][0] < shot["scratch_speed"][0]) & (shot["scratch_speed"][0] < 1)
    pocket = int(np.flatnonzero(inside)[0])
    pot, scratch = shot["pot_speed"][0, pocket], shot["scratch_speed"][0, pocket]
    assert -1 < pot < scratch < 1  # this shot has a window, inside the speed range
    speeds = [callshot.pool_call_shot_actions(_called(pocket, 0, s), obs)[0, 1] for s in
              (-1.0, -0.5, 0.0, 0.5, 1.0)]  # fmt: skip
    expected = [pot, (pot + scratch) / 2, scratch, (scratch + 1) / 2, 1.0]
    assert np.allclose(speeds, expected, rtol=0, atol=1e-12)
    # an empty window (the cue ball would scratch at any speed that pots): s <= 0 is the
    # pot speed, and above it the speed rises to full
    got = callshot.window_speed(np.array([-1.0, -0.3, 0.0, 0.5]), np.full(4, 0.2), np.full(4, -0.4))
    assert np.allclose(got, [0.2, 0.2, 0.2, 0.6])


def test_clearance_is_the_nearest_obstacle_from_a_path_in_ball_diameters() -> None:
    start = np.zeros((1, 2, 2))
    end = np.array([[[1.0, 0.0], [0.0, 1.0]]])
    d = 2 * BALL_RADIUS
    xy = np.array([[[0.5, 0.5 * d], [2.0, 0.0], [0.1, 5.0]]])
    on = np.array([[True, True, False]])
    got = callshot._clearance(start, end, xy, on)[0]
    # along x, ball 0 is half a diameter off the path: a ball rolling there hits it;
    # along y, ball 0 is 0.5 m off (capped), ball 1 beyond the end is 2 m from (0, 1)
    assert got[0] == pytest.approx(0.5)
    assert got[1] == callshot.CLEARANCE_CAP
    nothing = callshot._clearance(start, end, xy, np.zeros((1, 3), bool))
    assert np.all(nothing == callshot.CLEARANCE_CAP)


def test_the_features_describe_the_shots_the_action_plays() -> None:
    # cue ball; ball 1 on the way from the target to the (+x, +y) corner pocket (index 3);
    # the target ball 2, nearest the cue ball; ball 3 far off every path
    obs = _obs((-0.5, 0.0, 0), (0.6, 0.3, 0), (0.0, 0.0, 0), (-1.1, 0.2, 0))
    env = callshot.PoolCallShot(gym.make("Pool2D-v0", num_balls=3).unwrapped)
    out = env.observation(obs[0]).astype(np.float64)
    assert out.shape == env.observation_space.shape == (12 + callshot.POOL_FEATURES,)
    assert np.array_equal(out[:12], obs[0])
    shot = callshot.pool_target_shots(obs)
    assert out[12] == 1.0 and np.allclose(out[13:16], [0.5, 0.0, 0.5], atol=1e-6)
    per_pocket = out[16:].reshape(6, len(callshot.PER_POCKET))
    for column, key in enumerate(callshot.PER_POCKET):
        assert np.allclose(per_pocket[:, column], shot[key][0], atol=1e-6), key
    clear_ball = callshot.PER_POCKET.index("clear_ball")
    assert per_pocket[3, clear_ball] < 1.0  # the object ball's path to pocket 3 is blocked
    assert np.all(per_pocket[[0, 1, 4], clear_ball] == 3.0)  # the left corners, a side: clear
    assert np.all(per_pocket[:, callshot.PER_POCKET.index("clear_cue")] == 3.0)


def test_scratch_distance_follows_the_path_off_the_cushions() -> None:
    half_l, half_w = callshot.CUSHION_BOX
    corner = callshot.POCKETS[3]  # (+x, +y)
    # straight at the corner pocket from the middle of the table: it drops after the run
    start = np.array([[0.0, 0.0]])
    to_corner = corner / np.linalg.norm(corner)
    got = callshot.scratch_distance(start, to_corner[None])[0]
    radius = callshot.POCKET_RADII[3]
    assert np.linalg.norm(corner) - radius - 0.01 < got < np.linalg.norm(corner)
    # along the long axis from the head spot: off the foot cushion, back past the start to
    # the head cushion and back again, never near a pocket: the cap
    along = callshot.scratch_distance(np.array([[-0.6, 0.0]]), np.array([[1.0, 0.0]]))[0]
    assert along == callshot.SCRATCH_CAP
    # up the short axis at x = 0: into the side pocket (its centre is past the cushion line)
    side = callshot.scratch_distance(np.array([[0.0, 0.0]]), np.array([[0.0, 1.0]]))[0]
    assert half_w - callshot.POCKET_RADII[5] < side <= half_w
    # one bounce: aimed at the foot cushion's mirror image of the corner pocket
    mirror = np.array([2 * half_l - corner[0], corner[1]])
    start = np.array([0.3, -0.2])
    direction = (mirror - start) / np.linalg.norm(mirror - start)
    bounced = callshot.scratch_distance(start[None], direction[None])[0]
    assert bounced == pytest.approx(np.linalg.norm(mirror - start), abs=callshot.POCKET_RADII[3])


def test_the_speed_window_sorts_shots_that_pot_and_scratch() -> None:
    """On 512 random one-ball tables, the ghost-ball shot into the pocket with the least
    cut at a random speed: below the pot speed the ball stays out, within the window it
    drops and the cue ball mostly stays up, above the scratch speed it often follows."""
    venv = gym.make_vec("Pool2D-v0", 512, vectorization_mode="vector_entry_point", num_balls=1)
    obs, _ = venv.reset(seed=5)
    shot = callshot.pool_target_shots(obs)
    rows = np.arange(512)
    pocket = np.argmax(shot["cos"], axis=1)
    speed = np.random.default_rng(0).uniform(-1.0, 1.0, 512)
    action = np.full((512, 8), -1.0)
    action[rows, pocket], action[:, 6], action[:, 7] = 1.0, 0.0, speed
    game = callshot.pool_call_shot_actions(action, obs)
    game[:, 1] = speed  # the game's own speed action, not read against the window
    _, _, _, _, info = venv.step(game.astype(np.float32))
    potted, scratched = info["potted"] > 0, info["cue_potted"]
    slow = speed < shot["pot_speed"][rows, pocket]
    fast = speed > shot["scratch_speed"][rows, pocket]
    window = ~slow & ~fast
    assert potted[slow].mean() < 0.1 and potted[window].mean() > 0.85
    assert scratched[window].mean() < 0.1 < 0.3 < scratched[fast].mean()


@pytest.mark.parametrize(("num_balls", "least"), [(1, 0.95), (15, 11.0)])
def test_calling_the_ghost_ball_players_pocket_pots_as_it_does(num_balls, least) -> None:
    """A policy that calls the clear pocket with the smallest cut (the ghost-ball rule) at
    a firm speed pots the one ball nearly always and most of the rack (random play: 0.12
    and 7.5): the wrapper plays the shots its features describe."""
    from agents._tasks import play_episodes

    def caller(obs: np.ndarray) -> np.ndarray:
        shot = callshot.pool_target_shots(obs[:, : 3 * (num_balls + 1)])
        clear = (shot["clear_cue"] > 1) & (shot["clear_ball"] > 1)
        score = shot["cos"] ** 2 / (1 + shot["reach"] + shot["run"]) + clear
        action = np.zeros((len(obs), 8))
        action[np.arange(len(obs)), score.argmax(axis=1)] = 1.0
        action[:, 7] = -0.5  # halfway up the speed window
        return action

    env_id = "Pool2DCallShot-v0" if num_balls == 1 else "Pool2DRackCallShot-v0"
    record = play_episodes(env_id, {}, caller, 20, 1000)
    assert record["potted"].mean() >= least


# -- slingshot ----------------------------------------------------------------------------------
def _level(name: str) -> np.ndarray:
    obs, _ = gym.make("Slingshot2D-v0", level=name).reset(seed=0)
    return obs[None]


def _named(pig: int, arc: float = -1.0, trim: float = 0.0, speed: float = 1.0) -> np.ndarray:
    action = np.full((1, 7), -1.0)
    action[0, pig], action[0, 4:] = 1.0, (arc, trim, speed)
    return action


def _pigs(obs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    slots = obs[0, :-1].reshape(-1, slingshot.FEATURES)[: slingshot.MAX_PIGS].astype(np.float64)
    return slingshot.slot_positions(slots)


def test_the_ballistic_players_launches_are_call_shot_actions() -> None:
    obs = _level("twin-towers")  # two pigs
    x, _ = _pigs(obs)
    nearest = int(np.argmin(np.where(x > 0, x, np.inf)))
    for arc, which in ((-1.0, "low"), (1.0, "high")):
        got = callshot.slingshot_call_shot_actions(_named(nearest, arc), obs)[0]
        assert np.allclose(got, slingshot_ballistic(obs[0], which), atol=1e-6)


def test_arc_trim_and_speed_set_the_launch() -> None:
    obs = _level("twin-towers")
    x, y = _pigs(obs)
    lo, hi = slingshot.SPEED_RANGE
    speed = lo + 0.5 * (0.3 + 1) * (hi - lo)
    for pig in (0, 1):
        dx, dy = x[pig] - slingshot.SLING[0], y[pig] - slingshot.SLING[1]
        for arc in (-1.0, 1.0):
            angle = float(ballistic_angle(dx, dy, speed, arc > 0))
            want = angle + callshot.ANGLE_TRIM * 0.7
            got = callshot.slingshot_call_shot_actions(_named(pig, arc, 0.7, 0.3), obs)[0]
            assert got[0] == pytest.approx(4 * want / math.pi - 1, abs=1e-9)  # 0-90 degrees
            assert got[1] == 0.3
            # the launch passes through the pig's centre without the trim (drag-free)
            t = dx / (speed * math.cos(angle))
            assert speed * math.sin(angle) * t - 9.81 * t * t / 2 == pytest.approx(dy, abs=1e-9)


def test_dead_pigs_cannot_be_named_and_a_cleared_level_gives_45_degrees() -> None:
    obs = _level("twin-towers")
    dead = obs.copy()
    dead[0, : slingshot.FEATURES] = 0.0  # pig 0 destroyed: its slot reads as zeros
    prefers_dead = _named(0)
    prefers_dead[0, 1] = 0.5  # pig 1 is second best
    got = callshot.slingshot_call_shot_actions(prefers_dead, dead)
    assert np.array_equal(got, callshot.slingshot_call_shot_actions(_named(1), obs))
    cleared = obs.copy()
    cleared[0, : slingshot.FEATURES * slingshot.MAX_PIGS] = 0.0
    launch = callshot.slingshot_call_shot_actions(_named(2, trim=1.0), cleared)[0]
    assert launch[0] == pytest.approx(0.0, abs=1e-12)


# -- the wrappers and their ids -----------------------------------------------------------------
@pytest.mark.parametrize("env_id", list(CALL_SHOT_IDS))
def test_a_call_shot_id_plays_the_bare_games_episodes(env_id) -> None:
    """Each call-shot action, mapped by hand and given to the bare game under the id, gives
    bitwise the game's observation (the head of the call-shot one; all of it, for an id
    that observes pixels), reward and info."""
    game_id, kwargs = base_game(env_id)
    pixels = kwargs.get("obs_type") == "pixels"
    wrapped, bare = gym.make(env_id), gym.make(game_id, **kwargs)
    obs, _ = wrapped.reset(seed=3)
    raw, _ = bare.reset(seed=3)
    size = raw.shape[0]
    assert np.array_equal(obs[:size], raw)
    task = wrapped.get_wrapper_attr("task")  # the call-shot or best-shots task of the id
    rng = np.random.default_rng(0)
    for _ in range(3):
        action = rng.uniform(-1, 1, wrapped.action_space.shape).astype(np.float32)
        position = bare.unwrapped.game.observe()  # the state, whatever the env observes
        game_action = task.to_game(action[None].astype(np.float64), position)[0]
        obs, reward, terminated, truncated, info = wrapped.step(action)
        raw, reward_bare, terminated_bare, truncated_bare, info_bare = bare.step(
            game_action.astype(np.float32)
        )
        assert np.array_equal(obs[:size], raw)
        assert np.array_equal(obs, raw if pixels else task.observe(raw[None])[0])
        assert (reward, terminated, truncated, info) == (
            reward_bare,
            terminated_bare,
            truncated_bare,
            info_bare,
        )
        if terminated or truncated:
            break


@pytest.mark.parametrize("env_id", ["Pool2DCallShot-v0", "Slingshot2DCallShot-v0"])
@pytest.mark.parametrize("mode", list(AutoresetMode))
def test_the_vector_form_is_the_single_env_seeded_seed_plus_i(env_id, mode) -> None:
    n, seed = 4, 11
    venv = gym.make_vec(env_id, n, vectorization_mode="vector_entry_point", autoreset_mode=mode)
    envs = [gym.make(env_id) for _ in range(n)]
    obs, _ = venv.reset(seed=seed)
    singles = [env.reset(seed=seed + i)[0] for i, env in enumerate(envs)]
    assert np.array_equal(obs, np.stack(singles))
    assert venv.observation_space.contains(obs)
    rng = np.random.default_rng(1)
    ended = np.zeros(n, bool)
    for _ in range(6):
        actions = rng.uniform(-1, 1, venv.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = venv.step(actions)
        for i, env in enumerate(envs):
            if ended[i]:
                continue
            single = env.step(actions[i])
            done = terminated[i] or truncated[i]
            seen = info["final_obs"][i] if mode is AutoresetMode.SAME_STEP and done else obs[i]
            assert np.array_equal(seen, single[0]) and reward[i] == single[1]
            ended[i] |= done
        if ended.any():
            break


def test_save_and_restore_through_the_wrapper_replay_bitwise() -> None:
    venv = gym.make_vec("Pool2DRackCallShot-v0", 3, vectorization_mode="vector_entry_point")
    obs, _ = venv.reset(seed=0)
    state = venv.save_state()
    actions = np.random.default_rng(2).uniform(-1, 1, (2, 3, 8)).astype(np.float32)
    first = [venv.step(a)[:2] for a in actions]
    assert np.array_equal(venv.restore_state(state), obs)
    again = [venv.step(a)[:2] for a in actions]
    for (o1, r1), (o2, r2) in zip(first, again, strict=True):
        assert np.array_equal(o1, o2) and np.array_equal(r1, r2)


def test_a_wrapper_refuses_another_game_and_bad_actions_by_name() -> None:
    with pytest.raises(ValueError, match="must be a Pool2D env"):
        callshot.PoolCallShot(gym.make("Slingshot2D-v0"))
    env = gym.make("Pool2DCallShot-v0")
    env.reset(seed=0)
    for bad in (np.full(8, np.nan), np.zeros(2), "aim", np.zeros(8, complex)):
        with pytest.raises(ValueError, match="action"):
            env.step(bad)


@pytest.mark.parametrize("env_id", list(CALL_SHOT_IDS))
def test_both_checkers_pass_on_the_call_shot_ids(env_id, monkeypatch) -> None:
    from gymnasium.utils.env_checker import check_env
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    for name in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(name, raising=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(gym.make(env_id).unwrapped)
        sb3_check_env(gym.make(env_id))
        # Gymnasium's checker on the wrapped env itself: the one thing it says is that the
        # env is wrapped (the convention is to check .unwrapped, done above).
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*different from the unwrapped version")
            check_env(gym.make(env_id), skip_render_check=True)


def test_call_shot_observations_stay_in_their_space_over_many_tables() -> None:
    venv = gym.make_vec("Pool2DRackCallShot-v0", 64, vectorization_mode="vector_entry_point")
    obs, _ = venv.reset(seed=4)
    rng = np.random.default_rng(3)
    for _ in range(4):
        assert venv.observation_space.contains(obs)
        obs, *_ = venv.step(rng.uniform(-1, 1, venv.action_space.shape).astype(np.float32))


@pytest.mark.parametrize("mode", ["vector_entry_point", "sync"])
def test_cleanrl_style_wrappers_take_a_call_shot_id(mode) -> None:
    """What a CleanRL-style script does with an id: ``gym.make_vec`` (batched or one env
    per table) under ``RecordEpisodeStatistics``, ``ClipAction`` and
    ``NormalizeObservation``, through episodes that end."""
    from gymnasium.wrappers import vector as vw

    venv = gym.make_vec("Pool2DCallShot-v0", 3, vectorization_mode=mode)
    venv = vw.RecordEpisodeStatistics(vw.NormalizeObservation(vw.ClipAction(venv)))
    obs, _ = venv.reset(seed=0)
    rng = np.random.default_rng(0)
    episodes = 0
    for _ in range(8):
        actions = rng.uniform(-2, 2, (3, 8)).astype(np.float32)  # ClipAction's job
        obs, _, _, _, info = venv.step(actions)
        assert obs.shape == (3, 6 + callshot.POOL_FEATURES) and np.isfinite(obs).all()
        if "episode" in info:
            episodes += int(info["_episode"].sum())
    assert episodes >= 3
    venv.close()
