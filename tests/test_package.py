"""The package as users install it: its version, its installed commands, the training
code and its hyperparameter files inside it, the moved demo's old name, and the type
marker. (The wheel itself is built, installed into a fresh venv and smoke-tested by
``.ci/run``; ``tests/scripts/wheel_smoke.py`` is what it runs there.)"""

from __future__ import annotations

import importlib
import inspect
import re
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path

import pytest

import impulse2d

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_the_version_is_written_once_and_the_changelog_has_it():
    """``impulse2d.__version__`` is the package's version (pyproject reads it from there),
    a release number, and CHANGELOG.md has a section for it."""
    assert "version" in PYPROJECT["project"]["dynamic"]
    assert "version" not in PYPROJECT["project"]
    assert PYPROJECT["tool"]["setuptools"]["dynamic"]["version"] == {
        "attr": "impulse2d.__version__"
    }
    assert re.fullmatch(r"\d+\.\d+\.\d+", impulse2d.__version__)
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert f"## {impulse2d.__version__}" in changelog


@pytest.mark.parametrize("name", sorted(PYPROJECT["project"]["scripts"]))
def test_every_installed_command_names_a_main_that_takes_its_arguments(name):
    """Each console script points at a function that exists and parses ``--help`` (an
    installed command that names a missing module fails only when a user runs it)."""
    module_name, _, attr = PYPROJECT["project"]["scripts"][name].partition(":")
    main = getattr(importlib.import_module(module_name), attr)
    with pytest.raises(SystemExit) as stop:
        main(["--help"])
    assert stop.value.code == 0


@pytest.mark.parametrize("name", sorted(PYPROJECT["project"]["scripts"]))
def test_every_installed_command_gives_the_shell_an_exit_status(name):
    """A console script exits with what its function returns: a path or a dict would be
    printed and the command would exit with status 1 after a good run. So each command's
    function returns None or an int status (its annotation says which)."""
    module_name, _, attr = PYPROJECT["project"]["scripts"][name].partition(":")
    function = getattr(importlib.import_module(module_name), attr)
    assert inspect.signature(function).return_annotation in ("None", "int"), name


@pytest.mark.parametrize("command", ["train", "evaluate", "sweep"])
def test_a_training_command_tells_bad_input_in_one_line(command, capsys):
    module = importlib.import_module(f"impulse2d.agents.{command}")
    argv = ["--env", "NoSuchGame-v0"] if command != "evaluate" else ["--episodes", "0"]
    with pytest.raises(SystemExit) as stop:
        module.cli(argv)
    assert str(stop.value.code).startswith("error: "), stop.value.code


def test_the_training_code_is_installed_with_its_hyperparameters():
    """``impulse2d.agents`` is the clone's ``agents/``; its hyperparameter files are
    package data, found from the installed package (``pip install`` without the clone)."""
    from impulse2d.agents import _config

    assert set(PYPROJECT["tool"]["setuptools"]["package-dir"]) >= {"impulse2d.agents"}
    shipped = set()
    for package, patterns in PYPROJECT["tool"]["setuptools"]["package-data"].items():
        if package.startswith("impulse2d.agents"):
            folder = ROOT / "agents" / Path(*package.split(".")[2:])
            shipped |= {p for pattern in patterns for p in folder.glob(pattern)}
    assert set((ROOT / "agents" / "hyperparams").rglob("*.yml")) <= shipped
    entry = _config.load_hyperparams("ppo", "Pool2DCallShot-v0")
    assert entry["n_envs"] > 0


def test_the_demo_answers_to_its_old_name_and_says_where_it_went():
    """``python -m impulse2d.demo`` (the command earlier READMEs gave) still runs the
    demo, after a line saying where it moved; its names import with a FutureWarning."""
    result = subprocess.run(
        [sys.executable, "-m", "impulse2d.demo", "--list"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "impulse2d.apps.demo" in result.stderr and "0.4" in result.stderr
    assert "m01-constant-velocity" in result.stdout
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        from impulse2d.demo import SCENES
    from impulse2d.apps.demo import SCENES as moved

    assert SCENES is moved
    assert [w.category for w in caught] == [FutureWarning]


def test_the_package_says_it_is_typed():
    """``py.typed`` (PEP 561) is in the package and in its package data."""
    assert (Path(impulse2d.__file__).parent / "py.typed").exists()
    assert "py.typed" in PYPROJECT["tool"]["setuptools"]["package-data"]["impulse2d"]
