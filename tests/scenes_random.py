"""Random scenes for the property tests in ``test_random_scenes.py``.

A ``Scene`` is plain data (frozen dataclasses), drawn by the hypothesis strategy
``scenes(...)`` and turned into a ``World`` by ``build``. ``code(scene)`` writes the same
scene as a stand-alone snippet of ``impulse2d`` calls: a failing example is reported
with it (``hypothesis.note``), so it can be pasted into a bug report as it is.

Ranges: circle radius 0.05-1 m, box sides 0.05-2 m, masses 0.1-100 kg with at most a
factor 100 between the bodies of a scene, speeds up to 20 m/s, angular velocities up to
10 rad/s, restitution and friction 0-1. Centres start in a square around the origin (half
side 1 + 1.5 sqrt(bodies drawn) m), the bodies overlapping a little (``overlap``) or not
at all. Planes are put ``gap`` (>= 1 mm) beyond the farthest body along their normal, so
no body starts touching a plane and every centre starts in front of every plane.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from hypothesis import strategies as st

import impulse2d as p2
from impulse2d.core.state import CONTACT_COUNT
from impulse2d.envelope import ACCELERATION

GRAVITY = (0.0, -9.81)
# The wide scenes: a length scale from 3 mm to 20 m (sizes within 10x of it), masses
# anywhere in 1 mg - 1000 t with up to 6 decades between the bodies of a scene, speeds up
# to 200 m/s, dt from 0.1 ms to 0.1 s.
WIDE = {
    "scale": (3e-3, 20.0),
    "log_mass": (-6.0, 6.0),
    "mass_decades": 6.0,
    "max_speed": (1.0, 200.0),
    "dt": (1e-4, 0.1),
}
MOTIONS = ("dynamic", "fixed", "kinematic")


@dataclass(frozen=True)
class BodySpec:
    kind: str  # "circle" (width = radius), "box", "triangle" (base x height), "capsule"
    motion: str  # "dynamic", "fixed" or "kinematic"
    x: float
    y: float
    width: float
    height: float
    mass: float
    vx: float
    vy: float
    angle: float
    spin: float
    restitution: float
    friction: float

    @property
    def bound(self) -> float:
        """Radius of the circle around the body's centre that holds it."""
        if self.kind == "triangle":
            return float(np.hypot(*triangle(self.width, self.height).T).max())
        if self.kind == "capsule":
            return 0.5 * self.width + 0.5 * self.height
        return self.width if self.kind == "circle" else 0.5 * math.hypot(self.width, self.height)


def triangle(base: float, height: float) -> np.ndarray:
    """An isosceles triangle of ``base`` and ``height`` with its centroid at the origin
    (a "triangle" body; a "capsule" is ``width`` long with radius ``height / 2``)."""
    return np.array([(-0.5 * base, -height / 3), (0.5 * base, -height / 3), (0.0, 2 * height / 3)])


@dataclass(frozen=True)
class PlaneSpec:
    direction: float  # angle of the normal (rad)
    gap: float  # m between the plane and the farthest body behind it at the start
    restitution: float
    friction: float


@dataclass(frozen=True)
class SpringSpec:
    a: int  # indices into Scene.bodies, both dynamic
    b: int
    stiffness: float  # fraction of the stability limit h^2 k w < 2 (half of what is allowed)
    damping: float  # fraction of 2 h c w < 2
    rest_length: float
    anchor_a: tuple[float, float]  # fractions of the half sizes, body-local
    anchor_b: tuple[float, float]


@dataclass(frozen=True)
class Scene:
    bodies: tuple[BodySpec, ...]
    planes: tuple[PlaneSpec, ...]
    spring: SpringSpec | None
    gravity: bool
    dt: float
    substeps: int


# -- derived values: what build() adds ------------------------------------------------------------
def plane_placements(scene: Scene) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """(normal, point) of each plane: the plane lies ``gap`` beyond the body reaching
    farthest against its normal (its bounding circle), so every body is in front."""
    out = []
    for plane in scene.planes:
        n = (math.cos(plane.direction), math.sin(plane.direction))
        reach = min((b.x * n[0] + b.y * n[1] - b.bound for b in scene.bodies), default=0.0)
        d = reach - plane.gap
        out.append((n, (d * n[0], d * n[1])))
    return out


def _half(body: BodySpec) -> tuple[float, float]:
    return (body.width, body.width) if body.kind == "circle" else (body.width / 2, body.height / 2)


def _moment(body: BodySpec) -> float:
    if body.kind == "circle":
        return 0.5 * body.mass * body.width**2
    if body.kind in ("triangle", "capsule"):
        return body_object(body).moment
    return body.mass * (body.width**2 + body.height**2) / 12.0


def spring_values(scene: Scene) -> dict:
    """Keyword arguments of the scene's Spring: stiffness and damping as the drawn
    fractions of the stability limit ``h^2 k w + 2 h c w < 4`` at the substep ``h``,
    with ``w`` an upper bound of the inverse effective mass along the spring; each then
    capped so its pull stays inside the envelope's acceleration (``World.step`` refuses
    a spring that pulls its anchors apart faster, ``(k |L - L0| + c |v|) w``): a quarter
    of it for a stretch up to the start's plus the rest length plus 1 m, and for the
    damping a quarter at twice the fastest body's speed plus 10 m/s."""
    s = scene.spring
    a, b = scene.bodies[s.a], scene.bodies[s.b]
    ha, hb = _half(a), _half(b)
    ra = (s.anchor_a[0] * ha[0], s.anchor_a[1] * ha[1])
    rb = (s.anchor_b[0] * hb[0], s.anchor_b[1] * hb[1])
    w = 1 / a.mass + 1 / b.mass + math.hypot(*ra) ** 2 / _moment(a)
    w += math.hypot(*rb) ** 2 / _moment(b)
    h = scene.dt / scene.substeps
    start = math.hypot(b.x - a.x, b.y - a.y) + math.hypot(*ra) + math.hypot(*rb)
    stretch = abs(start - s.rest_length) + s.rest_length + 1.0
    fastest = max(math.hypot(body.vx, body.vy) for body in scene.bodies)
    pull = 0.25 * ACCELERATION / w
    return {
        "rest_length": s.rest_length,
        "stiffness": min(s.stiffness * 2.0 / (h * h * w), pull / stretch),
        "damping": min(s.damping / (h * w), pull / (2.0 * fastest + 10.0)),
        "anchor1": ra,
        "anchor2": rb,
    }


# -- building -------------------------------------------------------------------------------------
def body_object(body: BodySpec) -> p2.Body:
    moving = body.motion != "fixed"
    common = {
        "position": (body.x, body.y),
        "velocity": (body.vx, body.vy) if moving else (0.0, 0.0),
        "angle": body.angle,
        "angular_velocity": body.spin if moving else 0.0,
        "mass": body.mass,
        "restitution": body.restitution,
        "friction": body.friction,
        "fixed": body.motion == "fixed",
        "kinematic": body.motion == "kinematic",
    }
    if body.kind == "circle":
        return p2.Circle(radius=body.width, **common)
    if body.kind == "triangle":
        return p2.Polygon(vertices=triangle(body.width, body.height), **common)
    if body.kind == "capsule":
        return p2.Capsule(length=body.width, radius=0.5 * body.height, **common)
    return p2.Box(width=body.width, height=body.height, **common)


def build(scene: Scene, **world_kwargs) -> p2.World:
    """The scene in a new ``World(**world_kwargs)``: bodies (slots in order), planes, spring."""
    world = p2.World(
        gravity=GRAVITY if scene.gravity else (0.0, 0.0), substeps=scene.substeps, **world_kwargs
    )
    objects = [world.add(body_object(body)) for body in scene.bodies]
    for spec, (normal, point) in zip(scene.planes, plane_placements(scene), strict=True):
        world.add(
            p2.Plane(
                normal=normal, point=point, restitution=spec.restitution, friction=spec.friction
            )
        )
    if scene.spring is not None:
        a, b = objects[scene.spring.a], objects[scene.spring.b]
        world.add(p2.Spring(a, b, **spring_values(scene)))
    return world


def code(scene: Scene) -> str:
    """The scene as a stand-alone snippet (``world`` built as ``build`` does)."""
    g = GRAVITY if scene.gravity else (0.0, 0.0)
    lines = [
        "import impulse2d as p2",
        f"world = p2.World(gravity={g!r}, substeps={scene.substeps})",
        f"dt = {scene.dt!r}",
    ]
    for i, b in enumerate(scene.bodies):
        moving = b.motion != "fixed"
        cls, size = {
            "circle": ("Circle", f"radius={b.width!r}"),
            "box": ("Box", f"width={b.width!r}, height={b.height!r}"),
            "triangle": ("Polygon", f"vertices={triangle(b.width, b.height).tolist()!r}"),
            "capsule": ("Capsule", f"length={b.width!r}, radius={0.5 * b.height!r}"),
        }[b.kind]
        motion = {"fixed": ", fixed=True", "kinematic": ", kinematic=True"}.get(b.motion, "")
        speed = f"velocity=({b.vx!r}, {b.vy!r}), angular_velocity={b.spin!r}, " if moving else ""
        lines.append(
            f"b{i} = world.add(p2.{cls}("
            f"position=({b.x!r}, {b.y!r}), {size}, mass={b.mass!r}, angle={b.angle!r}, "
            f"{speed}restitution={b.restitution!r}, friction={b.friction!r}{motion}))"
        )
    for spec, (normal, point) in zip(scene.planes, plane_placements(scene), strict=True):
        lines.append(
            f"world.add(p2.Plane(normal={normal!r}, point={point!r}, "
            f"restitution={spec.restitution!r}, friction={spec.friction!r}))"
        )
    if scene.spring is not None:
        values = ", ".join(f"{k}={v!r}" for k, v in spring_values(scene).items())
        lines.append(f"world.add(p2.Spring(b{scene.spring.a}, b{scene.spring.b}, {values}))")
    return "\n".join(lines)


# -- strategies -----------------------------------------------------------------------------------
def unit(lo: float = 0.0, hi: float = 1.0) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    """A float whose log10 is uniform in [log10 lo, log10 hi]."""
    return unit(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)


def moderate_sizes(kind: str) -> tuple[st.SearchStrategy[float], st.SearchStrategy[float]]:
    """Width (a circle's radius) and height: 0.05-1 m radii, 0.05-2 m box sides."""
    return unit(0.05, 1.0 if kind == "circle" else 2.0), unit(0.05, 2.0)


def sizes_around(scale: float):
    """Sizes within a factor 10 of ``scale`` (m) either way, log-uniform."""

    def sizes(kind: str) -> tuple[st.SearchStrategy[float], st.SearchStrategy[float]]:
        side = log_uniform(max(scale / 10.0, 1e-3), scale * 10.0)
        return side, side

    return sizes


@st.composite
def body_specs(
    draw, motions, max_speed, restitution, friction, masses, sizes, room, kinds=("circle", "box")
) -> BodySpec:
    """One body; ``masses``: the range of log10 mass (kg); ``sizes(kind)``: strategies of
    width (a circle's radius) and height; ``room``: half side of the square of centres."""
    kind = draw(st.sampled_from(kinds))
    motion = draw(st.sampled_from(motions))
    speed, heading = draw(unit(0.0, max_speed)), draw(unit(-math.pi, math.pi))
    width, height = sizes(kind)
    return BodySpec(
        kind=kind,
        motion=motion,
        x=draw(unit(-room, room)),
        y=draw(unit(-room, room)),
        width=draw(width),
        height=draw(height),
        mass=10.0 ** draw(unit(*masses)),
        vx=speed * math.cos(heading),
        vy=speed * math.sin(heading),
        angle=draw(unit(-math.pi, math.pi)),
        spin=draw(unit(-10.0, 10.0)),
        restitution=draw(restitution),
        friction=draw(friction),
    )


def keep_apart(bodies: list[BodySpec], overlap: float) -> tuple[BodySpec, ...]:
    """Drop every body whose bounding circle overlaps one kept before it by more than
    ``overlap`` times the sum of the two radii (0: no overlap of the bounding circles)."""
    kept: list[BodySpec] = []
    for body in bodies:
        if all(
            math.hypot(body.x - o.x, body.y - o.y) > (1.0 - overlap) * (body.bound + o.bound)
            for o in kept
        ):
            kept.append(body)
    return tuple(kept)


@st.composite
def plane_specs(draw, min_planes, max_planes, bin, restitution, friction) -> tuple:
    """0-3 planes with random normals (often a floor, wall or ceiling); ``bin``: exactly a
    floor and two walls."""
    if bin:
        directions = (math.pi / 2, 0.0, math.pi)
    else:
        direction = st.one_of(
            st.sampled_from([math.pi / 2, 0.0, math.pi, -math.pi / 2]), unit(-math.pi, math.pi)
        )
        directions = draw(st.lists(direction, min_size=min_planes, max_size=max_planes))
    return tuple(
        PlaneSpec(d, draw(unit(0.001, 3.0)), draw(restitution), draw(friction)) for d in directions
    )


@st.composite
def spring_specs(draw, bodies: tuple[BodySpec, ...]) -> SpringSpec | None:
    """Maybe a spring between two dynamic bodies (None if there are fewer than two)."""
    dynamic = [i for i, b in enumerate(bodies) if b.motion == "dynamic"]
    if len(dynamic) < 2 or not draw(st.booleans()):
        return None
    a, b = draw(st.permutations(dynamic))[:2]
    anchor = st.tuples(unit(-1.0, 1.0), unit(-1.0, 1.0))
    stiffness, damping, rest = draw(unit(0.0, 0.5)), draw(unit(0.0, 0.5)), draw(unit(0.0, 3.0))
    return SpringSpec(a, b, stiffness, damping, rest, draw(anchor), draw(anchor))


@st.composite
def scenes(
    draw,
    *,
    max_bodies: int = 12,
    motions: tuple[str, ...] = MOTIONS,
    min_planes: int = 0,
    max_planes: int = 3,
    bin: bool = False,
    springs: bool = True,
    gravity: bool | None = None,
    max_speed: float = 20.0,
    restitution: st.SearchStrategy[float] | None = None,
    friction: st.SearchStrategy[float] | None = None,
    overlap: float = 0.2,
    wide: bool = False,
    kinds: tuple[str, ...] = ("circle", "box"),
) -> Scene:
    """A random scene (module docstring); keywords narrow it for one property.

    ``motions`` lists the motion types drawn (dynamic is weighted up: drawn from
    ``("dynamic", "dynamic", *motions)``); ``gravity=None`` draws it; ``bin``: the planes
    are a floor and two walls; ``overlap`` as in ``keep_apart``. ``wide`` draws from the
    whole envelope instead (``WIDE``)."""
    restitution = unit() if restitution is None else restitution
    friction = unit() if friction is None else friction
    count = draw(st.integers(1, max_bodies))
    if wide:
        scale = draw(log_uniform(*WIDE["scale"]))
        span = draw(unit(0.0, WIDE["mass_decades"]))
        low = draw(unit(WIDE["log_mass"][0], WIDE["log_mass"][1] - span))
        masses, sizes = (low, low + span), sizes_around(scale)
        max_speed = draw(log_uniform(*WIDE["max_speed"]))
        room = scale * (1.0 + 1.5 * math.sqrt(count))
    else:
        low = draw(unit(-1.0, 0.0))  # masses in [10^low, 10^(low + 2)] kg: ratio <= 100
        masses, sizes, room = (low, low + 2.0), moderate_sizes, 1.0 + 1.5 * math.sqrt(count)
    body = body_specs(
        ("dynamic", "dynamic", *motions) if "dynamic" in motions else motions,
        max_speed,
        restitution,
        friction,
        masses,
        sizes,
        room,  # half side of the square the centres start in
        kinds,
    )
    bodies = keep_apart(draw(st.lists(body, min_size=count, max_size=count)), overlap)
    return Scene(
        bodies=bodies,
        planes=draw(plane_specs(min_planes, max_planes, bin, restitution, friction)),
        spring=draw(spring_specs(bodies)) if springs else None,
        gravity=draw(st.booleans()) if gravity is None else gravity,
        dt=draw(log_uniform(*WIDE["dt"]) if wide else unit(1.0 / 240.0, 1.0 / 30.0)),
        substeps=draw(st.integers(1, 8)),
    )


# -- readouts -------------------------------------------------------------------------------------
def world_arrays(world: p2.World, k: int = 0) -> dict[str, bytes]:
    """The raw bytes of every state array of world ``k`` (contact rows up to its count)."""
    s = world.state
    count = int(s.world_i[k, CONTACT_COUNT])
    return {
        "body": s.body[k].tobytes(),
        "body_i": s.body_i[k].tobytes(),
        "spring": s.spring[k].tobytes(),
        "world_i": s.world_i[k].tobytes(),
        "time": s.time[k].tobytes(),
        "contact": s.contact[k, :count].tobytes(),
        "contact_i": s.contact_i[k, :count].tobytes(),
    }


def poses(world: p2.World) -> np.ndarray:
    """Position, velocity, angle and angular velocity of every circle and box through the
    public API: shape (bodies, 6), or (bodies, batch, 6) in a batch."""
    rows = []
    for body in world.bodies:
        if isinstance(body, p2.Plane):
            continue
        parts = [body.position, body.velocity, body.angle, body.angular_velocity]
        parts = [np.asarray(p, dtype=float).reshape(world.batch_size, -1) for p in parts]
        rows.append(np.concatenate(parts, axis=1))
    return np.array(rows) if world.batch_size > 1 else np.array(rows)[:, 0]
