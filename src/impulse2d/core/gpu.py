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

``launch`` makes one call of a ``Runner`` on the GPU: the state is copied to the device,
every world of the plan steps in one launch, and the state comes back (the world's
arrays stay on the host between calls, where the facades read and write them; keeping
them on the device between calls is the next step). The scratch rows live on the device
only, one per world: a step writes them before it reads them.

Imported only when asked for: numba-cuda is the ``gpu`` extra (``ptx`` for compiling
only, as CI does).
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
from numba import cuda

from . import pipeline
from .workspace import row_sizes

THREADS_PER_BLOCK = 64  # worlds per block; a world's step is long and branchy


def _advance_worlds(
    body, body_i, spring, sensor, contact, contact_i, world_i, time, layout, ctx, plan,
    max_steps, until_rest, floats, ints, pairs, undo,
) -> None:  # fmt: skip
    """``pipeline.advance_world`` for plan row ``cuda.grid(1)``, with scratch row of the
    same index (the arguments are ``pipeline.advance``'s, ``fresh`` left out: the caller
    zeroes the plan's counters)."""
    j = cuda.grid(1)
    if j < plan.shape[0]:
        state = (body, body_i, spring, sensor, contact, contact_i, world_i, time)
        pipeline.advance_world(
            state, layout, ctx, plan, j, max_steps, until_rest, floats[j], ints[j], pairs, undo
        )


advance_worlds = cuda.jit(_advance_worlds)


def signature(args: tuple) -> tuple:
    """numba's types of ``advance_worlds``'s arguments ``args`` (host arrays will do)."""
    return tuple(numba.typeof(a) for a in args)


def ptx(args: tuple, compute_capability: tuple[int, int]) -> str:
    """The PTX of ``advance_worlds`` for the types of ``args``, for a GPU of
    ``compute_capability`` (compiling needs numba-cuda and NVVM, not a GPU)."""
    text: Any
    text, _ = cuda.compile_ptx(_advance_worlds, signature(args), cc=compute_capability)
    return text


class DeviceScratch:
    """Scratch rows on the device: one float row and one int row per world of a launch
    (``workspace.row_sizes``), kept while the sizes fit."""

    def __init__(self) -> None:
        self.key: tuple[int, int, int, int] = (0, 0, 0, 0)
        self.floats: Any = None
        self.ints: Any = None

    def rows(self, worlds: int, bodies: int, points: int, pairs: int) -> tuple[Any, Any]:
        held = self.key
        if not (worlds <= held[0] and bodies == held[1] and points <= held[2] and pairs <= held[3]):
            floats, ints = row_sizes(bodies, points, pairs)
            self.floats = cuda.device_array((worlds, floats))
            self.ints = cuda.device_array((worlds, ints), dtype=np.int64)
            self.key = (worlds, bodies, points, pairs)
        return self.floats, self.ints


def launch(
    arrays: tuple, layout: np.ndarray, ctx: np.ndarray, plan: np.ndarray, max_steps: int,
    until_rest: bool, pairs: int, undo: np.ndarray, scratch: DeviceScratch,
) -> int:  # fmt: skip
    """One ``Runner`` call on the GPU: ``arrays`` (``WorldState``'s eight, in order),
    ``plan``, ``undo`` copied to the device, every plan row stepped by a thread of its
    own in one launch, and all of them copied back. Returns the largest status. The
    caller has zeroed the plan's counters for a fresh call."""
    body, contact = arrays[0], arrays[4]
    floats, ints = scratch.rows(plan.shape[0], body.shape[1], contact.shape[1], pairs)
    on_device = [cuda.to_device(a) for a in (*arrays, plan, undo)]
    blocks = (plan.shape[0] + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
    advance_worlds[blocks, THREADS_PER_BLOCK](
        *on_device[:8], cuda.to_device(layout), cuda.to_device(ctx), on_device[8], max_steps,
        until_rest, floats, ints, pairs, on_device[9],
    )  # fmt: skip
    for host, device in zip((*arrays, plan, undo), on_device, strict=True):
        device.copy_to_host(host)
    return int(plan[:, pipeline.PLAN_STATUS].max())
