"""RL Baselines3 Zoo trains and evaluates the learnable variants from their ids and the
project's hyperparameter file, as the README's command does (small budgets through the
Zoo's own ``-n`` and ``-params``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

CONFIG = Path(__file__).resolve().parents[1] / "agents" / "hyperparams" / "rl_zoo" / "ppo.yml"


@pytest.mark.parametrize("env_id", ["Pool2DOneBall-v0", "Slingshot2DHandmade-v0"])
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
