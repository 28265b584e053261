"""Singular positions met by sweeps, on mechanisms built for each kind of event.

Every case asserts the statuses, the located event inputs (against closed forms) and the
values around them (against tests/oracles.py).
"""

import numpy as np
import pytest

from planar import Status
from planar.mechanisms import four_bar, planetary_gear_train, slider_crank, watt_six_bar
from tests import oracles


def counts(res):
    return {Status(s).name: int(c) for s, c in zip(*np.unique(res.status, return_counts=True))}


def kinds(res):
    return [e.kind for e in res.events]


def test_triple_rocker_limit_and_re_entry():
    r1, r2, r3, r4 = 4.0, 3.0, 3.0, 2.5  # s + l > p + q: the crank rocks
    lim = np.arccos((r1**2 + r2**2 - (r3 + r4) ** 2) / (2 * r1 * r2))
    values = np.sort(np.r_[np.linspace(0, 2 * np.pi, 181), lim])
    res = four_bar(r1, r2, r3, r4).sweep(values)
    assert kinds(res) == ["limit", "limit"]
    ev, back = res.events
    assert abs(ev.input - lim) < 1e-10
    k = int(np.flatnonzero(values == lim)[0])
    assert ev.index == k and res.status[k] == Status.LIMIT
    # the range's other end, where the sweep re-enters it: located walking back from there
    assert abs(back.input - (2 * np.pi - lim)) < 1e-10
    assert back.index == int(np.searchsorted(values, 2 * np.pi - lim))
    assert np.all(np.isfinite(res.q[k])) and np.all(np.isnan(res.qd[k]))
    # the limit pose: coupler and rocker in line, B on the segment A-O4
    A, B, O4 = res.position("A")[k], res.position("B")[k], res.position("O4")[k]
    assert abs(np.linalg.norm(O4 - A) - (r3 + r4)) < 1e-10
    assert abs(np.linalg.norm(B - A) + np.linalg.norm(O4 - B) - np.linalg.norm(O4 - A)) < 1e-9
    out = (values > lim) & (values < 2 * np.pi - lim)
    assert np.all(res.status[out] == Status.NOT_ASSEMBLABLE)
    assert np.all(res.gap[out] > 0) and np.all(np.isnan(res.q[out]))
    tie = np.abs(values - np.pi) < 1e-9  # as far from either limit, up to their location's rounding
    np.testing.assert_allclose(res.nearest_limit[out & ~tie], np.where(values[out & ~tie] < np.pi, lim, 2 * np.pi - lim))
    inside = ~out & (values != lim)
    assert np.all(res.ok[inside])  # re-entered after the gap
    o = oracles.four_bar(r1, r2, r3, r4, values[inside], sigma=1)
    np.testing.assert_allclose(res.position("B")[inside], o["B"], atol=1e-9)
    far = inside & (np.abs(np.sin(values - np.pi)) > 0) & (np.abs(values - lim) > 0.05) & \
        (np.abs(values - 2 * np.pi + lim) > 0.05)
    np.testing.assert_allclose(res.omega("rocker")[far], o["w4"][far[inside]], rtol=1e-9, atol=1e-9)


def test_toggle_of_a_rocker_driven_crank_rocker():
    r1, r2, r3, r4 = 4.0, 1.5, 4.0, 3.5  # crank-rocker; driven by its rocker it meets toggles
    hi = np.arccos(((r3 - r2) ** 2 - r1**2 - r4**2) / (2 * r1 * r4))  # crank folded on the coupler
    lo = np.arccos(((r3 + r2) ** 2 - r1**2 - r4**2) / (2 * r1 * r4))  # crank and coupler stretched
    m = four_bar(r1, r2, r3, r4, driver="rocker", start=np.radians(110))
    values = np.r_[np.linspace(np.radians(110), np.radians(150), 41), np.linspace(np.radians(150), np.radians(75), 76)]
    res = m.sweep(values)
    assert kinds(res) == ["limit", "limit"]
    assert abs(res.events[0].input - hi) < 1e-10 and abs(res.events[1].input - lo) < 1e-10
    feasible = (values < hi) & (values > lo)
    assert np.all(res.ok[feasible]) and np.all(res.status[~feasible] == Status.NOT_ASSEMBLABLE)
    # at a toggle the crank and the coupler are in line: |B - O2| = r3 -+ r2
    for ev, d in zip(res.events, (r3 - r2, r3 + r2)):
        b, s = m.compile().points["B"]
        x, y, phi = ev.q[3 * b - 3 : 3 * b]
        assert abs(np.hypot(x + np.cos(phi) * s[0] - np.sin(phi) * s[1], y + np.sin(phi) * s[0] + np.cos(phi) * s[1]) - d) < 1e-9
    # loop closure and rates against the crank-driven closed form at the solved crank angles
    th2 = res.angle("crank")[feasible]
    B = res.position("B")[feasible]
    err = np.minimum(*(np.abs(oracles.four_bar(r1, r2, r3, r4, th2, sigma=s)["B"] - B).max(axis=1) for s in (1, -1)))
    assert err.max() < 1e-10


def test_change_point_takes_the_smooth_branch_or_the_other():
    r1, r2, r3, r4 = 4.0, 2.0, 3.0, 3.0  # s + l = p + q: the branches cross at th2 = pi
    values = np.linspace(0, 2 * np.pi, 181)
    m = four_bar(r1, r2, r3, r4)
    res = m.sweep(values)
    assert kinds(res) == ["bifurcation"]
    ev = res.events[0]
    assert abs(ev.input - np.pi) < 1e-9 and ev.index == 90
    assert res.status[90] == Status.BRANCH_EVENT and np.all(res.ok)
    assert set(counts(res)) <= {"SOLVED", "NEAR_SINGULAR", "BRANCH_EVENT"}
    # the smooth branch changes assembly mode at the change point
    before, after = values < np.pi - 1e-9, values > np.pi + 1e-9
    for sel, sigma in ((before, 1), (after, -1)):
        o = oracles.four_bar(r1, r2, r3, r4, values[sel], sigma=sigma)
        np.testing.assert_allclose(res.position("B")[sel], o["B"], atol=1e-11)
        np.testing.assert_allclose(res.omega("rocker")[sel], o["w4"], atol=1e-9)
        np.testing.assert_allclose(res.alpha("coupler")[sel], o["a3"], atol=1e-8)
    assert np.all(np.sign(res.branch[before]) == -np.sign(res.branch[after][0]))
    # at the change point: the smooth tangent, the mean of the two one-sided closed forms
    def mean(h):
        return 0.5 * (oracles.four_bar(r1, r2, r3, r4, np.pi - h, sigma=1)["w4"]
                      + oracles.four_bar(r1, r2, r3, r4, np.pi + h, sigma=-1)["w4"])

    # Richardson: the error of the mean is O(h^2) (closer in, the closed form loses digits)
    w4 = (4 * mean(1e-3) - mean(2e-3)) / 3
    assert abs(res.omega("rocker")[90] - w4) < 1e-8
    rocker = m.compile().body_id("rocker")
    assert abs(ev.tangents[0][3 * rocker - 1] - w4) < 1e-7
    # the other branch keeps its assembly mode through the crossing
    other = m.sweep(values, branch="other")
    assert "other branch" in other.events[0].note
    o = oracles.four_bar(r1, r2, r3, r4, values[after], sigma=1)
    np.testing.assert_allclose(other.position("B")[after], o["B"], atol=1e-11)
    assert abs(other.events[0].tangents[1][3 * rocker - 1] - o["w4"][0]) < 0.1


def test_parallelogram_fold_keeps_the_parallelogram_motion():
    m = four_bar(4, 2, 4, 2, start=-1.0, crossed=True)  # the parallelogram assembly
    values = np.linspace(-1, 1, 201)  # with the fold th2 = 0 itself
    res = m.sweep(values, velocity=2.0, acceleration=3.0)
    assert kinds(res) == ["bifurcation"]
    assert abs(res.events[0].input) < 1e-10
    assert res.status[100] == Status.BRANCH_EVENT and np.all(res.ok)
    np.testing.assert_allclose(res.angle("rocker"), res.angle("crank"), atol=1e-12)
    np.testing.assert_allclose(res.angle("coupler"), 0.0, atol=1e-12)
    np.testing.assert_allclose(res.omega("rocker"), 2.0, atol=1e-10)
    np.testing.assert_allclose(res.omega("coupler"), 0.0, atol=1e-10)
    # accelerations lose digits near the fold (they are interpolated from the branch there)
    np.testing.assert_allclose(res.alpha("rocker"), 3.0, atol=5e-9)
    np.testing.assert_allclose(res.alpha("coupler"), 0.0, atol=5e-9)
    # the two tangents (w3, w4) per unit input: (0, 1) followed, (-2, -3) the other
    model = m.compile()
    w = [[T[3 * model.body_id(b) - 1] for b in ("coupler", "rocker")] for T in res.events[0].tangents]
    np.testing.assert_allclose(w, [[0, 1], [-2, -3]], atol=1e-9)


def test_slider_driven_dead_centres():
    r2, r3, e = 2.0, 5.0, 1.0
    outer, inner = np.sqrt((r2 + r3) ** 2 - e**2), np.sqrt((r3 - r2) ** 2 - e**2)
    m = slider_crank(r2, r3, offset=e, driver="slider")
    u0 = m.compile().u0[0]
    values = np.r_[np.linspace(u0, 8, 30), outer, np.linspace(8, 2, 60), inner]
    res = m.sweep(values)
    assert kinds(res) == ["limit", "limit"]
    assert abs(res.events[0].input - outer) < 1e-10 * r3
    assert abs(res.events[1].input - inner) < 1e-10 * r3
    assert res.status[30] == Status.LIMIT and res.status[-1] == Status.LIMIT
    feasible = (values > inner) & (values < outer)
    assert np.all(res.ok[feasible])
    beyond = (values > outer) | (values < inner)
    assert np.all(res.status[beyond] == Status.NOT_ASSEMBLABLE)
    o = oracles.slider_crank_slider_driven(r2, r3, values[feasible], offset=e, sigma=1)
    np.testing.assert_allclose(res.position("A")[feasible], o["A"], atol=1e-10)
    # at the dead centres the crank and the coupler are in line
    for k, d in ((30, r2 + r3), (-1, r3 - r2)):
        assert abs(np.linalg.norm(res.position("B")[k]) - d) < 1e-9


def test_avoided_crossing_stays_on_its_branch_and_is_flagged():
    r1, r2, r3, r4 = 4.0, 2.0, 3.0, 3.0 + 1e-8  # the change point, split
    values = np.linspace(0, 2 * np.pi, 181)
    res = four_bar(r1, r2, r3, r4).sweep(values)
    assert "bifurcation" not in kinds(res) and "near_singular" in kinds(res)
    ev = next(e for e in res.events if e.kind == "near_singular")
    assert abs(ev.input - np.pi) < 0.05 and 0 < ev.singularity < 1e-4 and ev.error > 0
    assert np.all(res.ok) and np.all(res.branch == res.branch[0])  # no flip: the same mode
    assert res.status[90] == Status.NEAR_SINGULAR
    o = oracles.four_bar(r1, r2, r3, r4, values, sigma=1)
    np.testing.assert_allclose(res.position("B"), o["B"], atol=1e-9)


def test_redundant_double_parallelogram_passes_its_fold():
    m = four_bar(4, 2, 4, 2, start=-1.0, crossed=True)
    A = 2 * np.array([np.cos(-1.0), np.sin(-1.0)])
    m.add_body("crank3", angle=-1.0)
    m.add_revolute("O6", m.ground, "crank3", at=(2.0, 0.0))
    m.add_revolute("D", "crank3", "coupler", at=A + (2.0, 0.0))
    model = m.compile()
    assert model.redundant_joints and model.dof == 1
    values = np.linspace(-1, 1, 201)
    res = m.sweep(values)
    assert "INCONSISTENT" not in counts(res) and np.all(res.ok | (res.status == Status.BRANCH_EVENT))
    np.testing.assert_allclose(res.angle("rocker"), values, atol=1e-12)
    np.testing.assert_allclose(res.angle("crank3"), values, atol=1e-12)
    # the velocity at the fold comes from the branch, not a least-squares guess
    np.testing.assert_allclose([res.omega(b)[100] for b in ("coupler", "rocker", "crank3")], [0, 1, 1], atol=1e-9)


def test_planetary_carrier_through_two_turns_turns_the_sun_three_times_as_far():
    m = planetary_gear_train(1.0, 0.5, planets=3, fixed="ring", driver="carrier")
    assert m.compile().redundant_joints
    values = np.linspace(0, 4 * np.pi, 721)
    res = m.sweep(values)
    assert counts(res) == {"SOLVED": 721} and res.events == ()
    # Willis with the ring fixed: w_sun = w_c (1 + R_ring / R_sun) = 3 w_c, angles unwrapped
    np.testing.assert_allclose(res.angle("sun") - res.angle("sun")[0], 3 * values, atol=1e-12)
    np.testing.assert_allclose(res.omega("sun"), 3.0, atol=1e-12)
    assert abs(res.angle("sun")[-1] - res.angle("sun")[0] - np.radians(2160)) < 1e-11


@pytest.mark.parametrize("crank, coupler, offset", [(1e-3, 1e3, 0.5), (1e3, 1e3 + 1e-3, 1.0)])
def test_lengths_mixed_from_1e_3_to_1e3(crank, coupler, offset):
    L = max(crank, coupler)
    m = slider_crank(crank, coupler, offset=offset)
    values = np.linspace(0, 2 * np.pi, 361)
    res = m.sweep(values, velocity=7.0)
    o = oracles.slider_crank(crank, coupler, values, w2=7.0, offset=offset, sigma=1)
    ok = np.isfinite(o["r1"])
    assert np.all(res.ok[ok]) and np.all(res.status[~ok] == Status.NOT_ASSEMBLABLE)
    np.testing.assert_allclose(res.position("B")[ok], o["B"][ok], atol=1e-13 * L)
    np.testing.assert_allclose(res.coordinate("slide", 1)[ok], o["r1_v"][ok], atol=1e-11 * L * 7)
    # the slider-driven dead centres of the same dimensions, located to 1e-10 relative
    outer = np.sqrt((crank + coupler) ** 2 - offset**2)
    ms = slider_crank(crank, coupler, offset=offset, driver="slider")
    u0 = ms.compile().u0[0]
    res = ms.sweep(np.linspace(u0, outer + 1e-3 * L, 50))
    lim = [e for e in res.events if e.kind == "limit"]
    assert len(lim) == 1 and abs(lim[0].input - outer) < 1e-10 * L


def test_gap_inside_the_range_is_crossed_and_both_ends_located():
    # a Watt six-bar whose dyad C-E-D cannot close for a stretch of crank angles inside the
    # first loop's range: |C - D| < |link_5 - link_6| from 58.60 to 59.16 deg
    l5, l6 = 2.1463389680285707, 2.1102263651692366
    m = watt_six_bar(1, 1.75, 0.5, 1.5, crossed=True, coupler_point=(1.75, 1.75), rocker_point=(0, 1.5),
                     link_5=l5, link_6=l6, start=np.radians(30))
    values = np.radians(np.arange(30, 65.01, 0.1))
    res = m.sweep(values)
    assert kinds(res) == ["limit", "limit"]
    lo, hi = (e.input for e in res.events)
    assert np.degrees(lo) == pytest.approx(58.5959, abs=1e-3) and np.degrees(hi) == pytest.approx(59.1566, abs=1e-3)
    def at(name, q):
        b, s = res.model.point(name)
        x, y, phi = q[3 * b - 3 : 3 * b]
        return np.array([x + np.cos(phi) * s[0] - np.sin(phi) * s[1], y + np.sin(phi) * s[0] + np.cos(phi) * s[1]])

    for ev in res.events:  # at both ends the dyad is folded: |C - D| = link_5 - link_6
        assert abs(np.linalg.norm(at("C", ev.q) - at("D", ev.q)) - (l5 - l6)) < 1e-9
    gap = (values > lo) & (values < hi)
    assert np.all(res.status[gap] == Status.NOT_ASSEMBLABLE)
    assert res.ok[~gap].all()  # before the gap, and from its far end on (walked back to it)
    assert res.events[1].index == int(np.flatnonzero(values > hi)[0])
