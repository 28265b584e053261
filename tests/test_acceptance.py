"""The acceptance test both engines share (:mod:`planar.acceptance`) and the status rule
(:func:`planar.events.status_of`) on their boundaries, for scalars and arrays alike: the numpy
engine calls them on arrays, the compiled engine's loop on scalars, and both must draw the
line at the same place.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planar.acceptance import CERT, JUMP, ROUND, certified, on_course
from planar.events import HELD, NEAR, SINGULAR, status_of
from planar.results import Status

below = np.nextafter  # the float next to x towards y


def both_ways(f, *args):
    """f on scalars, and on arrays of those scalars: the two must agree element for element."""
    scalar = f(*args)
    array = f(*(np.array([a, a]) for a in args))
    assert array.shape == (2,) and (array == scalar).all()
    return scalar


# ----------------------------------------------------------------------------- certified


@given(sing=st.floats(1e-6, 1e6))
def test_a_move_of_cert_times_the_singularity_is_certified_and_no_more(sing):
    edge = CERT * sing
    assert both_ways(certified, edge, sing)
    assert not both_ways(certified, below(edge, np.inf), sing)
    assert both_ways(certified, below(edge, 0.0), sing)


def test_a_move_at_rounding_level_is_certified_whatever_the_singularity():
    for sing in (0.0, 1e-300, 1e-20):
        assert both_ways(certified, ROUND, sing)
        assert not both_ways(certified, below(ROUND, 1.0), sing)
    assert both_ways(certified, 0.0, 0.0)


def test_certified_takes_mixed_arrays_element_by_element():
    off = np.array([1e-3, 1e-3, 1e-14, 0.1])
    sing = np.array([0.3, 3e-3, 0.0, 1.0])
    assert certified(off, sing).tolist() == [True, False, True, True]


# ----------------------------------------------------------------------------- on_course


@given(move=st.floats(0.0, 1e6))
def test_a_move_of_jump_times_the_prediction_is_on_course_and_no_more(move):
    edge = JUMP * move + 1e-9
    assert both_ways(on_course, edge, move)
    assert not both_ways(on_course, below(edge, np.inf), move)


def test_a_correction_within_1e_9_is_on_course_even_without_a_predicted_move():
    assert both_ways(on_course, 1e-9, 0.0)
    assert both_ways(on_course, 0.0, 0.0)
    assert not both_ways(on_course, below(1e-9, 1.0), 0.0)


# ----------------------------------------------------------------------------- status_of


@pytest.mark.parametrize(
    "sing, status",
    [
        (1.0, Status.SOLVED),
        (NEAR, Status.SOLVED),
        (below(NEAR, 0.0), Status.NEAR_SINGULAR),
        (SINGULAR, Status.NEAR_SINGULAR),
        (below(SINGULAR, 0.0), Status.SINGULAR),
        (0.0, Status.SINGULAR),
    ],
)
def test_status_of_by_the_singularity_measure(sing, status):
    assert both_ways(status_of, sing) == status


@pytest.mark.parametrize("sing", [1.0, 1e-6, 0.0])
def test_a_redundant_joint_past_held_times_tol_is_inconsistent_whatever_the_measure(sing):
    tol = 1e-10
    assert both_ways(status_of, sing, HELD * tol, tol) == status_of(sing)
    assert both_ways(status_of, sing, below(HELD * tol, 1.0), tol) == Status.INCONSISTENT


def test_status_of_gives_only_the_statuses_of_a_converged_pose():
    sing = np.array([1.0, 1e-6, 0.0, 1.0, 1e-6, 0.0])
    red = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
    got = [Status(s) for s in status_of(sing, red, 1e-12)]
    assert got == [Status.SOLVED, Status.NEAR_SINGULAR, Status.SINGULAR] + [Status.INCONSISTENT] * 3
    assert all(s.posed for s in got[:3])


def test_without_a_tolerance_no_residual_is_inconsistent():
    assert status_of(1.0, red=1e300) == Status.SOLVED
