"""Demo scenes of impulse2d, one per milestone of the tutorial plus its extras.

    from impulse2d.apps import demo
    scene = demo.get("m08-box-plane")
    world = scene.build()
    for _ in range(scene.steps):
        scene.step(world)          # runs the scene's control (if any), then world.step(dt)

``python -m impulse2d.apps.demo --list`` prints the scenes; ``python -m impulse2d.apps.demo NAME``
renders one to a GIF (see ``impulse2d.apps.demo.__main__``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import impulse2d as p2

from . import scenes as _s
from . import scenes_joints as _j


@dataclass(frozen=True)
class Scene:
    """A demo scene: how to build it, how long to run it, and what the camera shows.

    ``build`` returns a fresh world each call. ``dt`` is the time step (s), ``seconds`` how
    long the scene is meant to run. ``view`` is the world rectangle ``(xmin, ymin, xmax,
    ymax)`` (m) the camera should show, or None to fit the bodies at the first frame.
    ``control``, if given, is called with the world before every step (the tutorial's
    per-frame input: a scene that pushes a body with ``apply_force`` over several steps).
    """

    name: str
    description: str
    build: Callable[[], p2.World]
    dt: float = 1 / 60
    seconds: float = 5.0
    view: tuple[float, float, float, float] | None = None
    control: Callable[[p2.World], None] | None = None

    @property
    def steps(self) -> int:
        """Number of steps of ``dt`` in ``seconds``."""
        return round(self.seconds / self.dt)

    def step(self, world: p2.World) -> None:
        """Advance ``world`` one step of ``dt``, running the scene's control first."""
        if self.control is not None:
            self.control(world)
        world.step(self.dt)


_ALL = (
    Scene(
        "m01-constant-velocity",
        "three circles in zero gravity at 1, 1.5 and 2 m/s: x = x0 + v t",
        _s.constant_velocity,
        seconds=5.0,
        view=(-1.0, -3.5, 11.0, 3.5),
    ),
    Scene(
        "m02-gravity",
        "balls thrown up at 8 m/s, one also sideways: both at y = v t - g t^2/2, one on a parabola",
        _s.gravity,
        seconds=3.0,
        view=(-1.0, -1.6, 9.0, 4.0),
    ),
    Scene(
        "m03-plane",
        "planes at 35, 0 and 20 degrees: a ball rolls down and across, boxes rest held by friction",
        _s.planes,
        seconds=8.0,
        view=(-8.0, -1.0, 10.0, 5.0),
    ),
    Scene(
        "m04-all-pairs",
        "ten elastic circles and boxes in a walled arena: every pair tested, they move like a gas",
        _s.all_pairs,
        seconds=8.0,
        view=(-4.2, -2.4, 4.2, 2.4),
    ),
    Scene(
        "m05-circle-plane",
        "balls of restitution 0.2, 0.5, 0.8 dropped from 3 m: each bounce rises e^2 of the last",
        _s.circle_plane,
        seconds=5.0,
        view=(-4.0, -0.5, 4.0, 4.0),
    ),
    Scene(
        "m06-circle-and-box",
        "twelve circles and boxes of random size and angle fall onto a plane and pile up",
        _s.circle_and_box,
        seconds=5.0,
        view=(-6.0, -0.5, 6.0, 7.0),
    ),
    Scene(
        "m07-rotation",
        "boxes spin at constant angular velocity; an off-centre apply_force pushes and turns one",
        _s.rotation,
        seconds=5.0,
        view=(-5.5, -3.0, 5.5, 3.2),
        control=_s.push_rotation,
    ),
    Scene(
        "m08-box-plane",
        "boxes dropped at an angle land on a corner, rotate and settle flat",
        _s.box_plane,
        seconds=4.0,
        view=(-6.5, -0.5, 6.5, 4.0),
    ),
    Scene(
        "m09-circle-circle",
        "billiards: equal balls swap speeds, heavy hits light, off-centre ones part at 90 degrees",
        _s.circle_circle,
        seconds=4.0,
        view=(-4.0, -5.0, 8.0, 3.5),
    ),
    Scene(
        "m10-circle-box",
        "balls hit free boxes: on the centre line the box just slides, off centre it also spins",
        _s.circle_box,
        seconds=4.0,
        view=(-4.0, -3.5, 5.0, 3.5),
    ),
    Scene(
        "m11-box-box",
        "a column of boxes stands; a leaning tower, each box 0.3 m further out, topples",
        _s.box_box,
        seconds=5.0,
        view=(-6.0, -0.5, 8.0, 6.0),
    ),
    Scene(
        "m12-drag-friction",
        "boxes slide to a stop after v^2/(2 mu g), mu 0.1, 0.3, 0.6; balls with drag fall slower",
        _s.drag_friction,
        seconds=5.0,
        view=(-1.5, -1.5, 15.0, 7.0),
    ),
    Scene(
        "springs",
        "a chain of masses on springs swings like a rope; damped vs undamped oscillators",
        _s.springs,
        dt=1 / 120,
        seconds=6.0,
        view=(-5.5, -0.5, 6.0, 5.0),
    ),
    Scene(
        "sleeping",
        "a stack falls asleep (dimmed by --debug sleeping); a ball dropping onto it wakes it",
        _s.sleeping,
        seconds=6.0,
        view=(-11.0, -0.5, 3.5, 7.5),
    ),
    Scene(
        "contact-forces",
        "30 circles spawned overlapping at one spot are pushed apart and settle into a heap",
        _s.contact_forces,
        seconds=5.0,
        view=(-3.5, -0.5, 3.5, 4.5),
    ),
    Scene(
        "energy",
        "a box swinging on a spring, an elastic ball: energy changes kind, the total stays fixed",
        _s.energy,
        dt=1 / 120,
        seconds=6.0,
        view=(-4.5, -0.5, 4.5, 5.5),
    ),
    Scene(
        "newtons-cradle",
        "five hanging elastic balls: the end one swings in, the far one out, the middle ones stay",
        _s.newtons_cradle,
        dt=1 / 240,
        seconds=6.0,
        view=(-0.9, -0.3, 1.75, 1.2),
    ),
    Scene(
        "pyramid",
        "the 10-row, 55-box pyramid stands still and falls asleep",
        _s.pyramid,
        seconds=4.0,
        view=(-7.5, -0.5, 7.5, 10.5),
    ),
    Scene(
        "pool-break",
        "the 16-ball pool break, top down: the rack scatters, balls bounce off cushions, slow down",
        _s.pool_break,
        dt=1 / 120,
        seconds=6.0,
        view=(-1.42, -0.8, 1.42, 0.8),
    ),
    Scene(
        "slingshot",
        "Angry Birds: a heavy ball flung at a two-storey tower brings it down, pig and all",
        _s.slingshot,
        seconds=5.0,
        view=(-1.0, -0.5, 12.0, 6.5),
    ),
    Scene(
        "polygon-pile",
        "forty polygons and capsules poured into a V of segments tumble and come to rest",
        _j.polygon_pile,
        seconds=8.0,
        view=(-7.0, -0.5, 7.0, 9.0),
    ),
    Scene(
        "pendulum-chain",
        "twelve capsules pinned end to end fall from level, whip and swing on a hook",
        _j.pendulum_chain,
        seconds=6.0,
        view=(-6.5, -0.5, 6.5, 7.0),
    ),
    Scene(
        "ragdolls",
        "three ragdolls tumble down a flight of stairs, their joints bending within limits",
        _j.ragdolls,
        seconds=6.0,
        view=(-1.0, -0.5, 12.0, 9.5),
    ),
    Scene(
        "car-hill",
        "a car on two motor-driven wheels climbs a hill of segments and rolls down the far side",
        _j.car_on_a_hill,
        seconds=8.0,
        view=(-8.0, -1.0, 24.0, 8.0),
    ),
)

SCENES: dict[str, Scene] = {scene.name: scene for scene in _ALL}
"""Every demo scene by name, in tutorial order."""


def get(name: str) -> Scene:
    """The scene called ``name``; a ValueError naming it and listing the valid names if none."""
    try:
        return SCENES[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown scene {name!r}; valid names: {', '.join(SCENES)}") from None


__all__ = ["SCENES", "Scene", "get"]
