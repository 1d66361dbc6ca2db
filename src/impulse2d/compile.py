"""Compile the engine's kernels into numba's cache ahead of the first run.

    python -m impulse2d.compile            # every kernel the engine and the games use
    python -m impulse2d.compile --engine   # the engine's only (no gymnasium needed)
    python -m impulse2d.compile --ship     # the portable kernels a wheel ships (CI)

The first step after installing or updating impulse2d compiles the physics kernels and
caches them; every later process loads them. Run this where that first step should not
pay for it: when building a container image, in a CI job's setup step, or once on a
cluster node's shared install before the workers start. It plays, in this process, what
a user does first (a world and its first step, a batch on threads, a shot of each game,
single and batched), so that numba compiles each kernel for the very argument types
those runs use, and writes it where they will look for it: next to the sources, under
``NUMBA_CACHE_DIR`` when set, or in the user's cache folder when the install folder is
read-only (``impulse2d.core._jit``). It compiles for this very CPU even where the
wheel's portable kernels would load (``impulse2d.core._shipped``): later runs prefer
this CPU's own compile, which is up to 1.2x faster in box stacks. Run it with the same
Python, numba and CPU as the runs that follow, and with the same ``NUMBA_CACHE_DIR``. A
cache that already holds the kernels makes it a few-second no-op.

``--ship`` builds what a wheel carries instead (``impulse2d.core._shipped``): the same
kernels compiled for each portable CPU target, one child process per target, into the
package's ``core/_kernels`` folder with a manifest of the sources, numba and Python they
fit. CI runs it before building the wheel; a clone never needs it.

It prints a line per group of kernels, with the seconds it took and how many kernels
numba compiled for it (0: loaded from the cache), and one at the end with the total.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from numba.core import event

__all__ = ["GROUPS", "compile_kernels", "main", "ship"]


class _Count(event.Listener):
    """Counts numba's compiles of this package's kernels (outermost ones only)."""

    def __init__(self) -> None:
        self.kernels = 0
        self._depth = 0

    def on_start(self, ev: event.Event) -> None:
        self._depth += 1
        function = getattr(ev.data["dispatcher"], "py_func", None)
        if getattr(function, "__module__", "").startswith("impulse2d."):
            self.kernels += 1

    def on_end(self, ev: event.Event) -> None:
        self._depth -= 1


def _world(batch: int) -> Any:
    """A world of every shape kind with a spring and a sensor; ``batch`` copies of it."""
    import impulse2d as p2

    world = p2.World()
    world.add(p2.Plane())
    ball = world.add(p2.Circle(position=(0.0, 1.0)))
    box = world.add(p2.Box(position=(1.0, 1.0)))
    world.add(p2.Spring(ball, box, stiffness=10.0))
    world.add(p2.Sensor(position=(0.0, 0.5), width=1.0, height=1.0))
    return world if batch == 1 else world.replicate(batch)


def _engine_one() -> None:
    world = _world(1)
    world.step(1 / 60)
    world.step(1 / 60, steps=2)


def _engine_batch() -> None:
    world = _world(4)
    world.threads = 2  # the batched kernel, on threads
    world.step(1 / 60)


def _game(env_id: str, batch: int) -> Callable[[], None]:
    def play() -> None:
        import gymnasium as gym

        import impulse2d  # noqa: F401  (registers the ids)

        if batch == 1:
            env = gym.make(env_id)
        else:
            env = gym.make_vec(env_id, num_envs=batch, vectorization_mode="vector_entry_point")
        env.reset(seed=0)
        env.step(env.action_space.sample())
        env.close()

    return play


# (name, what it runs, whether it needs gymnasium)
GROUPS: list[tuple[str, Callable[[], None], bool]] = [
    ("engine: one world's step", _engine_one, False),
    ("engine: a batch's step on threads", _engine_batch, False),
    ("Pool2D-v0: a shot", _game("Pool2D-v0", 1), True),
    ("Pool2D-v0: a shot of a batch of tables", _game("Pool2D-v0", 4), True),
    ("Slingshot2D-v0: a shot", _game("Slingshot2D-v0", 1), True),
    ("Slingshot2D-v0: a shot of a batch", _game("Slingshot2D-v0", 4), True),
]


def compile_kernels(engine_only: bool = False, say: Callable[[str], None] = print) -> float:
    """Compile (or load) every kernel of the groups into the cache; returns the seconds.

    ``say`` gets one line per group and one at the end."""
    import impulse2d  # noqa: F401  (before the clock: the import is not compiling)
    from impulse2d.core._jit import JIT_DISABLED

    if JIT_DISABLED:
        say("NUMBA_DISABLE_JIT is set: nothing to compile")
        return 0.0
    count = _Count()
    start = time.perf_counter()
    with event.install_listener("numba:compile", count):
        for name, run, needs_gym in GROUPS:
            if needs_gym and engine_only:
                continue
            before, began = count.kernels, time.perf_counter()
            run()
            compiled = count.kernels - before
            say(f"  {name:40s} {time.perf_counter() - began:6.1f} s  {compiled:3d} compiled")
    seconds = time.perf_counter() - start
    say(f"impulse2d: kernels compiled and cached in {seconds:.1f} s ({count.kernels} compiled)")
    return seconds


def _read_index(path: Path) -> tuple[str, Any, dict[Any, str]]:
    """numba's index file of one kernel: its numba version, its source stamp and its
    entries (index key -> data file name). numba's own format (``IndexDataCacheFile``):
    the version pickled, then the pickle of (stamp, entries)."""
    with open(path, "rb") as index:
        version = pickle.load(index)
        stamp, entries = pickle.loads(index.read())
    return version, stamp, entries


def _merge_index(source: Path, target: Path) -> None:
    """Add a scratch cache's entries of one kernel, with their data files, to the shipped
    index of that kernel: one index holds every target's compile. The data files are
    renumbered (numba numbers them from 1 in every cache)."""
    version, stamp, entries = _read_index(source)
    merged: dict[Any, str] = {}
    if target.exists():
        *made_by, merged = _read_index(target)
        if made_by != [version, stamp]:
            raise RuntimeError(f"{source.name}: compiled by another numba or from other sources")
    base, used, number = source.name.removesuffix(".nbi"), set(merged.values()), 1
    for key, data_name in entries.items():
        while f"{base}.{number}.nbc" in used:
            number += 1
        name = f"{base}.{number}.nbc"
        shutil.copy2(source.parent / data_name, target.parent / name)
        merged[key], used = name, used | {name}
    with open(target, "wb") as index:
        pickle.dump(version, index, protocol=-1)
        index.write(pickle.dumps((stamp, merged), protocol=-1))


def ship(say: Callable[[str], None] = print) -> Path:
    """Compile every group's kernels for each portable target into the shipped folder
    (emptied first) and write its manifest; returns the folder.

    Each target compiles in a child process of its own (numba reads the CPU to target
    when it starts) into a scratch cache, with the portable lookup off so that nothing is
    loaded from the other target."""
    from impulse2d.core import _jit, _shipped

    folder = _shipped.SHIPPED
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    for cpu, _ in _shipped.TARGETS:
        with tempfile.TemporaryDirectory() as scratch:
            target = {"NUMBA_CPU_NAME": cpu, "NUMBA_CPU_FEATURES": ""}
            env = {**os.environ, **target, "NUMBA_CACHE_DIR": scratch, _shipped.SWITCH: "0"}
            say(f"impulse2d: compiling the kernels for {cpu}...")
            command = [sys.executable, "-m", "impulse2d.compile"]
            subprocess.run(command, env=env, check=True)
            for index in sorted(Path(scratch).rglob("*.nbi")):
                _merge_index(index, folder / index.name)
    facts = _shipped.build_facts(_jit.kernel_sources_digest(_jit._PACKAGE))
    facts["targets"] = [cpu for cpu, _ in _shipped.TARGETS]
    (folder / _shipped.MANIFEST).write_text(json.dumps(facts, indent=1) + "\n")
    size = sum(path.stat().st_size for path in folder.iterdir()) / 2**20
    say(f"impulse2d: {len(list(folder.glob('*.nbi')))} kernels shipped in {folder} "
        f"({size:.1f} MiB)")  # fmt: skip
    return folder


def main(argv: list[str] | None = None) -> None:
    """The command line: ``python -m impulse2d.compile [--engine | --ship]``."""
    parser = argparse.ArgumentParser(
        prog="python -m impulse2d.compile",
        description="Compile impulse2d's kernels into numba's cache ahead of the first run "
        "(container images, CI, cluster nodes).",
    )
    parser.add_argument(
        "--engine", action="store_true", help="the engine's kernels only, not the games'"
    )
    parser.add_argument(
        "--ship", action="store_true",
        help="build the portable kernels a wheel ships, into the package (CI, before the wheel)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.ship:
        ship(say=lambda line: print(line, flush=True))
        return
    from impulse2d.core import _shipped

    os.environ[_shipped.SWITCH] = "0"  # compile for this CPU, even where portable ones load
    if not args.engine:
        try:
            import gymnasium  # noqa: F401
        except ImportError:
            print("gymnasium is not installed: compiling the engine's kernels only")
            args.engine = True
    print("impulse2d: compiling the kernels into the cache...", flush=True)
    compile_kernels(args.engine, say=lambda line: print(line, flush=True))


if __name__ == "__main__":
    main(sys.argv[1:])
