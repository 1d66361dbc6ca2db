"""Gymnasium faces of a shot game: a single ``gym.Env`` and a natively batched
``gym.vector.VectorEnv``.

Both wrap the same ``ShotGame``: the single env is a game with one world, the vector env a
game with ``num_envs`` worlds stepped in one engine. Env ``i`` of a vector env reset with
``seed`` uses the generator ``np_random(seed + i)``, the one a single env reset with
``seed + i`` gets from ``super().reset``, so both play bitwise the same episodes.

Autoreset (vector env), chosen with Gymnasium's keyword ``autoreset_mode`` and exposed
as the attribute ``autoreset_mode`` and in ``metadata``:

* ``AutoresetMode.NEXT_STEP`` (the default, as for Gymnasium's ``SyncVectorEnv``): the
  step that ends an env's episode returns its last observation; the next ``step``
  starts its new episode, ignores its action and returns the first observation, reward
  0 and neither terminated nor truncated.
* ``AutoresetMode.SAME_STEP``: the step that ends an episode returns the first
  observation of the next one; the last observation of the finished one is in
  ``info["final_obs"][i]`` and its info in ``info["final_info"]``. (SB3's convention,
  and no vector step spent on resets: what ``make_sb3_vec_env`` and the benchmarks use.)
* ``AutoresetMode.DISABLED``: nothing resets by itself; an env whose episode ended must
  be reset with ``reset(options={"reset_mask": mask})`` before it is stepped again
  (TorchRL's preferred mode).

Every info key has a ``_key`` mask saying which envs it holds (Gymnasium's layout).
``reset(options={"reset_mask": mask})`` resets only the envs of a boolean mask.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from impulse2d import _checks

from ._core import GameState, ShotGame, check_action

logger = logging.getLogger("impulse2d.envs")


@dataclass(frozen=True)
class EnvState:
    """A saved env (``save_state``): the game's state and, for a vector env, each world's
    shots this episode and whether it resets at the next step (NEXT_STEP)."""

    game: GameState
    moves: np.ndarray
    autoreset: np.ndarray


OBS_TYPES = ("state", "pixels")
PIXEL_SIZE = 84  # the side of a pixel observation (Atari's, and most vision RL's)


class _View:
    """What an env observes: the game's state vector (``obs_type="state"``) or its
    frames, ``pixel_size`` square, RGB uint8 (``"pixels"``, ``ShotGame.pixels``)."""

    def __init__(self, obs_type: Any, pixel_size: Any) -> None:
        self.obs_type = _checks.word("obs_type", obs_type, OBS_TYPES)
        self.size = _checks.int_in("pixel_size", pixel_size, 16, 1024)

    def space(self, game: ShotGame) -> gym.spaces.Box:
        if self.obs_type == "pixels":
            return gym.spaces.Box(0, 255, (self.size, self.size, 3), np.uint8)
        return gym.spaces.Box(game.observation_low, game.observation_high, dtype=np.float32)

    def observe(self, game: ShotGame) -> np.ndarray:
        return game.pixels(self.size) if self.obs_type == "pixels" else game.observe()


RENDER_SIZE = (480, 270)  # width, height of rgb_array frames (pixels)
RENDER_FPS = 30  # frames per simulated second in rgb_array_list and human modes


def _render_mode(render_mode: Any, modes: list[str]) -> str | None:
    """``render_mode`` checked: one of ``modes`` (strings) or None."""
    if render_mode is not None and not (isinstance(render_mode, str) and render_mode in modes):
        raise ValueError(f"render_mode must be one of {modes} or None, got {render_mode!r}")
    return None if render_mode is None else str(render_mode)


class _Frames:
    """Rendering for one game: the frame after a shot, frames during it, or a window.

    ``frames[i]`` holds world ``i``'s frames since the last ``take()`` (``rgb_array_list``):
    every world is drawn at each frame time, so the lists stay of one length and the
    frames of one time can be tiled side by side. ``human`` shows world 0. The envs pass
    ``during_shot`` and ``every`` to ``ShotGame.shoot`` (frames during a shot).

    ``human`` without a display: constructing the env never fails for it, and the window
    is opened at the first frame (the reset). Where none can open (no DISPLAY or
    WAYLAND_DISPLAY, and no ``SDL_VIDEODRIVER`` chosen), the env says so once, through
    the ``logging`` logger ``impulse2d.envs`` (a warning record: printed on stderr when
    logging is not set up), naming the display variables, ``xvfb-run`` and
    ``render_mode='rgb_array'``, and then plays on without drawing. Why not an error:
    Gymnasium's ``check_env`` makes the env in every render mode of ``metadata``, resets
    it and calls ``render()``, and it passes for its own envs on a headless machine, with
    warnings as errors; an error there (or a Python warning) would fail the checker, and
    a headless training job that asks for human mode would stop. Why not silently:
    a person who asked for a window is told why none came, at the moment it would.
    A missing pygame-ce is still an ImportError at construction: that is an install to
    do, not a machine without a screen.
    """

    def __init__(
        self, game: ShotGame, render_mode: str | None, modes: list[str], worlds: int = 1
    ) -> None:
        self.game, self.mode, self.worlds = game, _render_mode(render_mode, modes), worlds
        self.renderer: Any = None
        self.frames: list[list[np.ndarray]] = [[] for _ in range(worlds)]
        self.window: Any = None
        self.no_window = False  # human mode found no display: frames are not drawn
        if self.mode == "human":
            from impulse2d.envs._window import load_pygame

            load_pygame()  # an ImportError naming the extra, now rather than at a frame
        self.frame_every = max(1, round(1.0 / (RENDER_FPS * game.dt)))

    @property
    def every(self) -> int:
        """Physics steps between frames during a shot; 0 when none are drawn."""
        drawing = self.mode == "rgb_array_list" or (self.mode == "human" and not self.no_window)
        return self.frame_every if drawing else 0

    def frame(self, world: int = 0) -> np.ndarray:
        if self.renderer is None:
            self.renderer = self.game.make_renderer(*RENDER_SIZE)
        return self.renderer.render(self.game.world, world)

    def during_shot(self) -> None:
        """One frame time: every world into its list, or world 0 into the window."""
        if self.mode == "rgb_array_list":
            for i, frames in enumerate(self.frames):
                frames.append(self.frame(i))
        elif self.mode == "human" and self._window_open():
            self.show(self.frame(0))

    def take(self) -> list[list[np.ndarray]]:
        """Every world's frames since the last call (and forget them)."""
        taken, self.frames = self.frames, [[] for _ in range(self.worlds)]
        return taken

    def _window_open(self) -> bool:
        """Whether the human window is open, opening it at the first frame; without a
        display, say so once and draw nothing from then on (see the class docstring)."""
        if self.window is None and not self.no_window:
            from impulse2d.envs._window import Window

            try:
                self.window = Window(*RENDER_SIZE, RENDER_FPS)
            except RuntimeError as error:
                self.no_window = True
                logger.warning("%s. This env plays on without a window.", error)
        return self.window is not None

    def show(self, frame: np.ndarray) -> None:
        self.window.show(frame)

    def close(self) -> None:
        if self.window is not None:
            self.window.close()
            self.window = None


class ShotEnv(gym.Env):
    """A single environment on a ``ShotGame`` with one world (subclasses set ``game_class``
    and document the game).

    ``save_state()`` copies the position (the world, the random generator, the game's
    bookkeeping) in tens of microseconds; ``restore_state(state)`` brings it back and
    returns its observation, and the same actions then give bitwise the same
    observations, rewards and infos: a planner's rollouts from one position.
    ``copy.deepcopy`` and ``pickle`` of an env work too, and replay bitwise, at a few ms.
    """

    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": ["human", "rgb_array", "rgb_array_list"],
        "render_fps": RENDER_FPS,
    }
    game_class: type[ShotGame]

    def __init__(
        self,
        render_mode: str | None = None,
        obs_type: str = "state",
        pixel_size: int = PIXEL_SIZE,
        **game_options: Any,
    ) -> None:
        render_mode = _render_mode(render_mode, self.metadata["render_modes"])
        self._view = _View(obs_type, pixel_size)
        self.game = self.game_class(1, **game_options)
        self.obs_type, self.pixel_size = self._view.obs_type, self._view.size
        self.render_mode = render_mode
        self._frames = _Frames(self.game, render_mode, self.metadata["render_modes"])
        self.observation_space = self._view.space(self.game)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (self.game.action_size,), np.float32)
        self._ready = False

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.game.rngs[0] = self.np_random
        self.game.reset([0])
        self._ready = True
        self._frames.take()
        self._after_move()
        return self._view.observe(self.game)[0], {}

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if not self._ready:
            raise RuntimeError("call reset() before step()")
        action = check_action(action, self.action_space.shape)
        frames = self._frames
        reward, terminated, info = self.game.shoot(
            [0], action[None], frames.during_shot, frames.every
        )
        self._after_move()
        obs = self._view.observe(self.game)[0]
        return obs, float(reward[0]), bool(terminated[0]), False, _scalars(info)

    def save_state(self) -> EnvState:
        """A copy of everything the next steps depend on (the world, the generator, the
        game's bookkeeping): ``restore_state`` brings it back, and the same actions then
        give bitwise the same observations, rewards and infos. Cheap (tens of µs), for
        planners: a copy of the position, not of the env. (The step count of
        ``gym.make``'s ``TimeLimit`` lives in that wrapper: plan on ``env.unwrapped``.)"""
        self._require_reset()
        return EnvState(self.game.save_state(), np.zeros(1, np.int64), np.zeros(1, bool))

    def restore_state(self, state: EnvState) -> np.ndarray:
        """Bring back a ``save_state``; returns the observation there."""
        self._require_reset()
        if not isinstance(state, EnvState):
            raise ValueError(f"state must be an EnvState, got {type(state).__name__}")
        self.game.restore_state(state.game)
        return self._view.observe(self.game)[0]

    def _require_reset(self) -> None:
        if not self._ready:
            raise RuntimeError("call reset() before step(), save_state() or restore_state()")

    def _after_move(self) -> None:
        self._frames.during_shot()

    def render(self) -> np.ndarray | list[np.ndarray] | None:
        """``rgb_array``: the frame now; ``rgb_array_list``: every frame since the last
        call (during the shots and after each); ``human``: the window is already drawn."""
        if self.render_mode == "rgb_array":
            return self._frames.frame()
        if self.render_mode == "rgb_array_list":
            return self._frames.take()[0]
        return None

    def close(self) -> None:
        self._frames.close()


class ShotVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` games stepped in one batched engine (see the module docstring).

    ``max_episode_steps`` truncates episodes (``gym.make_vec`` passes the registered
    value); ``render_mode="rgb_array"`` renders every world after each step, and
    ``"rgb_array_list"`` also during the shots (see ``render``); ``threads`` is how many
    threads the batch is stepped on (default: every core; results do not depend on it).
    """

    metadata: ClassVar[dict[str, Any]] = {
        "render_modes": ["rgb_array", "rgb_array_list"],
        "render_fps": RENDER_FPS,
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }
    game_class: type[ShotGame]

    def __init__(
        self,
        num_envs: int = 1,
        max_episode_steps: int | None = None,
        render_mode: str | None = None,
        threads: int | None = None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        obs_type: str = "state",
        pixel_size: int = PIXEL_SIZE,
        **game_options: Any,
    ) -> None:
        # The cheap checks first, then the game (which checks num_envs and its own).
        self.autoreset_mode = _autoreset_mode(autoreset_mode)
        self.metadata = {**type(self).metadata, "autoreset_mode": self.autoreset_mode}
        if max_episode_steps is not None:
            # The episode's step count is an int64.
            max_episode_steps = _checks.int_in(
                "max_episode_steps", max_episode_steps, 1, 2**63 - 1, "2**63 - 1"
            )
        self.max_episode_steps = max_episode_steps
        render_mode = _render_mode(render_mode, self.metadata["render_modes"])
        self._view = _View(obs_type, pixel_size)
        self.obs_type, self.pixel_size = self._view.obs_type, self._view.size
        self.game = self.game_class(num_envs, **game_options)
        self.game.world.threads = threads  # checked there: None or an int in [1, cores]
        self.num_envs = self.game.batch_size
        self.render_mode = render_mode
        self._frames = _Frames(self.game, render_mode, self.metadata["render_modes"], self.num_envs)
        self.single_observation_space = self._view.space(self.game)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (self.game.action_size,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._moves = np.zeros(self.num_envs, np.int64)
        self._all = np.arange(self.num_envs)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)  # NEXT_STEP: reset at next step
        self._ready = False

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        # Gymnasium's base class seeds ``self.np_random`` from one int; the envs' own
        # generators come from the seeds below.
        super().reset(seed=seed if isinstance(seed, (int, np.integer)) else None)
        if seed is None:
            seeds: list[int | None] = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)):
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed must be an int or {self.num_envs} seeds, got {len(seeds)}")
        envs = self._all
        if options and "reset_mask" in options:
            if not self._ready:
                raise RuntimeError("call reset() without reset_mask first")
            envs = np.flatnonzero(_reset_mask(options["reset_mask"], self.num_envs))
        if seed is not None or not self._ready:
            for i in envs:
                self.game.rngs[i] = seeding.np_random(seeds[i])[0]
        if envs is self._all:
            self._frames.take()  # a new start: frames of earlier episodes are dropped
        self.game.reset(envs)
        self._moves[envs] = 0
        self._autoreset[envs] = False
        self._ready = True
        self._frames.during_shot()  # rgb_array_list: the position after the reset
        return self._view.observe(self.game), {}

    def step(
        self, actions: Any
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        if not self._ready:
            raise RuntimeError("call reset() before step()")
        actions = check_action(actions, self.action_space.shape)
        if self.autoreset_mode is AutoresetMode.NEXT_STEP:
            result = self._step_next(actions)
        elif self.autoreset_mode is AutoresetMode.DISABLED:
            result = self._step_disabled(actions)
        else:
            result = self._step_same(actions)
        self._frames.during_shot()  # rgb_array_list: the position after the step
        return result

    def _step_same(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """A SAME_STEP vector step: every env shoots; ended episodes reset at once."""
        reward, terminated, info = self._shoot(self._all, actions)
        self._moves += 1
        truncated = self._truncated(terminated)
        observations = self._view.observe(self.game)
        infos: dict[str, Any] = {}
        done = terminated | truncated
        if done.any():
            ended = np.flatnonzero(done)
            final_obs = np.full(self.num_envs, None, dtype=object)
            for i in ended:
                final_obs[i] = observations[i].copy()  # the row is overwritten by the reset
            infos["final_obs"], infos["_final_obs"] = final_obs, done.copy()
            infos["final_info"] = _masked(info, done)
            infos["_final_info"] = done.copy()
            self.game.reset(ended)
            self._moves[ended] = 0
            observations[ended] = self._view.observe(self.game)[ended]
        infos.update(_masked(info, ~done))
        return observations, reward, terminated, truncated, infos

    def save_state(self) -> EnvState:
        """A copy of every world's position (world, generator, the game's bookkeeping,
        the episode's step count and pending autoreset): ``restore_state`` brings it
        back into all worlds or chosen ones, which then play bitwise as they did from it.
        Cheap, for planners and rollouts from a position."""
        if not self._ready:
            raise RuntimeError("call reset() before save_state()")
        return EnvState(self.game.save_state(), self._moves.copy(), self._autoreset.copy())

    def restore_state(self, state: EnvState, worlds: Any = None) -> np.ndarray:
        """Bring back a ``save_state`` of this env into every world, or only into
        ``worlds`` (indices; the others go on as they were); returns the observations."""
        if not self._ready:
            raise RuntimeError("call reset() before restore_state()")
        if not isinstance(state, EnvState):
            raise ValueError(f"state must be an EnvState, got {type(state).__name__}")
        picked = self.game.restore_state(state.game, worlds)
        self._moves[picked] = state.moves[picked]
        self._autoreset[picked] = state.autoreset[picked]
        return self._view.observe(self.game)

    def _shoot(self, worlds: np.ndarray, actions: np.ndarray) -> tuple[Any, Any, Any]:
        """``game.shoot`` with the frames of the render mode during the shot."""
        return self.game.shoot(worlds, actions, self._frames.during_shot, self._frames.every)

    def _truncated(self, terminated: np.ndarray) -> np.ndarray:
        if self.max_episode_steps is None:
            return np.zeros(self.num_envs, dtype=bool)
        return (self._moves >= self.max_episode_steps) & ~terminated

    def _step_next(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """A NEXT_STEP vector step: the envs whose episode ended at the last step start
        their next one (their actions ignored); the others shoot."""
        starting = self._autoreset.copy()
        if starting.any():
            self.game.reset(np.flatnonzero(starting))
            self._moves[starting] = 0
        playing = np.flatnonzero(~starting)
        reward = np.zeros(self.num_envs, dtype=np.float64)
        terminated = np.zeros(self.num_envs, dtype=bool)
        infos: dict[str, Any] = {}
        if playing.size:
            shot_reward, shot_terminated, info = self._shoot(playing, actions[playing])
            reward[playing], terminated[playing] = shot_reward, shot_terminated
            self._moves[playing] += 1
            full = {}
            for key, value in info.items():
                full[key] = np.zeros((self.num_envs, *value.shape[1:]), dtype=value.dtype)
                full[key][playing] = value
            infos = _masked(full, ~starting)
        truncated = self._truncated(terminated) & ~starting
        self._autoreset = terminated | truncated
        return self._view.observe(self.game), reward, terminated, truncated, infos

    def _step_disabled(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """A DISABLED vector step: every env shoots; ended episodes wait for a reset."""
        if self._autoreset.any():
            ended = np.flatnonzero(self._autoreset).tolist()
            raise RuntimeError(
                f"envs {ended} ended their episodes and autoreset_mode is DISABLED: reset "
                "them first with reset(options={'reset_mask': mask})"
            )
        reward, terminated, info = self._shoot(self._all, actions)
        self._moves += 1
        truncated = self._truncated(terminated)
        self._autoreset = terminated | truncated
        infos = _masked(info, np.ones(self.num_envs, dtype=bool))
        return self._view.observe(self.game), reward, terminated, truncated, infos

    def render(self) -> tuple[np.ndarray, ...] | tuple[list[np.ndarray], ...] | None:
        """``rgb_array``: one frame per world, as a tuple. ``rgb_array_list``: per world,
        its frames since the last call (30 per simulated second during the shots, and
        one after each step and reset), laid out as ``SyncVectorEnv`` over single envs
        in that mode gives them. The worlds move together, so every world is drawn at
        each frame time until all are at rest, and the lists have one length. Record
        with a few worlds (e.g. ``num_envs=4``), not a training batch."""
        if self.render_mode == "rgb_array":
            return tuple(self._frames.frame(i) for i in range(self.num_envs))
        if self.render_mode == "rgb_array_list":
            return tuple(self._frames.take())
        return None

    def close_extras(self, **kwargs: Any) -> None:
        self._frames.close()


def _autoreset_mode(mode: Any) -> AutoresetMode:
    """``AutoresetMode.NEXT_STEP``, ``SAME_STEP`` or ``DISABLED``, also given as their values
    (``"NextStep"``, as Gymnasium's own vector envs take them) or names."""
    known = None
    if isinstance(mode, AutoresetMode):
        known = mode
    elif isinstance(mode, str):
        for member in AutoresetMode:
            if mode in (member.value, member.name, member.name.lower()):
                known = member
    if known is None:
        raise ValueError(
            "autoreset_mode must be AutoresetMode.NEXT_STEP, SAME_STEP or DISABLED "
            f"(or 'NextStep', 'SameStep', 'Disabled'), got {mode!r}"
        )
    return known


def _reset_mask(mask: Any, num_envs: int) -> np.ndarray:
    """``options["reset_mask"]``: a boolean array of one flag per env, some set."""
    if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_ or mask.shape != (num_envs,):
        raise ValueError(
            f"options['reset_mask'] must be a numpy bool array of shape ({num_envs},), got {mask!r}"
        )
    if not mask.any():
        raise ValueError("options['reset_mask'] must select at least one env, got none")
    return mask


def _scalars(info: dict[str, np.ndarray]) -> dict[str, Any]:
    """Info of a batch of one as plain Python values."""
    return {key: value[0].item() for key, value in info.items()}


def _masked(info: dict[str, np.ndarray], mask: np.ndarray) -> dict[str, np.ndarray]:
    """Gymnasium's vector info layout: each key with a ``_key`` mask of the envs it holds."""
    out: dict[str, np.ndarray] = {}
    for key, value in info.items():
        out[key] = np.where(mask, value, np.zeros_like(value))
        out[f"_{key}"] = mask.copy()
    return out
