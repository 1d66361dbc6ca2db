"""Driving the compiled pipeline: threads, scratch memory, room for more contacts.

``Runner.run`` makes one compiled call that steps the chosen worlds (``pipeline``):
on one thread when there is one world or one thread, otherwise with the worlds split in
chunks over ``threads`` threads. Each world is stepped whole by one thread and worlds
share nothing, so results are bitwise the same for any number of threads.

*Room.* A world that finds more candidate pairs or contact points than the scratch rows
hold stops before its step changes anything and says how many it needs; the runner
grows the arrays and calls again, and that world carries on where it stood, exactly as
if the room had been there from the start.

*Threads and fork.* numba's OpenMP layer (GNU libgomp, the default where installed)
cannot run threads in a child process forked after it started them; numba aborts the
child. A process forked after impulse2d ran threads (SB3's ``SubprocVecEnv`` with
``start_method="fork"``, Gymnasium's ``AsyncVectorEnv``) therefore steps its batches on
one thread, with the same results. Spawned and forkserver children are unaffected.
Calls from several Python threads take turns (numba's workqueue layer is not
thread-safe; the others are, and the lock costs nothing measurable).
"""

from __future__ import annotations

import os
import threading
from typing import Any

import numba
import numpy as np

from . import pipeline
from ._jit import JIT_DISABLED
from .state import WorldState, grown
from .workspace import Workspace

_CHUNKS_PER_THREAD = 8  # more chunks than threads, so a thread that finishes early helps
_lock = threading.Lock()
_threads_started = False  # this process has run a parallel kernel
_fork_unsafe = False  # ... and was forked from one that ran them on OpenMP


def _after_fork_in_child() -> None:
    global _fork_unsafe, _threads_started
    if _threads_started:
        try:
            layer = numba.threading_layer()
        except ValueError:  # never initialised
            layer = ""
        _fork_unsafe = _fork_unsafe or layer == "omp"
    _threads_started = False


os.register_at_fork(after_in_child=_after_fork_in_child)


def available_threads() -> int:
    """How many threads a batch may use here (numba's ``NUMBA_NUM_THREADS``)."""
    return int(numba.config.NUMBA_NUM_THREADS)


class Runner:
    """Steps worlds of one ``WorldState`` in compiled code (see the module docstring)."""

    def __init__(self, threads: int) -> None:
        self.threads = threads
        self.workspace: Workspace | None = None
        self.pair_capacity = 16
        self._scratch_key: tuple[int, ...] = ()
        self._scratch_rows: tuple[np.ndarray, np.ndarray] = (np.zeros((0, 0)), np.zeros((0, 0)))
        self._every = np.zeros(0, np.int64)
        self._every_plan = np.zeros((0, pipeline.PLAN_COLUMNS), np.int64)

    def run(
        self,
        state: WorldState,
        layout: Any,
        ctx: np.ndarray,
        worlds: np.ndarray,
        max_steps: int,
        until_rest: bool,
    ) -> np.ndarray:
        """Step ``worlds`` up to ``max_steps`` times each (until at rest, if asked).
        Returns the plan: per world its index, the steps it took and its status
        (``pipeline.UNSTABLE_SPRING`` for a world stopped by a spring too stiff)."""
        plan = self._plan(worlds)
        if plan.shape[0] == 0:
            return plan
        status = self._call(state, layout, ctx, plan, max_steps, until_rest)
        while status != pipeline.RUNNING:
            short = plan[:, pipeline.PLAN_STATUS] == pipeline.NEEDS_ROOM
            if not short.any():
                break
            self._make_room(state, plan[short])
            plan[short, pipeline.PLAN_STATUS] = pipeline.RUNNING
            status = self._call(state, layout, ctx, plan, max_steps, until_rest)
        return plan

    def _plan(self, worlds: np.ndarray) -> np.ndarray:
        """A fresh plan for ``worlds`` (the one for every world is kept and reused: a
        plain step must cost little besides the compiled call)."""
        if worlds is self._every:
            plan = self._every_plan
            plan[:, 1:] = 0
            return plan
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
    ) -> int:
        global _threads_started
        threads = min(self.threads, plan.shape[0])
        # A batch goes through the parallel kernel even on one thread: numba hands its
        # loop body arrays without reference counts, which makes it ~30 % faster than the
        # plain loop (a single world does not pay for the thread launch, ~0.5 us).
        serial = plan.shape[0] == 1 or _fork_unsafe
        rows = 1 if serial else min(plan.shape[0], _CHUNKS_PER_THREAD * threads)
        floats, ints = self._scratch(rows, state.body.shape[1], state.contact_capacity)
        args = (
            state.body, state.body_i, state.spring, state.sensor, state.contact,
            state.contact_i, state.world_i, state.time, layout.rows, ctx, plan, max_steps,
            until_rest, floats, ints, self.pair_capacity,
        )  # fmt: skip
        if serial:
            return pipeline.advance(*args)
        with _lock:
            if JIT_DISABLED:
                pipeline.advance_parallel(*args)
            else:
                # Chunks are handed out one at a time, so a thread the machine pauses (the
                # cores are shared) does not hold the others up with its fixed share.
                old = numba.get_num_threads(), numba.get_parallel_chunksize()
                numba.set_num_threads(threads)
                numba.set_parallel_chunksize(1)
                try:
                    pipeline.advance_parallel(*args)
                finally:
                    numba.set_num_threads(old[0])
                    numba.set_parallel_chunksize(old[1])
            _threads_started = True
        return int(plan[:, pipeline.PLAN_STATUS].max())

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
