"""Sweeps of hand-built mechanisms: closed forms, finite differences, reference cases.

The mechanisms are built here with the plain Mechanism API (not the catalogue), sketched from
the closed forms of tests/oracles.py.
"""

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import planar
from planar import Status
from tests import oracles



def four_bar(r1, r2, r3, r4, th1, th2, sigma, coupler=(0.6, 0.3)):
    o = oracles.four_bar(r1, r2, r3, r4, th2, th1=th1, sigma=sigma, p=coupler[0], q=coupler[1])
    A, B, C = o["A"], o["B"], o["C"]
    O4 = r1 * np.array([np.cos(th1), np.sin(th1)])
    m = planar.Mechanism("four-bar")
    cr = m.add_body("crank", angle=th2)
    co = m.add_body("coupler", angle=float(o["th3"]))
    ro = m.add_body("rocker", angle=float(o["th4"]))
    m.add_revolute("O2", m.ground, cr, at=(0, 0))
    m.add_revolute("A", cr, co, at=A)
    m.add_revolute("B", co, ro, at=B)
    m.add_revolute("O4", ro, m.ground, at=O4)
    m.add_point("C", co, at=C)
    m.drive("O2")
    return m


def slider_crank(r2, r3, offset, th1, th2, sigma, drive=True):
    o = oracles.slider_crank(r2, r3, th2, offset=offset, th1=th1, sigma=sigma)
    u = np.array([np.cos(th1), np.sin(th1)])
    foot = offset * np.array([-u[1], u[0]])
    m = planar.Mechanism("slider-crank")
    cr = m.add_body("crank", angle=th2)
    co = m.add_body("coupler", angle=float(o["th3"]))
    sl = m.add_body("slider", angle=th1)
    m.add_revolute("O2", m.ground, cr, at=(0, 0))
    m.add_revolute("A", cr, co, at=o["A"])
    m.add_revolute("B", co, sl, at=o["B"])
    m.add_prismatic("slide", m.ground, sl, at=o["B"], direction=u, origin=foot)
    if drive:
        m.drive("O2")
    return m


def angle_diff(a, b):
    return np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))


def fd_check(m, names, u0, w, a):
    """Velocity and acceleration of points against fourth-order central differences of
    positions along u(t) = u0 + w t + a t^2 / 2."""
    h = 1e-3 / (1 + abs(w) + np.sqrt(abs(a)))
    t = h * np.arange(-2, 3)
    res = m.sweep(u0 + w * t + 0.5 * a * t**2, velocity=w + a * t, acceleration=a)
    assert res.ok.all()
    for name in names:
        p = res.position(name)
        vel = (p[0] - 8 * p[1] + 8 * p[3] - p[4]) / (12 * h)
        acc = (-p[0] + 16 * p[1] - 30 * p[2] + 16 * p[3] - p[4]) / (12 * h**2)
        scale = 1 + np.abs(res.acceleration(name)[2]).max()
        np.testing.assert_allclose(res.velocity(name)[2], vel, atol=1e-6 * scale)
        np.testing.assert_allclose(res.acceleration(name)[2], acc, atol=1e-5 * scale)


lengths = st.floats(0.2, 5.0)
angles = st.floats(-np.pi, np.pi)


@st.composite
def four_bars(draw):
    """An assembled four-bar drawn from its pose: crank, coupler and rocker lengths and angles
    give A, B and O4, so r1 and the frame angle th1 follow. Returns (r1..r4, th1, th2, sigma)."""
    r2, r3, r4 = draw(lengths), draw(lengths), draw(lengths)
    th2, th3, th4 = draw(angles), draw(angles), draw(angles)
    A = r2 * np.exp(1j * th2)
    B = A + r3 * np.exp(1j * th3)
    O4 = B - r4 * np.exp(1j * th4)
    r1 = abs(O4)
    assume(r1 > 0.1)
    sigma = 1 if ((O4 - A).conjugate() * (B - A)).imag > 0 else -1
    return (r1, r2, r3, r4), float(np.angle(O4)), th2, sigma


@given(fb=four_bars(), w=st.floats(-10, 10), a=st.floats(-50, 50))
def test_four_bar_matches_closed_form_and_finite_differences(fb, w, a):
    r, th1, th2, sigma = fb
    r1, r2, r3, r4 = r
    span = np.linspace(th2, th2 + 0.3, 13)
    o = oracles.four_bar(r1, r2, r3, r4, span, w2=w, a2=a, th1=th1, sigma=sigma, p=0.6, q=0.3)
    # stay away from the limit positions, where the closed form itself is ill-conditioned
    assume(np.all(np.isfinite(o["th3"])) and np.all(np.abs(np.sin(o["th4"] - o["th3"])) > 0.05))
    m = four_bar(r1, r2, r3, r4, th1, th2, sigma)
    res = m.sweep(span, velocity=w, acceleration=a)
    assert res.ok.all()
    L = max(r)
    np.testing.assert_allclose(res.position("B"), o["B"], atol=1e-12 * L)
    np.testing.assert_allclose(res.position("C"), o["C"], atol=1e-12 * L)
    assert np.abs(angle_diff(res.angle("coupler"), o["th3"])).max() < 1e-11
    np.testing.assert_allclose(res.omega("rocker"), o["w4"], atol=1e-9 * (1 + np.abs(o["w4"]).max()))
    np.testing.assert_allclose(res.alpha("coupler"), o["a3"], atol=1e-8 * (1 + np.abs(o["a3"]).max()))
    np.testing.assert_allclose(res.acceleration("C"), o["C_acc"], atol=1e-8 * (1 + np.abs(o["C_acc"]).max()))
    # loop closure: the link lengths hold
    np.testing.assert_allclose(np.linalg.norm(res.position("B") - res.position("A"), axis=1), r3, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(res.position("B") - res.position("O4"), axis=1), r4, rtol=1e-12)
    fd_check(m, ["B", "C"], th2 + 0.15, w, a)


@given(r2=lengths, r3=lengths, offset=st.floats(-3, 3), th1=st.floats(-np.pi, np.pi),
       th2=st.floats(-np.pi, np.pi), sigma=st.sampled_from([-1, 1]), w=st.floats(-10, 10), a=st.floats(-50, 50))
def test_slider_crank_matches_closed_form_and_finite_differences(r2, r3, offset, th1, th2, sigma, w, a):
    span = np.linspace(th2, th2 + 0.3, 13)
    o = oracles.slider_crank(r2, r3, span, w2=w, a2=a, offset=offset, th1=th1, sigma=sigma)
    u = np.array([np.cos(th1), np.sin(th1)])
    cos_t = np.cos(o["th3"] - th1)  # the coupler must not stand across the slide (dead centre)
    assume(np.all(np.isfinite(o["r1"])) and np.all(np.abs(cos_t) > 0.05))
    m = slider_crank(r2, r3, offset, th1, th2, sigma)
    res = m.sweep(span, velocity=w, acceleration=a)
    assert res.ok.all()
    L = max(r2, r3, abs(offset))
    np.testing.assert_allclose(res.coordinate("slide"), o["r1"], atol=1e-12 * L)
    np.testing.assert_allclose(res.coordinate("slide", 1), o["r1_v"], atol=1e-9 * (1 + np.abs(o["r1_v"]).max()))
    np.testing.assert_allclose(res.coordinate("slide", 2), o["r1_a"], atol=1e-8 * (1 + np.abs(o["r1_a"]).max()))
    np.testing.assert_allclose(res.velocity("B") @ u, o["r1_v"], atol=1e-9 * (1 + np.abs(o["r1_v"]).max()))
    assert np.abs(angle_diff(res.angle("coupler"), o["th3"])).max() < 1e-11
    np.testing.assert_allclose(res.alpha("coupler"), o["a3"], atol=1e-8 * (1 + np.abs(o["a3"]).max()))
    fd_check(m, ["A", "B"], th2 + 0.15, w, a)


@given(fb=four_bars())
def test_non_assemblable_inputs_are_reported_not_answered(fb):
    r, th1, th2, sigma = fb
    r1, r2, r3, r4 = r
    o = oracles.four_bar(r1, r2, r3, r4, th2, th1=th1, sigma=sigma)
    assume(abs(np.sin(o["th4"] - o["th3"])) > 0.05)
    # the crank angle farthest from (or nearest to) O4, if the coupler and rocker cannot span it
    far, near = r1 + r2, abs(r1 - r2)
    margin = 1e-3 * max(r)
    if far > r3 + r4 + margin:
        out = th1 + np.pi
    else:
        assume(near < abs(r3 - r4) - margin)
        out = th1
    m = four_bar(r1, r2, r3, r4, th1, th2, sigma)
    res = m.sweep([th2, out])
    assert res.ok[0]
    assert res.status[1] == Status.NOT_ASSEMBLABLE
    assert np.isnan(res.position("B")[1]).all() and np.isnan(res.omega("rocker")[1])
    assert res.gap[1] > 1e-8


def test_sweep_keeps_good_points_past_an_impossible_stretch():
    # triple rocker (non-Grashof) 4, 3, 2, 4.5 swept over a whole turn: the crank cannot pass
    m = four_bar(4.0, 3.0, 2.0, 4.5, 0.0, np.pi / 2, 1)
    th = np.radians(np.arange(90, 451, 5.0))
    res = m.sweep(th)
    o = oracles.four_bar(4.0, 3.0, 2.0, 4.5, th, sigma=1)
    feasible = np.isfinite(o["th3"])
    assert not feasible.all()
    assert np.all(res.status[~feasible] == Status.NOT_ASSEMBLABLE)
    assert np.all(np.isnan(res.position("B")[~feasible]))
    # every value up to the limit is kept, and whatever is solved is right
    first_out = np.argmin(feasible)
    assert res.ok[:first_out].all()
    np.testing.assert_allclose(res.position("B")[res.ok], o["B"][res.ok], atol=1e-11)


REF = oracles.load_reference()


def geared_five_bar(r1, R2, R4, r5, general=False):
    """The seed's geared five-bar, sketched at its reference configuration (th2 = 0, links 3 and 4
    collinear), the gear pair on the arm 3 as carrier (or, ``general``, as a gear between
    centres on gears 2 and 4 whose distance the arm holds)."""
    r3 = R2 + R4
    th50 = np.arccos(((r3 + R4) ** 2 - r1**2 - r5**2) / (2 * r1 * r5))
    C = np.array([r1 + r5 * np.cos(th50), r5 * np.sin(th50)])
    th30 = np.arctan2(C[1], C[0])
    m = planar.Mechanism("geared five-bar")
    g2 = m.add_body("gear2")
    a3 = m.add_body("arm3", angle=th30)
    g4 = m.add_body("gear4", angle=th30)
    l5 = m.add_body("link5", angle=th50)
    m.add_revolute("O2", m.ground, g2, at=(0, 0))
    m.add_revolute("O2arm", m.ground, a3, at=(0, 0))
    B = r3 * np.array([np.cos(th30), np.sin(th30)])
    m.add_revolute("B", a3, g4, at=B)
    m.add_revolute("C", g4, l5, at=C)
    m.add_revolute("O5", l5, m.ground, at=(r1, 0))
    if general:
        m.add_gear("mesh", g2, g4, R2, R4, centre_a=(0, 0), centre_b=B)
    else:
        m.add_gear("mesh", g2, g4, R2, R4, carrier=a3)
    m.drive("O2")
    return m


@pytest.mark.parametrize("case", [c for c in REF if c.startswith("geared_five_bar")])
def test_geared_five_bar_reference_through_the_gear_joint(case):
    inp, exp = REF[case]["inputs"], REF[case]["expected"]
    m = geared_five_bar(inp["r1"], inp["R2"], inp["R4"], inp["r5"])
    assert m.compile().dof == 1 and m.compile().grubler == 1
    res = m.sweep(np.radians([inp["th2_deg"]]), velocity=inp["w2"])
    assert res.ok.all()
    for body, k in (("arm3", "3"), ("gear4", "4"), ("link5", "5")):
        assert abs(np.degrees(res.angle(body)[0]) - exp[f"th{k}_deg"]) < 1e-9 * 180 / np.pi
        assert abs(res.omega(body)[0] - exp[f"w{k}"]) < 1e-8 * abs(exp[f"w{k}"])


def test_general_gear_agrees_with_carrier_gear():
    """The geared five-bar with the mesh written as a general gear (centres on gear 2 and 4,
    distance held by the arm) gives the same motion as the carrier form."""
    a, b = geared_five_bar(8, 3, 3.5, 6), geared_five_bar(8, 3, 3.5, 6, general=True)
    th = np.radians(np.linspace(0, 200, 41))
    ra, rb = a.sweep(th, velocity=2.0, acceleration=-1.0), b.sweep(th, velocity=2.0, acceleration=-1.0)
    assert ra.ok.all() and rb.ok.all()
    for body in ("arm3", "gear4", "link5"):
        np.testing.assert_allclose(rb.angle(body), ra.angle(body), atol=1e-12)
        np.testing.assert_allclose(rb.alpha(body), ra.alpha(body), atol=1e-9)


def test_planet_on_fixed_ring_counter_rotates():
    """Willis: planet (radius 1) inside a fixed ring (radius 3) on a carrier: w_p = w_a (1 - 3/1),
    and the angles stay unwrapped over several carrier turns."""
    m = planar.Mechanism("ring")
    arm, planet = m.add_body("arm"), m.add_body("planet")
    m.add_revolute("O", m.ground, arm, at=(0, 0))
    m.add_revolute("P", arm, planet, at=(2, 0))
    m.add_gear("mesh", planet, m.ground, 1.0, 3.0, internal=True, carrier=arm, centre_b=(0, 0))
    m.drive("O")
    th = np.linspace(0, 4 * np.pi, 97)
    res = m.sweep(th, velocity=1.5)
    assert res.ok.all()
    np.testing.assert_allclose(res.angle("planet"), -2 * th, atol=1e-11)
    np.testing.assert_allclose(res.omega("planet"), -3.0, atol=1e-12)


def test_rack_on_a_moving_body_and_pinion_rolling():
    """Pinion pinned to the ground above a rack that slides on the ground: turning counter-
    clockwise, its lowest point moves to +x and takes the rack along, x_rack = R phi."""
    m = planar.Mechanism("rack and pinion")
    pinion, rack = m.add_body("pinion"), m.add_body("rack")
    m.add_revolute("axle", m.ground, pinion, at=(0, 0.5))
    m.add_prismatic("guide", m.ground, rack, at=(0, 0), direction=(1, 0))
    m.add_rack_pinion("mesh", pinion, rack, 0.5, centre=(0, 0.5), through=(0, 0), direction=(1, 0))
    m.drive("axle")
    res = m.sweep(np.linspace(0, 3, 7), velocity=2.0, acceleration=1.0)
    assert res.ok.all()
    np.testing.assert_allclose(res.coordinate("guide"), 0.5 * np.linspace(0, 3, 7), atol=1e-14)
    np.testing.assert_allclose(res.coordinate("guide", 1), 1.0, atol=1e-14)
    np.testing.assert_allclose(res.coordinate("guide", 2), 0.5, atol=1e-14)


def test_open_chain_with_two_inputs_matches_reference():
    case = REF["open_chain_2_0_0"]
    inp, exp = case["inputs"], case["expected"]
    th = np.radians(inp["abs_angles_deg"])
    m = planar.Mechanism("open chain")
    l1, l2 = m.add_body("link1", th[0]), m.add_body("link2", th[1])
    P1 = inp["lengths"][0] * np.array([np.cos(th[0]), np.sin(th[0])])
    m.add_revolute("O", m.ground, l1, at=(0, 0))
    m.add_revolute("J", l1, l2, at=P1)
    m.add_point("tip", l2, at=P1 + inp["lengths"][1] * np.array([np.cos(th[1]), np.sin(th[1])]))
    m.drive(body="link1")
    m.drive(body="link2")
    res = m.sweep([th], velocity=[inp["abs_angular_velocities"]], acceleration=[inp["abs_angular_accelerations"]])
    assert res.ok.all()
    np.testing.assert_allclose(res.position("tip")[0], exp["tip"], rtol=1e-12)
    np.testing.assert_allclose(res.velocity("tip")[0], exp["tip_vel"], rtol=1e-12)
    np.testing.assert_allclose(res.acceleration("tip")[0], exp["tip_acc"], rtol=1e-12)


def test_point_coordinate_driver():
    """A slider-crank driven by the x coordinate of its slider pin."""
    m = slider_crank(2.0, 5.0, 1.0, 0.0, 0.5, 1, drive=False)
    m.drive(point="B", axis="x")
    x = np.linspace(5.5, 6.5, 11)
    res = m.sweep(x, velocity=1.0)
    assert res.ok.all()
    np.testing.assert_allclose(res.position("B")[:, 0], x, atol=1e-13)
    np.testing.assert_allclose(res.velocity("B")[:, 0], 1.0, atol=1e-12)
