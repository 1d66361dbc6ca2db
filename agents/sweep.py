"""Sweeps over training seeds and hyperparameters, as trials of Ray Tune.

    python -m agents.sweep --env Pool2DCallShot-v0 --algo ppo --seeds 0-7
    python -m agents.sweep --env Pool2DCallShot-v0 --algo ppo --seeds 0-2 \\
        --search learning_rate=3e-4,1e-3 gamma=0.5,0.9          # 3 seeds x 4 settings
    python -m agents.sweep ... --address auto                 # a cluster (`ray start`)

Each trial runs the functions ``python -m agents.train`` runs: ``agents.train.train`` on
the YAML entry resolved with the trial's seed and values, then ``agents.evaluate.evaluate``
over the same seeded episodes as every other trial. A trial is therefore the run that
command gives with ``--seed`` and ``--hyperparams`` set that way, bitwise (tested). The
grid (every seed times every combination of ``--search`` values) is Ray Tune's
``grid_search``; Ray places the trials on the CPUs it has.

Without ``--address`` Ray starts itself on this machine and stops at the end. With
``--address`` the sweep joins a running Ray cluster: ``auto`` finds one started on this
machine with ``ray start --head``, and ``ray://HOST:10001`` reaches a remote head
through Ray Client. The project folder is then shipped to the workers as Ray's
``working_dir``. The workers need this project's ``rl`` extra installed, at the same
library versions if the trials are to repeat bitwise.

Results in ``--out`` (default ``runs/sweeps/<env>_<algo>/``): ``sweep.md``, one table over
the trials (and, when values are searched, one row per setting with mean ± std over the
seeds, like ``agents.evaluate --summarize``); ``sweep.json``; and ``sweep.png``, every
trial's learning curve with its evaluated reward. Ray's own records of the trials,
each trial's run directory (model, logs, results) among them, are under ``tune/``.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

from . import _config
from ._kernels import add_kernels_option, pin_torch_kernels

ROOT = Path(__file__).resolve().parents[1]
# Left out of the folder shipped to a cluster's workers.
SHIPPED_EXCLUDES = ["runs/", ".git/", ".venv/", "*.zip", "*.gif", "*.mp4", "notebooks/"]


def parse_seeds(text: str) -> list[int]:
    """``"0-7"``, ``"0,3,5"`` or a mix (``"0-2,9"``) as a list of distinct seeds >= 0."""
    seeds: list[int] = []
    for part in str(text).split(","):
        first, dash, last = part.strip().partition("-")
        try:
            low = int(first)
            high = int(last) if dash else low
        except ValueError:
            raise ValueError(f"seeds must look like 0-7 or 0,3,5, got {text!r}") from None
        if low < 0 or high < low:
            raise ValueError(f"seeds must be ranges low-high with 0 <= low <= high, got {text!r}")
        seeds += [s for s in range(low, high + 1) if s not in seeds]
    return seeds


def parse_search(items: list[str] | None) -> dict[str, list[Any]]:
    """``--search learning_rate=3e-4,1e-3 gamma=0.5,0.9``: each key with its values (read
    as YAML, as ``--hyperparams`` reads them)."""
    space: dict[str, list[Any]] = {}
    for item in items or []:
        key, sep, values = item.partition("=")
        if not sep or not key or not values:
            raise ValueError(f"search must be key=v1,v2,... pairs, got {item!r}")
        space[key] = [_config.parse_overrides([f"{key}={v}"])[key] for v in values.split(",")]
    return space


def settings(space: dict[str, list[Any]]) -> list[dict[str, Any]]:
    """Every combination of the searched values (one empty setting when nothing is)."""
    keys = list(space)
    return [dict(zip(keys, values, strict=True)) for values in itertools.product(*space.values())]


def trial_config(spec: dict[str, Any], seed: int, setting: dict[str, Any]) -> dict[str, Any]:
    """The resolved config of one trial: what ``agents.train`` resolves for this seed with
    the sweep's fixed overrides and the trial's searched values on top."""
    return _config.resolve(
        spec["algo"],
        spec["env_id"],
        config_file=spec["config_file"],
        timesteps=spec["timesteps"],
        num_envs=spec["num_envs"],
        env_kwargs=spec["env_kwargs"],
        overrides={**spec["overrides"], **setting},
        seed=seed,
    )


def run_trial(trial: dict[str, Any]) -> None:
    """One trial (Ray Tune's function trainable): train and evaluate in ``run/`` of the
    trial's directory, then report the evaluation and the learning curve to Tune."""
    if trial["spec"]["portable_kernels"]:
        pin_torch_kernels()  # a trial's worker is a fresh process: before torch loads
    from ray import tune

    from . import _media
    from .evaluate import evaluate
    from .train import train

    config = trial_config(trial["spec"], trial["seed"], trial["setting"])
    # The engine steps the batch on the CPUs Ray reserved for this trial (results do not
    # depend on the thread count).
    config["env_kwargs"] = {**config["env_kwargs"], "threads": trial["spec"]["cpus_per_trial"]}
    run_dir = Path(tune.get_context().get_trial_dir()) / "run"
    start = time.perf_counter()
    train(config, run_dir, progress_bar=False)
    results = evaluate(run_dir, episodes=trial["spec"]["eval_episodes"], video=None)
    steps, rewards = _media.read_progress(run_dir / "progress.csv")
    training = json.loads((run_dir / "training.json").read_text())
    metrics = {
        "seed": trial["seed"],
        "setting": trial["setting"],
        "policies": results["policies"],
        "targets": {name: t["met"] for name, t in results["targets"].items()},
        "scripted": results["scripted"],
        "metric_labels": {key: m["label"] for key, m in results["metrics"].items()},
        "rate_metrics": [key for key, m in results["metrics"].items() if m["kind"] == "rate"],
        "reward": results["policies"]["trained"]["reward"]["mean"],
        "timesteps": training["num_timesteps"],
        "train_seconds": training["wall_seconds"],
        "shots_per_second": training["steps_per_second"],
        "trial_seconds": round(time.perf_counter() - start, 1),
        "curve_steps": steps.tolist(),
        "curve_rewards": rewards.tolist(),
        "run_dir": str(run_dir),
    }
    tune.report(metrics)  # once, at the end: a trial is one run, not an iteration


def sweep(
    spec: dict[str, Any],
    seeds: list[int],
    space: dict[str, list[Any]],
    out: str | Path,
    address: str | None = None,
) -> list[dict[str, Any]]:
    """Run every seed x setting as a Ray Tune trial; write ``sweep.md``, ``sweep.json``
    and ``sweep.png`` to ``out`` and return the trials' reports (in grid order)."""
    import ray
    from ray import tune

    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    for setting in settings(space):  # a bad key or value fails here, before Ray starts
        trial_config(spec, seeds[0], setting)
    if address is None:
        # Workers on this machine import agents/ from the project folder.
        runtime_env = {"env_vars": {"PYTHONPATH": _pythonpath()}}
    else:
        runtime_env = {"working_dir": str(ROOT), "excludes": SHIPPED_EXCLUDES}
    ray.init(address=address, runtime_env=runtime_env, include_dashboard=False)
    try:
        trainable = tune.with_resources(run_trial, {"cpu": spec["cpus_per_trial"]})
        tuner = tune.Tuner(
            trainable,
            param_space={
                "spec": spec,
                "seed": tune.grid_search(seeds),  # Tune crosses the two axes
                "setting": tune.grid_search(settings(space)),
            },
            tune_config=tune.TuneConfig(metric="reward", mode="max"),
            run_config=tune.RunConfig(storage_path=str(out), name="tune", verbose=1),
        )
        grid_results = tuner.fit()
        errors = [r.error for r in grid_results if r.error is not None]
        if errors:
            raise RuntimeError(f"{len(errors)} trial(s) failed; the first: {errors[0]!r}")
        reports = [r.metrics for r in grid_results]
    finally:
        ray.shutdown()
    order = [json.dumps(g, sort_keys=True) for g in settings(space)]
    reports.sort(key=lambda r: (order.index(json.dumps(r["setting"], sort_keys=True)), r["seed"]))
    write_results(spec, reports, out)
    return reports


def _pythonpath() -> str:
    earlier = os.environ.get("PYTHONPATH")
    return str(ROOT) if not earlier else os.pathsep.join([str(ROOT), earlier])


def write_results(spec: dict[str, Any], reports: list[dict[str, Any]], out: Path) -> str:
    """``sweep.md`` (the table), ``sweep.json`` (the reports) and ``sweep.png``."""
    table = format_table(spec, reports)
    (out / "sweep.md").write_text(table)
    (out / "sweep.json").write_text(json.dumps({"spec": spec, "trials": reports}, indent=2))
    plot_trials(spec, reports, out / "sweep.png")
    print(table, end="", flush=True)
    return table


def _label(setting: dict[str, Any]) -> str:
    return ", ".join(f"{k}={v}" for k, v in setting.items()) or "the YAML's"


def format_table(spec: dict[str, Any], reports: list[dict[str, Any]]) -> str:
    """One row per trial; with searched values, also one row per setting over the seeds."""
    labels = reports[0]["metric_labels"]
    algo = spec["algo"].upper()
    lines = [
        f"# Sweep: {algo} on {spec['env_id']}, {len(reports)} trials on Ray Tune",
        "",
        f"Each trial trained for {(reports[0]['policies'] and spec['timesteps']) or 'the YAML'}"
        f" steps and was evaluated on {spec['eval_episodes']} episodes (the same seeded "
        "episodes for every trial); mean ± std over episodes. Scripted player "
        f"({reports[0]['scripted']}): "
        + ", ".join(
            f"{label} {reports[0]['policies']['scripted'][key]['mean']:.2f}"
            for key, label in labels.items()
        )
        + ".",
        "",
        "| seed | setting | " + " | ".join(labels.values()) + " | train s | shots/s |",
        "|---|---|" + "---|" * (len(labels) + 2),
    ]
    for r in reports:
        trained = r["policies"]["trained"]
        cells = [
            f"{trained[k]['mean']:.3f}"
            if k in r["rate_metrics"]
            else f"{trained[k]['mean']:.2f} ± {trained[k]['std']:.2f}"
            for k in labels
        ]
        lines.append(
            f"| {r['seed']} | {_label(r['setting'])} | "
            + " | ".join(cells)
            + f" | {r['train_seconds']:.0f} | {r['shots_per_second']:,.0f} |"
        )
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in reports:
        groups.setdefault(_label(r["setting"]), []).append(r)
    lines += ["", "| setting | seeds | " + " | ".join(labels.values()) + " |"]
    lines.append("|---|---|" + "---|" * len(labels))
    for name, group in groups.items():
        cells = []
        for key in labels:
            means = np.array([r["policies"]["trained"][key]["mean"] for r in group])
            cells.append(f"{means.mean():.2f} ± {means.std():.2f}")
        seeds = ",".join(str(r["seed"]) for r in group)
        lines.append(f"| {name} | {seeds} | " + " | ".join(cells) + " |")
    lines += ["", "(Per setting: mean ± std over the seeds of each trial's mean.)"]
    return "\n".join(lines) + "\n"


def plot_trials(spec: dict[str, Any], reports: list[dict[str, Any]], out: Path) -> bool:
    """Every trial's training curve, coloured by setting, with its evaluated reward."""
    from . import _media

    first = reports[0]["policies"]
    plt, fig, ax = _media.reward_axes(
        f"Sweep: {spec['algo'].upper()} on {spec['env_id']}, {len(reports)} trials",
        {
            "random, evaluated": first["random"]["reward"]["mean"],
            f"scripted ({reports[0]['scripted']}), evaluated": first["scripted"]["reward"]["mean"],
        },
    )
    names = list(dict.fromkeys(_label(r["setting"]) for r in reports))
    drawn = False
    for r in reports:
        if not r["curve_steps"]:
            continue
        colour = plt.get_cmap("tab10")(names.index(_label(r["setting"])) % 10)
        ax.plot(r["curve_steps"], r["curve_rewards"], color=colour, lw=1, alpha=0.8)
        ax.plot([r["curve_steps"][-1]], [r["reward"]], "o", color=colour)
        drawn = True
    for index, name in enumerate(names):
        ax.plot([], [], color=plt.get_cmap("tab10")(index % 10), label=f"{name} (dots: evaluated)")
    ax.legend(fontsize=7, loc="lower right")
    _media.save_figure(plt, fig, out)
    return drawn


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m agents.sweep",
        description="Train and evaluate over seeds x hyperparameter values as Ray Tune trials "
        "(locally, or on a cluster with --address); one table and one plot over the trials.",
    )
    parser.add_argument(
        "--env",
        default=_config.DEFAULT_ENV,
        help=f"env id, or id/variant (default {_config.DEFAULT_ENV})",
    )
    parser.add_argument("--algo", default="ppo", help="ppo or sac (default ppo)")
    parser.add_argument("--seeds", default="0-2", help="training seeds, e.g. 0-7 or 0,3,5")
    parser.add_argument(
        "--search", nargs="*", default=None, metavar="KEY=V1,V2",
        help="values to try, each key's crossed with the others' and the seeds",
    )  # fmt: skip
    parser.add_argument("--timesteps", default=None, help="env steps per trial (default: YAML)")
    parser.add_argument("--num-envs", default=None, help="worlds per trial (default: YAML)")
    parser.add_argument("--env-kwargs", default=None, help="JSON, as for agents.train")
    parser.add_argument("--config", default=None, help="hyperparameter YAML file to use")
    parser.add_argument(
        "--hyperparams", nargs="*", default=None, metavar="KEY=VALUE",
        help="fixed algorithm arguments for every trial",
    )  # fmt: skip
    parser.add_argument("--eval-episodes", type=int, default=100, help="per trial (100)")
    parser.add_argument("--cpus-per-trial", type=int, default=2, help="CPUs Ray gives a trial")
    parser.add_argument("--address", default=None, help="a Ray cluster: auto or ray://HOST:PORT")
    parser.add_argument("--out", default=None, help="default runs/sweeps/<env>_<algo>")
    add_kernels_option(parser)
    return parser


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    args = build_parser().parse_args(argv)
    env_id, algo = _config.check_env_id(args.env), _config.check_algo(args.algo)
    spec = {
        "env_id": env_id,
        "algo": algo,
        "config_file": None if args.config is None else str(Path(args.config).resolve()),
        "timesteps": args.timesteps,
        "num_envs": args.num_envs,
        "env_kwargs": _config.parse_json_kwargs("env_kwargs", args.env_kwargs),
        "overrides": _config.parse_overrides(args.hyperparams),
        "eval_episodes": _config.positive_count("eval_episodes", args.eval_episodes),
        "cpus_per_trial": _config.positive_count("cpus_per_trial", args.cpus_per_trial),
        "portable_kernels": args.portable_kernels,
    }
    out = args.out or Path("runs") / "sweeps" / f"{env_id.replace('/', '-')}_{algo}"
    return sweep(spec, parse_seeds(args.seeds), parse_search(args.search), out, args.address)


cli = _config.command(main)  # the command line: impulse2d-... and python -m


if __name__ == "__main__":
    cli()
