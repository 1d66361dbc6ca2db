"""Every keyword of Pool2D-v0 and Slingshot2D-v0, single and vector, given every kind of
wrong value: each is refused at construction with a ``ValueError`` that names the keyword
and its rule, through ``gym.make`` and ``gym.make_vec(..., "vector_entry_point")`` alike;
and the extreme values a rule allows construct and play a step with finite numbers.

The kinds of value are the engine's catalogue (``tests/inputs_catalog.py``: ``BAD`` and
``EXTREME``), with the numpy scalars and huge numbers of each kind added.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.core.runner import available_threads
from impulse2d.envs import pool, slingshot
from impulse2d.envs._core import MAX_ENVS, MAX_SHOT_SECONDS
from inputs_catalog import BAD, EXTREME, INF, NAN, Nonsense

REALS = [
    *(value for values in BAD["real"].values() for value in values),
    np.float32(NAN),
    np.float64(-INF),
    np.complex64(1.0),
    np.str_("1.0"),
    10**400,  # an int no float holds
    np.array([1.0]),
]
COUNTS = [
    *(value for kind, values in BAD["count"].items() if kind != "below 1" for value in values),
    NAN,
    INF,
    -INF,
    1e300,
    np.float64(NAN),
    np.float32(3.0),
    np.str_("2"),
    np.bool_(False),
    -1,
    np.int64(-1),
    10**30,
    np.uint64(2**64 - 1),
]
WORDS = [
    1,
    1.0,
    NAN,
    True,
    np.bool_(True),
    1 + 0j,
    b"rack",
    ["rack"],
    np.array(["rack"]),
    Nonsense(),
    {},
    "",
    "nonsense",
    np.str_("nonsense"),
]


def _positive_int(value: Any) -> bool:
    """An int > 0: every one is a seed, so a legal ``start_level``, however big."""
    is_int = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    return is_int and value > 0


# keyword -> the wrong values to give it, per env (the game's keywords reach the single
# and the vector env alike).
GAME_KEYWORDS: dict[str, dict[str, list[Any]]] = {
    "Pool2D-v0": {
        "num_balls": [*COUNTS, 0, 16, np.int64(16)],
        "layout": WORDS,  # None is the documented default
        "max_shot_seconds": [*REALS, 0, 0.0, -1.0, np.float64(-0.0), 3600.5, 1e300, 1e16],
        "shaping": [*REALS, -1.0, -5e-324, 1000.5, 1e300, np.float64(1e16)],
        "device": [*WORDS, None, "gpu", "cuda:0"],
        "obs_type": [*WORDS, None, "rgb", "pixel"],
        "pixel_size": [*COUNTS, 0, 15, 1025],
    },
    "Slingshot2D-v0": {
        "level": [*WORDS, None],
        "num_birds": [*COUNTS, 0, 11],
        "max_shot_seconds": [*REALS, 0, -1.0, 1e300, INF],
        "num_levels": [*COUNTS, 2**63],
        # start_level's own rule, with num_levels > 0 (without, start_level needs it).
        "start_level": [v for v in COUNTS if not _positive_int(v)],
        "device": [*WORDS, None, "gpu"],
        "obs_type": [*WORDS, None, "rgb"],
        "pixel_size": [*COUNTS, 0, 15, 1025],
    },
}
NOT_NONE = [value for value in COUNTS if value is not None]
# The vector env's own keywords (``gym.make`` has its own ``max_episode_steps``, the
# ``TimeLimit`` wrapper's, and refuses a float there with Gymnasium's TypeError).
VECTOR_KEYWORDS: dict[str, list[Any]] = {
    "num_envs": [*COUNTS, 0, MAX_ENVS + 1],
    "max_episode_steps": [*NOT_NONE, 0, 2**63],  # None: no truncation
    "threads": [*NOT_NONE, 0, available_threads() + 1],  # None: every core
    "autoreset_mode": [*WORDS, None, "next_step!"],
    "render_mode": [*WORDS, "human", "ascii"],  # no window for a batch
}
SINGLE_RENDER_MODES = [*WORDS, "ascii", "rgb"]
ENTRY = {"Pool2D-v0": pool.Pool2DEnv, "Slingshot2D-v0": slingshot.Slingshot2DEnv}
BASE = {"start_level": {"num_levels": 5}}  # what a keyword needs beside it


def _cases(vector: bool) -> list[Any]:
    cases = []
    for env_id, keywords in GAME_KEYWORDS.items():
        for name, values in keywords.items():
            cases += [pytest.param(env_id, name, v, id=f"{env_id}-{name}-{v!r}") for v in values]
    for env_id in GAME_KEYWORDS:
        if vector:
            for name, values in VECTOR_KEYWORDS.items():
                cases += [
                    pytest.param(env_id, name, v, id=f"{env_id}-{name}-{v!r}") for v in values
                ]
        else:
            cases += [
                pytest.param(env_id, "render_mode", v, id=f"{env_id}-render_mode-{v!r}")
                for v in SINGLE_RENDER_MODES
            ]
    return cases


def _refused(name: str, make: Any) -> None:
    with pytest.raises(ValueError) as raised:
        make()
    message = str(raised.value)
    assert message.startswith(name) and (" must " in message or " needs " in message), message


@pytest.mark.parametrize(("env_id", "name", "value"), _cases(vector=False))
def test_single_env_refuses_a_bad_keyword_by_name(env_id: str, name: str, value: Any) -> None:
    kwargs = {**BASE.get(name, {}), name: value}
    if name == "render_mode" and not isinstance(value, str):
        # ``gym.make`` itself reads a render mode that is not in ``metadata`` as a string
        # (``render_mode.endswith``) before the env sees it: give it to the env directly.
        _refused(name, lambda: ENTRY[env_id](**kwargs))
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # gym.make warns of an unknown render mode first
        _refused(name, lambda: gym.make(env_id, **kwargs))


@pytest.mark.parametrize(("env_id", "name", "value"), _cases(vector=True))
def test_vector_env_refuses_a_bad_keyword_by_name(env_id: str, name: str, value: Any) -> None:
    kwargs = {"num_envs": 2, **BASE.get(name, {}), name: value}
    _refused(name, lambda: gym.make_vec(env_id, vectorization_mode="vector_entry_point", **kwargs))


def test_messages_give_the_rule_and_the_value() -> None:
    """The project's style: the keyword, its range with its unit, the value given."""
    seconds = "max_shot_seconds must be"
    cases = [
        ("Pool2D-v0", {"max_shot_seconds": 1e300}, f"{seconds} in (0, 3600] s, got 1e+300"),
        (
            "Pool2D-v0",
            {"max_shot_seconds": NAN},
            f"{seconds} a real number in (0, 3600] s, got nan",
        ),
        ("Pool2D-v0", {"shaping": -1.0}, "shaping must be in [0, 1000], got -1"),
        ("Pool2D-v0", {"num_balls": 2.0}, "num_balls must be an int in [1, 15], got 2.0"),
        ("Pool2D-v0", {"layout": np.array(["rack"])}, "layout must be one of 'rack', 'random'"),
        ("Slingshot2D-v0", {"num_birds": 10**30}, f"num_birds must be in [1, 10], got {10**30}"),
        ("Slingshot2D-v0", {"level": None}, "level must be one of 'random', 'handmade', "),
    ]
    for env_id, kwargs, message in cases:
        with pytest.raises(ValueError) as raised:
            gym.make(env_id, **kwargs)
        assert str(raised.value).startswith(message)
    with pytest.raises(ValueError) as raised:
        gym.make_vec("Pool2D-v0", 2, vectorization_mode="vector_entry_point", max_episode_steps=1.5)
    assert str(raised.value) == "max_episode_steps must be an int in [1, 2**63 - 1], got 1.5"
    with pytest.raises(ValueError) as raised:
        gym.make_vec("Pool2D-v0", MAX_ENVS + 1, vectorization_mode="vector_entry_point")
    assert str(raised.value) == f"num_envs must be in [1, {MAX_ENVS}], got {MAX_ENVS + 1}"


def _plays(make: Any) -> None:
    """Reset, one random shot, finite observations and rewards."""
    env = make()
    obs, _ = env.reset(seed=0)
    assert np.isfinite(obs).all()
    obs, reward, *_ = env.step(env.action_space.sample())
    assert np.isfinite(obs).all() and np.isfinite(reward).all()
    env.close()


def _extreme_cases() -> list[Any]:
    cases = []
    for env_id, keywords in GAME_KEYWORDS.items():
        for name in keywords:
            if name in ("max_shot_seconds", "shaping"):
                for value in (*EXTREME, np.float32(1e-30)):
                    cases.append(pytest.param(env_id, name, value, id=f"{env_id}-{name}-{value!r}"))
    allowed = [
        ("Pool2D-v0", "max_shot_seconds", MAX_SHOT_SECONDS),
        ("Pool2D-v0", "max_shot_seconds", np.float64(5e-324)),
        ("Pool2D-v0", "shaping", 1000.0),
        ("Pool2D-v0", "num_balls", np.int8(1)),
        ("Pool2D-v0", "layout", np.str_("random")),
        ("Slingshot2D-v0", "max_shot_seconds", MAX_SHOT_SECONDS),
        ("Slingshot2D-v0", "num_birds", np.uint8(10)),
        ("Slingshot2D-v0", "num_levels", 2**63 - 1),
        ("Slingshot2D-v0", "start_level", 10**30),  # any seed: numpy takes big ints
        ("Slingshot2D-v0", "level", np.str_("tower")),
    ]
    cases += [pytest.param(*case, id=f"{case[0]}-{case[1]}-{case[2]!r}") for case in allowed]
    return cases


@pytest.mark.parametrize(("env_id", "name", "value"), _extreme_cases())
def test_extreme_values_are_refused_by_name_or_play(env_id: str, name: str, value: Any) -> None:
    """``EXTREME`` numbers either break the keyword's rule (a ValueError naming it) or
    are inside it and play, single and vector, with finite observations and rewards."""
    kwargs = {**({"num_levels": 1} if name == "start_level" else {}), name: value}
    makers = [
        lambda: gym.make(env_id, **kwargs),
        lambda: gym.make_vec(env_id, 2, vectorization_mode="vector_entry_point", **kwargs),
    ]
    for make in makers:
        try:
            make()
        except ValueError as error:
            assert str(error).startswith(name) and " must " in str(error), error
            continue
        _plays(make)


@pytest.mark.parametrize("env_id", list(GAME_KEYWORDS))
def test_vector_keywords_at_their_limits_play(env_id: str) -> None:
    """The vector env's own keywords at the ends of their rules, as numpy scalars too."""
    for kwargs in (
        {"max_episode_steps": 2**63 - 1},
        {"max_episode_steps": np.int64(1), "autoreset_mode": "SameStep"},
        {"threads": available_threads(), "autoreset_mode": AutoresetMode.DISABLED},
        {"threads": np.int32(1), "max_episode_steps": None, "render_mode": np.str_("rgb_array")},
    ):
        _plays(
            lambda kwargs=kwargs: gym.make_vec(
                env_id, np.int64(2), vectorization_mode="vector_entry_point", **kwargs
            )
        )


def test_a_one_step_shot_ends_at_the_cap() -> None:
    """The smallest ``max_shot_seconds`` (5e-324 s) is one physics step: the shot is
    stopped where it stands, and the next shot plays from there."""
    env = gym.make("Pool2D-v0", num_balls=1, max_shot_seconds=5e-324)
    env.reset(seed=0)
    _, _, _, _, info = env.step(np.array([0.0, 1.0], np.float32))
    assert info["physics_steps"] == 1 and math.isfinite(env.unwrapped.game.world.energy().total)
