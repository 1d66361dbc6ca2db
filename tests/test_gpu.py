"""The step on a GPU (``impulse2d.core.gpu``), checked on a machine without one.

numba-cuda compiles the engine's own per-world step for CUDA, so one source serves both
(``World(device='cuda')``). These checks need no GPU:

* the whole step compiles to PTX for compute capability 9.0 (an H200): the kernel a
  launch runs, ``advance_worlds``, with ``pipeline.advance_world`` and every stage below
  it, both for a number of steps and until rest (the shot loop). numba-cuda asks the
  driver which GPU it compiles a device function for; a stand-in answers (9, 0) here.
  That compile is the type check: an allocation, a Python object or a numpy call that
  allocates anywhere in the step is refused there, as a function that allocates is here;
* the step is compiled with NVVM told not to fuse ``a * b + c`` (the CPU rounds the
  product first), shown on a kernel whose PTX fuses it otherwise;
* numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) runs the launches on the CPU, a
  Python thread per GPU thread, with the step in plain Python (``NUMBA_DISABLE_JIT=1``:
  the simulator's arrays are not numpy's, so compiled CPU code cannot take them): a
  scene of every shape pair, springs, sensors, damage and a kinematic body, a batch
  whose contact rows grow in a call, a call refused by the envelope, and shots of the
  Pool and Slingshot vector envs end bitwise where the compiled CPU ends (which equals
  plain Python: ``test_compiled.py``).

numba-cuda and NVVM come with the ``ptx`` extra (in ``test``); without them these skip.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.core import pipeline

pytest.importorskip("numba_cuda", reason="numba-cuda (the ptx or gpu extra)")
from numba import cuda  # numba-cuda's, once it is installed

if cuda.is_available():
    pytest.skip("checks for a machine without a GPU", allow_module_level=True)

SCRIPTS = Path(__file__).parent / "scripts"
H200 = (9, 0)


@pytest.fixture
def h200(monkeypatch):
    """numba-cuda's question to the driver (which GPU?) answered without one; skips
    where NVVM, the compiler numba-cuda hands its code to, is not installed (the ptx
    extra brings it for Linux and Windows)."""
    import numba
    import numba.cuda.dispatcher as dispatcher

    device = types.SimpleNamespace(compute_capability=H200)
    monkeypatch.setattr(dispatcher, "get_current_device", lambda: device)

    def empty(x):
        x[cuda.grid(1)] = 0.0

    try:
        cuda.compile_ptx(empty, (numba.float64[:],), cc=H200)
    except Exception as error:  # what a missing NVVM raises differs between releases
        pytest.skip(f"no NVVM to compile with: {error}")


def _launch_arguments(world: p2.World, until_rest: bool) -> tuple:
    """What ``gpu.launch`` hands ``advance_worlds`` for ``world``, on the host with the
    device's layout (``gpu.world_innermost``): the types are what the compile sees."""
    from impulse2d.core import gpu
    from impulse2d.core.workspace import part_shapes

    state, runner = world.state, world._runner
    batch, bodies = state.body.shape[:2]
    plan = np.zeros((batch, pipeline.PLAN_COLUMNS), np.int64)
    shapes = part_shapes(bodies, state.contact_capacity, runner.pair_capacity)
    parts = tuple(np.zeros((batch, *shape), dtype) for shape, dtype in shapes)
    inner = gpu.world_innermost
    return (
        *(inner(a) for a in state.arrays().values()), world.layout.rows,
        world.settings.step_context(1 / 60), inner(plan), 10, until_rest,
        tuple(inner(part) for part in parts), *(inner(u) for u in runner._undo_rows(state)),
    )  # fmt: skip


def test_the_whole_step_compiles_to_ptx_for_an_h200(h200):
    import numba

    sys.path.insert(0, str(SCRIPTS))
    try:
        import small_scene
    finally:
        sys.path.remove(str(SCRIPTS))
    from impulse2d.core import gpu

    world = small_scene.build().replicate(3)
    args = _launch_arguments(world, until_rest=True)
    assert numba.typeof(args[0]).layout == "A"  # world innermost: strided, not C order
    text = gpu.ptx(args, H200)
    assert ".target sm_90" in text
    entries = [line for line in text.splitlines() if line.startswith(".visible .entry")]
    assert len(entries) == 1 and "_advance_worlds" in entries[0]
    assert "NRT_" not in text  # no numba runtime: nothing allocated, nothing counted
    assert text.count("\n") > 10_000  # the step itself, not an empty shell


_TURN = """
import numpy as np
from numba import cuda
from impulse2d.core import gpu
rows = np.arange(5 * 7, dtype=np.float64).reshape(5, 7)
columns = cuda.device_array((7, 5))
gpu._rows_to_columns[(1, 1), (32, 2)](cuda.to_device(rows), columns)  # 4 passes of 2
back = cuda.to_device(np.zeros((5, 7)))
gpu._columns_to_rows[(1, 1), (32, 2)](columns, back)
print(np.array_equal(columns.copy_to_host(), rows.T), np.array_equal(back.copy_to_host(), rows))
"""


def test_the_kernels_that_turn_arrays_world_innermost_and_back(h200):
    """On a GPU each array crosses as stored and is turned on the device: the two
    kernels compile for an H200 and, in the simulator, turn a (5, 7) array both ways
    with a grid smaller than it (each thread loops)."""
    import numba

    from impulse2d.core import gpu

    for kernel in (gpu._rows_to_columns, gpu._columns_to_rows):
        text, _ = cuda.compile_ptx(kernel.py_func, (numba.float64[:, ::1],) * 2, cc=H200)
        assert ".target sm_90" in text
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1", "NUMBA_DISABLE_JIT": "1"}
    done = subprocess.run(
        [sys.executable, "-c", _TURN], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["True", "True"]


def test_a_step_that_allocates_is_refused_by_the_compile(h200):
    """The compile above can fail: a per-world function in the engine's style that makes
    an array, as numpy code would, is refused when compiled for the GPU."""
    import numba
    from numba.core.errors import TypingError

    @numba.njit
    def per_world(body, w):
        scratch = np.zeros(body.shape[1])
        for i in range(body.shape[1]):
            scratch[i] = body[w, i, 0]
            body[w, i, 1] += scratch[i]

    def launch(body):
        w = cuda.grid(1)
        if w < body.shape[0]:
            per_world(body, w)

    with pytest.raises(TypingError):
        cuda.compile_ptx(launch, (numba.typeof(np.zeros((2, 3, 4))),), cc=H200)


def test_products_are_rounded_before_they_are_added_as_on_the_cpu(h200):
    """NVVM fuses ``a * b + c`` into one multiply-add unless told not to; the step is
    compiled with it told (``gpu._without_fma``). (The step's PTX keeps the fused ones
    inside CUDA's own ``exp``, ``sin`` and ``cos``.)"""
    import numba

    from impulse2d.core import gpu

    def kernel(a, b, c, out):
        i = cuda.grid(1)
        out[i] = a[i] * b[i] + c[i]

    vectors = (numba.float64[:],) * 4
    fused, _ = cuda.compile_ptx(kernel, vectors, cc=H200)
    with gpu._without_fma():
        rounded, _ = cuda.compile_ptx(kernel, vectors, cc=H200)
    assert "fma.rn.f64" in fused  # NVVM's default: the check below can fail
    assert "fma." not in rounded and "mul.rn.f64" in rounded


def _run(script: str, *args: str, simulator: bool) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_DISABLE_JIT",)}
    env.pop("NUMBA_ENABLE_CUDASIM", None)
    if simulator:
        env.update(NUMBA_ENABLE_CUDASIM="1", NUMBA_DISABLE_JIT="1")
    done = subprocess.run(
        [sys.executable, str(SCRIPTS / script), *args],
        env=env, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return done


def test_the_simulated_gpu_steps_every_shape_pair_as_the_cpu(tmp_path):
    gpu = _run("small_scene.py", str(tmp_path / "gpu.npz"), "--device", "cuda", simulator=True)
    cpu = _run("small_scene.py", str(tmp_path / "cpu.npz"), simulator=False)
    assert gpu.stdout.split()[0] == "cuda" and cpu.stdout.split()[0] == "cpu"
    with np.load(tmp_path / "gpu.npz") as on_gpu, np.load(tmp_path / "cpu.npz") as on_cpu:
        assert on_gpu.files == on_cpu.files
        for name in on_cpu.files:
            assert on_gpu[name].tobytes() == on_cpu[name].tobytes(), name
        assert on_cpu["world_i"][:, 0].min() > 0 and on_cpu["steps"].min() > 0


def test_the_simulated_gpu_makes_room_and_refuses_as_the_cpu():
    gpu = json.loads(_run("room_and_refusal.py", "cuda", simulator=True).stdout)
    cpu = json.loads(_run("room_and_refusal.py", "cpu", simulator=False).stdout)
    assert gpu.pop("device") == "cuda" and cpu.pop("device") == "cpu"
    assert gpu == cpu
    assert cpu["grown"][0] > cpu["rows"][0] and cpu["grown"][1] > cpu["rows"][1]
    assert cpu["refused"] == [1, 2, "speed"] and cpu["unchanged"]


def test_the_vector_envs_play_on_the_simulated_gpu_as_on_the_cpu():
    """``gym.make_vec(..., device="cuda")``: the same observations, rewards and endings
    for two shots of Pool and of Slingshot (each shot one launch for all envs)."""
    gpu = _run("env_on_device.py", "cuda", simulator=True).stdout.split()
    cpu = _run("env_on_device.py", "cpu", simulator=False).stdout.split()
    assert len(cpu) == 2 and gpu == cpu


def test_the_gpu_benchmark_runs_every_section_in_the_simulator():
    """``bench/bench_gpu.py`` is the one script the lent GPU machine runs; ``--smoke``
    runs each of its sections at a few worlds in the simulator, so it does not rot
    between the days a GPU is lent (its timings mean nothing here)."""
    bench = Path(__file__).parents[1] / "bench" / "bench_gpu.py"
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_DISABLE_JIT"}
    env.update(NUMBA_ENABLE_CUDASIM="1", NUMBA_DISABLE_JIT="1")
    done = subprocess.run(
        [sys.executable, str(bench), "--smoke"], env=env, capture_output=True, text=True,
        timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    out = done.stdout
    for section in ("first launch", "pool break", "agreement", "in the game", "Jax2D"):
        assert section in out, out
    assert "3/3" in out.split("agreement in the game")[1].splitlines()[3]
    agreement = out.split("agreement")[1].splitlines()[3].split()
    assert agreement[-1] == "3/3" and agreement[2] == agreement[3] == "0"
