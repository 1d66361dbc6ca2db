"""Sweeps on Ray Tune: two tiny trials run locally (Ray starts itself), each the run
``agents.train`` gives with that seed, and one table and one plot over them."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("ray.tune")

from agents import sweep

ROOT = Path(__file__).resolve().parents[1]
SHORT = '{"max_shot_seconds": 2.0}'
TINY = ["n_steps=8", "batch_size=16", "n_epochs=2"]


def test_two_tiny_trials_are_the_runs_agents_train_gives(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    done = subprocess.run(
        [sys.executable, "-m", "agents.sweep", "--env", "Pool2DCallShot-v0", "--algo", "ppo",
         "--seeds", "0", "--search", "learning_rate=3e-4,1e-3", "--timesteps", "64",
         "--num-envs", "4", "--env-kwargs", SHORT, "--hyperparams", *TINY,
         "--eval-episodes", "3", "--cpus-per-trial", "1", "--out", str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads((out / "sweep.json").read_text())
    trials = report["trials"]
    assert [(t["seed"], t["setting"]) for t in trials] == [
        (0, {"learning_rate": 3e-4}),
        (0, {"learning_rate": 1e-3}),
    ]
    table = (out / "sweep.md").read_text()
    assert "learning_rate=0.0003" in table and "learning_rate=0.001" in table
    assert (out / "sweep.png").stat().st_size > 10_000
    # Each trial is the run the training command gives with its seed and values (run as
    # a command: both then name torch's kernels before torch loads).
    for trial in trials:
        run_dir = tmp_path / f"direct_{trial['setting']['learning_rate']}"
        direct = subprocess.run(
            [sys.executable, "-m", "agents.train", "--timesteps", "64", "--num-envs", "4",
             "--seed", "0", "--run-dir", str(run_dir), "--env-kwargs", SHORT,
             "--no-progress-bar", "--eval-episodes", "3", "--hyperparams", *TINY,
             f"learning_rate={trial['setting']['learning_rate']}"],
            cwd=ROOT, capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        assert direct.returncode == 0, direct.stderr[-2000:]
        results = json.loads((run_dir / "results.json").read_text())
        assert results["policies"] == trial["policies"]
        assert Path(trial["run_dir"], "model.zip").is_file()
    assert trials[0]["policies"]["trained"] != trials[1]["policies"]["trained"]


def test_seeds_and_search_values_are_read_and_checked() -> None:
    assert sweep.parse_seeds("0-3") == [0, 1, 2, 3]
    assert sweep.parse_seeds("0-2,9,1") == [0, 1, 2, 9]
    for bad in ("x", "3-1", "-1", "1-"):
        with pytest.raises(ValueError, match="seeds must"):
            sweep.parse_seeds(bad)
    space = sweep.parse_search(["learning_rate=3e-4,1e-3", "gamma=0.5,0.9,0.99"])
    assert space == {"learning_rate": [3e-4, 1e-3], "gamma": [0.5, 0.9, 0.99]}
    assert len(sweep.settings(space)) == 6 and sweep.settings({}) == [{}]
    with pytest.raises(ValueError, match="search must be key=v1,v2"):
        sweep.parse_search(["learning_rate"])


def test_a_bad_searched_value_fails_before_ray_starts(tmp_path: Path) -> None:
    spec = {
        "env_id": "Pool2DCallShot-v0", "algo": "ppo", "config_file": None, "timesteps": 64,
        "num_envs": 4, "env_kwargs": {}, "overrides": {}, "eval_episodes": 1,
        "cpus_per_trial": 1,
    }  # fmt: skip
    with pytest.raises(ValueError, match="not_a_ppo_argument"):
        sweep.sweep(spec, [0], {"not_a_ppo_argument": [1]}, tmp_path)


def test_a_trial_is_the_shipped_entry_with_the_seed_and_setting() -> None:
    spec = {
        "env_id": "Slingshot2DGeneratedCallShot-v0", "algo": "ppo", "config_file": None,
        "timesteps": 64, "num_envs": 4, "env_kwargs": {}, "overrides": {},
    }  # fmt: skip
    config = sweep.trial_config(spec, 3, {"gamma": 0.5})
    assert config["env_id"] == config["entry"] == "Slingshot2DGeneratedCallShot-v0"
    assert config["seed"] == 3 and config["hyperparams"]["gamma"] == 0.5
    assert config["eval_env_kwargs"]["start_level"] > 0  # scored on levels it never saw
