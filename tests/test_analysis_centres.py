"""Instant centres from the velocity solution, against Kennedy's construction of the four-bar
(tests/oracles.py) and the pitch points of gears; loci over sweeps."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from planar.analysis import instant_centre, instant_centres
from planar.errors import ModelError
from planar.mechanisms import four_bar, gear_train, rolling_wheel, slider_crank
from tests.oracles import four_bar as fb_oracle, four_bar_instant_centres

length = st.floats(0.5, 5.0)
BODIES = {"1": "ground", "2": "crank", "3": "coupler", "4": "rocker"}


@settings(max_examples=200, deadline=None)
@given(r=st.tuples(length, length, length, length), th1=st.floats(-np.pi, np.pi), th2=st.floats(-np.pi, np.pi),
       crossed=st.booleans())
def test_four_bar_centres_match_kennedy(r, th1, th2, crossed):
    s, p, q, l = sorted(r)
    assume(abs(s + l - p - q) > 0.01 * l)  # a change point can fold a link onto another
    sigma = -1 if crossed else 1
    o = fb_oracle(*r, th2, th1=th1, sigma=sigma)
    assume(np.isfinite(o["th4"]) and abs(np.sin(o["th4"] - o["th3"])) > 0.05)
    res = four_bar(*r, frame_angle=th1, crossed=crossed, start=th2).sweep([th2])  # the sketch itself
    assert res.ok.all()
    expected = four_bar_instant_centres(*r, th2, th1=th1, sigma=sigma)
    found = instant_centres(res)
    for key, P in expected.items():
        pair = (BODIES[key[1]], BODIES[key[2]])
        if abs(res.omega(pair[0])[0] - res.omega(pair[1])[0]) < 1e-6:
            continue  # (nearly) no relative turning: the centre is ill-defined
        d = np.hypot(*P)
        assume(np.isfinite(d) and d < 1e3 * max(r))  # Kennedy's lines nearly parallel: far away
        err = np.hypot(*(found[pair][0] - P))
        assert err <= 1e-9 * max(r) * max(1.0, d / max(r)) ** 2, key


def test_loci_over_a_sweep_and_symmetry():
    th = np.linspace(0, 2 * np.pi, 73)
    res = four_bar().sweep(th)
    locus = instant_centre(res, "ground", "coupler")  # the coupler's fixed centrode
    assert locus.shape == (73, 2)
    np.testing.assert_allclose(instant_centre(res, "coupler", "ground"), locus)
    o = four_bar_instant_centres(4, 2, 3, 4, th)
    ok = np.hypot(*o["I13"].T) < 1e3
    np.testing.assert_allclose(locus[ok], o["I13"][ok], atol=1e-9 * 4, rtol=1e-9)


def test_gears_meet_at_their_pitch_point():
    res = gear_train((1.0, 2.0)).sweep([0.0, 1.0])
    np.testing.assert_allclose(instant_centre(res, "gear1", "gear2"), [[1.0, 0.0], [1.0, 0.0]], atol=1e-12)


def test_a_rolling_wheel_turns_about_its_contact_point():
    res = rolling_wheel(1.5).sweep(np.linspace(0, -4, 9))
    centre = res.position("centre")
    np.testing.assert_allclose(instant_centre(res, "ground", "wheel"), centre - [0, 1.5], atol=1e-12)


def test_a_translation_has_its_centre_at_infinity():
    res = slider_crank().sweep([0.3])
    assert np.isnan(instant_centre(res, "ground", "slider")).all()
    assert np.isfinite(instant_centre(res, "crank", "slider")).all()


def test_a_body_with_itself_has_no_centre():
    # (NaN: a body has no motion relative to itself)
    with pytest.raises(ModelError, match="an instant centre is of two bodies, got 'crank' twice"):
        instant_centre(four_bar().sweep([0.1]), "crank", "crank")
