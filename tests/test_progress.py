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


def _callback(total: int, every: float = 10.0) -> tuple[ProgressLines, _Model, _Clock]:
    clock, model = _Clock(), _Model()
    lines = ProgressLines(total, every_seconds=every, write=lambda _: None, clock=clock)
    lines.model = model  # what BaseCallback.init_callback sets
    lines._on_training_start()
    return lines, model, clock


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
    lines._on_training_end()  # the last line: the rate over the whole run
    assert len(lines.lines) == 3 and "1,536 shots/s" in lines.lines[2]
    assert lines.lines[2].endswith("20 s, 0 s left")


def test_time_left_is_the_rest_of_the_budget_at_the_current_rate():
    lines, model, clock = _callback(total=30_000, every=5.0)
    clock.now += 10.0
    model.num_timesteps = 10_000  # 1,000 shots/s: 20,000 shots left take 20 s
    lines._on_step()
    assert lines.lines[0].endswith("10 s, 20 s left")
    assert "(33%)" in lines.lines[0]


def test_a_resumed_run_counts_from_where_it_starts():
    clock, model = _Clock(), _Model()
    model.num_timesteps = 50_000
    lines = ProgressLines(10_000, write=lambda _: None, clock=clock)
    lines.model = model
    lines._on_training_start()
    clock.now += 10.0
    model.num_timesteps = 55_000
    lines._on_step()
    assert "55,000/60,000 shots (50%)" in lines.lines[0] and "500 shots/s" in lines.lines[0]


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
