"""Engine-neutral benchmark scene descriptions shared by impulse2d and its peers.

Every scene is plain data in SI units (metres, kilograms, seconds); this module
imports no physics engine, so each engine's adapter builds its own world from the
same numbers. Two scenes are defined:

* :func:`pool_break` - the 16-ball break on a 2.54 x 1.27 m table (contact-heavy
  burst, then many light contacts; used for the many-worlds throughput figure).
* :func:`pyramid` - the Box2D-style box pyramid on a static ground (stacking
  stability and per-step cost of a large contact graph).

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


def pool_break() -> PoolBreak:
    """Build the benchmark pool break (see the module docstring and inline notes)."""
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
    # A perfectly central hit (y offset 0.0) keeps the break deterministic and mirror
    # symmetric; engines may still break the symmetry through their contact ordering.
    cue_y_offset = 0.0

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


def validate(scene: PoolBreak | Pyramid) -> None:
    """Raise ValueError if the scene's bodies overlap or lie outside their bounds at t = 0."""
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
        d = np.abs(p[:, None, :] - p[None, :, :])
        hit = np.all(d < 2 * h - 1e-12, axis=-1)
        np.fill_diagonal(hit, False)
        if hit.any():
            raise ValueError("overlapping boxes in the pyramid")
    else:
        raise TypeError(f"unknown scene type {type(scene).__name__}")
