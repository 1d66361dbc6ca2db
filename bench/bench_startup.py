"""What a new user waits: compiling the kernels the first time, and loading them after.

Each case runs in a fresh Python process and times, from the top of the script (the
import included), the first thing a user does with the engine:

* ``engine``: ``import impulse2d``, a world of a plane, a circle and a box, its first
  ``step``, then the first step of a batch of 4 copies (its kernel is another one);
* ``Pool2D-v0`` / ``Slingshot2D-v0``: ``gym.make`` of the env, ``reset`` and the first
  shot;
* ``Pool2D-v0 x64``: the first shot of a batched vector env of 64 tables
  (``gym.make_vec(..., vectorization_mode="vector_entry_point")``), what training steps;
* ``main command``: ``python -m agents.train --env Pool2DCallShot-v0 --algo ppo`` until
  its first progress line (the process is then stopped; its run folder is a scratch one).

Compile cost is reported as process CPU time as well as wall time: the machine's cores
are shared, and CPU time is what compiling costs whatever else runs beside it. For the
cold run of each case the table after the times lists the CPU seconds numba spent on
each kernel (``numba:compile`` events, its own time: the kernels it compiled inside it
not counted), largest first; numba's own helpers (``builtins``, ``unicode``, ...) are
summed in one row.

``cold`` points numba's cache at an empty scratch directory of its own
(``NUMBA_CACHE_DIR``: never the repository's cache), which is the first run after
installing; every cold run gets a new one. ``cached`` runs again on the cache the first
cold run wrote. The notice lines the runs printed on stderr (``impulse2d: compiling
...``) are shown after the table, and a cached run must print none. The peer is pymunk,
which needs no compiling.

    python bench/bench_startup.py             # about 12 minutes on 2 cores: 10 cold compiles
    python bench/bench_startup.py --cases engine --repeats 1
    python bench/bench_startup.py --top 40    # more rows of the per-kernel table
    python bench/bench_startup.py --wheel dist/impulse2d-0.3.0-py3-none-any.whl

``--wheel`` installs a built wheel (``python -m impulse2d.compile --ship`` before
``python -m build``, as CI does) with the games' extra into a fresh venv and runs the
cases there, from an empty folder: what a user who ran ``pip install`` waits. Its "cold"
runs find only the wheel's portable kernels (``impulse2d.core._shipped``); with
``--no-shipped`` they compile, as an install without them does. The main command needs
the clone (and the ``rl`` extra), so a wheel's run leaves it out. pymunk's first step is
timed in this interpreter (the dev venv's pymunk).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

_Times = list[tuple[float, float]]  # (wall, cpu) seconds of each run

_HEAD = r"""
import json, time
from numba.core import event
t0, c0 = time.perf_counter(), time.process_time()
class _Kernels(event.Listener):  # CPU seconds of each compile, its nested ones left out
    def __init__(self):
        self.open, self.own = [], {}
    def on_start(self, ev):
        f = ev.data["dispatcher"].py_func
        name = f"{f.__module__.removeprefix('impulse2d.')}.{f.__name__}"
        if not f.__module__.startswith("impulse2d"):
            name = f"numba's {f.__module__.rsplit('.', 1)[-1]} helpers"
        self.open.append([name, time.process_time(), 0.0])
    def on_end(self, ev):
        name, start, inner = self.open.pop()
        spent = time.process_time() - start
        if self.open:
            self.open[-1][2] += spent
        self.own[name] = self.own.get(name, 0.0) + spent - inner
_kernels = _Kernels()
event.register("numba:compile", _kernels)
import impulse2d as p2
times, cpu = {}, {}
def mark(key):
    times[key], cpu[key] = time.perf_counter() - t0, time.process_time() - c0
mark("import")
"""

_TAIL = r"""
from impulse2d._compile_notice import seconds_compiling
times["compiling (notice)"] = cpu["compiling (notice)"] = seconds_compiling()
print(json.dumps({"wall": times, "cpu": cpu, "kernels": _kernels.own}))
"""

_CASES = {
    "engine": r"""
w = p2.World()
w.add(p2.Plane())
w.add(p2.Circle(position=(0.0, 1.0)))
w.add(p2.Box(position=(1.0, 1.0)))
w.step(1 / 60)
mark("first step")
w.replicate(4).step(1 / 60)
mark("first batch step")
""",
    "Pool2D-v0": r"""
import gymnasium as gym
env = gym.make("Pool2D-v0")
env.reset(seed=0)
env.step(env.action_space.sample())
mark("first Pool2D-v0 shot")
""",
    "Slingshot2D-v0": r"""
import gymnasium as gym
env = gym.make("Slingshot2D-v0")
env.reset(seed=0)
env.step(env.action_space.sample())
mark("first Slingshot2D-v0 shot")
""",
    "Pool2D-v0 x64": r"""
import gymnasium as gym
envs = gym.make_vec("Pool2D-v0", num_envs=64, vectorization_mode="vector_entry_point")
envs.reset(seed=0)
envs.step(envs.action_space.sample())
mark("first Pool2D-v0 x64 shot")
""",
}

# The main command's first progress line: run it in a child, stop it at that line.
_MAIN = r"""
import json, os, subprocess, sys, tempfile, time
t0, usage = time.perf_counter(), __import__("resource").getrusage
cmd = [sys.executable, "-u", "-m", "agents.train", "--env", "Pool2DCallShot-v0", "--algo", "ppo",
       "--run-dir", tempfile.mkdtemp()]
child = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
for line in child.stdout:
    if line.startswith("progress"):
        break
wall = time.perf_counter() - t0
child.kill()
child.wait()
ru = usage(__import__("resource").RUSAGE_CHILDREN)
key = "first progress line"
print(json.dumps({"wall": {key: wall}, "cpu": {key: ru.ru_utime + ru.ru_stime}, "kernels": {}}))
"""

_PYMUNK = r"""
import json, time
t0 = time.perf_counter()
import pymunk
space = pymunk.Space()
body = pymunk.Body(1.0, 1.0)
space.add(body, pymunk.Circle(body, 0.5))
space.step(1 / 60)
print(json.dumps({"import": time.perf_counter() - t0, "first step": time.perf_counter() - t0}))
"""


# Where the runs happen: this interpreter on the clone (the default), or a fresh venv
# with a built wheel installed (``--wheel``), run from an empty folder.
_PYTHON = {"python": sys.executable, "cwd": os.getcwd(), "path": os.getcwd(), "env": {}}


def _run(code: str, cache: str | None) -> tuple[dict[str, Any], list[str]]:
    """Run ``code`` in a fresh interpreter (numba's cache in ``cache``); its times and
    the notice lines it printed."""
    env = dict(os.environ, **_PYTHON["env"])
    for name in ("NUMBA_DISABLE_JIT", "IMPULSE2D_QUIET", "IMPULSE2D_COMPILE_RUN", "PYTHONPATH"):
        env.pop(name, None)  # a fresh run of its own, which may speak
    if _PYTHON["path"]:
        env["PYTHONPATH"] = _PYTHON["path"]
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    out = subprocess.run([_PYTHON["python"], "-c", code], env=env, check=True, cwd=_PYTHON["cwd"],
                         capture_output=True, text=True)  # fmt: skip
    notices = [line for line in out.stderr.splitlines() if line.startswith("impulse2d:")]
    return json.loads(out.stdout.strip().splitlines()[-1]), notices


def _code(case: str) -> str:
    return _MAIN if case == "main command" else _HEAD + _CASES[case] + _TAIL


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2, help="cold runs and cached runs")
    choices = [*_CASES, "main command"]
    parser.add_argument("--cases", nargs="+", choices=choices, default=choices)
    parser.add_argument("--top", type=int, default=20, help="rows of the per-kernel table")
    parser.add_argument("--wheel", help="a built wheel: run in a fresh venv with it installed")
    parser.add_argument(
        "--no-shipped", action="store_true",
        help="switch the wheel's portable kernels off (IMPULSE2D_SHIPPED_KERNELS=0)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.wheel:
        _install(args.wheel)
        args.cases = [case for case in args.cases if case != "main command"]
    if args.no_shipped:
        _PYTHON["env"]["IMPULSE2D_SHIPPED_KERNELS"] = "0"
    kernels: dict[str, dict[str, float]] = {}
    table: dict[str, list[tuple[str, _Times, _Times]]] = {}
    notices: dict[str, list[str]] = {}
    for case in args.cases:
        code = _code(case)
        cold, cached = [], []
        with tempfile.TemporaryDirectory() as first:
            for i in range(args.repeats):
                print(f"... {case}: cold run {i + 1}", file=sys.stderr, flush=True)
                if i == 0:
                    times, said = _run(code, first)
                else:
                    with tempfile.TemporaryDirectory() as cache:
                        times, said = _run(code, cache)
                cold.append(times)
                notices.setdefault(case, said)
                kernels.setdefault(case, times["kernels"])
            for i in range(args.repeats):
                print(f"... {case}: cached run {i + 1}", file=sys.stderr, flush=True)
                times, said = _run(code, first)
                cached.append(times)
                if said:
                    raise SystemExit(f"{case}: a cached run printed {said}")
        table[case] = [
            (
                key,
                [(t["wall"][key], t["cpu"][key]) for t in cold],
                [(t["wall"][key], t["cpu"][key]) for t in cached],
            )
            for key in cold[0]["wall"]
        ]
    try:
        where = dict(_PYTHON)  # pymunk in this interpreter, the wheel's venv has none
        _PYTHON.update(python=sys.executable, cwd=os.getcwd(), path=os.getcwd(), env={})
        peer, _ = _run(_PYMUNK, None)
        _PYTHON.update(where)
    except subprocess.CalledProcessError:
        peer = {}
    print(f"seconds since the script started, wall (cpu), {args.repeats} runs each")
    print(f"{'':34s} {'cold (empty cache)':>26s} {'cached':>24s} {'pymunk':>7s}")
    for case, rows in table.items():
        print(case)
        for key, cold_times, cached_times in rows:
            other = f"{peer[key]:7.2f}" if case == "engine" and key in peer else f"{'-':>7s}"
            print(f"  {key:32s} {_list(cold_times):>26s} {_list(cached_times):>24s} {other}")
    if "first step" in peer:
        print(f"pymunk, import to the first step: {peer['first step']:.2f} s")
    _print_kernels(kernels, args.top)
    print("what the first cold run of each case printed on stderr:")
    for case, said in notices.items():
        for line in said or ["(nothing)"]:
            print(f"  {case}: {line}")
    if "engine" in table:
        first = max(wall for wall, _ in dict((k, c) for k, _, c in table["engine"])["first step"])
        print(f"target: cached import + world + first step under 3 s: {first:.2f} s, "
              f"{'ok' if first < 3.0 else 'MISS'}")  # fmt: skip


def _install(wheel: str) -> None:
    """A fresh venv with ``wheel`` and the games' extra installed, as a new user's; the
    runs then use it, from an empty folder, with nothing of the clone on the path."""
    folder = Path(tempfile.mkdtemp(prefix="impulse2d-wheel-"))
    print(f"... installing {Path(wheel).name}[envs] into a fresh venv", file=sys.stderr)
    subprocess.run([sys.executable, "-m", "venv", str(folder / "venv")], check=True)
    python = str(folder / "venv" / "bin" / "python")
    subprocess.run([python, "-m", "pip", "install", "--quiet", f"{Path(wheel).resolve()}[envs]"],
                   check=True)  # fmt: skip
    (folder / "run").mkdir()
    _PYTHON.update(python=python, cwd=str(folder / "run"), path="")


def _print_kernels(kernels: dict[str, dict[str, float]], top: int) -> None:
    """The CPU seconds each kernel's compile took in the first cold run of each case."""
    print("compile CPU seconds per kernel, first cold run (its own, nested compiles out):")
    for case, own in kernels.items():
        if not own:
            continue
        rows = sorted(own.items(), key=lambda row: -row[1])
        print(f"  {case}: {sum(own.values()):.1f} s over {len(own)} kernels")
        for name, seconds in rows[:top]:
            print(f"    {name:44s} {seconds:6.2f}")
        if len(rows) > top:
            print(f"    {len(rows) - top} more {sum(t for _, t in rows[top:]):27.2f}")


def _list(times: _Times) -> str:
    return ", ".join(f"{wall:.1f} ({cpu:.1f})" for wall, cpu in times)


if __name__ == "__main__":
    main()
