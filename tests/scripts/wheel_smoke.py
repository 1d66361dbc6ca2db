"""The built wheel, installed into a fresh venv with the `envs` extra only, run from
outside the clone (``.ci/run``): the package imports from site-packages, its version is
the wheel's, a Pool2D-v0 shot plays with no kernel compiled (the wheel's portable
kernels load: ``impulse2d.core._shipped``), the installed commands answer, and the
training code's files are in the package. Prints the seconds from the import to the
first shot.

    python wheel_smoke.py [SCENE REFERENCE]

With ``tests/scripts/small_scene.py`` and the state it wrote in the clone with kernels
compiled for that CPU (``REFERENCE``, an .npz), the scene runs here on the shipped
kernels, as this CPU loads them and as a CPU without AVX2 would (the generic target),
and each final state must be the reference's bits."""

from __future__ import annotations

import importlib.metadata
import shutil
import subprocess
import sys
import time
from pathlib import Path

started = time.perf_counter()
from numba.core import event  # noqa: E402

compiled: list[str] = []


class _Count(event.Listener):
    def on_start(self, ev: event.Event) -> None:
        function = ev.data["dispatcher"].py_func
        if function.__module__.startswith("impulse2d."):
            compiled.append(f"{function.__module__}.{function.__name__}")

    def on_end(self, ev: event.Event) -> None:
        pass


event.register("numba:compile", _Count())
import gymnasium as gym  # noqa: E402

import impulse2d  # noqa: E402
from impulse2d.core import _shipped  # noqa: E402

here = Path(impulse2d.__file__).resolve()
assert "site-packages" in here.parts, f"impulse2d imported from {here}, not the install"
assert impulse2d.__version__ == importlib.metadata.version("impulse2d")
env = gym.make("Pool2D-v0")
env.reset(seed=0)
_, reward, terminated, truncated, info = env.step(env.action_space.sample())
first_shot = time.perf_counter() - started
assert info["physics_steps"] > 0
assert _shipped.shipped_folder() is not None, "the wheel's kernels do not fit this install"
assert compiled == [], f"compiled on a fresh install: {compiled}"
from impulse2d.core import pipeline  # noqa: E402

loaded = sorted(set(pipeline.advance._cache.loaded.values()))
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
if len(sys.argv) == 3:
    import numpy as np

    scene, reference = sys.argv[1:]
    with np.load(reference) as saved:
        expected = {name: saved[name] for name in saved.files}
    hide_v3 = "import impulse2d.core._shipped as s; s._host_features = lambda: frozenset(); "
    for cpu, prelude in (("this CPU", ""), ("a CPU without AVX2", hide_v3)):
        out = Path(reference).with_name(f"wheel-{len(prelude)}.npz")
        run = f"{prelude}import runpy, sys; sys.argv = sys.argv[1:]; runpy.run_path(sys.argv[0], run_name='__main__')"  # noqa: E501
        subprocess.run([sys.executable, "-c", run, scene, str(out)], check=True)
        with np.load(out) as saved:
            got = {name: saved[name] for name in saved.files}
        assert got.keys() == expected.keys()
        for name, array in got.items():
            assert array.tobytes() == expected[name].tobytes(), (cpu, name)
        print(f"wheel smoke test: the scene's state on {cpu} is the reference's bits")
print(f"wheel smoke test: impulse2d {impulse2d.__version__} from {here.parent}; "
      f"import to the first Pool2D-v0 shot {first_shot:.1f} s, nothing compiled "
      f"(the step loaded for {', '.join(loaded)}); commands answer")  # fmt: skip
