"""Batched Newton for positions, linear solves for velocities and accelerations.

Everything works on N configurations at once (numpy stacked solves); unconverged points are
compressed out of the active set each iteration. Residuals and steps are scaled: length rows
by the model's characteristic length L, x and y steps by L, angles as they are.
"""

import numpy as np


def _solve(J, b):
    """Stacked solve J x = b that survives exactly singular members (their x is NaN)."""
    try:
        return np.linalg.solve(J, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        sign, _ = np.linalg.slogdet(J)
        x = np.full(b.shape, np.nan)
        ok = sign != 0
        if ok.any():
            x[ok] = _solve(J[ok], b[ok])
        return x


def newton(model, q, u, *, tol=1e-12, step_tol=1e-10, max_iter=12, max_step=None):
    """Solve Phi(q; u) = 0 (independent rows plus drivers) from guesses q (N, n).

    Converged when the scaled residual is below ``tol`` and the scaled Newton step below
    ``step_tol`` (both: a residual test alone accepts plateaus near limit positions, a step
    test alone accepts stagnation). ``max_step`` (scaled) damps each step, for far guesses.
    Returns (q, converged, residual, iterations); ``residual`` is the scaled max-norm over all
    rows, redundant ones included, at the last evaluation.
    """
    q = np.array(q, dtype=float)
    N = q.shape[0]
    conv = np.zeros(N, bool)
    res = np.full(N, np.inf)
    iters = np.zeros(N, int)
    idx = np.arange(N)
    rows, rs, cs = model.active_rows, model.row_scale, model.col_scale
    with np.errstate(all="ignore"):
        for it in range(max_iter):
            if idx.size == 0:
                break
            Phi, J = model.system.evaluate(q[idx], u[idx])
            res[idx] = np.max(np.abs(Phi * rs), axis=1)
            dq = _solve(J[:, rows], Phi[:, rows])
            step = np.max(np.abs(dq / cs), axis=1)
            if max_step is not None:
                dq *= np.minimum(1.0, max_step / np.where(step > 0, step, 1.0))[:, None]
            q[idx] -= dq
            iters[idx] = it + 1
            done = (res[idx] <= tol) & (step <= step_tol)
            bad = ~np.isfinite(step) | ~np.isfinite(res[idx])
            conv[idx[done]] = True
            idx = idx[~done & ~bad]
    return q, conv, res, iters


def rates(model, q, u, ud, udd):
    """Velocities, accelerations and the singularity measure at solved positions q.

    ``ud`` and ``udd`` (N, f) are the input rates. Returns (qd, qdd, sing, sign): ``sing`` is
    |det| of the row- and column-scaled Jacobian over the product of its row norms (Hadamard,
    in [0, 1], 0 at a singular position), ``sign`` the sign of det (the assembly mode).
    """
    _, J = model.system.evaluate(q, u)
    rows, drows = model.active_rows, model.driver_rows_active
    Ja = J[:, rows]
    Js = Ja * model.row_scale[rows][None, :, None] * model.col_scale[None, None, :]
    norms = np.linalg.norm(Js, axis=2)
    sign, logdet = np.linalg.slogdet(Js)
    with np.errstate(all="ignore"):
        sing = np.exp(logdet - np.sum(np.log(norms), axis=1))
        nu = np.zeros(Ja.shape[:2])
        nu[:, drows] = ud
        qd = _solve(Ja, nu)
        gam = model.system.gamma(q, qd, u)[:, rows]
        gam[:, drows] += udd
        qdd = _solve(Ja, gam)
    return qd, qdd, sing, sign


def least_squares_gap(model, q, u, *, iterations=40):
    """Smallest scaled residual reachable from q by damped Gauss-Newton (Levenberg-Marquardt).

    For inputs the mechanism cannot reach this is the assembly gap; returns (q, gap).
    """
    q = np.array(q, dtype=float)
    rs, cs = model.row_scale, model.col_scale
    lam = np.full(q.shape[0], 1e-3)
    with np.errstate(all="ignore"):
        Phi, J = model.system.evaluate(q, u)
        r = Phi * rs
        cost = np.sum(r**2, axis=1)
        for _ in range(iterations):
            Js = J * rs[None, :, None] * cs[None, None, :]
            A = np.einsum("nki,nkj->nij", Js, Js)
            g = np.einsum("nki,nk->ni", Js, r)
            diag = np.einsum("nii->ni", A)
            A2 = A + lam[:, None, None] * np.eye(A.shape[1]) * (diag[:, :, None] + 1e-12)
            dq = _solve(A2, g) * cs
            q_new = q - np.nan_to_num(dq)
            Phi_n, J_n = model.system.evaluate(q_new, u)
            r_n = Phi_n * rs
            cost_n = np.sum(r_n**2, axis=1)
            better = cost_n < cost
            q[better], J[better], r[better], cost[better] = q_new[better], J_n[better], r_n[better], cost_n[better]
            lam = np.where(better, lam * 0.3, lam * 10.0)
    return q, np.max(np.abs(r), axis=1)
