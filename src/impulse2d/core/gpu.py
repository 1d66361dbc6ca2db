"""The step on a GPU: the same per-world kernels, compiled by numba-cuda, one thread a world.

On the CPU, ``pipeline.advance`` steps the worlds of a plan one after the other with one
scratch row; here ``advance_worlds``, a CUDA kernel, gives every plan row a thread of its
own (``cuda.grid(1)``) and every thread its own scratch row, and each thread calls the
very function the CPU loop calls, ``pipeline.advance_world``. numba-cuda compiles a plain
``numba.njit`` function called from a ``cuda.jit`` kernel for the device too, and every
function it calls in turn: one source for both. So nothing in the step may be what a GPU
cannot run (an array allocated, a Python object, an exception, a numpy call that
allocates); ``tests/test_gpu.py`` compiles the whole step to PTX on a machine without a
GPU to hold that, and runs it in numba's CUDA simulator against the CPU.

*Layout.* The kernels index ``body[w, i, column]``, world first, and on the CPU a world's
rows lie together (C order), which suits one thread walking one world. On the GPU the 32
threads of a warp step 32 worlds in lockstep, and each load they make together is fast
only if the 32 addresses are neighbours. So every array with a world axis (the state,
the plan, the undo rows, the scratch) lives on the device with the world axis
*innermost*: shape ``(B, N, F)`` as the kernels see it, strides ``(8, F B 8, B 8)``, so
``body[w, i, c]`` and ``body[w + 1, i, c]`` are 8 bytes apart. The kernels are the same;
numba compiles them once more for these strides (arrays of layout ``A``). The host keeps
the CPU's layout; ``launch`` transposes on the way in and out.

*Rounding.* NVVM fuses ``a * b + c`` into one multiply-add (rounded once) unless told
``-fma=0``; the CPU rounds the product first, as the kernels are written (numba passes no
``fastmath``). numba-cuda has no option for it, so while the step compiles
(``_without_fma``) its calls to NVVM are given ``fma=False``: the PTX has no ``fma``
(a test counts them). The functions the step takes from the maths library (``sqrt``,
``sin``, ``cos``, ``exp``) are CUDA's own on the GPU; only ``sqrt`` is rounded exactly
on both.

*Calls.* ``launch`` makes one call of a ``Runner`` on the GPU: the state copied to the
device, every world of the plan stepped in one launch, the state copied back (the
world's arrays stay on the host between calls, where the facades read and write them;
keeping them on the device between calls is the next step). The scratch lives on the
device only: a step writes it before it reads it.

Imported only when asked for: numba-cuda is the ``gpu`` extra (``ptx`` for compiling
only, as CI does).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import Any

import numba
import numpy as np
from numba import cuda

from . import pipeline
from .workspace import part_shapes, scratch_row

THREADS_PER_BLOCK = 64  # worlds per block; a world's step is long and branchy


def _advance_worlds(
    body, body_i, spring, sensor, contact, contact_i, world_i, time, hull, layout, ctx, plan,
    max_steps, until_rest, parts, undo_floats, undo_ints,
) -> None:  # fmt: skip
    """``pipeline.advance_world`` for plan row ``cuda.grid(1)``, with the scratch row of
    the same index (the arguments are ``pipeline.advance``'s, ``fresh`` left out: the
    caller zeroes the plan's counters)."""
    j = cuda.grid(1)
    if j < plan.shape[0]:
        state = (body, body_i, spring, sensor, contact, contact_i, world_i, time, hull)
        pipeline.advance_world(
            state, layout, ctx, plan, j, max_steps, until_rest, scratch_row(parts, j),
            undo_floats, undo_ints,
        )  # fmt: skip


advance_worlds = cuda.jit(_advance_worlds)


def world_innermost(array: np.ndarray) -> np.ndarray:
    """A copy of ``array`` (world axis first) with the world axis innermost in memory,
    seen with the same shape: the layout ``launch`` gives the device."""
    return np.moveaxis(np.ascontiguousarray(np.moveaxis(array, 0, -1)), -1, 0)


def signature(args: tuple) -> tuple:
    """numba's types of ``advance_worlds``'s arguments ``args`` (host arrays will do)."""
    return tuple(numba.typeof(a) for a in args)


@contextlib.contextmanager
def _without_fma() -> Iterator[None]:
    """NVVM told ``-fma=0`` for what compiles meanwhile (see *Rounding*): numba-cuda
    looks ``nvvm.compile_ir`` up on each compile, so it is wrapped for the while."""
    if numba.config.ENABLE_CUDASIM:  # the simulator compiles nothing
        yield
        return
    from numba.cuda.cudadrv import nvvm

    original = nvvm.compile_ir

    def compile_ir(llvmir: Any, **options: Any) -> Any:
        return original(llvmir, **{**options, "fma": False})

    nvvm.compile_ir = compile_ir
    try:
        yield
    finally:
        nvvm.compile_ir = original


def ptx(args: tuple, compute_capability: tuple[int, int]) -> str:
    """The PTX of ``advance_worlds`` for the types of ``args`` (laid out as ``launch``
    lays them out: ``world_innermost``), for a GPU of ``compute_capability``
    (compiling needs numba-cuda and NVVM, not a GPU)."""
    text: Any
    with _without_fma():
        text, _ = cuda.compile_ptx(_advance_worlds, signature(args), cc=compute_capability)
    return text


def _seen_world_first(stored: Any) -> Any:
    """The device array ``stored`` (world axis last, contiguous) seen with the world axis
    first, as the kernels index it, without moving it."""
    axes = (stored.ndim - 1, *range(stored.ndim - 1))
    if not hasattr(stored, "gpu_data"):  # the simulator's arrays are numpy's
        return stored.transpose(axes)
    from numba.cuda.cudadrv.devicearray import DeviceNDArray

    shape = tuple(stored.shape[a] for a in axes)
    strides = tuple(stored.strides[a] for a in axes)
    return DeviceNDArray(
        shape, strides, stored.dtype, stream=stored.stream, gpu_data=stored.gpu_data
    )


_TILE = (32, 8)  # threads of a transposing block: 32 worlds (a warp) by 8 values
_MOST_BLOCKS_Y = 65535  # CUDA's limit on a grid's second dimension


@cuda.jit
def _rows_to_columns(rows, columns):
    """``columns[m, w] = rows[w, m]``: a world's values, one row each, turned into one
    column each (threads along ``w`` write neighbouring addresses)."""
    w, first = cuda.grid(2)
    if w < rows.shape[0]:
        for m in range(first, rows.shape[1], cuda.gridDim.y * cuda.blockDim.y):
            columns[m, w] = rows[w, m]


@cuda.jit
def _columns_to_rows(columns, rows):
    """The way back: ``rows[w, m] = columns[m, w]``."""
    w, first = cuda.grid(2)
    if w < rows.shape[0]:
        for m in range(first, rows.shape[1], cuda.gridDim.y * cuda.blockDim.y):
            rows[w, m] = columns[m, w]


def _grid(worlds: int, values: int) -> tuple[tuple[int, int], tuple[int, int]]:
    blocks_y = min(max(1, -(-values // _TILE[1])), _MOST_BLOCKS_Y)
    return (-(-worlds // _TILE[0]), blocks_y), _TILE


class DeviceBuffers:
    """Device memory for the arrays a call moves, two buffers each (as stored, and
    turned), kept from call to call while their shapes hold: allocating gigabytes on
    every call costs time, and numba-cuda frees the old ones only later."""

    def __init__(self) -> None:
        self.held: dict[int, tuple] = {}

    def pair(self, slot: int, shape: tuple[int, int], dtype: Any) -> tuple[Any, Any]:
        key = (shape, np.dtype(dtype))
        if slot not in self.held or self.held[slot][0] != key:
            self.held[slot] = (
                key, cuda.device_array(shape, dtype), cuda.device_array(shape[::-1], dtype)
            )  # fmt: skip
        return self.held[slot][1], self.held[slot][2]


class _OnDevice:
    """A host array (world axis first, C order) copied to the device and turned world
    innermost there (``seen``); ``back`` brings it home in place. The turn is a kernel
    of its own, both ways: the host copies as it stores, in one piece, and the GPU moves
    the values (a transpose on the host would pass over every byte once more, slowly).
    In the simulator, whose kernels run a Python thread per GPU thread, numpy turns it
    and everything else is the same."""

    def __init__(self, host: np.ndarray, buffers: DeviceBuffers, slot: int) -> None:
        if not host.flags.c_contiguous:  # a reshape would copy, and ``back`` fill the copy
            raise RuntimeError(f"state arrays are C-contiguous; got strides {host.strides}")
        self.flat = host.reshape(host.shape[0], -1)
        self.rows, self.columns = buffers.pair(slot, self.flat.shape, host.dtype)
        self.rows.copy_to_device(self.flat)
        self._turn(_rows_to_columns, self.rows, self.columns)
        self.seen = _seen_world_first(self.columns.reshape(*host.shape[1:], host.shape[0]))

    def back(self) -> None:
        self._turn(_columns_to_rows, self.columns, self.rows)
        self.rows.copy_to_host(self.flat)

    def _turn(self, kernel: Any, source: Any, target: Any) -> None:
        if numba.config.ENABLE_CUDASIM:
            target.copy_to_device(np.ascontiguousarray(source.copy_to_host().T))
            return
        blocks, threads = _grid(*self.flat.shape)
        kernel[blocks, threads](source, target)


class DeviceScratch:
    """The scratch parts on the device, world innermost, a row per world of a launch
    (``workspace.part_shapes``), kept while the sizes fit."""

    def __init__(self) -> None:
        self.key: tuple[int, int, int, int] = (0, 0, 0, 0)
        self.parts: tuple = ()

    def rows(self, worlds: int, bodies: int, points: int, pairs: int) -> tuple:
        if self.key != (worlds, bodies, points, pairs):
            self.parts = tuple(
                _seen_world_first(cuda.device_array((*shape, worlds), dtype))
                for shape, dtype in part_shapes(bodies, points, pairs)
            )
            self.key = (worlds, bodies, points, pairs)
        return self.parts


def launch(
    arrays: tuple, layout: np.ndarray, ctx: np.ndarray, plan: np.ndarray, max_steps: int,
    until_rest: bool, pairs: int, undo: tuple, scratch: DeviceScratch, buffers: DeviceBuffers,
) -> int:  # fmt: skip
    """One ``Runner`` call on the GPU: ``arrays`` (``WorldState``'s nine, in order),
    ``plan`` and the two ``undo`` arrays copied to the device world innermost, every
    plan row stepped by a thread of its own in one launch, and all of them copied back.
    Returns the largest status. The caller has zeroed the plan's counters for a fresh
    call."""
    body, contact = arrays[0], arrays[4]
    parts = scratch.rows(plan.shape[0], body.shape[1], contact.shape[1], pairs)
    moved = [_OnDevice(a, buffers, slot) for slot, a in enumerate((*arrays, plan, *undo))]
    seen = [m.seen for m in moved]
    blocks = (plan.shape[0] + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
    with _without_fma():  # the first launch for these types compiles
        advance_worlds[blocks, THREADS_PER_BLOCK](
            *seen[:9], cuda.to_device(layout), cuda.to_device(ctx), seen[9], max_steps,
            until_rest, parts, seen[10], seen[11],
        )  # fmt: skip
    for m in moved:
        m.back()
    return int(plan[:, pipeline.PLAN_STATUS].max())
