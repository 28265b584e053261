"""slider_crank and inverted_slider_crank against the closed forms of tests/oracles.py over full
sweeps, every driver with a closed form, both assembly modes."""

import numpy as np
import pytest
from hypothesis import assume, given, strategies as st

import planar
from planar.mechanisms import inverted_slider_crank, slider_crank
from tests import oracles
from tests.test_mechanisms_four_bar import FAST, SETTINGS, SWEEPS, assert_angles, assert_close, run_in, rate

length = st.floats(0.5, 5.0)
angle = st.floats(-np.pi, np.pi)

# for each driver: the oracle, its input grid, and where its Jacobian is clear of singular:
# crank driven when the coupler is across the slide, coupler driven when the crank is, slider
# driven when crank and coupler are in line (the closed forms' mode sigma flips only there)
SLIDER = {
    "crank": (oracles.slider_crank, lambda o, th1, u: np.abs(np.cos(o["th3"] - th1))),
    "coupler": (oracles.slider_crank_coupler_driven, lambda o, th1, u: np.abs(np.cos(o["th2"] - th1))),
    "slider": (oracles.slider_crank_slider_driven, lambda o, th1, u: np.abs(np.sin(o["th3"] - o["th2"]))),
}


def sweep_against(closed, grid, clear, build, w, a, at):
    """Sweep the mechanism ``build(start)`` over the values of ``grid`` of one motion range
    where ``clear(closed form at grid) > 0.1`` (the closed form's mode holds there), from a
    start inside it; returns the sweep and the closed form ``closed(values, w, a)``."""
    with np.errstate(all="ignore"):  # the grid runs past the motion range
        values = run_in(grid, clear(closed(grid, 1.0, 0.0), grid) > 0.1)
    assume(values is not None)
    res = build(values[int(at * (len(values) - 1))]).sweep(values, velocity=w, acceleration=a, **FAST)
    assert res.ok.all()
    return res, closed(values, w, a)


@SWEEPS
@given(r2=length, r3=length, e=st.floats(-3, 3), th1=angle, crossed=st.booleans(),
       driver=st.sampled_from(sorted(SLIDER)), w=rate, a=rate, at=st.floats(0, 1))
def test_slider_crank_matches_closed_forms(r2, r3, e, th1, crossed, driver, w, a, at):
    oracle, clear = SLIDER[driver]
    reach = r2 + r3 + abs(e)
    grid = np.linspace(-reach, reach, 181) if driver == "slider" else th1 + np.linspace(-np.pi, np.pi, 181)
    res, o = sweep_against(
        lambda u, w_, a_: oracle(r2, r3, u, w_, a_, offset=e, th1=th1, sigma=-1 if crossed else 1), grid,
        lambda o, u: clear(o, th1, u),
        lambda start: slider_crank(r2, r3, offset=e, slide_angle=th1, crossed=crossed, driver=driver, start=start),
        w, a, at)
    L = max(r2, r3, abs(e))
    got = {"th2": res.angle("crank"), "th3": res.angle("coupler"), "r1": res.coordinate("slide"),
           "w2": res.omega("crank"), "w3": res.omega("coupler"), "r1_v": res.coordinate("slide", 1),
           "a2": res.alpha("crank"), "a3": res.alpha("coupler"), "r1_a": res.coordinate("slide", 2)}
    v_scale = max(abs(w), *(np.abs(o[k]).max() * (L if k == "r1_v" else 1) for k in ("w2", "w3", "r1_v") if k in o))
    a_scale = max(abs(a), v_scale**2, *(np.abs(o[k]).max() for k in ("a2", "a3", "r1_a") if k in o))
    for k, v in o.items():
        if k in ("th2", "th3"):
            assert_angles(got[k], v, k)
        elif k == "r1":
            assert_close(got[k], v, L, 1e-9, k)
        elif k in ("A", "B"):
            assert_close(res.position(k), v, L, 1e-9, k)
        else:
            assert_close(got[k], v, (v_scale if k in ("w2", "w3", "r1_v") else a_scale) * (L if "r1" in k else 1),
                         1e-8, k)


INVERTED = {
    "crank": (oracles.inverted_slider_crank, lambda o, u: np.abs(o["r3"])),
    "link3": (oracles.inverted_slider_crank_link3_driven, lambda o, u: np.abs(np.cos(o["th2"] - u))),
}


@SWEEPS
@given(r1=length, r2=length, r4=st.floats(-2, 2), th1=angle, crossed=st.booleans(),
       driver=st.sampled_from(sorted(INVERTED)), w=rate, a=rate, at=st.floats(0, 1))
def test_inverted_slider_crank_matches_closed_forms(r1, r2, r4, th1, crossed, driver, w, a, at):
    oracle, clear = INVERTED[driver]
    L = max(r1, r2, abs(r4))
    res, o = sweep_against(
        lambda u, w_, a_: oracle(r1, r2, r4, u, w_, a_, th1=th1, sigma=-1 if crossed else 1),
        th1 + np.linspace(-np.pi, np.pi, 181), lambda o, u: clear(o, u) / (L if driver == "crank" else 1),
        lambda start: inverted_slider_crank(r1, r2, offset=r4, frame_angle=th1, crossed=crossed, driver=driver,
                                            start=start),
        w, a, at)
    got = {"th2": res.angle("crank"), "th3": res.angle("link3"), "th4": res.angle("slider"),
           "r3": res.coordinate("slide"), "w2": res.omega("crank"), "w3": res.omega("link3"),
           "r3_v": res.coordinate("slide", 1), "a2": res.alpha("crank"), "a3": res.alpha("link3"),
           "r3_a": res.coordinate("slide", 2)}
    v_scale = max(abs(w), *(np.abs(o[k]).max() for k in ("w2", "w3") if k in o), np.abs(o["r3_v"]).max() / L)
    a_scale = max(abs(a), v_scale**2, *(np.abs(o[k]).max() for k in ("a2", "a3") if k in o), np.abs(o["r3_a"]).max() / L)
    for k, v in o.items():
        if k.startswith("th"):
            assert_angles(got[k], v, k)
        elif k == "r3":
            assert_close(got[k], v, L, 1e-9, k)
        else:
            scale = v_scale if k in ("w2", "w3", "r3_v") else a_scale
            assert_close(got[k], v, scale * (L if k.startswith("r3") else 1), 1e-8, k)


@SETTINGS
@given(r1=length, r2=length, r4=st.floats(-2, 2), th1=angle, crossed=st.booleans(), frac=st.floats(0.02, 0.98))
def test_inverted_slide_driver_gives_the_crank_driven_pose_and_rates(r1, r2, r4, th1, crossed, frac):
    lo, hi = max(abs(r1 - r2), abs(r4)), r1 + r2  # |A - O4| over the assembled poses
    D = lo + frac * (hi - lo)
    r3 = np.sqrt(max(D**2 - r4**2, 0.0))
    assume(r3 > 0.05 and hi - lo > 0.01)
    try:
        m = inverted_slider_crank(r1, r2, offset=r4, frame_angle=th1, crossed=crossed, driver="slide", start=r3)
        m.compile()
    except (planar.AssemblyError, planar.MobilityError):
        return  # no pose there, or a dead centre of the slide drive: refused by name
    res = m.sweep([r3])
    assume(res.ok[0] and res.singularity[0] > 1e-3)
    o = oracles.inverted_slider_crank(r1, r2, r4, res.angle("crank"), th1=th1, sigma=1)
    assume(abs(o["r3_v"][0]) > 1e-3)
    assert_angles(res.angle("link3"), o["th3"], "th3")
    assert_close(res.coordinate("slide"), o["r3"], max(r1, r2), 1e-9, "r3")
    # unit travel rate: the crank turns at 1 / (dr3 / dth2)
    assert_close(res.omega("crank")[0] * o["r3_v"][0], 1.0, 1.0, 1e-8, "w2")


@pytest.mark.parametrize("build, kw", [
    (slider_crank, dict(crank=1, coupler=1, offset=5)),
    (slider_crank, dict(driver="slider", start=100.0)),
    (inverted_slider_crank, dict(driver="link3", start=np.pi / 2, ground=5, crank=1)),
    (inverted_slider_crank, dict(driver="slide", start=1.0, ground=5, crank=1)),
])
def test_poses_outside_the_motion_range_are_refused(build, kw):
    with pytest.raises(planar.AssemblyError, match="cannot be placed"):
        build(**kw)


def test_default_slide_inputs_start_clear_of_dead_centres():
    for m in (slider_crank(driver="slider"), inverted_slider_crank(driver="slide"),
              slider_crank(offset=0.0, driver="slider")):
        u0 = m.compile().u0[0]
        res = m.sweep([u0, u0 + 0.1])
        assert res.ok.all() and res.singularity.min() > 1e-3
