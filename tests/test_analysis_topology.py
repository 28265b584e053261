"""Topology recognition: a loop of four revolutes read as a four-bar, whichever link is driven."""

import numpy as np
import pytest

from planar.analysis import four_bar_links
from planar.mechanisms import CATALOGUE


@pytest.mark.parametrize("driver, role", [("crank", "crank"), ("rocker", "crank"), ("coupler", "coupler")])
def test_four_bar_links_are_read_from_any_loop_of_four_revolutes(driver, role):
    start = {"crank": 1.0, "rocker": 2.0, "coupler": 0.5}[driver]
    model = CATALOGUE["four_bar"](4, 2, 3, 3.5, driver=driver, start=start).compile()
    lengths, got = four_bar_links(model)
    # driving the rocker makes it the crank of the loop walked the other way round
    assert got == role
    want = {"crank": (4, 2, 3, 3.5), "rocker": (4, 3.5, 3, 2), "coupler": (4, 2, 3, 3.5)}[driver]
    np.testing.assert_allclose(lengths, want, rtol=1e-12)
    assert four_bar_links(CATALOGUE["slider_crank"]().compile()) is None
