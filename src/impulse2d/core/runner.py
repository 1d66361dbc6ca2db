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

from . import pipeline, refusal
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
        self._undo = np.zeros((0, 0))
        self._undo_for: tuple[np.ndarray | None, np.ndarray | None] = (None, None)
        self._undo_contacts = 0

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
        undo = self._undo_rows(state)
        status = self._call(state, layout, ctx, plan, max_steps, until_rest, undo, True)
        while status != pipeline.RUNNING:
            if status >= pipeline.UNSTABLE_SPRING:
                self._undo_call(state, layout, plan, undo)
                break
            short = plan[:, pipeline.PLAN_STATUS] == pipeline.NEEDS_ROOM
            self._make_room(state, plan[short])
            plan[short, pipeline.PLAN_STATUS] = pipeline.RUNNING
            status = self._call(state, layout, ctx, plan, max_steps, until_rest, undo, False)
        return plan, status

    def _undo_call(
        self, state: WorldState, layout: Any, plan: np.ndarray, undo: np.ndarray
    ) -> None:
        """Every world the call stepped back as it was, and the contact arrays back to
        the capacity they had (a world may have grown them before one was refused)."""
        capacity = self._undo_contacts
        if state.contact_capacity > capacity:
            state.contact = state.contact[:, :capacity].copy()
            state.contact_i = state.contact_i[:, :capacity].copy()
        stepped = plan[plan[:, pipeline.SAVED] == 1, pipeline.PLAN_WORLD]
        refusal.restore(*state.arrays().values(), layout.rows, undo, stepped)

    def _undo_rows(self, state: WorldState) -> np.ndarray:
        """The undo rows for a call on ``state``, kept while its body and contact arrays
        are the same objects (they are replaced when they grow)."""
        if state.body is not self._undo_for[0] or state.contact is not self._undo_for[1]:
            batch, bodies, contacts = *state.body.shape[:2], state.contact_capacity
            self._undo = np.empty((batch, sum(refusal.undo_sizes(bodies, contacts))))
            self._undo_for, self._undo_contacts = (state.body, state.contact), contacts
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
        undo: np.ndarray,
        fresh: bool,
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
            until_rest, floats, ints, self.pair_capacity, undo, fresh,
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
