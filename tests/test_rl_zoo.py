"""RL Baselines3 Zoo trains and evaluates the call-shot tasks from their ids and the
project's hyperparameter file, as the command of docs/training.md does (small budgets through the
Zoo's own ``-n`` and ``-params``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

CONFIG = Path(__file__).resolve().parents[1] / "agents" / "hyperparams" / "rl_zoo" / "ppo.yml"


@pytest.mark.parametrize("env_id", ["Pool2DCallShot-v0", "Slingshot2DCallShot-v0"])
def test_rl_zoo_trains_and_evaluates_a_variant(env_id, tmp_path):
    command = [
        sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", env_id,
        "--gym-packages", "impulse2d", "-conf", str(CONFIG), "-f", str(tmp_path),
        "--seed", "0", "-n", "256", "--eval-freq", "64", "--eval-episodes", "2",
        "-params", "n_envs:4", "--log-interval", "-1",
    ]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    run = tmp_path / "ppo" / f"{env_id}_1"
    assert (run / f"{env_id}.zip").is_file()
    evaluations = np.load(run / "evaluations.npz")
    assert evaluations["results"].shape[1] == 2  # the evaluation env played its episodes
    assert np.isfinite(evaluations["results"]).all()


def test_rl_zoo_learns_the_call_shot_task_to_twice_random(tmp_path):
    """RL Zoo, from the id and the project's file alone, with a small budget (6,144 shots
    on 16 Python envs): the saved agent, played deterministically on 100 seeded episodes,
    scores at least twice what uniform random call-shot actions score on the same ones."""
    from agents._tasks import play_episodes
    from stable_baselines3 import PPO

    env_id = "Pool2DCallShot-v0"
    command = [
        sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", env_id,
        "--gym-packages", "impulse2d", "-conf", str(CONFIG), "-f", str(tmp_path),
        "--seed", "0", "-n", "6144", "--eval-freq", "-1", "--log-interval", "-1",
    ]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, timeout=900, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    model = PPO.load(tmp_path / "ppo" / f"{env_id}_1" / f"{env_id}.zip", device="cpu")
    trained = play_episodes(
        env_id, {}, lambda obs: model.predict(obs, deterministic=True)[0], 100, 1000
    )
    rng = np.random.default_rng(1000)
    random = play_episodes(
        env_id, {}, lambda obs: rng.uniform(-1, 1, (len(obs), 8)).astype(np.float32), 100, 1000
    )
    assert random["return"].mean() > 0.05  # a positive bar: twice it means something
    assert trained["return"].mean() >= 2 * random["return"].mean()
