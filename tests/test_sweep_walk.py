"""No lost value, no hang: every value the branch reaches is solved whatever the start, order,
spacing and repetition of the values, and a far input costs what a near one does (the pose of a
full-turn crank repeats every turn). Closed forms from tests/oracles.py."""

import json
import os
import runpy

from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings, strategies as st

from planar import io
from planar.blocks import Plan, plan as block_plan
from planar.errors import PlanarError
from planar.events.tracer import Tracer
from planar.mechanisms import (four_bar, gear_train, geared_five_bar, inverted_slider_crank, planetary_gear_train,
                               rack_and_pinion, rolling_wheel, slider_crank, stephenson_six_bar, two_loop_six_bar,
                               watt_six_bar)
from planar.results import POSED, VALID, Status
from planar.solver import rounding
from planar.units import Units
from planar.sweep import reentry
from planar.sweep import walk as walk_module
from planar.sweep.branch import Branch
from tests import oracles
from tests.strategies import build

# a sweep with far, repeated and out-of-order values costs ~0.1-0.5 s: 40 examples in CI, the
# profile's own count in a long run (HYPOTHESIS_PROFILE=long)
LONG = os.environ.get("HYPOTHESIS_PROFILE", "ci") != "ci"
# the strategies keep only mechanisms whose crank reaches two intervals: most draws are filtered
PROPS = settings(max_examples=settings.default.max_examples if LONG else 40, deadline=None,
                 suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
length = st.floats(0.5, 5.0)


def in_range(u, intervals, margin):
    """(inside, outside): values at least ``margin`` inside one of the input intervals over a
    turn (closed forms' limits), and at least ``margin`` outside all of them."""
    x = np.angle(np.exp(1j * np.asarray(u)))
    inside, near = np.zeros(x.shape, bool), np.zeros(x.shape, bool)
    for a, b in intervals:
        for s in (-2 * np.pi, 0.0, 2 * np.pi):
            inside |= (x > a + s + margin) & (x < b + s - margin)
            near |= (x > a + s - margin) & (x < b + s + margin)
    return inside, ~near


def assert_no_lost_value(res, intervals, th3, margin=1e-6):
    """In range: posed, on the closed form's pose; out of range: NOT_ASSEMBLABLE; nowhere
    NOT_CONVERGED."""
    u, status = res.inputs[:, 0], res.status
    inside, outside = in_range(u, intervals, margin)
    posed = POSED[status]
    assert not np.any(status == Status.NOT_CONVERGED), f"NOT_CONVERGED at {u[status == Status.NOT_CONVERGED][:5]}"
    assert posed[inside].all(), f"lost: {u[inside & ~posed][:5]} {status[inside & ~posed][:5]}"
    assert np.all(status[outside] == Status.NOT_ASSEMBLABLE), f"posed out of range: {u[outside & posed][:5]}"
    if inside.any():
        err = np.abs(np.angle(np.exp(1j * (res.angle("coupler")[inside] - th3[inside]))))
        assert err.max() <= 1e-8, f"off the closed form by {err.max():.2g} rad"


class Evaluations:
    """Counts the calls of ``owner``'s ``name`` in its ``with`` block: by default the constraint
    evaluations of the sweeps (each one batch of values), the walk's work whatever the engine's
    timing; ``Evaluations(Tracer, "step")`` the arclength tracer's steps (each several
    evaluations of its own), ``Evaluations(Tracer, "correct")`` its corrector solves (one a
    step, or one per halving where it is not accepted); ``Evaluations(reentry, name)``
    ``planar.sweep.reentry``'s searches' least squares (each a batch of values, up to 200
    iterations) or its tracings round a circuit (each ~100 tracer steps)."""

    def __init__(self, owner=Plan, name="evaluate"):
        self.owner, self.name, self.calls = owner, name, 0

    def __enter__(self):
        real = getattr(self.owner, self.name)

        def counted(*args, **kw):
            self.calls += 1
            return real(*args, **kw)

        self._patch = mock.patch.object(self.owner, self.name, counted)
        self._patch.start()
        return self

    def __exit__(self, *exc):
        self._patch.stop()


def test_the_four_bar_reproduction_solves_every_value_in_range():
    r = (1.228349473246219, 1.3074591228844887, 0.2107607718255605, 1.245859010662002)
    m = four_bar(*r, start=1.222402070420413, crossed=True)
    res = m.sweep(np.linspace(0.8387657370523275, 1.2224028021397049, 181))
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1)
    assert_no_lost_value(res, oracles.four_bar_input_limits(*r), o["th3"])
    assert res.ok[1:-1].all()


def test_the_slider_crank_reproduction_solves_every_value_in_range():
    r2, r3, e = 5.474267858194692, 0.2331023228883293, 0.8351501574893155
    m = slider_crank(r2, r3, offset=e, start=2.945191833876923)
    res = m.sweep(np.linspace(2.9451917440775626, 3.0313919576882036, 181))
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e)
    assert_no_lost_value(res, oracles.slider_crank_limits(r2, r3, e, "crank"), o["th3"])
    assert res.ok[1:-1].all()


@pytest.mark.parametrize("far", [1e3, 1e6, -1e6, 12345.6789])
def test_a_far_input_costs_what_a_near_one_does(far):
    m = four_bar(4, 2, 3, 4)
    with Evaluations() as count:
        near = m.sweep([0.0, 6.0, 0.1])
    near_calls = count.calls
    with Evaluations() as count:
        res = m.sweep([0.0, far, 0.1])
    assert res.ok.all(), res
    o = oracles.four_bar(4, 2, 3, 4, res.inputs[:, 0])
    assert_no_lost_value(res, [(-np.pi, np.pi)], o["th3"])
    np.testing.assert_allclose(res.angle("rocker")[[0, 2]], near.angle("rocker")[[0, 2]], atol=1e-12)
    # one turn walked to find the period, then less than a turn each way
    assert count.calls <= 3 * near_calls + 200, (count.calls, near_calls)


@pytest.mark.parametrize("joint, axis, at, past", [(1, 0, 1e5, Status.NOT_ASSEMBLABLE), (3, 1, 1e7, Status.NOT_CONVERGED),
                                                   (10, 0, 1e7, Status.NEAR_SINGULAR)])
def test_a_pivot_moved_far_out_of_the_mechanism_is_given_up_in_bounded_work(joint, axis, at, past):
    # every joint type with one joint moved 1e5 or 1e7 from a mechanism of size ~5: the traced
    # curve runs alongside another, within GAP_CROSS, for thousands of steps of ~2e-8 rad each
    # (1e5), or each step there halved ~15 times before it is taken (1e7): 4,800-6,200 corrector
    # solves, 25-35 s, where 300-400 give the same statuses
    build = runpy.run_path(str(Path(__file__).parents[1] / "examples" / "every_joint_type.py"))["build"]
    d = io.to_dict(build(), Units())
    d["joints"][joint]["at"][axis] = at
    model = io.from_dict(d).mechanism.compile()
    with Evaluations(Tracer, "correct") as solves:
        res = model.sweep(np.linspace(0.0, 0.5, 5))
    assert solves.calls <= 1000, solves.calls
    # (joints 3 and 10 at 1e7: the values assemble, where least squares stalled at gaps of
    # 1e-8 and more in the ill-conditioned valley and joint 3's read NOT_ASSEMBLABLE; joint
    # 10's are traced to, its steps predicted with the curve's curvature; joint 3's are not
    # reached: docs/hardening.md)
    assert res.status[0] == Status.NEAR_SINGULAR and (res.status[1:] == past).all(), res


def test_a_crossing_of_branches_met_again_is_given_up_not_located_over_and_over():
    # (the file fuzz) an inverted slider-crank with its crank's pivot moved to y = 1e7: the
    # crank's end passes 1.6e-5 from O4 (1.6e-12 of the size), the branches there apart at
    # rounding, and the tracing located the same crossing eight times (MAX_EVENTS) over
    # 4,700 steps
    d = io.to_dict(inverted_slider_crank(), Units())
    d["joints"][0]["at"] = [0.0, 1e7]
    model = io.from_dict(d).mechanism.compile()
    with Evaluations(Tracer, "step") as steps:
        res = model.sweep([-1.5707963, -1.5])
    assert steps.calls <= 2000, steps.calls
    assert [e.kind for e in res.events] == ["near_singular", "bifurcation"]


def test_a_tracing_that_creeps_up_on_a_crossing_in_halved_steps_is_given_up_in_bounded_work():
    # a parallelogram of crank 3e5 and coupler 1: its branches cross at pi at an angle of
    # ~7e-6, too shallow to certify (the value past it is JUMPED); each of the three tracings
    # towards it creeps on in steps halved below CROSS_STEP, the input leading, and is given
    # up after MAX_CLOSE of them, ~915 corrector solves (~1,500 if only steps where the input
    # does not lead counted)
    model = four_bar(3e5, 1, 3e5, 1, start=0.5).compile()
    with Evaluations(Tracer, "correct") as solves:
        res = model.sweep([3.0, 3.3])
    assert solves.calls <= 3300, solves.calls
    assert list(res.status) == [Status.NEAR_SINGULAR, Status.JUMPED]


def test_a_far_input_turns_the_coupler_of_a_drag_link_by_whole_turns():
    r = (2.2446494252851754, 3.18098070513203, 2.812102452743045, 3.625213568033311)  # ground shortest
    res = four_bar(*r, start=2.28).sweep([0.0, 8896.990394966295, -1633.4524182775226, 0.1])
    o = oracles.four_bar(*r, res.inputs[:, 0])
    assert_no_lost_value(res, [(-np.pi, np.pi)], o["th3"])
    # the coupler and rocker turn with the crank: their unwrapped angles follow it
    assert abs(res.angle("coupler")[1] - res.inputs[1, 0]) < 2 * np.pi + 4


@pytest.mark.parametrize("turns", [3, 1000])
def test_a_value_whole_periods_on_of_a_rocking_input_is_a_jump(turns):
    """The crank of a four-bar whose rocker is the shortest link rocks: a value whole turns on
    from the one before is reached by moving the pose by those turns, past two limits each
    turn, so it is JUMPED (its line breaks there), where the crank of a crank-rocker turns fully
    to it."""
    rocking = four_bar(0.6258855, 3.0296554, 3.04322927, 0.5518215, start=2.54985073)
    u0 = 2.54985073
    res = rocking.sweep([u0, u0 + 0.01 + 2 * np.pi * turns, u0 + 0.02 + 2 * np.pi * turns])
    assert res.status.tolist() == [Status.SOLVED, Status.JUMPED, Status.SOLVED]
    np.testing.assert_allclose(res.position("B")[1], rocking.sweep([u0 + 0.01]).position("B")[0], atol=1e-9)
    full = four_bar(4, 2, 3, 4)
    assert full.sweep([0.0, 0.01 + 2 * np.pi * turns]).status.tolist() == [Status.SOLVED, Status.SOLVED]


@pytest.mark.parametrize("at", [32 * np.pi, 1e5])
def test_far_values_of_a_rocking_input_jump_where_a_limit_lies_between(at):
    """Far values are solved whole periods back (16 turns at a time): a dense run across the
    border of those blocks stays SOLVED (no limit between its values), a value a thousand turns
    on from the one before is JUMPED, one 0.01 on is not."""
    rocking = four_bar(0.6258855, 3.0296554, 3.04322927, 0.5518215, start=2.54985073)
    u = 2.54985073 + at
    res = rocking.sweep(np.linspace(u - 0.05, u + 0.05, 11))
    assert (res.status == Status.SOLVED).all()
    assert rocking.sweep([u, u + 0.01 + 2000 * np.pi]).status.tolist() == [Status.SOLVED, Status.JUMPED]
    assert rocking.sweep([u, u + 0.01]).status.tolist() == [Status.SOLVED, Status.SOLVED]


@st.composite
def full_turn_four_bars(draw):
    r = draw(st.tuples(length, length, length, length))
    s, p, q, l = sorted(r)
    assume(s + l < p + q - 0.05 * l and min(r) in (r[0], r[1]))  # crank-rocker or drag-link
    return r


far = st.floats(-1e5, 1e5)


@PROPS
@given(r=full_turn_four_bars(), crossed=st.booleans(), start=st.floats(-np.pi, np.pi),
       values=st.lists(far, min_size=1, max_size=6), repeat=st.integers(0, 3))
def test_far_repeated_and_shuffled_inputs_of_a_full_turn_four_bar(r, crossed, start, values, repeat):
    m = four_bar(*r, crossed=crossed, start=start)
    U = np.array(values + values[:repeat] + [start])
    with Evaluations() as count:
        res = m.sweep(U)
    # a period walked once, then less than a period to each value (~250 evaluations)
    assert count.calls <= 1000 + 500 * len(U), count.calls
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1 if crossed else 1)
    assert_no_lost_value(res, [(-np.pi, np.pi)], o["th3"])


far_turns = st.floats(1e3, 1e6).flatmap(lambda x: st.sampled_from([x, -x]))


@PROPS
@given(radii=st.lists(st.floats(0.2, 5.0), min_size=2, max_size=4), start=st.floats(-np.pi, np.pi),
       values=st.lists(far_turns, min_size=1, max_size=3))
def test_a_far_input_of_a_gear_train_of_any_ratio_costs_what_a_near_one_does(radii, start, values):
    # a ratio of no small period: the gears' angles are moved along the tangent by a turn of
    # the input, exactly (the gear rows read them linearly)
    m = gear_train(radii, start=start)
    U = np.array([start, start + 0.5] + values + [start + 0.3])
    with Evaluations() as count:
        res = m.sweep(U)
    assert res.ok.all(), res.status
    assert count.calls <= 300, count.calls
    for k, Rk in enumerate(radii, 1):
        ratio = (-1) ** (k - 1) * radii[0] / Rk
        expected = res.angle(f"gear{k}")[0] + ratio * (U - start)
        np.testing.assert_allclose(res.angle(f"gear{k}"), expected, rtol=1e-14, atol=1e-12)


@PROPS
@given(Rs=st.floats(0.2, 5.0), Rp=st.floats(0.2, 5.0), planets=st.integers(1, 3),
       fixed=st.sampled_from(["sun", "carrier", "ring"]), pick=st.booleans(), start=st.floats(-np.pi, np.pi),
       values=st.lists(far_turns, min_size=1, max_size=3))
def test_a_far_input_of_a_planetary_train_is_solved_a_whole_turn_of_its_carrier_back(Rs, Rp, planets, fixed, pick,
                                                                                       start, values):
    driver = [b for b in ("sun", "carrier", "ring") if b != fixed][int(pick)]
    m = planetary_gear_train(Rs, Rp, planets=planets, fixed=fixed, driver=driver, start=start)
    U = np.array([start, start + 0.5] + values + [start + 0.3])
    with Evaluations() as count:
        res = m.sweep(U)
    assert res.ok.all(), res.status
    assert count.calls <= 400, count.calls
    # Willis: Rs (th_s - th_c) + Rr (th_r - th_c) = 0, to rounding of angles of up to 1e6 rad
    Rr = Rs + 2 * Rp
    th = {b: (res.angle(b) - res.angle(b)[0] if b != fixed else 0.0) for b in ("sun", "carrier", "ring")}
    np.testing.assert_allclose(Rs * (th["sun"] - th["carrier"]) + Rr * (th["ring"] - th["carrier"]), 0.0,
                               atol=1e-13 * Rr * (1 + np.abs(U).max()) * (1 + Rr / min(Rs, Rp)))
    # the planets' centres a planet's pitch circle from the sun's centre, the carrier's arm
    carrier = res.angle("carrier") if fixed != "carrier" else np.zeros_like(U)
    for k in range(1, planets + 1):
        c = res.position(f"P{k}")
        # (through the carrier's angle of up to 1e6 rad: its rounding)
        np.testing.assert_allclose(np.hypot(*c.T), Rs + Rp, rtol=1e-15 * (1 + np.abs(U).max()))
        arm = np.arctan2(c[:, 1], c[:, 0]) - carrier
        np.testing.assert_allclose(np.angle(np.exp(1j * (arm - arm[0]))), 0.0, atol=1e-9)


@pytest.mark.parametrize("build, kw, L", [
    (rolling_wheel, dict(radius=0.7, track_radius=2.3), 2.3),  # the centre goes round in 2 pi (2.3 - 0.7) / 0.7
    (rolling_wheel, dict(radius=0.7, driver="centre"), 0.7),
    (rack_and_pinion, dict(radius=0.7, driver="rack"), 0.7),
])
@pytest.mark.parametrize("far", [1e4, -7e5])
def test_a_far_input_of_a_rolling_contact_is_its_near_pose_moved_along(build, kw, L, far):
    m = build(start=0.2, **kw)
    near = m.sweep([0.2, 0.5, 0.2 + (far % (2 * np.pi * L)), 0.4])
    with Evaluations() as count:
        res = m.sweep([0.2, 0.5, 0.2 + far, 0.4])
    assert res.ok.all(), res.status
    assert count.calls <= 400, count.calls
    np.testing.assert_allclose(res.q[[0, 1, 3]], near.q[[0, 1, 3]], atol=1e-12)
    if "track_radius" in kw:  # the wheel's centre a turn of it round the track on: where it was
        k = 0.7 / (2.3 - 0.7)
        phi = far * k - 2 * np.pi * np.round(far * k / (2 * np.pi))
        psi = np.angle(np.exp(1j * (-np.pi / 2 - k * 0.2 - phi)))
        np.testing.assert_allclose(res.position("centre")[2], 1.6 * np.array([np.cos(psi), np.sin(psi)]), atol=1e-9)


def test_a_far_input_of_a_geared_linkage_with_no_period_is_entered_directly_as_a_jump():
    # gear ratio 30/37: no whole turn within PERIODS brings the sketch back, and a limit every
    # few radians; a walk to 480 rad met 66 limits in 23,000 evaluations (9 s)
    m = geared_five_bar(8.0, 3.0, 3.7, 6.0, start=0.3)
    with Evaluations() as count:
        res = m.sweep([0.3, 0.6, 480.2, -777.7, 0.5])
    assert count.calls <= 1500, count.calls
    assert list(res.status[[0, 1, 4]]) == [Status.SOLVED] * 3
    # valid, in the sketch's assembly modes, and not shown continuous from the value before it
    assert res.status[2] == Status.JUMPED and res.residual[2] <= 1e-12
    model = m.compile()
    br = Branch(model, block_plan(model, None), 1e-12)
    assert np.array_equal(br.signs(res.q[2][None], res.inputs[2][None]), br.signs(model.q0[None], model.u0[None]))
    assert res.status[3] in (Status.NOT_CONVERGED, Status.NOT_ASSEMBLABLE)
    # the values near the sketch are walked from it, not entered from the far pose solved first
    # (its arm's turns differ: the gears count them)
    near = geared_five_bar(8.0, 3.0, 3.7, 6.0, start=0.3).sweep([0.3, 0.6, 0.5])
    np.testing.assert_allclose(res.q[[0, 1, 4]], near.q, atol=1e-12)


GEARED_211 = dict(ground=12.048954468833484, gear_radius_2=3.9587203040952526, gear_radius_4=3.0317816721778468,
                  link_5=12.214707038611781, crossed=True, start=3.1114766890490175)


def test_far_values_of_a_geared_linkage_cost_a_few_searches_not_a_walk_through_every_gap():
    # (found by benchmarks/fuzz_campaign.py, seed 211) limit pairs every few radians and no
    # period: from -760.6 to -828.8 the walk entered 23 ranges at their gaps' far ends (25
    # searches); past MAX_GAPS (8) on the way to one value the value itself is entered
    m = geared_five_bar(**GEARED_211)
    with Evaluations(walk_module.Walker, "enter_any") as searches:
        res = m.sweep([3.2, 2.4, -760.615743, -828.75674])
    assert searches.calls <= 12, searches.calls
    # (which far values enter moves with the rounding of the machine's linear algebra, as below)
    assert list(res.status[:2]) == [Status.SOLVED] * 2
    assert set(res.status[2:]) <= {Status.SOLVED, Status.JUMPED, Status.NOT_ASSEMBLABLE}, res.status
    assert all(res.status[i] == Status.JUMPED for i in (2, 3) if POSED[res.status[i]] and POSED[res.status[i - 1]])
    # values too far to walk to are entered directly, not by tracing round a circuit from
    # other modes (1.5 s each, and one of many stretches a direct entry may land on: which
    # ones enter moves with the rounding of the machine's linear algebra)
    with Evaluations(reentry, "around") as tracings:
        res = m.sweep([3.2, 859864.9, 831082.0, 359799.7])
    assert tracings.calls == 0
    assert res.status[0] == Status.SOLVED
    assert set(res.status[1:]) <= {Status.SOLVED, Status.JUMPED, Status.NOT_ASSEMBLABLE}, res.status
    posed = POSED[res.status]
    assert posed.sum() >= 2, res.status
    # (a far value entered right after a posed one is a jump: not shown continuous from it)
    assert all(res.status[i] == Status.JUMPED for i in range(1, 4) if posed[i] and posed[i - 1]), res.status
    model = m.compile()
    br = Branch(model, block_plan(model, None), 1e-12)
    np.testing.assert_array_equal(br.signs(res.q[posed], res.inputs[posed]),
                                  np.repeat(br.signs(model.q0[None], model.u0[None]), posed.sum(), 0))


def test_a_far_value_beyond_one_no_search_entered_is_out_of_reach_not_unconverged():
    # (found by benchmarks/fuzz_campaign.py, seed 238) no assembly in the sketch's modes is
    # found at -241.1 or -786.4, both too far to walk; -786.4, further the same way, was
    # passed over as a walk that failed nearer would be, and read NOT_CONVERGED
    m = geared_five_bar(ground=16.436079311222223, gear_radius_2=3.706950375928348, gear_radius_4=7.665512881172466,
                        link_5=8.835950584724149, crossed=True, start=-0.5835589800190943)
    res = m.sweep([-0.5835589800190943, -241.11084868, -786.35303344])
    assert list(res.status) == [Status.SOLVED, Status.NOT_ASSEMBLABLE, Status.NOT_ASSEMBLABLE]
    alone = m.sweep([-0.5835589800190943, -786.35303344])
    assert list(alone.status) == [Status.SOLVED, Status.NOT_ASSEMBLABLE]


def test_far_values_of_a_geared_linkage_are_entered_from_the_poses_solved_and_held_to_their_rounding():
    # (found by a fuzz campaign) the loop of a geared five-bar closes at many poses of the same
    # modes at one input (the arm's and gear 4's angles are tied by the gears' ratio, which has
    # no period). At 2433.87 and 77177.94 Newton from the sketch and from the pose before lands
    # in other modes only, and the way round through a limit found none; at 242585.24 and
    # 301051.79 the rows, read at angles counted that far, hold to 4e-12 at best (the rounding
    # of the angles), above the tolerance: all four came back NOT_CONVERGED
    m = geared_five_bar(ground=12.75032542703261, gear_radius_2=2.160690500077992, gear_radius_4=4.459776962368497,
                        link_5=10.819613919924373, crossed=True, start=1.2288206418630878)
    far = np.array([2433.8687011203865, -2104.1221880702237, 77177.94136920969, 242585.23608797984,
                    301051.7880473607])
    U = np.r_[1.2288206418630878 + np.linspace(-0.5, 0.5, 11), far]
    res = m.sweep(U)
    assert not np.any(res.status == Status.NOT_CONVERGED), U[res.status == Status.NOT_CONVERGED]
    assert np.all(res.status[11:] == Status.JUMPED)
    # (the rounding of angles counted to 3e5 rad through coefficients of up to ~5: 3e-10)
    model = m.compile()
    assert np.all(res.residual[11:] <= np.maximum(1e-12, rounding(model, res.q[11:], np.arange(model.n))))
    br = Branch(model, block_plan(model, None), 1e-12)
    np.testing.assert_array_equal(br.signs(res.q[11:], res.inputs[11:]),
                                  np.repeat(br.signs(model.q0[None], model.u0[None]), far.size, 0))
    # each a valid pose: the links' lengths hold
    O5 = np.array([12.75032542703261, 0.0])
    np.testing.assert_allclose(np.linalg.norm(res.position("C")[11:] - O5, axis=1), 10.819613919924373, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(res.position("C")[11:] - res.position("B")[11:], axis=1),
                               4.459776962368497, atol=1e-9)


@pytest.mark.numba
def test_far_values_of_a_geared_linkage_are_the_same_on_both_engines():
    # (found by a fuzz campaign) the poses the two engines solve differ at rounding, and Newton
    # from them at a far value landed on poses of the arm counted turns apart; at 3.25e5 rad the
    # compiled engine's Newton steps wandered at 7e-10, over the rounding of the residual, and
    # the value came back NOT_CONVERGED there and JUMPED on numpy
    m = geared_five_bar(ground=5.873086029246162, gear_radius_2=2.623475552172559, gear_radius_4=4.346267788458001,
                        link_5=6.4196522454600515, start=-2.86773692205929)
    g = np.random.default_rng(51703)
    U = -2.86773692205929 + np.r_[g.uniform(-0.5, 0.5, 20), g.choice([-1.0, 1.0], 10) * 10 ** g.uniform(2, 6, 10)]
    a, b = m.sweep(U), m.sweep(U, engine="numba")
    np.testing.assert_array_equal(a.status, b.status)
    assert not np.any(a.status == Status.NOT_CONVERGED)
    posed = POSED[a.status]
    # (to the rounding of angles counted to 4e5 rad, WANDER times over: Newton's steps there)
    np.testing.assert_allclose(a.q[posed], b.q[posed], rtol=1e-12, atol=1e-8)


def test_a_value_entered_directly_is_no_start_that_brings_values_past_a_limit_within_reach():
    # (found by a fuzz campaign) far values below the sketch, entered directly, were taken for
    # the walk's start towards the near values past the limit at -0.1971: no limit lies between
    # them, so -0.393 (other modes assemble there) came back NOT_CONVERGED
    m = geared_five_bar(ground=7.487542510533224, gear_radius_2=8.6555827519966, gear_radius_4=1.484144101101302,
                        link_5=14.922897615308479)
    g = np.random.default_rng(33203)
    U = np.r_[g.uniform(-0.5, 0.5, 20), g.choice([-1.0, 1.0], 10) * 10 ** g.uniform(2, 6, 10)]
    res = m.sweep(U)
    assert not np.any(res.status == Status.NOT_CONVERGED), U[res.status == Status.NOT_CONVERGED]
    past = (U > -1.0) & (U < -0.1971)
    assert np.all(res.status[past] == Status.NOT_ASSEMBLABLE)
    np.testing.assert_allclose(res.nearest_limit[past], -0.19709824, atol=1e-6)


@st.composite
def near_end_slider_cranks(draw):
    """A crank-driven slider-crank whose crank cannot turn, sketched within 1e-9..1e-2 of an
    end of its motion range, and that range."""
    r2, r3, e = draw(length), draw(length), draw(st.floats(-3, 3))
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    assume(len(ranges) == 1 and ranges[0][1] - ranges[0][0] < 2 * np.pi - 0.1 and ranges[0][1] - ranges[0][0] > 0.05)
    a, b = ranges[0]
    d = 10 ** draw(st.floats(-9, -2))
    start = a + d if draw(st.booleans()) else b - d
    return r2, r3, e, start, (a, b)


@PROPS
@given(case=near_end_slider_cranks(), crossed=st.booleans(), over=st.floats(0.0, 0.5), n=st.integers(2, 181),
       backwards=st.booleans())
def test_a_slider_crank_started_next_to_a_limit_loses_no_value(case, crossed, over, n, backwards):
    r2, r3, e, start, (a, b) = case
    m = slider_crank(r2, r3, offset=e, crossed=crossed, start=start)
    U = np.linspace(a - over, b + over, n)
    res = m.sweep(U[::-1] if backwards else U)
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e, sigma=-1 if crossed else 1)
    assert_no_lost_value(res, [(a, b)], o["th3"])


@st.composite
def near_end_four_bars(draw):
    r = draw(st.tuples(length, length, length, length))
    s, p, q, l = sorted(r)
    assume(abs(s + l - p - q) > 0.05 * l)
    ranges = oracles.four_bar_input_limits(*r)
    assume(len(ranges) == 1 and 0.05 < ranges[0][1] - ranges[0][0] < 2 * np.pi - 0.1)
    a, b = ranges[0]
    d = 10 ** draw(st.floats(-9, -2))
    return r, (a + d if draw(st.booleans()) else b - d), (a, b)


@PROPS
@given(case=near_end_four_bars(), crossed=st.booleans(), over=st.floats(0.0, 0.5), n=st.integers(2, 181),
       backwards=st.booleans())
def test_a_four_bar_started_next_to_a_limit_loses_no_value(case, crossed, over, n, backwards):
    r, start, (a, b) = case
    m = four_bar(*r, crossed=crossed, start=start)
    U = np.linspace(a - over, b + over, n)
    res = m.sweep(U[::-1] if backwards else U)
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1 if crossed else 1)
    assert_no_lost_value(res, [(a, b)], o["th3"])


def two_intervals(draw, ranges, margin=0.05):
    """A start drawn inside one of two input intervals over a turn (``ranges``), within
    1e-9..1e-1 of one of its ends or anywhere in it."""
    a, b = ranges[draw(st.integers(0, 1))]
    if draw(st.booleans()):
        d = min(10 ** draw(st.floats(-9, -1)), (b - a) / 2)
        return a + d if draw(st.booleans()) else b - d
    return draw(st.floats(a + 1e-9, b - 1e-9))


WORK_TWO_INTERVALS = 2000  # evaluations a sweep of a crank with two intervals may take (see below)
WORK_PER_LIMIT = 350  # or, for a sweep that locates more limits (a turn and a half: up to 7), this many each


def work_two_intervals(res):
    """The evaluations a sweep ``res`` of a crank with two intervals may take."""
    return max(WORK_TWO_INTERVALS, WORK_PER_LIMIT * sum(e.kind == "limit" for e in res.events))


@st.composite
def two_interval_four_bars(draw):
    """A crank-driven four-bar whose crank reaches two separate intervals over a turn (the
    dyad folds flat and stretches out on both sides of the ground line), and a start."""
    r = draw(st.tuples(length, length, length, length))
    ranges = oracles.four_bar_input_limits(*r)
    assume(len(ranges) == 2 and min(b - a for a, b in ranges) > 0.01)
    assume(min(ranges[1][0] - ranges[0][1], ranges[0][0] + 2 * np.pi - ranges[1][1]) > 0.05)
    return r, two_intervals(draw, ranges), ranges


@st.composite
def two_interval_slider_cranks(draw):
    """A crank-driven slider-crank whose crank reaches two separate intervals over a turn (an
    offset and a rod shorter than the crank), and a start."""
    r2, r3, e = draw(length), draw(length), draw(st.floats(-3, 3))
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    assume(len(ranges) == 2 and min(b - a for a, b in ranges) > 0.01)
    assume(min(ranges[1][0] - ranges[0][1], ranges[0][0] + 2 * np.pi - ranges[1][1]) > 0.05)
    return (r2, r3, e), two_intervals(draw, ranges), ranges


def jumping(draw, start):
    """Values over a turn around the start, in random order (or in order up or down), some
    repeated; or a turn and a half up or down from the start in steps of 0.02-0.05 (an interval
    narrower than the search's spacing past a gap holds some of them)."""
    if draw(st.integers(0, 3)) == 0:
        return start + np.arange(0.0, 3 * np.pi, draw(st.floats(0.02, 0.05))) * draw(st.sampled_from([1, -1]))
    values = draw(st.lists(st.floats(-np.pi, np.pi), min_size=1, max_size=60))
    values += values[: draw(st.integers(0, 10))]
    values = draw(st.sampled_from([sorted(values), sorted(values)[::-1], draw(st.permutations(values))]))
    return start + np.array(values)


def assert_limits_named(res, ranges):
    """Every NOT_ASSEMBLABLE value names a located limit, an end of the closed form's ranges."""
    out = res.status == Status.NOT_ASSEMBLABLE
    if out.any():
        ends = np.array([x for ab in ranges for x in ab])
        lim = res.nearest_limit[out]
        assert np.isfinite(lim).all()
        off = np.abs(np.angle(np.exp(1j * (lim[:, None] - ends[None, :])))).min(axis=1)
        assert off.max() < 1e-9, off.max()


def test_a_fold_entered_far_from_the_value_before_it_walks_no_further_back():
    # (found by the property test below in CI) the search between two values past a gap entered
    # the crank's other interval [-1.2281, -0.8874], which holds no value: the walk from the
    # entry to the value past it met a limit, and the walk back to the value before it, 0.9 rad
    # away, met the other (2,001 evaluations where 1,393 were enough)
    r, start = (3.1175782842445776, 3.9091430404448197, 0.5, 3.6), 0.8873927598944861
    U = start + np.array(sorted([1e-13, -3.1415926535897927, 1.1537900842808648, -0.902294081496438,
                                 -2.575635792658225, -3.141592653589793, -2.495844518746499, 0.15164967405108687,
                                 0.3249863062482974, -2.399383369643451, 0.0, -0.902294081496438,
                                 -0.18907418215956628]))
    with Evaluations() as count:
        res = four_bar(*r, start=start).sweep(U)
    assert_no_lost_value(res, oracles.four_bar_input_limits(*r), oracles.four_bar(*r, res.inputs[:, 0])["th3"])
    assert count.calls <= work_two_intervals(res), count.calls


@PROPS
@given(case=two_interval_four_bars(), crossed=st.booleans(), data=st.data())
def test_a_four_bar_whose_crank_reaches_two_intervals_loses_no_value(case, crossed, data):
    r, start, ranges = case
    m = four_bar(*r, crossed=crossed, start=start)
    U = jumping(data.draw, start)
    with Evaluations() as count:
        res = m.sweep(U)
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1 if crossed else 1)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)
    # the values in the order of the input: the range and each gap crossed once (~100-400); values
    # jumping across both gaps walk to a limit up to six times, ~250 evaluations each as the
    # steps shrink towards it (the most in 2000 long-run cases: 1570); a dense sweep a turn and
    # a half locates up to 7 limits, ~300 evaluations each
    assert count.calls <= work_two_intervals(res), count.calls


@PROPS
@given(case=two_interval_slider_cranks(), crossed=st.booleans(), data=st.data())
def test_a_slider_crank_whose_crank_reaches_two_intervals_loses_no_value(case, crossed, data):
    (r2, r3, e), start, ranges = case
    m = slider_crank(r2, r3, offset=e, crossed=crossed, start=start)
    U = jumping(data.draw, start)
    with Evaluations() as count:
        res = m.sweep(U)
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e, sigma=-1 if crossed else 1)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)
    assert count.calls <= work_two_intervals(res), count.calls


@PROPS
@given(r2=st.floats(3.0, 6.0), r3=st.floats(0.05, 0.6), e=st.floats(-0.3, 0.3), crossed=st.booleans(),
       step=st.floats(0.02, 0.05), down=st.booleans(), data=st.data())
def test_a_slider_crank_with_a_short_coupler_loses_no_value_of_its_narrow_intervals(r2, r3, e, crossed, step, down,
                                                                                    data):
    # two intervals of the crank a turn, each 0.02-0.4 rad wide, swept densely a turn and a
    # half from a start in one of them: the search past each gap tries values up to 0.2 rad
    # apart (36 of 120 such sweeps lost the other interval's values before it looked where
    # the gap dips)
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    assume(len(ranges) == 2)
    start = two_intervals(data.draw, ranges)
    m = slider_crank(r2, r3, offset=e, crossed=crossed, start=start)
    res = m.sweep(start + np.arange(0.0, 3 * np.pi, step) * (-1 if down else 1))
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e, sigma=-1 if crossed else 1)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)


@pytest.mark.parametrize("backwards", [False, True])
def test_a_slider_crank_comes_back_to_the_sketchs_interval_from_its_other_one(backwards):
    # (found by a fuzz campaign) values from the other interval down across the gap into the
    # sketch's own: the search past the gap picked no value of that narrow interval, so it was
    # left NOT_CONVERGED, the sketch's own input among them
    r2, r3, e, start = 4.9470880707511995, 1.0173291197906345, -0.6811898278962669, 3.3444367840460476
    m = slider_crank(r2, r3, offset=e, coupler_point=(2.788314414496618, 0.2567907640082132), start=start)
    U = np.linspace(start - 3, start + 3, 181)
    res = m.sweep(U if backwards else U[::-1])
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)


@pytest.mark.parametrize("backwards", [False, True])
def test_a_narrow_interval_far_past_a_gap_is_found(backwards):
    # (found by a fuzz campaign) a dense sweep up from the sketch's interval: the search past
    # the gap tried the first values and eight spread over the 3 rad to the end, none in the
    # other interval (0.33 rad wide), which was left NOT_ASSEMBLABLE; sweeping down solved it
    r2, r3, e, start = 4.988096272542229, 0.8129413388567117, -1.0566510046610795, -3.0152769234591035
    m = slider_crank(r2, r3, offset=e, start=start)
    U = np.arange(start - 3, start + 3, 0.02)
    res = m.sweep(U[::-1] if backwards else U)
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)


@pytest.mark.parametrize("step", [0.02, -0.02, 0.035, -0.035])
def test_an_interval_narrower_than_the_searchs_spacing_past_a_gap_is_found(step):
    # a short coupler: two intervals of the crank a turn, each 0.062 rad wide; up or down a
    # turn from the sketch's, the search past the gap tried values 0.2 rad apart and went on
    # to the sketch's interval a turn on: the other one's 1-3 values were NOT_ASSEMBLABLE
    r2, r3, e, start = 5.6708230560143775, 0.17493667644335884, 0.07391228681162543, 0.013040361466222998
    m = slider_crank(r2, r3, offset=e, start=start)
    res = m.sweep(start + np.arange(0.0, 2 * np.pi + 0.5, abs(step)) * np.sign(step))
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)
    assert np.sum(in_range(res.inputs[:, 0], ranges[1:], 1e-6)[0]) >= 1  # (the other interval is asked)


def test_an_interval_past_a_gap_where_the_gap_shows_no_minimum_at_the_values_tried_is_found():
    # (found by benchmarks/fuzz_campaign.py, seed 3374 a) past the limit at -0.6392 the range
    # goes on in [-0.9913, -0.9388]; the search tried values 0.2 rad apart, -0.849 and -1.042
    # around it, the gap level at 5e-4 from the limit to -0.849 and rising from -1.042: no
    # minimum at a value tried, and the interval's values were NOT_ASSEMBLABLE (those 181
    # values alone, more sparsely spaced, tried -0.909 next to it and found it)
    m = two_loop_six_bar([6.62686856355119, 2.644548668480121, 2.893991371850322, 3.3509793517260977,
                          12.178490696894237, 1.958182958837209, 12.685355836236571, 2.433291144438236],
                         frame_angle=0.23277891704536602, frame_angle_2=-2.989690550500027, phase=-0.12996694026334898,
                         crossed_2=True, start=-0.5086944179728401)
    U = -0.5086944179728401 - np.linspace(0, 3, 181)
    values = np.unique(np.r_[U, np.arange(U.min(), U.max() + 0.02, 0.02)])
    res = m.sweep(values)
    inside = (values > -0.99133) & (values < -0.93881)
    assert inside.sum() >= 4 and POSED[res.status[inside]].all(), res.status[inside]
    limits = sorted(float(e.input) for e in res.events if e.kind == "limit")
    assert np.allclose(limits, [-0.99133370, -0.93880234, -0.63923071], atol=1e-6), limits
    assert not POSED[res.status[(values < -0.99134) | ((values > -0.93880) & (values < -0.63924))]].any()


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_a_value_just_past_a_limit_where_the_range_starts_again_before_the_limit_is_posed(engine):
    # (found by benchmarks/fuzz_campaign.py, seed 3514 c) a geared five-bar's range folds at
    # 1.83134 and starts again at 1.82971: least squares at 1.85 or 1.9 from the fold's pose (or
    # the sketch's) lands on the fold's side, its gap growing, and only from 1.98 on the stretch
    # beyond. Each value alone within SPREAD steps past the limit read NOT_ASSEMBLABLE, where the
    # sweep with values on past it entered further on and walked back: the values beyond are
    # searched too, and the value walked back to
    def build():
        return geared_five_bar(18.27423312610308, 8.435697237520094, 1.6774066620701853, 14.076378592809519,
                               start=1.7153049042548227)

    dense = build().compile().sweep(np.arange(1.72, 2.1, 0.01), engine=engine)
    assert [(e.kind, round(float(e.input), 5)) for e in dense.events] == [("limit", 1.82971), ("limit", 1.83134)]
    for u in (1.832, 1.85, 1.9):
        alone = build().compile().sweep([u], engine=engine)
        assert alone.status[0] == Status.SOLVED, (u, alone.status)
        assert sorted(round(float(e.input), 5) for e in alone.events) == [1.82971, 1.83134]
        want = build().compile().sweep(np.r_[np.arange(1.72, 2.1, 0.01), u], engine=engine)
        np.testing.assert_allclose(alone.q[0], want.q[-1], atol=1e-9)
    # (a value in a gap past a limit stays NOT_ASSEMBLABLE, its one event the limit)
    rocker = four_bar(4, 3, 3, 2.5).compile().sweep([1.85], engine=engine)
    assert rocker.status[0] == Status.NOT_ASSEMBLABLE and [e.kind for e in rocker.events] == ["limit"]


def test_a_watt_six_bar_comes_back_to_the_sketchs_interval_from_its_other_one():
    m = watt_six_bar(1.6202934626207093, 3.067590914397823, 4.785201881160209, 2.1956945791555653,
                     coupler_point=(-0.5890885839370759, 2.737501047719217),
                     rocker_point=(-2.296254044992292, 2.400721229076879), link_5=3.55380934205724,
                     link_6=1.046282412472003, start=1.4227268321356805)
    U = np.linspace(1.4227268321356805 - 3, 1.4227268321356805 + 3, 181)
    up, down = m.sweep(U), m.sweep(U[::-1])
    assert not np.any(up.status == Status.NOT_CONVERGED)
    assert np.array_equal(up.status, down.status[::-1])
    posed = POSED[up.status]
    assert posed[np.abs(U - 1.5) < 0.2].all() and posed[U < -1.3].all()  # both intervals
    assert np.allclose(up.q[posed], down.q[::-1][posed], atol=1e-9)


def test_a_watt_six_bars_other_interval_is_entered_from_the_poses_solved():
    # (found by a fuzz campaign) the sketch's interval [-1.333, -1.062] and another, [1.075,
    # 1.325], per turn. Up a turn in 0.035 rad steps, the search past the gap at -1.062 found
    # only the other modes of two blocks at 1.16 (least squares and Newton from the pose at the
    # limit and from the sketch), and the tracing round from them had not come back: 1.09-1.30
    # NOT_ASSEMBLABLE. Newton from a pose solved on the sketch's interval lands in its modes
    s = -1.290441837063891
    m = watt_six_bar(2.443382749357639, 3.4405591839016676, 0.5565511506230306, 3.16449800111078,
                     coupler_point=(-1.4547327849893643, -2.553987007193639),
                     rocker_point=(2.6504657750793115, -2.5090581914813743), link_5=2.6238476515696925,
                     link_6=5.23919288269596, crossed=True, start=s)
    U = np.arange(s, s + 2 * np.pi, 0.035)
    res = m.sweep(U)
    V = np.unique(np.r_[U, np.arange(s, s + 2 * np.pi, 0.01)])
    dense = m.sweep(V)
    other = (U > 1.08) & (U < 1.32)
    at = np.searchsorted(V, U[other])
    assert other.sum() == 7 and (res.status[other] == Status.SOLVED).all() and (dense.status[at] == Status.SOLVED).all()
    np.testing.assert_allclose(res.q[other], dense.q[at], rtol=0, atol=1e-9)


def test_a_watt_six_bar_enters_the_range_past_its_gap_where_least_squares_reaches_it_only_next_to_the_fold():
    # (found by a fuzz campaign) a gap (-0.2418, 0.4851) in the crank's range. Past it, least
    # squares from the pose at the limit reached an assembly (in other modes) only within
    # 0.485-0.505; from the values a walk step apart it found minima of 2e-4 and more, and the
    # values past the gap were all NOT_ASSEMBLABLE where values 0.02 apart entered the range
    kw = dict(coupler_point=(2.2273537142005764, 1.6108987882726922),
              rocker_point=(1.8537520802552692, -2.4450023510128407), link_5=6.496768882597824,
              link_6=2.4500015427422626, frame_angle=0.12166101856190314, start=-1.233838229240901)
    m = watt_six_bar(2.390656877217915, 3.799920650921477, 7.697301586116569, 5.916062690994709, **kw)
    U = np.linspace(0.55, 1.45, 10)
    res = m.sweep(U)
    dense = watt_six_bar(2.390656877217915, 3.799920650921477, 7.697301586116569, 5.916062690994709,
                         **kw).sweep(np.r_[np.arange(-1.2, 0.55, 0.02), U])
    assert [e.kind for e in res.events] == ["limit", "limit"]
    assert (res.status == Status.SOLVED).all() and (dense.status[-10:] == Status.SOLVED).all()
    np.testing.assert_allclose(res.q, dense.q[-10:], rtol=0, atol=1e-9)


@pytest.mark.parametrize("spacing", [0.045, 0.07, 0.1])
def test_a_stephenson_six_bar_enters_an_interval_narrower_than_its_values_spacing_inside_a_gap(spacing):
    # (found by a fuzz campaign) the crank's range has a gap (1.1163, 2.5611) with an interval
    # [1.8379, 1.9416] of the branch inside it, on another circuit. Least squares from the limit
    # reaches it only between the values, next to a dip of the gap past its far end: the search
    # there found it past the last value inside it (and walked on into the limit), or not at all
    # (its least gap 1.7e-4 at 1.946), and those values were NOT_ASSEMBLABLE
    kw = dict(coupler_point=(2.8245546285097127, 2.4123119703874774), link_5=9.967642148921762,
              link_6=5.026526879103095, pivot_6=(5.828478578930505, 6.911488258798285),
              frame_angle=2.251305330107381, start=0.6347294124023541)
    r = (3.0545989285969135, 3.8657984915018018, 8.898028677891755, 10.232943273242189)
    U = np.arange(0.6, 3.0, spacing)
    res = stephenson_six_bar(*r, **kw).sweep(U)
    inside = (U > 1.8379) & (U < 1.9416)
    assert inside.any() and (res.status[inside] == Status.SOLVED).all()
    limits = [float(e.input) for e in res.events if e.kind == "limit"]
    assert np.round(limits[:3], 4).tolist() == [1.1163, 1.8379, 1.9416]
    dense = stephenson_six_bar(*r, **kw).sweep(np.r_[np.arange(0.6, 3.0, 0.02), U[inside]])
    assert (dense.status[-inside.sum():] == Status.SOLVED).all()
    np.testing.assert_allclose(res.q[inside], dense.q[-inside.sum():], rtol=0, atol=1e-9)


def test_a_stephenson_six_bar_enters_an_interval_past_a_gap_where_newton_lands_in_other_modes():
    # (found by a fuzz campaign) past the gap above the limit at 1.9152 the crank's range holds an
    # interval [3.3403, 3.3986] in the sketch's modes, on another circuit. Least squares from the
    # limit reaches it, but Newton from there lands in other modes (of four closures there), and
    # the way round through a limit from those does not come back: its values were NOT_ASSEMBLABLE.
    # Newton from that pose with its angles drawn anew lands in ours
    kw = dict(coupler_point=(5.933588960402289, 3.0722284624144147), link_5=11.306866589896003,
              link_6=4.680509817462655, pivot_6=(5.314053815320511, 7.963644758061742),
              frame_angle=2.683524310792004, crossed=False, crossed_2=True)
    r = (9.756321914606612, 4.384579308040071, 1.4319310029500771, 8.262266623155677)
    U = np.arange(1.64, 3.5, 0.02)
    res = stephenson_six_bar(*r, start=1.6497819007361905, **kw).sweep(U)
    inside = (U > 3.3403) & (U < 3.3986)
    assert inside.sum() == 2 and (res.status[inside] == Status.SOLVED).all()
    limits = [float(e.input) for e in res.events if e.kind == "limit"]
    assert np.round(limits, 4).tolist() == [1.9152, 3.3403, 3.3986]
    # the same poses as a sketch drawn inside the interval with the same closures gives
    ref = stephenson_six_bar(*r, start=3.37, **kw).sweep(U[inside])
    np.testing.assert_allclose(res.q[inside], ref.q, rtol=0, atol=1e-9)


def test_the_search_past_a_gap_tries_the_values_before_the_first_that_assembles_in_other_modes():
    # (found by a fuzz campaign, seed 1277 b) past the limit at 1.9534 the crank's range holds an
    # interval [2.6174, 2.7456] in the sketch's modes; of the values past the gap the search tried
    # every fourth or so, the first that assembles (2.8031) only in other modes, and 2.6388,
    # between it and the one tried before, stayed NOT_ASSEMBLABLE
    kw = dict(coupler_point=(4.900347492389165, 3.994331942951912), link_5=10.144619514253412,
              link_6=5.149950944187592, pivot_6=(4.435594657600698, 8.36817924311202), frame_angle=2.2854070388344203,
              crossed=True, crossed_2=False)
    r = (3.844088722956988, 3.5722253875960144, 11.354829691971652, 10.100441012152055)
    U = np.array([2.437174311023695, 2.871477204912551, 2.0953902754187816, 2.266591740120233, 3.0228646933910084,
                  3.5363280184778145, 2.129963102433884, 4.612893032762155, 2.433202349637074, 4.002501523310011,
                  2.638784132461956, 2.365540529260023, 2.5873534158523683, 3.1509648878065932, 2.156381159794084,
                  2.2282794982012786, 2.157532919238603, 2.342330491262896, 2.127980292812501, 2.2016869905483794,
                  -2.9317155596119275, 2.3924426651894977, 3.100883519231196, 4.013994650256485, 2.4876689592921912,
                  1.9675858943247913])
    res = stephenson_six_bar(*r, start=0.8062058935025926, **kw).sweep(U)
    inside = (U > 2.6174) & (U < 2.7456)
    assert inside.sum() == 1 and POSED[res.status[inside]].all(), res.status[inside]
    limits = [float(e.input) for e in res.events if e.kind == "limit"]
    assert np.round(limits, 4).tolist() == [1.9534, 2.6174, 2.7456, 3.014]
    # the pose a sketch drawn inside the interval with the same closures gives (to whole turns)
    ref = stephenson_six_bar(*r, start=2.68, **kw).sweep(U[inside])
    np.testing.assert_allclose(np.angle(np.exp(1j * (res.q[inside] - ref.q))), 0.0, rtol=0, atol=1e-9)


def test_an_input_that_assembles_between_the_searched_values_sends_the_search_to_the_images_a_period_on():
    # (found by a fuzz campaign) a Stephenson six-bar whose crank's range has a gap (-2.3983,
    # -0.7178). Past it, least squares from the limit assembles only at -1.86..-1.89, in other
    # modes, between the values searched: the search read as if nothing there assembled at all,
    # and left out the sweep of the values' images a period on, which enters the range past the
    # gap (values 0.02 apart, one of them in -1.86..-1.89, had it)
    kw = dict(coupler_point=(1.532247435573936, 4.492026060434459), link_5=11.216623194224695,
              link_6=4.500564635513335, pivot_6=(2.440664695924962, 12.043715461032779),
              frame_angle=-1.9503721200850885, start=0.46761932012844554)
    r = (2.146922210982076, 2.6071143222829, 5.40101809669295, 5.876598222667723)
    U = np.linspace(-0.8, -3.5, 40)
    res = stephenson_six_bar(*r, **kw).sweep(U)
    dense = stephenson_six_bar(*r, **kw).sweep(np.r_[np.arange(0.46, -0.8, -0.02), U])
    past = U < -2.3983
    assert [e.kind for e in res.events] == ["limit", "limit"] and past.sum() == 16
    assert (res.status[past] == Status.SOLVED).all() and (dense.status[-40:][past] == Status.SOLVED).all()
    np.testing.assert_allclose(res.q[past], dense.q[-40:][past], rtol=0, atol=1e-9)
    # 0.3 apart, least squares between the values misses -1.86..-1.89 too: the walk's steps out to
    # them find it, which is as good a sign
    V = np.linspace(-0.8, -3.5, 10)
    sparse = stephenson_six_bar(*r, **kw).sweep(V)
    assert (sparse.status[V < -2.3983] == Status.SOLVED).sum() == 4
    np.testing.assert_allclose(sparse.q[V < -2.3983], stephenson_six_bar(*r, **kw).sweep(
        np.r_[np.arange(0.46, -0.8, -0.02), V]).q[-10:][V < -2.3983], rtol=0, atol=1e-9)


def test_values_out_of_reach_one_by_one_cost_what_one_search_does():
    # (found by a fuzz campaign) a Stephenson six-bar sketched 2e-9 from a limit: 166 of 181
    # shuffled values are out of the branch's reach, and the values tried one by one past the
    # gap each walked to the same limit the other way round a period on (28,400 evaluations,
    # 26 s); a walk from a pose that met a limit short of its target now meets it at once
    m = stephenson_six_bar(2.8772837780756246, 2.3865422744999227, 1.1265248967324824, 0.6334291111934824,
                           coupler_point=(-0.2223794637545553, 2.122919119776787),
                           pivot_6=(-0.4427388104452721, -0.7062167892541522), link_5=1.8605345855873636,
                           link_6=2.377963686030224, start=-0.018366276194705815)
    U = np.random.default_rng(19502).permutation(np.linspace(-4.018366276194706, 3.9816337238052943, 181))
    with Evaluations() as count:
        res = m.sweep(U)
    assert count.calls <= 5000, count.calls
    dense = m.sweep(np.sort(U))
    order = np.argsort(U)
    assert np.array_equal(POSED[res.status[order]], POSED[dense.status])  # (a jump is between values asked in turn)
    assert np.allclose(res.q[order][POSED[dense.status]], dense.q[POSED[dense.status]], atol=1e-9)
    assert np.sum(res.status == Status.NOT_ASSEMBLABLE) == 166 and not np.any(res.status == Status.NOT_CONVERGED)


def test_a_gap_searched_from_its_limit_is_not_searched_again_for_the_values_in_it():
    # (found by benchmarks/fuzz_campaign.py) a crank that rocks over [2.0, 4.28], 181 values
    # drawn over +-4 rad: each side of the start is walked from it to its limit, and the gap
    # past each limit is searched once (from the limit's pose and the sketch's, and where the
    # gap dips; the walk steps between two values 0.25 rad apart, more than the search's
    # spacing, too), and once past the first value in it within SPREAD steps of the limit (where
    # the range may start again before the limit), not again for the values in it: 14 searches
    r = (3.6024766824564676, 3.4003318427679505, 1.5451971727659182, 7.436348865464706)
    start = 1.0536061807635093 + 2.6004822959174714 - 2 * np.pi
    m = four_bar(*r, crossed=True, start=start)
    U = start + np.random.default_rng(2).uniform(-4, 4, 181)
    with Evaluations(reentry, "least_squares_gap") as count:
        res = m.sweep(U)
    assert count.calls <= 14, count.calls
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1)
    assert_no_lost_value(res, oracles.four_bar_input_limits(*r), o["th3"])
    assert sorted(e.kind for e in res.events) == ["limit", "limit"]


def test_values_past_a_limit_met_after_far_values_are_entered_past_the_gap():
    # (found by benchmarks/fuzz_campaign.py) a geared five-bar whose crank meets limits at
    # -2.018 and -1.935 (its sketch at -2.245), 20 values within a radian of the sketch then 10
    # far ones: the values above -1.935, left to the walk from the value solved before each, met
    # the limit, and 9 read NOT_ASSEMBLABLE where a sweep of the near values alone poses them;
    # the gap past it is now searched as the main walk searches it
    m = geared_five_bar(ground=7.395831623175523, gear_radius_2=6.275429819503751,
                        gear_radius_4=2.7298681392054993, link_5=10.311398190199988, crossed=True,
                        start=-2.245117402569223)
    near = np.array([-3.0880182962600022, -1.2919221882717649, -1.3268299803574892, -2.8308025210212673,
                     -2.6275269533494416, -3.1549046609779103, -2.7492772341823537, -2.666486291463325,
                     -1.6596132384337667, -2.7590739866137137, -2.444684852857771, -1.9743205352928574,
                     -1.5014249263190877, -1.911111303675771, -1.5522033965583142, -1.5361579153499152,
                     -3.1503927168817034, -1.6804836759397532, -1.3453927683493743, -2.469394905988816])
    far = [10018.402960061527, -32252.163510287308, 191.90656234299277, 725.1911551722717, -150021.7665695149,
           441.0095958736054, -7045.8499164685545, 30839.009586349846, -719.7249114038162, 12601.167163699198]
    res = m.sweep(np.r_[near, far])
    alone = m.compile().sweep(np.sort(near))
    assert POSED[alone.status].all()
    assert POSED[res.status[:20]].all(), [Status(s).name for s in res.status[:20]]
    k = np.searchsorted(np.sort(near), near)
    d = res.q[:20] - alone.q[k]
    d[:, 2::3] = np.angle(np.exp(1j * d[:, 2::3]))  # (angles up to whole turns)
    assert np.abs(d).max() < 1e-9


def test_the_range_past_a_gap_is_entered_between_values_where_the_first_lies_in_the_gap():
    # (found by benchmarks/fuzz_campaign.py) a two-loop six-bar whose crank meets a limit at
    # -2.102 going down and comes back at -3.649: the walk to -2.135, a step on, met the limit,
    # and the search among the values past it (least squares from the limit's pose and the
    # sketch's, 1.7 rad away at -3.83) found no assembly, so -3.83 read NOT_ASSEMBLABLE; the
    # search now tries the walk steps between the values too, as a sweep with values all the
    # way does (it enters at -3.65)
    m = two_loop_six_bar(lengths=(3.590647792847906, 3.5698318415474217, 8.334499515324916, 8.568966352698824,
                                  3.2754272033689373, 3.819896170757685, 8.800969476176805, 6.3651193369680445),
                         frame_angle=2.699796055630693, frame_angle_2=1.1161768033546124, phase=1.8346718839053908,
                         crossed=True, crossed_2=False, start=-1.394735546717167)
    res = m.sweep([-1.94, -2.135, -3.83])
    dense = m.compile().sweep(np.arange(-1.94, -3.84, -0.01))
    assert [Status(s).name for s in res.status] == ["SOLVED", "NOT_ASSEMBLABLE", "SOLVED"]
    assert sorted(round(float(np.ravel(e.input)[0]), 3) for e in res.events) == [-3.649, -2.102]
    assert POSED[dense.status[-1]] and np.allclose(res.q[2], dense.q[-1], atol=1e-9)


def test_a_value_between_a_walk_step_entered_past_a_gap_and_the_next_limit_is_solved():
    # a narrow interval [-0.0078, 0.0286] of the crank holding one value, 0.0098, and a walk
    # step past the gap from 3.113, 0.013: entered there, the walk on to the next anchor met
    # the limit at -0.0078, and the value between (no anchor) was left NOT_ASSEMBLABLE
    r2, r3, e, start = 3.0, 0.0546875, 0.03125, 3.125
    res = slider_crank(r2, r3, offset=e, start=start).sweep(start - np.arange(0.0, 3 * np.pi, 0.021484375))
    ranges = oracles.slider_crank_limits(r2, r3, e, "crank")
    o = oracles.slider_crank(r2, r3, res.inputs[:, 0], offset=e)
    assert_no_lost_value(res, ranges, o["th3"])
    assert_limits_named(res, ranges)


def test_values_a_walk_back_from_past_a_narrow_interval_passes_over_are_solved():
    # past the limit at 4.457 the search entered a narrow interval [5.6071, 5.6904] at 5.63; the
    # walk on from it re-entered past 5.6904 at 5.75, on another stretch of the branch that runs
    # back down to 4.3737. 5.0 and 4.8 lie on it, but the walk back from 5.63 met 5.6071 and the
    # one from 5.75 stopped at 5.67, solved on the narrow interval: both NOT_ASSEMBLABLE
    m = geared_five_bar(ground=17.415047727859392, gear_radius_2=3.721527582006219,
                        gear_radius_4=4.845214131881709, link_5=14.43467129449753, crossed=True,
                        start=-0.18091610142973247)
    res = m.sweep(np.r_[np.arange(-0.18, 4.5, 0.035), 5.63, 5.67, 5.75, 5.0, 4.8])
    assert np.all(POSED[res.status]) and np.all(res.residual <= 1e-12)
    assert {round(float(np.ravel(e.input)[0]), 4) for e in res.events if e.kind == "limit"} >= {4.457, 4.3737}


GEARED_85 = dict(ground=7.395831623175523, gear_radius_2=6.275429819503751, gear_radius_4=2.7298681392054993,
                 link_5=10.311398190199988, crossed=True, start=3.5313154574148524)


def test_values_in_order_from_their_far_end_are_walked_from_the_start_first():
    # (found by benchmarks/fuzz_campaign.py, seed 85) a geared five-bar sketched 3.4e-8 short of
    # the limit of another stretch over the same inputs ([0.7154, 3.5313155]): swept up from 0.5,
    # the walk went down past the sketch's limit at 3.4486 into that stretch and up along it,
    # and gave the sketch's own input that stretch's pose (5.5 off the sketch, NEAR_SINGULAR)
    u0 = GEARED_85["start"]
    u = np.sort(np.r_[np.arange(0.5, 3.7, 0.02), u0])
    up = geared_five_bar(**GEARED_85).sweep(u)
    down = geared_five_bar(**GEARED_85).sweep(u[::-1])
    model = up.model
    i = int(np.flatnonzero(u == u0)[0])
    assert up.status[i] == Status.SOLVED
    np.testing.assert_allclose(up.q[i], model.q0, atol=1e-12)
    # (values in order are solved from the end nearer the start, as values out of order are;
    # the jump over the sketch's limit at 3.4486 is marked on the value asked after it, either way)
    np.testing.assert_array_equal(POSED[up.status], POSED[down.status[::-1]])
    k = int(np.searchsorted(u, 3.4486))
    assert up.status[k] == Status.JUMPED and down.status[::-1][k - 1] == Status.JUMPED
    np.testing.assert_allclose(up.q, down.q[::-1], atol=1e-12)


def test_values_on_both_sides_of_the_start_are_walked_out_from_it():
    # (found by benchmarks/fuzz_campaign.py, seed 409) a geared five-bar swept in order over
    # [u0 - 10, u0 + 10]: the walk to the first value went down past the sketch's limits into
    # another stretch over the same inputs and up along it, and gave the sketch's own input
    # that stretch's pose (13.7 off the sketch, SOLVED). Each side of the start is now walked
    # out from it: the values of the sketch's stretch are its own, as swept on their own
    kw = dict(ground=9.667713243401131, gear_radius_2=8.89785390483146, gear_radius_4=6.2535309350600565,
              link_5=17.318758939469532, crossed=False, start=1.2802508647915838)
    u0 = kw["start"]
    u = np.union1d(np.arange(u0 - 10, u0 + 10, 0.02), [u0])
    res = geared_five_bar(**kw).sweep(u)
    i = int(np.flatnonzero(u == u0)[0])
    assert res.status[i] == Status.SOLVED
    np.testing.assert_allclose(res.q[i], res.model.q0, atol=1e-12)
    near = np.flatnonzero(np.abs(u - u0) <= 0.5)
    alone = geared_five_bar(**kw).sweep(u[near])
    assert np.all(res.status[near] == Status.SOLVED) and np.all(alone.status == Status.SOLVED)
    np.testing.assert_allclose(res.q[near], alone.q, atol=1e-12)


WATT_371 = dict(ground=4.727875498350099, crank=4.0184215095999765, coupler=5.765561894926633,
                rocker=1.9147776511829142, coupler_point=(4.444236383258523, 2.0864317027398513),
                rocker_point=(2.0278698026694135, -4.219427990119475), link_5=1.215396507685505,
                link_6=3.303462249689499, frame_angle=1.27151288059477, crossed=True, crossed_2=True,
                start=-0.37900200297385966)
VALUES_371 = np.array("""-3.3646 -3.3082 -3.2735 -3.1447 -2.8966 -2.8726 -2.8086 -2.7997 -2.7950 -2.7504 -2.6868
    -2.6390 -2.5750 -2.5701 -2.4622 -2.4520 -2.1850 -2.1127 -2.0753 -1.9507 -1.7744 -1.4684 -1.4101 -1.3709 -1.3251
    -1.2891 -1.1625 -1.1538 -1.1104 -0.8710 -0.8069 -0.7135 -0.4503 -0.4053 -0.3858 -0.2864 -0.1690 -0.1449 0.1414
    0.2070 0.3090 0.6250 0.7343 0.7996 0.8333 0.8937 0.9035 0.9376 1.0688 1.1421 1.3698 1.4997 1.6705 1.7288 1.8024
    1.8523 2.0637 2.3856 2.5006 2.5870""".split(), float)


def test_values_asked_again_do_not_crowd_out_the_values_a_search_past_a_gap_tries():
    # (found by benchmarks/fuzz_campaign.py, seed 371) a Watt six-bar whose crank reaches a
    # stretch 0.0116 rad wide ([-2.883, -2.8714]) past its limit at -0.628: asked once each, the
    # search past the gap enters it at -2.8726; asked three times each, the repeats took the
    # places of the values spread over the rest, and -2.8726 came back NOT_ASSEMBLABLE
    once = watt_six_bar(**WATT_371).sweep(VALUES_371)
    values = np.random.default_rng(0).permutation(np.repeat(VALUES_371, 3))
    thrice = watt_six_bar(**WATT_371).sweep(values)
    i = int(np.flatnonzero(VALUES_371 == -2.8726)[0])
    assert once.status[i] == Status.SOLVED
    for k in np.flatnonzero(values == -2.8726):
        assert thrice.status[k] in (Status.SOLVED, Status.JUMPED)
        np.testing.assert_allclose(thrice.q[k], once.q[i], atol=1e-12)
    np.testing.assert_array_equal(POSED[thrice.status], POSED[once.status[np.searchsorted(VALUES_371, values)]])


def test_a_far_value_where_the_search_finds_only_other_modes_is_out_of_reach():
    # the geared five-bar above (no period: its gears' ratio is not rational), a value 1000 rad
    # off: entered directly, where least squares and Newton land only in the other modes and
    # no tracing round comes back to the sketch's, it came back NOT_CONVERGED (gap 3e-11)
    m = geared_five_bar(ground=7.395831623175523, gear_radius_2=6.275429819503751,
                        gear_radius_4=2.7298681392054993, link_5=10.311398190199988, crossed=True,
                        start=-2.245117402569223)
    res = m.sweep([-2.6, -1.6, -1000.0])
    assert [Status(s).name for s in res.status] == ["SOLVED", "NOT_ASSEMBLABLE", "NOT_ASSEMBLABLE"]
    # (it assembles, in modes the branch does not reach: the gap, least squares from the nearest
    # guess 1000 rad off, reads 0 or a local minimum by the rounding of the machine's linear algebra)
    assert np.isfinite(res.gap[2]) and res.nearest_limit[2] == res.nearest_limit[1]


def test_a_linkage_past_a_gap_where_least_squares_finds_other_modes_is_not_traced_round():
    # (found by benchmarks/fuzz_campaign.py) a two-loop six-bar whose crank reaches [0.281,
    # 0.324] and [1.081, 3.198] a turn, 60 values over +-3 rad asked three times each: past the
    # limit at 0.281 least squares finds only other modes, and the tracing round from there
    # (0.4 s) does not come back to the branch's; the sweep of the values' images a period on
    # then traced the same circuit a turn on again (4 tracings, then 2 once a tracing was
    # remembered). Newton from the landing with its angles drawn anew finds every closure
    # there, none in ours: no tracing
    m = two_loop_six_bar((3.7241086415196696, 3.521626096754349, 6.349303661027999, 5.001675931394739,
                          9.622399160856425, 1.2380605853546698, 5.757440868377968, 3.6388399284965374),
                         frame_angle=0.6938550937791534, frame_angle_2=-1.7279331802441251, phase=-2.8438273054641607,
                         start=1.724989098190794)
    rng = np.random.default_rng(0)
    U = rng.permutation(np.repeat(1.724989098190794 + rng.uniform(-3, 3, 60), 3))
    with Evaluations(reentry, "around") as count:
        res = m.sweep(U)
    assert count.calls == 0, count.calls
    dense = m.sweep(np.sort(U))
    order = np.argsort(U)
    assert np.array_equal(POSED[res.status[order]], POSED[dense.status])


def test_a_linkage_landing_in_other_modes_on_both_sides_of_a_circuit_is_not_traced_round():
    # (found by benchmarks/fuzz_campaign.py, seed 787) a Stephenson six-bar whose crank meets a
    # limit at -0.2786 going up: past it least squares lands in other modes, on the two sides of
    # one circuit over [1.1414, 3.4396], and each side was traced round (0.2 s each; then 2
    # tracings, once a tracing that came back in the same modes both ways was remembered for
    # both sides). Newton from a landing with its angles drawn anew finds every closure there
    m = stephenson_six_bar(2.1823783136744317, 2.2597611642248254, 7.396286419699198, 8.652065412395118,
                           coupler_point=(3.885817004830795, 3.3453612719582475), link_5=8.719188193865417,
                           link_6=6.387628948101717, pivot_6=(1.0131519037765613, 14.31175729630554),
                           frame_angle=0.5691483568788915, crossed=True, start=-0.46618861794995015)
    U = np.linspace(-0.2, 3.5, 40)  # (none in the branch's narrow interval [1.1413, 1.1964] past the gap)
    with Evaluations(reentry, "around") as count:
        res = m.sweep(U)
    assert count.calls == 0, count.calls
    assert (res.status == Status.NOT_ASSEMBLABLE).all()
    # (the search past the gap enters the interval between the values, and walks into its limit)
    assert [round(float(e.input), 4) for e in res.events] == [-0.2786, 1.1964]


def test_a_value_in_a_narrow_interval_where_least_squares_lands_in_other_modes_is_solved():
    # the six-bar above: least squares from the limit at -0.2786 reaches 1.1709, in the interval
    # [1.1413, 1.1964], but lands in other modes, on the circuit traced round already, and the
    # value was NOT_ASSEMBLABLE (values 0.01 apart posed it). Newton from there with its
    # angles drawn anew lands in ours
    kw = dict(coupler_point=(3.885817004830795, 3.3453612719582475), link_5=8.719188193865417,
              link_6=6.387628948101717, pivot_6=(1.0131519037765613, 14.31175729630554),
              frame_angle=0.5691483568788915, crossed=True)
    r = (2.1823783136744317, 2.2597611642248254, 7.396286419699198, 8.652065412395118)
    U = np.linspace(-0.28, 3.5, 100)
    res = stephenson_six_bar(*r, start=-0.46618861794995015, **kw).sweep(U)
    inside = (U > 1.1413) & (U < 1.1964)
    assert inside.sum() == 1 and res.status[inside][0] == Status.SOLVED
    assert (res.status[~inside][1:] == Status.NOT_ASSEMBLABLE).all()
    assert [round(float(e.input), 4) for e in res.events] == [-0.2786, 1.1413, 1.1964]
    # the pose a sketch drawn inside the interval with the same closures gives (to whole turns)
    ref = stephenson_six_bar(*r, start=1.17, **kw).sweep(U[inside])
    np.testing.assert_allclose(np.angle(np.exp(1j * (res.q[inside] - ref.q))), 0.0, rtol=0, atol=1e-9)


def test_a_walk_into_a_limit_hands_it_to_the_tracer_without_creeping_up_on_it():
    # a geared five-bar of no period meets a limit pair at 1.42-1.43: the walk's steps that
    # passed at half the size failed again at the full one, a batch and two steps per halving
    # of the distance to the limit, and the period was looked for one candidate at a time
    # (1,066 evaluations for two values; 333 now)
    m = geared_five_bar(9.560566048385189, 6.226203063916225, 1.0506911088020563, 10.865965728760559, crossed=True,
                        start=0.8106588260535199)
    with Evaluations() as count:
        res = m.sweep([0.81, 1.8])
    assert count.calls <= 500, count.calls
    assert res.status.tolist() == [Status.SOLVED, Status.JUMPED]
    assert sorted(round(float(e.input), 4) for e in res.events if e.kind == "limit") == [1.4209, 1.432]
    # the first value asked, past the pair: its far limit located walking back towards the start
    res = geared_five_bar(9.560566048385189, 6.226203063916225, 1.0506911088020563, 10.865965728760559,
                          crossed=True, start=0.8106588260535199).sweep([1.8])
    assert sorted(round(float(e.input), 4) for e in res.events if e.kind == "limit") == [1.4209, 1.432]


def test_sparse_values_are_reached_through_stations_solved_many_gaps_a_batch():
    # 30 values over a turn lie 0.21 rad apart, beyond a wave's reach: each was walked to, a
    # batch or two of Newton a gap (160 evaluations, where 100 values over the turn take 34);
    # the stations between them are now solved in waves, many gaps a batch (43), each still
    # checked as one step from the one before, so the poses are the dense sweep's
    m = four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8))
    U = np.linspace(0.0, 2 * np.pi, 30, endpoint=False)
    with Evaluations() as count:
        res = m.sweep(U)
    assert count.calls <= 60, count.calls
    assert (res.status == Status.SOLVED).all()
    dense = m.sweep(np.linspace(0.0, 2 * np.pi, 300, endpoint=False))
    np.testing.assert_allclose(res.q, dense.q[::10], rtol=0, atol=1e-12)
    o = oracles.four_bar(4, 2, 3.5, 3, U)
    np.testing.assert_allclose(np.angle(np.exp(1j * (res.angle("rocker") - o["th4"]))), 0.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("backwards", [False, True])
def test_values_past_a_limit_at_the_sketch_whose_images_a_period_back_the_branch_reaches_are_solved(backwards):
    # (found by a fuzz campaign) a Stephenson six-bar whose crank rocks over [-1.8662, 1.8662],
    # sketched at its upper end and swept over [-1.134, 4.866] downwards: the values from
    # 4.417 on (the range a turn on) came back NOT_ASSEMBLABLE, as the search past the gap found
    # only other modes there and the sketch's own stretch further on was entered first; upwards
    # they were solved. Both ways now give the range a turn on, each pose the pose a turn back
    m = stephenson_six_bar(ground=4.880129187450895, crank=0.8724383512345397, coupler=3.2208235564912115,
                           rocker=1.980695432915346, coupler_point=(-1.2669528654086244, -1.9475098391811978),
                           pivot_6=(-2.4609938618607736, -2.143272440409377), link_5=3.274075215439777,
                           link_6=3.160135326460027, crossed=True, crossed_2=True, start=1.8661982797645835)
    U = np.linspace(-1.1338017202354165, 4.866198279764584, 181)
    res = m.sweep(U[::-1] if backwards else U)
    status = res.status[::-1] if backwards else res.status
    assert not np.any(status == Status.NOT_CONVERGED)
    posed = POSED[status]
    np.testing.assert_array_equal(posed, (U <= 1.8662) | (U >= 4.4170))
    image = m.sweep(U[U >= 4.4170] - 2 * np.pi)
    D = res.position("D")[::-1] if backwards else res.position("D")
    np.testing.assert_allclose(D[U >= 4.4170], image.position("D"), atol=1e-9)


def test_a_walk_from_next_to_a_limit_takes_its_own_steps_again_past_it():
    # (found by a fuzz campaign) a slider-crank sketched 7.7e-9 inside a limit of its crank's
    # range [0.1832, 2.9584]: the walk's steps fail there and the arclength tracer took over
    # for the whole way (a turn of the crank on, the walk over a period: 159 tracer steps);
    # past the singular stretch it now gives the walk back
    u0 = 0.18317895394778927
    m = slider_crank(crank=4.67137729979805, coupler=1.9403108163859453, offset=2.791231386324089,
                     coupler_point=(-0.7417895781775796, -1.8525216108965168), start=u0)
    with Evaluations(Tracer, "step") as steps:
        res = m.sweep([u0 + 2 * np.pi])
    assert steps.calls <= 40, steps.calls
    np.testing.assert_allclose(res.position("C"), m.sweep([u0]).position("C"), atol=1e-9)
    U = np.random.default_rng(42702).permutation(np.linspace(u0 - 4, u0 + 4, 181))
    res = m.sweep(U)
    (lo, hi), = oracles.slider_crank_limits(4.67137729979805, 1.9403108163859453, 2.791231386324089, "crank", 0.0)
    off = np.abs(np.angle(np.exp(1j * (U - 0.5 * (lo + hi))))) - 0.5 * (hi - lo)  # (from the range, a turn round)
    inside = off < -1e-6
    assert POSED[res.status[inside]].all() and not POSED[res.status[off > 1e-6]].any()
    o = oracles.slider_crank(4.67137729979805, 1.9403108163859453, U[inside], offset=2.791231386324089)
    np.testing.assert_allclose(res.position("B")[inside], o["B"], atol=1e-9)


def test_a_point_at_rest_gives_the_input_no_period():
    # (found by a fuzz campaign) a geared five-bar whose gears' ratio has no period within
    # twelve turns: a gear's centre, at rest, moves by rounding, and its speed over its
    # acceleration (2e-15 rad) was taken for a period of the input, so the values past the
    # limit at -2.2141 came back NOT_CONVERGED, 26 of 41
    m = geared_five_bar(ground=6.072652857824006, gear_radius_2=1.9323918248113148,
                        gear_radius_4=3.0935376218248507, link_5=11.831524553751766)
    U = np.linspace(-4.0, 4.0, 181)
    res = m.sweep(U)
    np.testing.assert_array_equal(POSED[res.status], U > -2.2141392)
    assert np.all(res.status[U < -2.2141392] == Status.NOT_ASSEMBLABLE)
    np.testing.assert_allclose(res.nearest_limit[U < -2.2141392], -2.2141392, atol=1e-6)


def test_far_values_out_of_a_rocking_range_are_out_of_reach_both_ways_round():
    # (found by a fuzz campaign) a Stephenson six-bar whose crank rocks over [-0.840, 1.353]
    # (the dyad C-D-O6 folds at both ends): far values outside that range a whole number of
    # turns on were NOT_CONVERGED (other modes assemble there) where the walk had met a limit
    # both ways round; the limit the other way round was dropped, so neither bounded the value
    m = stephenson_six_bar(2.8877078897674915, 1.9842262046234023, 3.60106001136451, 4.144924322506714,
                           coupler_point=(-2.3472251480830706, 1.032386230002066),
                           pivot_6=(6.741993849876746, 4.060706571707723), link_5=5.597441136024417,
                           link_6=3.6200181986201714, start=-0.1778297293504698)
    far = np.array([128.568388, -1543.9995, -248.69148, -395429.793])  # 2.90, 1.66, 2.64, 2.47 + whole turns
    near = np.array([-0.5, 0.0, 1.0])
    res = m.sweep(np.r_[near, far])
    assert POSED[res.status[:3]].all()
    assert np.all(res.status[3:] == Status.NOT_ASSEMBLABLE), res.status
    ends = np.array([-0.8401, 1.3526])
    off = np.abs(np.angle(np.exp(1j * (res.nearest_limit[3:, None] - ends[None, :])))).min(axis=1)
    assert off.max() < 1e-4


def test_a_value_a_period_round_is_tried_though_a_nearer_one_failed_the_direct_way():
    # (found by a fuzz campaign) a Watt six-bar over a turn, then 30 values jumping over +-20 rad:
    # 13.987 (its range [6.416, 7.830] a turn on) was not tried from 7.767 because 9.360 had
    # failed from there; the walk goes the other way round a period on, where 13.987 is near
    m = watt_six_bar(3.6182642633974726, 3.7294370195860065, 3.7378675208787753, 3.4823231274091184,
                     coupler_point=(0.9876207684286848, -1.9458399328867182),
                     rocker_point=(-1.774756350067655, 0.03170470319413621), link_5=5.662619764471767,
                     link_6=2.076777296991942, crossed=True, crossed_2=True, start=1.5017117722622761)
    u0 = 1.5017117722622761
    U = np.r_[np.arange(u0, u0 + 2 * np.pi, 0.035), u0 + np.random.default_rng(10405).uniform(-20, 20, 30)]
    res = m.sweep(U)
    assert not np.any(res.status == Status.NOT_CONVERGED)
    i = int(np.argmin(np.abs(U - 13.98687699)))
    dense = m.sweep(np.r_[np.arange(u0, 14.0, 0.02), U[i]])
    assert POSED[res.status[i]] and POSED[dense.status[-1]]
    assert np.allclose(res.position("E")[i], dense.position("E")[-1], atol=1e-9)


@st.composite
def rocking_four_bars(draw):
    """A crank-driven four-bar whose crank rocks (its range over a turn one or two intervals,
    each wider than 0.1), and a start inside a range."""
    r = draw(st.tuples(length, length, length, length))
    ranges = oracles.four_bar_input_limits(*r)
    assume(ranges and ranges != [(-np.pi, np.pi)] and min(b - a for a, b in ranges) > 0.1)
    a, b = ranges[draw(st.integers(0, len(ranges) - 1))]
    return r, draw(st.floats(a + 0.01, b - 0.01)), ranges


# a fuzz campaign's crank (its range over a turn two intervals, 0.87..2.00 rad and its mirror):
# before far values were solved whole periods back into one period, the first of these was
# NOT_CONVERGED
FUZZED = ((3.1591713721477857, 2.269132721550857, 1.078610675691412, 3.5081261684943073), 1.1565173518878389)
FUZZED_FAR = [311219.09168472205, 478688.59497750655, 900613.7256889333, 936614.0334233554, 217299.80573303346,
              861484.0610726231, 639821.5898704965, 327373.4686957388, 104623.5540350201, 426865.7579991881,
              323881.0445057351, 834375.6860181676, 19020.35664780518, 214185.412229394, 466656.8668332406,
              753871.3495419491, 481315.6655571167, 294966.28269556735, 691496.8297569149, 802035.9756568879]


@PROPS
@given(case=rocking_four_bars(), crossed=st.booleans(),
       far=st.lists(st.floats(1e2, 1e6) | st.floats(-1e6, -1e2), min_size=1, max_size=12), near=st.integers(0, 3),
       repeat=st.integers(0, 2), backwards=st.booleans())
@example(case=(*FUZZED, oracles.four_bar_input_limits(*FUZZED[0])), crossed=False, far=FUZZED_FAR, near=0, repeat=0,
         backwards=False)
def test_far_values_of_a_rocking_four_bar_lose_no_value(case, crossed, far, near, repeat, backwards):
    """Far values of a crank that rocks, some next to each other and some repeated, forwards
    or backwards: every one in range posed on the closed form, the others NOT_ASSEMBLABLE,
    none NOT_CONVERGED."""
    r, start, ranges = case
    m = four_bar(*r, crossed=crossed, start=start)
    values = np.array(far + [x + 0.01 for x in far[:near]] + far[:repeat])
    res = m.sweep(start + (values[::-1] if backwards else values))
    o = oracles.four_bar(*r, res.inputs[:, 0], sigma=-1 if crossed else 1)
    assert_no_lost_value(res, ranges, o["th3"])


def test_a_watt_six_bar_on_a_parallelogram_keeps_its_branch_past_its_change_points():
    m = watt_six_bar(4, 1, 4, 1, start=0.3)
    res = m.sweep(np.arange(0.3, 0.3 + 4 * np.pi, 0.023))  # two turns, four change points
    assert res.ok.all(), res
    assert [e.kind for e in res.events if e.kind != "near_singular"] == ["bifurcation"] * 4
    # the first loop stays a parallelogram: its rocker turns with the crank
    np.testing.assert_allclose(np.sin(res.angle("rocker") - res.angle("crank")), 0, atol=1e-10)


def jumps(res, points, factor=20.0):
    """(value, point, move, predicted) where a point moves between two valid values far more
    than its speed there predicts (a jump between circuits not reported JUMPED)."""
    u, ok = res.inputs[:, 0], VALID[res.status]
    both = np.flatnonzero(ok[:-1] & ok[1:] & (res.status[1:] != Status.JUMPED))
    found = []
    for P in points:
        x, v = res.position(P), np.linalg.norm(res.velocity(P), axis=1)
        move = np.linalg.norm(x[both + 1] - x[both], axis=1)
        pred = 0.5 * (v[both] + v[both + 1]) * np.abs(u[both + 1] - u[both])
        bad = move > factor * pred + 1e-6 * res.model.L
        found += [(int(i), P, float(d), float(e)) for i, d, e in zip(both[bad], move[bad], pred[bad])]
    return found


@st.composite
def grashof_boundary_watt_six_bars(draw):
    """The arguments of a Watt six-bar whose first loop is on the Grashof boundary (s + l = p + q:
    change points), with random points, second dyad, assembly modes and start."""
    s, p, q = sorted(draw(st.tuples(st.floats(0.5, 4), st.floats(0.5, 4), st.floats(0.5, 4))))
    point = st.tuples(st.floats(-3, 3), st.floats(-3, 3))
    return dict(zip(("ground", "crank", "coupler", "rocker"), draw(st.permutations([s, p, q, p + q - s]))),
                coupler_point=draw(point), rocker_point=draw(point), link_5=draw(st.floats(1, 6)),
                link_6=draw(st.floats(1, 6)), crossed=draw(st.booleans()), crossed_2=draw(st.booleans()),
                start=draw(st.floats(-np.pi, np.pi)))


@settings(max_examples=settings.default.max_examples if LONG else 10, deadline=None)
@given(args=grashof_boundary_watt_six_bars())
# past a gap, the walk the other way round a period came back through a change point in the
# other mode of the first loop, next to values re-entered in the sketch's: B moved 2.05 where
# its speed predicts 0.024, both values SOLVED
@example(args=dict(ground=2.3596475420856833, crank=1.7194630113541287, coupler=2.45422202326443,
                   rocker=1.6248885301753824, coupler_point=(0.25, 1.0406557143548225), rocker_point=(0.25, 0.0),
                   link_5=3.3567032173558995, link_6=5.999186132581008, crossed=True, crossed_2=False, start=-3.0))
def test_a_watt_six_bar_on_the_grashof_boundary_does_not_jump_between_valid_values(args):
    # a sketch within ~1e-8 of the change point (crank along the ground) is an ambiguous start
    # that the walk may not leave (hardening.md): not drawn here
    assume(abs(np.sin(args["start"])) > 1e-6)
    try:
        m = watt_six_bar(**args).compile()
        res = m.sweep(np.arange(args["start"], args["start"] + 2 * np.pi, 0.023))
    except PlanarError:  # a sketch that does not assemble, or drawn on a singular position
        assume(False)
    assert not jumps(res, ["B", "C", "D", "E"])
    assert not np.any(res.status == Status.NOT_CONVERGED)


def test_a_watt_six_bar_reaches_its_second_interval_a_turn_on_from_where_it_enters_it_the_other_way():
    # the crank reaches two intervals over a turn, the sketch 1.2e-3 from the first's lower end;
    # past the first's upper end the search finds only another circuit at the second's values
    # (they came back NOT_CONVERGED): the sweep downwards enters the second's image a turn back
    s0 = -2.08984375
    m = watt_six_bar(ground=0.56640625, crank=1.40234375, coupler=1.46875, rocker=0.5,
                     coupler_point=(-2.08984375, 2.1875), rocker_point=(-2.09375, 2.25), link_5=1.58984375,
                     link_6=4.57421875, start=s0).compile()
    u = np.arange(s0, s0 + 2 * np.pi, 0.023)
    res = m.sweep(u)
    second = (u > 1.0871) & (u < 2.0911)
    assert res.ok[second].all() and not res.ok[(u > -1.0871) & ~second].any()
    assert not np.any(res.status == Status.NOT_CONVERGED)
    limits = [e.input for e in res.events if e.kind == "limit"]
    np.testing.assert_allclose(limits, [-1.0871, 1.0871, 2.0911], atol=1e-4)
    # the same poses as a sweep that walks down through the interval's image first
    wide = m.sweep(np.r_[np.arange(s0 - 2 * np.pi, s0, 0.005), u])
    d = res.position("E")[second] - wide.position("E")[-u.size :][second]
    np.testing.assert_allclose(d, 0, atol=1e-12)
    # a million radians on, the same (solved whole periods back: the images of the second
    # interval's values just past the sketch, not 1e6 rad from it)
    with Evaluations() as ev:
        far = m.sweep(u + 2 * np.pi * 159155)
    assert ev.calls <= WORK_TWO_INTERVALS, ev.calls
    np.testing.assert_array_equal(far.status, res.status)
    # (u + 1e6 carries 1e-10 of rounding, which the values next to the limits, their points
    # moving 10-20x the crank there, pass on)
    np.testing.assert_allclose(far.position("E")[res.ok] - res.position("E")[res.ok], 0, atol=1e-8)


def test_a_far_input_of_a_six_bar_whose_smooth_branch_changes_modes_every_turn_costs_what_a_near_one_does():
    # the first loop on the Grashof boundary: its crank passes a change point every turn, and the
    # smooth branch comes out in the other modes of that loop, back in the sketch's after two
    # turns. A million radians on, the values were NOT_CONVERGED (no period of one turn: the
    # walk there is over any bound)
    args = dict(ground=1.498206210302061, crank=1.2983701472653801, coupler=3.2007591141589344,
                rocker=3.400595177195615, coupler_point=(2.1816104775288014, -2.121830334246634),
                rocker_point=(2.17007541691748, -0.4042472840475053), link_5=2.3667273919627716,
                link_6=2.7162233124631436, crossed=False, crossed_2=True, start=2.865334347525425)
    a = args["start"] + np.arange(0, 2 * np.pi, 0.035)
    near = {t: watt_six_bar(**args).compile().sweep(a + 2 * np.pi * t) for t in (1, 2)}
    for turns in (159155, 159156):  # odd, even
        with Evaluations() as ev:
            far = watt_six_bar(**args).compile().sweep(a + 2 * np.pi * turns)
        assert ev.calls <= 2000, ev.calls
        assert far.ok.all()
        # (the inputs' rounding at 1e6, 1e-10, moves the points ~1e-8 next to the change points)
        np.testing.assert_allclose(far.position("E"), near[2 - turns % 2].position("E"), atol=1e-7)


# a Watt six-bar on the Grashof boundary whose smooth branch passes its first loop's change point
# every turn, into modes where its second loop meets a limit pair: back in the sketch's after two
LIMITS_EVERY_OTHER_TURN = dict(ground=2.262237374804487, crank=1.2649326418576359, coupler=1.6325053564764112,
                               rocker=2.629810089423262, coupler_point=(-2.7075533425727167, -2.5665641329489106),
                               rocker_point=(2.0088656738883204, 2.940484434441621), link_5=5.716326024466156,
                               link_6=3.5938018593740626, start=-0.2765457554083546)


def test_a_far_input_of_a_six_bar_that_meets_limits_every_other_turn_is_the_sweep_a_turn_on():
    # as above, but in the first loop's other modes the second loop meets a limit pair: the
    # walk over a turn from the sketch comes back in other modes, and over the next meets a
    # limit. The period (two turns) is then found by a sweep from the sketch over four, and
    # the far values are those an odd number of periods back: a turn on
    values = watt_six_bar(**LIMITS_EVERY_OTHER_TURN)
    a = LIMITS_EVERY_OTHER_TURN["start"] + np.arange(0, 2 * np.pi, 0.035)
    near = values.compile().sweep(a + 2 * np.pi)
    far = values.compile().sweep(a + 2 * np.pi * 159155)
    assert not np.any(far.status == Status.NOT_CONVERGED)
    assert (near.status == Status.NOT_ASSEMBLABLE).sum() == 40
    np.testing.assert_array_equal(far.status, near.status)
    np.testing.assert_allclose(far.position("E")[near.ok], near.position("E")[near.ok], atol=1e-7)


def test_a_turn_of_a_six_bar_that_meets_limits_every_other_turn_swept_alone_is_the_dense_sweeps():
    # the walk from the sketch to the fourth turn meets the second's limit: the search past it
    # among the fourth turn's values entered the circuit nearest them (every value SOLVED, E
    # 6.9 from the dense sweep's), where the sweep through every turn enters the range right
    # past the gap and meets the limits again two turns on. The values' images a period back
    # are entered instead
    values = watt_six_bar(**LIMITS_EVERY_OTHER_TURN)
    a = LIMITS_EVERY_OTHER_TURN["start"] + np.arange(0, 2 * np.pi, 0.035)
    dense = values.compile().sweep(np.concatenate([a + 2 * np.pi * t for t in range(4)]))
    n = a.size
    assert [(dense.status[t * n : (t + 1) * n] == Status.NOT_ASSEMBLABLE).sum() for t in range(4)] == [0, 40, 0, 40]
    for t in (2, 3):
        alone = values.compile().sweep(a + 2 * np.pi * t)
        np.testing.assert_array_equal(alone.status, dense.status[t * n : (t + 1) * n])
        ok = alone.ok
        np.testing.assert_allclose(alone.position("E")[ok], dense.position("E")[t * n : (t + 1) * n][ok], atol=1e-9)


def test_a_watt_six_bar_crossing_its_change_point_at_a_shallow_angle_keeps_the_smooth_branch():
    # the two branches through the first loop's change point at 0 run within 1e-5..1e-4 of each
    # other (scaled) over ~0.06 of arclength: steps held to half that gap took ~10,000
    # evaluations, and the tracing gave up, leaving the value after it on the other branch
    s0 = -0.43190059575350315
    m = watt_six_bar(0.8, 3.8332059824945017, 1.7375209316550309, 4.770726914149533, coupler_point=(0, 3),
                     rocker_point=(0, 3), link_5=1.0, link_6=3.9658570442229797, start=s0)
    u = np.linspace(s0, s0 + 2 * np.pi, 178)
    with Evaluations() as ev:
        res = m.sweep(u)
    assert ev.calls <= 3000, ev.calls
    limits = sorted(e.input for e in res.events if e.kind == "limit")
    # the smooth branch turns back 0.0373 past the change point, and meets it again at -0.0373
    np.testing.assert_allclose(limits[:2], [-0.037308708833, 0.037308708833], atol=1e-9)
    assert [e.kind for e in res.events].count("bifurcation") >= 1
    # the value between the change point and that limit is on the smooth branch: a fine sweep
    # to it agrees; the value past the limit, on the other branch, is JUMPED
    fine = m.sweep(np.linspace(s0, u[13], 400))
    assert res.status[13] == Status.SOLVED and fine.status[-1] == Status.SOLVED
    np.testing.assert_allclose(res.q[13], fine.q[-1], atol=1e-9)
    assert res.status[14] == Status.JUMPED
    assert not jumps(res, ["B", "C", "D", "E"])
    assert not np.any(res.status == Status.NOT_CONVERGED)


def test_a_rocking_six_bar_over_several_periods_costs_one_period():
    # (found by a fuzz campaign) a turn and 30 jumps over +-20 rad of a Stephenson six-bar whose
    # crank rocks (two limit pairs a turn): the walk met the limits of each period and searched
    # past each gap again (6,200 evaluations, 3-4 s), and the sketch's own value came back three
    # turns of every body on; its values are now solved in one period (1,300 evaluations)
    m = stephenson_six_bar(1.0706470371661212, 1.8276881570318233, 2.911790209889607, 2.8554262882616586,
                           coupler_point=(-1.6708518597383861, -1.3900550776271732),
                           pivot_6=(-2.612741013749879, 1.3571472917248126), link_5=3.713325616698212,
                           link_6=2.6300548941211455, crossed=True, crossed_2=False, start=-0.3469061313233843)
    u0 = -0.3469061313233843
    U = np.r_[np.arange(u0, u0 + 2 * np.pi, 0.035), u0 + np.random.default_rng(9305).uniform(-20, 20, 30)]
    with Evaluations() as count:
        res = m.sweep(U)
    assert count.calls <= 3000, count.calls
    assert not np.any(res.status == Status.NOT_CONVERGED)
    assert np.allclose(res.q[0], m.compile().q0, atol=1e-9)  # the sketch, not some turns on
    # the far values are posed where their images in the sketch's turn are, at the same positions
    far = np.arange(U.size) >= 180
    images = u0 + np.mod(U[far] - u0, 2 * np.pi)
    ref = m.sweep(images)
    assert np.array_equal(POSED[res.status[far]], POSED[ref.status])
    both = POSED[ref.status]
    assert both.sum() >= 10
    assert np.allclose(res.position("D")[far][both], ref.position("D")[both], atol=1e-9)


def test_the_searches_past_gaps_sweep_the_images_once():
    # (found by a fuzz campaign) a Watt six-bar with 117 of 181 values out of reach: each of
    # three searches past a gap swept the images a period back of the values left, each a
    # subset of the first's (5,000 evaluations); they are now read from the first sweep (2,900)
    m = watt_six_bar(2.340830168957152, 0.6338739205904216, 2.1676098480453465, 3.9122378382489895,
                     coupler_point=(-1.602047746951434, 0.32636519278880627),
                     rocker_point=(-0.6630373700577037, 2.4014068198318235), link_5=3.95034571997458,
                     link_6=5.975560547440098, crossed=False, crossed_2=True, start=3.8647853931518235)
    U = np.linspace(3.8647853931518235 - 3, 3.8647853931518235 + 3, 181)
    with Evaluations() as count:
        res = m.sweep(U)
    assert count.calls <= 4000, count.calls
    assert np.sum(res.status == Status.SOLVED) == 64 and np.sum(res.status == Status.NOT_ASSEMBLABLE) == 117
    assert [round(float(e.input), 4) for e in res.events if e.kind == "limit"] == [
        2.1082, 4.175, 5.9518, 5.9861, 6.5803, 6.6146]


def _apex_rocker(ground, crank, k, U):
    """The rocker's angle of a four-bar whose coupler and rocker are both k long: B on the
    bisector of A and O4, k from both, on the side the catalogue draws it (no large squares cancel)."""
    O4 = np.array([ground, 0.0])
    A = crank * np.c_[np.cos(U), np.sin(U)]
    d = O4 - A
    half = np.hypot(*d.T) / 2
    h = np.sqrt((k - half) * (k + half))
    B = (A + O4) / 2 + np.c_[-d[:, 1], d[:, 0]] / (2 * half)[:, None] * h[:, None]
    return np.arctan2(B[:, 1], B[:, 0] - ground)


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
@pytest.mark.parametrize("k", [1e5, 1e6])
def test_two_long_links_over_a_short_base_are_walked_near_singular_all_along(k, engine):
    # a coupler and a rocker of k over a base of 3, crank 1: the singularity measure is about
    # 1 / k at every pose, the walk's steps (certified to 0.1 of it) shrank past their last
    # halving and gave the sweep to the tracer, which stalled: every value past the first
    # step was NOT_ASSEMBLABLE (1e6), where every crank angle assembles, or each traced
    # stretch an event of its own (1e5)
    U = np.linspace(0.0, 1.0, 11)
    res = four_bar(3.0, 1.0, k, k).compile().sweep(U, engine=engine)
    assert np.all(res.status == Status.NEAR_SINGULAR)
    assert [(e.kind, e.index) for e in res.events] == [("near_singular", 0)]
    # the pose holds to the rounding of coordinates of k over a transmission angle of 3 / k
    assert np.abs(res.angle("rocker") - _apex_rocker(3.0, 1.0, k, U)).max() <= 4 * np.finfo(float).eps * k


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_two_links_of_1e7_over_a_short_base_are_traced_on_their_closed_form(engine):
    # at 1e7 the rounding of the walk's corrections is above its certificate: each stretch is
    # traced (a near_singular event each), the tracer's steps predicted with the curve's
    # curvature; they stalled with the tangent's alone (the last value NOT_CONVERGED, the rest
    # entered by search, JUMPED)
    k, U = 1e7, np.linspace(0.0, 1.0, 11)
    res = four_bar(3.0, 1.0, k, k).compile().sweep(U, engine=engine)
    assert np.all(res.status == Status.NEAR_SINGULAR), res
    assert {e.kind for e in res.events} == {"near_singular"}
    assert np.abs(res.angle("rocker") - _apex_rocker(3.0, 1.0, k, U)).max() <= 4 * np.finfo(float).eps * k


@settings(max_examples=settings.default.max_examples if LONG else 8, deadline=None)
@given(ground=st.floats(2.0, 4.0), crank=st.floats(0.2, 1.5), k=st.floats(3.0, 5.0).map(lambda e: 10.0**e),
       span=st.floats(0.5, 7.0))
@example(ground=2.0, crank=1.0, k=1e5, span=1.0)  # (values past the first step were NOT_ASSEMBLABLE)
def test_a_crank_under_two_long_links_turns_on_its_closed_form_whatever_their_length(ground, crank, k, span):
    # (k up to 1e5 times the base: further, at angles of a turn, the rounding of the Newton
    # corrections nears the walk's certificate, and the walk leaves the stretch to the tracer)
    U = np.linspace(0.0, span, 13)
    res = four_bar(ground, crank, k, k).compile().sweep(U)
    assert np.all((res.status == Status.SOLVED) | (res.status == Status.NEAR_SINGULAR)), res
    err = np.abs(np.angle(np.exp(1j * (res.angle("rocker") - _apex_rocker(ground, crank, k, U)))))
    assert err.max() <= 16 * np.finfo(float).eps * k


def test_a_value_that_assembles_is_not_reported_out_of_range_where_least_squares_stalls():
    # two links of 1e7 over a base of 3: past the walk's reach (its corrections' rounding above
    # its certificate) the last value was NOT_ASSEMBLABLE at a gap of 2e-8, where least squares
    # stalled in the ill-conditioned valley; every crank angle assembles
    res = four_bar(3.0, 1.0, 1e7, 1e7).compile().sweep(np.linspace(0.0, 1.0, 11))
    assert not np.any(res.status == Status.NOT_ASSEMBLABLE), res
    assert np.all(np.isnan(res.gap) | (res.gap <= 1e-12))


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_an_interval_past_a_gap_that_the_search_misses_is_posed_from_its_image_a_turn_back(engine):
    # (found by a fuzz campaign) past the limit at 6.3362 the crank's range holds [6.6658,
    # 6.6879], no anchor inside it. Least squares from the limit stops in another valley (its gap
    # rising to 0.015), so the search past the gap found nothing and 6.68 was NOT_ASSEMBLABLE. The
    # interval a turn back, [0.3826, 0.4047], is entered from the other side of the start
    kw = dict(frame_angle=0.8296850447425062, frame_angle_2=1.265679468035648, phase=-0.07327897854953314,
              crossed=True, crossed_2=False, start=2.992811428728971)
    r = (3.7036892862606177, 3.6273127009190063, 10.731987426190987, 9.184264610372368, 7.51415853722821,
         3.960932393755239, 12.804072692913797, 8.488747118229444)
    m = two_loop_six_bar(r, **kw).compile()
    U = np.arange(-1.0, 7.0, 0.02)
    res = m.sweep(U, engine=engine)
    limits = np.round([float(e.input) for e in res.events if e.kind == "limit"], 4)
    assert {0.3826, 0.4047, 6.3362, 6.6658, 6.6879} <= set(limits.tolist())
    inside = (U > 6.6658) & (U < 6.6879)
    assert inside.sum() == 1 and res.status[inside][0] == Status.SOLVED
    # the pose a turn back, up to whole turns of its angles
    back = m.sweep(U[inside] - 2 * np.pi, engine=engine)
    assert back.status[0] in POSED
    d = res.q[inside][0] - back.q[0]
    d[2::3] = (d[2::3] + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(d)) < 1e-9


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_an_interval_entered_by_period_from_a_pose_next_to_its_limit_is_walked_into(engine):
    # (found by a fuzz campaign of random linkages) a crank with three slider dyads whose range
    # is five narrow intervals a turn; [3.5976, 3.8208] past the limit at 0.0037 is the image of
    # [-2.6856, -2.4624], where the walk down had solved two values next to the lower limit. The
    # search past the gap found nothing there in the sketch's modes; the entry by period tried
    # only values within a walk step of those poses' images (3.589, whose walk met the limit at
    # 3.5976), and the interval's values were NOT_ASSEMBLABLE
    data = json.loads((Path(__file__).parent / "data" / "random_linkage_narrow_intervals.json").read_text())
    m = build(data["desc"])[0].compile()
    U = np.array(data["values_rad"])
    res = m.sweep(U, engine=engine)
    limits = sorted(np.round([float(e.input) for e in res.events if e.kind == "limit"], 4).tolist())
    assert limits == [-2.6856, -2.4624, -1.1645, -0.7661, -0.4951, -0.0907, -0.0082, 0.0037, 3.5976, 3.8208]
    inside = (U > 3.5976) & (U < 3.8208)
    assert inside.sum() == 4 and (res.status[inside] == Status.SOLVED).all()
    # the poses a turn back (swept with the others: alone, the search does not find that
    # interval either), up to whole turns of their angles
    back = m.sweep(np.r_[U, U[inside] - 2 * np.pi], engine=engine)
    assert POSED[back.status[-4:]].all()
    d = res.q[inside] - back.q[-4:]
    d[:, 2::3] = (d[:, 2::3] + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(d)) < 1e-9


def test_the_entry_by_period_does_not_spend_its_tries_on_values_past_a_limit_it_met():
    # (found by benchmarks/fuzz_campaign.py, seed 2397) a Stephenson six-bar whose crank rocks
    # over [-0.3557, 4.8098]: past the limit at 4.8098 its values up to 5.9275 lie in the gap
    # and those after it in the range a turn on. The entry by period tries the values within a
    # step of a solved pose's image first, in order: the three next to 4.8098 and the five
    # next to 5.9275 (each walk meets the limit) spent its eight tries, and 5.9403 was
    # NOT_ASSEMBLABLE in a dense sweep (SOLVED in a sparser one)
    m = stephenson_six_bar(5.283821535801237, 3.9793694733762446, 6.685887685709365, 4.391479271731757,
                           coupler_point=(5.429544943676676, 3.612385665322961), link_5=3.013987434278115,
                           link_6=7.539636103895253, pivot_6=(1.2365703166466138, 3.1039796387087266),
                           frame_angle=-1.0587573264435375, crossed=True, crossed_2=True,
                           start=1.9705113833240304).compile()
    us = np.array([[-1.4788773313], [-0.3531998805]])  # (poses the sweep had solved, next to the limits)
    qs = m.sweep(us).q
    br = Branch(m, block_plan(m, None), 1e-12)
    walker = walk_module.Walker(br, 0.05, False)
    signs = np.repeat(br.signs(m.q0[None], m.u0[None]), 2, 0)
    T = np.array([4.8211, 4.8385, 4.8411, 5.8811, 5.8857, 5.9011, 5.9123, 5.9211, 5.9403])[:, None]
    c, q, s = walker.enter_by_period(qs, us, signs, T)
    assert c == 8 and np.array_equal(s, signs[0])
    # the pose a turn back, up to whole turns of its angles
    back = m.sweep(T[8] - 2 * np.pi).q[0]
    d = q - back
    d[2::3] = (d[2::3] + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(d)) < 1e-9
