"""Whole circuits (the input reversing at each limit) against the closed forms of
tests/oracles.py: limit inputs, coupler curves on both assembly modes, rates, closure."""

import numpy as np
import pytest
from scipy.optimize import fsolve

import planar.circuit
from planar import AssemblyError, InputError, Status
from planar.analysis import grashof
from planar.mechanisms import four_bar, gear_train, geared_five_bar, open_chain, planetary_gear_train, rack_and_pinion
from tests import oracles

PQ = (1.2, 0.8)  # coupler point: 1.2 along A -> B, 0.8 to its left


def _stretches(res):
    """(first, last) sample index of each stretch: the limits split the circuit."""
    cuts = [0] + [e.index for e in res.events if e.kind == "limit"] + [len(res) - 1]
    return list(zip(cuts[:-1], cuts[1:]))


def _closes(res):
    """The last pose is the first: every named point back in place, every angle back modulo
    a turn."""
    model = res.model
    for name in model.points:
        np.testing.assert_allclose(res.position(name)[-1], res.position(name)[0], atol=1e-12 * model.L)
    for b in model.body_names[1:]:
        turns = (res.angle(b)[-1] - res.angle(b)[0]) / (2 * np.pi)
        assert abs(turns - round(turns)) < 1e-12, b


def _holds_constraints(res):
    model = res.model
    posed = np.all(np.isfinite(res.q), axis=1)
    assert posed.all()
    Phi, _ = model.system.evaluate(res.q, res.inputs, jacobian=False)
    assert np.max(np.abs(Phi * model.row_scale)) <= 1e-12


def _rates_match_differences(res, point):
    """Velocities and accelerations against differences along the circuit, over the middle
    half of each stretch: five-point differences in the sample index k (the samples are
    evenly spaced along the circuit, where positions and the input are smooth) of the point's
    position P and the time t (input / rate: the input acceleration is 0), then dP/dt = P'/t'
    and d2P/dt2 = (P'' t' - P' t'') / t'^3. The spacing is even only to the trace's chords
    (the guesses' parameter), so the differences hold to ~1e-5, not to rounding."""
    P, V, A = res.position(point), res.velocity(point), res.acceleration(point)
    checked = 0
    for a, b in _stretches(res):
        m = max(2, (b - a) // 4)
        i = np.arange(a + m, b - m + 1)
        if i.size == 0:
            continue
        near = i[:, None] + np.arange(-2, 3)
        d1, d2 = np.array([1, -8, 0, 8, -1]) / 12, np.array([-1, 16, -30, 16, -1]) / 12
        tt = res.inputs[near, 0] / res.input_rates[i, 0][:, None]  # one rate over a stretch
        t1, t2 = tt @ d1, tt @ d2
        P1, P2 = np.einsum("k,ikj->ij", d1, P[near]), np.einsum("k,ikj->ij", d2, P[near])
        V_fd = P1 / t1[:, None]
        A_fd = (P2 * t1[:, None] - P1 * t2[:, None]) / (t1**3)[:, None]
        assert np.max(np.abs(V_fd - V[i])) <= 1e-4 * (1 + np.max(np.abs(V[i])))
        assert np.max(np.abs(A_fd - A[i])) <= 1e-3 * (1 + np.max(np.abs(A[i])))
        checked += i.size
    assert checked > len(res) // 3


def _limits(res):
    return [e.input for e in res.events if e.kind == "limit"]


# ---- a triple rocker -------------------------------------------------------------------------


def test_triple_rocker_circuit_runs_limit_to_limit_on_both_assembly_modes():
    r1, r2, r3, r4 = 4.0, 3.0, 3.0, 3.0
    assert oracles.grashof(r1, r2, r3, r4) == "triple-rocker" == grashof(r1, r2, r3, r4).kind
    res = four_bar(r1, r2, r3, r4, coupler_point=PQ, start=0.5).circuit(samples=801, velocity=2.0)
    [(lo, hi)] = oracles.four_bar_input_limits(r1, r2, r3, r4)
    # up from the sketch to one limit, down to the other, back up to the sketch
    assert [e.kind for e in res.events] == ["limit", "limit"]
    assert _limits(res) == pytest.approx([hi, lo], abs=1e-13)
    x = res.inputs[:, 0]
    (a, b), (c, d), (e, f) = _stretches(res)
    assert x[0] == x[-1] == 0.5 and x[b] == _limits(res)[0] and x[d] == _limits(res)[1]
    assert np.all(np.diff(x[a : b + 1]) > 0) and np.all(np.diff(x[c : d + 1]) < 0) and np.all(np.diff(x[e : f + 1]) > 0)
    assert np.all(res.status[[b, d]] == Status.LIMIT) and np.isnan(res.qd[[b, d]]).all()
    assert res.ok.sum() == len(res) - 2
    # the input's rate follows its direction: +2 up, -2 down
    assert set(res.input_rates[res.ok, 0]) == {2.0, -2.0}
    _closes(res)
    _holds_constraints(res)
    _rates_match_differences(res, "C")
    # samples evenly spaced along the circuit: the coupler curve is as fine at a limit as elsewhere
    chords = np.linalg.norm(np.diff(res.position("C"), axis=0), axis=1)
    assert chords.max() < 3 * np.median(chords)

    # the coupler curve: the sketch's closed-form assembly mode (B left of A -> O4) up to the
    # first limit, the other one down to the second, the sketch's again back to the start
    C = res.position("C")
    for (a, b), sigma in zip(_stretches(res), (1, -1, 1)):
        i = np.arange(a, b + 1)
        # (a located limit may lie an ulp outside the closed form's range, where it reads NaN)
        want = oracles.four_bar(r1, r2, r3, r4, np.clip(x[i], lo, hi), w2=res.input_rates[i, 0], p=PQ[0], q=PQ[1],
                                sigma=sigma)
        np.testing.assert_allclose(C[i], want["C"], atol=1e-7)  # the oracle is ~sqrt(eps) at a limit
        ok = res.ok[i]
        np.testing.assert_allclose(C[i[ok]], want["C"][ok], atol=1e-12)
        np.testing.assert_allclose(res.velocity("C")[i[ok]], want["C_vel"][ok], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(res.omega("rocker")[i[ok]], want["w4"][ok], rtol=1e-9, atol=1e-9)
    # so it is the union of both closed-form branches, each over the whole motion range
    (a, b), (c, d), (e, f) = _stretches(res)
    for x_mode in (np.r_[x[a : b + 1], x[e : f + 1]], x[c : d + 1]):
        assert (x_mode.min(), x_mode.max()) == pytest.approx((lo, hi), abs=1e-13)


# ---- a crank-rocker driven by its rocker ------------------------------------------------------


def test_rocker_driven_crank_rocker_swings_there_and_back_while_the_crank_turns_once():
    r1, r2, r3, r4 = 4.0, 2.0, 3.0, 3.5
    g = grashof(r1, r2, r3, r4, driver="rocker")
    assert g.kind == "crank-rocker" and not g.input_turns
    res = four_bar(r1, r2, r3, r4, driver="rocker", start=2.0, coupler_point=PQ).circuit(samples=721)
    # the rocker's range: the loop walked from O4 (ground O4 -> O2 at pi) has the rocker as its crank
    ranges = oracles.four_bar_input_limits(r1, r4, r3, r2)
    lo, hi = next((np.pi - b, np.pi - a) for a, b in ranges if a > 0)
    assert _limits(res) == pytest.approx([hi, lo], abs=1e-13)
    assert np.all(res.status[[e.index for e in res.events]] == Status.LIMIT)
    _closes(res)
    _holds_constraints(res)
    _rates_match_differences(res, "C")
    th2 = res.angle("crank")
    assert abs(abs(th2[-1] - th2[0]) - 2 * np.pi) < 1e-12  # the crank completed its turn
    # crank-driven, a crank-rocker stays on one assembly mode: the circuit is its coupler curve
    sigma = 1 if np.allclose(oracles.four_bar(r1, r2, r3, r4, th2[0], p=PQ[0], q=PQ[1])["C"], res.position("C")[0]) else -1
    want = oracles.four_bar(r1, r2, r3, r4, th2, p=PQ[0], q=PQ[1], sigma=sigma)
    np.testing.assert_allclose(res.position("C"), want["C"], atol=1e-12)
    np.testing.assert_allclose(np.angle(np.exp(1j * res.angle("rocker"))), want["th4"], atol=1e-12)


# ---- the geared five-bar -----------------------------------------------------------------------


def _five_bar_residuals(r1, R2, R4, r5, th2, th4):
    """Loop closure |C - O5|^2 - r5^2 with th3 from the rolling row (oracles.geared_five_bar),
    and its derivative in th4 (zero at a limit position of th2)."""
    r3, r4, g = R2 + R4, R4, R4 / R2
    ref = oracles.geared_five_bar(r1, R2, R4, r5, 0.0)
    th30 = ref["th30"]
    th3 = th30 + (th2 + g * (th4 - th30)) / (1 + g)
    C = r3 * np.exp(1j * th3) + r4 * np.exp(1j * th4)
    dC = 1j * r3 * np.exp(1j * th3) * g / (1 + g) + 1j * r4 * np.exp(1j * th4)
    f = np.abs(C - r1) ** 2 - r5**2
    df = 2 * np.real(np.conj(C - r1) * dC)
    return f, df, th3


def test_geared_five_bar_circuit_reverses_at_each_limit_and_closes_after_whole_turns():
    dims = (8.0, 3.0, 3.5, 6.0)
    res = geared_five_bar(*dims).circuit(samples=1201)
    th2, th4 = res.inputs[:, 0], res.angle("gear4")
    # every limit: the loop closes and d(loop)/d th4 = 0 (th2 turns back), solved from the
    # closed form near the circuit's limit
    lims = [e for e in res.events if e.kind == "limit"]
    assert len(lims) >= 2
    for e in lims:
        root = fsolve(lambda v: _five_bar_residuals(*dims, *v)[:2], [e.input, th4[e.index]], xtol=1e-13)
        assert e.input == pytest.approx(root[0], abs=1e-11)
        assert res.status[e.index] == Status.LIMIT
    # the first: the oracle's continuation from the reference configuration stops there
    up = oracles.geared_five_bar(*dims, np.array([lims[0].input - 1e-6, lims[0].input + 1e-3]))
    assert np.isfinite(up["th4"][0]) and np.isnan(up["th4"][1])
    # on the first stretch, the oracle's angles and rates
    i = np.arange(lims[0].index)
    want = oracles.geared_five_bar(*dims, th2[i])
    np.testing.assert_allclose(res.angle("arm")[i], want["th3"], atol=1e-11)
    np.testing.assert_allclose(res.omega("link5")[i], want["w5"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(res.alpha("gear4")[i], want["a4"], rtol=1e-8, atol=1e-8)
    # every pose closes the loop and keeps the gears meshed
    f, _, th3 = _five_bar_residuals(*dims, th2, th4)
    assert np.max(np.abs(f)) <= 1e-11 and np.max(np.abs(res.angle("arm") - th3)) <= 1e-12
    # the input turns back at each limit, and the circuit closes after whole input turns
    x = th2
    for (a, b), (c, d) in zip(_stretches(res)[:-1], _stretches(res)[1:]):
        assert np.sign(x[b] - x[a]) == -np.sign(x[d] - x[c])
    turns = (x[-1] - x[0]) / (2 * np.pi)
    assert turns > 1 and abs(turns - round(turns)) < 1e-12
    _closes(res)
    _holds_constraints(res)
    _rates_match_differences(res, "C")


# ---- an input that turns fully ----------------------------------------------------------------


def test_a_crank_that_turns_fully_gives_one_turn_on_one_assembly_mode():
    r1, r2, r3, r4 = 4.0, 2.0, 3.0, 4.0
    assert grashof(r1, r2, r3, r4).input_turns
    res = four_bar(r1, r2, r3, r4, coupler_point=PQ, start=1.0).circuit(samples=361, velocity=3.0, acceleration=-1.0)
    assert res.events == () and res.ok.all()
    x = res.inputs[:, 0]
    assert x[0] == 1.0 and x[-1] == pytest.approx(1.0 + 2 * np.pi, abs=1e-14) and np.all(np.diff(x) > 0)
    want = oracles.four_bar(r1, r2, r3, r4, res.inputs[:, 0], w2=3.0, a2=-1.0, p=PQ[0], q=PQ[1])
    for key, got in (("C", res.position("C")), ("C_vel", res.velocity("C")), ("C_acc", res.acceleration("C"))):
        np.testing.assert_allclose(got, want[key], atol=1e-11 * (1 + np.max(np.abs(want[key]))))
    _closes(res)


def test_a_circuit_of_an_input_that_turns_fully_is_swept_whatever_its_coordinates():
    res = planetary_gear_train(1.0, 0.5, planets=50).circuit(91)
    assert res.model.n == 156 and res.ok.all() and res.events == ()
    # the carrier turns at a third of the sun's rate (Willis, the ring held): back after three turns
    assert res.inputs[-1, 0] == 6 * np.pi
    np.testing.assert_allclose(res.omega("carrier"), 1 / 3, rtol=1e-12)
    # its poses lie on a straight line in the scaled coordinates: evenly spaced inputs
    np.testing.assert_allclose(np.diff(res.inputs[:, 0]), 6 * np.pi / 90, rtol=1e-9)


@pytest.mark.parametrize("ratio", [100, 1000])
def test_a_gear_train_of_a_large_ratio_closes_after_one_turn(ratio):
    """The circuit is that turn swept, not traced (1,000: 38 s of trace steps a fraction of a
    turn each, then an error): its blocks are the same at every pose, as regular anywhere
    (they read a close approach to a singular position: the small gear's entry is 1/ratio of
    the other's)."""
    res = gear_train([1.0, 1.0 / ratio]).circuit(73)
    assert np.all(res.status == Status.SOLVED) and not res.events and np.all(res.singularity == 1.0)
    assert res.inputs[0, 0] == 0.0 and res.inputs[-1, 0] == 2 * np.pi
    np.testing.assert_allclose(res.angle("gear2"), -ratio * res.inputs[:, 0], rtol=1e-12, atol=1e-9)


def test_a_circuit_whose_steps_stay_short_says_so(monkeypatch):
    # (a coupler of 4.3 between links of 1e6: it turns many times as fast as the crank; with
    # the limit of 1e4 steps, 10 s before the error, which named only a gear ratio)
    monkeypatch.setattr(planar.circuit, "MAX_STEPS", 200)
    with pytest.raises(AssemblyError, match="within 200 steps .* a body turns many times as fast as the input"):
        four_bar(2.0, 1e6, 4.3, 1e6).circuit(73, max_step=0.4)


def test_a_parallelogram_keeps_to_the_smooth_branch_through_its_change_points():
    r1, r2, r3, r4 = 4.0, 2.0, 4.0, 2.0
    assert oracles.grashof(r1, r2, r3, r4) == "change-point"
    res = four_bar(r1, r2, r3, r4, start=0.5, coupler_point=PQ).circuit(samples=181)
    # the branches cross where the links are in line (th2 = pi, 2 pi); the parallelogram goes on
    assert [e.kind for e in res.events] == ["bifurcation", "bifurcation"]
    assert [e.input for e in res.events] == pytest.approx([np.pi, 2 * np.pi], abs=1e-9)
    assert all("smooth branch" in e.note for e in res.events)
    assert res.ok.all()
    th2 = res.inputs[:, 0]
    np.testing.assert_allclose(np.angle(np.exp(1j * (res.angle("rocker") - th2))), 0.0, atol=1e-12)
    np.testing.assert_allclose(res.angle("coupler"), 0.0, atol=1e-12)
    _closes(res)


def test_circuit_refuses_what_it_cannot_do():
    with pytest.raises(InputError, match="exactly one input"):
        open_chain().circuit()
    with pytest.raises(InputError, match="at least 4 for 'four_bar'"):
        four_bar(4, 3, 3, 3).circuit(samples=3)
    with pytest.raises(InputError, match="whole number"):
        four_bar(4, 3, 3, 3).circuit(samples=10.5)
    with pytest.raises(InputError, match="velocity must be one finite number"):
        four_bar(4, 2, 3, 4).circuit(velocity=[1.0, 2.0])
    with pytest.raises(InputError, match="acceleration must be one finite number"):
        four_bar(4, 2, 3, 4).circuit(acceleration=np.nan)
    with pytest.raises(AssemblyError, match="does not come back to its sketch within 12 turns"):
        rack_and_pinion().circuit(samples=9)  # (the rack moves on for ever)
    res = four_bar(4, 3, 3, 3).circuit(samples=4)  # the ends and the limits, nothing between
    assert res.status.tolist() == [Status.SOLVED, Status.LIMIT, Status.LIMIT, Status.SOLVED]
