"""Driving the compiled pipeline: threads, scratch memory, room for more contacts.

``Runner.run`` makes one compiled call that steps the chosen worlds (``pipeline``):
on one thread when there is one world or one thread, otherwise with the worlds split in
chunks over ``threads`` threads. Each world is stepped whole by one thread and worlds
share nothing, so results are bitwise the same for any number of threads.

*Room.* A world that finds more candidate pairs or contact points than the scratch rows
hold stops before its step changes anything and says how many it needs; the runner
grows the arrays and calls again, and that world carries on where it stood, exactly as
if the room had been there from the start.

*Refusals.* When a world is refused (a spring too stiff, a world out of the envelope:
``pipeline``), the runner puts every world of the call back as it was before it
(``refusal.restore``, from the undo rows each world's first step filled) and returns the
plan, whose refused row says why; ``World`` raises.

*Threads.* A batch is cut into chunks of consecutive worlds (``_CHUNKS_PER_THREAD`` per
thread, so a thread that finishes early, or that the shared machine does not pause,
takes more), and Python threads take the chunks one at a time, each making one call of
the compiled ``pipeline.advance`` on its chunk: the kernels release the GIL, so the
threads run at once. The calling thread is one of them. Plain threads rather than
numba's ``prange``: a parallel kernel compiled in 8 s of every first batched run (its
loop is outlined and the whole step linked and optimised again), and numba's threading
layers (OpenMP cannot start threads in a child forked after it ran them; the workqueue
layer is not thread-safe) are not involved. A process forked while the helper threads
exist makes new ones when it first needs them. ``in_chunks`` is that one way of sharing
work out, for other compiled calls too (``impulse2d.pixels``).

*A call a step.* ``step_once`` is the call an RL loop makes, ``World.step(dt)``: it keeps
the arguments of its last compiled call and calls the compiled step's entry point with
them again while the state's arrays (their ``generation``), the layout and the step
context are the same objects, without numba's typing and dispatch of every argument.

*The GPU.* On device ``"cuda"`` a call is one launch of ``gpu.advance_worlds``, a
thread a world (``gpu.launch``); room and refusals are handled here the same way.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numba
import numpy as np

from . import pipeline, refusal
from ._jit import JIT_DISABLED
from .state import WorldState, grown
from .workspace import Workspace

_CHUNKS_PER_THREAD = 8  # more chunks than threads: a thread that finishes early helps
_NO_FAST_PATH = (None,) * 6  # Runner.step_once has no call to repeat
_helpers: ThreadPoolExecutor | None = None  # the threads besides the caller's, made on demand


def _drop_helpers_in_child() -> None:
    global _helpers
    _helpers = None  # a forked child has none of the parent's threads


os.register_at_fork(after_in_child=_drop_helpers_in_child)


def _helper_threads(count: int) -> ThreadPoolExecutor:
    """A pool of at least ``count`` helper threads (grown once, kept for the process)."""
    global _helpers
    if _helpers is None or _helpers._max_workers < count:
        if _helpers is not None:
            _helpers.shutdown(wait=False)  # its threads end once the chunks queued on it are done
        _helpers = ThreadPoolExecutor(max_workers=count, thread_name_prefix="impulse2d")
    return _helpers


def available_threads() -> int:
    """How many threads a batch may use here (numba's ``NUMBA_NUM_THREADS``)."""
    return int(numba.config.NUMBA_NUM_THREADS)


class Runner:
    """Steps worlds of one ``WorldState`` in compiled code (see the module docstring)."""

    def __init__(self, threads: int, device: str = "cpu") -> None:
        self._threads = threads
        self.device = device
        self._gpu: Any = None  # device "cuda": (the gpu module, DeviceScratch, DeviceBuffers)
        self.workspace: Workspace | None = None
        self.pair_capacity = 16
        self._scratch_key: tuple[int, ...] = ()
        self._scratch_rows: tuple[np.ndarray, np.ndarray] = (np.zeros((0, 0)), np.zeros((0, 0)))
        self._every = np.zeros(0, np.int64)
        self._every_plan = np.zeros((0, pipeline.PLAN_COLUMNS), np.int64)
        self._undo: tuple[np.ndarray, np.ndarray] = (np.zeros((0, 0)), np.zeros((0, 0), np.int64))
        self._undo_for: tuple[np.ndarray | None, ...] = (None, None, None)
        self._undo_contacts = 0
        # step_once's kept call: (state, generation, layout rows, ctx, call, arguments).
        self._fast: tuple = _NO_FAST_PATH
        self._last_args: tuple | None = None  # of the last one-chunk compiled call

    @property
    def threads(self) -> int:
        """How many threads a batched call may use."""
        return self._threads

    @threads.setter
    def threads(self, count: int) -> None:
        self._threads, self._fast = count, _NO_FAST_PATH

    def __getstate__(self) -> dict:
        # Neither the compiled entry point nor device memory pickles.
        return {**self.__dict__, "_fast": _NO_FAST_PATH, "_gpu": None}

    def step_once(self, state: WorldState, layout: Any, ctx: np.ndarray) -> tuple[np.ndarray, int]:
        """``run(state, layout, ctx, every world, 1, False)``, the call an RL loop makes
        each step: while the state's arrays, the layout and the context are those of the
        last such call, it reuses that call's arguments and calls the compiled step's
        entry point for them directly (no argument typing and dispatch: ~0.4 us of a
        ~2 us step), when the whole batch is one chunk."""
        state_then, generation, rows, ctx_then, call, args = self._fast
        if (
            state_then is state and generation == state.generation
            and rows is layout.rows and ctx_then is ctx
        ):  # fmt: skip
            status = call(*args)
            if status == pipeline.RUNNING:
                return self._every_plan, status
            self._fast = _NO_FAST_PATH  # room is made (new scratch) or the call is undone
            plan = self._every_plan
            return plan, self._carry_on(state, layout, ctx, plan, 1, False, status)
        plan, status = self.run(state, layout, ctx, self.every_world(state.time.size), 1, False)
        args = self._last_args
        if status == pipeline.RUNNING and args is not None and args[-1]:  # one fresh call
            self._fast = (state, state.generation, layout.rows, ctx, _entry_point(args), args)
        return plan, status

    def run(
        self,
        state: WorldState,
        layout: Any,
        ctx: np.ndarray,
        worlds: np.ndarray,
        max_steps: int,
        until_rest: bool,
    ) -> tuple[np.ndarray, int]:
        """Step ``worlds`` up to ``max_steps`` times each (until at rest, if asked).
        Returns the plan (per world its index, the steps it took and its status) and the
        largest status. When a world was refused (a status from
        ``pipeline.UNSTABLE_SPRING`` on), every world is back as it was before the call."""
        plan = self._plan(worlds)
        if plan.shape[0] == 0:
            return plan, pipeline.RUNNING
        status = self._call(state, layout, ctx, plan, max_steps, until_rest, True)
        return plan, self._carry_on(state, layout, ctx, plan, max_steps, until_rest, status)

    def _carry_on(
        self,
        state: WorldState,
        layout: Any,
        ctx: np.ndarray,
        plan: np.ndarray,
        max_steps: int,
        until_rest: bool,
        status: int,
    ) -> int:
        """After a call that ended with ``status``: room made and the call made again
        until every world went as far as asked, or a refused call undone. Returns the
        final status."""
        while status != pipeline.RUNNING:
            if status >= pipeline.UNSTABLE_SPRING:
                self._undo_call(state, layout, plan, self._undo)
                break
            short = plan[:, pipeline.PLAN_STATUS] == pipeline.NEEDS_ROOM
            self._make_room(state, plan[short])
            plan[short, pipeline.PLAN_STATUS] = pipeline.RUNNING
            status = self._call(state, layout, ctx, plan, max_steps, until_rest, False)
        return status

    def _undo_call(
        self, state: WorldState, layout: Any, plan: np.ndarray, undo: tuple[np.ndarray, ...]
    ) -> None:
        """Every world the call stepped back as it was, and the contact arrays back to
        the capacity they had (a world may have grown them before one was refused)."""
        capacity = self._undo_contacts
        if state.contact_capacity > capacity:
            state.contact = state.contact[:, :capacity].copy()
            state.contact_i = state.contact_i[:, :capacity].copy()
        stepped = plan[plan[:, pipeline.SAVED] == 1, pipeline.PLAN_WORLD]
        refusal.restore(*state.arrays().values(), layout.rows, *undo, stepped)

    def _undo_rows(self, state: WorldState) -> tuple[np.ndarray, np.ndarray]:
        """The undo rows for a call on ``state``, kept while its body and contact arrays
        are the same objects (they are replaced when they grow)."""
        kept = (state.body, state.contact, state.spring)
        if any(a is not b for a, b in zip(kept, self._undo_for, strict=True)):
            batch, bodies, contacts = *state.body.shape[:2], state.contact_capacity
            floats, ints = refusal.undo_sizes(bodies, contacts, state.spring.shape[1])
            self._undo = (np.empty((batch, floats)), np.empty((batch, ints), np.int64))
            self._undo_for, self._undo_contacts = kept, contacts
        return self._undo

    def _plan(self, worlds: np.ndarray) -> np.ndarray:
        """A plan for ``worlds`` (the one for every world is kept and reused, its
        counters zeroed by the first compiled call: a plain step must cost little
        besides that call)."""
        if worlds is self._every:
            return self._every_plan
        plan = np.zeros((worlds.size, pipeline.PLAN_COLUMNS), np.int64)
        plan[:, pipeline.PLAN_WORLD] = worlds
        return plan

    def every_world(self, batch: int) -> np.ndarray:
        """The world indices of a batch, as ``run`` recognises them for its fast path."""
        if self._every.size != batch:
            self._every = np.arange(batch, dtype=np.int64)
            self._every_plan = np.zeros((batch, pipeline.PLAN_COLUMNS), np.int64)
            self._every_plan[:, pipeline.PLAN_WORLD] = self._every
        return self._every

    def _make_room(self, state: WorldState, rows: np.ndarray) -> None:
        points = int(rows[:, pipeline.NEED_POINTS].max())
        pairs = int(rows[:, pipeline.NEED_PAIRS].max())
        if points > state.contact_capacity:
            state.grow_rows("contact", grown(state.contact_capacity, points))
        self.pair_capacity = grown(self.pair_capacity, pairs)

    def _call(
        self,
        state: WorldState,
        layout: Any,
        ctx: np.ndarray,
        plan: np.ndarray,
        max_steps: int,
        until_rest: bool,
        fresh: bool,
    ) -> int:
        """One compiled call (in chunks on threads for a batch); ``fresh``: the first of
        a run (the undo rows are filled and the plan's counters zeroed)."""
        undo = self._undo_rows(state) if fresh else self._undo
        if self.device == "cuda":
            return self._launch(state, layout, ctx, plan, max_steps, until_rest, undo, fresh)
        rows = plan.shape[0]
        threads = 1 if JIT_DISABLED else min(self.threads, rows)
        chunks = 1 if threads == 1 else min(rows, _CHUNKS_PER_THREAD * threads)
        floats, ints = self._scratch(chunks, state.body.shape[1], state.contact_capacity)
        args = (
            state.body, state.body_i, state.spring, state.sensor, state.contact,
            state.contact_i, state.world_i, state.time, state.hull, layout.rows, ctx, plan,
            max_steps, until_rest, floats, ints, self.pair_capacity, *undo, fresh,
        )  # fmt: skip
        if chunks == 1:
            self._last_args = args
            return pipeline.advance(*args)
        self._last_args = None
        _in_chunks(args, chunks, threads)
        return int(plan[:, pipeline.PLAN_STATUS].max())

    def _launch(
        self,
        state: WorldState,
        layout: Any,
        ctx: np.ndarray,
        plan: np.ndarray,
        max_steps: int,
        until_rest: bool,
        undo: tuple[np.ndarray, np.ndarray],
        fresh: bool,
    ) -> int:
        """``_call`` on the GPU (``gpu.launch``): every world a thread, one launch."""
        if self._gpu is None:
            from . import gpu  # numba-cuda: only where a world asks for the GPU

            self._gpu = (gpu, gpu.DeviceScratch(), gpu.DeviceBuffers())
        gpu, scratch, buffers = self._gpu
        if fresh:
            plan[:, pipeline.PLAN_WORLD + 1 :] = 0
        self._last_args = None
        arrays = tuple(state.arrays().values())
        return gpu.launch(
            arrays, layout.rows, ctx, plan, max_steps, until_rest, self.pair_capacity, undo,
            scratch, buffers,
        )  # fmt: skip

    def _scratch(self, rows: int, bodies: int, points: int) -> tuple[np.ndarray, np.ndarray]:
        """``rows`` scratch rows for worlds of ``bodies`` slots and ``points`` contacts."""
        key = (rows, bodies, points, self.pair_capacity)
        if key != self._scratch_key:
            space = self.workspace
            if space is None or not space.fits(rows, bodies, points, self.pair_capacity):
                more = space.rows if space is not None and space.bodies == bodies else 1
                space = self.workspace = Workspace(
                    max(rows, more), bodies, points, self.pair_capacity
                )
            self._scratch_rows = (space.floats[:rows], space.ints[:rows])
            self._scratch_key = key
        return self._scratch_rows


def _entry_point(args: tuple) -> Any:
    """The compiled ``pipeline.advance`` for exactly these argument types, callable
    without numba's dispatch (which types every argument on each call); the dispatcher
    itself where there is none (the JIT switched off)."""
    overloads = getattr(pipeline.advance, "overloads", None)
    if overloads is None:
        return pipeline.advance
    types = tuple(pipeline.advance.typeof_pyval(a) for a in args)
    compiled = overloads.get(types)
    return pipeline.advance if compiled is None else compiled.entry_point


def in_chunks(call: Callable[[int, int, int], Any], rows: int, chunks: int, threads: int) -> None:
    """``call(c, lo, hi)`` for chunk ``c`` of ``chunks`` chunks of consecutive rows
    ``lo:hi`` of ``rows``, the chunks taken one at a time by ``threads`` threads (the
    caller's and helpers). For compiled calls that release the GIL."""
    next_chunk = itertools.count()  # each chunk to one thread only (its next is atomic)

    def take_chunks() -> None:
        for c in next_chunk:
            if c >= chunks:
                return
            call(c, c * rows // chunks, (c + 1) * rows // chunks)

    helpers = [_helper_threads(threads - 1).submit(take_chunks) for _ in range(threads - 1)]
    take_chunks()
    for helper in helpers:
        helper.result()


def _in_chunks(args: tuple, chunks: int, threads: int) -> None:
    """``pipeline.advance(*args)`` with the plan's rows cut into ``chunks`` chunks, each
    with a scratch row of its own (``in_chunks``)."""
    *arrays, plan, max_steps, until_rest, floats, ints, pairs, undo_floats, undo_ints, fresh = args

    def advance_chunk(c: int, lo: int, hi: int) -> None:
        pipeline.advance(
            *arrays, plan[lo:hi], max_steps, until_rest, floats[c : c + 1], ints[c : c + 1],
            pairs, undo_floats, undo_ints, fresh,
        )  # fmt: skip

    in_chunks(advance_chunk, plan.shape[0], chunks, threads)
