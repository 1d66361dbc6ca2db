"""Engine-neutral benchmark scene descriptions shared by impulse2d and its peers.

Every scene is plain data in SI units (metres, kilograms, seconds); this module
imports no physics engine, so each engine's adapter builds its own world from the
same numbers. These scenes are defined:

* :func:`pool_break` - the 16-ball break on a 2.54 x 1.27 m table (contact-heavy
  burst, then many light contacts; used for the many-worlds throughput figure).
  :func:`pool_cue_offsets` gives every world of a batch its own shot (the cue ball
  moved sideways by up to 1 cm), as in reinforcement learning.
* :func:`pyramid` - the Box2D-style box pyramid on a static ground (stacking
  stability and per-step cost of a large contact graph). :func:`large_pyramid` is Box2D
  v3's own ``large_pyramid`` benchmark (100 rows, 5,050 boxes), measured by how far it
  settles (:func:`pyramid_settling`).
* :func:`rain` - ``count`` circles and boxes dropped at random onto the ground over a
  strip whose width grows with ``count`` (per-step cost against scene size).

Coordinates: y points up. Static bodies are given as axis-aligned boxes by
centre and half extents. :func:`validate` checks a scene's initial state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Vec2 = tuple[float, float]


@dataclass(frozen=True)
class StaticBox:
    """A fixed, axis-aligned box given by its centre and half extents (m)."""

    center: Vec2
    half_extents: Vec2


def _frozen(a: np.ndarray) -> np.ndarray:
    """Return a float64 copy that cannot be written to, so a scene stays immutable."""
    out = np.array(a, dtype=np.float64)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class PoolBreak:
    """Pool break: 15 racked object balls struck by the cue ball (index 0)."""

    play_area: Vec2  # (length along x, width along y), centred on the origin
    cushion_thickness: float
    cushions: tuple[StaticBox, ...]
    ball_radius: float
    ball_mass: float
    positions: np.ndarray  # (16, 2); row 0 is the cue ball
    velocities: np.ndarray  # (16, 2)
    restitution_ball_ball: float
    restitution_ball_cushion: float
    friction: float  # same coefficient for every contact pair
    gravity: Vec2
    linear_drag: float  # 1/s: with no contacts, v(t) = v0 * exp(-linear_drag * t)
    dt: float
    steps: int
    rack_gap: float
    cue_y_offset: float

    @property
    def n_balls(self) -> int:
        """Number of dynamic balls, cue ball included."""
        return int(self.positions.shape[0])

    def describe(self) -> str:
        """One-line summary for benchmark tables."""
        length, width = self.play_area
        vx, vy = self.velocities[0]
        return (
            f"pool break: {self.n_balls} balls r={self.ball_radius} m on a {length} x {width} m "
            f"table, cue v=({vx:g}, {vy:g}) m/s, e={self.restitution_ball_ball}/"
            f"{self.restitution_ball_cushion}, drag {self.linear_drag}/s, dt=1/{1 / self.dt:.0f}, "
            f"{self.steps} steps"
        )


@dataclass(frozen=True, eq=False)
class Pyramid:
    """Box pyramid: unit boxes stacked in ``base`` rows on a wide static ground."""

    base: int
    box_size: float  # edge length of the square boxes
    box_mass: float
    friction: float
    restitution: float
    ground: StaticBox
    positions: np.ndarray  # (n_boxes, 2), row by row from the bottom; last row is the top box
    gravity: Vec2
    dt: float
    steps: int  # steps that are timed
    drift_steps: int  # total steps after which drift is measured

    @property
    def n_boxes(self) -> int:
        """Number of dynamic boxes."""
        return int(self.positions.shape[0])

    @property
    def top_index(self) -> int:
        """Index of the single box in the top row."""
        return self.n_boxes - 1

    def describe(self) -> str:
        """One-line summary for benchmark tables."""
        return (
            f"pyramid base {self.base}: {self.n_boxes} boxes {self.box_size} m / "
            f"{self.box_mass} kg, mu={self.friction}, e={self.restitution}, "
            f"dt=1/{1 / self.dt:.0f}, {self.steps} timed steps, drift after {self.drift_steps}"
        )


def pool_break(cue_y_offset: float = 0.0) -> PoolBreak:
    """Build the benchmark pool break (see the module docstring and inline notes).

    ``cue_y_offset`` (m) moves the cue ball sideways from the head spot (it still travels
    along +x), so the hit on the apex ball is off centre; see :func:`pool_cue_offsets`.
    """
    length, width = 2.54, 1.27
    half_l, half_w = length / 2, width / 2
    thick = 0.1
    # Cushions sit just outside the play area: their inner faces are the play-area edges.
    # The long cushions run past the corners so the short ones need not overlap them.
    cushions = (
        StaticBox((0.0, half_w + thick / 2), (half_l + thick, thick / 2)),
        StaticBox((0.0, -half_w - thick / 2), (half_l + thick, thick / 2)),
        StaticBox((half_l + thick / 2, 0.0), (thick / 2, half_w)),
        StaticBox((-half_l - thick / 2, 0.0), (thick / 2, half_w)),
    )

    r = 0.028575  # 2 1/4 inch ball
    gap = 1e-5  # keeps every racked pair 10 um apart, so nothing touches at t = 0
    pitch = 2 * r + gap  # centre distance of neighbouring racked balls
    row_dx = pitch * math.sqrt(3) / 2  # row spacing of a close-packed triangle
    foot_spot, head_spot = (length / 4, 0.0), (-length / 4, 0.0)
    # The default, a perfectly central hit (y offset 0.0), keeps the break deterministic and
    # mirror symmetric; engines may still break the symmetry through their contact ordering.
    cue_y_offset = float(cue_y_offset)

    positions = [(head_spot[0], head_spot[1] + cue_y_offset)]
    for row in range(5):  # apex on the foot spot, rows widening away from the cue ball
        for j in range(row + 1):
            positions.append((foot_spot[0] + row * row_dx, (j - row / 2) * pitch))
    velocities = np.zeros((len(positions), 2))
    velocities[0] = (8.0, 0.0)

    return PoolBreak(
        play_area=(length, width),
        cushion_thickness=thick,
        cushions=cushions,
        ball_radius=r,
        ball_mass=0.17,
        positions=_frozen(positions),
        velocities=_frozen(velocities),
        restitution_ball_ball=0.95,
        restitution_ball_cushion=0.75,
        # Top-down 2D has no ball-table contact, so nothing would ever turn spin into
        # travel; tangential friction at ball-ball / ball-cushion contacts would only
        # inject spin that the model cannot use. Zero everywhere, in every engine.
        friction=0.0,
        gravity=(0.0, 0.0),
        linear_drag=0.7,  # stand-in for rolling resistance
        dt=1 / 120,
        steps=1200,
        rack_gap=gap,
        cue_y_offset=cue_y_offset,
    )


def pool_cue_offsets(n_worlds: int, seed: int = 0) -> np.ndarray:
    """Cue-ball y offsets (m) for a batch of ``n_worlds`` pool breaks, one shot per world.

    World ``i`` starts its cue ball at ``y = offsets[i]`` instead of on the table's long
    axis (x and the 8 m/s velocity along +x unchanged): ``offsets`` is
    ``np.random.default_rng(seed).uniform(-0.01, 0.01, n_worlds)``, up to 1 cm either side,
    about a third of a ball radius, so every world hits the apex ball at its own angle and
    the racks scatter differently - the realistic reinforcement-learning case, where no two
    worlds of a batch play the same shot. World ``i`` is ``pool_break(offsets[i])``.
    """
    return np.random.default_rng(seed).uniform(-0.01, 0.01, n_worlds)


def pyramid(base: int) -> Pyramid:
    """Box2D's pyramid benchmark with ``base`` boxes in the bottom row."""
    if base < 1:
        raise ValueError(f"base must be >= 1, got {base}")
    size, spacing = 1.0, 1.05  # 0.05 m horizontal gap between neighbours, as in Box2D
    positions = []
    for row in range(base):
        n = base - row
        for i in range(n):
            # Bottoms of row r touch the tops of row r - 1 exactly; the ground top is y = 0.
            positions.append(((i - (n - 1) / 2) * spacing, size / 2 + row * size))
    return Pyramid(
        base=base,
        box_size=size,
        box_mass=1.0,
        friction=0.6,
        restitution=0.0,
        ground=StaticBox((0.0, -0.5), (100.0, 0.5)),  # 200 m x 1 m, top face at y = 0
        positions=_frozen(positions),
        gravity=(0.0, -9.81),
        dt=1 / 60,
        steps=300,
        drift_steps=600,
    )


LATERAL_CREEP_M = 0.25  # m: a box of a settled pyramid that moved further sideways "crept"


def large_pyramid() -> Pyramid:
    """Box2D v3's ``large_pyramid`` benchmark scene (its benchmark program's ``LargePyramid``).

    100 rows of 1 m boxes (1 kg: density 1), 5,050 in all, touching their neighbours
    side by side (no gap, unlike :func:`pyramid`) and stacked half a box over, row ``i``
    at ``y = i + 0.5`` with its boxes at ``x = (i + 1) / 2 + (j - i) - 50``; the ground a
    200 x 2 m box centred at (0, -1), top face at y = 0; friction 0.6 (Box2D's default),
    restitution 0, gravity (0, -10), dt = 1/60, and Box2D times 500 steps. ``steps`` and
    ``drift_steps`` are both 500: every step is timed and the settling is measured after
    the last (:func:`pyramid_settling`).
    """
    base, h = 100, 0.5
    positions = [
        ((i + 1) * h + 2 * (j - i) * h - h * base, (2 * i + 1) * h)
        for i in range(base)
        for j in range(i, base)
    ]
    return Pyramid(
        base=base,
        box_size=2 * h,
        box_mass=1.0,
        friction=0.6,
        restitution=0.0,
        ground=StaticBox((0.0, -1.0), (100.0, 1.0)),
        positions=_frozen(positions),
        gravity=(0.0, -10.0),
        dt=1 / 60,
        steps=500,
        drift_steps=500,
    )


def pyramid_settling(scene: Pyramid, positions: np.ndarray) -> dict:
    """How far a pyramid's boxes have moved from ``scene.positions`` to ``positions`` (n, 2).

    ``apex_sink_m``: how far the top box has come down; ``max_dx_m``: the largest sideways
    movement of any box; ``crept``: how many boxes moved more than ``LATERAL_CREEP_M``
    sideways; ``finite``. Every engine's result is measured by this one function.
    """
    dx = np.abs(positions[:, 0] - scene.positions[:, 0])
    top = scene.top_index
    return {
        "apex_sink_m": float(scene.positions[top, 1] - positions[top, 1]),
        "max_dx_m": float(dx.max()),
        "crept": int(np.count_nonzero(dx > LATERAL_CREEP_M)),
        "finite": bool(np.all(np.isfinite(positions))),
    }


@dataclass(frozen=True, eq=False)
class Rain:
    """Rain: ``count`` circles and boxes released at random over a wide static ground.

    Bodies alternate circle (even index), box (odd index). The ground is the half-plane
    y <= 0 (a plane in engines that have one); ``ground`` is a finite stand-in for it,
    wider than the drop zone by ``ground_margin`` on each side, for engines that need one.
    """

    count: int
    seed: int
    width: float  # W: bodies start at x in [-W/2, W/2]
    drop_heights: Vec2  # (lowest, highest) starting y of the centres
    circle_radius: float
    box_size: Vec2  # (width, height)
    mass: float  # every body
    friction: float  # every contact pair, ground included
    restitution: float
    is_circle: np.ndarray  # (count,) bool
    positions: np.ndarray  # (count, 2)
    angles: np.ndarray  # (count,); 0 for circles
    ground: StaticBox  # top face at y = 0
    ground_margin: float
    gravity: Vec2
    dt: float
    settle_steps: int  # untimed steps first: bodies are landing and piling, not in free fall
    steps: int  # then timed

    @property
    def n_circles(self) -> int:
        return int(np.count_nonzero(self.is_circle))

    def describe(self) -> str:
        """One-line summary for benchmark tables (``count`` left out: it varies)."""
        bw, bh = self.box_size
        lo, hi = self.drop_heights
        return (
            f"rain: circles r={self.circle_radius} m and boxes {bw} x {bh} m alternating, "
            f"{self.mass} kg, mu={self.friction}, e={self.restitution}, dropped from rest over a "
            f"strip {self.width / self.count:g} m wide per body, y in [{lo:g}, {hi:g}] m, onto "
            f"the ground y = 0; dt=1/{1 / self.dt:.0f}, {self.steps} timed steps after "
            f"{self.settle_steps} untimed"
        )


RAIN_WIDTH_PER_BODY = 0.6  # m of drop-zone width per body: the same density at every count


def rain(count: int, seed: int = 0) -> Rain:
    """``count`` bodies dropped at random onto the ground; the cost-against-size scene.

    The drop zone is ``W = 0.6 * count`` m wide and 5.5 m tall, so the density, the pile
    height and the contacts per body do not depend on ``count``; only their number does,
    and a step should cost about ``count`` times a constant (not ``count ** 2``).
    Positions and box angles come from ``np.random.default_rng(seed)``: x uniform in
    [-W/2, W/2], y in [0.5, 6.0] m, box angles in [0, 3) rad; everything starts at rest.
    Bodies may overlap at t = 0 (every engine starts from the same overlaps); none reaches
    into the ground.
    """
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    width = RAIN_WIDTH_PER_BODY * count
    lo, hi = 0.5, 6.0
    rng = np.random.default_rng(seed)
    x = rng.uniform(-width / 2, width / 2, count)
    y = rng.uniform(lo, hi, count)
    angles = rng.uniform(0.0, 3.0, count)
    is_circle = np.arange(count) % 2 == 0
    angles[is_circle] = 0.0
    margin = 50.0
    is_circle.setflags(write=False)
    return Rain(
        count=count,
        seed=seed,
        width=width,
        drop_heights=(lo, hi),
        circle_radius=0.2,
        box_size=(0.4, 0.3),
        mass=1.0,
        friction=0.6,
        restitution=0.0,
        is_circle=is_circle,
        positions=_frozen(np.column_stack([x, y])),
        angles=_frozen(angles),
        ground=StaticBox((0.0, -0.5), (width / 2 + margin, 0.5)),  # top face at y = 0
        ground_margin=margin,
        gravity=(0.0, -9.81),
        dt=1 / 60,
        settle_steps=60,
        steps=120,
    )


def validate(scene: PoolBreak | Pyramid | Rain) -> None:
    """Raise ValueError if the scene's bodies overlap or lie outside their bounds at t = 0.

    For :class:`Rain` only the ground is checked: its bodies may overlap each other.
    """
    if isinstance(scene, PoolBreak):
        p, r = scene.positions, scene.ball_radius
        half = np.array(scene.play_area) / 2
        outside = np.any(np.abs(p) + r > half, axis=1)
        if outside.any():
            raise ValueError(f"balls outside the play area: {np.flatnonzero(outside).tolist()}")
        dist = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
        np.fill_diagonal(dist, np.inf)
        pairs = np.argwhere(np.triu(dist < 2 * r)).tolist()
        if pairs:
            raise ValueError(f"overlapping balls: {pairs}")
    elif isinstance(scene, Pyramid):
        p, h = scene.positions, scene.box_size / 2
        if np.any(p[:, 1] - h < -1e-12):
            raise ValueError("a box reaches below the ground's top face (y = 0)")
        # Axis-aligned unit boxes overlap iff they overlap on both axes (touching is fine).
        # In blocks of rows: the large pyramid's full 5,050 x 5,050 table would take 400 MB.
        for start in range(0, len(p), 512):
            d = np.abs(p[start : start + 512, None, :] - p[None, :, :])
            hit = np.all(d < 2 * h - 1e-12, axis=-1)
            hit[np.arange(len(hit)), start + np.arange(len(hit))] = False  # a box and itself
            if hit.any():
                raise ValueError("overlapping boxes in the pyramid")
    elif isinstance(scene, Rain):
        hw, hh = scene.box_size[0] / 2, scene.box_size[1] / 2
        c, s = np.abs(np.cos(scene.angles)), np.abs(np.sin(scene.angles))
        reach = np.where(scene.is_circle, scene.circle_radius, hw * s + hh * c)  # below centre
        if np.any(scene.positions[:, 1] - reach <= 0.0):
            raise ValueError("a rain body starts in the ground")
        if np.any(np.abs(scene.positions[:, 0]) > scene.width / 2):
            raise ValueError("a rain body starts outside the drop zone")
    else:
        raise TypeError(f"unknown scene type {type(scene).__name__}")
