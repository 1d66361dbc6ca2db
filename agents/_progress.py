"""What a person sees while an agent trains: progress with shots per second.

In a terminal, SB3's progress bar (tqdm and rich) shows it: its rate is env steps per
second, and one env step is one shot. Where output is not a terminal (a log file, CI, a
notebook) a redrawn bar is either hidden or thousands of carriage returns, so
``ProgressLines`` prints a plain line instead, every ``every_seconds`` and at the end::

    progress  30,720/150,000 shots (20%)  1,480 shots/s  ep_rew_mean 0.12  21 s, 81 s left
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
    recent training episodes, time spent and an estimate of time left."""

    def __init__(
        self,
        total_timesteps: int,
        every_seconds: float = 10.0,
        write: Callable[[str], Any] | None = None,
        clock: Callable[[], float] = time.perf_counter,
    ) -> None:
        super().__init__()
        if not every_seconds > 0:
            raise ValueError(f"every_seconds must be > 0, got {every_seconds!r}")
        self.total = int(total_timesteps)
        self.every = float(every_seconds)
        self.write = write if write is not None else (lambda line: print(line, flush=True))
        self.clock = clock
        self.lines: list[str] = []

    def _on_training_start(self) -> None:
        self.start_time = self.last_time = self.clock()
        self.start_steps = self.last_steps = self.model.num_timesteps
        self.goal = self.start_steps + self.total

    def _on_step(self) -> bool:
        now = self.clock()
        if now - self.last_time >= self.every:
            self._line(now)
        return True

    def _on_training_end(self) -> None:
        self._line(self.clock(), rate_since_start=True)

    def _line(self, now: float, rate_since_start: bool = False) -> None:
        steps = self.model.num_timesteps
        since_steps, since_time = (
            (steps - self.start_steps, now - self.start_time)
            if rate_since_start
            else (steps - self.last_steps, now - self.last_time)
        )
        rate = since_steps / since_time if since_time > 0 else 0.0
        done = steps - self.start_steps
        share = done / self.total if self.total else 1.0
        parts = [
            f"progress  {steps:,}/{self.goal:,} shots ({share:.0%})",
            f"{rate:,.0f} shots/s",
        ]
        mean = _episode_mean(self.model)
        if mean is not None:
            parts.append(f"ep_rew_mean {mean:.3g}")
        spent = now - self.start_time
        left = (self.goal - steps) / rate if rate > 0 and steps < self.goal else 0.0
        parts.append(f"{spent:.0f} s, {left:.0f} s left")
        line = "  ".join(parts)
        self.lines.append(line)
        self.write(line)
        self.last_time, self.last_steps = now, steps


def _episode_mean(model: Any) -> float | None:
    """The mean return of the training episodes in SB3's window, if any have ended."""
    buffer = getattr(model, "ep_info_buffer", None)
    if not buffer:
        return None
    return sum(float(info["r"]) for info in buffer) / len(buffer)
