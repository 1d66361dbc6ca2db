"""Hyperparameter files and the resolved configuration of a run.

A hyperparameter file (``agents/hyperparams/<algo>.yml``) maps env ids to settings, RL Zoo
style: any id impulse2d registers (``impulse2d.envs.all_ids()``), the call-shot tasks
(``Pool2DCallShot-v0``) among them. An id can have more entries, named ``<env id>/<variant>``
(another budget, say), trained on the same env.
The run keys (``RUN_KEYS``) belong to this package; every other key is passed to the
algorithm's constructor (so a misspelt one is caught by checking it against the
constructor's signature, here, rather than deep inside Stable-Baselines3)::

    Pool2DCallShot-v0:
      n_timesteps: 1.5e5        # training budget (env steps = shots)
      n_envs: 512               # worlds in the batched vector env
      env_kwargs: {}            # over the id's own arguments
      eval_env_kwargs: {}       # over env_kwargs, for evaluation only (held-out levels)
      normalize: false          # VecNormalize: false, true, or {norm_obs: .., norm_reward: ..}
      policy: MlpPolicy
      policy_kwargs: {net_arch: [128, 128], activation_fn: tanh}
      pretrain_encoder: {frames: 32768}  # pixel tasks: the encoder pretrained (_pretrain.py)
      initial_action: [1, 0, 0, 0, 0, 0, 0, -0.6]  # PPO's mean action at the start
      learning_rate: 3.0e-4     # ... and any other constructor argument

A schedule is written as RL Zoo writes it: ``learning_rate: lin_5e-4`` (or ``clip_range:
lin_0.2``) falls linearly from 5e-4 at the start of training to 0 at the end. SB3 calls a
schedule with ``progress_remaining`` (1 at the start, 0 at the end), so the value is
``progress_remaining * 5e-4``.

``activation_fn`` is written by name (``tanh``, ``relu``, ``elu``, ``leaky_relu``), and
so is an image task's ``features_extractor_class`` (``NatureCNN``, ``ShotCNN``,
``KeypointCNN``); each is
turned into its class only when the model is built, so the resolved config written to a
run directory stays plain YAML.
"""

from __future__ import annotations

import copy
import inspect
import json
import math
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

import impulse2d.envs as _envs

from . import _pretrain

HYPERPARAMS_DIR = Path(__file__).parent / "hyperparams"
ALGOS = ("ppo", "sac")
ENV_IDS = tuple(_envs.all_ids())
DEFAULT_ENV = "Pool2DCallShot-v0"
# Keys of a hyperparameter entry that configure the run, not the algorithm.
RUN_KEYS = (
    "n_timesteps",
    "n_envs",
    "env_kwargs",
    "eval_env_kwargs",
    "normalize",
    "policy",
    "pretrain_encoder",
    "initial_action",
)
ACTIVATIONS = ("tanh", "relu", "elu", "leaky_relu")
FEATURE_EXTRACTORS = ("NatureCNN", "ShotCNN", "KeypointCNN")  # SB3's, and agents._cnn's
SCHEDULED = ("learning_rate", "clip_range")  # keys that take ``lin_<value>``


class _Loader(yaml.SafeLoader):
    """YAML 1.1 reads ``1e-3`` (no dot) as a string; hyperparameters mean a number."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$"
    ),
    list("-+0123456789."),
)


def _yaml(text: Any) -> Any:
    return yaml.load(text, Loader=_Loader)  # a SafeLoader subclass: no arbitrary objects


def algo_class(algo: str) -> type:
    """The Stable-Baselines3 class of ``algo`` (imported lazily: torch is slow to load)."""
    check_algo(algo)
    from stable_baselines3 import PPO, SAC

    return {"ppo": PPO, "sac": SAC}[algo]


def check_algo(algo: Any) -> str:
    if algo not in ALGOS:
        raise ValueError(f"algo must be one of {list(ALGOS)}, got {algo!r}")
    return algo


def check_env_id(env_id: Any) -> str:
    """An env id impulse2d registers, or ``<env id>/<variant>``: another entry of the
    hyperparameter file for that env, trained on the same env."""
    base, sep, variant = env_id.partition("/") if isinstance(env_id, str) else (env_id, "", "")
    if base not in ENV_IDS or (sep and not re.fullmatch(r"[A-Za-z0-9_.-]+", variant)):
        raise ValueError(
            f"env must be one of {list(ENV_IDS)}, or one of them followed by /<variant> "
            f"(another YAML entry for that id), got {env_id!r}"
        )
    return env_id


def env_of(entry: str) -> str:
    """The env id of a hyperparameter entry's name (``Pool2D-v0/long`` -> ``Pool2D-v0``)."""
    return entry.partition("/")[0]


def positive_count(name: str, value: Any) -> int:
    """A positive whole number, also from ``2e5`` or ``"2e5"`` (the CLI's spelling)."""
    try:
        number = float(value)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a positive number, got {value!r}") from error
    if isinstance(value, bool) or not math.isfinite(number) or number != int(number):
        raise ValueError(f"{name} must be a positive whole number, got {value!r}")
    if number <= 0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return int(number)


def load_hyperparams(algo: str, env_id: str, path: str | Path | None = None) -> dict[str, Any]:
    """The entry for ``env_id`` in ``path`` (default: ``agents/hyperparams/<algo>.yml``),
    checked; a copy the caller may change."""
    check_algo(algo)
    check_env_id(env_id)
    path = Path(path) if path is not None else HYPERPARAMS_DIR / f"{algo}.yml"
    if not path.is_file():
        raise ValueError(f"config: no such file {str(path)!r}")
    with open(path) as file:
        table = _yaml(file) or {}
    if not isinstance(table, dict) or env_id not in table:
        raise ValueError(f"config: {str(path)!r} has no entry for {env_id!r}")
    entry = copy.deepcopy(table[env_id])
    if not isinstance(entry, dict):
        raise ValueError(f"config: the {env_id!r} entry of {str(path)!r} must be a mapping")
    return entry


def parse_json_kwargs(name: str, text: str | None) -> dict[str, Any]:
    """``--env-kwargs '{"num_balls": 1}'`` as a dict."""
    if text is None or text == "":
        return {}
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        raise ValueError(f"{name} must be a JSON object, got {text!r}: {error}") from error
    if not isinstance(value, dict):
        raise ValueError(f"{name} must be a JSON object, got {text!r}")
    return value


def parse_overrides(items: list[str] | None) -> dict[str, Any]:
    """``--hyperparams learning_rate=1e-3 n_steps=16`` as a dict (values read as YAML)."""
    out: dict[str, Any] = {}
    for item in items or []:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise ValueError(f"hyperparams must be key=value pairs, got {item!r}")
        out[key] = _yaml(value)
    return out


def resolve(
    algo: str,
    env_id: str,
    *,
    config_file: str | Path | None = None,
    timesteps: Any = None,
    num_envs: Any = None,
    env_kwargs: dict[str, Any] | None = None,
    overrides: dict[str, Any] | None = None,
    seed: Any = 0,
    base: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """The full configuration of a run: the file's entry (or, with ``base``, a resolved
    config such as a resumed run's) with the command line's values on top, checked.
    ``env_id`` names the entry: an env id, or ``<env id>/<variant>``. Returns
    ``{"env_id", "entry", "algo", "seed", "n_timesteps", "n_envs", "env_kwargs",
    "eval_env_kwargs", "normalize", "policy", "pretrain_encoder", "initial_action", "hyperparams"}``
    (plain YAML-able values; ``env_id`` is the env itself, ``entry`` the entry's name)."""
    check_env_id(env_id)
    if base is not None:
        entry = {key: copy.deepcopy(base[key]) for key in RUN_KEYS if key in base}
        entry.update(copy.deepcopy(base.get("hyperparams", {})))
    else:
        entry = load_hyperparams(algo, env_id, config_file)
    entry.update(overrides or {})
    if seed is None or isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be an int >= 0, got {seed!r}")
    config: dict[str, Any] = {"env_id": env_of(env_id), "entry": env_id, "algo": algo}
    config["seed"] = seed
    steps = timesteps if timesteps is not None else entry.pop("n_timesteps", None)
    entry.pop("n_timesteps", None)
    if steps is None:
        raise ValueError("timesteps: not given and the config has no n_timesteps")
    config["n_timesteps"] = positive_count("timesteps", steps)
    envs = num_envs if num_envs is not None else entry.pop("n_envs", 8)
    entry.pop("n_envs", None)
    config["n_envs"] = positive_count("num_envs", envs)
    kwargs = entry.pop("env_kwargs", None) or {}
    if not isinstance(kwargs, dict):
        raise ValueError(f"env_kwargs must be a mapping, got {kwargs!r}")
    config["env_kwargs"] = {**kwargs, **(env_kwargs or {})}
    # What evaluation plays, over env_kwargs: held-out generated levels, say.
    evaluation = entry.pop("eval_env_kwargs", None) or {}
    if not isinstance(evaluation, dict):
        raise ValueError(f"eval_env_kwargs must be a mapping, got {evaluation!r}")
    config["eval_env_kwargs"] = evaluation
    config["normalize"] = _check_normalize(entry.pop("normalize", False))
    config["policy"] = entry.pop("policy", "MlpPolicy")
    config["initial_action"] = _check_initial_action(algo, entry.pop("initial_action", None))
    # A pixel task's encoder taught to read the table first (agents/_pretrain.py).
    config["pretrain_encoder"] = _pretrain.check_pretrain(entry.pop("pretrain_encoder", None))
    _check_algo_kwargs(algo, entry)
    config["hyperparams"] = entry
    return config


def _check_initial_action(algo: str, value: Any) -> list[float] | None:
    """The policy's mean action before training (PPO): None, or a list of numbers in
    [-1, 1], one per action dimension (its length is checked against the env's when the
    model is built)."""
    if value is None:
        return None
    if algo != "ppo":
        raise ValueError(f"initial_action is a PPO setting (its Gaussian's mean), not {algo}'s")
    ok = (
        isinstance(value, list)
        and value
        and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and -1.0 <= v <= 1.0
            for v in value
        )
    )
    if not ok:
        raise ValueError(f"initial_action must be a list of numbers in [-1, 1], got {value!r}")
    return [float(v) for v in value]


def _check_normalize(value: Any) -> bool | dict[str, Any]:
    if isinstance(value, bool):
        return value
    allowed = {"norm_obs", "norm_reward", "clip_obs", "clip_reward", "gamma", "epsilon"}
    if isinstance(value, dict) and set(value) <= allowed:
        return value
    raise ValueError(f"normalize must be true, false or a mapping of {sorted(allowed)}")


def _check_algo_kwargs(algo: str, kwargs: dict[str, Any]) -> None:
    """Unknown constructor arguments and bad activation names fail here, by name."""
    cls = algo_class(algo)
    known = set(inspect.signature(cls.__init__).parameters) - {"self", "policy", "env"}
    unknown = sorted(set(kwargs) - known)
    if unknown:
        raise ValueError(f"hyperparams: {cls.__name__} has no parameter(s) {unknown}")
    for key in SCHEDULED:
        if key in kwargs:
            _schedule_start(key, kwargs[key])
    policy_kwargs = kwargs.get("policy_kwargs") or {}
    if not isinstance(policy_kwargs, dict):
        raise ValueError(f"policy_kwargs must be a mapping, got {policy_kwargs!r}")
    activation = policy_kwargs.get("activation_fn")
    if activation is not None and activation not in ACTIVATIONS:
        raise ValueError(f"policy_kwargs.activation_fn must be one of {ACTIVATIONS}")
    extractor = policy_kwargs.get("features_extractor_class")
    if extractor is not None and extractor not in FEATURE_EXTRACTORS:
        raise ValueError(
            f"policy_kwargs.features_extractor_class must be one of {FEATURE_EXTRACTORS} "
            f"(the image encoders; a state task's features are part of its observation), "
            f"got {extractor!r}"
        )


class LinearSchedule:
    """``start * progress_remaining``: SB3 passes 1 at the start of training, 0 at the end.
    A class, not a closure, so that a saved model pickles it by reference."""

    def __init__(self, start: float) -> None:
        self.start = float(start)

    def __call__(self, progress_remaining: float) -> float:
        return self.start * progress_remaining

    def __repr__(self) -> str:
        return f"lin_{self.start:g}"


def _schedule_start(key: str, value: Any) -> float | None:
    """The start of a ``lin_<value>`` schedule, None for a plain number; else an error."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if not math.isfinite(value) or value <= 0:
            raise ValueError(f"{key} must be > 0, got {value!r}")
        return None
    if isinstance(value, str) and value.startswith("lin_"):
        try:
            start = float(value[4:])
        except ValueError:
            start = math.nan
        if math.isfinite(start) and start > 0:
            return start
    raise ValueError(f"{key} must be a number > 0 or lin_<number > 0>, got {value!r}")


def algo_kwargs(config: dict[str, Any]) -> dict[str, Any]:
    """The constructor arguments of a resolved config, with the activation, written by
    name, as a class, and ``lin_`` schedules as callables."""
    import torch.nn as nn

    kwargs = copy.deepcopy(config["hyperparams"])
    for key in SCHEDULED:
        start = _schedule_start(key, kwargs[key]) if key in kwargs else None
        if start is not None:
            kwargs[key] = LinearSchedule(start)
    policy_kwargs = kwargs.get("policy_kwargs") or {}
    if isinstance(policy_kwargs.get("activation_fn"), str):
        names = {"tanh": nn.Tanh, "relu": nn.ReLU, "elu": nn.ELU, "leaky_relu": nn.LeakyReLU}
        policy_kwargs["activation_fn"] = names[policy_kwargs["activation_fn"]]
    if isinstance(policy_kwargs.get("features_extractor_class"), str):
        from stable_baselines3.common.torch_layers import NatureCNN

        from agents._cnn import KeypointCNN, ShotCNN

        classes = {"NatureCNN": NatureCNN, "ShotCNN": ShotCNN, "KeypointCNN": KeypointCNN}
        name = policy_kwargs["features_extractor_class"]
        policy_kwargs["features_extractor_class"] = classes[name]
    return kwargs


def save_config(config: dict[str, Any], path: Path) -> None:
    with open(path, "w") as file:
        yaml.safe_dump(config, file, sort_keys=False)


def load_config(run_dir: str | Path) -> dict[str, Any]:
    """The resolved config of a run directory (``config.yml``)."""
    path = Path(run_dir) / "config.yml"
    if not path.is_file():
        raise ValueError(f"run_dir: {str(run_dir)!r} has no config.yml (not a training run?)")
    with open(path) as file:
        return yaml.safe_load(file)


def command(main: Callable[[list[str] | None], object]) -> Callable[[list[str] | None], None]:
    """The command line of ``main`` (an installed console script such as
    ``impulse2d-train``, and ``python -m agents.train`` in the clone): bad input told in
    one line with exit status 1, not a traceback, and nothing returned to the shell (a
    console script exits with what its function returns: a path would be printed and
    exit 1 after a good run)."""

    def cli(argv: list[str] | None = None) -> None:
        try:
            main(argv)
        except ValueError as error:
            sys.exit(f"error: {error}")

    return cli
