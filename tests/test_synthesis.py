"""Synthesis against textbook closed forms and known linkages; every result is checked on the
built mechanism by a sweep of its own, not by the formula that made it."""

import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from planar.errors import InputError, ModelError, SynthesisError
from planar.mechanisms import four_bar, slider_crank
from planar.synthesis import (burmester_curves, burmester_points, compatible, dyad, four_bar_lengths, freudenstein,
                              function_four_bar, function_slider_crank, motion_four_bar,
                              path_check, path_four_bar, path_six_bar, precision_points, slider_crank_dimensions,
                              stephenson_tracer)
from planar.synthesis.families import FOUR_BAR, STEPHENSON
from tests.oracles import four_bar as fb_oracle
from tests.oracles import slider_crank as sc_oracle


def wrap(a):
    return np.angle(np.exp(1j * np.asarray(a)))


# ---- function generation -----------------------------------------------------------------------


def test_three_point_freudenstein_log10():
    """y = log10(x) on 1 <= x <= 2, crank 45 -> 105 deg, rocker 135 -> 225 deg, Chebyshev
    spacing: K1, K2, K3 by Cramer's rule here, the linkage's rocker angles by the closed form."""
    j = np.arange(1, 4)
    x = 1.5 - 0.5 * np.cos((2 * j - 1) * np.pi / 6)
    th2 = np.radians(45 + 60 * (x - 1))
    th4 = np.radians(135 + 90 * np.log10(x) / np.log10(2))
    M = np.stack((np.cos(th4), -np.cos(th2), np.ones(3)), axis=1)
    rhs = np.cos(th2 - th4)
    K = [np.linalg.det(np.where(np.arange(3) == k, rhs[:, None], M)) / np.linalg.det(M) for k in range(3)]
    r2, r4 = 1 / K[0], 1 / K[1]
    r3 = np.sqrt(1 + r2**2 + r4**2 - 2 * r2 * r4 * K[2])

    s = function_four_bar(np.log10, (1, 2), np.radians([45, 105]), np.radians([135, 225]))
    assert np.allclose(precision_points((1, 2)), x, atol=1e-15)
    assert np.allclose(freudenstein(th2, th4), K, rtol=1e-12)
    d = s.design
    # r4 < 0: the rocker is built pointing the other way, its angles half a turn on
    assert r2 > 0 and r4 < 0 and s.notes["shift"] == (0.0, np.pi)
    assert np.allclose([d["ground"], d["crank"], d["coupler"], d["rocker"]], [1, r2, r3, -r4], rtol=1e-12)
    sigma = -1 if d["crossed"] else 1
    got = fb_oracle(1.0, r2, r3, -r4, th2, sigma=sigma)["th4"]
    assert np.allclose(wrap(got - th4 - np.pi), 0, atol=1e-12)
    assert s.ok and s.max_error < 1e-12
    # planar's own sweep of the built four-bar, through the precision points
    res = four_bar(**d).sweep(np.r_[np.radians(45), th2])
    assert np.allclose(wrap(res.angle("rocker")[1:] - th4 - np.pi), 0, atol=1e-10)
    # the structural error between the precision points is small but not zero
    assert 1e-4 < s.notes["structural_error"] < np.radians(0.5)


def test_freudenstein_recovers_a_known_four_bar_by_least_squares():
    r1, r2, r3, r4 = 5.0, 2.0, 4.5, 4.0
    th2 = np.radians(np.linspace(30, 150, 9))
    th4 = fb_oracle(r1, r2, r3, r4, th2)["th4"]
    K = freudenstein(th2, th4)
    assert np.allclose(K, [r1 / r2, r1 / r4, (r1**2 + r2**2 - r3**2 + r4**2) / (2 * r2 * r4)], rtol=1e-10)
    # the same as function generation over many points: the generated function is met exactly
    xs, ys = np.degrees(th2), th4

    def g(x):
        return fb_oracle(r1, r2, r3, r4, np.radians(x))["th4"]

    s = function_four_bar(g, (xs[0], xs[-1]), th2[[0, -1]], ys[[0, -1]], points=9, spacing="even", ground=r1)
    assert s.ok and s.max_error < 1e-9 and s.notes["structural_error"] < 1e-9
    assert np.allclose([s.design[k] for k in ("crank", "coupler", "rocker")], [r2, r3, r4], rtol=1e-9)


def test_slider_crank_function_generator():
    r2, r3, e = 2.0, 5.0, 1.0
    th2 = np.radians([20.0, 70.0, 130.0])
    s_ = sc_oracle(r2, r3, th2, offset=e)["r1"]
    assert np.allclose(slider_crank_dimensions(th2, s_), (r2, r3, e), rtol=1e-12)

    s = function_slider_crank(np.sqrt, (1, 4), np.radians([30, 150]), (6.0, 3.0))
    assert s.ok and s.max_error < 1e-12
    res = slider_crank(**s.design).sweep(s.inputs)
    assert np.allclose(res.coordinate("slide"), s.targets, atol=1e-10)


def test_function_generation_refuses_bad_ranges():
    with pytest.raises(InputError, match="output range"):
        function_four_bar(np.cos, (0, 2 * np.pi), (0, 1), (0, 1))
    with pytest.raises(InputError, match="three"):
        function_four_bar(np.log10, (1, 2), (0, 1), (2, 3), points=[1.2, 1.5])
    with pytest.raises(InputError, match="not finite"):
        function_four_bar(lambda x: 1 / (x - 1.5) if x != 1.5 else np.nan, (1, 2), (0, 1), (2, 3))


@given(lengths=st.tuples(*[st.floats(0.5, 5.0)] * 4), th2=st.tuples(*[st.floats(-np.pi, np.pi)] * 3),
       sigma=st.sampled_from([1, -1]))
def test_freudenstein_recovers_any_four_bar(lengths, th2, sigma):
    r1, r2, r3, r4 = lengths
    th4 = fb_oracle(r1, r2, r3, r4, np.array(th2), sigma=sigma)["th4"]
    assume(np.all(np.isfinite(th4)))
    M = np.stack((np.cos(th4), -np.cos(th2), np.ones(3)), axis=1)
    assume(np.linalg.cond(M) < 1e6)
    K = [r1 / r2, r1 / r4, (r1**2 + r2**2 - r3**2 + r4**2) / (2 * r2 * r4)]
    assert np.allclose(freudenstein(th2, th4), K, rtol=1e-6, atol=1e-6)
    assert np.allclose(four_bar_lengths(K, r1), lengths, rtol=1e-12)


def test_pivot_moves_the_whole_four_bar():
    u = np.radians([0.0, 50.0, 100.0])
    here = four_bar(coupler_point=(1, 1), frame_angle=0.4).sweep(u)
    there = four_bar(coupler_point=(1, 1), frame_angle=0.4, pivot=(2.5, -1.0)).sweep(u)
    for name in ("O2", "A", "B", "O4", "C"):
        assert np.allclose(there.position(name), here.position(name) + (2.5, -1.0), atol=1e-12)


# ---- motion generation -------------------------------------------------------------------------


@settings(max_examples=100)
@given(W=st.complex_numbers(min_magnitude=0.3, max_magnitude=3), Z=st.complex_numbers(min_magnitude=0.0, max_magnitude=3),
       beta=st.tuples(*[st.floats(0.2, 6.0)] * 2), alpha=st.tuples(*[st.floats(-3.0, 3.0)] * 2))
def test_dyad_recovers_the_dyad_that_made_the_positions(W, Z, beta, alpha):
    b, a = np.r_[0.0, beta], np.r_[0.0, alpha]
    P = W * np.exp(1j * b) + Z * np.exp(1j * a)  # the ground pivot at the origin
    M = np.column_stack((np.exp(1j * b[1:]) - 1, np.exp(1j * a[1:]) - 1))
    assume(abs(np.linalg.det(M)) > 1e-3)
    Wf, Zf = dyad(np.column_stack((P.real, P.imag, a)), beta)
    assert abs(Wf - W) < 1e-8 and abs(Zf - Z) < 1e-8


def test_three_positions_recover_a_known_four_bar():
    """Positions made by a known four-bar (pivot at (1, 2)), with its crank's and rocker's
    rotations as the free choices: the dyads give back the same linkage."""
    r1, r2, r3, r4, p, q = 4.0, 1.5, 3.5, 3.0, 1.5, 1.0
    th2 = np.radians([40.0, 75.0, 120.0])
    o = fb_oracle(r1, r2, r3, r4, th2, p=p, q=q)
    P = np.column_stack((o["C"] + (1, 2), o["th3"]))
    s = motion_four_bar(P, beta=th2[1:] - th2[0], gamma=wrap(o["th4"][1:] - o["th4"][0]))
    d = s.design
    assert np.allclose([d["ground"], d["crank"], d["coupler"], d["rocker"]], [r1, r2, r3, r4], rtol=1e-10)
    assert np.allclose(d["pivot"], (1, 2), atol=1e-10) and np.allclose(d["coupler_point"], (p, q), atol=1e-10)


def test_three_positions_are_passed_in_point_and_angle():
    P = np.array([(1.0, 2.0, np.radians(10)), (2.2, 2.9, np.radians(35)), (3.0, 2.5, np.radians(70))])
    s = motion_four_bar(P, beta=np.radians([40, 95]), gamma=np.radians([15, 50]))
    assert s.ok
    # planar's own sweep of the built four-bar, at the crank angles of the positions
    res = four_bar(**s.design).sweep(s.inputs)
    assert np.allclose(res.position("C"), P[:, :2], atol=1e-9, rtol=0)
    th = res.angle("coupler") - res.angle("coupler")[0] + P[0, 2]
    assert np.allclose(wrap(th - P[:, 2]), 0, atol=1e-9)
    assert s.errors.shape == (3, 2) and s.max_error < 1e-9
    assert np.allclose(s.inputs - s.inputs[0], [0, *np.radians([40, 95])])


@pytest.fixture
def five_positions():
    """Five positions of a known four-bar's coupler, with its crank's and rocker's rotations."""
    r1, r2, r3, r4, p, q = 4.0, 1.5, 3.5, 3.0, 1.5, 1.0
    th2 = np.radians([40.0, 60, 85, 110.0, 135])
    o = fb_oracle(r1, r2, r3, r4, th2, p=p, q=q)
    return np.column_stack((o["C"], o["th3"])), th2[1:] - th2[0], wrap(o["th4"][1:] - o["th4"][0])


def test_four_positions_by_the_compatibility_equation(five_positions):
    P, beta, gamma = five_positions
    P, beta, gamma = P[:4], beta[:3], gamma[:3]
    assert any(np.allclose(b, beta, atol=1e-12) for b in compatible(P, beta[0]))
    assert any(np.allclose(g, gamma, atol=1e-12) for g in compatible(P, gamma[0]))
    # every compatible set makes a dyad through all four positions
    for b in compatible(P, 1.0) + compatible(P, 2.5):
        W, Z = dyad(P, b)
        z = P[:, 0] + 1j * P[:, 1]
        assert np.allclose(z[0] - Z - W + W * np.exp(1j * np.r_[0, b]) + Z * np.exp(1j * (P[:, 2] - P[0, 2])), z,
                           atol=1e-12)
    with pytest.raises(SynthesisError, match="compatible"):
        dyad(P, [beta[0], beta[1], beta[2] + 0.1])
    s = motion_four_bar(P, beta=beta, gamma=gamma)
    assert s.ok and s.max_error < 1e-9
    beta2, centre, circle = burmester_curves(P, samples=720)
    # the crank's pivots on the curves: its ground pivot O2 = 0, its moving pivot A in position 1
    k = np.argmin(np.abs(beta2 - beta[0]))
    A1 = 1.5 * np.exp(1j * np.radians(40))
    assert np.nanmin(np.abs(centre[k - 1:k + 2])) < 0.05 and np.nanmin(np.abs(circle[k - 1:k + 2] - A1)) < 0.05


def test_five_positions_by_burmester_points(five_positions):
    P, beta, gamma = five_positions
    found = burmester_points(P)
    assert len(found) in (2, 4)
    for true in (beta, gamma):
        assert any(np.allclose(np.exp(1j * f), np.exp(1j * true), atol=1e-9) for f in found)
    s = motion_four_bar(P, beta=beta, gamma=gamma)
    res = four_bar(**s.design).sweep(s.inputs)
    assert np.allclose(res.position("C"), P[:, :2], atol=1e-9)


def test_dyad_refuses_a_singular_choice():
    P = [(0, 0, 0), (1, 0, 0.3), (2, 1, 0.6)]
    with pytest.raises(SynthesisError, match="singular"):
        dyad(P, [0.3, 0.6])  # the coupler's own rotations: W and Z parallel
    assert np.all(np.isfinite(dyad(P, [0.5, 1.0])))


# ---- path generation ---------------------------------------------------------------------------


def known_targets(u):
    m = four_bar(4, 1.5, 3.5, 3, coupler_point=(1.5, 1.0), pivot=(1, 2), frame_angle=0.3)
    return m.sweep(np.r_[0.0, u]).position("C")[1:]


def check_found(s, T, point="C"):
    """The answer passes every target within 1e-6 of their size on planar's own sweep of the
    built mechanism, and is defect-free between the first target and the last."""
    size = np.ptp(T, axis=0).max()
    res = s.builder(**s.design).sweep(s.inputs)
    assert np.all(np.hypot(*(res.position(point) - T).T) < 1e-6 * size)
    assert s.ok and s.max_error < 1e-6 * size
    assert s.sweep.ok.all()
    assert not [e for e in s.sweep.events if e.kind in ("limit", "bifurcation", "singular")]
    assert np.all(np.sign(s.sweep.branch) == np.sign(s.sweep.branch[0]))
    assert np.all(np.diff(s.inputs) > 0) or np.all(np.diff(s.inputs) < 0)


@pytest.mark.parametrize("seed", range(5))
def test_four_bar_path_generation_on_a_known_four_bar(seed):
    T = known_targets(np.radians(np.linspace(20, 250, 7)))
    check_found(path_four_bar(T, seed=seed), T)


def test_path_generation_free_timing_is_reproducible():
    T = known_targets(np.radians(np.linspace(20, 250, 6)))
    s = path_four_bar(T, seed=1)
    check_found(s, T)
    # the same seed, the same linkage: to rounding, as the refinement ends anywhere on the family of
    # exact solutions (15 unknowns for 12 equations), where last-bit differences of vectorised
    # functions leave it
    again = path_four_bar(T, seed=1).design
    assert again.keys() == s.design.keys() and again["crossed"] == s.design["crossed"]
    for k in ("ground", "crank", "coupler", "rocker", "frame_angle", "start", "pivot", "coupler_point"):
        assert np.allclose(again[k], s.design[k], rtol=1e-6, atol=1e-6 * np.ptp(T, axis=0).max())


def test_path_generation_with_prescribed_timing():
    u = np.radians(np.linspace(20, 250, 6))
    T = known_targets(u)
    s = path_four_bar(T, timing=u, seed=1)
    check_found(s, T)
    assert np.allclose(s.inputs - s.inputs[0], u - u[0], atol=1e-12)


def test_path_generation_follows_a_curve_of_many_points():
    T = known_targets(np.radians(np.linspace(10, 330, 25)))  # more targets than a four-bar has freedoms
    check_found(path_four_bar(T), T)


SIX = dict(ground=4.0, crank=1.5, coupler=4.0, rocker=3.5, coupler_point=(2.0, 1.5), link_5=4.0, link_6=3.0,
           pivot_6=(2.0, 6.0))


def test_stephenson_tracer_is_the_catalogue_six_bar_with_a_tracer():
    from planar.mechanisms import stephenson_six_bar
    from planar.synthesis.families import tracer_points

    u = np.radians(np.arange(0.0, 360.0, 30.0))
    ours = stephenson_tracer(**SIX, tracer=(1.0, 0.5)).sweep(u)
    theirs = stephenson_six_bar(**SIX).sweep(u)
    for name in ("A", "B", "C", "D", "O6"):
        assert np.allclose(ours.position(name), theirs.position(name), atol=1e-12)
    # the search's closed form: the same tracer
    X = np.r_[0, 0, np.log(4), 0, np.log([1.5, 4.0, 3.5]), 2.0, 1.5, 2.0, 6.0, np.log([4.0, 3.0]), 1.0, 0.5]
    P, reach = tracer_points(X[None], np.array([[1.0, 1.0]]), u[None])
    assert np.allclose(np.column_stack((P[0].real, P[0].imag)), ours.position("P"), atol=1e-12) and np.all(reach <= 1)


@pytest.mark.parametrize("seed", range(5))
def test_six_bar_path_generation_through_more_points_than_a_four_bar_can(seed):
    m = stephenson_tracer(**{**SIX, "pivot_6": (3.0, 4.0)}, tracer=(1.0, 0.5), pivot=(1.0, -2.0))
    T = m.sweep(np.radians(np.linspace(0, 300, 11))).position("P")
    check_found(path_six_bar(T, seed=seed), T, point="P")


@pytest.mark.parametrize("family", [FOUR_BAR, STEPHENSON])
def test_the_search_moves_designs_with_their_curves(family):
    """The search's similarity move z -> a z + b of a design moves its tracer's points alike
    and turns the crank angles by arg a."""
    rng = np.random.default_rng(0)
    X, sigma = family.sample(rng.uniform(size=(50, family.cube)))
    a, b = rng.normal(size=50) * np.exp(2j * np.pi * rng.uniform(size=50)), rng.normal(size=50) + 1j
    th = rng.uniform(-np.pi, np.pi, (50, 7))
    P, reach = family.points(X, sigma, th)
    Q, moved = family.points(family.move(X, a, b), sigma, th + np.angle(a)[:, None])
    ok = reach <= 1
    assert ok.any() and np.allclose(moved, reach, rtol=1e-9)  # |cos gamma| is a ratio of lengths
    assert np.allclose(Q[ok], (a[:, None] * P + b[:, None])[ok], atol=1e-9 * np.abs(a).max())


def test_path_generation_says_when_it_fails():
    T = np.random.default_rng(3).uniform(0, 1, (12, 2))  # 24 equations, 21 unknowns
    with pytest.raises(SynthesisError, match="found no defect-free four-bar"):
        path_four_bar(T, designs=2000, refine=1)
    with pytest.raises(InputError, match="coincide"):
        path_four_bar(np.zeros((3, 2)))


def test_refining_every_design_leaves_out_those_shrunk_to_a_point():
    # (refine = designs kept designs whose best move scales them by 0: a RuntimeWarning from log 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert path_four_bar([(0, 0), (1, 0), (1, 1)], designs=2000, refine=2000).ok


# ---- defects -----------------------------------------------------------------------------------


def test_defect_not_assemblable():
    d = dict(ground=4, crank=3, coupler=3, rocker=3, coupler_point=(1, 1))  # a triple rocker: +-117 deg
    s = path_check(d, np.radians([0, 60, 150]), np.zeros((3, 2)))
    assert any(m.startswith("not assemblable") for m in s.defects)
    assert path_check(d, np.radians([0, 60, 110]), np.zeros((3, 2))).ok


def test_defect_branch_event_and_change_of_circuit():
    d = dict(ground=4, crank=2, coupler=4, rocker=2, coupler_point=(1, 1), start=0.5)  # a parallelogram
    s = path_check(d, [0.5, 2.0, 4.0], np.zeros((3, 2)))
    assert any("bifurcation" in m for m in s.defects)
    assert any(m.startswith("change of circuit") for m in s.defects)
    assert path_check(d, [0.5, 2.0, 3.0], np.zeros((3, 2))).ok


def test_defect_a_target_reached_only_in_the_other_assembly_mode():
    """Three positions give a four-bar through them in some assembly mode at each; where the
    one built misses the second (its other mode passes it), that is a circuit defect."""
    P = [(0, 0, 0), (1, 0.5, 0.35), (2, 0.6, 0.785)]
    s = motion_four_bar(P, beta=[1.0, 1.3], gamma=[2.0, -0.5])
    assert not s.ok and s.max_error > 0.5
    assert [m.split(" missed")[0] for m in s.defects] == ["target 2"] and "circuit defect" in s.defects[0]
    assert np.max(s.errors[[0, 2]]) < 1e-12
    held = motion_four_bar(P, beta=[0.5, 1.2], gamma=[0.3, 0.9])
    assert held.max_error < 1e-12 and not any("missed" in m for m in held.defects)


def test_defect_wrong_order():
    d = dict(ground=4, crank=2, coupler=3, rocker=4, coupler_point=(1, 1))
    s = path_check(d, [0.0, 1.0, 0.5, 2.0], np.zeros((4, 2)))
    assert any(m.startswith("wrong order") for m in s.defects)
    assert path_check(d, [0.0, 0.5, 1.0, 2.0], np.zeros((4, 2))).ok


def test_defect_six_bar_second_loop():
    """The six-bar's links 5 and 6 reach 5 of the 2.3 to 5.8 that C comes from O6 over a turn:
    its second loop breaks from about 200 deg of crank on."""
    d = {**SIX, "link_5": 3.0, "link_6": 2.0, "tracer": (1.0, 0.5)}
    s = path_check(d, [0.0, 1.5, 4.0], np.zeros((3, 2)))
    assert any(m.startswith("not assemblable") for m in s.defects)
    assert any(m.startswith("wrong order") for m in path_check(d, [0.0, 1.0, 2.0, 0.5], np.zeros((4, 2))).defects)
    assert path_check(d, [0.0, 1.0, 2.0], np.zeros((3, 2))).ok


def test_defect_poor_transmission():
    d = dict(ground=4, crank=2, coupler=3, rocker=4, coupler_point=(1, 1))  # 28.96 deg at worst over a turn
    u = np.radians([0, 90, 180, 270, 350])
    s = path_check(d, u, np.zeros((5, 2)), min_transmission=np.radians(35))
    assert any(m.startswith("transmission angle down to 29") for m in s.defects)
    assert path_check(d, u, np.zeros((5, 2)), min_transmission=np.radians(25)).ok


def test_save_writes_a_mechanism_file_over_the_targets(tmp_path):
    from planar import io

    P = np.array([(1.0, 2.0, np.radians(10)), (2.2, 2.9, np.radians(35)), (3.0, 2.5, np.radians(70))])
    s = motion_four_bar(P, beta=np.radians([40, 95]), gamma=np.radians([15, 50]))
    doc = io.load(s.save(tmp_path / "m.json"))
    assert np.allclose(doc.sweep.start + doc.sweep.stop, np.degrees(s.inputs[[0, -1]]))
    res = doc.mechanism.sweep(s.inputs)
    assert np.allclose(res.position("C"), P[:, :2], atol=1e-9)


def test_draw_shows_the_targets():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    P = np.array([(1.0, 2.0, np.radians(10)), (2.2, 2.9, np.radians(35)), (3.0, 2.5, np.radians(70))])
    ax = motion_four_bar(P, beta=np.radians([40, 95]), gamma=np.radians([15, 50])).draw()
    marks = [ln for ln in ax.lines if ln.get_label() == "targets"]
    assert len(marks) == 1 and np.allclose(marks[0].get_xydata(), P[:, :2])


# ---- bad arguments -----------------------------------------------------------------------------

P4 = [(0, 0, 0), (1, 0.2, 0.3), (1.8, 0.6, 0.7), (2.4, 1.3, 1.0)]
P5 = P4 + [(2.6, 2.0, 1.2)]
THREE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.3), (1.5, 0.5, 0.6)]
FAR = [(1e308, 0.0, 0.0), (-1e308, 0.0, 0.3), (1.5, 0.5, 0.6)]
DESIGN = dict(ground=4, crank=2, coupler=3, rocker=4, coupler_point=(1, 1))
TWO = [(0.0, 0.0), (1.0, 0.6)]
ANGLES = np.radians([45, 105]), np.radians([135, 225])
SAMPLES = r"samples must be a whole number from 2 to 100000 \(values of beta_2 over a turn; the default is \d+\), got "

BAD_SYNTHESIS_CALLS = [
    # (call, message): each an InputError, no numpy warning on the way
    (lambda: compatible(P4, None), r"beta2 must be a finite angle in radians .*, got None"),  # (a TypeError)
    (lambda: compatible(P4, "x"), r"beta2 must be a finite angle .*, got 'x'"),
    (lambda: compatible(P4, []), r"beta2 must be a finite angle .*, got \[\]"),
    (lambda: compatible(P4, 10**400), r"beta2 must be a finite angle"),  # (an OverflowError)
    (lambda: compatible(P4, np.array([])), r"beta2 must be a finite angle"),  # (a numpy ValueError)
    (lambda: compatible(P4, np.nan), r"beta2 must be a finite angle .*, got nan"),  # (a RuntimeWarning)
    (lambda: compatible(P4, np.inf), r"beta2 must be a finite angle .*, got inf"),
    (lambda: compatible(P4, np.complex128(1)), r"beta2 must be a finite angle"),  # (its real part)
    (lambda: compatible(np.array(P4) + 0j, 0.5), r"positions must be an \(N, 3\) array"),  # (a ComplexWarning)
    (lambda: burmester_curves(P4, -1), SAMPLES + "-1"),  # (a ValueError from linspace)
    (lambda: burmester_curves(P4, np.nan), SAMPLES + "nan"),
    (lambda: burmester_curves(P4, 10**400), SAMPLES + "1000"),
    (lambda: burmester_curves(P4, None), SAMPLES + "None"),  # (a TypeError)
    (lambda: burmester_curves(P4, 10**7), SAMPLES + "10000000"),  # (minutes of work)
    (lambda: burmester_curves(P4, 2.5), SAMPLES + "2.5"),
    (lambda: burmester_points(P5, -1), SAMPLES + "-1"),  # (no points found)
    (lambda: burmester_points(P5, None), SAMPLES + "None"),
    (lambda: burmester_points(P5, 10**5 + 1), SAMPLES + "100001"),
    (lambda: motion_four_bar(FAR, beta=[0.5, 1.0], gamma=[0.3, 0.7]),  # (a RuntimeWarning: overflow)
     r"positions reach x, y = 1e\+308, .*: give x, y within \+-1e\+100"),
    (lambda: dyad(FAR, [0.5, 1.0]), r"positions reach x, y = 1e\+308"),
    (lambda: motion_four_bar(THREE, beta=[1e9, 1e9], gamma=[0.3, 0.7]),  # (a MemoryError: 213 GiB of values)
     r"the design is checked by a sweep .* 1e\+09 rad of travel, more than 10 turns: give inputs within a turn"),
    (lambda: path_check(DESIGN, [0, 1e4, 1e4], np.zeros((3, 2))),  # (out of order: swept as given, minutes)
     r"1e\+04 rad of travel, more than 10 turns"),
    (lambda: dyad(np.zeros((0, 3)), []), r"motion generation takes 3, 4 or 5 positions, got 0"),
    (lambda: dyad(THREE, np.array([0.5, 1.0]) + 0j), r"rotations must be 2 finite angles"),  # (a ComplexWarning)
    (lambda: path_check(DESIGN, None, TWO), r"inputs must hold one finite crank angle \(radians\) per target \(2\), "
                                            r"got None"),  # (an IndexError)
    (lambda: path_check(DESIGN, [0, 1, 2], TWO), r"inputs must hold one finite crank angle .*, got \[0, 1, 2\]"),
    (lambda: path_check(DESIGN, "abc", TWO), r"inputs must hold one finite crank angle .*, got 'abc'"),
    (lambda: path_check(DESIGN, [0, np.nan], TWO), r"inputs must hold one finite crank angle .*, got \[0, nan\]"),
    (lambda: path_check(DESIGN, [[0], [1]], TWO), r"inputs must hold one finite crank angle"),  # (a TypeError)
    (lambda: path_check(DESIGN, [0, 1], TWO, "x"), r"min_transmission must be an angle from 0 to pi/2 .*, got 'x'"),
    (lambda: path_check(DESIGN, [0, 1], TWO, [0.5]), r"min_transmission must be an angle .*, got \[0.5\]"),
    (lambda: path_check({**DESIGN, "bogus": 1}, [0, 1], TWO),  # (a TypeError from four_bar)
     r"design has an unknown key 'bogus': give four_bar's keyword arguments \(ground, crank"),
    (lambda: path_check({**DESIGN, "link_5": 3}, [0, 1], TWO), r"design lacks 'link_6': give stephenson_tracer's"),
    (lambda: path_four_bar([(0, 0), (1e308, 0), (-1e308, 1)]),  # (a RuntimeWarning: overflow)
     r"target points reach 1e\+308, beyond the numbers a sketch holds \(\+-1e\+100\)"),
    (lambda: path_four_bar(np.zeros((3, 2)) + 0j), r"targets must be an \(N, 2\) array"),  # (a ComplexWarning)
    (lambda: precision_points((1, 2), 3, spacing=np.array([1.0, 1.5, 2.0])),  # (a numpy ValueError)
     r"spacing must be 'chebyshev' or 'even', got array"),
    (lambda: function_four_bar(np.log10, (0, 7), *ANGLES),  # (a RuntimeWarning: log10(0))
     r"f must take different finite values at the ends of x_range \(0.0, 7.0\), got -inf"),
    (lambda: function_four_bar(lambda x: complex(x, 1), (1, 2), *ANGLES),  # (a ComplexWarning)
     r"f must give one number for each x \(a real float\), got \(1.06698\d*\+1j\) at x = 1.06698"),
    (lambda: function_four_bar(lambda x: np.complex128(x), (1, 2), *ANGLES), r"got (np.complex128)?\(1.06"),
    (lambda: function_four_bar(lambda x: [x, x], (1, 2), *ANGLES),
     r"f must give one number .*, got \[(np.float64\()?1.06"),
    (lambda: function_four_bar(lambda x: 1e308 if x < 1.5 else -1e308, (1, 2), *ANGLES),  # (a RuntimeWarning)
     r"f's values at the precision points .* overflow: give f in other units"),
    (lambda: function_four_bar(np.sin, (-1e308, 1e308), *ANGLES),  # (a RuntimeWarning: overflow)
     r"x_range must be within \+-1e\+100, got \(-1e\+308, 1e\+308\): give it in another unit"),
    (lambda: function_slider_crank(np.sin, (0, 1), np.radians([45, 105]), (-1e308, 1e308)),
     r"output_range must be within \+-1e\+100"),
    (lambda: freudenstein(np.array([1, 2, 3]) + 0j, [1, 2, 3]), r"th2 must be a list of numbers"),  # (a ComplexWarning)
]


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("call, message", BAD_SYNTHESIS_CALLS)
def test_bad_synthesis_arguments_are_input_errors(call, message):
    with pytest.raises(InputError, match=message):
        call()


@pytest.mark.parametrize("link, message", [
    (None, "must be finite, got None"),  # (each a TypeError in dimensions.circle_circle)
    ("x", "must be numeric, got 'x'"),
    ((1, 2, 3), r"must have shape \(\), got \(1, 2, 3\)"),
    (-3, "must be positive, got -3"),
])
@pytest.mark.parametrize("which", ["link_5", "link_6"])
def test_stephenson_tracer_refuses_bad_links_by_name(which, link, message):
    links = {"link_5": 3, "link_6": 3, which: link}
    with pytest.raises(ModelError, match=which + " " + message):
        stephenson_tracer(4, 2, 3, 4, coupler_point=(1, 1), pivot_6=(5, 3), tracer=(1, 0), **links)


def test_burmester_samples_take_numpy_integers():
    beta2, centre, circle = burmester_curves(P4, np.int64(4))
    assert len(beta2) == 3 and centre.shape == circle.shape == (3, 2)
    assert burmester_points(P5, np.int32(2)) == []


# ---- command line ------------------------------------------------------------------------------


def test_cli_synth_path_writes_a_mechanism_file_through_the_targets(tmp_path, capsys):
    from planar import io
    from planar.cli import main

    u = np.linspace(20, 250, 6)
    T = known_targets(np.radians(u))
    csv = tmp_path / "targets.csv"
    csv.write_text("x,y,input\n" + "".join(f"{x:.17g},{y:.17g},{a:.17g}\n" for (x, y), a in zip(T, u)))
    assert main(["synth", "path", str(csv), "--timing", "--seed", "1", "--no-plot"]) == 0
    assert "no defects" in capsys.readouterr().out
    doc = io.load(tmp_path / "targets-synth.json")
    model = doc.mechanism.compile()
    U, _, _ = doc.sweep.values(model, doc.units)
    start = U[0, 0]
    res = model.sweep(start + np.radians(u - u[0]))
    assert np.allclose(res.position("C"), T, atol=1e-6 * np.ptp(T, axis=0).max())


def test_cli_synth_function_from_a_table(tmp_path, capsys):
    from planar import io
    from planar.cli import main

    csv = tmp_path / "log.csv"
    x = np.linspace(1, 2, 101)
    csv.write_text("x,y\n" + "".join(f"{a:.17g},{np.log10(a):.17g}\n" for a in x))
    assert main(["synth", "function", str(csv), "--input-range", "45", "105", "--output-range", "135", "225",
                 "--no-plot"]) == 0
    assert "no defects" in capsys.readouterr().out
    # the table's interpolation is close to log10: the design is close to the exact one's
    exact = function_four_bar(np.log10, (1, 2), np.radians([45, 105]), np.radians([135, 225])).design
    doc = io.load(tmp_path / "log-synth.json")
    assert np.allclose(doc.data["sweep"]["start"], 45 + 60 * (precision_points((1, 2))[0] - 1))
    got = four_bar_lengths(freudenstein(*_angles(doc.mechanism)), 1.0)
    assert np.allclose(np.abs(got), [exact[k] for k in ("ground", "crank", "coupler", "rocker")], rtol=1e-3)


def _angles(mech):
    res = mech.sweep(np.radians([50.0, 75.0, 100.0]))
    return res.angle("crank"), res.angle("rocker")


def test_cli_synth_reports_bad_files(tmp_path, capsys):
    from planar.cli import main

    csv = tmp_path / "bad.csv"
    csv.write_text("x,y,angle\n1,2,10\n2,oops,20\n3,1,30\n")
    assert main(["synth", "motion", str(csv), "--beta", "40", "95", "--gamma", "15", "50"]) == 1
    assert "line 3, column y" in capsys.readouterr().err
    csv.write_text("x,y\n1,2\n2,3\n3,1\n")
    assert main(["synth", "path", str(csv), "--timing"]) == 1
    assert "input column" in capsys.readouterr().err
    csv.write_text("x,y\n1,2\n2,nan\n3,1e400\n")  # (it named neither the file nor the row)
    assert main(["synth", "path", str(csv)]) == 1
    assert f"{csv}: line 3, column y: 'nan' is not a finite number" in capsys.readouterr().err


@pytest.mark.parametrize("targets, message", [
    ([(1e9, 1e9), (1e9 + 1, 1e9), (1e9 + 1, 1e9 + 1)], "span 1 and lie up to 1e\\+09 from the origin"),  # (12 s)
    ([(0, 0), (1e-200, 0), (2e-200, 1e-200)], "span 2e-200"),  # (no design found, the best missing by 1e-16)
    ([(0, 0), (1, np.nan), (2, 1)], r"target point 1 is \(1.0, nan\): give finite points"),
])
def test_targets_a_sketch_cannot_hold_are_refused_up_front(targets, message):
    with pytest.raises(InputError, match=message):
        path_four_bar(targets, designs=2000)


@pytest.mark.parametrize("problem, options, message", [
    ("path", [], "target points reach 1e+308, beyond the numbers a sketch holds"),
    ("function", ["--input-range", "0", "90", "--output-range", "0", "90"], "the x column must increase"),
])
def test_cli_synth_far_targets_print_one_error_line(tmp_path, problem, options, message):
    # (numpy's overflow warnings came first)
    (tmp_path / "huge.csv").write_text("x,y\n1e308,1e308\n-1e308,1e308\n0,0\n")
    run = subprocess.run([sys.executable, "-m", "planar.cli", "synth", problem, "huge.csv", *options],
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 1
    assert run.stderr.splitlines() == [run.stderr.strip()] and run.stderr.startswith("planar: error:")
    assert message in run.stderr
