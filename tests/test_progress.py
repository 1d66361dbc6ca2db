"""Progress while training: SB3's bar in a terminal, plain lines elsewhere (logs, CI,
notebooks), with shots per second."""

from __future__ import annotations

import io

import pytest
from agents._progress import ProgressLines, wants_lines


class _Model:
    """What the callback reads of an SB3 model: the step count and the episode window."""

    def __init__(self) -> None:
        self.num_timesteps = 0
        self.ep_info_buffer: list[dict[str, float]] = []


class _Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _callback(
    total: int, every: float = 10.0, compiled: list[float] | None = None
) -> tuple[ProgressLines, _Model, _Clock]:
    """The callback at the start of training, on a fake clock. ``compiled`` holds the
    seconds the process has spent compiling the engine (as impulse2d counts them)."""
    clock, model = _Clock(), _Model()
    seconds = compiled if compiled is not None else [0.0]
    lines = ProgressLines(
        total, every_seconds=every, write=lambda _: None, clock=clock,
        compiling=lambda: seconds[0],
    )  # fmt: skip
    lines.model = model  # what BaseCallback.init_callback sets
    lines._on_training_start()
    return lines, model, clock


def _steps(lines: ProgressLines, model: _Model, clock: _Clock, n: int, seconds: float) -> None:
    """``n`` env steps of 512 shots, ``seconds`` each."""
    for _ in range(n):
        clock.now += seconds
        model.num_timesteps += 512
        lines._on_step()


def test_a_line_every_interval_with_shots_per_second_and_time_left():
    lines, model, clock = _callback(total=30_720)
    for _ in range(19):  # 512 shots every 0.5 s: 1,024 shots/s
        clock.now += 0.5
        model.num_timesteps += 512
        lines._on_step()
    assert lines.lines == []  # 9.5 s: not yet a line
    model.ep_info_buffer = [{"r": 0.5}, {"r": 1.0}]
    clock.now += 0.5
    model.num_timesteps += 512
    lines._on_step()
    assert lines.lines == [
        "progress  10,240/30,720 shots (33%)  1,024 shots/s  ep_rew_mean 0.75  10 s, 20 s left"
    ]
    for _ in range(40):  # twice as fast now: the line gives the rate since the last one
        clock.now += 0.25
        model.num_timesteps += 512
        lines._on_step()
    assert "2,048 shots/s" in lines.lines[1] and "(100%)" in lines.lines[1]
    lines._on_training_end()  # the last line: the rate over the whole run but its first step
    assert len(lines.lines) == 3 and "1,549 shots/s" in lines.lines[2]  # 30,208 in 19.5 s
    assert lines.lines[2].endswith("20 s, 0 s left")


def test_time_left_is_the_rest_of_the_budget_at_the_current_rate():
    lines, model, clock = _callback(total=30_000, every=5.0)
    model.num_timesteps = 1_000  # the first step, at once
    lines._on_step()
    clock.now += 9.0
    model.num_timesteps = 10_000  # 1,000 shots/s: 20,000 shots left take 20 s
    lines._on_step()
    assert lines.lines[0].endswith("9 s, 20 s left")
    assert "(33%)" in lines.lines[0]


def test_a_resumed_run_counts_from_where_it_starts():
    clock, model = _Clock(), _Model()
    model.num_timesteps = 50_000
    lines = ProgressLines(10_000, write=lambda _: None, clock=clock)
    lines.model = model
    lines._on_training_start()
    model.num_timesteps = 50_500
    lines._on_step()
    clock.now += 10.0
    model.num_timesteps = 55_500
    lines._on_step()
    assert "55,500/60,000 shots (55%)" in lines.lines[0] and "500 shots/s" in lines.lines[0]


def test_the_first_step_compiling_the_engine_is_left_out_of_rate_and_time_left():
    # The first run after installing: the first env step compiles the engine (52 s of
    # its 54 s). Counted in, the first line would read 9 shots/s and 15,793 s left.
    compiled = [3.0]  # compiled before training started (the env's reset): not counted
    lines, model, clock = _callback(total=150_000, compiled=compiled)
    compiled[0] += 52.0
    _steps(lines, model, clock, 1, 54.0)
    assert lines.lines == [
        "progress  512/150,000 shots (0%)  "
        "warming up 54 s (52 s compiling the engine; first run only)"
    ]
    _steps(lines, model, clock, 9, 1.0)  # 512 shots/s from here
    assert len(lines.lines) == 1  # the next line a whole interval after the first
    _steps(lines, model, clock, 1, 1.0)
    assert lines.lines[1] == "progress  5,632/150,000 shots (4%)  512 shots/s  64 s, 282 s left"
    _steps(lines, model, clock, 10, 1.0)
    lines._on_training_end()  # the whole run's rate: the first step left out
    assert "512 shots/s" in lines.lines[-1] and "74 s," in lines.lines[-1]


def test_a_slow_first_step_without_compiling_is_a_warm_up_too():
    lines, model, clock = _callback(total=150_000)
    _steps(lines, model, clock, 1, 12.0)
    assert lines.lines == ["progress  512/150,000 shots (0%)  warming up 12 s (the first step)"]
    _steps(lines, model, clock, 10, 1.0)
    assert "512 shots/s" in lines.lines[1]


def test_a_quick_first_step_prints_nothing_and_is_left_out_of_the_rate():
    lines, model, clock = _callback(total=150_000)
    _steps(lines, model, clock, 1, 2.0)  # loading a cached engine: no warm-up line
    assert lines.lines == []
    _steps(lines, model, clock, 8, 1.0)  # 10 s since the start: the first line
    assert len(lines.lines) == 1 and "512 shots/s" in lines.lines[0]


def test_a_run_that_ends_at_its_first_step_gives_the_whole_rate():
    lines, model, clock = _callback(total=512)
    _steps(lines, model, clock, 1, 4.0)
    lines._on_training_end()
    assert lines.lines == ["progress  512/512 shots (100%)  128 shots/s  4 s, 0 s left"]


def test_lines_where_output_is_not_a_terminal():
    class _Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    assert wants_lines(io.StringIO())
    assert not wants_lines(_Tty())
    assert wants_lines(object())  # no isatty at all (some notebook streams)


def test_every_seconds_is_checked():
    with pytest.raises(ValueError, match="every_seconds must be > 0, got 0"):
        ProgressLines(100, every_seconds=0)
