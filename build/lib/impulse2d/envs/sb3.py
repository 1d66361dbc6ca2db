"""Stable-Baselines3 ``VecEnv`` adapter for natively batched Gymnasium vector envs.

SB3 trains on its own ``VecEnv`` API; ``SB3VecEnv`` puts that face on a
``gym.vector.VectorEnv`` (such as the batched Pool2D env, which steps every table in one
engine), so PPO and friends train on it directly, without one Python env per table::

    from stable_baselines3 import PPO
    from impulse2d.envs.sb3 import make_sb3_vec_env

    venv = make_sb3_vec_env("Pool2D-v0", num_envs=64, seed=0, num_balls=1)
    model = PPO("MlpPolicy", venv).learn(10_000)

It behaves like SB3's ``DummyVecEnv`` over single envs seeded the same way:

* ``seed(s)`` makes the next ``reset()`` seed env ``i`` with ``s + i`` (then forgets it);
  the same seed and the same actions give bitwise the same observations.
* ``step`` returns ``(obs, rewards float32, dones bool, infos)``, one info dict per env.
  A finished env's observation is already the first of its next episode; its info is the
  last step's, with ``terminal_observation`` and ``TimeLimit.truncated`` (truncated and
  not terminated), and its new episode's reset info goes to ``reset_infos[i]``.

SB3 resets finished envs in the step that ends them. A vector env that does so
(``AutoresetMode.SAME_STEP``) is passed through; one that resets them at the next step
(``NEXT_STEP``, Gymnasium's default) or never (``DISABLED``) has them reset at once with
``reset(options={"reset_mask": done})``, as Gymnasium's vector envs allow: the same
episodes, bitwise. ``make_sb3_vec_env`` asks the batched env for ``SAME_STEP``.

Attributes and methods live on the one batched env, not on per-env objects: ``get_attr``
returns its value once per requested index, ``env_method`` calls the method once and
repeats the result, and ``set_attr`` changes every env, so it requires all indices.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from copy import deepcopy
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.vec_env import VecVideoRecorder
from stable_baselines3.common.vec_env.base_vec_env import (
    VecEnv,
    VecEnvIndices,
    VecEnvObs,
    VecEnvStepReturn,
    tile_images,
)

__all__ = ["RecordShotVecVideo", "SB3VecEnv", "make_sb3_vec_env"]

_FINAL_KEYS = ("final_obs", "_final_obs", "final_info", "_final_info")


class SB3VecEnv(VecEnv):
    """SB3's ``VecEnv`` API over a ``gym.vector.VectorEnv`` (any autoreset mode).

    ``observation_space`` and ``action_space`` are the vector env's *single* spaces, as
    SB3 expects. See the module docstring for seeding, infos and attributes.
    """

    def __init__(self, venv: gym.vector.VectorEnv) -> None:
        mode = getattr(venv, "autoreset_mode", None)
        mode = (
            venv.metadata.get("autoreset_mode", AutoresetMode.NEXT_STEP) if mode is None else mode
        )
        try:
            mode = AutoresetMode(mode)
        except ValueError:
            raise ValueError(
                f"SB3VecEnv: unknown autoreset_mode {mode!r} of the vector env"
            ) from None
        self.same_step = mode is AutoresetMode.SAME_STEP
        self.venv = venv
        self._actions: np.ndarray | None = None
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        # SB3 knows no ``rgb_array_list``: over such a vector env this adapter is an
        # ``rgb_array`` VecEnv (``render()`` tiles each env's latest frame), and
        # ``shot_frames()`` gives every frame of the last step, tiled the same way.
        self._lists = self.render_mode == "rgb_array_list"
        self._step_frames: list[list[np.ndarray]] = [[] for _ in range(self.num_envs)]
        if self._lists:
            self.render_mode = "rgb_array"
        modes = ["human", "rgb_array"] if self._lists else self.metadata["render_modes"]
        self.metadata = {"render_modes": modes, "render_fps": venv.metadata.get("render_fps", 30)}

    # -- reset and step -----------------------------------------------------------------------
    def reset(self) -> VecEnvObs:
        """Reset every env, with the seeds and options set since the last reset (if any)."""
        seeds, options = self._seeds, self._options
        kwargs: dict[str, Any] = {}
        if any(s is not None for s in seeds):
            first = seeds[0]
            consecutive = first is not None and seeds == [first + i for i in range(self.num_envs)]
            kwargs["seed"] = first if consecutive else list(seeds)
        if any(options):
            if any(o != options[0] for o in options):
                raise ValueError("a batched vector env takes one options dict for all envs")
            kwargs["options"] = options[0]
        obs, info = self.venv.reset(**kwargs)
        self._keep_frames()
        self.reset_infos = [_env_info(info, i) for i in range(self.num_envs)]
        self._reset_seeds()
        self._reset_options()
        return _copy(obs)

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> VecEnvStepReturn:
        if self._actions is None:
            raise RuntimeError("call step_async() before step_wait()")
        actions, self._actions = self._actions, None
        obs, rewards, terminated, truncated, info = self.venv.step(actions)
        terminated = np.asarray(terminated, dtype=bool)
        truncated = np.asarray(truncated, dtype=bool)
        dones = terminated | truncated
        if not self.same_step and dones.any():
            obs, info = self._reset_finished(obs, info, dones)
        self._keep_frames()
        final_obs = info.get("final_obs")
        final_info = info.get("final_info", {})
        infos: list[dict[str, Any]] = []
        for i in range(self.num_envs):
            if dones[i]:
                env_info = _env_info(final_info, i)
                env_info["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
                if final_obs is None or not info.get("_final_obs", dones)[i]:
                    raise RuntimeError(f"env {i} ended but the vector env gave no final_obs")
                env_info["terminal_observation"] = deepcopy(final_obs[i])
                self.reset_infos[i] = _env_info(info, i)
            else:
                env_info = _env_info(info, i)
                env_info["TimeLimit.truncated"] = False
            infos.append(env_info)
        return _copy(obs), np.asarray(rewards, dtype=np.float32), dones, infos

    def _reset_finished(
        self, obs: np.ndarray, info: dict[str, Any], dones: np.ndarray
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Same-step autoreset over a NEXT_STEP or DISABLED vector env: the finished envs
        reset now, their last observation and info laid out as SAME_STEP gives them."""
        final_obs = np.full(self.num_envs, None, dtype=object)
        for i in np.flatnonzero(dones):
            final_obs[i] = np.array(obs[i], copy=True)
        fresh, reset_info = self.venv.reset(options={"reset_mask": dones.copy()})
        obs = np.array(obs, copy=True)
        obs[dones] = np.asarray(fresh)[dones]
        # The still-running envs keep their step info; the finished ones get their reset
        # info, and their step info moves to final_info.
        merged = _select(info, ~dones)
        fresh_info = _select(reset_info, dones)
        for key, value in fresh_info.items():
            if key.startswith("_") or f"_{key}" not in fresh_info:
                continue
            mask = fresh_info[f"_{key}"]
            if key in merged and f"_{key}" in merged:
                merged[key] = np.where(mask, value, merged[key])
                merged[f"_{key}"] = merged[f"_{key}"] | mask
            else:
                merged[key], merged[f"_{key}"] = value, mask
        merged.update({"final_obs": final_obs, "_final_obs": dones.copy()})
        merged.update({"final_info": info, "_final_info": dones.copy()})
        return obs, merged

    def close(self) -> None:
        self.venv.close()

    # -- rendering ----------------------------------------------------------------------------
    def get_images(self) -> Sequence[np.ndarray | None]:
        """One frame per env (``render_mode="rgb_array"`` only; else ``None`` per env)."""
        if self.render_mode != "rgb_array":
            warnings.warn(
                f"render_mode is {self.render_mode!r}; get_images() needs 'rgb_array'",
                stacklevel=2,
            )
            return [None] * self.num_envs
        if self._lists:
            return [frames[-1] if frames else None for frames in self._step_frames]
        frames = self.venv.render()
        if frames is None:
            return [None] * self.num_envs
        return list(frames)

    def shot_frames(self) -> list[np.ndarray]:
        """Every frame of the last ``step`` (or ``reset``), each the envs' frames of one
        moment tiled as ``render()`` tiles them: the motion during the shots. Needs a
        vector env made with ``render_mode="rgb_array_list"``; ``RecordShotVecVideo``
        writes these into SB3's videos."""
        if not self._lists:
            raise ValueError(
                "shot_frames() needs a vector env made with render_mode='rgb_array_list', "
                f"got render_mode={getattr(self.venv, 'render_mode', None)!r}"
            )
        moments = zip(*self._step_frames, strict=True)
        return [tile_images(list(frames)) for frames in moments]

    def _keep_frames(self) -> None:
        """rgb_array_list: hold the frames of this step (those of earlier steps go)."""
        if self._lists:
            self._step_frames = [list(frames) for frames in self.venv.render()]

    # -- attributes: they live on the one batched env ------------------------------------------
    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        """The batched env's attribute, repeated once per index (it is shared by all)."""
        value = getattr(self._owner(attr_name), attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        """Set an attribute of the batched env: that changes every env, so ``indices``
        must be None or cover all of them."""
        self._check_all(indices, "set_attr")
        try:
            owner = self._owner(attr_name)
        except AttributeError:
            owner = self.venv
        setattr(owner, attr_name, value)

    def env_method(
        self,
        method_name: str,
        *method_args: Any,
        indices: VecEnvIndices = None,
        **method_kwargs: Any,
    ) -> list[Any]:
        """Call a method of the batched env once; its result is repeated once per index."""
        result = getattr(self._owner(method_name), method_name)(*method_args, **method_kwargs)
        return [result for _ in self._get_indices(indices)]

    def env_is_wrapped(
        self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None
    ) -> list[bool]:
        """False for every index: there are no per-env ``gym.Env`` objects to wrap (the
        envs are rows of one batched env), so no ``gym.Wrapper`` (e.g. ``Monitor``) can be
        around one. Use SB3's ``VecMonitor`` for episode statistics."""
        return [False for _ in self._get_indices(indices)]

    def _owner(self, name: str) -> Any:
        """The outermost of the vector env and the envs it wraps that has ``name``."""
        env: Any = self.venv
        while True:
            if hasattr(env, name):
                return env
            if not isinstance(env, gym.vector.VectorWrapper):
                raise AttributeError(f"{type(self.venv).__name__} has no attribute {name!r}")
            env = env.env

    def _check_all(self, indices: VecEnvIndices, what: str) -> None:
        if sorted(set(self._get_indices(indices))) != list(range(self.num_envs)):
            raise ValueError(
                f"{what}: the envs share one batched env, so indices must be None or all of "
                f"0..{self.num_envs - 1}"
            )


def make_sb3_vec_env(
    env_id: str, num_envs: int, seed: int | None = None, **kwargs: Any
) -> SB3VecEnv:
    """``gym.make_vec(env_id, num_envs, vectorization_mode="vector_entry_point", **kwargs)``
    as an SB3 ``VecEnv``; with ``seed``, env ``i`` is seeded ``seed + i`` at the first
    ``reset()`` (which SB3's algorithms call)."""
    kwargs.setdefault("autoreset_mode", AutoresetMode.SAME_STEP)  # no step spent on resets
    venv = gym.make_vec(
        env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **kwargs
    )
    env = SB3VecEnv(venv)
    if seed is not None:
        env.seed(seed)
    return env


class RecordShotVecVideo(VecVideoRecorder):
    """SB3's ``VecVideoRecorder`` recording every frame of each step (the envs tiled, from
    ``SB3VecEnv.shot_frames()``), where the recorder itself takes one frame a step: over
    ``make_sb3_vec_env(..., render_mode="rgb_array_list")``, videos show the shots."""

    def _capture_frame(self) -> None:
        try:
            shot_frames = self.env.shot_frames  # found through VecEnv wrappers too
        except AttributeError:
            raise ValueError(
                "RecordShotVecVideo needs an SB3VecEnv (make_sb3_vec_env) of a vector env "
                "made with render_mode='rgb_array_list'"
            ) from None
        self.recorded_frames += shot_frames()


def _select(info: dict[str, Any], envs: np.ndarray) -> dict[str, Any]:
    """``info`` (Gymnasium's vector layout) with every ``_key`` mask limited to ``envs``."""
    out: dict[str, Any] = {}
    for key, value in info.items():
        is_mask = key.startswith("_") and key[1:] in info
        out[key] = np.asarray(value, dtype=bool) & envs if is_mask else value
    return out


def _env_info(info: dict[str, Any], i: int) -> dict[str, Any]:
    """Env ``i``'s info from Gymnasium's vector layout: the keys whose ``_key`` mask holds
    ``i`` (recursively for nested dicts), numpy scalars as Python values. The final
    observation and info of finished envs are left out (``step_wait`` places them)."""
    out: dict[str, Any] = {}
    for key, value in info.items():
        if key in _FINAL_KEYS or (key.startswith("_") and key[1:] in info):
            continue  # the final entries, and the masks
        mask = info.get(f"_{key}")
        if mask is None or not mask[i]:
            continue
        if isinstance(value, dict):
            out[key] = _env_info(value, i)
        else:
            item = value[i]
            out[key] = item.item() if isinstance(item, np.generic) else deepcopy(item)
    return out


def _copy(obs: Any) -> Any:
    """A copy of a batch of observations (a vector env may reuse its buffers)."""
    if isinstance(obs, dict):
        return {key: _copy(value) for key, value in obs.items()}
    if isinstance(obs, tuple):
        return tuple(_copy(value) for value in obs)
    return np.array(obs, copy=True)
