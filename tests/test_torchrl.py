"""TorchRL over the envs, as its users wrap them: ``GymEnv`` on an id and ``GymWrapper``
on the batched vector env (TorchRL takes DISABLED, its preferred mode, or SAME_STEP
autoreset, as docs/envs/index.md says)."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch
from gymnasium.vector import AutoresetMode
from torchrl.envs import GymWrapper
from torchrl.envs.libs.gym import GymEnv
from torchrl.envs.utils import check_env_specs

import impulse2d  # noqa: F401  (registers the ids)


@pytest.mark.parametrize("env_id", ["Pool2DOneBall-v0", "Pool2DCallShot-v0"])
def test_gym_env_on_an_id_plays_an_episode_to_its_end(env_id):
    env = GymEnv(env_id)
    check_env_specs(env)
    torch.manual_seed(0)
    rollout = env.rollout(20)  # stops at the episode's end: five shots at most
    assert 1 <= rollout.shape[0] <= 5 and bool(rollout[-1]["next", "done"])
    assert torch.isfinite(rollout["next", "observation"]).all()


@pytest.mark.parametrize("env_id", ["Pool2DOneBall-v0", "Pool2DCallShot-v0"])
@pytest.mark.parametrize("mode", [AutoresetMode.DISABLED, AutoresetMode.SAME_STEP])
def test_gym_wrapper_on_the_batched_vector_env_goes_through_resets(env_id, mode):
    venv = gym.make_vec(env_id, 4, vectorization_mode="vector_entry_point",
                        autoreset_mode=mode)  # fmt: skip
    env = GymWrapper(venv)
    assert tuple(env.batch_size) == (4,)
    check_env_specs(env)
    torch.manual_seed(0)
    rollout = env.rollout(12, break_when_any_done=False)
    assert tuple(rollout.shape) == (4, 12)
    assert int(rollout["next", "done"].sum()) >= 4  # every table finished an episode
    assert torch.isfinite(rollout["next", "observation"]).all()


def test_torchrl_names_the_mode_it_needs():
    venv = gym.make_vec("Pool2DOneBall-v0", 2, vectorization_mode="vector_entry_point")
    with pytest.raises(RuntimeError, match="DISABLED"):
        GymWrapper(venv)  # NEXT_STEP, the default: TorchRL says what to choose
