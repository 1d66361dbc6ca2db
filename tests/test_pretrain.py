"""The pixel encoder's pretraining (``agents._pretrain``): its labels are the state task's
observations of the very positions drawn, its regression learns, its settings are
checked by name, and a run with ``pretrain_encoder`` starts PPO from the fitted encoder."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from agents import _config, _pretrain, train

import impulse2d  # noqa: F401  (registers the ids)

PIXELS = "Pool2DPixelsCallShot-v0"


def test_labels_are_the_state_tasks_observations_of_the_frames_positions() -> None:
    """Reset frames of the pixel task carry, as labels, Pool2DCallShot-v0's observation
    of the same seeded tables, scaled column by column from [low, high] to [-1, 1]."""
    frames, labels = _pretrain.table_frames(PIXELS, {}, 300, seed=7)
    assert frames.shape == (300, 64, 64, 3) and frames.dtype == np.uint8
    worlds = _pretrain.WORLDS
    state = gym.make_vec("Pool2DCallShot-v0", worlds, vectorization_mode="vector_entry_point")
    obs, _ = state.reset(seed=7)
    low, high = state.single_observation_space.low, state.single_observation_space.high
    scaled = 2.0 * (obs.astype(np.float64) - low) / (high - low) - 1.0
    np.testing.assert_allclose(labels[: _pretrain.WORLDS], scaled, atol=1e-6)
    assert labels.min() >= -1.0 and labels.max() <= 1.0
    # the frames after a shot are among them: some tables changed between the two draws
    assert not np.array_equal(labels[_pretrain.WORLDS :], labels[: 300 - _pretrain.WORLDS])
    # and the frames are those positions: a table's frame differs where its balls differ
    pixels = gym.make_vec(PIXELS, 2, vectorization_mode="vector_entry_point")
    np.testing.assert_array_equal(pixels.reset(seed=7)[0], frames[:2])


def test_a_state_task_is_refused() -> None:
    with pytest.raises(ValueError, match="pretrain_encoder needs a pixel task"):
        _pretrain.table_frames("Pool2DCallShot-v0", {}, 20, seed=0)


def test_r_squared_by_hand() -> None:
    target = np.array([[0.0, 1.0], [2.0, 1.0], [4.0, 1.0]])
    predicted = np.array([[1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    # column 0: variance 8/3, residual 2/3 -> 1 - 1/4; column 1 never varies: nan
    r2 = _pretrain._r_squared(predicted, target)
    assert r2[0] == pytest.approx(0.75) and np.isnan(r2[1])


def _policy() -> object:
    from stable_baselines3 import PPO

    from impulse2d.envs.sb3 import make_sb3_vec_env

    config = _config.resolve("ppo", PIXELS, seed=0)
    venv = make_sb3_vec_env(PIXELS, 2, seed=0)
    policy_kwargs = _config.algo_kwargs(config)["policy_kwargs"]
    return PPO(config["policy"], venv, n_steps=8, batch_size=16, policy_kwargs=policy_kwargs).policy


def test_fitting_lowers_the_loss_and_changes_only_the_encoder() -> None:
    import torch

    torch.manual_seed(0)
    policy = _policy()
    frames, labels = _pretrain.table_frames(PIXELS, {}, 512, seed=1)
    encoder = [p.detach().clone() for p in policy.features_extractor.parameters()]
    action = policy.action_net.weight.detach().clone()
    before = len(list(policy.parameters()))
    settings = {**_pretrain.DEFAULTS, "epochs": 4, "batch_size": 64}
    report = _pretrain.fit_encoder(policy, frames, labels, settings, seed=0)
    assert len(report["train_loss"]) == 4
    assert report["train_loss"][-1] < 0.95 * report["train_loss"][0]
    assert len(report["held_out_r2"]) == labels.shape[1]
    after = list(policy.features_extractor.parameters())
    assert all(not torch.equal(a, b) for a, b in zip(encoder, after, strict=True))
    assert torch.equal(policy.action_net.weight, action)  # the head is the regression's own
    assert len(list(policy.parameters())) == before


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ([1], "pretrain_encoder must be a mapping"),
        ({"frame": 10}, "pretrain_encoder must be a mapping"),
        ({"frames": 10}, "frames must be >= 20"),
        ({"epochs": 0}, "epochs must be an int >= 1"),
        ({"batch_size": 2.5}, "batch_size must be an int >= 1"),
        ({"learning_rate": 0}, r"learning_rate must be in \(0, 1\)"),
        ({"learning_rate": True}, r"learning_rate must be in \(0, 1\)"),
    ],
)
def test_bad_settings_are_named(value: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        _config.resolve("ppo", PIXELS, overrides={"pretrain_encoder": value})


def test_settings_take_their_defaults() -> None:
    config = _config.resolve("ppo", PIXELS, overrides={"pretrain_encoder": {"frames": 64}})
    assert config["pretrain_encoder"] == {**_pretrain.DEFAULTS, "frames": 64}
    assert _config.resolve("ppo", "Pool2DCallShot-v0")["pretrain_encoder"] is None


def test_a_run_with_pretraining_starts_from_the_fitted_encoder(tmp_path: Path) -> None:
    """Built with and without ``pretrain_encoder`` from the same seed, the models differ
    in their encoders only; the run writes what the regression reached."""
    import torch

    tiny = {"n_steps": 4, "batch_size": 16, "n_epochs": 1}
    plain = _config.resolve("ppo", PIXELS, num_envs=4, overrides={**tiny, "pretrain_encoder": None})
    fitted = _config.resolve("ppo", PIXELS, num_envs=4, overrides={
        **tiny, "pretrain_encoder": {"frames": 64, "epochs": 1, "batch_size": 32}})  # fmt: skip
    models = [train.build(c, tmp_path / name).model for c, name in ((plain, "a"), (fitted, "b"))]
    encoders = [m.policy.features_extractor.state_dict() for m in models]
    assert any(not torch.equal(encoders[0][k], encoders[1][k]) for k in encoders[0])
    heads = [m.policy.action_net.state_dict() for m in models]
    assert all(torch.equal(heads[0][k], heads[1][k]) for k in heads[0])
    report = json.loads((tmp_path / "b" / "pretrain.json").read_text())
    assert report["settings"]["frames"] == 64 and len(report["train_loss"]) == 1
    assert not (tmp_path / "a" / "pretrain.json").exists()
    assert _config.load_config(tmp_path / "b")["pretrain_encoder"]["frames"] == 64
