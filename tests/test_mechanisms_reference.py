"""Every worked example of tests/data/textbook_reference.json (but the motion limits, checked
with the sweeps) through the builders and analyses of the library.

Tolerances (spec README): positions and angles to 1e-9 relative to the largest link, rates to
1e-8 relative to the largest expected rate of the same kind.
"""

import numpy as np
import pytest

from planar.mechanisms import four_bar
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
