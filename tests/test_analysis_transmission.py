"""Transmission angles against the four-bar's closed form (tests/oracles.py), and refusals."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import planar
from planar.analysis import transmission_angle
from planar.mechanisms import four_bar
from tests.oracles import four_bar as fb_oracle, four_bar_transmission_angle

length = st.floats(0.5, 5.0)


@settings(max_examples=200, deadline=None)
@given(r=st.tuples(length, length, length, length), th1=st.floats(-np.pi, np.pi), th2=st.floats(-np.pi, np.pi),
       crossed=st.booleans())
def test_four_bar_transmission_angle(r, th1, th2, crossed):
    o = fb_oracle(*r, th2, th1=th1, sigma=-1 if crossed else 1)
    assume(np.isfinite(o["th4"]) and abs(np.sin(o["th4"] - o["th3"])) > 1e-3)
    res = four_bar(*r, frame_angle=th1, crossed=crossed, start=th2).sweep([th2])
    expected = four_bar_transmission_angle(*r, th2, th1=th1)
    assert abs(transmission_angle(res, ("B", "A"), ("B", "O4"))[0] - expected) <= 1e-9
    assert abs(transmission_angle(res, "coupler", "rocker")[0] - expected) <= 1e-9


def test_transmission_angle_refuses_unknown_directions():
    res = four_bar().sweep([0.0])
    with pytest.raises(planar.ModelError, match="unknown body"):
        transmission_angle(res, "beam", "rocker")
    with pytest.raises(planar.ModelError, match="pair of point names"):
        transmission_angle(res, ("A",), "rocker")
    with pytest.raises(planar.ModelError, match="got 'B' twice"):
        transmission_angle(res, ("B", "B"), "rocker")


def test_a_direction_of_no_length_has_no_angle():
    # (a coupler point on A: the direction A -> C was of no length, its angle 0 or pi)
    res = four_bar(coupler_point=(0.0, 0.0)).sweep([0.0, 1.0])
    assert np.isnan(transmission_angle(res, ("A", "C"), "rocker")).all()
    assert np.isfinite(transmission_angle(res, ("B", "C"), "rocker")).all()
