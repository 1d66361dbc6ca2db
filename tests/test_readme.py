"""The README's Python examples run as written: every ```python block, in order, in one
namespace (later blocks use what earlier ones made, as a reader would in one session),
and the values its comments promise are what they give."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", README.read_text(), flags=re.S | re.M)


def test_the_readme_has_its_examples():
    assert len(python_blocks()) >= 4


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_every_python_block_runs_and_gives_what_it_says(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # anything an example writes lands here
    namespace: dict = {}
    for block in python_blocks():
        exec(compile(block, str(README), "exec"), namespace)
    # "steps each world took: [58]" and "False, 0 (the pocket), -1"
    assert list(namespace["steps"]) == [58]
    ball = namespace["ball"]
    assert (bool(ball.enabled), int(ball.sensed), int(ball.first_contact)) == (False, 0, -1)
    # "shape (1024, 2): one row per world"
    assert namespace["box"].position.shape == (1024, 2)
    # "the shot, 30 frames per second"; "env i is the single env seeded 0 + i"
    assert len(namespace["frames"]) >= 3
    assert namespace["model"].num_timesteps == 64 * 16 * 10  # 10,240 shots, as it says
    assert np.isfinite(namespace["e"].total)
    # "speed 0.0: the call changed nothing"
    pumped = namespace["pumped"]
    assert pumped.time == 0.0 and tuple(pumped.bodies[-1].velocity) == (0.0, 10.0)
