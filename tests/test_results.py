"""The frozen :class:`planar.results.Sweep`: named access against hand computations.

A four-bar O2 (origin) - A - B - O4 (4, 0) with crank 2, coupler 3.5, rocker 3 and a coupler
point C: positions from the link lengths and angles, velocities and accelerations against
central differences along the input, the chain rule for other input rates, joint coordinates
against body angles, and the :class:`Status` tables.
"""

import numpy as np
import pytest

from planar.errors import ModelError
from planar.geometry import perp
from planar.mechanisms import four_bar, slider_crank
from planar.results import POSED, VALID, Status

P, Q = 1.0, 0.5  # C: P along A -> B, Q to its left
H = 1e-4  # input step of the central differences


def unit(a):
    return np.stack((np.cos(a), np.sin(a)), axis=-1)


@pytest.fixture(scope="module")
def model():
    return four_bar(4, 2, 3.5, 3, coupler_point=(P, Q)).compile()


@pytest.fixture(scope="module")
def triples(model):
    """A sweep at u - H, u, u + H for u along a turn, and the three (N, ...) slices."""
    u = np.linspace(0.2, 6.0, 7)
    res = model.sweep((u[:, None] + [-H, 0.0, H]).ravel())
    assert res.ok.all()
    return res, u, (slice(0, None, 3), slice(1, None, 3), slice(2, None, 3))


def test_positions_are_the_links_at_their_angles(model, triples):
    res, u, (_, at, _) = triples
    th2, th3, th4 = (res.angle(b)[at] for b in ("crank", "coupler", "rocker"))
    np.testing.assert_allclose(th2, u, rtol=0, atol=1e-12)  # the crank's angle is the input
    A, B, C = (res.position(p)[at] for p in ("A", "B", "C"))
    np.testing.assert_allclose(res.position("O2"), 0.0, atol=1e-12)
    np.testing.assert_allclose(res.position("O4"), np.tile([4.0, 0.0], (len(res), 1)), atol=1e-12)
    np.testing.assert_allclose(A, 2 * unit(th2), atol=1e-12)
    np.testing.assert_allclose(B, A + 3.5 * unit(th3), atol=1e-12)
    np.testing.assert_allclose(B, [4.0, 0.0] + 3 * unit(th4), atol=1e-12)
    e = (B - A) / 3.5
    np.testing.assert_allclose(C, A + P * e + Q * perp(e), atol=1e-12)


def test_rates_are_the_derivatives_of_the_positions(model, triples):
    res, _, (dn, at, up) = triples
    for name in ("A", "B", "C"):
        x = res.position(name)
        np.testing.assert_allclose(res.velocity(name)[at], (x[up] - x[dn]) / (2 * H), rtol=0, atol=1e-6, err_msg=name)
        v = res.velocity(name)
        np.testing.assert_allclose(res.acceleration(name)[at], (v[up] - v[dn]) / (2 * H), rtol=0, atol=1e-6,
                                   err_msg=name)
        np.testing.assert_allclose(res.acceleration(name)[at], (x[up] - 2 * x[at] + x[dn]) / H**2, rtol=0,
                                   atol=1e-4, err_msg=name)
    for body in ("crank", "coupler", "rocker"):
        a, w = res.angle(body), res.omega(body)
        np.testing.assert_allclose(w[at], (a[up] - a[dn]) / (2 * H), rtol=0, atol=1e-7, err_msg=body)
        np.testing.assert_allclose(res.alpha(body)[at], (w[up] - w[dn]) / (2 * H), rtol=0, atol=1e-7, err_msg=body)
    np.testing.assert_array_equal(res.omega("crank"), np.ones(len(res)))
    np.testing.assert_array_equal(res.alpha("crank"), np.zeros(len(res)))


def test_other_input_rates_follow_the_chain_rule(model):
    """omega = v w1 and alpha = v^2 a1 + a w1 (w1, a1: per unit input rate); points likewise."""
    u = np.linspace(0.0, 6.0, 13)
    one = model.sweep(u)
    v, a = 2.5, -0.7
    res = model.sweep(u, velocity=v, acceleration=a)
    for body in ("coupler", "rocker"):
        np.testing.assert_allclose(res.omega(body), v * one.omega(body), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(res.alpha(body), v**2 * one.alpha(body) + a * one.omega(body), rtol=1e-10,
                                   atol=1e-12)
    np.testing.assert_allclose(res.velocity("C"), v * one.velocity("C"), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(res.acceleration("C"), v**2 * one.acceleration("C") + a * one.velocity("C"),
                               rtol=1e-10, atol=1e-12)


def test_ground_is_still_and_unknown_names_are_refused(model, triples):
    res = triples[0]
    for f in (res.angle, res.omega, res.alpha):
        np.testing.assert_array_equal(f("ground"), np.zeros(len(res)))
    with pytest.raises(ModelError, match="unknown body 'frame'"):
        res.angle("frame")
    with pytest.raises(ModelError, match="unknown point or joint 'D'"):
        res.position("D")


def test_every_array_is_read_only(triples):
    res = triples[0]
    arrays = {k: v for k, v in vars(res).items() if isinstance(v, np.ndarray)}
    assert {"q", "qd", "qdd", "status", "inputs", "gap"} <= set(arrays)
    for name, a in arrays.items():
        with pytest.raises(ValueError, match="read-only"):
            a[0] = a[0]
    with pytest.raises(AttributeError):
        res.q = None  # frozen


def test_a_revolutes_coordinate_is_the_relative_angle_of_its_bodies(model, triples):
    """Revolute A joins crank and coupler: its angle is th3 - th2 (up to the sketch's), its
    rates the differences of the bodies' rates."""
    res = triples[0]
    rel = res.angle("coupler") - res.angle("crank")
    c0 = res.coordinate("A")
    np.testing.assert_allclose(c0 - rel, np.full(len(res), (c0 - rel)[0]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.coordinate("A", 1), res.omega("coupler") - res.omega("crank"), atol=1e-12)
    np.testing.assert_allclose(res.coordinate("A", 2), res.alpha("coupler") - res.alpha("crank"), atol=1e-12)


def test_a_sliders_travel_and_its_rates():
    """A slider crank (crank 2, coupler 5, offset 1): the slider's travel along its line, the
    crank's tip projected plus the coupler's run, and its derivatives by central differences."""
    model = slider_crank(2, 5, offset=1).compile()
    u = np.linspace(0.3, 6.0, 5)
    res = model.sweep((u[:, None] + [-H, 0.0, H]).ravel())
    dn, at, up = slice(0, None, 3), slice(1, None, 3), slice(2, None, 3)
    s = res.coordinate("slide")
    x = res.position("B")[:, 0]
    np.testing.assert_allclose(s - x, np.full(len(res), (s - x)[0]), atol=1e-12)  # the line is along x
    np.testing.assert_allclose(x, 2 * np.cos(res.inputs[:, 0]) + np.sqrt(25 - (1 - 2 * np.sin(res.inputs[:, 0])) ** 2),
                               atol=1e-12)
    np.testing.assert_allclose(res.coordinate("slide", 1)[at], (s[up] - s[dn]) / (2 * H), atol=1e-7)
    sd = res.coordinate("slide", 1)
    np.testing.assert_allclose(res.coordinate("slide", 2)[at], (sd[up] - sd[dn]) / (2 * H), atol=1e-6)
    with pytest.raises(ModelError, match="derivative must be 0, 1 or 2"):
        res.coordinate("slide", 3)
    with pytest.raises(ModelError, match="has no coordinate"):
        res.coordinate("crank")


def test_a_coordinate_of_bodies_a_sweep_left_unsolved_is_nan():
    # (outputs= left the joint's bodies out: their coordinates, NaN, were read as 0; B came back 0)
    full = four_bar().sweep([0.3, 0.6])
    assert np.isnan(four_bar().sweep([0.3, 0.6], outputs=["crank"]).coordinate("B")).all()
    part = slider_crank().sweep([0.3, 0.6], outputs=["A"])
    for d in (0, 1, 2):
        assert np.isnan(part.coordinate("slide", d)).all()
        np.testing.assert_allclose(part.coordinate("O2", d), slider_crank().sweep([0.3, 0.6]).coordinate("O2", d),
                                   rtol=0, atol=1e-12)
        np.testing.assert_allclose(four_bar().sweep([0.3, 0.6], outputs=["B"]).coordinate("B", d),
                                   full.coordinate("B", d), rtol=0, atol=1e-12)


def test_points_out_of_reach_are_nan_and_name_the_nearest_limit():
    """A triple rocker (4, 3, 3, 3) turns its crank to +-117.28 deg only."""
    model = four_bar(4, 3, 3, 3).compile()
    deg = np.array([100.0, 120.0, 140.0, -100.0, -130.0])
    res = model.sweep(np.radians(deg))
    assert [Status(s) for s in res.status] == [Status.SOLVED, Status.NOT_ASSEMBLABLE, Status.NOT_ASSEMBLABLE,
                                               Status.SOLVED, Status.NOT_ASSEMBLABLE]
    np.testing.assert_array_equal(res.ok, [True, False, False, True, False])
    limit = np.radians(117.279613)
    np.testing.assert_allclose(res.nearest_limit, [np.nan, limit, limit, np.nan, -limit], atol=1e-8)
    miss = ~res.ok
    assert np.isnan(res.position("B")[miss]).all() and np.isfinite(res.position("B")[~miss]).all()
    assert np.isnan(res.coordinate("A")[miss]).all() and np.isnan(res.coordinate("A", 2)[miss]).all()
    assert np.all(res.gap[miss] > 0) and np.isnan(res.gap[~miss]).all()
    assert repr(res) == "Sweep('four_bar', N=5, inputs=['crank'], {'SOLVED': 2, 'NOT_ASSEMBLABLE': 3})"
    assert len(res) == 5


def test_status_tables_say_which_outputs_are_valid():
    valid = {Status.SOLVED, Status.NEAR_SINGULAR, Status.BRANCH_EVENT, Status.JUMPED}
    posed = valid | {Status.SINGULAR, Status.LIMIT}
    for s in Status:
        assert s.valid == (s in valid) == VALID[s]
        assert s.posed == (s in posed) == POSED[s]
        assert str(s) == s.name and f"{s:>20}" == f"{s.name:>20}"
    assert list(Status) == sorted(Status) and [int(s) for s in Status] == list(range(len(Status)))
