"""The compiled core is Python: with numba's JIT switched off (``NUMBA_DISABLE_JIT=1``) the
same functions run in CPython and give bitwise the same state, for a scene with every
shape pair, a spring, sensors, breakable bodies, a kinematic body, a batch and a shot run
to rest on several threads."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

SCENE = Path(__file__).parent / "scripts" / "small_scene.py"


def _run(path: Path, jit: bool) -> dict[str, np.ndarray]:
    env = dict(os.environ)
    env.pop("NUMBA_DISABLE_JIT", None)
    if not jit:
        env["NUMBA_DISABLE_JIT"] = "1"
    subprocess.run([sys.executable, str(SCENE), str(path)], check=True, env=env, timeout=600)
    with np.load(path) as saved:
        return {name: saved[name] for name in saved.files}


def test_compiled_and_plain_python_agree_bitwise(tmp_path):
    compiled = _run(tmp_path / "compiled.npz", jit=True)
    python = _run(tmp_path / "python.npz", jit=False)
    assert compiled.keys() == python.keys()
    for name, array in compiled.items():
        assert array.tobytes() == python[name].tobytes(), name
    # The scene is not trivial: things touched, broke and ran.
    assert compiled["world_i"][:, 0].min() > 0  # contact points in every world
    assert (compiled["body_i"][:, :, 0] == 0).any()  # something was switched off
    assert compiled["steps"].min() > 0
