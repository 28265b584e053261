"""grashof against tests/oracles.py: the class, and whether the crank turns (its motion range)."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import planar
from planar.analysis import grashof
from planar.mechanisms import four_bar
from tests.oracles import four_bar_input_limits, grashof as grashof_oracle

length = st.floats(0.1, 10.0)


@settings(max_examples=200, deadline=None)
@given(r=st.tuples(length, length, length, length))
def test_class_and_full_turn_match_the_closed_forms(r):
    s, p, q, l = sorted(r)
    assume(abs(s + l - p - q) > 1e-9 * l and s + p + q > l)  # off the change point; assemblable
    g = grashof(*r)
    assert g.kind == grashof_oracle(*r)
    assert np.isclose(g.excess, s + l - p - q)
    assert g.input_turns == (four_bar_input_limits(*r) == [(-np.pi, np.pi)])


@pytest.mark.parametrize("r, kind, turns", [
    ((4, 2, 3, 4), "crank-rocker", {"crank": True, "coupler": False, "rocker": False}),
    ((2, 4, 3.5, 3), "drag-link", {"crank": True, "coupler": True, "rocker": True}),
    ((4, 3, 2, 4), "double-rocker", {"crank": False, "coupler": True, "rocker": False}),
    ((4, 4, 3, 2), "rocker-crank", {"crank": False, "coupler": False, "rocker": True}),
    ((4, 3, 3, 3), "triple-rocker", {"crank": False, "coupler": False, "rocker": False}),
    ((4, 2, 4, 2), "change-point", {"crank": True, "coupler": False, "rocker": True}),
])
def test_every_class_and_which_link_turns(r, kind, turns):
    for driver, expected in turns.items():
        g = grashof(*r, driver=driver)
        assert g.kind == kind and g.input_turns == expected, driver


@pytest.mark.parametrize("r, driver", [((4, 3, 2, 4), "coupler"), ((2, 4, 3.5, 3), "coupler"),
                                       ((2, 4, 3.5, 3), "rocker"), ((4, 4, 3, 2), "rocker")])
def test_the_links_said_to_turn_do_turn_in_a_sweep(r, driver):
    m = four_bar(*r, driver=driver, start=_assembling_start(r, driver))
    u0 = m.compile().u0[0]
    assert m.sweep(u0 + np.linspace(0, 2 * np.pi, 73)).ok.all()


def _assembling_start(r, driver):
    for start in np.linspace(-np.pi, np.pi, 37):
        try:
            four_bar(*r, driver=driver, start=start)
            return start
        except planar.AssemblyError:
            pass
    raise AssertionError("no assembling start")


def test_bad_lengths_and_driver_are_refused():
    with pytest.raises(planar.ModelError, match="coupler"):
        grashof(4, 2, -3, 4)
    with pytest.raises(planar.ModelError, match="driver"):
        grashof(4, 2, 3, 4, driver="ground")
