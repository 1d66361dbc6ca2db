"""The agents package: smoke training of each algorithm on each env, the run directory's
files, resuming, determinism, the evaluation's outputs and bad input.

Budgets are tiny (a few worlds, shots capped at 2 s of simulated time, 64-128 steps): the
point is that every piece runs and writes what it promises, not that the agent learns.
"""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

pytest.importorskip("stable_baselines3")

from agents import _config, evaluate, train

ROOT = Path(__file__).resolve().parents[1]
SHORT = '{"max_shot_seconds": 2.0}'  # short shots: the tests time the code, not the physics
# Tiny versions of each algorithm's settings (the YAML's values otherwise). A constant
# learning rate: under a lin_ schedule a run's last update has rate 0 (SB3 updates at the
# progress reached after the rollout), and a tiny run has only one or two.
TINY = {
    "ppo": ["n_steps=8", "batch_size=16", "n_epochs=2", "learning_rate=3e-4"],
    "sac": ["learning_starts=16", "gradient_steps=2", "batch_size=16", "buffer_size=500"],
}
EXPECTED_COLUMNS = {
    "Pool2DCallShot-v0": ["reward / episode", "potted / episode", "potted / shot", "fouls / shot"],
    "Slingshot2DCallShot-v0": [
        "reward / episode",
        "pigs destroyed / episode",
        "birds used / episode",
    ],
}


def _train(
    run_dir: Path, env: str = "Pool2DCallShot-v0", algo: str = "ppo", steps: int = 64, *extra: str
) -> Path:
    argv = [
        "--env", env, "--algo", algo, "--timesteps", str(steps), "--num-envs", "4",
        "--seed", "0", "--run-dir", str(run_dir), "--env-kwargs", SHORT,
        "--no-progress-bar", "--no-evaluate", "--hyperparams", *TINY[algo], *extra,
    ]  # fmt: skip
    return train.main(argv)


def _progress(run_dir: Path) -> list[dict[str, str]]:
    with open(run_dir / "progress.csv", newline="") as file:
        return list(csv.DictReader(file))


def test_the_pixel_task_trains_its_cnn_on_the_frames(tmp_path: Path) -> None:
    """Pool2DPixelsCallShot-v0 trains agents._cnn.ShotCNN on 64 x 64 frames (SB3 puts
    channels first), and its evaluation plays the agent on frames, the others on state."""
    from agents import evaluate
    from agents._cnn import ShotCNN

    # the entry's pretraining, shrunk (its 65,536 frames take minutes)
    tiny = "pretrain_encoder={frames: 64, epochs: 1}"
    run_dir = _train(tmp_path / "run", "Pool2DPixelsCallShot-v0", "ppo", 32, tiny)
    model = _config.algo_class("ppo").load(str(run_dir / "model.zip"), device="cpu")
    assert isinstance(model.policy.features_extractor, ShotCNN)
    assert model.observation_space.shape == (3, 64, 64)
    assert (run_dir / "pretrain.json").is_file()
    results = evaluate.evaluate(run_dir, episodes=4, video=None)
    assert set(results["policies"]) == {"trained", "random", "scripted", "random_call_shot"}
    # the scripted player read positions: it pots as it does on the state task
    assert results["policies"]["scripted"]["potted"]["mean"] >= 0.75


def _params(run_dir: Path, algo: str) -> list[np.ndarray]:
    model = _config.algo_class(algo).load(str(run_dir / "model.zip"), device="cpu")
    return [p.detach().numpy().copy() for p in model.policy.parameters()]


@pytest.mark.parametrize("env", ["Pool2DCallShot-v0", "Slingshot2DCallShot-v0"])
@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_smoke_training_writes_the_run_directory(tmp_path: Path, env: str, algo: str) -> None:
    run_dir = _train(tmp_path / "run", env, algo, 64)
    for name in ("model.zip", "config.yml", "command.txt", "progress.csv", "monitor.csv"):
        assert (run_dir / name).is_file(), name
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    assert config["env_id"] == env and config["algo"] == algo and config["n_envs"] == 4
    # The YAML's env arguments (none: the id has its own), with the command line's on top.
    assert config["env_kwargs"] == {"max_shot_seconds": 2.0}
    assert config["hyperparams"]["batch_size"] == 16
    command = (run_dir / "command.txt").read_text()
    assert command.startswith("python -m agents.train ") and f"--algo {algo}" in command
    summary = json.loads((run_dir / "training.json").read_text())
    assert summary["num_timesteps"] >= 64
    rows = _progress(run_dir)
    # PPO logs after every rollout, so its last row is the end; SAC logs every few
    # episodes, so its last row may be a little before it.
    last = int(float(rows[-1]["time/total_timesteps"])) if rows else 0
    assert 0 < last <= summary["num_timesteps"]
    if algo == "ppo":
        assert last == summary["num_timesteps"]
    assert int(float(rows[-1]["train/n_updates"])) > 0  # the networks were trained
    try:
        import tensorboard  # noqa: F401

        assert any((run_dir / "tb").iterdir())
    except ImportError:
        pass


def test_same_seed_trains_the_same_network(tmp_path: Path) -> None:
    a = _params(_train(tmp_path / "a", steps=32), "ppo")
    b = _params(_train(tmp_path / "b", steps=32), "ppo")
    c = _params(_train(tmp_path / "c", "Pool2DCallShot-v0", "ppo", 32, "--seed", "1"), "ppo")
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    assert not all(np.array_equal(x, z) for x, z in zip(a, c, strict=True))


def test_resume_continues_the_timesteps_and_the_log(tmp_path: Path) -> None:
    first = _train(tmp_path / "run", steps=64)
    before = json.loads((first / "training.json").read_text())["num_timesteps"]
    params = _params(first, "ppo")
    # No --env, --algo, --num-envs or --env-kwargs: a resumed run keeps its own settings.
    argv = ["--timesteps", "32", "--resume", str(first / "model.zip"), "--no-progress-bar",
            "--no-evaluate"]  # fmt: skip
    run_dir = train.main(argv)
    assert run_dir == first  # by default a resumed run goes on in its own directory
    after = json.loads((run_dir / "training.json").read_text())
    assert after["num_timesteps"] == before + 32 and after["steps_this_run"] == 32
    steps = [int(float(row["time/total_timesteps"])) for row in _progress(run_dir)]
    assert steps == sorted(steps) and steps[0] <= before and steps[-1] == before + 32
    assert any(s <= before for s in steps) and any(s > before for s in steps)
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    assert config["resumed_from"].endswith("model.zip")
    assert config["resumed_at_timesteps"] == before
    assert config["n_envs"] == 4 and config["env_kwargs"]["max_shot_seconds"] == 2.0
    moved = _params(run_dir, "ppo")
    assert not all(np.array_equal(x, y) for x, y in zip(params, moved, strict=True))


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    run_dir = _train(tmp_path_factory.mktemp("eval") / "run", steps=32)
    results = evaluate.evaluate(run_dir, episodes=6, seed=1000, video="gif", video_shots=2)
    return run_dir, results


def test_evaluation_writes_the_table_curve_and_video(evaluated: tuple[Path, Any]) -> None:
    run_dir, results = evaluated
    on_disk = json.loads((run_dir / "results.json").read_text())
    assert on_disk == json.loads(json.dumps(results))
    assert set(on_disk["policies"]) == {"trained", "random", "scripted", "random_call_shot"}
    for row in on_disk["policies"].values():
        assert set(row) == set(on_disk["metrics"])
        assert all(set(cell) == {"mean", "std"} for cell in row.values())
    assert on_disk["episodes"] == 6 and on_disk["episode_seeds"] == [1000, 1005]
    assert set(on_disk["targets"]) == {
        "beats_random_2x", "half_of_scripted", "pots_half_of_scripted", "matches_scripted",
    }  # fmt: skip
    # Random actions of the call-shot id's own space are played on the id: 8 numbers.
    assert on_disk["policies"]["random_call_shot"]["shots"]["mean"] >= 1
    # The scripted player pots nearly every ball; the table must show it.
    scripted, random = on_disk["policies"]["scripted"], on_disk["policies"]["random"]
    assert scripted["potted"]["mean"] > random["potted"]["mean"]
    table = (run_dir / "results.md").read_text().splitlines()
    header = next(line for line in table if line.startswith("| policy |"))
    columns = [c.strip() for c in header.strip("|").split("|")][1:5]
    assert columns == EXPECTED_COLUMNS["Pool2DCallShot-v0"]
    rows = [line for line in table if line.startswith("| ") and "---" not in line][1:]
    assert [r.split("|")[1].strip() for r in rows] == [
        "trained PPO", "random", "scripted (ghost ball)", "random call-shot actions",
    ]  # fmt: skip
    assert all(len(r.strip("|").split("|")) == len(on_disk["metrics"]) + 1 for r in rows)
    assert (run_dir / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import imageio.v3 as iio

    frames = iio.imread(run_dir / "agent.gif")
    # The GIF encoder merges identical consecutive frames (the balls at rest), so the file
    # may hold fewer frames than were rendered, never more.
    assert frames.ndim == 4 and 2 < frames.shape[0] <= on_disk["video_frames"]


def test_evaluation_is_deterministic(evaluated: tuple[Path, Any]) -> None:
    run_dir, results = evaluated
    again = evaluate.evaluate(run_dir, episodes=6, seed=1000, video=None)
    assert again["policies"] == results["policies"]


def test_summary_over_runs(evaluated: tuple[Path, Any], tmp_path: Path) -> None:
    run_dir, results = evaluated
    out = tmp_path / "summary.md"
    plot = tmp_path / "curves.png"
    argv = ["--summarize", str(run_dir), str(run_dir), "--out", str(out), "--plot", str(plot)]
    table = evaluate.main(argv)
    assert out.read_text() == table
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "2 training seeds (0, 0)" in table
    trained = next(line for line in table.splitlines() if line.startswith("| trained PPO"))
    mean = results["policies"]["trained"]["reward"]["mean"]
    assert trained.split("|")[2].strip() == f"{mean:.2f} ± 0.00"  # two equal runs: std 0
    assert "beats_random_2x: met in" in table
    with pytest.raises(ValueError, match=r"^summarize: .* has no results\.json"):
        evaluate.summarize_runs([tmp_path])


@pytest.mark.parametrize("env", ["Slingshot2DCallShot-v0", "Slingshot2DBlocksCallShot-v0"])
def test_slingshot_metrics_in_the_table(tmp_path: Path, env: str) -> None:
    """Both slingshot games (boxes, and boxes with triangles and stones) are scored on
    the slingshot's metrics against the ballistic player."""
    run_dir = _train(tmp_path / "run", env, "ppo", 32)
    results = evaluate.evaluate(run_dir, episodes=3, seed=0, video=None)
    labels = [spec["label"] for spec in results["metrics"].values()]
    assert all(label in labels for label in EXPECTED_COLUMNS["Slingshot2DCallShot-v0"])
    assert results["scripted"] == "ballistic" and "scripted" in results["policies"]
    for row in results["policies"].values():
        # Three birds: an episode uses one to three of them (it ends when a level is clear).
        assert 1.0 <= row["birds_used"]["mean"] <= 3.0
        assert 0.0 <= row["cleared"]["mean"] <= 1.0


def _shipped_entries() -> list[tuple[str, str]]:
    return [
        (algo, entry)
        for algo in ("ppo", "sac")
        for entry in yaml.safe_load((_config.HYPERPARAMS_DIR / f"{algo}.yml").read_text())
    ]


@pytest.mark.parametrize(("algo", "env"), _shipped_entries())
def test_shipped_hyperparameters_resolve(algo: str, env: str) -> None:
    config = _config.resolve(algo, env)
    assert config["entry"] == env and config["env_id"] == env.partition("/")[0]
    assert config["n_timesteps"] > 0 and config["n_envs"] > 0
    from impulse2d.envs import base_game

    # Image tasks take the CNN policy, every other task the MLP one.
    pixels = base_game(config["env_id"])[1].get("obs_type") == "pixels"
    assert "env_kwargs" in config and config["policy"] == ("CnnPolicy" if pixels else "MlpPolicy")
    assert "gamma" in config["hyperparams"]
    built = _config.algo_kwargs(config)["policy_kwargs"]
    assert ("features_extractor_class" in built) == pixels


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--env", "Pong-v0"], "env must be one of"),
        (["--algo", "dqn"], "algo must be one of"),
        (["--timesteps", "0"], "timesteps must be > 0"),
        (["--timesteps", "-5"], "timesteps must be > 0"),
        (["--timesteps", "lots"], "timesteps must be a positive number"),
        (["--timesteps", "2.5"], "timesteps must be a positive whole number"),
        (["--num-envs", "0"], "num_envs must be > 0"),
        (["--env-kwargs", "{num_balls: 1}"], "env_kwargs must be a JSON object"),
        (["--env-kwargs", "[1]"], "env_kwargs must be a JSON object"),
        (
            ["--hyperparams", "learning_rat=0.1"],
            "hyperparams: PPO has no parameter(s) ['learning_rat']",
        ),
        (["--hyperparams", "gamma"], "hyperparams must be key=value"),
        (["--config", "/nonexistent.yml"], "config: no such file"),
        (["--resume", "/nonexistent/model.zip"], "resume: no model file"),
        (["--seed", "-1"], "seed must be an int >= 0"),
        (
            ["--hyperparams", "policy_kwargs={features_extractor_class: ResNet}"],
            "policy_kwargs.features_extractor_class must be one of "
            "('NatureCNN', 'ShotCNN', 'KeypointCNN')",
        ),
    ],
)
def test_bad_training_input_names_the_parameter(
    tmp_path: Path, argv: list[str], message: str
) -> None:
    with pytest.raises(ValueError, match="^" + _escape(message)):
        train.main([*argv, "--run-dir", str(tmp_path / "run"), "--no-evaluate"])
    assert not (tmp_path / "run" / "model.zip").exists()


def test_linear_schedule_falls_from_its_start_to_zero(tmp_path: Path) -> None:
    config = _config.resolve(
        "ppo",
        "Pool2DCallShot-v0",
        overrides={"learning_rate": "lin_1e-3", "clip_range": "lin_0.2"},
    )
    assert config["hyperparams"]["learning_rate"] == "lin_1e-3"  # plain YAML in config.yml
    kwargs = _config.algo_kwargs(config)
    rate, clip = kwargs["learning_rate"], kwargs["clip_range"]
    assert [rate(p) for p in (1.0, 0.5, 0.0)] == [1e-3, 5e-4, 0.0]
    assert clip(0.25) == 0.05
    # In training, SB3 applies it at each update: 64 steps of 4 worlds x n_steps 8 are two
    # updates, after 32 steps (progress left 0.5) and after 64 (0). progress.csv logs an
    # update's values in the row written after it: the first update's rate, 5e-4.
    run = _train(tmp_path / "run", "Pool2DCallShot-v0", "ppo", 64, "learning_rate=lin_1e-3")
    logged = [row["train/learning_rate"] for row in _progress(run)]
    assert [float(value) for value in logged if value] == [5e-4]
    assert yaml.safe_load((run / "config.yml").read_text())["hyperparams"]["learning_rate"] == (
        "lin_1e-3"
    )


@pytest.mark.parametrize("value", ["lin_-1", "lin_x", "exp_1e-3", 0, -0.1, True])
def test_bad_schedule_names_the_key_and_rule(value: Any) -> None:
    with pytest.raises(ValueError, match=r"^learning_rate must be"):
        _config.resolve("ppo", "Pool2DCallShot-v0", overrides={"learning_rate": value})


def test_resume_refuses_another_algorithm(tmp_path: Path) -> None:
    first = _train(tmp_path / "run", steps=32)
    with pytest.raises(
        ValueError, match=r"^resume: the model is ppo on Pool2DCallShot-v0, not sac"
    ):
        train.main(["--resume", str(first), "--algo", "sac", "--no-evaluate"])


def test_bad_env_kwargs_fail_in_the_env(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="num_balls"):
        _train(tmp_path / "run", "Pool2DCallShot-v0", "ppo", 16, "--env-kwargs", '{"num_balls": 0}')


def test_bad_evaluation_input(tmp_path: Path, evaluated: tuple[Path, Any]) -> None:
    with pytest.raises(ValueError, match=r"^run_dir: .* has no config\.yml"):
        evaluate.evaluate(tmp_path)
    run_dir, _ = evaluated
    with pytest.raises(ValueError, match=r"^episodes must be > 0"):
        evaluate.evaluate(run_dir, episodes=0)
    with pytest.raises(ValueError, match=r"^video must be"):
        evaluate.evaluate(run_dir, episodes=1, video="avi")


def test_command_line_reports_bad_input_in_one_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "agents.train", "--env", "Pong-v0"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode != 0
    assert done.stderr.strip().splitlines()[-1].startswith("error: env must be one of")
    assert "Traceback" not in done.stderr


def test_training_into_a_log_prints_progress_lines_with_shots_per_second(tmp_path) -> None:
    """Output to a pipe (a log, CI, a notebook): plain progress lines, no redrawn bar."""
    done = subprocess.run(
        [sys.executable, "-m", "agents.train", "--timesteps", "64", "--num-envs", "4",
         "--run-dir", str(tmp_path / "run"), "--env-kwargs", SHORT, "--no-evaluate",
         "--hyperparams", *TINY["ppo"]],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stdout.splitlines() if line.startswith("progress ")]
    assert lines, done.stdout
    assert re.search(r"64/64 shots \(100%\)  [\d,]+ shots/s", lines[-1]), lines[-1]
    assert "\r" not in done.stdout + done.stderr  # no bar redrawn into the log


def _escape(text: str) -> str:
    import re

    return re.escape(text)


VARIANT = "Slingshot2DGeneratedCallShot-v0/small"
VARIANT_YAML = """
Slingshot2DGeneratedCallShot-v0/small:
  n_timesteps: 32
  n_envs: 4
  env_kwargs: {num_levels: 10}
  eval_env_kwargs: {start_level: 1000}
  policy: MlpPolicy
  n_steps: 8
  batch_size: 32
"""


def test_variant_entries_name_their_env_and_run_directory(tmp_path: Path) -> None:
    path = tmp_path / "ppo.yml"
    path.write_text(VARIANT_YAML)
    config = _config.resolve("ppo", VARIANT, config_file=path)
    assert config["env_id"] == "Slingshot2DGeneratedCallShot-v0" and config["entry"] == VARIANT
    assert config["env_kwargs"] == {"num_levels": 10}
    assert config["eval_env_kwargs"] == {"start_level": 1000}
    assert train.default_run_dir(config["entry"], "ppo", 3) == Path(
        "runs/Slingshot2DGeneratedCallShot-v0-small_ppo_seed3"
    )
    for bad in ("Pong-v0/generated", "Slingshot2D-v0/", "Slingshot2D-v0/a b", 7):
        with pytest.raises(ValueError, match=r"^env must be one of .* followed by /<variant>"):
            _config.resolve("ppo", bad, config_file=path)
    with pytest.raises(ValueError, match=r"has no entry for .Slingshot2D-v0/other."):
        _config.resolve("ppo", "Slingshot2D-v0/other", config_file=path)
    with pytest.raises(ValueError, match=r"^eval_env_kwargs must be a mapping"):
        _config.resolve(
            "ppo", VARIANT, config_file=path, overrides={"eval_env_kwargs": [1]},
        )  # fmt: skip


def test_evaluation_plays_the_eval_env_kwargs_over_the_training_ones(tmp_path: Path) -> None:
    from agents._tasks import play_episodes, summarize, task

    from impulse2d.envs.baselines import slingshot_ballistic

    path = tmp_path / "ppo.yml"
    path.write_text(VARIANT_YAML)
    run_dir = _train(tmp_path / "run", VARIANT, "ppo", 32, "--config", str(path))
    assert yaml.safe_load((run_dir / "config.yml").read_text())["entry"] == VARIANT
    results = evaluate.evaluate(
        run_dir, episodes=3, seed=5, video=None, env_kwargs={"num_birds": 1}
    )
    trained_on = {"num_levels": 10, **json.loads(SHORT)}
    played = {**trained_on, "start_level": 1000, "num_birds": 1}
    assert results["env_kwargs"] == played
    assert results["train_env_kwargs"] == trained_on
    assert results["entry"] == VARIANT
    # The scripted row is that of the held-out levels with one bird, not the training ones:
    # the game under the id, its arguments and episode length, with those on top.
    game = {"level": "random", "max_episode_steps": 10, **played}
    direct = summarize(task("Slingshot2D-v0"), play_episodes(
        "Slingshot2D-v0", game, slingshot_ballistic, 3, 5
    ))  # fmt: skip
    assert results["policies"]["scripted"] == direct
    assert results["policies"]["scripted"]["birds_used"]["mean"] == 1.0


def test_bad_evaluation_env_kwargs_fail_before_training(tmp_path: Path) -> None:
    path = tmp_path / "ppo.yml"
    path.write_text(VARIANT_YAML.replace("start_level: 1000", "start_level: -1"))
    with pytest.raises(ValueError, match=r"^start_level must be an int >= 0, got -1"):
        _train(tmp_path / "run", VARIANT, "ppo", 32, "--config", str(path))
    assert not (tmp_path / "run" / "model.zip").exists()
    with pytest.raises(ValueError, match=r"^env_kwargs must be a mapping"):
        evaluate.evaluate(tmp_path, env_kwargs=[("level", "random")])


def test_targets_compare_the_trained_agent_with_the_named_player() -> None:
    from agents._tasks import task

    def rows(**means: tuple[float, float, float]) -> dict[str, Any]:
        keys = ("reward", "potted", "potted_per_shot")
        return {p: {k: {"mean": v, "std": 0.0} for k, v in zip(keys, m, strict=True)}
                for p, m in means.items()}  # fmt: skip

    # reward, potted / episode, potted / shot
    got = evaluate._targets(task("Pool2D-v0"), rows(
        trained=(0.95, 0.9, 0.05), random=(-1.8, 0.1, 0.03), scripted=(0.93, 1.0, 0.8)
    ))  # fmt: skip
    assert {name: t["met"] for name, t in got.items()} == {
        "beats_random_2x": False,  # 0.05 pots a shot < 2 x 0.03
        "half_of_scripted": True,
        "pots_half_of_scripted": True,
        "matches_scripted": True,  # 0.95 >= 0.93
    }
    assert got["beats_random_2x"]["needed"] == pytest.approx(0.06)
    assert got["matches_scripted"]["needed"] == pytest.approx(0.93)
    got = evaluate._targets(task("Pool2D-v0"), rows(
        trained=(0.4, 0.3, 0.0), random=(-1.8, 0.1, 0.0), scripted=(0.93, 1.0, 0.8)
    ))  # fmt: skip
    assert not got["beats_random_2x"]["met"]  # 0 >= 2 x 0, but twice nothing is no bar
    assert not got["pots_half_of_scripted"]["met"] and not got["matches_scripted"]["met"]


def test_initial_action_starts_ppo_at_that_shot(tmp_path: Path) -> None:
    """``initial_action`` sets PPO's mean action before training: the untrained policy
    plays it (within SB3's small initial weights) on any observation."""
    prior = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.6]
    small = {"n_steps": 4, "batch_size": 16}
    config = _config.resolve(
        "ppo", "Pool2DCallShot-v0", num_envs=4, overrides={**small, "initial_action": prior}
    )
    model = train.build(config, tmp_path / "run").model
    obs = np.random.default_rng(0).uniform(-1, 1, (32, *model.observation_space.shape))
    actions, _ = model.predict(obs.astype(np.float32), deterministic=True)
    np.testing.assert_allclose(actions, np.broadcast_to(prior, actions.shape), atol=0.1)
    plain = train.build(
        _config.resolve("ppo", "Pool2DCallShot-v0", num_envs=4, overrides=small), tmp_path / "b"
    )
    untrained = plain.model.predict(obs.astype(np.float32), deterministic=True)[0]
    assert np.abs(untrained).max() < 0.1  # SB3's own start: every mean near 0
    assert yaml.safe_load((tmp_path / "run" / "config.yml").read_text())["initial_action"] == prior


@pytest.mark.parametrize(
    ("algo", "value", "match"),
    [
        ("sac", [0.0] * 8, "initial_action is a PPO setting"),
        ("ppo", [2.0] + [0.0] * 7, r"initial_action must be a list of numbers in \[-1, 1\]"),
        ("ppo", "up", r"initial_action must be a list of numbers in \[-1, 1\]"),
        ("ppo", [], r"initial_action must be a list of numbers in \[-1, 1\]"),
        ("ppo", [True] * 8, r"initial_action must be a list of numbers in \[-1, 1\]"),
    ],
)
def test_bad_initial_action_is_named(algo: str, value: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        _config.resolve(algo, "Pool2DCallShot-v0", overrides={"initial_action": value})


def test_initial_action_of_the_wrong_size_is_named(tmp_path: Path) -> None:
    config = _config.resolve("ppo", "Pool2DCallShot-v0", num_envs=4,
                             overrides={"initial_action": [0.0, 0.5], "n_steps": 4,
                                        "batch_size": 16})  # fmt: skip
    with pytest.raises(ValueError, match=r"initial_action must have 8 numbers .* got 2"):
        train.build(config, tmp_path / "run")
