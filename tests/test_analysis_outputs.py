"""Outputs named in the one grammar, "kind:name", against the results' own accessors, and
the refusals that name the fix."""

import numpy as np
import pytest

import planar
from planar.analysis import output
from planar.mechanisms import slider_crank


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
