"""The compiled core is Python: with numba's JIT switched off (``NUMBA_DISABLE_JIT=1``) the
same functions run in CPython and give bitwise the same state, for a scene with every
shape pair, a spring, sensors, breakable bodies, a kinematic body, a batch and a shot run
to rest on several threads."""

import itertools
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


def test_cut_is_the_slice_and_reshape_it_stands_for_and_writes_through():
    """``_jit.cut(flat, start, rows, cols)`` is ``flat[start:start + rows * cols]`` as
    a (rows, cols) array, on the same memory (how a call cuts its scratch row), for float
    and int rows and any start; and the scratch views a step uses are those cuts."""
    import numba

    from impulse2d.core import workspace
    from impulse2d.core._jit import cut

    @numba.njit
    def cut_and_write(flat, start, rows, cols):
        view = cut(flat, start, rows, cols)
        view[rows - 1, cols - 1] = -1
        return view.copy()

    for dtype in (np.float64, np.int64):
        for start, rows, cols in ((0, 3, 4), (5, 2, 7), (11, 1, 1), (2, 4, 1)):
            flat = np.arange(40, dtype=dtype)
            expected = flat[start : start + rows * cols].reshape(rows, cols).copy()
            expected[-1, -1] = -1
            np.testing.assert_array_equal(cut_and_write(flat, start, rows, cols), expected)
            assert flat[start + rows * cols - 1] == -1  # the caller's memory
    bodies, points, pairs = 5, 9, 4
    floats, ints = (
        np.arange(n, dtype=t)
        for n, t in zip(
            workspace.row_sizes(bodies, points, pairs), (np.float64, np.int64), strict=True
        )
    )
    scratch = workspace.views(floats, ints, bodies, points, pairs)
    shapes = workspace.part_shapes(bodies, points, pairs)
    spans = {np.float64: [], np.int64: []}
    for part, (shape, dtype) in zip(scratch, shapes, strict=True):
        row = floats if dtype is np.float64 else ints
        assert part.shape == shape and part.dtype == dtype and part.flags.c_contiguous
        start = (part.ctypes.data - row.ctypes.data) // row.itemsize
        np.testing.assert_array_equal(part.ravel(), row[start : start + part.size])
        spans[dtype].append((start, start + part.size))
    for dtype, row in ((np.float64, floats), (np.int64, ints)):  # the parts tile the row
        ordered = sorted(spans[dtype])
        assert ordered[0][0] == 0 and ordered[-1][1] == row.size
        assert all(a[1] == b[0] for a, b in itertools.pairwise(ordered))


def test_a_borrowed_array_is_the_same_memory_and_costs_no_reference():
    """``_jit.borrowed`` hands a kernel the caller's array without numba's reference
    count: the kernel reads and writes the caller's memory, and the caller's array has
    as many references after a step of every kind (``pipeline.advance`` borrows all its
    arrays) as before: none taken, none dropped."""
    import numba

    import impulse2d as p2
    from impulse2d.core._jit import borrowed

    @numba.njit
    def write_through(a):
        view = borrowed(a)
        view[1, 2] = 7.0
        return view.sum(), view.shape

    a = np.zeros((3, 4))
    total, shape = write_through(a)
    assert a[1, 2] == 7.0 and total == 7.0 and shape == (3, 4)
    world = p2.World(batch_size=2)
    world.add(p2.Plane())
    world.add(p2.Box(position=(0.0, 0.5)))
    world.add(p2.Circle(position=(0.3, 2.0), radius=0.2))
    world.step(1 / 60)
    arrays = world.state.arrays()
    before = {name: sys.getrefcount(array) for name, array in arrays.items()}
    for _ in range(30):
        world.step(1 / 60)
    world.run_until_rest(1 / 60, 200)
    assert {name: sys.getrefcount(array) for name, array in arrays.items()} == before
