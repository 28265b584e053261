"""Sweeps: continuation along the branch drawn in the sketch, batched where it can be.

1. Anchors: a sequential predictor-corrector walk from the assembled sketch through the input
   values in order, in steps no longer than ``max_step`` (scaled input units), halving a step
   whose solution changes assembly mode (sign of det) or lands far from its predictor.
2. Every other value is solved in one batch from its anchor with the second-order Taylor
   predictor ``q + q_u du + 1/2 q_uu du du`` (the velocity and acceleration solutions at
   input rate ``du``), and passes the same acceptance test; failures are walked to one by one.
3. Velocities and accelerations by two linear solves with the solved Jacobian; points whose
   Jacobian is singular keep their positions and get NaN rates; points that cannot be reached
   get NaN everywhere, their status and the assembly gap.
"""

import numpy as np

from planar.results import Status, Sweep
from planar.solver import least_squares_gap, newton, rates

CHUNK = 4096
SINGULAR = 1e-10  # normalised |det| below which rates are not computed
NEAR_SINGULAR = 1e-6
GAP = 1e-8  # scaled residual above which a least-squares minimum is not an assembly
JUMP = 0.2  # accepted distance from the predictor, as a fraction of the predicted move


def _scaled_norm(model, du):
    s = np.where(model.input_lengths, 1.0 / model.L, 1.0)
    return np.max(np.abs(du * s), axis=-1)


def _predict(model, q, u, du):
    """Second-order Taylor predictor from solved poses q at inputs u, for input steps du."""
    qd, qdd, _, sign = rates(model, q, u, du, np.zeros_like(du))
    return q + qd + 0.5 * qdd, sign


def _accept(model, q, q_pred, q_from, conv, sign, sign_ref):
    move = np.max(np.abs((q_pred - q_from) / model.col_scale), axis=1)
    off = np.max(np.abs((q - q_pred) / model.col_scale), axis=1)
    return conv & (sign == sign_ref) & (off <= JUMP * move + 1e-9)


def _sign(model, q, u):
    return rates(model, q, u, np.zeros_like(u), np.zeros_like(u))[3]


class _Walker:
    """Sequential continuation of one pose (batch of one) with step halving."""

    def __init__(self, model, tol, max_step):
        self.model, self.tol, self.max_step = model, tol, max_step

    def walk(self, q, u, sign, target):
        """Follow the branch from (q, u) to input ``target``; returns (q, sign) or None."""
        m = self.model
        total = float(_scaled_norm(m, target - u))
        if total == 0.0:
            return q, sign
        h = min(1.0, self.max_step / total)
        t = 0.0
        u0 = u
        while t < 1.0:
            dt = min(h, 1.0 - t)
            u_next = u0 + (t + dt) * (target - u0)
            q_pred, _ = _predict(m, q[None], u[None], (u_next - u)[None])
            qn, conv, _, _ = newton(m, q_pred, u_next[None], tol=self.tol)
            sn = _sign(m, qn, u_next[None])
            if _accept(m, qn, q_pred, q[None], conv, sn, sign)[0]:
                q, u, t = qn[0], u_next, t + dt
                h = min(2 * h, self.max_step / total)
            else:
                h /= 2
                if h * total < 1e-10:
                    return None
        return q, sign

    def enter(self, q, sign, target):
        """Re-enter the motion range at ``target`` from a pose q of the same branch."""
        m = self.model
        qn, conv, _, _ = newton(m, q[None], target[None], tol=self.tol, max_iter=40, max_step=0.3)
        if not conv[0]:
            return None
        if _sign(m, qn, target[None])[0] != sign:
            return None
        return qn[0], sign


def _anchors(model, U, max_step):
    """Indices of the values where the sequential walk stops: the first, and each value more
    than ``max_step`` from the previous anchor."""
    idx = [0]
    s = np.where(model.input_lengths, 1.0 / model.L, 1.0)
    last = U[0] * s
    for i, row in enumerate(U * s):
        if np.max(np.abs(row - last)) > max_step:
            idx.append(i)
            last = row
    return np.array(idx)


def run_sweep(model, U, Ud, Udd, *, tol=1e-12, max_step=0.05):
    N, n = U.shape[0], model.n
    walker = _Walker(model, tol, max_step)
    q = np.full((N, n), np.nan)
    solved = np.zeros(N, bool)
    anchor_sign = np.zeros(N)

    # 1. the sequential walk over anchors, from the assembled sketch
    sign0 = _sign(model, model.q0[None], model.u0[None])[0]
    state = (model.q0, model.u0, sign0)
    anchors = _anchors(model, U, max_step)
    for i in anchors:
        got = walker.walk(state[0], state[1], state[2], U[i])
        if got is None:
            got = walker.enter(state[0], state[2], U[i])
        if got is not None:
            q[i], solved[i], anchor_sign[i] = got[0], True, got[1]
            state = (got[0], U[i], got[1])

    # 2. every other value from the nearest solved anchor before it (else after it)
    good = anchors[solved[anchors]]
    rest = np.setdiff1d(np.arange(N), good)
    q_pred = np.full((N, n), np.nan)
    if good.size and rest.size:
        pos = np.searchsorted(good, rest) - 1
        src = np.where(pos >= 0, good[np.maximum(pos, 0)], good[0])
        for lo in range(0, rest.size, CHUNK):
            i, a = rest[lo : lo + CHUNK], src[lo : lo + CHUNK]
            qp, _ = _predict(model, q[a], U[a], U[i] - U[a])
            qn, conv, _, _ = newton(model, qp, U[i], tol=tol, max_iter=6)
            sn = _sign(model, qn, U[i])
            ok = _accept(model, qn, qp, q[a], conv, sn, anchor_sign[a])
            q[i[ok]], solved[i[ok]], anchor_sign[i[ok]] = qn[ok], True, sn[ok]
            q_pred[i] = qp

    # 3. the rest one by one, from the solved point before each
    last = None
    for i in np.flatnonzero(~solved):
        prev = np.flatnonzero(solved[:i])
        j = prev[-1] if prev.size else None
        if j is None:
            start = (model.q0, model.u0, sign0)
        else:
            start = (q[j], U[j], anchor_sign[j])
        if last is not None and last == j:
            continue  # the walk from this pose failed already: stay out until a new anchor
        got = walker.walk(*start, U[i])
        if got is None:
            last = j
            continue
        q[i], solved[i], anchor_sign[i] = got[0], True, got[1]

    return _finish(model, U, Ud, Udd, q, solved, q_pred, tol)


def _finish(model, U, Ud, Udd, q, solved, q_pred, tol):
    N, n = q.shape
    status = np.full(N, Status.NOT_CONVERGED, dtype=np.int8)
    qd = np.full((N, n), np.nan)
    qdd = np.full((N, n), np.nan)
    residual = np.full(N, np.nan)
    iters = np.zeros(N, int)
    sing = np.full(N, np.nan)
    branch = np.zeros(N)
    gap = np.full(N, np.nan)
    idx = np.flatnonzero(solved)
    for lo in range(0, idx.size, CHUNK):
        i = idx[lo : lo + CHUNK]
        # one more Newton pass: the reported residual and iteration count at the final pose
        qn, conv, res, it = newton(model, q[i], U[i], tol=tol)
        q[i], residual[i], iters[i] = qn, res, it
        a, b, s, sg = rates(model, qn, U[i], Ud[i], Udd[i])
        sing[i], branch[i] = s, sg
        st = np.where(s < NEAR_SINGULAR, Status.NEAR_SINGULAR, Status.SOLVED)
        st = np.where(s < SINGULAR, Status.SINGULAR, st)
        Phi, _ = model.system.evaluate(qn, U[i], jacobian=False)
        red = model.redundant_rows
        if red.size:
            bad = np.max(np.abs(Phi[:, red] * model.row_scale[red]), axis=1) > 1e3 * tol
            st = np.where(bad, Status.INCONSISTENT, st)
        st = np.where(conv, st, Status.NOT_CONVERGED)
        status[i] = st
        rate_ok = (st <= Status.BRANCH_EVENT)[:, None]
        qd[i], qdd[i] = np.where(rate_ok, a, np.nan), np.where(rate_ok, b, np.nan)
    q[status > Status.SINGULAR] = np.nan

    # unreached points: the assembly gap from the best guess at hand
    miss = np.flatnonzero(~solved)
    for lo in range(0, miss.size, CHUNK):
        i = miss[lo : lo + CHUNK]
        guess = np.where(np.isnan(q_pred[i]), model.q0, q_pred[i])
        _, g = least_squares_gap(model, guess, U[i])
        gap[i] = g
        status[i] = np.where(g > GAP, Status.NOT_ASSEMBLABLE, Status.NOT_CONVERGED)
    return Sweep(model, U.copy(), np.array(Ud), np.array(Udd), q, qd, qdd, status, residual, iters,
                 sing, branch, gap)
