"""The test oracles against the reference data (tests/data/textbook_reference.json) and against
finite differences of their own positions.

Tolerances (spec README): positions and angles to 1e-9 relative to the largest link, rates to
1e-8 relative. Finite differences: the input is swept as theta(t) = th + w t + a t^2 / 2 and the
outputs are differentiated at t = 0 with fourth-order central stencils; relative tolerance 1e-6.
"""
import json

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from tests.oracles import (
    REFERENCE_PATH, four_bar, four_bar_input_limits, four_bar_instant_centres,
    four_bar_transmission_angle, geared_five_bar, grashof, inverted_slider_crank,
    inverted_slider_crank_link3_driven, load_reference, open_chain, slider_crank,
    slider_crank_coupler_driven, slider_crank_limits, slider_crank_slider_driven,
    slider_crank_stroke, slider_crank_time_ratio,
)

REF = load_reference()
rad = np.radians
FD = settings(max_examples=200, deadline=None)


COVERED = set()  # ids of the reference cases some test runs


def cases(mechanism, *must_have):
    """Parametrise over the reference cases of one mechanism whose inputs or expected values
    have all the keys (and record them for test_every_reference_case_is_checked)."""
    found = [c for c in REF.values() if c["mechanism"] == mechanism
             and all(k in c["inputs"] or k in c["expected"] for k in must_have)]
    assert found, (mechanism, must_have)
    COVERED.update(c["id"] for c in found)
    return pytest.mark.parametrize("case", found, ids=[c["id"] for c in found])


# ----------------------------------------------------------------------------- comparisons

def wrap(t):
    return np.angle(np.exp(1j * np.asarray(t, dtype=float)))


def check_angle(actual, expected_deg, what=""):
    err = np.max(np.abs(wrap(np.asarray(actual) - rad(expected_deg))))
    assert err <= 1e-9, f"{what}: angle off by {err:.3g} rad"


def check_length(actual, expected, scale, what=""):
    err = np.max(np.abs(np.asarray(actual) - np.asarray(expected)))
    assert err <= 1e-9 * scale, f"{what}: off by {err:.3g} (scale {scale})"


def check_rate(actual, expected, what=""):
    expected = np.asarray(expected, dtype=float)
    err = np.max(np.abs(np.asarray(actual) - expected))
    assert err <= 1e-8 * max(np.max(np.abs(expected)), 1e-300), f"{what}: off by {err:.3g}"


def cplx(xy):
    """(..., 2) points as complex numbers."""
    return np.ascontiguousarray(xy, dtype=float).view(complex)[..., 0]  # exact, even for inf


def sigma_of(assembly):
    return 1 if "left" in assembly else -1


# ----------------------------------------------------------------------------- reference cases

@cases("four_bar", "w2")
def test_four_bar_reference(case):
    i, x = case["inputs"], case["expected"]
    cp = i.get("coupler_point")
    pq = (cp["distance_from_A"] * np.exp(1j * rad(cp["angle_from_AB_deg"]))) if cp else None
    out = four_bar(i["r1"], i["r2"], i["r3"], i["r4"], rad(i["th2_deg"]), i["w2"], i["a2"],
                   th1=rad(i["th1_deg"]), sigma=sigma_of(i["assembly"]),
                   p=None if pq is None else pq.real, q=None if pq is None else pq.imag)
    scale = max(i["r1"], i["r2"], i["r3"], i["r4"])
    for key in ("th3", "th4"):
        check_angle(out[key], x[key + "_deg"], key)
    for key in ("w3", "w4", "a3", "a4", "C_vel", "C_acc"):
        if key in x:
            check_rate(out[key], x[key], key)
    for key in ("A", "B", "C"):
        if key in x:
            check_length(out[key], x[key], scale, key)
    assert ("C" in x) == (cp is not None)


@cases("four_bar", "I13")
def test_four_bar_instant_centres_reference(case):
    i, x = case["inputs"], case["expected"]
    out = four_bar_instant_centres(i["r1"], i["r2"], i["r3"], i["r4"], rad(i["th2_deg"]),
                                   th1=rad(i["th1_deg"]), sigma=sigma_of(i["assembly"]))
    assert set(out) == set(x)
    for key in x:
        check_length(out[key], x[key], max(i["r1"], i["r2"], i["r3"], i["r4"]), key)


@cases("slider_crank", "driver")
def test_slider_crank_reference(case):
    i, x = case["inputs"], case["expected"]
    r2, r3, e, th1 = i["crank"], i["coupler"], i["offset"], rad(i["th1_deg"])
    scale = max(r2, r3, abs(e))
    if i["driver"] == "crank":
        assert "r1 > 0" in i["assembly"]
        out = slider_crank(r2, r3, rad(i["th2_deg"]), i["w2"], i["a2"], e, th1, sigma=1)
        check_angle(out["th3"], x["th3_deg"], "th3")
        check_length(out["r1"], x["slider_r1"], scale, "r1")
        for key, ref in (("w3", "w3"), ("a3", "a3"), ("r1_v", "slider_v"), ("r1_a", "slider_a")):
            check_rate(out[key], x[ref], key)
    elif i["driver"] == "coupler":
        # The seed ran sigma = +1: the larger-r1 root.
        out = slider_crank_coupler_driven(r2, r3, rad(i["th3_deg"]), i["w3"], i["a3"], e, th1,
                                          sigma=1)
        check_angle(out["th2"], x["th2_deg"], "th2")
        check_length(out["r1"], x["slider_r1"], scale, "r1")
        for key, ref in (("w2", "w2"), ("a2", "a2"), ("r1_v", "slider_v"), ("r1_a", "slider_a")):
            check_rate(out[key], x[ref], key)
    else:
        # expected: crank pin left of O2 -> B (sigma = +1, th2 near 119 deg); other_assembly: right.
        assert i["driver"] == "slider"
        for sigma, ref in ((1, x), (-1, case["other_assembly"])):
            out = slider_crank_slider_driven(r2, r3, i["slider_r1"], i["slider_v"],
                                             i["slider_a"], e, th1, sigma=sigma)
            for key in ("th2", "th3"):
                check_angle(out[key], ref[key + "_deg"], f"{key} sigma={sigma}")
            for key in ("w2", "w3", "a2", "a3"):
                check_rate(out[key], ref[key], f"{key} sigma={sigma}")


@cases("slider_crank", "stroke")
def test_slider_crank_offset_stroke_reference(case):
    # Student-report form: crank pivot at the origin, slider pin on y = offset: the seed form
    # with th1 = 0, so the slider's x is r1.
    i, x = case["inputs"], case["expected"]
    r2, r3, e = i["crank"], i["coupler"], i["offset"]
    out = slider_crank(r2, r3, rad(i["th2_deg"]), i["w2"], i["a2"], offset=e, sigma=1)
    check_length(out["r1"], x["slider_x"], max(r2, r3), "slider_x")
    check_angle(out["th3"], x["th3_deg"], "th3")
    for key, ref in (("r1_v", "slider_v"), ("r1_a", "slider_a"), ("w3", "w3"), ("a3", "a3")):
        check_rate(out[key], x[ref], key)
    check_length(slider_crank_stroke(r2, r3, e), x["stroke"], max(r2, r3), "stroke")
    check_rate(slider_crank_time_ratio(r2, r3, e), x["time_ratio"], "time ratio")


def _driver_input_assembles(i, values):
    """Whether the slider-crank of a limits case assembles at each input value (a sweep)."""
    r2, r3, e = i["crank"], i["coupler"], i["offset"]
    if i["driver"] == "crank":
        return np.isfinite(slider_crank(r2, r3, values, offset=e)["r1"])
    if i["driver"] == "coupler":
        return np.isfinite(slider_crank_coupler_driven(r2, r3, values, offset=e)["r1"])
    return np.isfinite(slider_crank_slider_driven(r2, r3, values, offset=e)["th2"])


def _inside(intervals, values, margin):
    return np.any([(values >= lo + margin) & (values <= hi - margin) for lo, hi in intervals]
                  + [np.zeros_like(values, dtype=bool)], axis=0)


def _near_edge(intervals, values, margin, period=None):
    ends = np.ravel(intervals)
    d = values[:, None] - ends[None, :]
    if period:
        d = (d + period / 2) % period - period / 2
    return np.any(np.abs(d) < margin, axis=1)


@cases("slider_crank_limits")
def test_slider_crank_limits_reference(case):
    i, x = case["inputs"], case["expected"]
    got = slider_crank_limits(i["crank"], i["coupler"], i["offset"], i["driver"], rad(i["th1_deg"]))
    slider = i["driver"] == "slider"
    want = x["feasible_intervals_r1" if slider else "feasible_intervals_deg"]
    assert len(got) == len(want)
    for (lo, hi), (wlo, whi) in zip(got, want):
        if slider:
            check_length([lo, hi], [wlo, whi], max(i["crank"], i["coupler"]), "travel limits")
        else:
            check_angle([lo, hi], [wlo, whi], "angle limits")
    # The intervals are exactly where the oracles assemble (dense sweep, away from the ends).
    if slider:
        values = np.linspace(-1.2 * got[-1][1], 1.2 * got[-1][1], 4001)
        inside = _inside(got, values, 0.0)
        edge = _near_edge(got, values, 1e-9)
    else:
        values = np.linspace(-np.pi, np.pi, 7201)
        inside = _inside(got, values, 0.0) | _inside(got, values + 2 * np.pi, 0.0)
        edge = _near_edge(got, values, 1e-9, period=2 * np.pi)
    ok = _driver_input_assembles(i, values)
    assert np.array_equal(ok[~edge], inside[~edge])


@cases("inverted_slider_crank")
def test_inverted_slider_crank_reference(case):
    # Both seed examples ran sigma = +1: r3 > 0 for the crank driver, the larger-r3 root for
    # the link-3 driver (18.85 here; the other root, 17.40, is near example 1's pose).
    i, x = case["inputs"], case["expected"]
    scale = max(i["r1"], i["r2"], abs(i["r4"]))
    if i["driver"] == "crank":
        out = inverted_slider_crank(i["r1"], i["r2"], i["r4"], rad(i["th2_deg"]), i["w2"],
                                    i["a2"], rad(i["th1_deg"]), sigma=1)
        check_angle(out["th3"], x["th3_deg"], "th3")
        rates = ("w3", "a3", "r3_v", "r3_a")
    else:
        assert i["driver"] == "link3"
        out = inverted_slider_crank_link3_driven(i["r1"], i["r2"], i["r4"], rad(i["th3_deg"]),
                                                 i["w3"], i["a3"], rad(i["th1_deg"]), sigma=1)
        check_angle(out["th2"], x["th2_deg"], "th2")
        rates = ("w2", "a2", "r3_v", "r3_a")
    check_length(out["r3"], x["r3"], scale, "r3")
    for key in rates:
        check_rate(out[key], x[key], key)


@cases("geared_five_bar")
def test_geared_five_bar_reference(case):
    i, x = case["inputs"], case["expected"]
    assert i["arm_r3"] == i["R2"] + i["R4"]
    out = geared_five_bar(i["r1"], i["R2"], i["R4"], i["r5"], rad(i["th2_deg"]), i["w2"])
    for key in ("th3", "th4", "th5"):
        check_angle(out[key], x[key + "_deg"], key)
    for key in ("w3", "w4", "w5"):
        check_rate(out[key], x[key], key)
    check_angle([out["th30"], out["th40"], out["th50"]], x["reference_angles_deg"], "reference")


@cases("open_chain")
def test_open_chain_reference(case):
    i, x = case["inputs"], case["expected"]
    out = open_chain(i["lengths"], rad(i["abs_angles_deg"]), i["abs_angular_velocities"],
                     i["abs_angular_accelerations"])
    scale = max(i["lengths"])
    check_length(out["tip"], x["tip"], scale, "tip")
    check_length(out["magnitudes"][0], x["magnitudes"][0], scale, "|tip|")
    for key in ("tip_vel", "tip_acc"):
        check_rate(out[key], x[key], key)
    for k in (1, 2):
        check_rate(out["magnitudes"][k], x["magnitudes"][k], f"magnitude {k}")
    check_angle(out["angles"], x["angles_deg"], "angles")


def test_every_reference_case_is_checked():
    assert COVERED == set(REF)


def test_reference_copy_is_sane():
    # Every case survives load_reference (ids are unique) and the mechanisms are the known ones.
    raw = json.loads(REFERENCE_PATH.read_text(encoding="utf-8"))["cases"]
    assert len(raw) == len(REF) == 27
    assert {c["mechanism"] for c in REF.values()} == {
        "four_bar", "slider_crank", "slider_crank_limits", "inverted_slider_crank",
        "geared_five_bar", "open_chain"}


# ----------------------------------------------------------------------------- finite differences

STENCIL = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
STEP = 2e-4  # how far the input moves per stencil step (rad; link lengths for a slider input)
# Least distance (in the input) from a toggle or limit position: near a square-root singularity
# at distance d the stencil's error is about (STEP / d)^4 relative, so 50 steps keep it ~1e-7;
# the round-off of the second difference is ~1e-7 relative at this STEP.
MARGIN = 50 * STEP


def swept(x, rate, acc, unit=1.0):
    """Input at the stencil times and the time step: x(t) = x + rate t + acc t^2 / 2, with a
    step that moves the input by about STEP * unit."""
    h = STEP * unit / max(abs(rate), np.sqrt(abs(acc) * unit))
    t = STENCIL * h
    return x + rate * t + acc * t**2 / 2, h


def derivs(values, h, angle=False):
    """First and second time derivatives at the middle of the stencil (axis 0), fourth order."""
    v = np.asarray(values, dtype=float)
    if angle:  # differentiate a continuous angle, whatever the wrapping
        v = v[2] + wrap(v - v[2])
    d1 = (v[0] - 8 * v[1] + 8 * v[3] - v[4]) / (12 * h)
    d2 = (-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h**2)
    return d1, d2


def check_fd(pairs, what=""):
    """pairs: (finite difference, analytic) in common units; relative to the largest analytic
    value of the group, so a quantity passing through zero is judged on the group's scale."""
    scale = max(np.max(np.abs(an)) for _, an in pairs)
    for k, (fd, an) in enumerate(pairs):
        err = np.max(np.abs(np.asarray(fd) - an))
        assert err <= 1e-6 * scale, f"{what} #{k}: fd {fd} vs {an} (scale {scale:.3g})"


lengths = st.floats(0.5, 5.0)
angles = st.floats(-np.pi, np.pi)
signs = st.sampled_from([1, -1])
rates = st.one_of(st.floats(-20.0, -0.1), st.floats(0.1, 20.0))  # zero would leave no scale
accels = st.floats(-100.0, 100.0)


@FD
@given(r1=lengths, r2=lengths, th1=angles, th2=angles, at_A=st.floats(0.25, np.pi - 0.75),
       at_O4=st.floats(0.0, 1.0), sigma=signs, w=rates, a=accels, p=st.floats(-3, 3),
       q=st.floats(-3, 3))
def test_four_bar_finite_differences(r1, r2, th1, th2, at_A, at_O4, sigma, w, a, p, q):
    # Assemblable by construction: the triangle A-B-O4 is built from its side L = |A - O4| and
    # its angles at A and O4 (each, and the transmission angle at B, >= 0.25 rad from 0 and pi).
    L = abs(r1 * np.exp(1j * th1) - r2 * np.exp(1j * th2))
    gamma = 0.25 + at_O4 * (np.pi - 0.75 - at_A)
    mu = np.pi - at_A - gamma
    r3, r4 = L * np.sin(gamma) / np.sin(mu), L * np.sin(at_A) / np.sin(mu)
    # L moves at most r2 per radian of input; it must stay inside [|r3 - r4|, r3 + r4] and off 0.
    assume(min(L - abs(r3 - r4), r3 + r4 - L, L) / r2 >= MARGIN)
    th, h = swept(th2, w, a)
    pos = four_bar(r1, r2, r3, r4, th, th1=th1, sigma=sigma, p=p, q=q)
    an = four_bar(r1, r2, r3, r4, th2, w, a, th1=th1, sigma=sigma, p=p, q=q)
    assert np.all(np.isfinite(pos["th3"]))
    # Position sanity: the loop closes and B is on the side sigma says.
    A, B = cplx(an["A"]), cplx(an["B"])
    O4 = r1 * np.exp(1j * th1)
    assert abs(abs(B - A) - r3) < 1e-12 * L and abs(abs(B - O4) - r4) < 1e-12 * L
    assert np.sign(np.imag(np.conj(O4 - A) * (B - A))) == sigma
    d3, d4, dC = derivs(pos["th3"], h, True), derivs(pos["th4"], h, True), derivs(pos["C"], h)
    s = max(r1, r2, r3, r4)
    check_fd([(s * d3[0], s * an["w3"]), (s * d4[0], s * an["w4"]), (dC[0], an["C_vel"]),
              (s * w, s * w)], "velocity")
    check_fd([(s * d3[1], s * an["a3"]), (s * d4[1], s * an["a4"]), (dC[1], an["C_acc"]),
              (s * w * w, s * w * w), (s * a, s * a)], "acceleration")


@FD
@given(r2=lengths, th1=angles, th2=angles, e=st.floats(-3, 3), along=st.floats(0.5, 5.0),
       sigma=signs, w=rates, a=accels)
def test_slider_crank_finite_differences(r2, th1, th2, e, along, sigma, w, a):
    # Assemblable by construction: the coupler's component along the slide is `along` > 0
    # (zero is the toggle, coupler perpendicular to the slide).
    normal = e - r2 * np.sin(th2 - th1)
    r3 = np.hypot(normal, along)
    assume((r3 - abs(normal)) / r2 >= MARGIN)  # `normal` moves at most r2 per radian
    th, h = swept(th2, w, a)
    pos = slider_crank(r2, r3, th, offset=e, th1=th1, sigma=sigma)
    an = slider_crank(r2, r3, th2, w, a, offset=e, th1=th1, sigma=sigma)
    assert np.all(np.isfinite(pos["r1"]))
    d1, d3 = derivs(pos["r1"], h), derivs(pos["th3"], h, True)
    s = max(r2, r3)
    check_fd([(d1[0], an["r1_v"]), (s * d3[0], s * an["w3"]), (s * w, s * w)], "velocity")
    check_fd([(d1[1], an["r1_a"]), (s * d3[1], s * an["a3"]), (s * w * w, s * w * w),
              (s * a, s * a)], "acceleration")


@FD
@given(r3=lengths, th1=angles, th3=angles, e=st.floats(-3, 3), along=st.floats(0.5, 5.0),
       sigma=signs, w=rates, a=accels)
def test_slider_crank_coupler_driven_finite_differences(r3, th1, th3, e, along, sigma, w, a):
    # Assemblable by construction: the crank's component along the slide is `along` > 0.
    normal = e - r3 * np.sin(th3 - th1)
    r2 = np.hypot(normal, along)
    assume((r2 - abs(normal)) / r3 >= MARGIN)
    th, h = swept(th3, w, a)
    pos = slider_crank_coupler_driven(r2, r3, th, offset=e, th1=th1, sigma=sigma)
    an = slider_crank_coupler_driven(r2, r3, th3, w, a, offset=e, th1=th1, sigma=sigma)
    assert np.all(np.isfinite(pos["r1"]))
    d1, d2 = derivs(pos["r1"], h), derivs(pos["th2"], h, True)
    s = max(r2, r3)
    check_fd([(d1[0], an["r1_v"]), (s * d2[0], s * an["w2"]), (s * w, s * w)], "velocity")
    check_fd([(d1[1], an["r1_a"]), (s * d2[1], s * an["a2"]), (s * w * w, s * w * w),
              (s * a, s * a)], "acceleration")


@FD
@given(r1=st.floats(-5, 5), r2=lengths, th1=angles, e=st.floats(-3, 3),
       at_O2=st.floats(0.2, np.pi - 0.2), sigma=signs, v=rates, a=accels)
def test_slider_crank_slider_driven_finite_differences(r1, r2, th1, e, at_O2, sigma, v, a):
    # Assemblable by construction: the coupler length comes from the triangle O2-A-B with the
    # angle at O2 away from 0 and pi (crank and coupler aligned: the limit positions).
    B = (r1 + 1j * e) * np.exp(1j * th1)
    r3 = abs(B - r2 * np.exp(1j * (np.angle(B) + at_O2)))
    s = max(r2, r3)
    # |B| moves at most as fast as the slider; it must stay inside [|r2 - r3|, r2 + r3].
    assume(min(abs(B) - abs(r2 - r3), r2 + r3 - abs(B)) >= MARGIN * s)
    x, h = swept(r1, v, a, unit=s)
    pos = slider_crank_slider_driven(r2, r3, x, offset=e, th1=th1, sigma=sigma)
    an = slider_crank_slider_driven(r2, r3, r1, v, a, offset=e, th1=th1, sigma=sigma)
    assert np.all(np.isfinite(pos["th2"]))
    d2, d3 = derivs(pos["th2"], h, True), derivs(pos["th3"], h, True)
    check_fd([(s * d2[0], s * an["w2"]), (s * d3[0], s * an["w3"]), (v, v)], "velocity")
    check_fd([(s * d2[1], s * an["a2"]), (s * d3[1], s * an["a3"]), (a, a)], "acceleration")


@FD
@given(r1=lengths, r2=lengths, th1=angles, th2=angles, frac=st.floats(-0.9, 0.9), sigma=signs,
       w=rates, a=accels)
def test_inverted_slider_crank_finite_differences(r1, r2, th1, th2, frac, sigma, w, a):
    # Assemblable by construction: |r4| < |A - O4| (equality puts the slider on the pivot).
    D = abs(r2 * np.exp(1j * th2) - r1 * np.exp(1j * th1))
    r4 = frac * D
    assume((D - abs(r4)) / r2 >= MARGIN)  # |A - O4| moves at most r2 per radian
    th, h = swept(th2, w, a)
    pos = inverted_slider_crank(r1, r2, r4, th, th1=th1, sigma=sigma)
    an = inverted_slider_crank(r1, r2, r4, th2, w, a, th1=th1, sigma=sigma)
    assert np.all(np.isfinite(pos["r3"])) and np.sign(an["r3"]) == sigma
    d3, dr = derivs(pos["th3"], h, True), derivs(pos["r3"], h)
    s = max(r1, r2)
    check_fd([(s * d3[0], s * an["w3"]), (dr[0], an["r3_v"]), (s * w, s * w)], "velocity")
    check_fd([(s * d3[1], s * an["a3"]), (dr[1], an["r3_a"]), (s * w * w, s * w * w),
              (s * a, s * a)], "acceleration")


@FD
@given(r1=lengths, th1=angles, th3=angles, r4=st.floats(-3, 3), half_chord=st.floats(0.5, 5.0),
       sigma=signs, w=rates, a=accels)
def test_inverted_slider_crank_link3_driven_finite_differences(r1, th1, th3, r4, half_chord,
                                                              sigma, w, a):
    # Assemblable by construction: the line of link 3 cuts the crank circle in a chord of half
    # length `half_chord` > 0 (a tangent line is the limit position).
    u = np.exp(1j * th3)
    P = r1 * np.exp(1j * th1) - 1j * r4 * u
    dist = abs(np.imag(P * np.conj(u)))      # from O2 to the line; moves at most r1 per radian
    r2 = np.hypot(dist, half_chord)
    assume((r2 - dist) / r1 >= MARGIN)
    th, h = swept(th3, w, a)
    pos = inverted_slider_crank_link3_driven(r1, r2, r4, th, th1=th1, sigma=sigma)
    an = inverted_slider_crank_link3_driven(r1, r2, r4, th3, w, a, th1=th1, sigma=sigma)
    assert np.all(np.isfinite(pos["r3"]))
    d2, dr = derivs(pos["th2"], h, True), derivs(pos["r3"], h)
    s = max(r1, r2, abs(r4))
    check_fd([(s * d2[0], s * an["w2"]), (dr[0], an["r3_v"]), (s * w, s * w)], "velocity")
    check_fd([(s * d2[1], s * an["a2"]), (dr[1], an["r3_a"]), (s * w * w, s * w * w),
              (s * a, s * a)], "acceleration")


@pytest.mark.parametrize("dims", [(8, 3, 3.5, 6), (50, 12, 14, 50)],
                         ids=["8_3_3.5_6", "50_12_14_50"])
@pytest.mark.parametrize("th2_deg, w, a", [(60, 10, 0), (30, -4, 7), (-20, 2.5, -30), (5, 1, 1)])
def test_geared_five_bar_finite_differences(dims, th2_deg, w, a):
    r1, R2, R4, r5 = dims
    th, h = swept(rad(th2_deg), w, a)
    pos = geared_five_bar(r1, R2, R4, r5, th)
    an = geared_five_bar(r1, R2, R4, r5, rad(th2_deg), w, a)
    assert np.all(np.isfinite(pos["th4"]))
    # The position satisfies the loop and the rolling row to machine precision.
    r3, r4, g = R2 + R4, R4, R4 / R2
    loop = (r3 * np.exp(1j * an["th3"]) + r4 * np.exp(1j * an["th4"])
            - r1 - r5 * np.exp(1j * an["th5"]))
    assert abs(loop) < 1e-13 * r1
    roll = (1 + g) * (an["th3"] - an["th30"]) - rad(th2_deg) - g * (an["th4"] - an["th40"])
    assert abs(roll) < 1e-13
    d = [derivs(pos[k], h, True) for k in ("th3", "th4", "th5")]
    check_fd([(d[k][0], an[f"w{k + 3}"]) for k in range(3)] + [(w, w)], "velocity")
    check_fd([(d[k][1], an[f"a{k + 3}"]) for k in range(3)] + [(w * w, w * w), (a, a)],
             "acceleration")


def test_geared_five_bar_vectorised_and_continuous():
    # An unsorted array (both signs of th2) gives the values of the scalar calls, and the branch
    # followed from th2 = 0 moves continuously.
    th2 = rad(np.array([60.0, -20.0, 0.0, 30.0, -5.0]))
    out = geared_five_bar(8, 3, 3.5, 6, th2, 10)
    for k, t in enumerate(th2):
        one = geared_five_bar(8, 3, 3.5, 6, t, 10)
        for key in ("th3", "th4", "th5", "w3", "w4", "w5"):
            assert abs(out[key][k] - one[key]) < 1e-12 * max(1, abs(one[key]))
    assert abs(out["th4"][2] - out["th40"]) < 1e-12
    sweep = geared_five_bar(8, 3, 3.5, 6, rad(np.linspace(0, 60, 61)))
    assert np.max(np.abs(np.diff(sweep["th4"]))) < 0.1


@pytest.mark.parametrize("case", [REF[k] for k in sorted(REF) if k.startswith("open_chain")],
                         ids=lambda c: c["id"])
def test_open_chain_finite_differences(case):
    i = case["inputs"]
    th0, w, a = rad(np.array(i["abs_angles_deg"])), np.array(i["abs_angular_velocities"], float), \
        np.array(i["abs_angular_accelerations"], float)
    h = 1e-3 / max(np.max(np.abs(w)), 1.0)
    t = STENCIL[:, None] * h
    pos = open_chain(i["lengths"], th0 + w * t + a * t**2 / 2, w, a)
    an = open_chain(i["lengths"], th0, w, a)
    d = derivs(pos["tip"], h)
    check_fd([(d[0], an["tip_vel"])], "velocity")
    check_fd([(d[1], an["tip_acc"])], "acceleration")


# ----------------------------------------------------------------------------- other properties

@settings(max_examples=100, deadline=None)
@given(r1=lengths, r2=lengths, r3=lengths, r4=lengths, th2=angles, sigma=signs)
def test_four_bar_instant_centres_are_equal_velocity_points(r1, r2, r3, r4, th2, sigma):
    # Ijk is the point whose velocity is the same as a point of body j and of body k (w2 = 1).
    fb = four_bar(r1, r2, r3, r4, th2, w2=1.0, sigma=sigma)
    assume(np.isfinite(fb["th3"]) and abs(np.sin(fb["th4"] - fb["th3"])) > 0.1)
    ic = {k: cplx(v) for k, v in four_bar_instant_centres(r1, r2, r3, r4, th2, sigma=sigma).items()}
    assume(abs(ic["I13"]) < 1e3 and abs(ic["I24"]) < 1e3)  # not (nearly) at infinity
    A, O4 = cplx(fb["A"]), r1 + 0j
    velocity = {1: lambda P: 0 * P,
                2: lambda P: 1j * P,
                3: lambda P: 1j * A + 1j * fb["w3"] * (P - A),
                4: lambda P: 1j * fb["w4"] * (P - O4)}
    scale = max(r1, r2, r3, r4) * max(1, abs(fb["w3"]), abs(fb["w4"]))
    for name, P in ic.items():
        j, k = int(name[1]), int(name[2])
        assert abs(velocity[j](P) - velocity[k](P)) <= 1e-9 * scale * max(1, abs(P)), name


def test_transmission_angle():
    th2 = np.linspace(-np.pi, np.pi, 73)
    for sigma in (1, -1):
        fb = four_bar(4, 2, 3, 4, th2, sigma=sigma)
        mu = four_bar_transmission_angle(4, 2, 3, 4, th2, sigma=sigma)
        assert np.all((mu >= 0) & (mu <= np.pi))
        assert np.allclose(mu, np.abs(wrap(fb["th4"] - fb["th3"])), atol=1e-12)
    # Crank-rocker extremes at th2 = 0 and pi (cosine rule).
    assert np.isclose(four_bar_transmission_angle(4, 2, 3, 4, 0.0), np.arccos((9 + 16 - 4) / 24))
    assert np.isclose(four_bar_transmission_angle(4, 2, 3, 4, np.pi), np.arccos((9 + 16 - 36) / 24))
    assert np.isnan(four_bar_transmission_angle(10, 1, 2, 3, 0.0))


@pytest.mark.parametrize("dims, kind", [
    ((4, 2, 3, 4), "crank-rocker"),      # seed 000's movef4centros linkage
    ((2, 4, 3, 4), "drag-link"),
    ((4, 3, 2, 4), "double-rocker"),
    ((4, 3, 4, 2), "rocker-crank"),
    ((4, 2, 4, 2), "change-point"),      # parallelogram
    ((3, 2, 3, 4), "change-point"),
    ((2, 2, 1, 1), "change-point"),      # kite driven by a long link: the input rocks
    ((5, 4, 3, 3.5), "triple-rocker"),
])
def test_grashof(dims, kind):
    assert grashof(*dims) == kind
    full = four_bar_input_limits(*dims) == [(-np.pi, np.pi)]
    assert full == _input_turns_fully(dims)


def _input_turns_fully(dims):
    # s + l <= p + q: the shortest link turns fully relative to the others, so the input does
    # when it or the ground is a shortest link; never for a non-Grashof linkage.
    return grashof(*dims) != "triple-rocker" and min(dims[:2]) == min(dims)


@settings(max_examples=100, deadline=None)
@given(r1=lengths, r2=lengths, r3=lengths, r4=lengths)
def test_four_bar_input_limits_match_a_sweep(r1, r2, r3, r4):
    dims = (r1, r2, r3, r4)
    got = four_bar_input_limits(*dims)
    s, p, q, l = sorted(dims)
    if l > s + p + q:                       # never closes
        assert got == []
    elif _input_turns_fully(dims):
        assert got == [(-np.pi, np.pi)]
    elif grashof(*dims) == "triple-rocker":
        assert len(got) == 1
        c = (r1**2 + r2**2 - (r3 + r4) ** 2) / (2 * r1 * r2)
        if -1 <= c <= 1 and got[0][0] < 0:  # oscillating through th2 = 0: the spec's th2max
            assert np.isclose(got[0][1], np.arccos(c), atol=1e-12)
    else:                                   # Grashof, input not shortest: it rocks
        assert 1 <= len(got) <= 2 and got != [(-np.pi, np.pi)]
    th2 = np.linspace(-np.pi, np.pi, 3601)
    ok = np.isfinite(four_bar(*dims, th2)["th3"])
    inside = _inside(got, th2, 0.0) | _inside(got, th2 + 2 * np.pi, 0.0)
    # Judged away from where rounding decides: |A - O4| at a bound (interval ends, change
    # points) or at 0 (A on O4: B undetermined, the oracle gives NaN).
    L = np.abs(r2 * np.exp(1j * th2) - r1)
    away = np.min(np.abs(L[:, None] - [abs(r3 - r4), r3 + r4, 0.0]), axis=1) > 1e-9 * l
    assert np.array_equal(ok[away], inside[away])


@settings(max_examples=100, deadline=None)
@given(r2=lengths, th2=angles, e=st.floats(-3, 3), along=st.floats(0.5, 5.0), sigma=signs)
def test_slider_crank_drivers_agree(r2, th2, e, along, sigma):
    # The same pose reached from each input: coupler-driven and slider-driven forms recover
    # the crank-driven one with one of their two roots.
    r3 = np.hypot(e - r2 * np.sin(th2), along)
    base = slider_crank(r2, r3, th2, offset=e, sigma=sigma)
    by_coupler = [slider_crank_coupler_driven(r2, r3, base["th3"], offset=e, sigma=s)
                  for s in (1, -1)]
    assert min(abs(wrap(o["th2"] - th2)) + abs(o["r1"] - base["r1"]) for o in by_coupler) < 1e-9
    B = cplx(base["B"])
    assume(abs(B) > 0.5 and abs(np.sin(np.angle(B) - th2)) > 1e-3)
    by_slider = [slider_crank_slider_driven(r2, r3, base["r1"], offset=e, sigma=s) for s in (1, -1)]
    assert min(abs(wrap(o["th2"] - th2)) + abs(wrap(o["th3"] - base["th3"]))
               for o in by_slider) < 1e-9


def test_nan_where_not_assembled():
    assert np.isnan(four_bar(10, 1, 2, 3, 0.3)["th3"])
    assert np.isnan(slider_crank(5, 3, np.pi / 2, offset=-1)["r1"])
    assert np.isnan(slider_crank_coupler_driven(1, 5, np.pi / 2, offset=0)["th2"])
    assert np.isnan(slider_crank_slider_driven(1, 2, 10.0)["th2"])
    assert np.isnan(inverted_slider_crank(4, 1, 5, 0.0)["r3"])
    assert np.isnan(inverted_slider_crank_link3_driven(4, 1, 0, np.pi / 2)["th2"])
    # The geared five-bar's input range ends near th2 = 213.6 deg (rates diverge there): the
    # continuation stops rather than jumping to another branch.
    assert np.isnan(geared_five_bar(8, 3, 3.5, 6, rad(300.0))["th4"])
