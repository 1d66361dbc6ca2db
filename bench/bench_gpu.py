"""The GPU benchmark: impulse2d's step on a GPU against its own CPU path (and Jax2D).

One prepared script for the lent GPU machine, printing in one run:

1. the first launch: what compiling the step for the GPU costs, once per process;
2. the 16-ball pool break (``scenes.pool_break``), every world its own shot (cue ball up
   to 1 cm off the axis, ``scenes.pool_cue_offsets``), at 10^3 to 10^6 worlds:
   world-steps/s on the GPU (one ``World.step(dt, steps=S)`` call: one launch, the state
   copied in and out) and through the CPU path on all the machine's cores (the same
   call, on at most ``--cpu-worlds`` of the worlds: a world costs the CPU the same
   however many there are), and a GPU call's fixed cost (a one-step call);
3. agreement: 256 shots played on both, the largest difference in a ball's position and
   velocity after the break, and how many worlds ended bitwise equal; then in the game,
   256 full racks of ``Pool2D-v0`` and five seeded random shots each on both: how many
   shots gave the same reward, pots and fouls;
4. ``Pool2D-v0``'s vector env: shots/s at 10^4 and 10^5 tables on the GPU (every table's
   shot one launch), and on the CPU;
5. Jax2D's pool break on the same GPU at 10^4 and 10^5 worlds (each size compiles
   anew in JAX), where ``jax2d`` is installed (``bench/jax2d_peer.py``; skipped with a
   line saying so otherwise);

with the targets beside them (10^7 world-steps/s and 10x the CPU path for the break,
3x Jax2D, 2x10^4 shots/s for the env). A size that does not fit the GPU's free memory is
skipped with the memory it needs.

``python bench/bench_gpu.py`` (meant to finish in under five minutes on an H200;
``--quick`` for 10^3 and 10^4 worlds). On the lent machine, whose image has numba,
numba-cuda, JAX, flax and chex but not gymnasium or jax2d: carry wheels of gymnasium,
farama-notifications and jax2d into ``/tmp/site`` (the device tool's README says how),
add impulse2d there (``python3 -m pip install -q --no-deps --no-index
--no-build-isolation --target /tmp/site .``: the envs live in ``envs/``, which only an
install maps to ``impulse2d.envs``) and run ``PYTHONPATH=/tmp/site python3
bench/bench_gpu.py``. Without a GPU,
``NUMBA_ENABLE_CUDASIM=1 NUMBA_DISABLE_JIT=1 python bench/bench_gpu.py --smoke`` runs
every section at a few worlds in numba's CUDA simulator: a check of the script
(``tests/test_gpu.py`` runs it), not a timing.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/: engine_runs, scenes

import engine_runs
import impulse2d as p2
from scenes import pool_break, pool_cue_offsets

TARGET_RATE = 1e7  # world-steps/s on one H200
TARGET_VS_CPU = 10.0
TARGET_VS_JAX2D = 3.0
TARGET_SHOTS = 2e4  # Pool2D-v0 vector env shots/s


def say(text: str) -> None:
    """Progress on stderr, flushed (the machine's output is read after the run)."""
    print(f"[{time.strftime('%H:%M:%S')}] {text}", file=sys.stderr, flush=True)


def machine() -> str:
    from numba import config, cuda

    if config.ENABLE_CUDASIM:
        return "numba's CUDA simulator (no GPU: nothing below is a timing)"
    device = cuda.get_current_device()
    free, total = cuda.current_context().get_memory_info()
    name = device.name.decode() if isinstance(device.name, bytes) else device.name
    return (
        f"{name}, compute capability {device.compute_capability}, "
        f"{total / 2**30:.0f} GiB ({free / 2**30:.0f} free); CPU: {os.cpu_count()} cores"
    )


def bytes_per_world() -> int:
    """Device memory one pool world needs in a launch: its state, undo rows and scratch,
    and the transposed copies of the state made on the way (x2)."""
    from impulse2d.core import refusal
    from impulse2d.core.workspace import row_sizes

    world, _ = engine_runs.pool_batch_world(2)
    world.step(pool_break().dt)
    state = sum(a.nbytes for a in world.state.arrays().values()) // 2
    bodies, contacts = world.state.body.shape[1], world.state.contact_capacity
    scratch = sum(row_sizes(bodies, contacts, world._runner.pair_capacity)) * 8
    springs = world.state.spring.shape[1]
    return 2 * state + scratch + sum(refusal.undo_sizes(bodies, contacts, springs)) * 8


def fits(worlds: int, per_world: int) -> tuple[bool, float]:
    from numba import config, cuda

    needed = worlds * per_world
    if config.ENABLE_CUDASIM:
        return True, needed / 2**30
    free, _ = cuda.current_context().get_memory_info()
    return needed < 0.8 * free, needed / 2**30


def break_world(worlds: int, device: str) -> p2.World:
    """The pool break in ``worlds`` worlds, world ``i`` playing shot ``i``."""
    world, _ = engine_runs.pool_batch_world(
        worlds, cue_y_offsets=pool_cue_offsets(worlds), device=device
    )
    return world


def timed_call(world: p2.World, steps: int) -> float:
    dt = pool_break().dt
    t0 = time.perf_counter()
    world.step(dt, steps=steps)
    return time.perf_counter() - t0


def first_launch() -> float:
    say("first launch: compiling the step for the GPU")
    return timed_call(break_world(2, "cuda"), 1)


def break_rates(sizes: list[int], steps: int, cpu_worlds: int, per_world: int) -> list[list]:
    rows = []
    for n in sizes:
        ok, gib = fits(n, per_world)
        if not ok:
            rows.append([f"{n:,}", f"skipped: needs ~{gib:.0f} GiB", "", "", "", ""])
            continue
        say(f"pool break: {n:,} worlds on the GPU, {steps} steps")
        gpu_world = break_world(n, "cuda")
        fixed = timed_call(gpu_world, 1)
        gpu_world = break_world(n, "cuda")
        gpu = n * steps / timed_call(gpu_world, steps)
        m = min(n, cpu_worlds)
        say(f"pool break: {m:,} worlds on the CPU, {steps} steps")
        cpu_world = break_world(m, "cpu")
        cpu = m * steps / timed_call(cpu_world, steps)
        rows.append([
            f"{n:,}", f"{gpu:,.0f}", f"{cpu:,.0f} ({m:,} worlds)", f"{gpu / cpu:.1f}",
            f"{fixed * 1e3:.1f}", _mark(gpu >= TARGET_RATE and gpu / cpu >= TARGET_VS_CPU),
        ])  # fmt: skip
    return rows


def agreement(worlds: int, steps: int) -> list[str]:
    say(f"agreement: {worlds} shots, {steps} steps on both")
    ends = []
    for device in ("cpu", "cuda"):
        world = break_world(worlds, device)
        world.step(pool_break().dt, steps=steps)
        state = world.state
        ends.append(state.body[:, :, :6].copy())
    cpu, gpu = ends
    same = int(np.all(cpu == gpu, axis=(1, 2)).sum())
    position = float(np.abs(cpu[:, :, :2] - gpu[:, :, :2]).max())
    velocity = float(np.abs(cpu[:, :, 3:5] - gpu[:, :, 3:5]).max())
    return [f"{worlds}", f"{steps}", f"{position:.3g}", f"{velocity:.3g}", f"{same}/{worlds}"]


def game_agreement(tables: int, shots: int, seconds: float | None) -> list[str]:
    """The same seeded racks and shots of ``Pool2D-v0`` (15 balls) on both: how many of
    the shots gave the same reward, pots and fouls, and the largest difference in a
    ball's place after them (m)."""
    say(f"game agreement: {tables} racks, {shots} shots on both")
    played = []
    for device in ("cpu", "cuda"):
        env = _pool_tables(tables, device, seconds)
        env.reset(seed=0)
        actions = np.random.default_rng(0).uniform(-1, 1, (shots, *env.action_space.shape))
        outcomes = []
        for action in actions.astype(np.float32):
            _, reward, _, _, info = env.step(action)
            outcomes.append((reward, info["potted"], info["fouls"]))
        played.append((outcomes, env.unwrapped.game.world.state.body[:, :, :2].copy()))
    (cpu, cpu_end), (gpu, gpu_end) = played
    same = sum(
        int(np.sum((c[0] == g[0]) & (c[1] == g[1]) & (c[2] == g[2])))
        for c, g in zip(cpu, gpu, strict=True)
    )
    place = float(np.abs(cpu_end - gpu_end).max())
    return [f"{tables}", f"{shots}", f"{same}/{tables * shots}", f"{place:.3g}"]


def _pool_tables(tables: int, device: str, seconds: float | None) -> Any:
    """The Pool2D-v0 vector env of ``tables`` on ``device`` (shots cut at ``seconds``)."""
    import gymnasium as gym

    options = {"max_shot_seconds": seconds} if seconds else {}
    return gym.make_vec(
        "Pool2D-v0", tables, vectorization_mode="vector_entry_point", device=device,
        autoreset_mode="same_step", **options,
    )  # fmt: skip


def env_rate(tables: int, device: str, shots: int, seconds: float | None = None) -> float:
    env = _pool_tables(tables, device, seconds)
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1, 1, (shots, *env.action_space.shape))
    t0 = time.perf_counter()
    for action in actions.astype(np.float32):
        env.step(action)
    return tables * shots / (time.perf_counter() - t0)


def env_rates(sizes: list[int], shots: int, cpu_tables: int, seconds: float | None) -> list[list]:
    rows = []
    for n in sizes:
        say(f"Pool2D-v0: {n:,} tables on the GPU, {shots} shots")
        gpu = env_rate(n, "cuda", shots, seconds)
        m = min(n, cpu_tables)
        say(f"Pool2D-v0: {m:,} tables on the CPU, {shots} shots")
        cpu = env_rate(m, "cpu", shots, seconds)
        rows.append([f"{n:,}", f"{gpu:,.0f}", f"{cpu:,.0f} ({m:,} tables)", f"{gpu / cpu:.1f}",
                     _mark(gpu >= TARGET_SHOTS)])  # fmt: skip
    return rows


def jax2d_rows(sizes: list[int], steps: int, impulse2d: dict[int, float]) -> list[list]:
    # JAX takes three quarters of the GPU's memory when it starts unless told not to.
    os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")
    try:
        import jax2d_peer
    except ImportError as missing:
        return [["-", f"not run: {missing}", "", ""]]
    rows = []
    for n in sizes:
        say(f"Jax2D pool break: {n:,} worlds, {steps} steps")
        rate = jax2d_peer.pool_break_rate(n, steps)
        ours = impulse2d.get(n)
        ratio = f"{ours / rate:.1f}" if ours else "-"
        rows.append([f"{n:,}", f"{rate:,.0f}", ratio, _mark(bool(ours) and ours / rate >= 3)])
    return rows


def _mark(met: bool) -> str:
    return "met" if met else "MISS"


def table(title: str, header: list[str], rows: list[list]) -> None:
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    print(f"\n{title}")
    for row in [header, ["-" * w for w in widths], *rows]:
        print("  ".join(str(c).ljust(w) for c, w in zip(row, widths, strict=True)).rstrip())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", default="1000,10000,100000,1000000", help="worlds")
    parser.add_argument("--steps", type=int, default=240, help="steps of the break timed")
    parser.add_argument("--cpu-worlds", type=int, default=16384, help="most worlds on the CPU")
    parser.add_argument("--jax2d-sizes", default="10000,100000", help="worlds for Jax2D")
    parser.add_argument("--quick", action="store_true", help="10^3 and 10^4 worlds only")
    parser.add_argument("--smoke", action="store_true", help="a few worlds (the simulator)")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    env_sizes, shots, env_seconds, agree = [10_000, 100_000], 3, None, (256, 1200)
    if args.quick:
        sizes, env_sizes = [1000, 10_000], [10_000]
    if args.smoke:
        sizes, env_sizes, shots, env_seconds, agree = [4], [3], 1, 0.5, (3, 20)
        args.jax2d_sizes = "4"
        args.steps = 10
    started = time.perf_counter()
    print(f"impulse2d on a GPU: {machine()}")
    print(f"first launch (compiles the step for the GPU): {first_launch():.1f} s")
    per_world = bytes_per_world()
    rows = break_rates(sizes, args.steps, args.cpu_worlds, per_world)
    table(
        f"pool break, every world its own shot, {args.steps} steps (world-steps/s; target "
        f">= {TARGET_RATE:.0e} and >= {TARGET_VS_CPU:.0f}x the CPU path)",
        ["worlds", "GPU", "CPU path, all cores", "GPU/CPU", "GPU call fixed ms", "target"],
        rows,
    )
    table(
        "agreement, CPU against GPU (m, m/s)",
        ["worlds", "steps", "max |dx|", "max |dv|", "bitwise equal"],
        [agreement(*agree)],
    )
    table(
        "agreement in the game: Pool2D-v0, full racks, random shots on both",
        ["tables", "shots", "same reward, pots, fouls", "max |dx| after (m)"],
        [game_agreement(agree[0], 5 if not args.smoke else 1, env_seconds)],
    )
    table(
        f"Pool2D-v0 vector env, {shots} random shots (shots/s; target >= {TARGET_SHOTS:.0e})",
        ["tables", "GPU", "CPU, all cores", "GPU/CPU", "target"],
        env_rates(env_sizes, shots, 4096, env_seconds),
    )
    ours = {int(r[0].replace(",", "")): float(r[1].replace(",", "")) for r in rows if r[2]}
    table(
        f"Jax2D's pool break on the same GPU (world-steps/s; target impulse2d >= "
        f"{TARGET_VS_JAX2D:.0f}x)",
        ["worlds", "Jax2D", "impulse2d / Jax2D", "target"],
        jax2d_rows([int(s) for s in args.jax2d_sizes.split(",")], args.steps, ours),
    )
    print(f"\ntotal {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
