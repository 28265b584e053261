"""A sweep's values against the events located on the way (:mod:`planar.sweep.located`): which
values sit on an event, the index an event gets, and which values lie past a limit the walk
met, on a line of inputs and round a periodic one.
"""

import numpy as np
import pytest

from planar.events import Event
from planar.mechanisms import four_bar
from planar.sweep.located import EVENT_TOL, at_events, event_index, on_event, past_limit, same_event

TURN = 2 * np.pi
MODEL = four_bar().compile()  # one angle input: its scaled distances are radians


def column(*u):
    return np.array(u, float)[:, None]


# ----------------------------------------------------------------------------- on an event


def test_values_within_event_tol_of_a_limit_or_bifurcation_sit_on_it():
    lim, bif, near = Event("limit", 1.0, 0), Event("bifurcation", 2.0, 0), Event("near_singular", 3.0, 0)
    U = column(1.0, 1.0 + EVENT_TOL / 2, 1.0 + 2 * EVENT_TOL, 2.0 - EVENT_TOL / 2, 3.0, 0.0)
    assert on_event(MODEL, U, [lim, bif, near]).tolist() == [True, True, False, True, False, False]
    assert at_events(MODEL, U, [lim, bif, near]) == {0: lim, 1: lim, 3: bif}
    assert not on_event(MODEL, U, []).any() and at_events(MODEL, U, []) == {}


def test_a_singular_position_passed_smoothly_counts_as_an_event_too():
    fold = Event("singular", 0.5, 0)
    assert on_event(MODEL, column(0.5, 0.6), [fold]).tolist() == [True, False]


def test_the_same_event_is_the_same_kind_at_the_same_input_to_1e_8():
    a = Event("limit", 1.0, 3)
    assert same_event(a, Event("limit", 1.0 + 5e-9, 7), MODEL)
    assert not same_event(a, Event("limit", 1.0 + 2e-8, 3), MODEL)
    assert not same_event(a, Event("bifurcation", 1.0, 3), MODEL)


# ----------------------------------------------------------------------------- event_index


@pytest.mark.parametrize(
    "u_star, index",
    [(0.05, 1), (0.1, 1), (0.1 - 1e-14, 1), (0.15, 2), (0.3, 3), (0.35, 4), (0.4, 4), (9.0, 4)],
)
def test_an_event_gets_the_first_value_at_or_past_it_walking_forwards(u_star, index):
    U = column(0.0, 0.1, 0.2, 0.3, 0.4)
    assert event_index(U, 0, 4, U[0], np.array([u_star])) == index


def test_an_event_gets_the_first_value_at_or_past_it_walking_backwards():
    U = column(0.4, 0.3, 0.2, 0.1, 0.0)
    assert event_index(U, 0, 4, U[0], np.array([0.25])) == 2
    assert event_index(U, 1, 4, U[1], np.array([0.05])) == 4
    assert event_index(U, 1, 3, U[1], np.array([0.2])) == 2


# ----------------------------------------------------------------------------- past_limit


def test_past_a_limit_on_a_line_of_inputs_is_strictly_beyond_it_in_its_direction():
    up = [(Event("limit", 1.0, 0), np.array([1.0]))]
    to = column(0.9, 1.0, 1.1, 5.0)
    assert past_limit(up, column(0.5), to).tolist() == [False, False, True, True]
    assert past_limit(up, column(1.0), to).tolist() == [False, False, True, True]  # from the limit itself
    assert not past_limit(up, column(1.2), to).any()  # starting beyond it
    down = [(Event("limit", 1.0, 0), np.array([-1.0]))]
    assert past_limit(down, column(1.5), column(1.1, 0.9, -3.0)).tolist() == [False, True, True]
    assert not past_limit([], column(0.0), to).any()


def test_past_a_limit_of_two_inputs_needs_both_beyond_it():
    lim = [(Event("limit", np.array([1.0, 1.0]), 0), np.array([1.0, 1.0]))]
    to = np.array([[2.0, 2.0], [2.0, 0.5], [0.5, 2.0]])
    assert past_limit(lim, np.zeros((1, 2)), to).tolist() == [True, False, False]


# A rocking input between limits at -1 (met going down) and 1 (met going up), periodic in a turn.
ROCKING = [(Event("limit", 1.0, 0), np.array([1.0])), (Event("limit", -1.0, 0), np.array([-1.0]))]


@pytest.mark.parametrize(
    "u_to, past",
    [
        (0.5, False),  # inside the range, either way round
        (0.5 + TURN, False),  # the same pose a turn on
        (0.5 - 3 * TURN, False),
        (1.5, True),  # past the upper limit one way, past the lower the other
        (1.5 + TURN, True),
        (-1.5, True),
        (-1.5 - 2 * TURN, True),
    ],
)
def test_past_a_limit_round_a_periodic_input_is_past_it_both_ways_round(u_to, past):
    assert past_limit(ROCKING, column(0.0), column(u_to), (TURN, None)).tolist() == [past]


def test_round_a_periodic_input_one_limit_leaves_the_other_way_free():
    upper = ROCKING[:1]
    assert past_limit(upper, column(0.0), column(1.5), None).tolist() == [True]
    assert past_limit(upper, column(0.0), column(1.5), (TURN, None)).tolist() == [False]
