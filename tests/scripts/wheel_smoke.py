"""The built wheel, installed into a fresh venv with the `envs` extra only, run from
outside the clone (``.ci/run``): the package imports from site-packages, its version is
the wheel's, a Pool2D-v0 shot plays, the installed commands answer, and the training
code's files are in the package. Prints the seconds from the import to the first shot
(the kernels compile there on a fresh install)."""

from __future__ import annotations

import importlib.metadata
import shutil
import subprocess
import sys
import time
from pathlib import Path

started = time.perf_counter()
import gymnasium as gym  # noqa: E402

import impulse2d  # noqa: E402

here = Path(impulse2d.__file__).resolve()
assert "site-packages" in here.parts, f"impulse2d imported from {here}, not the install"
assert impulse2d.__version__ == importlib.metadata.version("impulse2d")
env = gym.make("Pool2D-v0")
env.reset(seed=0)
_, reward, terminated, truncated, info = env.step(env.action_space.sample())
first_shot = time.perf_counter() - started
assert info["physics_steps"] > 0
agents = here.parent / "agents"
assert (agents / "hyperparams" / "ppo.yml").is_file() and (agents / "train.py").is_file()
assert (here.parent / "py.typed").is_file()
for command in ("impulse2d-tour", "impulse2d-compile", "impulse2d-demo"):
    path = shutil.which(command) or str(Path(sys.executable).parent / command)
    done = subprocess.run([path, "--help"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, (command, done.stderr)
moved = subprocess.run(
    [sys.executable, "-m", "impulse2d.demo", "--list"], capture_output=True, text=True
)
assert moved.returncode == 0 and "impulse2d.apps.demo" in moved.stderr, moved.stderr
print(f"wheel smoke test: impulse2d {impulse2d.__version__} from {here.parent}; "
      f"import to the first Pool2D-v0 shot {first_shot:.1f} s; commands answer")  # fmt: skip
