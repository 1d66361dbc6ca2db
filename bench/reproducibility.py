"""What makes a training run repeat bitwise, and what makes it part: one knob at a time.

Same code, same seed, same library versions: what differs between two machines is the
CPU, and with it the kernels the libraries pick for it. Each library here picks kernels by
instruction set at run time, and each has a switch that forces its portable path, so this
machine can stand in for another kind:

* torch (ATen's vectorised kernels): ``ATEN_CPU_CAPABILITY=default`` (no AVX2);
* oneMKL, torch's matrix products on x86: ``MKL_CBWR=COMPATIBLE`` (its SSE2 path);
* numpy (its SIMD loops): ``NPY_DISABLE_CPU_FEATURES=X86_V3`` (no AVX2), and without its
  AVX-512 loops (``X86_V4 AVX512_ICL AVX512_SPR``);
* numba (the engine, compiled for the host CPU): ``NUMBA_CPU_NAME=generic``;
* threads: the engine on one thread instead of two, torch on two instead of one.

The probe calls ``agents.train.train`` directly, so its baseline runs torch's kernels as
picked for this CPU; the last case names them, as ``python -m agents.train`` does.

Each case runs in a fresh process (numba's cache is shared, except by the case that
changes the CPU name, which compiles other code): the engine alone (16 tables, 5 seeded
random shots, and the 15-ball rack, 3 shots; a hash of every observation and reward,
comparable across machines), then a short PPO run of the Pool entry (a
hash of the trained weights, and its mean reward over 10 evaluation episodes). A case
that matches the baseline shows that knob does not change results; one that differs
shows it does.

    python bench/reproducibility.py           # about 15 minutes on 2 cores
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_PROBE = r"""
import hashlib, json, sys
import numpy as np
torch_threads = int(sys.argv[2])
import torch
_set = torch.set_num_threads
torch.set_num_threads = lambda n: _set(torch_threads)  # train() asks for 1
import gymnasium as gym
import impulse2d  # noqa: F401
from agents import _config, evaluate
from agents.train import train

engine_threads = None if sys.argv[3] == "all" else int(sys.argv[3])
def rollout(shots, kwargs, rng):
    # sha256 of every observation and reward after the reset, first 16 hex digits
    venv = gym.make_vec("Pool2D-v0", 16, vectorization_mode="vector_entry_point",
                        threads=engine_threads, **kwargs)
    digest = hashlib.sha256()
    venv.reset(seed=0)
    for a in np.random.default_rng(rng).uniform(-1, 1, (shots, 16, 2)).astype(np.float32):
        obs, reward, *_ = venv.step(a)
        digest.update(obs.tobytes()); digest.update(reward.tobytes())
    return digest.hexdigest()[:16]
one_ball, rack = rollout(5, {"num_balls": 1}, 0), rollout(3, {}, 1)
config = _config.resolve("ppo", "Pool2DCallShot-v0", timesteps=int(sys.argv[4]), num_envs=64,
                         seed=0)
if engine_threads is not None:
    config["env_kwargs"]["threads"] = engine_threads
run = train(config, sys.argv[1], progress_bar=False)
model = _config.algo_class("ppo").load(str(run / "model.zip"), device="cpu")
weights = hashlib.sha256()
for p in model.policy.parameters():
    weights.update(p.detach().numpy().tobytes())
results = evaluate.evaluate(run, episodes=10, video=None)
print("RESULT " + json.dumps({
    "engine": one_ball, "rack": rack, "weights": weights.hexdigest()[:12],
    "reward": results["policies"]["trained"]["reward"]["mean"],
    "torch_capability": torch.backends.cpu.get_cpu_capability(),
}))
"""

PORTABLE = {"ATEN_CPU_CAPABILITY": "avx2", "MKL_CBWR": "AVX2"}  # agents/_kernels.PINNED
CASES = [
    ("baseline (kernels picked for the CPU)", {}, 1, "all"),
    ("baseline again", {}, 1, "all"),
    ("engine on 1 thread", {}, 1, "1"),
    ("torch on 2 threads", {}, 2, "all"),
    ("torch: ATEN_CPU_CAPABILITY=default", {"ATEN_CPU_CAPABILITY": "default"}, 1, "all"),
    ("MKL: MKL_CBWR=COMPATIBLE", {"MKL_CBWR": "COMPATIBLE"}, 1, "all"),
    ("numpy: NPY_DISABLE_CPU_FEATURES=X86_V3", {"NPY_DISABLE_CPU_FEATURES": "X86_V3"}, 1, "all"),
    (
        "numpy without AVX-512",
        {"NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR"},
        1,
        "all",
    ),
    ("numba: NUMBA_CPU_NAME=generic", {"NUMBA_CPU_NAME": "generic"}, 1, "all"),
    # The kernels named, not picked for the CPU: what agents.train sets by default.
    ("named: ATEN_CPU_CAPABILITY=avx2 + MKL_CBWR=AVX2", PORTABLE, 1, "all"),
]


def run_case(
    env: dict[str, str], torch_threads: int, engine_threads: str, steps: int, cache: Path
) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        if "NUMBA_CPU_NAME" in env:
            cache = Path(tmp) / "numba_cache"
        child = {**os.environ, **env, "NUMBA_CACHE_DIR": str(cache)}
        child["PYTHONPATH"] = os.pathsep.join([str(ROOT), child.get("PYTHONPATH", "")])
        done = subprocess.run(
            [sys.executable, "-c", _PROBE, str(Path(tmp) / "run"), str(torch_threads),
             engine_threads, str(steps)],
            cwd=ROOT, env=child, capture_output=True, text=True, check=False,
        )  # fmt: skip
    lines = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]
    if done.returncode != 0 or not lines:
        raise RuntimeError(f"case failed:\n{done.stderr[-2000:]}")
    return json.loads(lines[-1][len("RESULT ") :])


def _cpu() -> str:
    """The CPU's model name and its widest vector extension (Linux), for the table."""
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return "CPU unknown"
    model = next((line.split(":", 1)[1].strip() for line in text.splitlines()
                  if line.startswith("model name")), "CPU unknown")  # fmt: skip
    flags = next((line for line in text.splitlines() if line.startswith("flags")), "")
    widest = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "no AVX2"
    return f"{model} ({widest})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2048, help="PPO steps per case (2048)")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        for name, env, torch_threads, engine_threads in CASES:
            result = run_case(env, torch_threads, engine_threads, args.steps, Path(cache))
            rows.append((name, result))
            print(f"{name}: {result}", file=sys.stderr, flush=True)
    base = rows[0][1]
    print(f"\n{args.steps:,} PPO steps on 64 tables, seed 0; evaluated on 10 episodes; {_cpu()}")
    print(
        f"engine rollouts (sha256 of observations and rewards, 16 hex digits): one ball "
        f"{base['engine']}, rack {base['rack']}\n"
    )
    print("| case | engine rollout | trained weights | reward | torch kernels |")
    print("|---|---|---|---|---|")
    for name, r in rows:
        same = (r["engine"], r["rack"]) == (base["engine"], base["rack"])
        same_engine = "same" if same else "DIFFERS"
        same_weights = "same" if r["weights"] == base["weights"] else "DIFFERS"
        print(
            f"| {name} | {same_engine} | {same_weights} | {r['reward']:.2f} | "
            f"{r['torch_capability']} |"
        )


if __name__ == "__main__":
    main()
