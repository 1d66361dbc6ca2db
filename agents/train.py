"""Train an agent on an impulse2d task, RL Zoo style.

    python -m agents.train --env Pool2DCallShot-v0 --algo ppo    # the defaults in ppo.yml
    python -m agents.train --env Slingshot2DCallShot-v0 --algo ppo --timesteps 5e4 --seed 1
    python -m agents.train --resume runs/Pool2DCallShot-v0_ppo_seed0/model.zip

The hyperparameters come from ``agents/hyperparams/<algo>.yml`` (or ``--config FILE``),
keyed by env id; the command line overrides the budget (``--timesteps``), the number of
worlds (``--num-envs``), env arguments (``--env-kwargs``, JSON) and any algorithm
argument (``--hyperparams key=value ...``). Training runs on the natively batched vector
env (every world stepped in one engine) through the Stable-Baselines3 adapter.

The run directory (default ``runs/<env>_<algo>_seed<k>/``) gets ``model.zip``,
``config.yml`` (the resolved configuration), ``command.txt``, ``progress.csv`` (SB3's CSV
log), ``monitor.csv`` (every episode's return and length), TensorBoard logs in ``tb/``
(when tensorboard is installed), ``vecnormalize.pkl`` (when observations or rewards are
normalised) and ``training.json`` (wall time, speed). Unless ``--no-evaluate``, the run is
then evaluated (``agents.evaluate``): results table, learning curve and video.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shlex
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import _config
from ._kernels import add_kernels_option, pin_torch_kernels, torch_thread_callback

DEFAULT_RUNS = Path("runs")


def default_run_dir(entry: str, algo: str, seed: int) -> Path:
    """``runs/<env>_<algo>_seed<k>``; an entry ``Pool2D-v0/long`` gives ``Pool2D-v0-long``."""
    return DEFAULT_RUNS / f"{entry.replace('/', '-')}_{algo}_seed{seed}"


def make_vec_env(config: dict[str, Any], seed: int, monitor: Path | None = None) -> Any:
    """The training env of a resolved config: the id's batched vector env as an SB3
    ``VecEnv`` (env ``i`` seeded ``seed + i``), under ``VecMonitor`` (episode statistics
    for SB3's logs, and ``monitor.csv`` when ``monitor`` is a directory). A call-shot id
    brings its own action and features (``impulse2d.envs.callshot``)."""
    from stable_baselines3.common.vec_env import VecMonitor

    import impulse2d  # noqa: F401  (registers the env ids)
    from impulse2d.envs.sb3 import make_sb3_vec_env

    venv = make_sb3_vec_env(config["env_id"], config["n_envs"], seed=seed, **config["env_kwargs"])
    return VecMonitor(venv, filename=str(monitor) if monitor is not None else None)


def _check_evaluation_env(config: dict[str, Any]) -> None:
    """Build the env evaluation will play (``eval_env_kwargs`` over ``env_kwargs``) once,
    so that a bad argument fails now, by name, not after the training it would end."""
    if not config.get("eval_env_kwargs"):
        return
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the env ids)

    kwargs = {**config["env_kwargs"], **config["eval_env_kwargs"]}
    gym.make(config["env_id"], **kwargs).close()


def _normalized(venv: Any, config: dict[str, Any], stats: Path | None) -> Any:
    """Wrap in ``VecNormalize`` if the config asks for it (loading saved statistics when
    resuming, so the agent sees the inputs it was trained on)."""
    from stable_baselines3.common.vec_env import VecNormalize

    if not config["normalize"]:
        return venv
    if stats is not None and stats.is_file():
        venv = VecNormalize.load(str(stats), venv)
        venv.training = True
        return venv
    options = dict(config["normalize"]) if isinstance(config["normalize"], dict) else {}
    options.setdefault("gamma", config["hyperparams"].get("gamma", 0.99))
    return VecNormalize(venv, **options)


def _logger(run_dir: Path) -> tuple[Any, str]:
    """SB3 logger writing ``progress.csv`` and, if tensorboard is importable, ``tb/``."""
    from stable_baselines3.common.logger import CSVOutputFormat, Logger

    formats: list[Any] = [CSVOutputFormat(str(run_dir / "progress.csv"))]
    try:
        from stable_baselines3.common.logger import TensorBoardOutputFormat

        formats.append(TensorBoardOutputFormat(str(run_dir / "tb")))
        note = f"TensorBoard logs in {run_dir / 'tb'}"
    except ImportError:  # SB3 raises it when torch.utils.tensorboard cannot load
        note = "tensorboard is not installed: no TensorBoard logs (pip install tensorboard)"
    return Logger(folder=str(run_dir), output_formats=formats), note


@dataclass
class Experiment:
    """A run being trained, as ``build`` sets it up (RL Zoo's ``ExperimentManager`` in
    three steps: ``build``, ``learn``, ``save``)."""

    config: dict[str, Any]
    run_dir: Path
    model: Any
    venv: Any
    logger: Any
    previous_progress: Path | None  # a resumed run's earlier progress.csv, kept aside
    torch_threads: int = 1
    start_timesteps: int = 0
    seconds: float = 0.0
    interrupted: bool = False


def build(
    config: dict[str, Any],
    run_dir: str | Path,
    *,
    resume: str | Path | None = None,
    command: str | None = None,
    verbose: int = 0,
    torch_threads: int = 1,
) -> Experiment:
    """The model and its env for a resolved config (``agents._config.resolve``), or, with
    ``resume``, the saved model loaded to go on; ``run_dir`` made and its config written."""
    import torch
    from stable_baselines3.common.utils import set_random_seed

    # Two cores, shared: one thread keeps torch off the core the physics needs, and makes
    # runs bitwise repeatable (held there after every env step: agents/_kernels.py).
    torch_threads = _config.positive_count("torch_threads", torch_threads)
    torch.set_num_threads(torch_threads)
    run_dir = Path(run_dir)
    resume_path = _check_resume(resume)
    run_dir.mkdir(parents=True, exist_ok=True)
    cls = _config.algo_class(config["algo"])
    previous_progress = _prepare_run_dir(run_dir, resume_path)
    seed = config["seed"]
    set_random_seed(seed)
    _check_evaluation_env(config)
    venv = make_vec_env(config, seed, monitor=run_dir)
    stats = resume_path.parent / "vecnormalize.pkl" if resume_path is not None else None
    venv = _normalized(venv, config, stats)
    if resume_path is None:
        kwargs = _config.algo_kwargs(config)
        model = cls(config["policy"], venv, seed=seed, device="cpu", verbose=verbose, **kwargs)
        if config.get("initial_action") is not None:
            set_initial_action(model, config["initial_action"])
        if config.get("pretrain_encoder"):
            from . import _pretrain

            _pretrain.pretrain(model.policy, config, run_dir)
    else:
        # Loading with the env sizes the rollout buffer for this run's number of worlds.
        model = cls.load(str(resume_path), env=venv, device="cpu")
        steps_done = int(model.num_timesteps)
        # A resumed run plays fresh episodes: env i is seeded seed + steps_done + i (this also
        # seeds the sampling).
        model.set_random_seed(seed + steps_done)
        config = {**config, "resumed_from": str(resume_path), "resumed_at_timesteps": steps_done}
    if command is not None:
        (run_dir / "command.txt").write_text(command + "\n")
    _config.save_config(config, run_dir / "config.yml")
    logger, note = _logger(run_dir)
    model.set_logger(logger)
    print(
        f"training {config['algo'].upper()} on {config['env_id']} with {config['n_envs']} "
        f"worlds for {config['n_timesteps']:,} steps -> {run_dir} ({note})",
        flush=True,
    )
    return Experiment(config, run_dir, model, venv, logger, previous_progress, torch_threads)


def set_initial_action(model: Any, action: list[float]) -> None:
    """Start PPO's policy at ``action``: the bias of the layer giving the Gaussian's mean.
    That layer starts with weights of scale 0.01 (SB3's orthogonal init), so the mean is
    ``action`` on every observation, give or take a few hundredths (with SB3's default
    ``ortho_init``), until training moves it
    (a warm start at a fixed shot: ``agents/TUNING.md``, Pool2DRackBestShots-v0)."""
    import torch

    layer = model.policy.action_net
    if len(action) != layer.out_features:
        raise ValueError(
            f"initial_action must have {layer.out_features} numbers (the action's size), "
            f"got {len(action)}"
        )
    with torch.no_grad():
        layer.bias.copy_(torch.tensor(action, dtype=layer.bias.dtype))


def learn(experiment: Experiment, *, progress_bar: bool = True, resumed: bool = False) -> None:
    """Train for ``n_timesteps`` more steps, with progress shown (SB3's bar in a terminal,
    plain lines elsewhere); Ctrl-C stops early and keeps what was learnt."""
    from ._progress import ProgressLines, wants_lines

    model, config = experiment.model, experiment.config
    bar = progress_bar and not wants_lines() and _has_progress_bar()
    callbacks = [torch_thread_callback(experiment.torch_threads)]
    if progress_bar and not bar:
        callbacks.append(ProgressLines(config["n_timesteps"]))
    experiment.start_timesteps = model.num_timesteps
    start = time.perf_counter()
    try:
        model.learn(
            total_timesteps=config["n_timesteps"],
            reset_num_timesteps=not resumed,
            progress_bar=bar,
            callback=callbacks,
        )
    except KeyboardInterrupt:  # keep what was learnt so far; --resume can go on
        experiment.interrupted = True
        print("interrupted: saving the model as it is", flush=True)
    experiment.seconds = time.perf_counter() - start


def save(experiment: Experiment) -> Path:
    """Write the model (and normalisation statistics), merge a resumed run's progress and
    write ``training.json``; returns the run directory."""
    model, run_dir, seconds = experiment.model, experiment.run_dir, experiment.seconds
    model.save(str(run_dir / "model.zip"))
    if experiment.config["normalize"]:
        experiment.venv.save(str(run_dir / "vecnormalize.pkl"))
    experiment.logger.close()
    experiment.venv.close()
    if experiment.previous_progress is not None:
        _merge_progress(experiment.previous_progress, run_dir / "progress.csv")
    steps = int(model.num_timesteps - experiment.start_timesteps)
    summary = {
        "num_timesteps": int(model.num_timesteps),
        "steps_this_run": steps,
        "wall_seconds": round(seconds, 1),
        "steps_per_second": round(steps / max(seconds, 1e-9), 1),
        "interrupted": experiment.interrupted,
        "torch_kernels": _torch_kernels(),
    }
    (run_dir / "training.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(
        f"trained {steps:,} steps in {seconds:.0f} s ({summary['steps_per_second']} steps/s); "
        f"model in {run_dir / 'model.zip'}",
        flush=True,
    )
    return run_dir


def train(
    config: dict[str, Any],
    run_dir: str | Path,
    *,
    resume: str | Path | None = None,
    progress_bar: bool = True,
    command: str | None = None,
    verbose: int = 0,
    torch_threads: int = 1,
) -> Path:
    """Train (or, with ``resume``, continue training) the agent of a resolved config for
    ``config["n_timesteps"]`` more env steps; save everything in ``run_dir`` and return it.
    ``build``, ``learn`` and ``save`` in turn."""
    experiment = build(
        config,
        run_dir,
        resume=resume,
        command=command,
        verbose=verbose,
        torch_threads=torch_threads,
    )
    learn(experiment, progress_bar=progress_bar, resumed=resume is not None)
    return save(experiment)


def _torch_kernels() -> dict[str, Any]:
    """What decides torch's rounding in this run (``agents/_kernels.py``): its version,
    threads, the ATen kernels in use and the named kernels, if any."""
    import torch

    return {
        "torch": torch.__version__,
        "threads": torch.get_num_threads(),
        "aten_kernels": torch.backends.cpu.get_cpu_capability(),
        **{name: os.environ.get(name) for name in ("ATEN_CPU_CAPABILITY", "MKL_CBWR")},
    }


def _check_resume(resume: str | Path | None) -> Path | None:
    if resume is None:
        return None
    path = Path(resume)
    if path.is_dir():
        path = path / "model.zip"
    if not path.is_file():
        raise ValueError(f"resume: no model file {str(path)!r}")
    return path


def _prepare_run_dir(run_dir: Path, resume: Path | None) -> Path | None:
    """Clear a fresh run's old logs; when resuming, keep the earlier ``progress.csv`` aside
    (SB3's CSV writer starts a new file) to be merged back after training."""
    for name in ("tb", "progress.prev.csv"):
        path = run_dir / name
        if path.is_dir():
            shutil.rmtree(path)
        elif path.exists():
            path.unlink()
    if resume is None:
        return None
    earlier = resume.parent / "progress.csv"
    if not earlier.is_file():
        return None
    kept = run_dir / "progress.prev.csv"
    shutil.copyfile(earlier, kept)
    return kept


def _merge_progress(earlier: Path, current: Path) -> None:
    """``progress.csv`` = the earlier rows, then this run's (columns: the union)."""
    rows: list[dict[str, str]] = []
    fields: list[str] = []
    for path in (earlier, current):
        if not path.is_file():
            continue
        with open(path, newline="") as file:
            reader = csv.DictReader(file)
            fields += [f for f in reader.fieldnames or [] if f not in fields]
            rows += list(reader)
    with open(current, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    earlier.unlink()


def _has_progress_bar() -> bool:
    """SB3's progress bar needs tqdm and rich; without them, train without one."""
    try:
        import rich  # noqa: F401
        import tqdm  # noqa: F401
    except ImportError:
        print("note: install tqdm and rich for a progress bar", flush=True)
        return False
    return True


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m agents.train",
        description="Train PPO or SAC on an impulse2d env id (hyperparameters from "
        "agents/hyperparams/<algo>.yml), then evaluate the agent.",
    )
    parser.add_argument(
        "--env",
        default=None,
        help=f"env id, or id/variant: a YAML entry (default {_config.DEFAULT_ENV})",
    )
    parser.add_argument("--algo", default=None, help="ppo or sac (default ppo)")
    parser.add_argument("--timesteps", default=None, help="env steps, e.g. 2e5 (default: YAML)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--num-envs", default=None, help="worlds in the batch (default: YAML)")
    parser.add_argument("--run-dir", default=None, help="default runs/<env>_<algo>_seed<k>")
    parser.add_argument("--env-kwargs", default=None, help="JSON, e.g. '{\"num_balls\": 1}'")
    parser.add_argument("--config", default=None, help="hyperparameter YAML file to use")
    parser.add_argument(
        "--hyperparams",
        nargs="*",
        default=None,
        metavar="KEY=VALUE",
        help="algorithm arguments overriding the YAML, e.g. learning_rate=1e-3",
    )
    parser.add_argument("--resume", default=None, help="model.zip (or its run dir) to go on from")
    parser.add_argument(
        "--no-progress-bar",
        action="store_true",
        help="train without the progress bar (in a terminal) or lines (elsewhere)",
    )
    parser.add_argument(
        "--evaluate",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="evaluate after training (default on; --no-evaluate to skip)",
    )
    parser.add_argument("--eval-episodes", type=int, default=100, help="episodes (default 100)")
    parser.add_argument("--eval-seed", type=int, default=1000, help="first episode seed")
    parser.add_argument(
        "--eval-video",
        choices=("gif", "mp4", "none"),
        default="gif",
        help="the evaluation's video of the agent (default gif)",
    )
    parser.add_argument("--verbose", type=int, default=0, help="SB3 verbosity (default 0)")
    parser.add_argument(
        "--torch-threads",
        type=int,
        default=1,
        help="torch's threads for the updates (default 1: runs repeat bitwise; another "
        "count rounds differently)",
    )
    add_kernels_option(parser)
    return parser


def main(argv: list[str] | None = None) -> Path:
    """The command line: resolve the config, train, and evaluate unless told not to."""
    args = build_parser().parse_args(argv)
    if args.portable_kernels:
        pin_torch_kernels()  # before torch loads
    argv = sys.argv[1:] if argv is None else argv
    base = None
    if args.resume is not None:
        # Go on with the resumed run's own settings (env variant, worlds, algorithm
        # arguments), not the YAML's, which may have changed since.
        saved = _check_resume(args.resume).parent / "config.yml"
        base = _config.load_config(saved.parent) if saved.is_file() else None
    saved_entry = (base or {}).get("entry", (base or {}).get("env_id", _config.DEFAULT_ENV))
    env_id = _config.check_env_id(args.env or saved_entry)
    algo = _config.check_algo(args.algo or (base or {}).get("algo", "ppo"))
    if base is not None and (saved_entry, base["algo"]) != (env_id, algo):
        raise ValueError(
            f"resume: the model is {base['algo']} on {saved_entry}, not {algo} on {env_id}"
        )
    config = _config.resolve(
        algo,
        env_id,
        config_file=args.config,
        timesteps=args.timesteps,
        num_envs=args.num_envs,
        env_kwargs=_config.parse_json_kwargs("env_kwargs", args.env_kwargs),
        overrides=_config.parse_overrides(args.hyperparams),
        seed=args.seed,
        base=base if args.config is None else None,
    )
    if args.resume is None and args.run_dir is None:
        run_dir = default_run_dir(env_id, algo, args.seed)
    elif args.run_dir is None:
        run_dir = _check_resume(args.resume).parent  # continue in the resumed run's dir
    else:
        run_dir = Path(args.run_dir)
    if args.evaluate:
        _config.positive_count("eval_episodes", args.eval_episodes)
    command = "python -m agents.train " + " ".join(shlex.quote(a) for a in argv)
    start = time.perf_counter()
    train(
        config,
        run_dir,
        resume=args.resume,
        progress_bar=not args.no_progress_bar,
        command=command,
        verbose=args.verbose,
        torch_threads=args.torch_threads,
    )
    if args.evaluate:
        from .evaluate import evaluate

        video = None if args.eval_video == "none" else args.eval_video
        evaluate(run_dir, episodes=args.eval_episodes, seed=args.eval_seed, video=video)
        print(f"train + evaluate: {time.perf_counter() - start:.0f} s wall time", flush=True)
    return run_dir


cli = _config.command(main)  # the command line: impulse2d-... and python -m


if __name__ == "__main__":
    cli()
