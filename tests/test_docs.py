"""The documentation site (docs/) builds with no warning, and its pages' Python examples
run as written: on each page, every ```python block in order in one namespace (later
blocks use what earlier ones made, as a reader would in one session), with the values
its prose and comments promise checked, as tests/test_readme.py does for the README."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
BUILD_SKIP = "the docs extra is not installed (pip install -e '.[docs]')"


def python_blocks(page: Path) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", page.read_text(), flags=re.S | re.M)


def pages_with_examples() -> list[str]:
    return sorted(str(page.relative_to(DOCS)) for page in DOCS.rglob("*.md") if python_blocks(page))


def run_page(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> dict:
    monkeypatch.chdir(tmp_path)  # anything an example writes lands here
    page = DOCS / name
    namespace: dict = {}
    for block in python_blocks(page):
        exec(compile(block, str(page), "exec"), namespace)
    return namespace


def check_getting_started(ns: dict, printed: str) -> None:
    # help(impulse2d)'s example: a ball dropped on the ground, two seconds later
    x, y = ns["ball"].position
    assert np.isfinite([x, y]).all() and y >= 0.5 - 0.01  # on the plane, not through it
    assert np.isfinite(ns["world"].energy().total)
    assert printed.strip()  # it prints the position and the energy


def check_engine(ns: dict, printed: str) -> None:
    # "e.kinetic_linear, e.kinetic_rotational, e.potential, e.elastic, e.total"
    assert np.isfinite(ns["e"].total)
    # "shape (1024, 2): one row per world"; the copies of c and b
    assert ns["box"].position.shape == (1024, 2)
    assert ns["batch"].batch_size == 1024
    # "steps each world took: [58]" and "False, 0 (the pocket), -1"
    assert list(ns["steps"]) == [58]
    ball = ns["ball"]
    assert (bool(ball.enabled), int(ball.sensed), int(ball.first_contact)) == (False, 0, -1)
    assert ns["block"].health == 30.0 and ns["wall"].damage_speed == 0.5
    # "speed 0.0: the call changed nothing"
    pumped = ns["pumped"]
    assert pumped.time == 0.0 and tuple(pumped.bodies[-1].velocity) == (0.0, 10.0)
    assert printed.split() == ["speed", "0.0"]


def check_games(ns: dict, printed: str) -> None:
    # "the shot, 30 frames per second"
    assert len(ns["frames"]) >= 3
    # 64 envs x 16 shots a rollout: "10,240 shots"
    assert ns["model"].num_timesteps == 64 * 16 * 10
    # "(1024, 84, 84, 3) uint8: every table"
    images = ns["images"]
    assert images.shape == (1024, 84, 84, 3) and images.dtype == np.uint8
    assert ns["video_env"] is not None and ns["video_venv"] is not None


def check_gpu(ns: dict, printed: str) -> None:
    # "one launch on the GPU" (here the CPU: "the same results either way")
    shot_steps = np.asarray(ns["shot_steps"])
    assert shot_steps.shape == (256,) and (shot_steps > 0).all()
    assert ns["tables"].device == ns["device"]


CHECKS = {
    "getting-started.md": check_getting_started,
    "engine.md": check_engine,
    "envs/index.md": check_games,
    "gpu.md": check_gpu,
}


def test_the_pages_have_their_examples():
    assert set(pages_with_examples()) == set(CHECKS)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize("name", sorted(CHECKS))
def test_every_python_block_of_a_page_runs_and_gives_what_it_says(
    name, tmp_path, monkeypatch, capsys
):
    namespace = run_page(name, tmp_path, monkeypatch)
    CHECKS[name](namespace, capsys.readouterr().out)


def test_the_site_builds_with_no_warning(tmp_path):
    """What CI runs (``python -m sphinx -W --keep-going``), into a scratch folder: every
    page, the env specifications from their docstrings and the API reference."""
    for module in ("sphinx", "furo", "myst_parser"):
        pytest.importorskip(module, reason=BUILD_SKIP)
    out = tmp_path / "html"
    command = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html"]
    done = subprocess.run(
        [*command, "-d", str(tmp_path / "doctrees"), str(DOCS), str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "WARNING" not in done.stderr and "ERROR" not in done.stderr, done.stderr[-3000:]
    pages = {str(p.relative_to(out)) for p in out.rglob("*.html")}
    for page in DOCS.rglob("*.md"):
        if "_build" not in page.parts:
            assert str(page.relative_to(DOCS).with_suffix(".html")) in pages
    # The env pages carry their docstring's specification, the API its classes.
    pool = (out / "envs" / "pool2d.html").read_text()
    assert "Action Space" in pool and "Observation Space" in pool and "28.575 mm" in pool
    assert "num_birds" in (out / "envs" / "slingshot2d.html").read_text()
    api = (out / "api.html").read_text()
    for name in ("impulse2d.World", "impulse2d.Circle", "impulse2d.envs.sb3.SB3VecEnv"):
        assert f'id="{name}"' in api, name
