"""Batched Newton for positions, linear solves for velocities and accelerations.

Everything works on N configurations at once and goes through the block-triangular plan of
:mod:`planar.blocks`: a Newton step, a velocity and an acceleration are forward substitutions
through small blocks. Unconverged points are compressed out of the active set each iteration.
Residuals and steps are scaled: length rows by the model's characteristic length L, x and y
steps by L, angles as they are.
"""

import numpy as np

from planar.blocks import plan as block_plan

# Newton's iteration caps, by how far its guess may be from the solution (it converges
# quadratically: a good guess takes 2-4 steps, a cap only stops one that does not converge)
PREDICTED = 8  # a predictor one walk step from a solved pose
STEPS = 12  # the default
PROJECTED = 10  # a point of a traced curve, moved onto a value of the input
ALONG_TANGENT = 20  # a guess along a tangent or a secant of a traced curve, next to a singular position
DISTANT = 30  # a pose from the tracer, a period away, or a batch value off its guess
REENTRY = 40  # a guess across a gap of the motion range, or a least-squares minimum
RESTARTED = 20  # a solved pose with some angles drawn at random (those that converge take 7-20 steps)
# Newton's steps at a pose solved to the rounding of its coordinates (:func:`rounding`), over
# that rounding: they solve the rows' rounding noise through the Jacobian's inverse
WANDER = 10.0
GAP = 1e-8  # scaled residual above which a least-squares minimum is not an assembly
# a least-squares search that only decides whether a point assembles (its gap above or below
# a threshold) stops a point above it whose step lowers its cost by less than this fraction
DECIDED = 1e-7
# a least-squares point whose cost fell by less than this fraction over its last STALL_STEPS
# steps, at a gap, is at its minimum to that fraction: the crawl along a nearly flat valley of
# minima (a loop that cannot close shares out its gap among the joints in a continuum of ways)
STALL, STALL_STEPS = 1e-4, 10


def _solve(J, b):
    """Stacked dense solve J x = b that survives exactly singular members (their x is NaN)."""
    try:
        return np.linalg.solve(J, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        sign, _ = np.linalg.slogdet(J)
        x = np.full(b.shape, np.nan)
        ok = sign != 0
        if ok.any():
            x[ok] = _solve(J[ok], b[ok])
        return x


def rounding(model, q, cols):
    """(N,) the scaled residual and Newton step below which poses q (N, n) cannot be solved:
    the rounding of their coordinates (columns ``cols``, scaled) through the rows' coefficients.
    Below the tolerances for poses of ordinary size; above them for angles counted to 1e5 rad
    with no period to bring them back (a geared linkage of irrational ratio), whose rows hold
    only to that rounding.

    >>> from planar.mechanisms import four_bar
    >>> m = four_bar(4, 2, 3, 4).compile()
    >>> bool(rounding(m, m.q0[None], np.arange(m.n))[0] < 1e-14), bool(rounding(m, m.q0[None] + 1e6, np.arange(m.n))[0] > 1e-12)
    (True, True)
    """
    with np.errstate(invalid="ignore"):
        return np.finfo(float).eps * model.Phi_q_norm * np.max(np.abs(q[:, cols]) / model.col_scale[cols], axis=1)


def converged(model, q, cols, res, step, tol, step_tol, wander=1.0):
    """(N,) the residuals ``res`` within ``tol`` and the steps ``step`` within ``step_tol`` of
    poses q, or within their :func:`rounding` (the step's ``wander`` times it). The rounding is
    computed only for the poses the tolerances alone do not pass: in Newton's loop, those still
    stepping (a few array operations over them an iteration, against its evaluation and solve);
    in a final step, the few the tolerances miss."""
    ok = (res <= tol) & (step <= step_tol)
    far = np.flatnonzero(~ok & np.isfinite(res) & np.isfinite(step))
    if far.size:
        floor = rounding(model, q[far], cols)
        ok[far] = (res[far] <= np.maximum(tol, floor)) & (step[far] <= np.maximum(step_tol, wander * floor))
    return ok


def newton(model, q, u, *, tol=1e-12, step_tol=1e-10, max_iter=STEPS, max_step=None, plan=None, engine=None):
    """Solve Phi(q; u) = 0 (independent rows plus drivers) from guesses q (N, n).

    Converged when the scaled residual is below ``tol`` and the scaled Newton step below
    ``step_tol`` (both: a residual test alone accepts plateaus near limit positions, a step
    test alone accepts stagnation). ``max_step`` (scaled) damps each step, for far guesses.
    Both tests hold at least to the rounding of the pose's coordinates (:func:`rounding`; the
    step's, WANDER times it).
    ``plan`` (default: the whole model) restricts the solve to some blocks. ``engine``: the
    module :mod:`planar.compiled`, to take the undamped iterations in its compiled loop, each
    value on its own (default: numpy).
    Returns (q, converged, residual, iterations); ``residual`` is the scaled max-norm of the
    solved rows at the last evaluation.
    """
    p = block_plan(model) if plan is None else plan
    if engine is not None and max_step is None:
        f = engine.final(model, p, q, u, u, u, rates=False, steps=max_iter, tol=tol, step_tol=step_tol)
        return f["q"], converged(model, f["q"], p.cols, f["res"], f["step"], tol, step_tol, WANDER), f["res"], f["iters"]
    q = np.array(q, dtype=float)
    N = q.shape[0]
    conv = np.zeros(N, bool)
    res = np.full(N, np.inf)
    iters = np.zeros(N, int)
    idx = np.arange(N)
    rs, cs = model.row_scale[p.rows], model.col_scale[p.cols]
    with np.errstate(all="ignore"):
        for it in range(max_iter):
            if idx.size == 0:
                break
            Phi, _, Jv = p.evaluate(q[idx], u[idx])
            res[idx] = np.max(np.abs(Phi * rs), axis=1)
            dq = p.factor(Jv, dets=False).solve(Phi)
            step = np.max(np.abs(dq[:, p.cols] / cs), axis=1)
            if max_step is not None:
                dq *= np.minimum(1.0, max_step / np.where(step > 0, step, 1.0))[:, None]
            q[idx] -= dq
            iters[idx] = it + 1
            done = converged(model, q[idx], p.cols, res[idx], step, tol, step_tol, WANDER)
            bad = ~np.isfinite(step) | ~np.isfinite(res[idx])
            conv[idx[done]] = True
            idx = idx[~done & ~bad]
    return q, conv, res, iters


def velocity(p, lu, ud):
    """qd (N, n) solving the kept rows of plan ``p`` (factored: ``lu``) with input rates
    ``ud`` (N, f)."""
    nu = np.zeros((ud.shape[0], p.rows.size))
    nu[:, p.drivers] = ud[:, p.driver_inputs]
    return lu.solve(nu)


def acceleration(p, lu, q, qd, u, udd):
    """qdd (N, n) from gamma at (q, qd) and input accelerations ``udd`` (N, f)."""
    gam = p.system.gamma(q, qd, u)[:, p.rows]
    gam[:, p.drivers] += udd[:, p.driver_inputs]
    return lu.solve(gam)


def least_squares_gap(model, q, u, *, iterations=200, decide=None):
    """Smallest scaled residual reachable from q by damped Gauss-Newton (Levenberg-Marquardt).

    For inputs the mechanism cannot reach this is the assembly gap; returns (q, gap). Each
    point stops once assembled, stuck (over ten rejected steps in a row) or no longer
    improving (a non-zero minimum: the gap, once a step lowers the cost by less than 1e-10 of
    it, or STALL_STEPS steps by less than STALL); the others go on, so the iteration budget
    is spent on the few that converge slowly (next to a limit, where the solution is singular
    and Gauss-Newton converges only linearly). ``decide``: a gap that only needs to be told
    above or below this (the searches past a gap): a point stops once its gap is a hundredth
    of it (Newton takes it on from there), or, its gap above it, once a step lowers its cost
    by less than DECIDED of it (a minimum crept up on: over a fuzz campaign's 6,000 points
    none of those went on to assemble).
    """
    q = np.array(q, dtype=float)
    rs, cs = model.row_scale, model.col_scale
    N = q.shape[0]
    lam = np.full(N, 1e-3)
    with np.errstate(all="ignore"):
        Phi, J = model.system.evaluate(q, u)
        r = Phi * rs
        cost = np.sum(r**2, axis=1)
        act = np.arange(N)
        last = cost.copy()  # each point's cost STALL_STEPS steps ago
        for it in range(1, iterations + 1):
            if act.size == 0:
                break
            Js = J[act] * rs[None, :, None] * cs[None, None, :]
            A = np.einsum("nki,nkj->nij", Js, Js)
            g = np.einsum("nki,nk->ni", Js, r[act])
            diag = np.einsum("nii->ni", A)
            A2 = A + lam[act, None, None] * np.eye(A.shape[1]) * (diag[:, :, None] + 1e-12)
            dq = _solve(A2, g) * cs
            q_new = q[act] - np.nan_to_num(dq)
            Phi_n, J_n = model.system.evaluate(q_new, u[act])
            r_n = Phi_n * rs
            cost_n = np.sum(r_n**2, axis=1)
            cost_o = cost[act]
            better = cost_n < cost_o
            flat = better & (cost_n > cost_o * (1 - 1e-10))
            b = act[better]
            q[b], J[b], r[b], cost[b] = q_new[better], J_n[better], r_n[better], cost_n[better]
            lam[act] = np.where(better, lam[act] * 0.3, lam[act] * 10.0)
            done = (cost[act] <= 1e-32) | (lam[act] > 1e8) | flat
            if it % STALL_STEPS == 0:
                done |= (cost[act] > r.shape[1] * (decide or GAP) ** 2) & (cost[act] > last[act] * (1 - STALL))
                last[act] = cost[act]
            if decide is not None:
                # (a cost over m decide^2 has a row over decide)
                done |= (cost[act] <= (0.01 * decide) ** 2) | (better & (cost_n > r.shape[1] * decide**2) &
                                                               (cost_n > cost_o * (1 - DECIDED)))
            act = act[~done]
    return q, np.max(np.abs(r), axis=1)
