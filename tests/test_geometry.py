"""Convex polygons' rules and mass properties (``impulse2d.geometry``) against closed
forms, an independent numerical integration, and invariances over random polygons."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impulse2d import geometry


def _grid_moments(vertices, radius, cells=1200):
    """Area, centroid and second moment about the centroid by counting the cells of a
    fine grid whose centres lie within ``radius`` of the polygon: an integration that
    shares nothing with ``geometry.mass``."""
    points = np.asarray(vertices, dtype=float)
    lo, hi = points.min(axis=0) - radius, points.max(axis=0) + radius
    side = max(hi - lo) / cells
    xs = np.arange(lo[0] + side / 2, hi[0], side)
    ys = np.arange(lo[1] + side / 2, hi[1], side)
    x, y = np.meshgrid(xs, ys)
    inside = np.ones_like(x, dtype=bool)
    distance = np.full_like(x, np.inf)
    for a, b in zip(points, np.roll(points, -1, axis=0), strict=True):
        edge = b - a
        inside &= edge[0] * (y - a[1]) - edge[1] * (x - a[0]) >= 0.0
        t = np.clip(((x - a[0]) * edge[0] + (y - a[1]) * edge[1]) / (edge @ edge), 0.0, 1.0)
        distance = np.minimum(distance, np.hypot(x - a[0] - t * edge[0], y - a[1] - t * edge[1]))
    solid = inside | (distance <= radius)
    cell = side * side
    area = solid.sum() * cell
    cx, cy = (x[solid].sum() * cell / area), (y[solid].sum() * cell / area)
    moment = (
        ((x[solid] - cx) ** 2 + (y[solid] - cy) ** 2).sum() + solid.sum() / 6 * side**2
    ) * cell
    return area, (cx, cy), moment


def test_a_right_triangle_has_its_closed_form():
    a, b = 3.0, 2.0
    area, centroid, moment = geometry.mass([(0.0, 0.0), (a, 0.0), (0.0, b)])
    assert area == pytest.approx(a * b / 2)
    assert centroid == pytest.approx((a / 3, b / 3))
    assert moment == pytest.approx(area * (a * a + b * b) / 18)


def test_a_rectangle_gives_the_boxs_inertia_wherever_it_sits():
    w, h = 1.2, 0.4
    for dx, dy in [(0.0, 0.0), (5.0, -3.0)]:
        corners = [(dx - w / 2, dy - h / 2), (dx + w / 2, dy - h / 2),
                   (dx + w / 2, dy + h / 2), (dx - w / 2, dy + h / 2)]  # fmt: skip
        area, centroid, moment = geometry.mass(corners)
        assert centroid == pytest.approx((dx, dy))
        assert moment / area == pytest.approx((w * w + h * h) / 12)  # the Box's m (w²+h²)/12


@pytest.mark.parametrize(
    "vertices, radius",
    [
        ([(0.0, 0.0), (1.0, 0.0), (0.2, 0.7)], 0.15),
        ([(-0.5, -0.25), (0.5, -0.25), (0.5, 0.25), (-0.5, 0.25)], 0.1),
        ([(0.0, -0.4), (0.6, 0.0), (0.3, 0.5), (-0.3, 0.5), (-0.6, 0.0)], 0.05),
    ],
)
def test_rounded_polygons_agree_with_a_numerical_integration(vertices, radius):
    area, centroid, moment = geometry.mass(vertices, radius)
    grid_area, grid_centroid, grid_moment = _grid_moments(vertices, radius)
    assert area == pytest.approx(grid_area, rel=2e-3)
    assert centroid == pytest.approx(grid_centroid, abs=2e-3)
    assert moment == pytest.approx(grid_moment, rel=4e-3)


def test_a_rounded_polygon_has_the_closed_area_and_a_tiny_one_is_a_disc():
    square = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    area, _, _ = geometry.mass(square, 0.2)
    assert area == pytest.approx(1.0 + 4.0 * 0.2 + math.pi * 0.04)  # A + P r + pi r^2
    tiny = [(x * 1e-2, y * 1e-2) for x, y in square]
    area, centroid, moment = geometry.mass(tiny, 1.0)
    assert moment / area == pytest.approx(0.5, rel=0.05)  # a disc: m r^2 / 2
    assert centroid == pytest.approx((0.0, 0.0), abs=1e-12)


def test_a_clockwise_list_is_reversed_keeping_its_first_vertex():
    clockwise = [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0)]
    assert geometry.check_polygon(clockwise).tolist() == [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    assert geometry.mass(clockwise) == geometry.mass([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])


@pytest.mark.parametrize(
    "vertices, radius, message",
    [
        ([(0.0, 0.0), (1.0, 0.0)], 0.0, "must number 3 to 8, got 2"),
        ([(math.cos(k), math.sin(k)) for k in np.linspace(0, 6, 9)], 0.0, "got 9"),
        ([(0.0, 0.0), (1.0, 0.0), (float("nan"), 1.0)], 0.0, "must be finite"),
        ([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)], -0.1, "radius must be >= 0"),
        ([(0.0, 0.0), (1.0, 0.0), (1.001, 0.0), (0.0, 1.0)], 0.0, "at least 0.005 m apart"),
        ([(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (0.0, 1.0)], 0.0, "vertex 1 (1.0, 0.0) is collinear"),
        ([(0.0, 0.0), (2.0, 0.0), (0.5, 0.5), (0.0, 2.0)], 0.0, "vertex 2 (0.5, 0.5) turns back"),
        ([(math.cos(k * 4 * math.pi / 5), math.sin(k * 4 * math.pi / 5)) for k in range(5)],
         0.0, "wind round twice"),
        ([[0.0, 0.0, 0.0]] * 3, 0.0, "list of (x, y) pairs"),
    ],
)  # fmt: skip
def test_bad_polygons_are_refused_by_rule(vertices, radius, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        geometry.mass(vertices, radius)


@st.composite
def convex_polygons(draw):
    n = draw(st.integers(3, geometry.MAX_VERTICES))
    gaps = np.array(draw(st.lists(st.floats(0.2, 1.0), min_size=n, max_size=n)))
    angles = np.cumsum(gaps / gaps.sum() * 2 * math.pi)
    radii = np.array(draw(st.lists(st.floats(0.9, 1.1), min_size=n, max_size=n)))
    scale = draw(st.floats(0.1, 3.0))
    return np.stack([np.cos(angles), np.sin(angles)], axis=1) * (radii * scale)[:, None]


@settings(max_examples=150, deadline=None)
@given(
    convex_polygons(),
    st.floats(0.0, 0.3),
    st.floats(-math.pi, math.pi),
    st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
    st.integers(0, 7),
)
def test_mass_is_the_same_whatever_the_pose_or_the_first_vertex(points, radius, turn, shift, k):
    try:
        area, centroid, moment = geometry.mass(points, radius)
    except ValueError:  # a drawn corner too straight or an edge too short: not convex here
        return
    c, s = math.cos(turn), math.sin(turn)
    moved = points @ np.array([[c, s], [-s, c]]) + np.array(shift)
    moved = np.roll(moved, k % len(points), axis=0)
    area2, centroid2, moment2 = geometry.mass(moved, radius)
    assert area2 == pytest.approx(area, rel=1e-9)
    assert moment2 == pytest.approx(moment, rel=1e-9, abs=1e-12)
    expected = np.array(centroid) @ np.array([[c, s], [-s, c]]) + np.array(shift)
    assert centroid2 == pytest.approx(tuple(expected), abs=1e-9)
    assert area > 0 and moment > 0
