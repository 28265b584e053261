"""Mobility reports, transmission angles and named outputs."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import planar
from planar.analysis import mobility, output, transmission_angle
from planar.mechanisms import CATALOGUE, four_bar, planetary_gear_train, slider_crank
from tests.oracles import four_bar as fb_oracle, four_bar_transmission_angle

length = st.floats(0.5, 5.0)


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_every_builder_reports_its_mobility(name):
    m = CATALOGUE[name]()
    report = mobility(m)
    assert report.dof == len(report.inputs) == report.coordinates - report.rank
    assert report.grubler == report.coordinates - report.joint_rows
    # each redundant joint row is one more than Grubler counts
    assert report.dof - report.grubler >= 0
    assert mobility(m.compile()) == report == mobility(m.sweep(m.compile().u0[None]))


@pytest.mark.parametrize("planets", [1, 2, 4])
def test_planetary_redundancy(planets):
    report = mobility(planetary_gear_train(planets=planets))
    assert (report.grubler, report.dof, len(report.redundant_joints)) == (2 - planets, 1, planets - 1)
    assert "redundant joints" in str(report)


def test_mobility_refuses_other_things():
    with pytest.raises(planar.ModelError, match="mobility needs"):
        mobility(3)


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


def test_outputs_by_name():
    res = slider_crank(2, 5, offset=1).sweep([0.3], velocity=2.0, acceleration=0.5)
    np.testing.assert_array_equal(output(res, "angle:coupler", 1), res.omega("coupler"))
    np.testing.assert_array_equal(output(res, "travel:slide", 2), res.coordinate("slide", 2))
    np.testing.assert_array_equal(output(res, "joint_angle:A", 1), res.coordinate("A", 1))
    np.testing.assert_array_equal(output(res, "y:B"), res.position("B")[:, 1])
    np.testing.assert_array_equal(output(res, "x:A", 1), res.velocity("A")[:, 0])
    np.testing.assert_array_equal(output(res, "vx:A"), res.velocity("A")[:, 0])
    with pytest.raises(planar.InputError, match="unknown output 'z:B'"):
        output(res, "z:B")
    with pytest.raises(planar.InputError, match="angle is an output of a body"):
        output(res, "angle:B")
    with pytest.raises(planar.InputError, match="derivative"):
        output(res, "x:B", 3)
    with pytest.raises(planar.InputError, match="no derivative"):
        output(res, "speed:B", 1)


def test_the_dotted_spelling_is_refused_naming_the_fix():
    res = slider_crank(2, 5, offset=1).sweep([0.3])
    for old, new in (("B.x", "x:B"), ("coupler", "angle:coupler"), ("slide", "travel:slide"), ("A", "joint_angle:A")):
        with pytest.raises(planar.InputError, match=f"here {new}"):
            output(res, old)
