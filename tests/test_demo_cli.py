"""The demo command line, ``python -m impulse2d.apps.demo``: listing, argument errors, output."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from impulse2d.apps import demo
from impulse2d.apps.demo.__main__ import frame_interval, list_scenes, main


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run ``main(argv)``, expect an exit with status 2, return what it wrote to stderr."""
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    return capsys.readouterr().err


def test_list_as_a_module():
    """``python -m impulse2d.apps.demo --list`` prints every scene with its description, the
    descriptions aligned in one column, and exits 0."""
    result = subprocess.run(
        [sys.executable, "-m", "impulse2d.apps.demo", "--list"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == len(demo.SCENES)
    columns = set()
    for line, (name, scene) in zip(lines, demo.SCENES.items(), strict=True):
        assert line.startswith(name + " ") and line.endswith(scene.description)
        columns.add(line.index(scene.description))
    assert len(columns) == 1


def test_list_from_main(capsys):
    """``main(["--list"])`` prints the same listing and returns 0."""
    assert main(["--list"]) == 0
    assert capsys.readouterr().out.strip() == list_scenes()


def test_unknown_scene_names_it_and_the_valid_ones(capsys):
    """An unknown scene is an argument error naming the scene and listing the valid names."""
    err = _fails(["no-such-scene"], capsys)
    assert "argument name" in err and "no-such-scene" in err
    assert all(name in err for name in demo.SCENES)


def test_missing_name(capsys):
    """Without a scene name (and without --list) the error says the name is required."""
    assert "name" in _fails([], capsys)


@pytest.mark.parametrize(
    ("argv", "argument"),
    [
        (["--seconds", "0"], "--seconds"),
        (["--seconds", "-1.5"], "--seconds"),
        (["--seconds", "nan"], "--seconds"),
        (["--seconds", "soon"], "--seconds"),
        (["--fps", "0"], "--fps"),
        (["--fps", "-30"], "--fps"),
        (["--width", "0"], "--width"),
        (["--width", "12.5"], "--width"),
        (["--height", "-36"], "--height"),
        (["--debug", "contacts,glitter"], "--debug"),
        (["--world-index", "-1"], "--world-index"),
        (["--world-index", "3"], "--world-index"),
        (["--out", "pyramid.txt"], "--out"),
        (["--png", "last.jpg"], "--png"),
    ],
)
def test_bad_arguments_name_the_argument(argv, argument, capsys):
    """A bad value exits with status 2 and a message naming the argument."""
    err = _fails(["pyramid", *argv], capsys)
    assert f"argument {argument}" in err


def test_unknown_debug_overlay_lists_the_valid_ones(capsys):
    """The --debug error names the unknown overlay and the valid ones."""
    err = _fails(["pyramid", "--debug", "glitter"], capsys)
    assert "glitter" in err
    assert all(name in err for name in ("contacts", "velocities", "sleeping", "aabbs"))


def test_bad_arguments_as_a_module():
    """Run as a module, an argument error exits 2 with the message on stderr."""
    result = subprocess.run(
        [sys.executable, "-m", "impulse2d.apps.demo", "pyramid", "--seconds", "-1"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert result.returncode == 2
    assert "argument --seconds" in result.stderr


def test_missing_imageio_is_named(monkeypatch, tmp_path, capsys):
    """Without imageio installed the error names the package, before anything is simulated."""
    monkeypatch.setitem(sys.modules, "imageio", None)  # makes `import imageio...` fail
    monkeypatch.setitem(sys.modules, "imageio.v3", None)
    with pytest.raises(SystemExit) as stop:
        main(["pyramid", "--out", str(tmp_path / "p.gif")])
    assert "imageio" in str(stop.value.code) and "pip install" in str(stop.value.code)
    assert not (tmp_path / "p.gif").exists()


def test_missing_imageio_ffmpeg_is_named(monkeypatch, tmp_path):
    """Writing .mp4 without imageio-ffmpeg names that package."""
    pytest.importorskip("imageio")
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(SystemExit) as stop:
        main(["pyramid", "--out", str(tmp_path / "p.mp4")])
    assert "imageio-ffmpeg" in str(stop.value.code)


@pytest.mark.parametrize(
    ("dt", "fps", "every"), [(1 / 60, 30, 2), (1 / 120, 30, 4), (1 / 240, 30, 8), (1 / 60, 240, 1)]
)
def test_frame_interval(dt, fps, every):
    """A frame every round(1 / (fps dt)) steps, never fewer than every step."""
    assert frame_interval(dt, fps) == every


# -- rendering (needs impulse2d.render and the optional packages) --------------------------------


def test_small_gif(tmp_path, capsys):
    """A scene renders to a 64x36 GIF: 0.2 s at 30 frames/s is the first frame plus six."""
    iio = pytest.importorskip("imageio.v3")
    pytest.importorskip("impulse2d.render")
    out = tmp_path / "m01.gif"
    argv = ["m01-constant-velocity", "--seconds", "0.2", "--width", "64", "--height", "36"]
    assert main([*argv, "--out", str(out)]) == 0
    assert str(out) in capsys.readouterr().out
    frames = iio.imread(out, index=None)
    assert frames.shape[:3] == (7, 36, 64)
    assert len({f.tobytes() for f in frames}) > 1  # the circles move


def test_debug_overlays_render(tmp_path):
    """Every debug overlay can be asked for at once."""
    pytest.importorskip("imageio")
    pytest.importorskip("impulse2d.render")
    out = tmp_path / "pool.gif"
    argv = ["pool-break", "--seconds", "0.1", "--width", "64", "--height", "36"]
    assert main([*argv, "--debug", "contacts,velocities,sleeping,aabbs", "--out", str(out)]) == 0
    assert out.exists()


def test_png_only_writes_the_last_frame(tmp_path):
    """--png alone writes one PNG of the last frame and no animation."""
    iio = pytest.importorskip("imageio.v3")
    pytest.importorskip("impulse2d.render")
    png = tmp_path / "last.png"
    argv = ["m08-box-plane", "--seconds", "0.2", "--width", "64", "--height", "36"]
    assert main([*argv, "--png", str(png)]) == 0
    image = iio.imread(png)
    assert image.shape[:2] == (36, 64) and image.dtype == np.uint8
    assert [p.name for p in tmp_path.iterdir()] == ["last.png"]


def test_mp4(tmp_path):
    """An .mp4 is written with imageio-ffmpeg."""
    pytest.importorskip("imageio")
    pytest.importorskip("imageio_ffmpeg")
    pytest.importorskip("impulse2d.render")
    out = tmp_path / "m01.mp4"
    argv = ["m01-constant-velocity", "--seconds", "0.2", "--width", "64", "--height", "36"]
    assert main([*argv, "--out", str(out)]) == 0
    assert out.stat().st_size > 0


def test_energy_plot_is_written(tmp_path, capsys):
    """The energy scene also writes <stem>_energy.png next to the animation."""
    pytest.importorskip("imageio")
    pytest.importorskip("matplotlib")
    pytest.importorskip("impulse2d.render")
    out = tmp_path / "swing.gif"
    argv = ["energy", "--seconds", "0.2", "--width", "64", "--height", "36"]
    assert main([*argv, "--out", str(out)]) == 0
    plot = tmp_path / "swing_energy.png"
    assert out.exists() and plot.exists() and plot.stat().st_size > 0
    assert str(plot) in capsys.readouterr().out


@pytest.mark.parametrize("name", list(demo.SCENES))
def test_every_scene_renders_to_a_file(name, tmp_path):
    """Every registered scene renders headless to a small GIF that shows something."""
    iio = pytest.importorskip("imageio.v3")
    out = tmp_path / f"{name}.gif"
    argv = [name, "--seconds", "0.1", "--width", "48", "--height", "27", "--fps", "20"]
    assert main([*argv, "--out", str(out)]) == 0
    frames = iio.imread(out, index=None)
    assert frames.shape[1:3] == (27, 48)
    assert frames[0].std() > 0  # not a blank frame
