"""Render a demo scene to a GIF or MP4: ``python -m impulse2d.apps.demo NAME``.

    python -m impulse2d.apps.demo --list
    python -m impulse2d.apps.demo m08-box-plane                      # writes m08-box-plane.gif
    python -m impulse2d.apps.demo pool-break --out break.mp4 --fps 60 --debug contacts,velocities
    python -m impulse2d.apps.demo pyramid --png pyramid.png          # just the last frame

The physics is stepped at the scene's own ``dt``; a frame is rendered every
``round(1 / (fps * dt))`` steps, and the file plays at the frame rate that gives (which is
``fps`` whenever ``1 / (fps * dt)`` is a whole number) so it runs in real time. The
``energy`` scene also writes ``<stem>_energy.png``, a plot of its energy over time.

Writing needs ``imageio`` (and ``imageio-ffmpeg`` for .mp4), the plot ``matplotlib``, and
the progress bar ``tqdm`` if it is installed: ``pip install -e ".[demo]"``.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import SCENES, Scene, get

DEBUG_OVERLAYS = ("contacts", "velocities", "sleeping", "aabbs")
VIDEO_SUFFIXES = (".gif", ".mp4")
ENERGY_SCENES = ("energy",)


# -- argument parsing ----------------------------------------------------------------------


def _scene_name(value: str) -> str:
    """argparse type: a known scene name."""
    try:
        return get(value).name
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _positive(kind: Callable[[str], Any], what: str) -> Callable[[str], Any]:
    """argparse type: a number of ``kind`` that must be > 0."""

    def parse(value: str) -> Any:
        try:
            number = kind(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {value!r}") from None
        if not number > 0:  # also refuses nan
            raise argparse.ArgumentTypeError(f"must be > 0, got {value}")
        return number

    return parse


def _debug(value: str) -> tuple[str, ...]:
    """argparse type: a comma-separated list of debug overlays."""
    names = tuple(part.strip() for part in value.split(",") if part.strip())
    for name in names:
        if name not in DEBUG_OVERLAYS:
            raise argparse.ArgumentTypeError(
                f"unknown overlay {name!r}; choose from {', '.join(DEBUG_OVERLAYS)}"
            )
    return names


def _non_negative_int(value: str) -> int:
    """argparse type: an integer >= 0."""
    try:
        number = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {value!r}") from None
    if number < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {number}")
    return number


def build_parser() -> argparse.ArgumentParser:
    """The command line parser of ``python -m impulse2d.apps.demo``."""
    parser = argparse.ArgumentParser(
        prog="python -m impulse2d.apps.demo",
        description="Render an impulse2d demo scene to a GIF or MP4 (or its last frame to PNG).",
    )
    parser.add_argument("name", nargs="?", type=_scene_name, help="scene to render (see --list)")
    parser.add_argument("--list", action="store_true", help="list the scenes and exit")
    parser.add_argument(
        "--seconds",
        type=_positive(float, "a number"),
        help="simulated time (default: the scene's own)",
    )
    parser.add_argument(
        "--out", type=Path, help="output .gif or .mp4 (default: NAME.gif; with --png: none)"
    )
    parser.add_argument("--png", type=Path, help="also (or only) save the last frame as a PNG")
    parser.add_argument("--width", type=_positive(int, "an integer"), default=480, help="pixels")
    parser.add_argument("--height", type=_positive(int, "an integer"), default=270, help="pixels")
    parser.add_argument(
        "--fps", type=_positive(float, "a number"), default=30.0, help="frames per second"
    )
    parser.add_argument(
        "--debug",
        type=_debug,
        default=(),
        help=f"comma-separated overlays: {','.join(DEBUG_OVERLAYS)}",
    )
    parser.add_argument(
        "--world-index",
        type=_non_negative_int,
        default=0,
        help="which world of a batch to draw (scenes are single worlds: 0)",
    )
    return parser


def list_scenes() -> str:
    """Every scene's name and description, one a line, names padded to align."""
    width = max(len(name) for name in SCENES)
    return "\n".join(f"{name:<{width}}  {scene.description}" for name, scene in SCENES.items())


# -- optional dependencies ---------------------------------------------------------------------


def _require(module: str, package: str, purpose: str) -> Any:
    """Import ``module`` or exit with an error naming the missing ``package``."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise SystemExit(
            f"error: {purpose} needs the package '{package}', which is not installed: "
            f'pip install {package}   (or pip install -e ".[demo]")'
        ) from None


def _progress(total: int, label: str) -> Any:
    """A tqdm progress bar over ``total`` steps, or a stand-in that does nothing."""
    try:
        from tqdm import tqdm
    except ImportError:
        return _NoBar()
    return tqdm(total=total, desc=label, unit="step", leave=False, file=sys.stderr)


class _NoBar:
    """What stands in for tqdm when it is not installed."""

    def update(self, n: int = 1) -> None:
        """Do nothing."""

    def close(self) -> None:
        """Do nothing."""


# -- running -----------------------------------------------------------------------------------


def frame_interval(dt: float, fps: float) -> int:
    """Steps between rendered frames: ``round(1 / (fps dt))``, at least 1."""
    return max(1, round(1.0 / (fps * dt)))


def simulate(
    scene: Scene,
    seconds: float,
    every: int,
    draw: Callable[[Any], np.ndarray] | None,
    record_energy: bool = False,
    only_last: bool = False,
) -> tuple[list[np.ndarray], list[tuple[float, ...]]]:
    """Build ``scene`` and step it for ``seconds`` (rounded to whole steps of its ``dt``).

    ``draw(world)`` renders a frame at the start and after every ``every`` steps, or with
    ``only_last`` just once at the end (None: no frames). With ``record_energy`` the energy
    is sampled at the start and after every step as ``(time, kinetic_linear,
    kinetic_rotational, potential, elastic, total)``.
    """
    world = scene.build()
    steps = max(1, round(seconds / scene.dt))
    frames, energy = [], []

    def sample() -> None:
        e = world.energy()
        energy.append(
            (world.time, e.kinetic_linear, e.kinetic_rotational, e.potential, e.elastic, e.total)
        )

    drawing = draw is not None and not only_last
    if drawing:
        frames.append(draw(world))
    if record_energy:
        sample()
    bar = _progress(steps, scene.name)
    try:
        for k in range(1, steps + 1):
            scene.step(world)
            if record_energy:
                sample()
            if drawing and k % every == 0:
                frames.append(draw(world))
            bar.update(1)
    finally:
        bar.close()
    if draw is not None and only_last:
        frames.append(draw(world))
    return frames, energy


def write_video(path: Path, frames: Sequence[np.ndarray], fps: float) -> None:
    """Write ``frames`` as a looping GIF or an H.264 MP4, chosen by the suffix of ``path``."""
    iio = _require("imageio.v3", "imageio", f"writing {path.suffix}")
    if path.suffix.lower() == ".mp4":
        _require("imageio_ffmpeg", "imageio-ffmpeg", "writing .mp4")
        # H.264 needs even sizes; macro_block_size=2 keeps e.g. 480x270 as it is, where the
        # default (16) would stretch it to 480x272.
        iio.imwrite(path, np.stack(frames), fps=fps, codec="libx264", macro_block_size=2)
    else:
        iio.imwrite(path, np.stack(frames), duration=1000.0 / fps, loop=0)


def plot_energy(path: Path, samples: Iterable[tuple[float, ...]], title: str) -> None:
    """Plot kinetic (linear, rotational), potential, elastic and total energy against time."""
    matplotlib = _require("matplotlib", "matplotlib", "the energy plot")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = np.asarray(list(samples), dtype=float)
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=100)
    labels = ("kinetic (linear)", "kinetic (rotational)", "potential", "elastic", "total")
    for column, label in enumerate(labels, start=1):
        ax.plot(data[:, 0], data[:, column], label=label, lw=2.0 if label == "total" else 1.2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (argument errors exit with 2)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.list:
        print(list_scenes())
        return 0
    if args.name is None:
        parser.error("the following arguments are required: name (or use --list)")
    scene = get(args.name)
    if args.world_index != 0:
        parser.error(
            f"argument --world-index: scene {scene.name!r} is a single world, so it must be 0, "
            f"got {args.world_index}"
        )
    out = args.out
    if out is None and args.png is None:
        out = Path(f"{scene.name}.gif")
    if out is not None and out.suffix.lower() not in VIDEO_SUFFIXES:
        parser.error(f"argument --out: must end in .gif or .mp4, got {str(out)!r}")
    if args.png is not None and args.png.suffix.lower() != ".png":
        parser.error(f"argument --png: must end in .png, got {str(args.png)!r}")
    seconds = args.seconds if args.seconds is not None else scene.seconds
    every = frame_interval(scene.dt, args.fps)
    fps = 1.0 / (every * scene.dt)  # the rate the frames really are apart: plays in real time

    # Fail on a missing package before the simulation runs, not after.
    _require("imageio.v3", "imageio", "writing images")
    if out is not None and out.suffix.lower() == ".mp4":
        _require("imageio_ffmpeg", "imageio-ffmpeg", "writing .mp4")
    record_energy = scene.name in ENERGY_SCENES
    if record_energy:
        _require("matplotlib", "matplotlib", "the energy plot")

    try:
        from impulse2d.render import Camera, Renderer
    except ImportError as error:  # pragma: no cover - only while render.py is missing
        raise SystemExit(f"error: the renderer is not available: {error}") from None
    camera = (
        Camera.fit_view(scene.view, args.width, args.height) if scene.view is not None else None
    )
    renderer = Renderer(args.width, args.height, camera=camera, debug=args.debug)

    def draw(world: Any) -> np.ndarray:
        return renderer.render(world, world_index=args.world_index)

    # With no video wanted (only --png) just the last frame is rendered.
    frames, energy = simulate(scene, seconds, every, draw, record_energy, only_last=out is None)

    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
        write_video(out, frames, fps)
        print(f"wrote {out} ({len(frames)} frames, {args.width}x{args.height}, {fps:g} fps)")
    if args.png is not None:
        import imageio.v3 as iio

        args.png.parent.mkdir(parents=True, exist_ok=True)
        iio.imwrite(args.png, frames[-1])
        print(f"wrote {args.png} (the frame at t = {seconds:g} s)")
    if record_energy:
        stem = (out if out is not None else args.png).with_suffix("")
        plot_path = stem.with_name(f"{stem.name}_energy.png")
        plot_energy(plot_path, energy, f"{scene.name}: energy over time")
        print(f"wrote {plot_path} (energy over time)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
