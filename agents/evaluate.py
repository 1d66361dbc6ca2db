"""Evaluate a trained agent beside the random and scripted players.

    python -m agents.evaluate --run-dir runs/Pool2DCallShot-v0_ppo_seed0 [--episodes N] [--seed S]
    python -m agents.evaluate --summarize runs/Pool2DCallShot-v0_ppo_seed* [--out FILE] [--plot PNG]

The three policies play the same seeded episodes (episode ``k`` starts from env seed
``seed + k``, on the env variant the agent was trained on), the trained agent acting
deterministically and the random player from a generator seeded ``seed``, so running it
twice gives the same numbers. The trained agent plays the id it trained on (a call-shot
id: its own action and features); random and scripted play the game under it, with the
same arguments, in the game's own action (``impulse2d.envs.base_game``): the same
positions, the same rules and rewards. Written to the run directory:

* ``results.json`` / ``results.md``: mean ± std over episodes of the reward and the task
  metrics (Pool: balls potted, fouls and scratches per shot; Slingshot: pigs and blocks
  destroyed, birds used, levels cleared), and whether the targets are met;
* ``learning_curve.png``: the training return against env steps, with the baselines;
* ``agent.gif`` (or ``.mp4``): the trained agent playing a few shots.

``--summarize`` puts several evaluated runs (one per training seed) in one table: mean ±
std over the seeds.
"""

from __future__ import annotations

import argparse
import json
import pickle
import time
from pathlib import Path
from typing import Any

import numpy as np

from . import _config, _media, _tasks
from ._kernels import add_kernels_option, one_torch_thread, pin_torch_kernels

POLICIES = ("trained", "random", "scripted")
RANDOM_CALL_SHOT = "random_call_shot"  # uniform actions of a call-shot id's own space


def load_policy(run_dir: str | Path) -> tuple[_tasks.Policy, dict[str, Any]]:
    """The trained agent of a run directory as a batch policy (observations -> env
    actions, deterministic), and the run's config."""
    model, normalizer, config = load_model(run_dir)
    return agent_policy(model, normalizer), config


def load_model(run_dir: str | Path) -> tuple[Any, Any, dict[str, Any]]:
    """The SB3 model of a run directory, its ``VecNormalize`` (None if the run did not
    normalize) and the run's config."""
    import torch

    torch.set_num_threads(1)
    run_dir = Path(run_dir)
    config = _config.load_config(run_dir)
    path = run_dir / "model.zip"
    if not path.is_file():
        raise ValueError(f"run_dir: {str(run_dir)!r} has no model.zip")
    model = _config.algo_class(config["algo"]).load(str(path), device="cpu")
    normalizer = None
    stats = run_dir / "vecnormalize.pkl"
    if stats.is_file():
        with open(stats, "rb") as file:  # our own file, written by agents.train
            normalizer = pickle.load(file)
        normalizer.training = False
    return model, normalizer, config


def agent_policy(model: Any, normalizer: Any = None) -> _tasks.Policy:
    """A trained SB3 model as a batch policy: observations (normalized if the run used
    ``VecNormalize``) -> the model's deterministic actions."""

    def policy(obs: np.ndarray) -> np.ndarray:
        one_torch_thread()  # the env's step may have set OpenMP to every core
        seen = normalizer.normalize_obs(obs) if normalizer is not None else obs
        action, _ = model.predict(seen, deterministic=True)
        return np.asarray(action, np.float32)

    return policy


def random_policy(seed: int, size: int = 2) -> _tasks.Policy:
    """Uniform actions in [-1, 1]^size from a generator seeded ``seed``."""
    rng = np.random.default_rng(seed)
    return lambda obs: rng.uniform(-1.0, 1.0, (len(obs), size)).astype(np.float32)


def _own_action_size(env_id: str) -> int | None:
    """The action size of a call-shot id (None for a game's own id)."""
    from impulse2d.envs import CALL_SHOT_IDS
    from impulse2d.envs.callshot import POOL_TASK, SLINGSHOT_TASK

    if env_id not in CALL_SHOT_IDS:
        return None
    pool = CALL_SHOT_IDS[env_id][0] == "Pool2D-v0"
    return (POOL_TASK if pool else SLINGSHOT_TASK).action_size


def evaluate(
    run_dir: str | Path,
    episodes: int = 100,
    seed: int = 1000,
    video: str | None = "gif",
    video_shots: int = 6,
    env_kwargs: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Evaluate the run in ``run_dir`` (see the module docstring); returns the results
    (what ``results.json`` holds). ``video``: ``"gif"``, ``"mp4"`` or None (no video).
    The episodes are of the env the agent trained on, with the config's
    ``eval_env_kwargs`` and then ``env_kwargs`` on top (held-out levels, say)."""
    episodes = _config.positive_count("episodes", episodes)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an int >= 0, got {seed!r}")
    if video not in ("gif", "mp4", None):
        raise ValueError(f"video must be 'gif', 'mp4' or None, got {video!r}")
    if env_kwargs is not None and not isinstance(env_kwargs, dict):
        raise ValueError(f"env_kwargs must be a mapping, got {env_kwargs!r}")
    run_dir = Path(run_dir)
    start = time.perf_counter()
    trained, config = load_policy(run_dir)
    from impulse2d.envs import base_game

    game_id, game_kwargs = base_game(config["env_id"])
    task = _tasks.task(game_id)
    trained_on = config["env_kwargs"]
    env_kwargs = {**trained_on, **config.get("eval_env_kwargs", {}), **(env_kwargs or {})}
    players = {"trained": trained, "random": random_policy(seed), "scripted": task.scripted}
    own_action = _own_action_size(config["env_id"])
    if own_action is not None:  # what the call-shot action gives without learning
        players[RANDOM_CALL_SHOT] = random_policy(seed, own_action)
    rows = {}
    for name, policy in players.items():
        # The agent on its own id; the others on the game under it, in the game's actions,
        # observing its state: the scripted players read positions, not images (the
        # episodes are the same ones whatever is observed).
        game_play = {**game_kwargs, **_episode_limit(config["env_id"]), **env_kwargs}
        env_id, kwargs = (
            (config["env_id"], env_kwargs)
            if name in ("trained", RANDOM_CALL_SHOT)
            else (game_id, _state_kwargs(game_play))
        )
        record = _tasks.play_episodes(env_id, kwargs, policy, episodes, seed)
        rows[name] = _tasks.summarize(task, record)
    training = run_dir / "training.json"
    results: dict[str, Any] = {
        "env_id": config["env_id"],
        "game": task.env_id,
        "algo": config["algo"],
        "train_seed": config["seed"],
        "entry": config.get("entry", config["env_id"]),
        "env_kwargs": env_kwargs,
        "train_env_kwargs": trained_on,
        "trained_timesteps": json.loads(training.read_text())["num_timesteps"]
        if training.is_file()
        else None,
        "episodes": episodes,
        "episode_seeds": [seed, seed + episodes - 1],
        "scripted": task.scripted_name,
        "metrics": {m.key: {"label": m.label, "kind": m.kind} for m in task.metrics},
        "policies": rows,
        "targets": _targets(task, rows),
    }
    reward = {name: rows[name]["reward"]["mean"] for name in POLICIES}
    _media.learning_curve(
        run_dir,
        run_dir / "learning_curve.png",
        f"{config.get('entry', config['env_id'])}: {config['algo'].upper()}, seed {config['seed']}",
        {
            f"random ({reward['random']:.2f})": reward["random"],
            f"scripted: {task.scripted_name} ({reward['scripted']:.2f})": reward["scripted"],
        },
        trained=(reward["trained"], rows["trained"]["reward"]["std"] / np.sqrt(episodes)),
        skip_before=_skip_before(run_dir),
    )
    if video is not None:
        frames = _media.record_video(
            config["env_id"], env_kwargs, trained, run_dir / f"agent.{video}", seed, video_shots
        )
        results["video_frames"] = frames
    results["eval_seconds"] = round(time.perf_counter() - start, 1)
    (run_dir / "results.json").write_text(json.dumps(results, indent=2) + "\n")
    table = format_table(results)
    (run_dir / "results.md").write_text(table)
    print(table, flush=True)
    return results


def _skip_before(run_dir: Path) -> int:
    """The steps before every world of a run can have finished an episode (see
    ``_media.learning_curve``)."""
    config = _config.load_config(run_dir)
    return config["n_envs"] * _episode_cap(config["env_id"], config["env_kwargs"])


def _state_kwargs(kwargs: dict[str, Any]) -> dict[str, Any]:
    """``kwargs`` observing the game's state (without ``obs_type`` and ``pixel_size``)."""
    return {k: v for k, v in kwargs.items() if k not in ("obs_type", "pixel_size")}


def _episode_limit(env_id: str) -> dict[str, int]:
    """``{"max_episode_steps": n}`` of a registered id, for playing the game under it with
    the same episode length (empty if the id sets none)."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the env ids)

    steps = gym.spec(env_id).max_episode_steps
    return {} if steps is None else {"max_episode_steps": int(steps)}


def _episode_cap(env_id: str, env_kwargs: dict[str, Any]) -> int:
    """The most steps an episode can last (``max_episode_steps``)."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the env ids)

    return int(env_kwargs.get("max_episode_steps") or gym.spec(env_id).max_episode_steps or 1)


def _targets(task: _tasks.Task, rows: dict[str, Any]) -> dict[str, Any]:
    """Each of the task's targets (definitions in agents/README.md), met or not."""
    out = {}
    for target in task.targets:
        trained = rows["trained"][target.metric]["mean"]
        needed = target.factor * rows[target.against][target.metric]["mean"]
        met = trained >= needed and (target.against != "random" or trained > 0)
        out[target.name] = {
            "metric": target.metric,
            "trained": trained,
            "needed": needed,
            "met": bool(met),
        }
    return out


def format_table(results: dict[str, Any]) -> str:
    """``results.md``: the comparison table and the targets, as Markdown."""
    metrics = results["metrics"]
    labels = {key: spec["label"] for key, spec in metrics.items()}
    algo = results["algo"].upper()
    names = {
        "trained": f"trained {algo}",
        "random": "random",
        "scripted": f"scripted ({results['scripted']})",
    }
    lines = [
        f"# {results.get('entry', results['env_id'])}: {algo} (seed {results['train_seed']}, "
        f"{results['trained_timesteps'] or 0:,} steps) vs random vs scripted",
        "",
        f"{results['episodes']} episodes, env seeds {results['episode_seeds'][0]}-"
        f"{results['episode_seeds'][1]}, env_kwargs `{json.dumps(results['env_kwargs'])}`; "
        "mean ± std over episodes (rates: total / total shots).",
        "",
        "| policy | " + " | ".join(labels.values()) + " |",
        "|---|" + "---|" * len(labels),
    ]
    names[RANDOM_CALL_SHOT] = "random call-shot actions"
    for key in [*POLICIES, RANDOM_CALL_SHOT]:
        if key not in results["policies"]:
            continue
        row = results["policies"][key]
        cells = []
        for metric in labels:
            mean, std = row[metric]["mean"], row[metric]["std"]
            rate = metrics[metric]["kind"] == "rate"
            cells.append(f"{mean:.3f}" if rate else f"{mean:.2f} ± {std:.2f}")
        lines.append(f"| {names[key]} | " + " | ".join(cells) + " |")
    lines.append("")
    for name, target in results["targets"].items():
        verdict = "met" if target["met"] else "NOT met"
        lines.append(
            f"* {name}: {labels[target['metric']]} {target['trained']:.2f} vs needed "
            f"{target['needed']:.2f}: {verdict}"
        )
    return "\n".join(lines) + "\n"


def summarize_runs(run_dirs: list[str | Path], plot: str | Path | None = None) -> str:
    """A Markdown table over several evaluated runs (e.g. one per training seed) of the
    same env and algo: per policy and metric, mean ± std over the runs of each run's mean.
    With ``plot``, also a PNG of every run's learning curve beside the baselines."""
    if not run_dirs:
        raise ValueError("summarize: give at least one run directory")
    runs = []
    for run_dir in run_dirs:
        path = Path(run_dir) / "results.json"
        if not path.is_file():
            raise ValueError(f"summarize: {str(run_dir)!r} has no results.json (evaluate it)")
        runs.append(json.loads(path.read_text()))
    first = runs[0]
    for run in runs[1:]:
        same = (run["env_id"], run["algo"], run["env_kwargs"])
        if same != (first["env_id"], first["algo"], first["env_kwargs"]):
            raise ValueError("summarize: the runs differ in env, algo or env_kwargs")
    labels = {key: spec["label"] for key, spec in first["metrics"].items()}
    seeds = ", ".join(str(run["train_seed"]) for run in runs)
    algo = first["algo"].upper()
    lines = [
        f"# {first.get('entry', first['env_id'])}: {algo}, {len(runs)} training seeds ({seeds}) "
        "vs random vs scripted",
        "",
        f"Each run evaluated on {first['episodes']} episodes (env seeds "
        f"{first['episode_seeds'][0]}-{first['episode_seeds'][1]}); mean ± std over the "
        "runs of each run's mean (random and scripted play the same episodes in every run, "
        f"hence std 0). env_kwargs `{json.dumps(first['env_kwargs'])}`.",
        "",
        "| policy | " + " | ".join(labels.values()) + " |",
        "|---|" + "---|" * len(labels),
    ]
    names = {
        "trained": f"trained {algo}",
        "random": "random",
        "scripted": f"scripted ({first['scripted']})",
        RANDOM_CALL_SHOT: "random call-shot actions",
    }
    for key in [k for k in names if all(k in run["policies"] for run in runs)]:
        cells = []
        for metric in labels:
            values = np.array([run["policies"][key][metric]["mean"] for run in runs])
            cells.append(f"{values.mean():.2f} ± {values.std():.2f}")
        lines.append(f"| {names[key]} | " + " | ".join(cells) + " |")
    if plot is not None:
        baselines = {
            "random, evaluated": first["policies"]["random"]["reward"]["mean"],
            f"scripted ({first['scripted']}), evaluated": first["policies"]["scripted"]["reward"][
                "mean"
            ],
        }
        if RANDOM_CALL_SHOT in first["policies"]:
            baselines["random call-shot actions, evaluated"] = first["policies"][RANDOM_CALL_SHOT][
                "reward"
            ]["mean"]
        _media.seed_curves(
            [
                (
                    Path(run_dir),
                    f"seed {run['train_seed']}",
                    run["policies"]["trained"]["reward"]["mean"],
                )
                for run_dir, run in zip(run_dirs, runs, strict=True)
            ],
            Path(plot),
            f"{algo} on {first.get('entry', first['env_id'])}: {len(runs)} training seeds",
            baselines,
            skip_before=_skip_before(Path(run_dirs[0])),
        )
    met = {name: sum(run["targets"][name]["met"] for run in runs) for name in first["targets"]}
    lines.append("")
    lines += [f"* {name}: met in {count} of {len(runs)} runs" for name, count in met.items()]
    return "\n".join(lines) + "\n"


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m agents.evaluate",
        description="Compare a trained agent with the random and scripted players over the "
        "same seeded episodes; write results.md/json, learning_curve.png and a video.",
    )
    parser.add_argument("--run-dir", help="a directory made by agents.train")
    parser.add_argument(
        "--summarize",
        nargs="+",
        metavar="RUN_DIR",
        help="instead: one table over these evaluated runs (mean ± std over training seeds)",
    )
    parser.add_argument("--out", help="with --summarize: also write the table to this file")
    parser.add_argument("--plot", help="with --summarize: a PNG of every run's learning curve")
    parser.add_argument("--episodes", type=int, default=100, help="episodes (default 100)")
    parser.add_argument("--seed", type=int, default=1000, help="first episode seed (1000)")
    parser.add_argument("--video", choices=("gif", "mp4", "none"), default="gif")
    parser.add_argument("--video-shots", type=int, default=6, help="shots in the video (6)")
    parser.add_argument(
        "--env-kwargs", default=None, help="JSON over the run's env kwargs, e.g. other levels"
    )
    add_kernels_option(parser)
    return parser


def main(argv: list[str] | None = None) -> dict[str, Any] | str:
    args = build_parser().parse_args(argv)
    if args.portable_kernels:
        pin_torch_kernels()  # before torch loads, as agents.train does
    if args.summarize:
        table = summarize_runs(args.summarize, args.plot)
        if args.out:
            Path(args.out).write_text(table)
        print(table, end="", flush=True)
        return table
    if args.run_dir is None:
        raise ValueError("run_dir: give --run-dir (or --summarize RUN_DIR ...)")
    video = None if args.video == "none" else args.video
    kwargs = _config.parse_json_kwargs("env_kwargs", args.env_kwargs)
    return evaluate(args.run_dir, args.episodes, args.seed, video, args.video_shots, kwargs)


cli = _config.command(main)  # the command line: impulse2d-... and python -m


if __name__ == "__main__":
    cli()
