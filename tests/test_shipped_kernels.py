"""Kernels compiled for a portable CPU target load into a process on another CPU without
compiling (``impulse2d.core._shipped``), this CPU's own compile wins over them, and the
shipped folder is used only by the sources, numba and Python it was built from.

numba reads the CPU to compile for when it starts, so each compile runs in a child
process of its own, on a one-function module (seconds, not the step's 35 s). The wheel's
real folder, the step's kernels in it and their bits on each target are checked by CI
(``tests/scripts/wheel_smoke.py``, ``tests/scripts/small_scene.py``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

from impulse2d import compile as compile_command
from impulse2d.core import _jit, _shipped

pytestmark = pytest.mark.skipif(bool(numba.config.DISABLE_JIT), reason="nothing compiles")

HOST_TRIPLE = "x86_64-unknown-linux-gnu"
V3_CPU = frozenset(_shipped._V3)
V2_CPU = frozenset(_shipped._V2)

# A module with one cached kernel, given the package's cache, and a script that calls it
# and prints what numba compiled and which portable target, if any, was loaded.
MODULE = """
import numba
from impulse2d.core._shipped import portable

@portable
@numba.njit(cache=True)
def dot(a, b):
    total = 0.0
    for i in range(a.size):
        total += a[i] * b[i]
    return total
"""
CALL = """
import json, sys
import numpy as np
from numba.core import event
compiled = []
class Count(event.Listener):
    def on_start(self, ev): compiled.append(ev.data["dispatcher"].py_func.__name__)
    def on_end(self, ev): pass
event.register("numba:compile", Count())
if sys.argv[1] == "without-v3":  # a CPU without AVX2: only the generic target runs here
    import impulse2d.core._shipped as shipped
    shipped._host_features = lambda: frozenset()
import kernel
value = kernel.dot(np.arange(4.0), np.ones(4))
print(json.dumps({"value": value, "compiled": compiled,
                  "loaded": sorted(kernel.dot._cache.loaded.values())}))
"""


def _call(folder: Path, cache: Path, cpu: str | None = None, how: str = "host", **env: str):
    """Run CALL in a child process with numba's cache in ``cache`` (compiling for ``cpu``
    when given); returns what it printed."""
    child = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    child.update(NUMBA_CACHE_DIR=str(cache), PYTHONPATH=str(folder), **env)
    if cpu is not None:
        child.update(NUMBA_CPU_NAME=cpu, NUMBA_CPU_FEATURES="")
    done = subprocess.run(
        [sys.executable, "-c", CALL, how], env=child, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout.splitlines()[-1])
    assert result["value"] == 6.0
    return result


@pytest.fixture
def module(tmp_path: Path) -> Path:
    folder = tmp_path / "module"
    folder.mkdir()
    (folder / "kernel.py").write_text(MODULE)
    return folder


def test_the_targets_a_cpu_runs_are_those_its_features_allow(monkeypatch):
    monkeypatch.setattr(_shipped, "_host_features", lambda: V3_CPU | {"avx512f"})
    assert _shipped.runnable_targets(HOST_TRIPLE) == ["x86-64-v3", "generic"]
    monkeypatch.setattr(_shipped, "_host_features", lambda: V2_CPU)  # an older x86-64
    assert _shipped.runnable_targets(HOST_TRIPLE) == ["generic"]
    monkeypatch.setattr(_shipped, "_host_features", lambda: V3_CPU - {"fma"})
    assert _shipped.runnable_targets(HOST_TRIPLE) == ["generic"]
    assert _shipped.runnable_targets("aarch64-unknown-linux-gnu") == []


def test_a_portable_compile_loads_and_this_cpus_own_compile_wins(module, tmp_path):
    cache = tmp_path / "cache"
    first = _call(module, cache, cpu="generic")
    assert first["compiled"] == ["dot"] and first["loaded"] == []
    # This CPU's key misses; the generic compile loads, with nothing compiled.
    assert _call(module, cache) == {"value": 6.0, "compiled": [], "loaded": ["generic"]}
    # Switched off, the kernel compiles for this CPU (impulse2d-compile does this) ...
    off = _call(module, cache, **{_shipped.SWITCH: "0"})
    assert off["compiled"] == ["dot"] and off["loaded"] == []
    # ... and from then on this CPU's own compile is the one loaded.
    assert _call(module, cache) == {"value": 6.0, "compiled": [], "loaded": []}


def _cache_folder(cache: Path) -> Path:
    (folder,) = {index.parent for index in cache.rglob("*.nbi")}
    return folder


def test_merged_targets_load_best_first_and_as_the_cpu_allows(module, tmp_path):
    """``impulse2d.compile --ship`` merges each target's compile into one index per
    kernel; a CPU loads the best target it runs and never one it cannot."""
    for cpu in ("x86-64-v3", "generic"):
        _call(module, tmp_path / cpu, cpu=cpu)
    merged = tmp_path / "merged" / _cache_folder(tmp_path / "generic").name
    merged.mkdir(parents=True)
    for cpu in ("x86-64-v3", "generic"):
        for index in _cache_folder(tmp_path / cpu).glob("*.nbi"):
            compile_command._merge_index(index, merged / index.name)
    (index,) = merged.glob("*.nbi")
    _, _, entries = compile_command._read_index(index)
    assert sorted(key[1][1] for key in entries) == ["generic", "x86-64-v3"]
    assert len(set(entries.values())) == 2 and all((merged / n).is_file() for n in entries.values())
    best = _call(module, tmp_path / "merged")
    assert best["compiled"] == [] and best["loaded"] == (
        ["x86-64-v3"] if _shipped.runnable_targets(HOST_TRIPLE)[0] == "x86-64-v3" else ["generic"]
    )
    older = _call(module, tmp_path / "merged", how="without-v3")
    assert older == {"value": 6.0, "compiled": [], "loaded": ["generic"]}


def test_an_index_of_other_sources_is_not_merged(tmp_path):
    import pickle

    for name, stamp in (("a", b"one source"), ("b", b"another")):
        (tmp_path / name).mkdir()
        with open(tmp_path / name / "k.f-1.py311.nbi", "wb") as index:
            pickle.dump(numba.__version__, index)
            index.write(pickle.dumps((stamp, {}), protocol=-1))
    compile_command._merge_index(tmp_path / "a" / "k.f-1.py311.nbi", tmp_path / "k.f-1.py311.nbi")
    with pytest.raises(RuntimeError, match="other sources"):
        compile_command._merge_index(
            tmp_path / "b" / "k.f-1.py311.nbi", tmp_path / "k.f-1.py311.nbi"
        )


def test_the_shipped_folder_is_used_only_by_what_built_it(tmp_path, monkeypatch):
    folder = tmp_path / "_kernels"
    folder.mkdir()
    monkeypatch.setattr(_shipped, "SHIPPED", folder)
    facts = _shipped.build_facts(_jit.kernel_sources_digest(_jit._PACKAGE))
    for changed, fits in [
        ({}, True),
        ({"sources": "0" * 64}, False),  # built from other sources
        ({"numba": "0.1.0"}, False),  # by another numba
        ({"python": "3.10"}, False),  # for another Python
    ]:
        (folder / _shipped.MANIFEST).write_text(json.dumps({**facts, **changed}))
        _shipped.shipped_folder.cache_clear()
        assert (_shipped.shipped_folder() == folder) is fits, changed
    (folder / _shipped.MANIFEST).unlink()
    _shipped.shipped_folder.cache_clear()
    assert _shipped.shipped_folder() is None
    _shipped.shipped_folder.cache_clear()  # leave the real one for other tests


def test_the_cache_module_is_not_part_of_the_kernels_stamp(tmp_path):
    """Editing how kernels are found recompiles nothing (``_jit._NOT_COMPILED``)."""
    import shutil

    package = tmp_path / "impulse2d"
    shutil.copytree(_jit._PACKAGE.parent, package, ignore=shutil.ignore_patterns("__pycache__"))
    before = _jit.kernel_sources_digest(package / "core")
    with open(package / "core" / "_shipped.py", "a") as source:
        source.write("# an edit to the cache lookup\n")
    assert _jit.kernel_sources_digest(package / "core") == before
