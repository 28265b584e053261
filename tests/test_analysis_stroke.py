"""stroke: extremes, stroke and time ratio against closed forms (tests/oracles.py for the offset
slider-crank; below, the crank-rocker's rocker swing, whose extremes are where crank and
coupler line up: |O2 B| = r3 + r2 or r3 - r2)."""

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

import planar
from planar.analysis import stroke
from planar.mechanisms import four_bar, inverted_slider_crank, slider_crank
from tests.oracles import slider_crank_stroke, slider_crank_time_ratio

# each stroke sweeps a turn and refines in one or two more sweeps: about 0.2 s an example
STROKES = settings(max_examples=25, deadline=None)
FAST = {"max_step": 0.5}


@STROKES
@given(r2=st.floats(0.5, 3), extra=st.floats(0.5, 5), efrac=st.floats(-0.9, 0.9), th1=st.floats(-np.pi, np.pi))
@example(r2=0.5, extra=1.0, efrac=0.0, th1=0.0)  # an extreme on the first sample
@example(r2=0.5, extra=1.0, efrac=0.0, th1=7e-306)  # ... where the rate is a subnormal number
def test_slider_crank_stroke_time_ratio_and_extremes(r2, extra, efrac, th1):
    r3 = r2 + extra
    e = efrac * (r3 - r2)
    s = stroke(slider_crank(r2, r3, offset=e, slide_angle=th1, start=th1), "travel:slide", **FAST)
    assert abs(s.stroke - slider_crank_stroke(r2, r3, e)) <= 1e-9 * r3
    ratio = slider_crank_time_ratio(r2, r3, e)  # forward over return: below 1 for e < 0
    assert abs(s.time_ratio - max(ratio, 1 / ratio)) <= 1e-8 * s.time_ratio
    # extremes where crank and coupler are in line: extended (farthest), folded (nearest)
    at_max = th1 + np.arcsin(e / (r2 + r3))
    at_min = th1 + np.pi + np.arcsin(e / (r3 - r2))
    for got, want in ((s.input_at_maximum, at_max), (s.input_at_minimum, at_min)):
        assert abs(np.angle(np.exp(1j * (got - want)))) <= 1e-10
    assert len(s.extremes) == 2


def rocker_extremes(r1, r2, r3, r4):
    """Crank and rocker angles at the crank-rocker's two limit positions (B above O2 O4)."""
    out = []
    for d, folded in ((r3 + r2, False), (r3 - r2, True)):
        at_O2 = np.arccos((d**2 + r1**2 - r4**2) / (2 * d * r1))  # angle B O2 O4
        at_O4 = np.arccos((r1**2 + r4**2 - d**2) / (2 * r1 * r4))  # angle O2 O4 B
        out.append((at_O2 + (np.pi if folded else 0.0), np.pi - at_O4))
    return out


@STROKES
@given(others=st.tuples(st.floats(1, 5), st.floats(1, 5), st.floats(1, 5)), frac=st.floats(0, 1))
def test_crank_rocker_swing_and_time_ratio(others, frac):
    # a crank-rocker clear of the change point: the crank shortest, s + l < p + q - 0.1 l
    r1, r3, r4 = others
    p, q, l = sorted(others)
    longest_crank = min(p, p + q - 1.1 * l)
    assume(longest_crank > 0.3)
    r2 = 0.2 + frac * (longest_crank - 0.3)
    r = (r1, r2, r3, r4)
    s = stroke(four_bar(*r), "angle:rocker", **FAST)
    (th2_ext, th4_ext), (th2_fold, th4_fold) = rocker_extremes(*r)
    assert abs(s.stroke - abs(th4_fold - th4_ext)) <= 1e-9
    forward = (th2_fold - th2_ext) % (2 * np.pi)
    ratio = max(forward, 2 * np.pi - forward) / min(forward, 2 * np.pi - forward)
    assert abs(s.time_ratio - ratio) <= 1e-8 * ratio
    assert abs(np.angle(np.exp(1j * (s.input_at_minimum - th2_ext)))) <= 1e-10
    assert abs(np.angle(np.exp(1j * (s.input_at_maximum - th2_fold)))) <= 1e-10


def test_a_sweep_result_gives_the_same_stroke():
    m = slider_crank()
    res = m.sweep(np.linspace(0, 2 * np.pi, 181), **FAST)
    a, b = stroke(res, "x:B", **FAST), stroke(m, "x:B", **FAST)
    assert abs(a.stroke - b.stroke) < 1e-12 and abs(a.input_at_minimum - b.input_at_minimum) < 1e-10


def test_any_back_and_forth_output_of_any_mechanism():
    # the slotted link of an inverted slider-crank (a quick-return): its swing and time ratio
    s = stroke(inverted_slider_crank(4.0, 2.0), "angle:link3", **FAST)
    swing = 2 * np.arcsin(2.0 / 4.0)  # the link is tangent to the crank circle at its extremes
    assert abs(s.stroke - swing) < 1e-9
    assert abs(s.time_ratio - (np.pi + swing) / (np.pi - swing)) < 1e-8


@pytest.mark.parametrize("source, output, error, match", [
    (four_bar(4, 3, 3, 3, start=0.5), "angle:rocker", planar.AssemblyError, "does not turn fully"),
    (four_bar(), "angle:crank", planar.InputError, "does not come back"),
    (slider_crank(driver="slider"), "angle:crank", planar.InputError, "one input angle"),
    (four_bar(), "z:rocker", planar.InputError, "unknown output"),
])
def test_refusals_name_the_cause(source, output, error, match):
    with pytest.raises(error, match=match):
        stroke(source, output, **FAST)


def test_a_sweep_not_over_one_turn_is_refused():
    with pytest.raises(planar.InputError, match="exactly one turn"):
        stroke(four_bar().sweep(np.linspace(0, np.pi, 10)), "angle:rocker")
