"""The line a first run prints while numba compiles the step, and how long it took.

numba compiles a kernel the first time it is called, unless its cache has it; the cache
is written next to the sources (or under ``NUMBA_CACHE_DIR``) and kept until the kernel
modules change. An installed wheel carries the kernels compiled for portable x86-64
targets and loads them instead (``core._shipped``). Elsewhere (a clone, an sdist,
another numba or Python than the wheel was built with, a CPU no shipped target fits) the
first step after installing or updating impulse2d waits while the step kernel compiles,
about 25 s on two cores, and every later run loads them in well under a second
(``python -m impulse2d.compile`` fills the cache ahead, for images, CI and cluster
nodes). So that nobody takes that wait for a hang, the first run says
what it is doing, on stderr::

    impulse2d: compiling the physics kernels (first run after installing or updating;
    about 25 s on 2 cores, cached afterwards)...
    impulse2d: compiled in 23 s; later runs load them from the cache

(each is one line). A cached run prints nothing.

*How it knows.* numba announces a compile with its ``numba:compile`` event only after
the cache missed, so the notice is exact: it listens for the kernel every step is one
compiled call of (``pipeline.advance``, for one world or a chunk of a batch) and stays
quiet for the small kernels the facades call (a few seconds in all). The step kernel
compiled over stages already compiled takes a few seconds, and says so.

*Processes.* The first ``import impulse2d`` of a process tree puts a run token in the
environment, which child processes inherit; the first process of the tree to compile a
kernel claims it (a file in the temp folder) and speaks, so eight workers compiling at
once print one line, not eight.

``IMPULSE2D_QUIET=1`` silences it.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TextIO

from numba.core import event

__all__ = ["QUIET", "CompileNotice", "install", "seconds_compiling"]

QUIET = "IMPULSE2D_QUIET"
_RUN = "IMPULSE2D_COMPILE_RUN"  # the run token child processes inherit

# Seconds the step kernel takes to compile with an empty cache, measured with
# bench/bench_startup.py on this project's machine (2 shared cores). Compiled over stages
# already compiled (or cached): about ANOTHER_SECONDS.
TYPICAL_SECONDS = {("impulse2d.core.pipeline", "advance"): 25}
ANOTHER_SECONDS = 5
# A stage under the step kernel: when it is compiled (or cached), the step kernel left to
# compile takes ANOTHER_SECONDS, not the whole compile.
_CORE = ("impulse2d.core.solver", "sweep")


def _name(dispatcher: Any) -> tuple[str, str]:
    function = getattr(dispatcher, "py_func", None)
    return getattr(function, "__module__", ""), getattr(function, "__name__", "")


def core_compiled() -> bool:
    """Whether the stages of the step are compiled here, or in numba's cache or the
    shipped portable kernels for this machine and these sources (then a step kernel takes
    about ANOTHER_SECONDS)."""
    try:
        import importlib

        core = getattr(importlib.import_module(_CORE[0]), _CORE[1])
        if core.overloads:
            return True
        # numba's cache of this dispatcher (private, hence try): _shipped.KernelCache
        return core._cache.holds_any(core.targetctx.codegen())
    except Exception:  # another numba: assume the long compile
        return False


def _run_token() -> str:
    """This process tree's run token (set on the first import, inherited by children)."""
    token = os.environ.get(_RUN)
    if not token:
        token = os.environ[_RUN] = f"{os.getpid()}-{time.time_ns()}"
        root = os.getpid()

        def forget() -> None:  # the root removes the claims of its run
            if os.getpid() == root:
                for claim in Path(tempfile.gettempdir()).glob(f"impulse2d-compile-{token}-*"):
                    claim.unlink(missing_ok=True)

        atexit.register(forget)
    return token


class CompileNotice(event.Listener):
    """Listens to numba's ``numba:compile`` events; prints a line when one of
    ``kernels`` (``{(module, name): typical seconds}``) starts compiling and one when
    it is done. Nested compiles (the stages a kernel calls) are part of the outer one."""

    def __init__(
        self,
        kernels: dict[tuple[str, str], float] | None = None,
        stream: Callable[[], TextIO | None] = lambda: sys.stderr,
        clock: Callable[[], float] = time.perf_counter,
        ready: Callable[[], bool] = core_compiled,
        claims: Path | None = None,
    ) -> None:
        self.kernels = TYPICAL_SECONDS if kernels is None else kernels
        self.stream, self.clock, self.ready = stream, clock, ready
        self.claims = Path(tempfile.gettempdir()) if claims is None else claims
        self.seconds = 0.0  # spent compiling the kernels, in this process
        self._pid = os.getpid()
        self._depth = 0
        self._started: float | None = None  # when the kernel being compiled started
        self._spoke = False  # ... and whether its start was told
        self._mine: set[str] = set()  # the kernels this process claimed

    def on_start(self, ev: event.Event) -> None:
        if self._pid != os.getpid():  # a forked child starts afresh
            self._pid, self._depth, self._started, self.seconds = os.getpid(), 0, None, 0.0
            self._mine = set()
        self._depth += 1
        if self._depth != 1:
            return
        key = _name(ev.data["dispatcher"])
        if key not in self.kernels:
            return
        self._started = self.clock()
        self._spoke = not _quiet() and self._claim(key[1])
        if self._spoke:
            if self.ready():
                about = f"about {ANOTHER_SECONDS} s"
                line = f"compiling one more physics kernel (first run only; {about})..."
            else:
                line = (
                    "compiling the physics kernels (first run after installing or updating; "
                    f"about {self.kernels[key]:.0f} s on 2 cores, cached afterwards)..."
                )
            self._say(f"impulse2d: {line}")

    def on_end(self, ev: event.Event) -> None:
        self._depth = max(self._depth - 1, 0)
        if self._depth != 0 or self._started is None:
            return
        spent = self.clock() - self._started
        self.seconds += spent
        self._started = None
        if self._spoke:
            self._say(f"impulse2d: compiled in {spent:.0f} s; later runs load them from the cache")

    def _claim(self, kernel: str) -> bool:
        """True for the first process of this run to compile ``kernel`` (which speaks
        again if it compiles it again, for other argument types)."""
        if kernel not in self._mine:
            path = self.claims / f"impulse2d-compile-{_run_token()}-{kernel}"
            try:
                os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            except FileExistsError:
                return False
            except OSError:  # no temp folder to write in: better twice than never
                pass
            self._mine.add(kernel)
        return True

    def _say(self, line: str) -> None:
        stream = self.stream()  # looked up now: a progress bar may have redirected it
        if stream is None:  # pythonw, some daemons
            return
        with contextlib.suppress(OSError, ValueError):  # closed or broken stream
            stream.write(line + "\n")
            stream.flush()


def _quiet() -> bool:
    return os.environ.get(QUIET, "").strip() not in ("", "0")


_notice: CompileNotice | None = None


def install() -> CompileNotice:
    """Start listening (once per process; ``import impulse2d`` does it)."""
    global _notice
    if _notice is None:
        _run_token()
        _notice = CompileNotice()
        event.register("numba:compile", _notice)
    return _notice


def seconds_compiling() -> float:
    """Seconds this process has spent compiling the step kernels (0.0 on a cached run)."""
    return _notice.seconds if _notice is not None else 0.0
