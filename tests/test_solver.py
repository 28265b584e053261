"""Newton, the rate solves and the assembly gap, against exact solutions and finite differences.

Exact positions come from a sweep (solved to rounding); Newton from a perturbed guess must
converge quadratically and say so; at an input the mechanism cannot reach it must say it did
not. Velocities and accelerations are checked against central differences of Newton's
positions in the input. The assembly gap of a triple rocker four-bar (4, 3, 3, 3) past its
limit is checked against the hand value where the geometry gives it.
"""

from unittest import mock

import numpy as np
import pytest

from planar import solver
from planar.blocks import plan
from planar.mechanisms import four_bar, geared_five_bar, slider_crank, watt_six_bar
from planar.system import System

MECHANISMS = {
    "four_bar": lambda: four_bar(4, 2, 3.5, 3),
    "watt_six_bar": watt_six_bar,
    "geared_five_bar": geared_five_bar,
    "slider_crank": lambda: slider_crank(2, 5, offset=1),
}


@pytest.fixture(scope="module", params=sorted(MECHANISMS))
def solved(request):
    """(model, inputs U (5, f), exact positions q (5, n)) along a stretch of the input."""
    model = MECHANISMS[request.param]().compile()
    U = model.u0 + np.linspace(0.0, 1.0, 5)[:, None]
    res = model.sweep(U)
    assert res.ok.all()
    return model, U, np.array(res.q)


def scaled(model, dq):
    return np.max(np.abs(dq / model.col_scale), axis=-1)


def residual(model, q, u):
    """Scaled max-norm of the Newton rows (independent joint rows and drivers) at q."""
    Phi, _ = model.system.evaluate(q, u, jacobian=False)
    rows = np.asarray(model.active_rows)
    return np.max(np.abs(Phi[:, rows] * model.row_scale[rows]), axis=1)


def test_newton_converges_quadratically_to_the_solution(solved):
    model, U, exact = solved
    rng = np.random.default_rng(1)
    guess = exact + 3e-2 * rng.normal(size=exact.shape) * model.col_scale
    errors = [scaled(model, guess - exact)]
    for k in range(1, 5):  # tol 0: k iterations, unless the pose is solved to its rounding before
        q, conv, res, iters = solver.newton(model, guess, U, tol=0.0, step_tol=0.0, max_iter=k)
        assert np.all(iters[~conv] == k) and np.all(res[conv] <= solver.rounding(model, q[conv], np.arange(model.n)))
        errors.append(scaled(model, q - exact))
    e = np.array(errors)
    assert e[-1].max() < 1e-14
    # the error squares each step, down to rounding: from 1e-4 to 1e-8, where a linear rate
    # (even a hundredfold a step) would leave 1e-6
    assert np.all(e[1:] <= 5.0 * e[:-1] ** 2 + 1e-15), e.T


def test_converged_points_satisfy_the_constraints_to_the_tolerance(solved):
    model, U, exact = solved
    rng = np.random.default_rng(2)
    guess = exact + 3e-2 * rng.normal(size=exact.shape) * model.col_scale
    q, conv, res, iters = solver.newton(model, guess, U, tol=1e-12, step_tol=1e-10)
    assert conv.all() and np.all(iters <= 6)
    assert np.all(res <= 1e-12) and np.all(residual(model, q, U) <= 1e-12)
    np.testing.assert_allclose(q, exact, rtol=0, atol=1e-10 * model.L)
    # from the exact solution: one evaluation, a step of nothing, done
    q1, conv1, _, iters1 = solver.newton(model, exact, U)
    assert conv1.all() and np.all(iters1 == 1)
    np.testing.assert_allclose(q1, exact, rtol=0, atol=1e-14 * model.L)


def test_a_batch_solves_each_point_as_if_alone(solved):
    model, U, exact = solved
    rng = np.random.default_rng(3)
    guess = exact + 1e-1 * rng.normal(size=exact.shape) * model.col_scale
    q, conv, res, iters = solver.newton(model, guess, U)
    for i in range(len(U)):
        qi, ci, ri, ii = solver.newton(model, guess[i : i + 1], U[i : i + 1])
        np.testing.assert_allclose(qi[0], q[i], rtol=0, atol=1e-15 * model.L)
        assert (ci[0], ii[0]) == (conv[i], iters[i])


def test_max_step_bounds_each_scaled_step(solved):
    model, U, exact = solved
    guess = exact + 0.5 * np.random.default_rng(4).normal(size=exact.shape) * model.col_scale
    q, conv, _, _ = solver.newton(model, guess, U, max_iter=1, max_step=0.01)
    assert not conv.any()
    steps = scaled(model, q - guess)
    assert np.all(steps <= 0.01 * (1 + 1e-12)) and np.all(steps > 0.0099)


def test_a_plan_for_some_columns_moves_only_the_columns_it_solves():
    model = watt_six_bar().compile()
    rocker = 3 * model.body_id("rocker") - 1
    p = plan(model, [rocker])
    assert p.cols.size < model.n
    rng = np.random.default_rng(5)
    guess = model.q0 + 1e-2 * rng.normal(size=(3, model.n)) * model.col_scale
    u = model.u0 + np.array([[0.1], [0.2], [0.3]])
    q, conv, _, _ = solver.newton(model, guess, u, plan=p)
    assert conv.all()
    others = np.setdiff1d(np.arange(model.n), p.cols)
    np.testing.assert_array_equal(q[:, others], guess[:, others])
    full, _, _, _ = solver.newton(model, guess, u)
    np.testing.assert_allclose(q[:, p.cols], full[:, p.cols], rtol=0, atol=1e-12 * model.L)


def test_an_input_out_of_reach_is_reported_not_converged():
    """A triple rocker at crank angle pi: the four x rows of the loop must close a gap of 7 - 6
    = 1 (a quarter of L = 4), so no pose has a scaled residual below 1/16."""
    model = four_bar(4, 3, 3, 3).compile()
    u = np.array([[np.pi]])
    q, conv, res, iters = solver.newton(model, model.q0[None], u, max_iter=30)
    assert not conv[0] and iters[0] <= 30
    assert res[0] >= 1 / 16 * (1 - 1e-9) or not np.isfinite(res[0])


def _positions(model, U, start):
    """Newton's positions at inputs U (N, f) from ``start`` (a nearby solution)."""
    q, conv, _, _ = solver.newton(model, np.broadcast_to(start, (len(U), model.n)), U, tol=1e-15, step_tol=1e-13,
                                  max_iter=30)
    assert conv.all()
    return q


def test_velocity_and_acceleration_are_the_derivatives_of_the_positions(solved):
    """With unit input rate and no input acceleration, qd = dq/du and qdd = d2q/du2."""
    model, U, exact = solved
    p = plan(model)
    f = U.shape[1]
    for k in range(f):
        e = np.zeros(f)
        e[k] = h = 1e-4
        up, dn = (_positions(model, U + s * e, exact) for s in (1, -1))
        ud = np.tile(e / h, (len(U), 1))
        _, _, Jv = p.evaluate(exact, U)
        lu = p.factor(Jv, dets=False)
        qd = solver.velocity(p, lu, ud)
        np.testing.assert_allclose(qd, (up - dn) / (2 * h), rtol=0, atol=1e-6 * model.L)
        qdd = solver.acceleration(p, lu, exact, qd, U, np.zeros_like(ud))
        np.testing.assert_allclose(qdd, (up - 2 * exact + dn) / h**2, rtol=0, atol=2e-4 * model.L)
        # rates are linear in the input rate; an input acceleration adds udd times qd
        np.testing.assert_allclose(solver.velocity(p, lu, 3 * ud), 3 * qd, rtol=1e-12, atol=1e-14)
        qdd2 = solver.acceleration(p, lu, exact, qd, U, 0.5 * ud)
        np.testing.assert_allclose(qdd2, qdd + 0.5 * qd, rtol=1e-10, atol=1e-12 * model.L)


def test_stacked_solve_survives_singular_members():
    rng = np.random.default_rng(6)
    J = rng.normal(size=(4, 3, 3))
    J[2] = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]  # exactly singular
    b = rng.normal(size=(4, 3))
    x = solver._solve(J, b)
    assert np.isnan(x[2]).all()
    ok = [0, 1, 3]
    np.testing.assert_allclose(x[ok], np.linalg.solve(J[ok], b[ok][..., None])[..., 0], rtol=1e-12)


def _cost(model, q, u):
    Phi, _ = model.system.evaluate(q, u, jacobian=False)
    return np.sum((Phi * model.row_scale) ** 2, axis=1)


def test_least_squares_gap_of_a_triple_rocker_past_its_limit():
    model = four_bar(4, 3, 3, 3).compile()
    deg = np.array([118.0, 130.0, 150.0, 180.0, 200.0, 240.0])  # limits at +-117.28 deg
    u = np.radians(deg)[:, None]
    q, gap = solver.least_squares_gap(model, np.tile(model.q0, (len(u), 1)), u)
    Phi, _ = model.system.evaluate(q, u, jacobian=False)
    np.testing.assert_allclose(gap, np.max(np.abs(Phi * model.row_scale), axis=1), rtol=0, atol=1e-15)
    # at pi the loop is a straight line: the gap of 1 splits over the four x rows, 1/4 / L each
    assert gap[3] == pytest.approx(1 / 16, rel=1e-8)
    # holding the crank at the input (its driver row at 0), the best cost is (7 - ...)^2 / 64:
    # the gap of the lengths split over the four joints; turning the crank can only do better
    A = 3 * np.stack((np.cos(u[:, 0]), np.sin(u[:, 0])), axis=1)
    short = np.linalg.norm(np.array([4.0, 0.0]) - A, axis=1) - 6.0
    cost = _cost(model, q, u)
    assert np.all(cost <= short**2 / 64 * (1 + 1e-9)) and np.all(cost > 0.5 * short**2 / 64)
    # the further past the limit, the larger the gap (both ways round from pi)
    assert np.all(np.diff(gap[:4]) > 0) and np.all(np.diff(gap[3:]) < 0)
    # a local minimum of the cost: no small move lowers it
    rng = np.random.default_rng(7)
    for _ in range(20):
        dq = 1e-4 * rng.normal(size=q.shape) * model.col_scale
        assert np.all(_cost(model, q + dq, u) >= cost * (1 - 1e-12))


def test_least_squares_gap_that_only_decides_stops_once_the_side_of_the_threshold_is_plain():
    # the searches past a gap ask only whether a point assembles (gap <= GAP): a point stops
    # at a hundredth of it (Newton goes on from there) or, above it, once its steps barely
    # lower the cost, where the full search drives assemblies to rounding and minima to 1e-10
    model = four_bar(4, 3, 3, 3).compile()
    u = np.radians([[0.0], [60.0], [117.0], [118.0], [150.0], [180.0]])  # limits at +-117.28 deg
    q0 = np.tile(model.q0, (len(u), 1))
    real, count = System.evaluate, []

    def counted(system, q, *args, **kw):
        count.append(q.shape[0])
        return real(system, q, *args, **kw)

    with mock.patch.object(System, "evaluate", counted):
        _, full = solver.least_squares_gap(model, q0, u)
        work = sum(count)
        count.clear()
        q, decided = solver.least_squares_gap(model, q0, u, decide=1e-8)
    assert sum(count) < 0.8 * work, (sum(count), work)
    np.testing.assert_array_equal(decided <= 1e-8, full <= 1e-8)
    assert np.all(decided[:3] <= 1e-10) and np.all(residual(model, q[:3], u[:3]) <= 1e-10)
    np.testing.assert_allclose(decided[3:], full[3:], rtol=1e-4)


def test_least_squares_gap_stops_a_point_crawling_along_a_valley_of_minima():
    # a geared five-bar 5.7 rad into the gap of its crank's range: the loop cannot close and
    # shares out its gap among the joints in a continuum of ways; damped Gauss-Newton crawls
    # along that valley, each step lowering the cost by ~1e-6 of it, up to the iteration cap
    model = geared_five_bar(ground=22.77, gear_radius_2=5.04, gear_radius_4=10.28, link_5=3.11,
                            start=-0.78).compile()
    q0, u = model.q0[None], np.array([[9.1]])
    real, count = System.evaluate, []

    def counted(system, q, *args, **kw):
        count.append(q.shape[0])
        return real(system, q, *args, **kw)

    with mock.patch.object(System, "evaluate", counted):
        with mock.patch.object(solver, "STALL", 0.0):
            _, crawled = solver.least_squares_gap(model, q0, u)
        crawl = len(count)
        count.clear()
        _, gap = solver.least_squares_gap(model, q0, u)
        stopped = len(count)
        count.clear()
        _, decided = solver.least_squares_gap(model, q0, u, decide=1e-8)
    assert crawl > 150 and stopped < 0.6 * crawl and len(count) <= stopped, (crawl, stopped, len(count))
    # the gap of a valley is its height to the percent: the crawl's 150 more steps move it less
    assert gap[0] == pytest.approx(crawled[0], rel=1e-2) and decided[0] > 0.1


def test_least_squares_gap_is_zero_where_the_mechanism_assembles():
    model = four_bar(4, 3, 3, 3).compile()
    u = np.radians([[0.0], [60.0], [-110.0]])
    q, gap = solver.least_squares_gap(model, np.tile(model.q0, (3, 1)), u)
    assert np.all(gap < 1e-12)
    assert np.all(residual(model, q, u) < 1e-12)
