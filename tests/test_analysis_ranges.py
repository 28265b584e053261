"""Motion ranges: every interval of the one input where the mechanism assembles."""

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

import planar
from planar.analysis.ranges import motion_range, runs, swept_ranges
from planar.mechanisms import four_bar, geared_five_bar, slider_crank
from planar.results import POSED, Status
from tests import oracles
from tests.strategies import build, linkages

REF = oracles.load_reference()
LIMIT_CASES = sorted(k for k in REF if k.startswith("slider_limits_"))


@pytest.mark.parametrize("case", LIMIT_CASES)
def test_slider_crank_limits_of_the_reference(case):
    i, expected = REF[case]["inputs"], REF[case]["expected"]
    angle = i["driver"] != "slider"
    want = expected["feasible_intervals_deg"] if angle else expected["feasible_intervals_r1"]
    # sketch inside the first interval of the closed form (independent of the expected data)
    first = oracles.slider_crank_limits(i["crank"], i["coupler"], i["offset"], i["driver"])[0]
    m = slider_crank(i["crank"], i["coupler"], offset=i["offset"], driver=i["driver"], start=float(np.mean(first)))
    got = motion_range(m)
    if angle:
        got = [tuple(np.degrees(g)) for g in got]
    assert len(got) == len(want)  # the two seed prints that merge intervals come out as two
    np.testing.assert_allclose(got, want, atol=1e-10 * (1 if angle else max(i["crank"], i["coupler"])))


def test_four_bar_ranges_against_the_closed_form():
    for dims in [(4, 3, 3, 2.5), (4, 3, 1, 3.5)]:  # triple rocker; Grashof double-rocker
        want = oracles.four_bar_input_limits(*dims)
        m = four_bar(*dims, start=float(np.mean(want[0])))
        np.testing.assert_allclose(motion_range(m), want, atol=1e-10)
    assert motion_range(four_bar(4, 2, 3, 4)) == ((-np.pi, np.pi),)  # crank-rocker: a full turn


def test_a_sweep_reads_the_same_ends_as_far_as_it_went():
    m = four_bar(4, 3, 3, 2.5, start=0.3)
    (lo, hi), = motion_range(m)
    res = m.sweep(np.linspace(0.0, 2 * np.pi, 73))
    got = swept_ranges(res)
    # up from 0 to the upper limit; back in from the lower limit (one turn on) to 2 pi
    assert len(got) == 2
    np.testing.assert_allclose([got[0][1], got[1][0]], [hi, lo + 2 * np.pi], atol=1e-9)
    assert got[0][0] == 0.0 and got[1][1] == 2 * np.pi
    assert swept_ranges(m.sweep([0.0, 0.1])) == [(0.0, 0.1)]


def test_runs_of_a_mask():
    assert runs([True, False, False, True, True]) == [(0, 0), (3, 4)]
    assert runs([]) == [] and runs([False]) == []


def test_a_geared_five_bars_stretches_over_the_same_inputs_are_ranges_of_their_own():
    # past its limit at 4.457 the crank re-enters a stretch that reaches back to 4.3737 and a
    # narrow one [5.6071, 5.6904] over the same inputs: every value of the turn assembles on
    # one or another, and that read as one run of values had been a full turn
    m = geared_five_bar(ground=17.415047727859392, gear_radius_2=3.721527582006219,
                        gear_radius_4=4.845214131881709, link_5=14.43467129449753, crossed=True,
                        start=-0.18091610142973247)
    wrap = lambda u: (u + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    ranges = np.array(motion_range(m))
    assert len(ranges) == 3
    np.testing.assert_allclose(np.sort(wrap(ranges[:, 0])), np.sort(wrap(np.array([-3.8066, 4.3737, 5.6071]))), atol=1e-4)
    assert np.any(np.abs(wrap(ranges[:, 1] - 4.457004808008)) < 1e-9)  # the sketch's stretch ends at its limit
    assert np.any(np.abs(wrap(ranges[:, 1] - 5.690360105685)) < 1e-9)


def test_a_limit_on_a_sample_of_the_turn_is_the_end_of_its_range():
    # the limit 3.66519 falls on the 420th of 720 samples: its event was not read as the end
    # (rounding put it just outside the pair of samples), and the range ended half a sample on
    got = motion_range(slider_crank(2, 1.5, offset=0.5))
    np.testing.assert_allclose(got, oracles.slider_crank_limits(2, 1.5, 0.5, "crank"), rtol=0, atol=1e-9)


@settings(max_examples=6)
@given(desc=st.one_of(linkages(), linkages(max_dyads=2, rolling=True)))
@example(desc={"pivot": (0.0, 0.5), "crank_tip": (0.0, 0.0), "dyads": [("RRP", 0, (0.0, 0.0), (1.0, 0.0), 1, (0.0, 0.0), 0.0)],
               "rolling": ("gear", 0, (1.0, 0.0), (0.0, 0.0), 0, (0.0, 2.0), 0.5, False, 0.0, "left")})
def test_motion_range_agrees_with_the_sweeps_from_the_sketch_on_random_linkages(desc):
    """Random linkages, some closed by a gear or a rack: an interval that holds the sketch's
    input (whole turns on or not; a geared linkage's may overlap others) is posed inside by the
    sweep from the sketch, and that sweep a little past each of its ends meets the limit there
    or leaves the branch; a full turn meets no limit over two turns each way. A sketch near a
    singular position is an ambiguous start (docs/hardening.md) and is left out."""
    try:
        model = build(desc)[0].compile()
        R = motion_range(model)
    except planar.PlanarError:
        assume(False)
    u0 = float(model.u0[0])
    assume(model.sweep([u0]).status[0] == Status.SOLVED)
    if R == ((-np.pi, np.pi),):
        res = model.sweep(u0 + np.linspace(-4 * np.pi, 4 * np.pi, 161))
        assert not [e for e in res.events if e.kind == "limit"]
        return
    turns = 2 * np.pi * np.arange(-20, 21)
    held = [(lo + k, hi + k) for lo, hi in R for k in turns if lo + k - 1e-9 <= u0 <= hi + k + 1e-9]
    assert held, (u0, R)
    why = []
    for lo, hi in held:
        inside = model.sweep(np.linspace(lo, hi, 23)[1:-1])
        ends = []
        for end, way in ((hi, 1), (lo, -1)):
            past = model.sweep([u0, end + way * 1e-3 * max(1.0, hi - lo)])
            met = [float(np.ravel(e.input)[0]) for e in past.events if e.kind == "limit"]
            ends.append(any(abs(v - end) <= 1e-8 * max(1.0, abs(end)) for v in met) or past.status[1] != Status.SOLVED)
        if POSED[inside.status].all() and all(ends):
            return
        why.append((lo, hi, inside.status.tolist(), ends))
    raise AssertionError(f"no interval holding the sketch's input agrees with the sweeps: {why}")
