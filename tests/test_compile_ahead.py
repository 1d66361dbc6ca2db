"""The kernels can be compiled ahead (``python -m impulse2d.compile``), and cached in the
user's cache folder when the install folder is read-only (impulse2d/core/_jit.py): after the
command, a new process's first step and first Pool2D-v0 shot compile nothing."""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numba
import pytest

import impulse2d
from impulse2d.core import _jit

ROOT = Path(__file__).resolve().parents[1]

# A first engine step and a first Pool2D-v0 shot; prints the impulse2d kernels numba
# compiled for them (none when the cache holds them), and where the package lives.
FIRST_RUN = r"""
import json
from numba.core import event
compiled = []
class Count(event.Listener):
    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        if function.__module__.startswith("impulse2d."):
            compiled.append(function.__module__ + "." + function.__name__)
    def on_end(self, ev):
        pass
event.register("numba:compile", Count())
import gymnasium as gym
import impulse2d as p2
from impulse2d.core import _jit
world = p2.World()
world.add(p2.Plane())
world.add(p2.Circle(position=(0.0, 1.0)))
world.step(1 / 60)
env = gym.make("Pool2D-v0")
env.reset(seed=0)
env.step(env.action_space.sample())
print(json.dumps({"compiled": compiled, "package": p2.__file__, "cache": _jit.CACHE_DIR}))
"""


def _read_only_install(tmp_path: Path) -> Path:
    """A copy of the package (the envs as its ``envs`` subpackage, as installed) whose
    folders cannot be written; returns the folder to put on the path."""
    root = tmp_path / "site"
    package = root / "impulse2d"
    shutil.copytree(_jit._PACKAGE.parent, package, ignore=shutil.ignore_patterns("__pycache__"))
    envs = Path(impulse2d.__file__).parent / "envs"
    if not envs.is_dir():  # an editable install maps the top-level envs/ folder
        envs = ROOT / "envs"
    shutil.copytree(envs, package / "envs", ignore=shutil.ignore_patterns("__pycache__"))
    for folder, _, files in os.walk(root):
        for name in files:
            os.chmod(Path(folder) / name, stat.S_IRUSR)
        os.chmod(folder, stat.S_IRUSR | stat.S_IXUSR)
    return root


def _run(args: list[str], root: Path, cache_home: Path, cwd: Path, extra: dict[str, str]) -> str:
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("NUMBA_CACHE_DIR", "NUMBA_DISABLE_JIT", "IMPULSE2D_COMPILE_RUN")
    }
    env.update(PYTHONPATH=str(root), XDG_CACHE_HOME=str(cache_home), IMPULSE2D_QUIET="1")
    env.update(extra)
    done = subprocess.run(
        [sys.executable, *args], env=env, cwd=cwd, capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


@pytest.mark.skipif(bool(numba.config.DISABLE_JIT), reason="nothing compiles")
def test_compile_ahead_into_the_user_cache_of_a_read_only_install(tmp_path):
    pytest.importorskip("gymnasium")
    root = _read_only_install(tmp_path)
    cache_home, cwd = tmp_path / "cache-home", tmp_path / "cwd"
    cwd.mkdir()
    # root writes through read-only modes: there the cache goes to NUMBA_CACHE_DIR, and
    # the choice of the user cache folder is left to the test below.
    read_only = not os.access(root / "impulse2d", os.W_OK)
    extra = {} if read_only else {"NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}
    try:
        said = _run(["-m", "impulse2d.compile"], root, cache_home, cwd, extra)
        assert "kernels compiled and cached in" in said.splitlines()[-1]
        assert "Pool2D-v0: a shot" in said
        first = json.loads(_run(["-c", FIRST_RUN], root, cache_home, cwd, extra).splitlines()[-1])
    finally:  # let pytest remove the copy
        for folder, _, _ in os.walk(root):
            os.chmod(folder, stat.S_IRWXU)
    assert first["package"].startswith(str(root))  # the copy ran
    assert first["compiled"] == []  # all loaded from the cache the command wrote
    if read_only:
        assert first["cache"] == str(cache_home / "impulse2d" / "numba")
        assert not (root / "impulse2d" / "__pycache__").exists()


def test_the_user_cache_folder_is_chosen_only_when_the_install_cannot_be_written(
    tmp_path, monkeypatch
):
    monkeypatch.setattr(_jit, "JIT_DISABLED", False)
    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    package = tmp_path / "package"
    package.mkdir()
    assert _jit.choose_cache_dir(package) is None  # numba caches next to the sources
    assert numba.config.CACHE_DIR == "" and (package / "__pycache__").is_dir()
    # The install folder read-only (faked: root writes through file modes).
    cannot = package / "__pycache__"
    real = _jit._writable
    monkeypatch.setattr(_jit, "_writable", lambda folder: folder != cannot and real(folder))
    chosen = _jit.choose_cache_dir(package)
    assert chosen == str(tmp_path / "xdg" / "impulse2d" / "numba")
    assert numba.config.CACHE_DIR == chosen and Path(chosen).is_dir()
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert _jit.user_cache_dir() == Path.home() / ".cache" / "impulse2d" / "numba"
    monkeypatch.setattr(numba.config, "CACHE_DIR", "/somewhere/else")  # NUMBA_CACHE_DIR wins
    assert _jit.choose_cache_dir(package) is None
    assert numba.config.CACHE_DIR == "/somewhere/else"


def test_compile_command_has_help():
    done = subprocess.run(
        [sys.executable, "-m", "impulse2d.compile", "--help"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and "--engine" in done.stdout
