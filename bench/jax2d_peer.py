"""The pool break in Jax2D (the engine under Kinetix), for ``bench_gpu.py``.

Jax2D is JAX: a world's state is a pytree of arrays, ``PhysicsEngine.step`` steps one
world, and ``jax.vmap`` steps a batch on the GPU. This builds ``scenes.pool_break`` in
it, every world its own shot (``scenes.pool_cue_offsets``), and times ``steps`` steps of
the whole batch in one compiled call (``jax.lax.fori_loop``), as impulse2d's GPU call
does. Where the two engines differ: Jax2D works in float32, solves every pair of shapes
every step (10 iterations, its default; no broadphase), mixes restitution as the product
of the two shapes' (so the balls get sqrt(0.95) and the cushions 0.75 / sqrt(0.95), which
gives the scene's 0.95 and 0.75), and has no drag (the scene's 0.7/s is left out).

Needs ``jax`` (with CUDA on the GPU machine), ``jax2d``, ``flax`` and ``chex``; it imports
nothing of impulse2d. ``python bench/jax2d_peer.py`` runs a small batch on whatever
device JAX has and prints the rate and a sanity check.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
from jax2d.engine import PhysicsEngine, create_empty_sim
from jax2d.scene import add_circle_to_scene, add_rectangle_to_scene
from jax2d.sim_state import SimParams, StaticSimParams

sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/: scenes
from scenes import pool_break, pool_cue_offsets


def _one_world():
    """The break's world (cue ball on the axis), its static and dynamic parameters."""
    scene = pool_break()
    # One polygon slot more than the cushions, left empty: Jax2D lists the pairs of
    # polygons that are not both fixed, and fails on an empty list.
    static = StaticSimParams(
        num_polygons=len(scene.cushions) + 1, num_circles=len(scene.positions), num_joints=1,
        num_thrusters=1, num_static_fixated_polys=len(scene.cushions),
    )  # fmt: skip
    state = create_empty_sim(static, add_floor=False, add_walls_and_ceiling=False)
    state = state.replace(gravity=jnp.zeros(2))
    ball_e = math.sqrt(scene.restitution_ball_ball)
    for box in scene.cushions:
        state, _ = add_rectangle_to_scene(
            state, static, jnp.array(box.center), 2 * jnp.array(box.half_extents),
            friction=scene.friction, restitution=scene.restitution_ball_cushion / ball_e,
            fixated=True,
        )  # fmt: skip
    density = scene.ball_mass / (math.pi * scene.ball_radius**2)
    for position, velocity in zip(scene.positions, scene.velocities, strict=True):
        state, _ = add_circle_to_scene(
            state, static, jnp.array(position), scene.ball_radius, velocity=jnp.array(velocity),
            density=density, friction=scene.friction, restitution=ball_e,
        )  # fmt: skip
    return state, static, SimParams(dt=scene.dt)


def pool_break_batch(worlds: int):
    """``worlds`` worlds of the break, world ``i`` with shot ``i``'s cue ball; returns the
    batched state and a compiled ``run(state, steps) -> state``."""
    state, static, params = _one_world()
    batch = jax.tree.map(lambda x: jnp.repeat(x[None], worlds, axis=0), state)
    cue = batch.circle.position[:, 0].at[:, 1].set(jnp.asarray(pool_cue_offsets(worlds)))
    batch = batch.replace(
        circle=batch.circle.replace(position=batch.circle.position.at[:, 0].set(cue))
    )
    engine = PhysicsEngine(static)
    actions = jnp.zeros(static.num_joints + static.num_thrusters)
    step = jax.vmap(lambda s: engine.step(s, params, actions)[0])

    @jax.jit
    def run(states, steps):
        return jax.lax.fori_loop(0, steps, lambda _, s: step(s), states)

    return batch, run


def pool_break_rate(worlds: int, steps: int) -> float:
    """World-steps per second of ``steps`` steps of ``worlds`` breaks (compiled first)."""
    batch, run = pool_break_batch(worlds)
    jax.block_until_ready(run(batch, 1))  # compiles (steps is traced: one compile)
    t0 = time.perf_counter()
    jax.block_until_ready(run(batch, steps))
    return worlds * steps / (time.perf_counter() - t0)


if __name__ == "__main__":
    batch, run = pool_break_batch(8)
    end = run(batch, 240)
    scene = pool_break()
    half = np.array(scene.play_area) / 2 + scene.ball_radius
    inside = np.all(np.abs(np.asarray(end.circle.position)) <= half)
    moved = float(np.abs(np.asarray(end.circle.position - batch.circle.position)).max())
    print(f"{jax.devices()[0]}: {pool_break_rate(64, 240):,.0f} world-steps/s at 64 worlds; "
          f"balls on the table after 2 s: {inside}; largest move {moved:.2f} m")  # fmt: skip
