"""The notebooks run from top to bottom and show what they promise.

Each notebook is copied into a temporary directory and executed there in a fresh kernel
(nbclient), so nothing is written into the repository; the training notebook gets a tiny
budget through its environment variables. The committed copies keep the outputs of one
real run (see ``notebooks/README.md``): they are checked for size and for errors, not
re-run.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path
from typing import Any

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOKS = Path(__file__).resolve().parents[1] / "notebooks"
TOUR = "01_engine_tour.ipynb"
TRAIN = "02_train_pool.ipynb"
IMAGES = ("image/png", "image/gif")
MAX_BYTES = 1_500_000
# 8 tables x 8 shots: one PPO rollout; 4 evaluation episodes per player.
TINY_BUDGET = {
    "IMPULSE2D_NB_TIMESTEPS": "64",
    "IMPULSE2D_NB_ENVS": "8",
    "IMPULSE2D_NB_EPISODES": "4",
}


def _execute(name: str, workdir: Path) -> Any:
    """Run a copy of ``notebooks/name`` in ``workdir``; the executed notebook."""
    path = workdir / name
    shutil.copyfile(NOTEBOOKS / name, path)
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        notebook,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(workdir)}},
    )
    client.execute()  # raises CellExecutionError, naming the cell, if any cell fails
    return notebook


def _sections(notebook: Any) -> dict[str, list[dict[str, Any]]]:
    """The outputs of the code cells under each ``## `` heading, by heading."""
    sections: dict[str, list[dict[str, Any]]] = {}
    current = None
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            heading = re.search(r"^## (.+)$", cell.source, re.MULTILINE)
            if heading:
                current = heading.group(1).strip()
                sections[current] = []
        elif current is not None:
            sections[current].extend(cell.get("outputs", []))
    return sections


def _text(outputs: list[dict[str, Any]]) -> str:
    return "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")


def _has_image(outputs: list[dict[str, Any]]) -> bool:
    return any(mime in o.get("data", {}) for o in outputs for mime in IMAGES)


def test_engine_tour_runs_and_every_milestone_shows_a_picture(tmp_path: Path) -> None:
    notebook = _execute(TOUR, tmp_path)
    sections = _sections(notebook)
    assert len(sections) >= 15, list(sections)
    without = [title for title, outputs in sections.items() if not _has_image(outputs)]
    assert not without, f"sections without an image: {without}"
    text = _text([o for outputs in sections.values() for o in outputs])
    # Measured against theory wherever there is a law to check.
    assert text.count("theory") >= 15, text
    assert not re.search(r"\bnan\b", text, re.IGNORECASE), text
    assert "bitwise where it did in the batch: True" in text
    assert list(tmp_path.iterdir()) == [tmp_path / TOUR], "the tour wrote files"


def test_training_notebook_runs_on_a_tiny_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("stable_baselines3")
    for key, value in TINY_BUDGET.items():
        monkeypatch.setenv(key, value)  # the kernel inherits the environment
    # The copy runs outside notebooks/: tell it where agents/ is.
    monkeypatch.setenv("IMPULSE2D_REPO", str(NOTEBOOKS.parent))
    notebook = _execute(TRAIN, tmp_path)
    outputs = [o for cell in notebook.cells for o in cell.get("outputs", [])]
    text = _text(outputs)
    assert "trained 64 shots on 8 tables" in text, text
    for player in ("trained PPO", "random", "ghost ball (scripted)"):
        assert re.search(rf"^\| {re.escape(player)} \| -?\d", text, re.MULTILINE), text
    assert "4 episodes each" in text
    # It trains the call-shot task with ppo.yml's tuned entry, not a copy of old settings.
    from agents import resolve

    n_steps = resolve("ppo", "Pool2DCallShot-v0")["hyperparams"]["n_steps"]
    assert "env_id: Pool2DCallShot-v0" in text and f"n_steps: {n_steps}" in text, text
    # Its own tally of the episodes counts the pots (the ghost-ball player pots each ball
    # of these four tables with its first shot): the shot that ends an episode counts.
    ghost = re.search(
        r"^\| ghost ball \(scripted\) \| ([\d.]+) ± [\d.]+ \| ([\d.]+) \|", text, re.M
    )
    assert ghost and ghost.groups() == ("1.00", "1.00"), text
    mimes = {mime for o in outputs for mime in o.get("data", {})}
    assert {"image/png", "image/gif"} <= mimes  # the learning curve, the agent playing
    assert list(tmp_path.iterdir()) == [tmp_path / TRAIN], "the notebook wrote files"


@pytest.mark.parametrize("name", [TOUR, TRAIN])
def test_committed_notebooks_are_valid_small_and_without_errors(name: str) -> None:
    path = NOTEBOOKS / name
    assert path.stat().st_size < MAX_BYTES, f"{name} is {path.stat().st_size:,} bytes"
    notebook = nbformat.read(path, as_version=4)
    nbformat.validate(notebook)
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    outputs = [o for cell in code for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    if outputs:  # committed with outputs: from one run, top to bottom
        counts = [cell.get("execution_count") for cell in code]
        assert counts == list(range(1, len(code) + 1)), counts
