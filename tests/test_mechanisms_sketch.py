"""The builders' sketch constructions against what each point must satisfy: its distances,
its line, its side, and the refusals when the figure cannot close."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from planar.errors import AssemblyError
from planar.mechanisms.sketch import along, angle_of, circle_circle, circle_line, left_of, line_through, polar

coord = st.floats(-10, 10)
point = st.tuples(coord, coord)
radius = st.floats(0.1, 10)
angle = st.floats(-10, 10)
EPS = 1e-9


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


@settings(max_examples=60, deadline=None)
@given(point, radius, point, radius)
def test_circle_circle_gives_both_meeting_points_left_first(c1, r1, c2, r2):
    c1, c2 = np.array(c1), np.array(c2)
    L = np.hypot(*(c2 - c1))
    if L == 0 or L > r1 + r2 or L < abs(r1 - r2):
        with pytest.raises(AssemblyError, match="do not meet"):
            circle_circle(c1, r1, c2, r2)
        return
    assume(min(r1 + r2 - L, L - abs(r1 - r2)) > 1e-6)  # not tangent: the points are well defined
    left, right = circle_circle(c1, r1, c2, r2)
    for P in (left, right):
        assert np.linalg.norm(P - c1) == pytest.approx(r1, abs=EPS * 10)
        assert np.linalg.norm(P - c2) == pytest.approx(r2, abs=EPS * 10)
    assert cross(c2 - c1, left - c1) >= 0 >= cross(c2 - c1, right - c1)


@settings(max_examples=60, deadline=None)
@given(point, radius, st.floats(1e3, 1e12), angle, st.floats(-0.95, 0.95), st.booleans())
def test_circle_circle_meets_a_far_larger_circle_to_the_rounding_of_the_coordinates(c, r, R, th, t, small_first):
    # a circle of radius R passing through a small one (its centre R + t r away): the points of
    # a rocker of 1.5 beside a coupler of 1e8 (naive squares put them on the line of centres,
    # 1 from the rocker's pivot: the four-bar was refused as not assembling)
    c = np.array(c)
    C = c + (R + t * r) * np.array([np.cos(th), np.sin(th)])
    circles = ((c, r), (C, R)) if small_first else ((C, R), (c, r))
    (c1, r1), (c2, r2) = circles
    left, right = circle_circle(c1, r1, c2, r2)
    tol = 8 * np.finfo(float).eps * (np.abs(C).max() + R)  # (the coordinates' rounding)
    for P in (left, right):
        for centre, radius in circles:
            assert abs(np.linalg.norm(P - centre) - radius) <= tol
    assert cross(c2 - c1, left - c1) >= 0 >= cross(c2 - c1, right - c1)


@settings(max_examples=60, deadline=None)
@given(point, radius, point, angle)
def test_circle_line_gives_both_meeting_points_ahead_first(c, r, p, th):
    c, p, u = np.array(c), np.array(p), 3.0 * np.array([np.cos(th), np.sin(th)])  # u need not be a unit
    dist = abs(cross(u, c - p)) / np.linalg.norm(u)
    if dist > r * (1 + 1e-12):
        with pytest.raises(AssemblyError, match="cannot be placed"):
            circle_line(c, r, p, u)
        return
    assume(r - dist > 1e-6)
    ahead, behind = circle_line(c, r, p, u)
    for P in (ahead, behind):
        assert np.linalg.norm(P - c) == pytest.approx(r, abs=EPS * 10)
        assert abs(cross(u, P - p)) / np.linalg.norm(u) < EPS * 10  # on the line
    assert np.dot(ahead - behind, u) >= 0


@settings(max_examples=60, deadline=None)
@given(point, radius, angle, st.floats(-1e12, 1e12), st.floats(-0.95, 0.95))
def test_circle_line_meets_a_line_through_a_far_point_to_the_rounding_of_the_coordinates(c, r, th, T, t):
    # the line through p, T along it from the foot of the perpendicular from c, t r from c
    # (|c - p|^2 - t0^2 cancelled in squares of T)
    c, u = np.array(c), np.array([np.cos(th), np.sin(th)])
    p = c + T * u + t * r * np.array([-u[1], u[0]])
    ahead, behind = circle_line(c, r, p, u)
    tol = 8 * np.finfo(float).eps * (np.abs(p).max() + abs(T) + r)  # (the coordinates' rounding)
    for P in (ahead, behind):
        assert abs(np.linalg.norm(P - c) - r) <= tol
        assert abs(cross(u, P - p)) <= tol
    assert np.dot(ahead - behind, u) >= 0


@settings(max_examples=60, deadline=None)
@given(point, radius, angle, point, st.floats(-5, 5), st.floats(-5, 5))
def test_polar_along_angle_of_and_left_of(o, r, th, B, p, q):
    o = np.array(o)
    P = polar(o, r, th)
    assert np.linalg.norm(P - o) == pytest.approx(r)
    assert angle_of(o, P) == pytest.approx(np.arctan2(np.sin(th), np.cos(th)), abs=1e-9)
    B = np.array(B)
    assume(np.linalg.norm(B - o) > 1e-3)
    C = along(o, B, p, q)
    u = (B - o) / np.linalg.norm(B - o)
    assert np.dot(C - o, u) == pytest.approx(p, abs=1e-9) and cross(u, C - o) == pytest.approx(q, abs=1e-9)
    if abs(q) > 1e-6:
        assert left_of(o, B, C) == (q > 0)


@settings(max_examples=60, deadline=None)
@given(point, st.floats(-3, 3), point, st.booleans())
def test_line_through_runs_offset_right_of_the_pivot_through_the_point(pivot, offset, P, longer):
    pivot, P = np.array(pivot), np.array(P)
    D = np.linalg.norm(P - pivot)
    if D == 0 or D < abs(offset):
        with pytest.raises(AssemblyError, match="less than the offset"):
            line_through(pivot, offset, P, longer)
        return
    th, r = line_through(pivot, offset, P, longer)
    e = np.array([np.cos(th), np.sin(th)])
    n = np.array([-e[1], e[0]])
    np.testing.assert_allclose(pivot + r * e - offset * n, P, atol=1e-9)  # (r - i offset) e^{i theta}
    assert (r >= 0) == longer or r == 0


def test_places_within_rounding_of_each_other_are_one_site_across_cells():
    # sites are kept by cells of side 1e-12 L: a place next to a cell's edge finds the site
    # across it, and one two cells on is another site
    from planar.model.resolve import sites

    tol = 1e-12
    points = {n: ("b", np.array([x * tol, 5.0])) for n, x in (("a", 9.9), ("b", 10.1), ("c", 12.5))}
    X0, site, _ = sites(points, [], 1.0)
    assert site["a"] == site["b"] != site["c"] and len(X0) == 2
