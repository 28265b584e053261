"""geared_five_bar against the closed form of tests/oracles.py (the seed's loop and rolling
rows, followed from the reference configuration) over its motion range, both configurations."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import planar
from planar.mechanisms import geared_five_bar
from tests.oracles import geared_five_bar as g5_oracle
from tests.test_mechanisms_four_bar import assert_angles, assert_close, run_in, rate


def mirrored(r1, R2, R4, r5, th2, w2, a2):
    """The closed form for the lower reference configuration: the mirror image in the x axis
    of the upper one driven by -th2 (the oracle draws the upper configuration only)."""
    o = g5_oracle(r1, R2, R4, r5, -th2, -w2, -a2)
    return {k: -v for k, v in o.items()}


def jacobian_det(o, R2, R4, r5):
    """det of the closed form's rate equations (two loop rows and the rolling row in w3, w4,
    w5), normalised: 0 where the mechanism is at a singular position."""
    r3, g = R2 + R4, R4 / R2
    t3, t4, t5 = o["th3"], o["th4"], o["th5"]
    M = np.stack([np.stack([-r3 * np.sin(t3), -R4 * np.sin(t4), r5 * np.sin(t5)], -1),
                  np.stack([r3 * np.cos(t3), R4 * np.cos(t4), -r5 * np.cos(t5)], -1),
                  np.stack(np.broadcast_arrays(1 + g, -g, 0.0 * t3), -1)], -2)
    return np.linalg.det(np.nan_to_num(M)) / (r3 * R4 * r5 * (1 + 2 * g)) * np.isfinite(t5)


# the default continuation step is needed here (see below), so a sweep costs about 0.3 s
@settings(max_examples=20, deadline=None)
@given(r1=st.floats(2, 10), R2=st.floats(0.5, 3), R4=st.floats(0.5, 3), r5=st.floats(2, 10),
       crossed=st.booleans(), w2=rate, a2=rate)
def test_matches_closed_form_over_its_range(r1, R2, R4, r5, crossed, w2, a2):
    reach = R2 + 2 * R4
    assume(abs(r1 - r5) + 0.2 < reach < r1 + r5 - 0.2)  # the reference configuration assembles
    closed = mirrored if crossed else g5_oracle
    grid = np.linspace(-np.pi / 2, np.pi / 2, 61)
    with np.errstate(invalid="ignore"):
        o = closed(r1, R2, R4, r5, grid, 1.0, 0.0)
        good = np.abs(jacobian_det(o, R2, R4, r5)) > 0.05  # clear of singular positions
    values = run_in(grid, good)
    assume(values is not None and values[0] <= 0 <= values[-1])
    m = geared_five_bar(r1, R2, R4, r5, crossed=crossed)
    # the default continuation step: with max_step 0.2 or 0.5 the sweep can land on another
    # branch of the same determinant sign and report it solved (see the report of issue 3)
    res = m.sweep(values, velocity=w2, acceleration=a2)
    assert res.ok.all()
    o = closed(r1, R2, R4, r5, values, w2, a2)
    w = max(abs(w2), *(np.abs(o[f"w{k}"]).max() for k in "345"))
    a = max(abs(a2), w**2, *(np.abs(o[f"a{k}"]).max() for k in "345"))
    for body, k in (("arm", "3"), ("gear4", "4"), ("link5", "5")):
        assert_angles(res.angle(body), o[f"th{k}"], f"th{k}")
        assert_close(res.omega(body), o[f"w{k}"], w, 1e-8, f"w{k}")
        assert_close(res.alpha(body), o[f"a{k}"], a, 1e-8, f"a{k}")
    L = max(r1, r5, R2 + 2 * R4)
    C = (R2 + R4) * np.exp(1j * o["th3"]) + R4 * np.exp(1j * o["th4"])
    assert_close(res.position("C"), np.stack([C.real, C.imag], -1), L, 1e-9, "C")


def test_a_start_past_a_limit_is_refused():
    with pytest.raises(planar.AssemblyError, match="cannot reach gear angle"):
        geared_five_bar(2, 2, 0.5, 4, start=-2.0)  # its gear 2 stops near -55 deg


def test_the_reference_configuration_must_assemble():
    with pytest.raises(planar.AssemblyError, match="reference configuration"):
        geared_five_bar(ground=20.0)
