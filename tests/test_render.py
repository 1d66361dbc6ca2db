"""The numpy rasteriser: pixel checks on simple scenes, and one reference frame."""

from pathlib import Path

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.render import Camera, Renderer, Style

BACKGROUND = np.array(Style().background, np.uint8)
REFERENCE = Path(__file__).parent / "data" / "reference_frame.npz"


def _world(*bodies, gravity=(0.0, 0.0)) -> p2.World:
    world = p2.World(gravity=gravity)
    for body in bodies:
        world.add(body)
    return world


def _painted(frame: np.ndarray) -> np.ndarray:
    """Pixels that differ from the background."""
    return np.any(frame != BACKGROUND, axis=-1)


def test_frame_shape_and_dtype():
    """A frame is (height, width, 3) uint8."""
    frame = Renderer(64, 36).render(_world(p2.Circle()))
    assert frame.shape == (36, 64, 3) and frame.dtype == np.uint8


@pytest.mark.parametrize("radius_px", [5.0, 12.0, 30.0])
def test_circle_covers_its_area(radius_px):
    """A disc's coverage (anti-aliased coverage summed) is pi r^2 within 2 %, and nothing is
    painted farther than r + 1 pixels from its centre."""
    camera = Camera((0.0, 0.0), pixels_per_metre=radius_px)  # radius 1 m = radius_px pixels
    style = Style(background=(0, 0, 0), circle=(200, 200, 200))
    frame = Renderer(101, 101, camera, style).render(_world(p2.Circle(radius=1.0)))
    # Subtract the rotation mark, which is darker: use the red channel's coverage only where
    # the mark is not (the mark runs along +x from the centre, angle 0).
    coverage = frame[..., 0].astype(float) / 200.0
    rows, cols = np.indices(coverage.shape)
    dx, dy = cols + 0.5 - 50.5, rows + 0.5 - 50.5
    mark = (np.abs(dy) <= max(1.0, 0.15 * radius_px) / 2 + 1.0) & (dx > -2)
    area = coverage[~mark].sum() + mark[np.hypot(dx, dy) <= radius_px].sum()
    assert area == pytest.approx(np.pi * radius_px**2, rel=0.02)
    assert not np.any(coverage[np.hypot(dx, dy) > radius_px + 1.0] > 0)


def test_y_points_up_and_scale_is_metres():
    """A body 1 m above the camera centre is drawn ppm pixels above the frame's middle."""
    camera = Camera((0.0, 0.0), pixels_per_metre=20.0)
    frame = Renderer(100, 100, camera).render(_world(p2.Circle(position=(0, 1), radius=0.2)))
    rows = np.flatnonzero(_painted(frame).any(axis=1))
    assert rows.mean() == pytest.approx(50 - 20, abs=1.0)


def test_rotated_box_corners():
    """A box turned 30 degrees: pixels just inside each corner are painted, just outside are
    not, and nothing outside its outline is painted."""
    angle = np.pi / 6
    camera = Camera((0.0, 0.0), pixels_per_metre=40.0)
    box = p2.Box(width=2.0, height=1.0, angle=angle)
    frame = Renderer(160, 120, camera).render(_world(box))
    painted = _painted(frame)
    c, s = np.cos(angle), np.sin(angle)
    for lx, ly in ((1, 0.5), (-1, 0.5), (-1, -0.5), (1, -0.5)):
        for scale, expected in ((0.9, True), (1.1, False)):
            x, y = scale * lx, scale * ly
            wx, wy = c * x - s * y, s * x + c * y
            col, row = camera.to_pixels(wx, wy, 160, 120)
            assert painted[int(row), int(col)] == expected, (lx, ly, scale)
    rows, cols = np.indices(painted.shape)
    wx, wy = (cols + 0.5 - 80) / 40.0, (60 - rows - 0.5) / 40.0
    local_x, local_y = c * wx + s * wy, -s * wx + c * wy
    far = (np.abs(local_x) > 1.0 + 1.5 / 40) | (np.abs(local_y) > 0.5 + 1.5 / 40)
    assert not painted[far].any()


def test_rotation_mark_follows_the_angle():
    """The circle's mark points along its angle: right at 0, up at pi/2."""
    camera = Camera((0.0, 0.0), pixels_per_metre=40.0)
    for angle, (row, col) in ((0.0, (50, 85)), (np.pi / 2, (15, 50))):
        frame = Renderer(100, 100, camera).render(_world(p2.Circle(radius=1.0, angle=angle)))
        fill = np.array(Style().circle)
        assert np.all(frame[row, col] < fill * 0.6), angle  # the dark mark, not the fill


def test_plane_shades_its_solid_side_only():
    """The ground's solid side is shaded; the open side stays background."""
    camera = Camera((0.0, 0.0), pixels_per_metre=10.0)
    frame = Renderer(80, 60, camera).render(_world(p2.Plane(normal=(0, 1), point=(0, 0))))
    painted = _painted(frame)
    assert painted[40:, :].all()  # below the line (solid)
    assert not painted[:28, :].any()  # above it
    tilted = Renderer(80, 60, camera).render(_world(p2.Plane(normal=(1, 0), point=(0, 0))))
    assert _painted(tilted)[:, :38].all() and not _painted(tilted)[:, 43:].any()


def test_only_the_shapes_are_painted():
    """Every painted pixel lies within a pixel of some shape (springs included)."""
    a = p2.Circle(position=(-1.0, 0.0), radius=0.3)
    b = p2.Box(position=(1.0, 0.5), width=0.6, height=0.4)
    world = _world(a, b)
    world.add(p2.Spring(a, b, stiffness=1.0))
    camera = Camera((0.0, 0.0), pixels_per_metre=40.0)
    painted = _painted(Renderer(160, 120, camera).render(world))
    rows, cols = np.indices(painted.shape)
    wx, wy = (cols + 0.5 - 80) / 40.0, (60 - rows - 0.5) / 40.0
    slack = 1.5 / 40.0
    near_a = np.hypot(wx + 1.0, wy) <= 0.3 + slack
    near_b = (np.abs(wx - 1.0) <= 0.3 + slack) & (np.abs(wy - 0.5) <= 0.2 + slack)
    # The spring: within its zig-zag amplitude (4 px) of the segment between the centres.
    t = np.clip(((wx + 1.0) * 2.0 + wy * 0.5) / (2.0**2 + 0.5**2), 0.0, 1.0)
    near_spring = np.hypot(wx + 1.0 - 2.0 * t, wy - 0.5 * t) <= (5.5 / 40.0)
    assert painted[near_a].any() and painted[near_b].any()
    assert not painted[~(near_a | near_b | near_spring)].any()


def test_disabled_bodies_are_not_drawn_and_batches_render_per_world():
    """render_batch gives one frame per world; a body switched off in a world is absent."""
    world = _world(p2.Circle(radius=0.5)).replicate(3)
    world.bodies[0].enabled = np.array([True, False, True])
    frames = Renderer(40, 40, Camera((0.0, 0.0), 20.0)).render_batch(world)
    assert frames.shape == (3, 40, 40, 3)
    assert _painted(frames[0]).any() and not _painted(frames[1]).any()
    np.testing.assert_array_equal(frames[0], frames[2])


def test_debug_overlays_add_pixels():
    """Velocity arrows, contact points, AABBs and sleeping dimming each change the frame."""
    world = p2.World(gravity=(0.0, -9.81))
    world.add(p2.Plane())
    ball = world.add(p2.Circle(position=(0, 0.5), radius=0.5, velocity=(2.0, 0.0)))
    world.step(1 / 60)
    camera = Camera((0.0, 0.5), 40.0)
    plain = Renderer(120, 80, camera).render(world)
    for overlay in ("velocities", "contacts", "aabbs"):
        assert np.any(Renderer(120, 80, camera, debug=(overlay,)).render(world) != plain), overlay
    ball.velocity, ball.angular_velocity = (0.0, 0.0), 0.0
    for _ in range(60):
        world.step(1 / 60)
    assert not ball.awake
    dimmed = Renderer(120, 80, camera, debug="sleeping").render(world)
    assert dimmed.sum() < Renderer(120, 80, camera).render(world).sum()


def test_camera_fit_shows_every_body():
    """The fitted camera keeps every body inside the frame."""
    world = _world(p2.Circle(position=(-3, 2), radius=0.5), p2.Box(position=(4, -1)))
    renderer = Renderer(200, 100)
    painted = _painted(renderer.render(world))
    assert painted.any()
    assert not painted[0, :].any() and not painted[-1, :].any()
    assert not painted[:, 0].any() and not painted[:, -1].any()


def test_rendering_is_deterministic():
    """The same world renders to the same bytes."""
    world = _world(p2.Circle(radius=0.4, angle=1.0), p2.Box(position=(1, 0), angle=0.3))
    renderer = Renderer(64, 48)
    np.testing.assert_array_equal(renderer.render(world), renderer.render(world))


def test_bad_arguments_are_rejected():
    """Bad sizes, overlays, cameras and world indices raise ValueError naming them."""
    with pytest.raises(ValueError, match="width"):
        Renderer(0, 10)
    with pytest.raises(ValueError, match="height"):
        Renderer(10, -1)
    with pytest.raises(ValueError, match="debug"):
        Renderer(10, 10, debug=("wireframe",))
    with pytest.raises(ValueError, match="camera"):
        Renderer(10, 10, camera=(0, 0))
    with pytest.raises(ValueError, match="pixels_per_metre"):
        Camera((0, 0), 0.0)
    with pytest.raises(ValueError, match="view"):
        Camera.fit_view((1, 0, 0, 1), 10, 10)
    with pytest.raises(ValueError, match="world_index"):
        Renderer(10, 10).render(_world(p2.Circle()), world_index=1)


def _reference_world() -> p2.World:
    world = p2.World(gravity=(0.0, -9.81))
    world.add(p2.Plane(normal=(0.1, 1.0), point=(0.0, 0.0)))
    ball = world.add(p2.Circle(position=(-1.0, 1.0), radius=0.4, angle=0.7))
    box = world.add(p2.Box(position=(1.0, 0.8), width=1.0, height=0.5, angle=0.4))
    world.add(p2.Box(position=(2.6, 1.0), width=0.3, height=2.0, fixed=True))
    world.add(p2.Spring(ball, box, stiffness=10.0))
    return world


def test_matches_the_reference_frame():
    """A small scene renders like the stored reference (tests/data/reference_frame.npz) to
    within one level per channel. Regenerate it with ``python tests/test_render.py`` after
    an intended change to the look."""
    frame = Renderer(96, 54, Camera((0.5, 0.8), 18.0)).render(_reference_world())
    reference = np.load(REFERENCE)["frame"]
    assert np.abs(frame.astype(int) - reference.astype(int)).max() <= 1


if __name__ == "__main__":
    REFERENCE.parent.mkdir(exist_ok=True)
    frame = Renderer(96, 54, Camera((0.5, 0.8), 18.0)).render(_reference_world())
    np.savez_compressed(REFERENCE, frame=frame)
    print(f"wrote {REFERENCE}")
