"""What a person sees while an agent trains: progress with shots per second.

In a terminal, SB3's progress bar (tqdm and rich) shows it: its rate is env steps per
second, and one env step is one shot. Where output is not a terminal (a log file, CI, a
notebook) a redrawn bar is either hidden or thousands of carriage returns, so
``ProgressLines`` prints a plain line instead, every ``every_seconds`` and at the end::

    progress  30,720/150,000 shots (20%)  1,480 shots/s  ep_rew_mean 0.12  21 s, 81 s left

Rates and time left count from the end of the first env step. On the first run after
installing, that step compiles the engine (about a minute on two cores, and the engine
says so on stderr as it starts: ``impulse2d._compile_notice``); counted in, it would
make the first line read 9 shots/s and 15,000 s left. When the first step took a whole
line's interval, the first line says so instead::

    progress  512/150,000 shots (0%)  warming up 54 s (52 s compiling the engine; first run only)

SB3's bar needs nothing of the kind: the notice prints above it (rich redirects stderr
while it draws), and its rate is measured over the last seconds only.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import Any

from stable_baselines3.common.callbacks import BaseCallback

__all__ = ["ProgressLines", "wants_lines"]


def wants_lines(stream: Any = None) -> bool:
    """True where a redrawn progress bar would not show: the stream is not a terminal."""
    stream = sys.stdout if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    return not (callable(isatty) and isatty())


class ProgressLines(BaseCallback):
    """An SB3 callback printing one progress line every ``every_seconds`` of wall time:
    shots done of the budget, shots per second since the last line, the mean return of
    recent training episodes, time spent and an estimate of time left. The first env
    step (the compile, on a first run) is left out of the rates (module docstring)."""

    def __init__(
        self,
        total_timesteps: int,
        every_seconds: float = 10.0,
        write: Callable[[str], Any] | None = None,
        clock: Callable[[], float] = time.perf_counter,
        compiling: Callable[[], float] | None = None,
    ) -> None:
        super().__init__()
        if not every_seconds > 0:
            raise ValueError(f"every_seconds must be > 0, got {every_seconds!r}")
        self.total = int(total_timesteps)
        self.every = float(every_seconds)
        self.write = write if write is not None else (lambda line: print(line, flush=True))
        self.clock = clock
        self.compiling = compiling if compiling is not None else _seconds_compiling
        self.lines: list[str] = []

    def _on_training_start(self) -> None:
        self.start_time = self.last_time = self.clock()
        self.start_steps = self.model.num_timesteps
        self.goal = self.start_steps + self.total
        # Rates count from here: the end of the first env step, once it is done.
        self.rate_time, self.rate_steps = self.start_time, self.start_steps
        self.warm = False
        self.compiled_before = self.compiling()

    def _on_step(self) -> bool:
        now = self.clock()
        if not self.warm:
            self.warm = True
            self.warm_time, self.warm_steps = now, self.model.num_timesteps
            self.rate_time, self.rate_steps = self.warm_time, self.warm_steps
            if now - self.last_time >= self.every:
                self._warm_up_line(now)
        elif now - self.last_time >= self.every:
            self._line(now)
        return True

    def _on_training_end(self) -> None:
        now, steps = self.clock(), self.model.num_timesteps
        if not self.warm or steps == self.warm_steps:  # no step after the first one
            self.rate_time, self.rate_steps = self.start_time, self.start_steps
        else:  # the whole run's rate, the first step left out
            self.rate_time, self.rate_steps = self.warm_time, self.warm_steps
        self._line(now)

    def _warm_up_line(self, now: float) -> None:
        spent = now - self.start_time
        compiled = self.compiling() - self.compiled_before
        why = f"{compiled:.0f} s compiling the engine; first run only" if compiled >= 1 else ""
        self._write(f"{self._done()}  warming up {spent:.0f} s ({why or 'the first step'})", now)

    def _line(self, now: float) -> None:
        steps = self.model.num_timesteps
        since_steps, since_time = steps - self.rate_steps, now - self.rate_time
        rate = since_steps / since_time if since_time > 0 else 0.0
        parts = [self._done(), f"{rate:,.0f} shots/s"]
        mean = _episode_mean(self.model)
        if mean is not None:
            parts.append(f"ep_rew_mean {mean:.3g}")
        spent = now - self.start_time
        left = (self.goal - steps) / rate if rate > 0 and steps < self.goal else 0.0
        parts.append(f"{spent:.0f} s, {left:.0f} s left")
        self._write("  ".join(parts), now)

    def _done(self) -> str:
        steps = self.model.num_timesteps
        share = (steps - self.start_steps) / self.total if self.total else 1.0
        return f"progress  {steps:,}/{self.goal:,} shots ({share:.0%})"

    def _write(self, line: str, now: float) -> None:
        self.lines.append(line)
        self.write(line)
        self.last_time = self.rate_time = now
        self.rate_steps = self.model.num_timesteps


def _seconds_compiling() -> float:
    """Seconds this process spent compiling the engine's step (0.0 once it is cached)."""
    try:
        from impulse2d._compile_notice import seconds_compiling
    except ImportError:  # an impulse2d without the notice
        return 0.0
    return seconds_compiling()


def _episode_mean(model: Any) -> float | None:
    """The mean return of the training episodes in SB3's window, if any have ended."""
    buffer = getattr(model, "ep_info_buffer", None)
    if not buffer:
        return None
    return sum(float(info["r"]) for info in buffer) / len(buffer)
