"""``Polygon``, ``Capsule`` and ``Segment`` as users meet them: how vertices are taken
(centred on the centre of mass, order kept, a clockwise list reversed), ``placed``,
mass properties, point queries, refusals by name, removal and re-adding, batches equal
to single worlds, snapshots, and drawing (the renderer and the compiled frames)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from impulse2d import geometry
from impulse2d.pixels import Frames
from impulse2d.polygons import capsule_unit_moment
from impulse2d.render import Renderer

TRIANGLE = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]


def test_vertices_are_centred_on_the_centre_of_mass_in_their_order():
    tri = p2.Polygon(vertices=TRIANGLE, position=(2.0, 3.0))
    np.testing.assert_allclose(tri.vertices, np.array(TRIANGLE) - 1.0 / 3.0, atol=1e-15)
    world = p2.World()
    world.add(tri)
    offset = np.array([2.0 - 1.0 / 3.0, 3.0 - 1.0 / 3.0])
    np.testing.assert_allclose(tri.world_vertices(), np.array(TRIANGLE) + offset)


def test_a_clockwise_list_is_reversed_keeping_its_first_vertex():
    clockwise = [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0)]
    tri = p2.Polygon(vertices=clockwise)
    first = np.array(clockwise[0]) - 1.0 / 3.0
    np.testing.assert_allclose(tri.vertices[0], first, atol=1e-15)
    np.testing.assert_allclose(tri.vertices[1], np.array((1.0, 0.0)) - 1.0 / 3.0, atol=1e-15)


def test_placed_puts_the_outline_on_the_given_world_points():
    points = np.array([(3.0, 1.0), (4.0, 1.2), (3.6, 2.0), (2.9, 1.8)])
    world = p2.World()
    quad = world.add(p2.Polygon.placed(points, angle=0.7))
    np.testing.assert_allclose(quad.world_vertices(), points, atol=1e-12)
    assert quad.angle == pytest.approx(0.7)
    np.testing.assert_allclose(quad.position, geometry.mass(points).centroid, atol=1e-12)


def test_mass_properties_follow_the_geometry():
    """A polygon's moment is its mass times ``geometry.mass``'s second moment over its
    area (rounded or not); a capsule's the closed form, checked on a fine grid here."""
    rounded = p2.Polygon(vertices=TRIANGLE, radius=0.2, mass=3.0)
    props = geometry.mass(TRIANGLE, 0.2)
    assert rounded.moment == pytest.approx(3.0 * props.moment / props.area, rel=1e-12)
    length, radius = 1.4, 0.3
    xs = np.linspace(-1.0, 1.0, 1601)
    x, y = np.meshgrid(xs, xs)
    inside = np.hypot(np.clip(np.abs(x) - 0.5 * length, 0.0, None), y) <= radius
    grid = float(((x**2 + y**2) * inside).sum() / inside.sum())
    assert capsule_unit_moment(length, radius) == pytest.approx(grid, rel=2e-3)
    assert p2.Capsule(length=length, radius=radius, mass=2.0).moment == pytest.approx(
        2.0 * capsule_unit_moment(length, radius), rel=1e-12
    )


def test_point_queries_see_the_outlines():
    world = p2.World(gravity=(0.0, 0.0))
    tri = world.add(p2.Polygon.placed([(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)]))
    cap = world.add(p2.Capsule(length=1.0, radius=0.25, position=(5.0, 0.0), angle=math.pi / 2))
    ramp = world.add(p2.Segment(start=(-3.0, 0.0), end=(-1.0, 0.0), radius=0.05))
    assert tri.is_inside((0.5, 0.5)) and not tri.is_inside((1.2, 1.2))
    assert cap.is_inside((5.0, 0.7)) and not cap.is_inside((5.3, 0.0))
    assert ramp.is_inside((-2.0, 0.04)) and not ramp.is_inside((-2.0, 0.06))
    assert world.query_point((0.5, 0.5)) == [tri]
    assert world.query_point((5.0, -0.7)) == [cap]
    assert world.query_point((-2.0, 0.0)) == [ramp]
    assert world.query_point((1.2, 1.2)) == []


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: p2.Polygon(vertices=[(0, 0), (1, 0), (1, 1), (0.8, 0.2)]), "convex"),
        (lambda: p2.Polygon(vertices=[(0, 0), (1, 0)]), "vertices must number 3 to 8"),
        (lambda: p2.Polygon(vertices=TRIANGLE, radius=-1.0), "radius must be >= 0, got -1.0"),
        (lambda: p2.Polygon(vertices=[(0, 0), (1, 0), (0.5, 1e-4)]), "thick"),
        (lambda: p2.Capsule(length=0.0), "length must be in"),
        (lambda: p2.Capsule(radius=0.0), "radius must be in"),
        (lambda: p2.Segment(start=(0, 0), end=(0, 0)), "end must be at least"),
        (lambda: p2.Segment(start=(0, 0), end=(1, 0), fixed=False), "Segment is placed"),
        (lambda: p2.Polygon.placed(TRIANGLE, position=(1, 1)), "leave position out"),
    ],
)
def test_bad_outlines_are_refused_by_name(make, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        make()


def test_an_outline_cannot_be_changed_after_it_is_made():
    tri = p2.Polygon(vertices=TRIANGLE)
    with pytest.raises(AttributeError):
        tri.vertices = [(0, 0), (2, 0), (0, 2)]
    with pytest.raises(AttributeError):
        tri.radius = 0.1
    before = tri.vertices
    tri.vertices[0] = (5.0, 5.0)  # a copy: the polygon keeps its own
    np.testing.assert_array_equal(tri.vertices, before)


def test_a_removed_polygon_comes_back_the_same_and_its_slot_serves_a_circle():
    world = p2.World()
    world.add(p2.Plane())
    tri = world.add(p2.Polygon(vertices=TRIANGLE, position=(0.0, 2.0), mass=2.0))
    world.step(1 / 60, 10)
    saved = (np.array(tri.position), tri.moment, tri.vertices)
    world.remove(tri)
    ball = world.add(p2.Circle(radius=0.3, position=(3.0, 1.0)))
    world.step(1 / 60, 60)
    assert float(ball.position[1]) == pytest.approx(0.3, abs=1e-3)
    world.add(tri)
    np.testing.assert_array_equal(tri.position, saved[0])
    assert tri.moment == saved[1]
    np.testing.assert_array_equal(tri.vertices, saved[2])


def _scene(batch_size: int = 1) -> p2.World:
    world = p2.World(batch_size=batch_size)
    world.add(p2.Plane())
    world.add(p2.Segment(start=(-4.0, 2.0), end=(-1.0, 1.0)))
    world.add(p2.Polygon(vertices=TRIANGLE, position=(-2.5, 3.0), angular_velocity=1.0))
    world.add(p2.Capsule(length=0.8, radius=0.2, position=(0.5, 1.0), angle=0.4))
    world.add(p2.Box(width=1.0, height=0.4, position=(0.4, 0.2)))
    world.add(p2.Circle(radius=0.25, position=(0.6, 2.0)))
    return world


def test_a_batch_steps_each_world_bitwise_as_the_single_world():
    single, batch = _scene(), _scene().replicate(3)
    for _ in range(90):
        single.step(1 / 60)
        batch.step(1 / 60)
    for name, array in single.state.arrays().items():
        batched = getattr(batch.state, name)
        if name in ("contact", "contact_i"):
            count = int(single.state.world_i[0, 0])
            array, batched = array[:, :count], batched[:, :count]
        for w in range(3):
            assert array[0].tobytes() == batched[w].tobytes(), name


def test_a_snapshot_of_outlines_replays_bitwise():
    world = _scene()
    world.step(1 / 60, 20)
    snap = world.snapshot()
    world.step(1 / 60, 40)
    first = world.state.copy()
    world.restore(snap)
    world.step(1 / 60, 40)
    for name, array in first.arrays().items():
        assert array.tobytes() == getattr(world.state, name).tobytes(), name


def test_outlines_are_drawn_by_the_renderer_and_in_the_compiled_frames():
    """A polygon's colour at its centroid and the background beyond its corner, in the
    renderer's frame and in the compiled frames (``pixels.Frames``)."""
    world = p2.World(gravity=(0.0, 0.0))
    tri = world.add(p2.Polygon.placed([(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0)]))
    world.add(p2.Capsule(length=1.0, radius=0.3, position=(2.5, 0.0), fixed=True))
    frames = Frames(world, width=64, height=64, view=((-2.0, -2.0), (2.0, 2.0)))
    frames.colour(tri, (255, 0, 0))
    frame = frames()[0]
    x, y = frames.to_pixels(*tri.position)
    assert tuple(frame[int(y), int(x)]) == (255, 0, 0)
    cx, cy = frames.to_pixels(0.6, 0.6)  # beyond the hypotenuse
    assert tuple(frame[int(cy), int(cx)]) != (255, 0, 0)
    cap_x, cap_y = frames.to_pixels(1.9, 0.0)  # inside the capsule's left cap (1.7 to 2.3)
    assert int(cap_x) < 64 and tuple(frame[int(cap_y), int(cap_x)]) != tuple(frame[1, 1])
    picture = Renderer(width=160, height=120).render(world)
    assert picture.shape == (120, 160, 3)
    background = picture[1, 1]
    assert (np.abs(picture.astype(int) - background).sum(axis=-1) > 60).mean() > 0.05
