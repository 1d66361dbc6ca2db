"""The laws every random scene must obey, as measurements (``test_random_scenes.py``
asserts them over a few hundred scenes, ``bench/fuzz_scenes.py`` counts them over
thousands).

Each ``*_excess`` function steps a world and returns the worst violation seen, scaled so
that a value above 1 breaks the law (0 or below: held with room to spare).
"""

from __future__ import annotations

import math

import numpy as np

import impulse2d as p2
import scenes_random as sr
from impulse2d.core.state import ANGLE, HEALTH, KEPT_TORQUE, MASS, MOMENT, OMEGA, VX, VY, X, Y

ENERGY_TOLERANCE = 0.01  # relative kinetic energy gain allowed (solver error)
MOMENTUM_TOLERANCE = 1e-9  # relative drift of linear and angular momentum


def finite(world: p2.World) -> bool:
    """Every float of the state finite (health may be +inf: unbreakable), and the energy."""
    arrays = world.state.arrays()
    body = np.delete(arrays.pop("body"), HEALTH, axis=-1)
    floats = [a for a in arrays.values() if a.dtype.kind == "f"]
    return bool(np.isfinite(body).all() and all(np.isfinite(a).all() for a in floats)) and (
        math.isfinite(world.energy().total)
    )


def movers(world: p2.World) -> list:
    """The circles and boxes that can be given a velocity (dynamic and kinematic)."""
    return [b for b in world.bodies if not isinstance(b, p2.Plane) and not b.fixed]


def signed_distances(world: p2.World) -> np.ndarray:
    """(dynamic bodies, planes) signed distance of each centre to each plane (m, > 0: in
    front)."""
    bodies = [b for b in movers(world) if not b.kinematic]
    planes = [b for b in world.bodies if isinstance(b, p2.Plane)]
    if not bodies or not planes:
        return np.zeros((0, 0))
    centres = np.array([b.position for b in bodies])
    return np.array([(centres - p.point) @ p.normal for p in planes]).T


def kinetic(world: p2.World) -> float:
    e = world.energy()
    return e.kinetic_linear + e.kinetic_rotational


def momenta(world: p2.World) -> tuple[np.ndarray, float]:
    """Total linear momentum (2,) and angular momentum about the origin of world 0."""
    body = world.state.body[0, : len(world.bodies)]
    m, x, y = body[:, MASS], body[:, X], body[:, Y]
    vx, vy, w = body[:, VX], body[:, VY], body[:, OMEGA]
    linear = np.array([(m * vx).sum(), (m * vy).sum()])
    return linear, float((m * (x * vy - y * vx)).sum() + (body[:, MOMENT] * w).sum())


def momentum_scales(world: p2.World) -> tuple[float, float]:
    """What the momenta are measured against: the sums of the magnitudes, ``sum m |v|``
    and ``sum m |x x v| + I |w|`` (a total near zero, bodies flying apart, has no
    relative error of its own)."""
    body = world.state.body[0, : len(world.bodies)]
    m, x, y = body[:, MASS], body[:, X], body[:, Y]
    vx, vy, w = body[:, VX], body[:, VY], body[:, OMEGA]
    linear = float((m * np.hypot(vx, vy)).sum())
    angular = float(
        (m * np.hypot(x, y) * np.hypot(vx, vy)).sum() + (body[:, MOMENT] * abs(w)).sum()
    )
    return linear, angular


def plane_excess(world: p2.World, dt: float, steps: int) -> float:
    """How far (m) the deepest centre got behind a plane over ``steps`` steps, positive
    when it did (0 if the scene has no planes). Stops early at a non-finite number
    (``inf``)."""
    deepest = -np.inf
    for _ in range(steps):
        world.step(dt)
        d = signed_distances(world)
        if d.size:
            if not np.isfinite(d).all():
                return np.inf
            deepest = max(deepest, float(-d.min()))
    return deepest if np.isfinite(deepest) else 0.0


def energy_excess(world: p2.World, dt: float, steps: int) -> float:
    """The largest kinetic energy gain over the start, over ``ENERGY_TOLERANCE`` times the
    start (+1e-12 J)."""
    start = kinetic(world)
    worst = 0.0
    for _ in range(steps):
        world.step(dt)
        worst = max(worst, kinetic(world) - start)
    return worst / (ENERGY_TOLERANCE * start + 1e-12)


def impact_torque_bound(world: p2.World, before: np.ndarray, dt: float) -> float:
    """An upper bound of the angular momentum the last step's impacts may exert
    (``contacts.follow_bodies``); every other point pushes both bodies at one world point
    and exerts nothing.

    A point that may bounce (a restitution > 0, closing faster than the threshold at the
    step start) keeps its anchors' offsets ``rA``, ``rB`` from the centres for the whole
    step. Its push ``i`` gives B the impulse ``P_i = l_i n + f_i t`` (normal and friction)
    and A ``-P_i``, so the angular momentum about the origin changes by ``(xB + rB) x P_i
    - (xA + rA) x P_i = m(t_i) x P_i``, with ``m(t) = d(t) - d(0)``, ``d = xB - xA`` (both
    anchors are at one world point at the step start). Summed over the pushes::

        |sum_i m(t_i) x P_i| <= max |m| sum_i (|l_i| + |f_i|),

    which the engine records per point (``state.KEPT_TORQUE``: pushes happen only where
    the positions stand between integrations, where it measures ``|m|``). Not the net
    normal impulse: pushes the relax pass or the bounce take back still turn the pair,
    ``+l`` at ``m_1`` then ``-l`` at ``m_2`` exerting ``l (m_1 - m_2) x n`` with no net
    impulse (``test_random_scenes``), and friction turns the pair as well.

    Two discs that do not bounce keep their anchors on the normal through both centres,
    which before they touch is the line of centres at the predicted impact: their pushes
    act ``m`` off it, ``|m| <= dt u``, ``u`` the larger relative speed of the centres at
    the step's start and end; so at most ``dt u G``, ``G`` the gross impulse
    (``ContactPoints.gross``)."""
    c = world.contacts()
    if c.size == 0:
        return 0.0
    kept_torque = float(world.state.contact[0, : c.size, KEPT_TORQUE].sum())
    slots = world.objects["bodies"]
    disc = np.array([isinstance(slots[i], p2.Circle) for i in range(len(slots))] + [False])
    bouncy = np.array(
        [
            slots[i] is not None and float(np.max(slots[i].restitution)) > 0.0
            for i in range(len(slots))
        ]
        + [False]
    )
    a, b = c.slot_a, c.slot_b
    bounce = (bouncy[a] | bouncy[b]) & (c.approach < -world.restitution_threshold)
    discs = disc[a] & disc[b] & ~bounce
    if not discs.any():
        return kept_torque
    after = world.state.body[0, :, VX : VY + 1]
    a, b, gross = a[discs], b[discs], c.gross[discs]
    u = np.maximum(np.hypot(*(before[b] - before[a]).T), np.hypot(*(after[b] - after[a]).T))
    return kept_torque + float((dt * u * gross).sum())


def momentum_excess(world: p2.World, dt: float, steps: int) -> tuple[float, float]:
    """The largest drift of linear and of angular momentum over ``steps`` steps, each over
    ``MOMENTUM_TOLERANCE`` times its scale: the largest ``momentum_scales`` seen so far
    (rounding grows with the magnitudes summed, which a spring can raise), at least 1e-3.
    The angular drift is counted beyond what impacts may exert (``impact_torque_bound``,
    summed over the steps); without bounces or two discs that is 0."""
    p0, l0 = momenta(world)
    sp, sl = momentum_scales(world)
    worst_p = worst_l = allowance = 0.0
    for _ in range(steps):
        before = world.state.body[0, :, VX : VY + 1].copy()
        world.step(dt)
        allowance += impact_torque_bound(world, before, dt)
        p, angular = momenta(world)
        now_p, now_l = momentum_scales(world)
        sp, sl = max(sp, now_p), max(sl, now_l)
        tp, tl = MOMENTUM_TOLERANCE * max(sp, 1e-3), MOMENTUM_TOLERANCE * max(sl, 1e-3)
        worst_p = max(worst_p, float(np.hypot(*(p - p0))) / tp)
        worst_l = max(worst_l, (abs(angular - l0) - allowance) / tl)
    return worst_p, worst_l


def make_worlds_differ(batch: p2.World) -> None:
    """Give worlds 1.. of a batch other velocities (world 0 keeps its own, so it is not
    woken) and switch the first body off in the last world."""
    for i, body in enumerate(movers(batch)):
        v, spin = np.array(body.velocity), np.array(body.angular_velocity)
        for k in range(1, batch.batch_size):
            v[k] = -0.5 * v[k] + (1.5 * k, 0.3 * i)
            spin[k] = 0.5 * spin[k] - k
        body.velocity, body.angular_velocity = v, spin
    if batch.batch_size > 2 and batch.bodies:
        mask = np.ones(batch.batch_size, dtype=bool)
        mask[-1] = False
        batch.bodies[0].enabled = mask


def batch_differs_from_single(scene: sr.Scene, steps: int, batch_size: int = 3) -> bool:
    """Whether world 0 of a batch (worlds 1.. moving otherwise) ends bitwise different
    from the scene stepped alone."""
    single, batch = sr.build(scene), sr.build(scene, batch_size=batch_size, threads=1)
    make_worlds_differ(batch)
    for _ in range(steps):
        single.step(scene.dt)
        batch.step(scene.dt)
    return sr.world_arrays(batch, 0) != sr.world_arrays(single)


def replay_differs(scene: sr.Scene, before: int, after: int) -> bool:
    """Whether stepping ``after`` steps from a snapshot taken after ``before`` steps, then
    restoring it and stepping again, gives bitwise different states."""
    world = sr.build(scene)
    for _ in range(before):
        world.step(scene.dt)
    snap = world.snapshot()
    for _ in range(after):
        world.step(scene.dt)
    first = sr.world_arrays(world)
    world.restore(snap)
    for _ in range(after):
        world.step(scene.dt)
    return sr.world_arrays(world) != first


def poses_finite(world: p2.World) -> bool:
    body = world.state.body[0, : len(world.bodies)]
    return bool(np.isfinite(body[:, [X, Y, ANGLE, VX, VY, OMEGA]]).all())


# -- the families of wide scenes, and the laws each must obey -----------------------------------
# Keywords of ``scenes_random.scenes(wide=True, ...)`` for each family.
FAMILIES: dict[str, dict] = {
    "any": {},
    "planes": {"min_planes": 1},
    "conservative": {
        "motions": ("dynamic", "fixed"),
        "springs": False,
        "gravity": False,
        "overlap": 0.0,
    },
    "free": {"motions": ("dynamic",), "max_planes": 0, "gravity": False, "springs": False},
    "free boxes": {"motions": ("dynamic",), "max_planes": 0, "gravity": False, "kinds": ("box",)},
    # Scenes built to leave the envelope by themselves: bounces that add energy
    # (restitution 1-2), kinematic pushers, wedges of two or three planes, overlapping starts.
    "edge": {
        "motions": ("dynamic", "kinematic"),
        "min_planes": 2,
        "restitution": sr.unit(1.0, 2.0),
        "overlap": 0.5,
    },
}
LEFT_THE_ENVELOPE = "left the envelope"


def check(family: str, scene: sr.Scene, steps: int) -> list[str]:
    """The laws ``scene`` of ``family`` broke over ``steps`` steps, or
    ``[LEFT_THE_ENVELOPE]`` if a step refused it (a spring stretched so far that it pulls
    harder than the envelope allows: the one value a scene can take out of it itself).

    * any: the state stays finite; world 0 of a batch of 3 is bitwise the world alone;
      snapshot, step, restore, step repeats;
    * planes: no dynamic body's centre gets behind a plane;
    * conservative: kinetic energy never more than 1 % above the start;
    * free, free boxes: linear and angular momentum kept (``momentum_excess``);
    * edge: every step finite, and a refused step leaves the state bitwise as it was
      (``edge_broken``)."""
    if family == "edge":
        return edge_broken(scene, steps)
    try:
        return _broken(family, scene, steps)
    except ValueError as error:
        if "supported range" not in str(error):
            raise
        return [LEFT_THE_ENVELOPE]


def _broken(family: str, scene: sr.Scene, steps: int) -> list[str]:
    broken = []
    if family == "any":
        world = sr.build(scene)
        for _ in range(steps):
            world.step(scene.dt)
        if not finite(world):
            return ["finite"]
        if batch_differs_from_single(scene, min(steps, 60)):
            broken.append("batch == single")
        if replay_differs(scene, min(steps, 30), min(steps, 30)):
            broken.append("snapshot replay")
    elif family == "planes":
        depth = plane_excess(sr.build(scene), scene.dt, steps)
        broken += ["finite"] if depth == np.inf else ["in front of planes"] * (depth > 0)
    elif family == "conservative":
        world = sr.build(scene)
        if energy_excess(world, scene.dt, steps) > 1.0:
            broken.append("energy")
        broken += [] if finite(world) else ["finite"]
    else:
        world = sr.build(scene, sleeping=False)
        linear, angular = momentum_excess(world, scene.dt, steps)
        broken += ["linear momentum"] * (linear > 1.0) + ["angular momentum"] * (angular > 1.0)
        broken += [] if finite(world) else ["finite"]
    return broken


def same_state(world: p2.World, snapshot: p2.Snapshot) -> bool:
    """Every state array of ``world`` bitwise that of ``snapshot`` (NaN equal to NaN)."""
    saved = snapshot.state.arrays()
    return all(
        np.array_equal(array, saved[name], equal_nan=True)
        for name, array in world.state.arrays().items()
    )


def edge_broken(scene: sr.Scene, steps: int) -> list[str]:
    """Step ``scene`` until a step is refused: each step that goes through leaves a finite
    state, and the refused one (``EnvelopeError``, or a spring pulling harder than the
    envelope allows) leaves it bitwise as it was. ``[LEFT_THE_ENVELOPE]`` when a step was
    refused as it should be."""
    world = sr.build(scene)
    for _ in range(steps):
        before = world.snapshot()
        try:
            world.step(scene.dt)
        except ValueError as error:
            if "supported range" not in str(error):
                raise
            return [LEFT_THE_ENVELOPE] if same_state(world, before) else ["refusal changes nothing"]
        if not finite(world):
            return ["finite"]
    return []
