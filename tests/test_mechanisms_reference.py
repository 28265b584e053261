"""Every worked example of tests/data/textbook_reference.json (but the motion limits, checked
with the sweeps) through the builders and analyses of the library.

Tolerances (spec README): positions and angles to 1e-9 relative to the largest link, rates to
1e-8 relative to the largest expected rate of the same kind.
"""

import numpy as np
import pytest

from planar.analysis import instant_centres, stroke
from planar.mechanisms import four_bar, geared_five_bar, inverted_slider_crank, open_chain, slider_crank
from tests.oracles import load_reference

REF = load_reference()
rad = np.radians
COVERED = set()


def cases(mechanism, *must_have):
    """Parametrise over the reference cases of one mechanism having all the keys; record them."""
    found = [c for c in REF.values() if c["mechanism"] == mechanism
             and all(k in c["inputs"] or k in c["expected"] for k in must_have)]
    assert found, (mechanism, must_have)
    COVERED.update(c["id"] for c in found)
    return pytest.mark.parametrize("case", found, ids=[c["id"] for c in found])


def check_angle(actual, expected, what):
    """Angles (radians) equal modulo 2 pi to 1e-9."""
    err = np.max(np.abs(np.angle(np.exp(1j * (np.asarray(actual, float) - expected)))))
    assert err <= 1e-9, f"{what}: off by {err:.3g} rad"


def check_length(actual, expected, scale, what):
    err = np.max(np.abs(np.asarray(actual, float) - np.asarray(expected, float)))
    assert err <= 1e-9 * scale, f"{what}: off by {err:.3g} (largest link {scale})"


def check_rate(actual, expected, scale, what):
    err = np.max(np.abs(np.asarray(actual, float) - np.asarray(expected, float)))
    assert err <= 1e-8 * scale, f"{what}: off by {err:.3g} (rate scale {scale:.3g})"


def rate_scale(expected, keys):
    return max(np.max(np.abs(expected[k])) for k in keys if k in expected)


# ----------------------------------------------------------------------------- four-bar

@cases("four_bar", "th3_deg")
def test_four_bar(case):
    i, e = case["inputs"], case["expected"]
    cp = i.get("coupler_point")
    pq = None if cp is None else tuple(cp["distance_from_A"] * np.array(
        [np.cos(rad(cp["angle_from_AB_deg"])), np.sin(rad(cp["angle_from_AB_deg"]))]))
    crossed = i["assembly"].startswith("B right")
    m = four_bar(i["r1"], i["r2"], i["r3"], i["r4"], frame_angle=rad(i["th1_deg"]), coupler_point=pq,
                 crossed=crossed, start=rad(i["th2_deg"]))
    res = m.sweep([rad(i["th2_deg"])], velocity=i["w2"], acceleration=i["a2"])
    assert res.ok.all()
    L = max(i["r1"], i["r2"], i["r3"], i["r4"])
    check_angle(res.angle("coupler"), rad(e["th3_deg"]), "th3")
    check_angle(res.angle("rocker"), rad(e["th4_deg"]), "th4")
    w, a = rate_scale(e, ("w3", "w4")), rate_scale(e, ("a3", "a4"))
    check_rate(res.omega("coupler"), e["w3"], w, "w3")
    check_rate(res.omega("rocker"), e["w4"], w, "w4")
    check_rate(res.alpha("coupler"), e["a3"], a, "a3")
    check_rate(res.alpha("rocker"), e["a4"], a, "a4")
    for p in ("A", "B", "C"):
        if p in e:
            check_length(res.position(p)[0], e[p], L, p)
    if "C_vel" in e:
        check_rate(res.velocity("C")[0], e["C_vel"], np.max(np.abs(e["C_vel"])), "C_vel")
        check_rate(res.acceleration("C")[0], e["C_acc"], np.max(np.abs(e["C_acc"])), "C_acc")


FOUR_BAR_BODIES = {"1": "ground", "2": "crank", "3": "coupler", "4": "rocker"}


@cases("four_bar", "I13")
def test_four_bar_instant_centres(case):
    i, e = case["inputs"], case["expected"]
    m = four_bar(i["r1"], i["r2"], i["r3"], i["r4"], frame_angle=rad(i["th1_deg"]),
                 crossed=i["assembly"].startswith("B right"))
    found = instant_centres(m.sweep([rad(i["th2_deg"])]))
    L = max(i["r1"], i["r2"], i["r3"], i["r4"])
    for key, expected in e.items():
        pair = (FOUR_BAR_BODIES[key[1]], FOUR_BAR_BODIES[key[2]])
        check_length(found[pair][0], expected, L, key)


# ----------------------------------------------------------------------------- slider-cranks

SLIDER_INPUT = {"crank": ("th2_deg", "w2", "a2"), "coupler": ("th3_deg", "w3", "a3"),
                "slider": ("slider_r1", "slider_v", "slider_a")}


def _slider_outputs(res):
    return {"th2_deg": res.angle("crank"), "th3_deg": res.angle("coupler"), "slider_r1": res.coordinate("slide"),
            "w2": res.omega("crank"), "w3": res.omega("coupler"), "slider_v": res.coordinate("slide", 1),
            "a2": res.alpha("crank"), "a3": res.alpha("coupler"), "slider_a": res.coordinate("slide", 2)}


@cases("slider_crank", "driver")
def test_slider_crank(case):
    i = case["inputs"]
    value, rate, acc = SLIDER_INPUT[i["driver"]]
    u = rad(i[value]) if value.endswith("_deg") else i[value]
    L = max(i["crank"], i["coupler"], abs(i["offset"]))
    modes = [(False, case["expected"])] + ([(True, case["other_assembly"])] if "other_assembly" in case else [])
    for crossed, e in modes:
        m = slider_crank(i["crank"], i["coupler"], offset=i["offset"], slide_angle=rad(i["th1_deg"]),
                         crossed=crossed, driver=i["driver"], start=u)
        res = m.sweep([u], velocity=i[rate], acceleration=i[acc])
        assert res.ok.all()
        got = _slider_outputs(res)
        rates = [k for k in e if k[0] == "w" or k == "slider_v"]
        accs = [k for k in e if k[0] == "a" or k == "slider_a"]
        for k, v in e.items():
            if k.endswith("_deg"):
                check_angle(got[k], rad(v), k)
            elif k == "slider_r1":
                check_length(got[k], v, L, k)
            else:
                check_rate(got[k], v, rate_scale(e, rates if k in rates else accs), k)


@cases("slider_crank", "stroke")
def test_slider_crank_stroke_and_time_ratio(case):
    i, e = case["inputs"], case["expected"]
    m = slider_crank(i["crank"], i["coupler"], offset=i["offset"])
    for out in ("x:B", "travel:slide"):
        s = stroke(m, out)
        check_length(s.stroke, e["stroke"], max(i["crank"], i["coupler"]), "stroke")
        check_rate(s.time_ratio, e["time_ratio"], e["time_ratio"], "time ratio")


@cases("slider_crank", "stroke")
def test_slider_crank_offset_point_and_rates(case):
    i, e = case["inputs"], case["expected"]
    m = slider_crank(i["crank"], i["coupler"], offset=i["offset"], start=rad(i["th2_deg"]))
    res = m.sweep([rad(i["th2_deg"])], velocity=i["w2"], acceleration=i["a2"])
    L = max(i["crank"], i["coupler"], abs(i["offset"]))
    check_length(res.position("B")[0], [e["slider_x"], i["offset"]], L, "B")
    check_rate(res.velocity("B")[0, 0], e["slider_v"], abs(e["slider_v"]), "slider_v")
    check_rate(res.acceleration("B")[0, 0], e["slider_a"], abs(e["slider_a"]), "slider_a")
    check_angle(res.angle("coupler"), rad(e["th3_deg"]), "th3")
    check_rate(res.omega("coupler"), e["w3"], abs(e["w3"]), "w3")
    check_rate(res.alpha("coupler"), e["a3"], abs(e["a3"]), "a3")


INVERTED_INPUT = {"crank": ("crank", "th2_deg", "w2", "a2"), "link3": ("link3", "th3_deg", "w3", "a3")}


@cases("inverted_slider_crank", "driver")
def test_inverted_slider_crank(case):
    i, e = case["inputs"], case["expected"]
    driver, value, rate, acc = INVERTED_INPUT[i["driver"]]
    m = inverted_slider_crank(i["r1"], i["r2"], offset=i["r4"], frame_angle=rad(i["th1_deg"]), driver=driver,
                              start=rad(i[value]))
    res = m.sweep([rad(i[value])], velocity=i[rate], acceleration=i[acc])
    assert res.ok.all()
    got = {"th2_deg": res.angle("crank"), "th3_deg": res.angle("link3"), "r3": res.coordinate("slide"),
           "w2": res.omega("crank"), "w3": res.omega("link3"), "r3_v": res.coordinate("slide", 1),
           "a2": res.alpha("crank"), "a3": res.alpha("link3"), "r3_a": res.coordinate("slide", 2)}
    rates, accs = [k for k in e if k in ("w2", "w3", "r3_v")], [k for k in e if k in ("a2", "a3", "r3_a")]
    for k, v in e.items():
        if k.endswith("_deg"):
            check_angle(got[k], rad(v), k)
        elif k == "r3":
            check_length(got[k], v, max(i["r1"], i["r2"]), k)
        else:
            check_rate(got[k], v, rate_scale(e, rates if k in rates else accs), k)


# ----------------------------------------------------------------------------- geared five-bar, open chain

@cases("geared_five_bar", "th5_deg")
def test_geared_five_bar(case):
    i, e = case["inputs"], case["expected"]
    model = geared_five_bar(i["r1"], i["R2"], i["R4"], i["r5"]).compile()
    sketch = [model.body_angles0[model.body_id(b)] for b in ("arm", "gear4", "link5")]
    check_angle(sketch, rad(e["reference_angles_deg"]), "reference configuration")
    for start in (0.0, rad(i["th2_deg"])):  # swept from the reference, or sketched at the input
        res = geared_five_bar(i["r1"], i["R2"], i["R4"], i["r5"], start=start).sweep(
            [rad(i["th2_deg"])], velocity=i["w2"])
        assert res.ok.all()
        w = rate_scale(e, ("w3", "w4", "w5"))
        for body, k in (("arm", "3"), ("gear4", "4"), ("link5", "5")):
            check_angle(res.angle(body), rad(e[f"th{k}_deg"]), f"th{k}")
            check_rate(res.omega(body), e[f"w{k}"], w, f"w{k}")


@cases("open_chain", "tip")
def test_open_chain(case):
    i, e = case["inputs"], case["expected"]
    th = rad(i["abs_angles_deg"])
    res = open_chain(i["lengths"], start=th).sweep([th], velocity=i["abs_angular_velocities"],
                                                   acceleration=i["abs_angular_accelerations"])
    assert res.ok.all()
    tip = [res.position("tip")[0], res.velocity("tip")[0], res.acceleration("tip")[0]]
    check_length(tip[0], e["tip"], max(i["lengths"]), "tip")
    for k, got in (("tip_vel", tip[1]), ("tip_acc", tip[2])):
        check_rate(got, e[k], np.max(np.abs(e[k])), k)
    for j, got in enumerate(tip):
        check_rate(np.hypot(*got), e["magnitudes"][j], e["magnitudes"][j], "magnitude")
        check_angle(np.arctan2(got[1], got[0]), rad(e["angles_deg"][j]), "angle")


def test_every_reference_case_is_checked():
    missing = {k for k in REF if not k.startswith("slider_limits_")} - COVERED
    assert not missing, f"reference cases with no test: {sorted(missing)}"
