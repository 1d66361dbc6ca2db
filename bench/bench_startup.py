"""What a new user waits: compiling the kernels the first time, and importing them after.

Each case runs in a fresh Python process. ``cold`` points numba's cache at an empty
directory (``NUMBA_CACHE_DIR``), which is what the first import after installing is;
``cached`` uses the cache the cold run wrote. Both import impulse2d, build a world and
step it (one world, then a batch, which has kernels of its own), then make and step
``gym.make("Pool2D-v0")``. The peer is pymunk, which needs no compiling.

    python bench/bench_startup.py        # about half a minute: the cold compile dominates
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

_PROBE = r"""
import json, time
t0 = time.perf_counter()
import impulse2d as p2
t1 = time.perf_counter()
w = p2.World()
w.add(p2.Plane())
w.add(p2.Circle(position=(0.0, 1.0)))
w.add(p2.Box(position=(1.0, 1.0)))
w.step(1 / 60)
t2 = time.perf_counter()
w.replicate(4).step(1 / 60)
t3 = time.perf_counter()
import gymnasium as gym
env = gym.make("Pool2D-v0", num_balls=1)
env.reset(seed=0)
env.step(env.action_space.sample())
t4 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "first step": t2 - t0, "first batch step": t3 - t0,
                  "first Pool2D shot": t4 - t0}))
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


def _run(code: str, cache: str | None) -> dict[str, float]:
    env = dict(os.environ)
    env.pop("NUMBA_DISABLE_JIT", None)
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                         capture_output=True, text=True)  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="cached runs (median)")
    args = parser.parse_args(argv)
    print("... cold compile (empty numba cache)", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory() as cache:
        cold = _run(_PROBE, cache)
        cached_runs = [_run(_PROBE, cache) for _ in range(args.repeats)]
    cached = {k: sorted(r[k] for r in cached_runs)[args.repeats // 2] for k in cold}
    try:
        peer = _run(_PYMUNK, None)
    except subprocess.CalledProcessError:
        peer = {}
    print(
        f"{'seconds since the interpreter started':40s} {'cold':>8s} {'cached':>8s} {'pymunk':>8s}"
    )
    for key in cold:
        other = f"{peer[key]:8.2f}" if key in peer else f"{'-':>8s}"
        print(f"{key:40s} {cold[key]:8.2f} {cached[key]:8.2f} {other}")
    print(f"target: cached import + world + first step under 3 s: {cached['first step']:.2f} s, "
          f"{'ok' if cached['first step'] < 3.0 else 'MISS'}")  # fmt: skip


if __name__ == "__main__":
    main()
