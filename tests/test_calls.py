"""``agents.calls``: a one-ball agent's first calls against the ghost-ball player's
pocket, on the evaluation's tables."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from agents import calls, train

from impulse2d.envs import baselines, bestshots, pool


def _run(tmp_path: Path, env: str) -> Path:
    argv = [
        "--env", env, "--timesteps", "16", "--num-envs", "4", "--seed", "0",
        "--run-dir", str(tmp_path / env), "--no-progress-bar", "--no-evaluate",
        "--hyperparams", "n_steps=4", "batch_size=16", "n_epochs=1", "pretrain_encoder=null",
    ]  # fmt: skip
    return train.main(argv)


@pytest.mark.parametrize("env", ["Pool2DCallShot-v0", "Pool2DPixelsCallShot-v0"])
def test_first_calls_and_the_ghost_ball_players_pocket(tmp_path: Path, env: str) -> None:
    """The same tables for the state and the pixel task (frames fed channels first)."""
    run = _run(tmp_path, env)
    out = calls.first_calls(run, tables=20, seed=1000)
    assert out["called"].shape == out["ghost"].shape == out["clear"].shape == (20,)
    assert ((0 <= out["called"]) & (out["called"] < 6)).all()
    # the ghost pocket is the scripted player's best clear shot, table by table
    for i in range(20):
        game = pool.PoolGame(1, num_balls=1, layout="random")
        game.seed([0], [1000 + i])
        game.reset([0])
        row = game.observe()
        scripted = baselines.pool_shots(row[0])
        if scripted:
            best = max(s[0] for s in scripted)
            score = bestshots.table_shots(row)["score"][0, out["ghost"][i]]
            assert score == pytest.approx(best, rel=1e-9)
    text = calls.table([str(run)], tables=20)
    counts = [int(c) for c in text.splitlines()[2].split("|")[2].split()]
    assert sum(counts) == 20 and "best fixed pocket" in text
    fixed = int(np.bincount(out["ghost"], minlength=6).max())
    assert f"| best fixed pocket | | {fixed}/20 | |" in text


def test_runs_of_other_tasks_and_bad_counts_are_refused(tmp_path: Path) -> None:
    run = _run(tmp_path, "Slingshot2DCallShot-v0")
    with pytest.raises(ValueError, match="run_dir: a run of one of"):
        calls.first_calls(run)
    with pytest.raises(ValueError, match="tables"):
        calls.first_calls(run, tables=0)
