"""Teach a pixel task's encoder to read the table before PPO starts.

PPO from pixels alone (``Pool2DPixelsCallShot-v0``'s runs B, K and C in
``agents/TUNING.md``) never learned to see: a ball is 1.5 pixels across at 64 x 64, and
the only signal reaching the encoder is the advantage of a shot, which says little about
*where* anything is until the policy already uses where things are. The agents settled
on a fixed call that ignores the image (0.60-0.65, the best constant call's score).

So the encoder first learns, by supervised regression, to read off a frame what the
state task (``Pool2DCallShot-v0``) is told about the same position: the balls' places and,
per pocket, the cut, the distances, how clear both paths are and the speed window (the
call-shot observation, ``impulse2d.envs.callshot``), each column scaled to [-1, 1] by its
bounds. The labels come from the simulator and are used in training only; the policy
that plays still sees nothing but the frame. (This is privileged-information
pretraining, as asymmetric actor-critic and "learning by cheating" use the simulator's
state to train a vision policy.) Then PPO trains the whole policy, the encoder
included, from these weights.

The frames are the task's own: ``frames`` positions from the pixel task's vector env,
played from reset with random call-shot actions (so that the positions after a shot are
among them), each world seeded from ``seed``. A tenth is held out to report how well the
encoder reads them: the coefficient of determination R^2 of each label column on those
frames (1 is perfect; 0 is no better than the mean). Named in a hyperparameter file as a
run key::

    pretrain_encoder: {frames: 32768, epochs: 8, batch_size: 256, learning_rate: 1.0e-3}
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import numpy as np

DEFAULTS = {"frames": 32768, "epochs": 8, "batch_size": 256, "learning_rate": 1.0e-3}
WORLDS = 256  # worlds in the vector env that plays the frames
HELD_OUT = 0.1  # share of the frames kept to measure R^2


def check_pretrain(value: Any) -> dict[str, Any] | None:
    """The ``pretrain_encoder`` run key: None (no pretraining) or a mapping of
    ``DEFAULTS``'s keys (missing ones take their defaults)."""
    if value is None or value is False:
        return None
    if not isinstance(value, dict) or not set(value) <= set(DEFAULTS):
        raise ValueError(f"pretrain_encoder must be a mapping of {sorted(DEFAULTS)}, got {value!r}")
    out = {**DEFAULTS, **value}
    for key in ("frames", "epochs", "batch_size"):
        if isinstance(out[key], bool) or not isinstance(out[key], int) or out[key] < 1:
            raise ValueError(f"pretrain_encoder.{key} must be an int >= 1, got {out[key]!r}")
    if out["frames"] < 20:
        raise ValueError(f"pretrain_encoder.frames must be >= 20, got {out['frames']!r}")
    rate = out["learning_rate"]
    if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not 0 < rate < 1:
        raise ValueError(f"pretrain_encoder.learning_rate must be in (0, 1), got {rate!r}")
    return out


def table_frames(
    env_id: str, env_kwargs: dict[str, Any], count: int, seed: int
) -> tuple[np.ndarray, np.ndarray]:
    """``count`` frames of a call-shot pixel task ``(count, h, w, 3)`` uint8 and the
    state task's observation of each ``(count, f)`` float32 in [-1, 1] (module docstring)."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the env ids)

    venv = gym.make_vec(env_id, WORLDS, vectorization_mode="vector_entry_point", **env_kwargs)
    if getattr(venv.unwrapped, "obs_type", None) != "pixels":
        venv.close()
        raise ValueError(f"pretrain_encoder needs a pixel task; {env_id} observes states")
    low, high = venv.state_observation_bounds()
    rng = np.random.default_rng(seed)
    obs, _ = venv.reset(seed=seed)
    # Filled in place: 65,536 frames of 64 x 64 are 0.8 GB, and a list of batches
    # concatenated at the end would hold them twice.
    frames = np.empty((count, *obs.shape[1:]), np.uint8)
    labels = np.empty((count, low.size), np.float32)
    start = time.perf_counter()
    for first in range(0, count, WORLDS):
        n = min(WORLDS, count - first)
        frames[first : first + n] = obs[:n]
        scaled = 2.0 * (venv.state_observation() - low) / (high - low) - 1.0
        labels[first : first + n] = scaled[:n]
        actions = rng.uniform(-1.0, 1.0, venv.action_space.shape).astype(np.float32)
        obs = venv.step(actions)[0]
    venv.close()
    print(f"pretrain encoder: {count:,} frames of {env_id} drawn in "
          f"{time.perf_counter() - start:.0f} s", flush=True)  # fmt: skip
    return frames, labels


def _r_squared(predicted: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Per column: 1 - residual variance / variance (columns that never vary: nan)."""
    variance = target.var(axis=0)
    residual = ((predicted - target) ** 2).mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(variance > 1e-12, 1.0 - residual / variance, np.nan)


def fit_encoder(
    policy: Any, frames: np.ndarray, labels: np.ndarray, settings: dict[str, Any], seed: int
) -> dict[str, Any]:
    """Train ``policy``'s features extractor and a linear head on it to predict
    ``labels`` from ``frames`` (mean squared error, Adam); the head is dropped after.
    Returns the losses and the held-out R^2 of each label column."""
    import torch
    from torch import nn

    generator = torch.Generator().manual_seed(seed)
    encoder = policy.features_extractor
    head = nn.Linear(encoder.features_dim, labels.shape[1])
    parameters = list(encoder.parameters()) + list(head.parameters())
    optimiser = torch.optim.Adam(parameters, lr=settings["learning_rate"])
    images = torch.as_tensor(frames).permute(0, 3, 1, 2)  # channels first, as SB3 feeds them
    targets = torch.as_tensor(labels)
    split = max(1, int(len(frames) * HELD_OUT))
    order = torch.randperm(len(frames), generator=generator)
    test, train = order[:split], order[split:]

    def predict(index: torch.Tensor) -> torch.Tensor:
        return head(policy.extract_features(images[index].float(), encoder))

    start, losses = time.perf_counter(), []
    for epoch in range(settings["epochs"]):
        shuffled = train[torch.randperm(len(train), generator=generator)]
        total = 0.0
        for batch in shuffled.split(settings["batch_size"]):
            loss = nn.functional.mse_loss(predict(batch), targets[batch])
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            total += float(loss.detach()) * len(batch)
        losses.append(total / len(train))
        print(f"pretrain encoder: epoch {epoch + 1}/{settings['epochs']}  loss {losses[-1]:.4f}  "
              f"{time.perf_counter() - start:.0f} s", flush=True)  # fmt: skip
    with torch.no_grad():
        predicted = torch.cat([predict(batch) for batch in test.split(1024)]).numpy()
    r2 = _r_squared(predicted, labels[test.numpy()])
    seconds = time.perf_counter() - start
    return {"train_loss": losses, "held_out_r2": r2.tolist(), "seconds": seconds}


def pretrain(policy: Any, config: dict[str, Any], run_dir: Path | None = None) -> dict[str, Any]:
    """Pretrain ``policy``'s encoder as the config's ``pretrain_encoder`` says (module
    docstring); writes ``pretrain.json`` into ``run_dir`` when given."""
    settings = check_pretrain(config.get("pretrain_encoder"))
    if settings is None:
        raise ValueError("pretrain: the config has no pretrain_encoder")
    frames, labels = table_frames(
        config["env_id"], config["env_kwargs"], settings["frames"], config["seed"]
    )
    report = {"settings": settings, **fit_encoder(policy, frames, labels, settings, config["seed"])}
    r2 = np.array(report["held_out_r2"], dtype=float)
    print(f"pretrain encoder: held-out R^2 {np.nanmean(r2):.3f} (mean over {np.isfinite(r2).sum()} "
          f"label columns), {report['seconds']:.0f} s", flush=True)  # fmt: skip
    if run_dir is not None:
        (Path(run_dir) / "pretrain.json").write_text(json.dumps(report, indent=2) + "\n")
    return report
