"""impulse2d: a 2D rigid-body physics engine in Python, compiled by numba, batched at its core.

    import impulse2d as p2
    world = p2.World(gravity=(0.0, -9.81))
    ball = world.add(p2.Circle(position=(0, 5), radius=0.5, restitution=0.5))
    world.add(p2.Plane(normal=(0, 1), point=(0, 0)))
    for _ in range(120):
        world.step(1 / 60)
    print(ball.position, world.energy().total)

A ``World(batch_size=1024)`` (or ``world.replicate(1024)``) steps 1,024 copies of a scene
in one set of arrays. SI units throughout.

The first step after installing or updating compiles the engine's kernels (about 25 s
on two cores; numba caches them, and later runs load them in under half a second;
``python -m impulse2d.compile`` fills the cache ahead). It says so on stderr while it
does; ``IMPULSE2D_QUIET=1`` silences it.
"""

from . import _compile_notice
from .envelope import EnvelopeError
from .joints import DistanceJoint, MouseJoint, PrismaticJoint, RevoluteJoint, WeldJoint
from .polygons import Capsule, Polygon, Segment
from .readouts import ContactPoints, Energy
from .sensors import Sensor
from .shapes import Body, Box, Circle, Plane
from .springs import Spring
from .world import Snapshot, World

__all__ = [
    "Body",
    "Box",
    "Capsule",
    "Circle",
    "ContactPoints",
    "DistanceJoint",
    "Energy",
    "EnvelopeError",
    "MouseJoint",
    "Plane",
    "Polygon",
    "PrismaticJoint",
    "RevoluteJoint",
    "Segment",
    "Sensor",
    "Snapshot",
    "Spring",
    "WeldJoint",
    "World",
]
__version__ = "0.3.0"

_compile_notice.install()


def _register_environments() -> None:
    """Make ``gym.make("Pool2D-v0")`` work after ``import impulse2d``, if gymnasium is
    installed (the engine itself needs only numpy and numba)."""
    try:
        import gymnasium  # noqa: F401
    except ImportError:
        return
    from .envs import register

    register()


_register_environments()
