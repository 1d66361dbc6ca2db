"""The first run says what it is doing: a line on stderr while numba compiles the step
kernels (only then: a cached run prints nothing), how long it took, silenced by
``IMPULSE2D_QUIET=1``, and said once by a tree of processes (impulse2d/_compile_notice.py)."""

from __future__ import annotations

import importlib
import io
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numba
import pytest
from numba.core import event

import impulse2d as p2
from impulse2d import _compile_notice
from impulse2d._compile_notice import QUIET, TYPICAL_SECONDS, CompileNotice

STEP, STAGE, OTHER = (
    ("impulse2d.core.pipeline", "advance"),
    ("impulse2d.core.pipeline", "stage"),
    ("x", "f"),
)


def _dispatcher(key: tuple[str, str]) -> Any:
    """What the listener reads of a numba dispatcher: its Python function's name."""
    function = SimpleNamespace(__module__=key[0], __name__=key[1])
    return SimpleNamespace(py_func=function)


class _Compiles:
    """numba's ``numba:compile`` events, sent to one listener, on a fake clock."""

    def __init__(self, notice: CompileNotice, clock: list[float]) -> None:
        self.notice, self.clock = notice, clock

    def start(self, key: tuple[str, str]) -> None:
        data = {"dispatcher": _dispatcher(key)}
        self.notice.notify(event.Event("numba:compile", event.EventStatus.START, data))

    def end(self, key: tuple[str, str], seconds: float = 0.0) -> None:
        self.clock[0] += seconds
        data = {"dispatcher": _dispatcher(key)}
        self.notice.notify(event.Event("numba:compile", event.EventStatus.END, data))


def _notice(
    tmp_path: Path, ready: bool = False, stream: Callable[[], Any] | None = None
) -> tuple[CompileNotice, _Compiles, io.StringIO]:
    out, clock = io.StringIO(), [0.0]
    notice = CompileNotice(
        kernels={STEP: 55},
        stream=stream if stream is not None else (lambda: out),
        clock=lambda: clock[0],
        ready=lambda: ready,
        claims=tmp_path,
    )
    return notice, _Compiles(notice, clock), out


@pytest.fixture(autouse=True)
def _speaking(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    monkeypatch.delenv(QUIET, raising=False)
    # A run of its own per test, so that claims of other tests do not silence it.
    token = f"test-{os.getpid()}-{id(monkeypatch)}"
    monkeypatch.setenv("IMPULSE2D_COMPILE_RUN", token)
    yield
    for claim in Path(tempfile.gettempdir()).glob(f"impulse2d-compile-{token}-*"):
        claim.unlink(missing_ok=True)  # what this process's own notice claimed


def test_a_line_before_the_step_kernel_compiles_and_one_when_it_is_done(tmp_path):
    notice, compiles, out = _notice(tmp_path)
    compiles.start(STEP)
    assert out.getvalue() == (
        "impulse2d: compiling the physics kernels (first run after installing or updating; "
        "about 55 s on 2 cores, cached afterwards)...\n"
    )
    compiles.start(STAGE)  # the stages the kernel calls compile inside it: no line
    compiles.end(STAGE, 30.0)
    compiles.end(STEP, 22.0)
    assert out.getvalue().splitlines()[1:] == [
        "impulse2d: compiled in 52 s; later runs load them from the cache"
    ]
    assert notice.seconds == 52.0


def test_other_kernels_compile_without_a_word(tmp_path):
    notice, compiles, out = _notice(tmp_path)
    compiles.start(STAGE)  # a small kernel the facades call, compiled on its own
    compiles.end(STAGE, 2.0)
    compiles.start(OTHER)  # someone else's numba function, with a step kernel inside
    compiles.start(STEP)
    compiles.end(STEP, 5.0)
    compiles.end(OTHER, 1.0)
    assert out.getvalue() == "" and notice.seconds == 0.0


def test_a_step_kernel_over_compiled_stages_takes_less_and_says_so(tmp_path):
    _, compiles, out = _notice(tmp_path, ready=True)
    compiles.start(STEP)
    compiles.end(STEP, 8.0)
    assert out.getvalue().splitlines() == [
        "impulse2d: compiling one more physics kernel (first run only; "
        f"about {_compile_notice.ANOTHER_SECONDS} s)...",
        "impulse2d: compiled in 8 s; later runs load them from the cache",
    ]


def test_quiet_silences_it_but_the_seconds_still_count(tmp_path, monkeypatch):
    monkeypatch.setenv(QUIET, "1")
    notice, compiles, out = _notice(tmp_path)
    compiles.start(STEP)
    compiles.end(STEP, 50.0)
    assert out.getvalue() == "" and notice.seconds == 50.0
    monkeypatch.setenv(QUIET, "0")  # "0" speaks
    notice, compiles, out = _notice(tmp_path)
    compiles.start(STEP)
    assert out.getvalue().startswith("impulse2d: compiling")


def test_the_processes_of_one_run_say_it_once(tmp_path):
    # Workers of one run (the token they inherit) compiling the same kernel at once.
    _, first_compiles, first_out = _notice(tmp_path)
    _, second_compiles, second_out = _notice(tmp_path)
    first_compiles.start(STEP)
    second_compiles.start(STEP)
    second_compiles.end(STEP, 50.0)
    first_compiles.end(STEP, 1.0)
    assert len(first_out.getvalue().splitlines()) == 2 and second_out.getvalue() == ""
    first_compiles.start(STEP)  # a process that spoke speaks again (another kernel, later)
    assert len(first_out.getvalue().splitlines()) == 3
    other = CompileNotice(
        kernels={("impulse2d.core.pipeline", "another_kernel"): 75},
        stream=lambda: second_out,
        ready=lambda: False,
        claims=tmp_path,
    )
    _Compiles(other, [0.0]).start(("impulse2d.core.pipeline", "another_kernel"))
    assert "about 75 s" in second_out.getvalue()  # another kernel: its own line


def test_no_stderr_or_a_closed_one_is_no_error(tmp_path):
    closed = io.StringIO()
    closed.close()
    for name, stream in [("none", None), ("closed", closed)]:
        (tmp_path / name).mkdir()  # each its own claims: each speaks
        notice, compiles, _ = _notice(tmp_path / name, stream=lambda stream=stream: stream)
        compiles.start(STEP)
        compiles.end(STEP, 1.0)
        assert notice.seconds == 1.0


def test_numba_announces_a_real_compile_and_not_a_compiled_call(tmp_path):
    def twice(x):
        return 2.0 * x

    compiled = numba.njit(twice)
    out = io.StringIO()
    notice = CompileNotice(
        kernels={(twice.__module__, "twice"): 1},
        stream=lambda: out,
        ready=lambda: False,
        claims=tmp_path,
    )
    with event.install_listener("numba:compile", notice):
        assert compiled(1.5) == 3.0
        assert compiled(2.5) == 5.0  # compiled already: nothing more
    lines = out.getvalue().splitlines()
    assert (
        len(lines) == 2 and "about 1 s" in lines[0] and lines[1].startswith("impulse2d: compiled")
    )


def test_the_kernels_it_listens_for_are_the_step_kernels():
    for module, name in [*TYPICAL_SECONDS, _compile_notice._CORE]:
        kernel = getattr(importlib.import_module(module), name)
        assert kernel.py_func.__module__ == module and kernel.py_func.__name__ == name
    assert _compile_notice.install() is _compile_notice.install()  # once per process


@pytest.mark.skipif(bool(numba.config.DISABLE_JIT), reason="nothing compiles")
def test_a_cached_run_prints_nothing(tmp_path):
    world = p2.World()  # compiled here if it is not cached yet (that run may speak)
    world.add(p2.Circle(position=(0.0, 1.0)))
    world.step(1 / 60)
    assert _compile_notice.core_compiled()
    env = {k: v for k, v in os.environ.items() if k not in (QUIET, "IMPULSE2D_COMPILE_RUN")}
    code = (
        "import impulse2d as p2\n"
        "w = p2.World()\n"
        "w.add(p2.Circle(position=(0.0, 1.0)))\n"
        "w.step(1 / 60)\n"
        "from impulse2d._compile_notice import seconds_compiling\n"
        "print(seconds_compiling())\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert "impulse2d:" not in done.stderr and float(done.stdout) == 0.0


def test_child_processes_of_one_run_say_it_once(tmp_path):
    # Three workers inherit the run token and compile at once: one of them speaks.
    code = (
        "import numba\n"
        "from numba.core import event\n"
        "from impulse2d._compile_notice import CompileNotice\n"
        "def f(x):\n"
        "    return x + 1\n"
        "notice = CompileNotice(kernels={('__main__', 'f'): 1}, ready=lambda: False)\n"
        "event.register('numba:compile', notice)\n"
        "numba.njit(f)(1)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != QUIET}
    env["IMPULSE2D_COMPILE_RUN"] = f"test-children-{os.getpid()}"
    env["TMPDIR"] = str(tmp_path)  # where they claim it
    workers = [
        subprocess.Popen([sys.executable, "-c", code], env=env, stderr=subprocess.PIPE, text=True)
        for _ in range(3)
    ]
    said = [worker.communicate(timeout=120)[1] for worker in workers]
    assert all(worker.returncode == 0 for worker in workers), said
    assert sorted(len(err.splitlines()) for err in said) == [0, 0, 2], said
