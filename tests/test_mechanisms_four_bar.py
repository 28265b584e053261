"""four_bar against the closed forms of tests/oracles.py over full sweeps, both assembly modes."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import planar
from planar.mechanisms import four_bar
from tests.oracles import four_bar as fb_oracle

SETTINGS = settings(max_examples=200, deadline=None)
# a full sweep costs about 0.1 s (its continuation walk), so sweeping tests draw fewer examples
# to keep this module within its time budget
SWEEPS = settings(max_examples=30, deadline=None)
FAST = {"max_step": 0.5}  # continuation anchors every 0.5 rad: the walk dominates a sweep's time
length = st.floats(0.5, 5.0)
angle = st.floats(-np.pi, np.pi)
rate = st.floats(-10, 10, allow_subnormal=False)  # subnormal rates defeat any relative tolerance


def assert_angles(actual, expected, what):
    err = np.max(np.abs(np.angle(np.exp(1j * (np.asarray(actual) - expected)))))
    assert err <= 1e-9, f"{what}: off by {err:.3g} rad"


def assert_close(actual, expected, scale, tol, what):
    err = np.max(np.abs(np.asarray(actual) - np.asarray(expected)))
    assert err <= tol * scale, f"{what}: off by {err:.3g} (scale {scale:.3g})"


def run_in(grid, good):
    """The longest run of consecutive grid values where ``good`` holds (a full turn when it
    holds everywhere), or None when it is shorter than five values."""
    if good.all():
        return grid
    best, start = (0, 0), None
    for k, g in enumerate(np.r_[good, False]):
        if g and start is None:
            start = k
        elif not g and start is not None:
            best = max(best, (k - start, start))
            start = None
    n, s = best
    return grid[s : s + n] if n >= 5 else None


def compare_four_bar(res, r, th1, sigma, w2, a2, pq=None, prefix=""):
    """Every output of a crank-driven four-bar sweep against the oracle (names with ``prefix``)."""
    o = fb_oracle(*r, res.inputs[:, 0], w2, a2, th1=th1, sigma=sigma,
                  p=None if pq is None else pq[0], q=None if pq is None else pq[1])
    L = max(r)
    assert_angles(res.angle(prefix + "coupler"), o["th3"], "th3")
    assert_angles(res.angle(prefix + "rocker"), o["th4"], "th4")
    w = max(np.max(np.abs(o["w3"])), np.max(np.abs(o["w4"])), abs(w2))
    a = max(np.max(np.abs(o["a3"])), np.max(np.abs(o["a4"])), abs(a2), w**2)
    assert_close(res.omega("coupler"), o["w3"], w, 1e-8, "w3")
    assert_close(res.omega("rocker"), o["w4"], w, 1e-8, "w4")
    assert_close(res.alpha("coupler"), o["a3"], a, 1e-8, "a3")
    assert_close(res.alpha("rocker"), o["a4"], a, 1e-8, "a4")
    assert_close(res.position("A"), o["A"], L, 1e-9, "A")
    assert_close(res.position("B"), o["B"], L, 1e-9, "B")
    if pq is not None:
        assert_close(res.position("C"), o["C"], L, 1e-9, "C")
        assert_close(res.velocity("C"), o["C_vel"], np.max(np.abs(o["C_vel"])) + w * L, 1e-8, "C_vel")
        assert_close(res.acceleration("C"), o["C_acc"], np.max(np.abs(o["C_acc"])) + a * L, 1e-8, "C_acc")
    return o


def crank_range(r, th1, sigma):
    """Crank angles of one motion range (or the full turn) kept away from its limit positions,
    where the coupler and rocker line up; None near a change point (s + l = p + q), where the
    branches meet and the closed form's mode is ill-defined."""
    s, p, q, l = sorted(r)
    if abs(s + l - p - q) < 0.05 * l:
        return None
    grid = th1 + np.linspace(-np.pi, np.pi, 181)
    o = fb_oracle(*r, grid, th1=th1, sigma=sigma)
    with np.errstate(invalid="ignore"):
        good = np.abs(np.sin(o["th4"] - o["th3"])) > 0.1
    return run_in(grid, good)


@SWEEPS
@given(r=st.tuples(length, length, length, length), th1=angle, crossed=st.booleans(),
       pq=st.tuples(st.floats(-3, 3), st.floats(-3, 3)), w2=rate, a2=rate,
       at=st.floats(0, 1))
def test_crank_driven_matches_closed_form(r, th1, crossed, pq, w2, a2, at):
    sigma = -1 if crossed else 1
    values = crank_range(r, th1, sigma)
    assume(values is not None)
    start = values[int(at * (len(values) - 1))]
    m = four_bar(*r, frame_angle=th1, coupler_point=pq, crossed=crossed, start=start)
    res = m.sweep(values, velocity=w2, acceleration=a2, **FAST)
    assert res.ok.all()
    compare_four_bar(res, r, th1, sigma, w2, a2, pq)


@SETTINGS
@given(r=st.tuples(length, length, length, length), th1=angle, crossed=st.booleans(),
       driver=st.sampled_from(["coupler", "rocker"]), start=angle)
def test_coupler_and_rocker_drivers_give_the_crank_driven_pose_and_rates(r, th1, crossed, driver, start):
    try:
        m = four_bar(*r, frame_angle=th1, crossed=crossed, driver=driver, start=start)
        m.compile()
    except planar.AssemblyError:
        return  # no pose on that side at that input: refused by name, checked below
    except planar.MobilityError:
        return  # the sketch is a dead centre of that driver (crank and rocker parallel): refused
    try:
        res = m.sweep([start])
    except planar.AssemblyError:
        return  # sketched on a singular position (a change point): refused by name
    assume(res.ok[0] and res.singularity[0] > 1e-3)
    th2 = res.angle("crank")
    o = fb_oracle(*r, th2, th1=th1, sigma=-1 if crossed else 1)
    assume(abs(np.sin(o["th4"][0] - o["th3"][0])) > 1e-3)  # B clear of the line A O4
    A, B, O4 = res.position("A")[0], res.position("B")[0], res.position("O4")[0]
    d, e = O4 - A, B - A
    assert (d[0] * e[1] - d[1] * e[0] < 0) == crossed
    assert_angles(res.angle("coupler"), o["th3"], "th3")
    assert_angles(res.angle("rocker"), o["th4"], "th4")
    # unit input rate: the crank turns at 1 / (d input / d th2)
    k = o["w3"][0] if driver == "coupler" else o["w4"][0]
    assert_close(res.omega("crank")[0] * k, 1.0, 1.0, 1e-8, "w2")


def test_a_driver_with_no_pose_on_the_asked_side_is_refused():
    # rocker of the 4-2-3-4 four-bar at 110 deg: both crank positions put B left of A -> O4
    four_bar(driver="rocker", start=np.radians(110))
    with pytest.raises(planar.AssemblyError, match="no pose with B right"):
        four_bar(driver="rocker", start=np.radians(110), crossed=True)


def test_outside_the_motion_range_is_refused_by_name():
    with pytest.raises(planar.AssemblyError, match="crank angle"):
        four_bar(4, 3, 3, 3, start=np.pi)  # triple-rocker: the crank cannot point back


@pytest.mark.parametrize("bad", [dict(crank=-1), dict(ground=0), dict(driver="ground"), dict(coupler_point=(1,)),
                                 dict(start=np.nan), dict(frame_angle="x")])
def test_bad_arguments_name_the_argument(bad):
    key = next(iter(bad))
    with pytest.raises(planar.ModelError, match=key):
        four_bar(**bad)


def test_names_and_sketch_angles():
    m = four_bar(frame_angle=0.3, coupler_point=(1, 1), start=7.0)  # start beyond a turn stays unwrapped
    model = m.compile()
    assert model.body_names == ("ground", "crank", "coupler", "rocker")
    assert {"O2", "A", "B", "O4", "C"} <= set(model.points)
    assert model.u0[0] == 7.0
    res = m.sweep([7.0, 7.5])
    assert res.ok.all()
    np.testing.assert_allclose(res.position("O4")[0], 4 * np.array([np.cos(0.3), np.sin(0.3)]), atol=1e-12)
