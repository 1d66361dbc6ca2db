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


def _package_copy(tmp_path: Path) -> Path:
    import shutil

    from impulse2d.core import _jit

    copy = tmp_path / "package"
    shutil.copytree(_jit._PACKAGE.parent, copy, ignore=shutil.ignore_patterns("__pycache__"))
    return copy


def test_kernel_digest_follows_kernel_sources_only(tmp_path):
    """numba checks a cached kernel against its own file only, so the package stamps its
    cache: an edit to a module kernels are compiled from changes the stamp, an edit to a
    facade does not (so it costs no recompile)."""
    from impulse2d.core._jit import kernel_sources_digest

    package = _package_copy(tmp_path)
    before = kernel_sources_digest(package / "core")
    for facade in ("world.py", "settings.py", "apps/sandbox.py"):
        with open(package / facade, "a") as source:
            source.write("# an edit outside the kernels\n")
    assert kernel_sources_digest(package / "core") == before
    for module in ("core/solver.py", "core/state.py", "core/context.py", "envelope.py"):
        edited = _package_copy(tmp_path / module.replace("/", "_"))
        with open(edited / module, "a") as source:
            source.write("# an edit the kernels are compiled from\n")
        assert kernel_sources_digest(edited / "core") != before, module


def test_stale_cache_is_emptied_and_current_cache_kept(tmp_path, monkeypatch):
    from impulse2d.core import _jit

    cache = tmp_path / "cache"
    cache.mkdir()
    stale = cache / "solver.relax-1.py311.nbi"
    stale.write_bytes(b"compiled from other sources")
    _jit.clear_stale_cache(str(cache))
    assert not stale.exists()
    assert (cache / "kernels.sha256").read_text() == _jit.kernel_sources_digest(_jit._PACKAGE)
    current = cache / "solver.relax-1.py311.nbc"
    current.write_bytes(b"compiled from these sources")
    _jit.clear_stale_cache(str(cache))
    assert current.exists()
    # The same sources edited: the stamp no longer matches and the cache goes.
    monkeypatch.setattr(_jit, "kernel_sources_digest", lambda package: "another digest")
    _jit.clear_stale_cache(str(cache))
    assert not current.exists()
    assert (cache / "kernels.sha256").read_text() == "another digest"
