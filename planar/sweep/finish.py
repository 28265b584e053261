"""The results of a sweep: the final step of the values not yet final, the values on and around
located events, unreached values and their gaps, jumps, near-singular stretches, and the values
put back in the asked order and shifted back by whole periods."""

from dataclasses import replace

import numpy as np

from planar.events import NEAR_CURVE, Event, status_of
from planar.results import POSED as POSED_MASK
from planar.results import VALID as VALID_MASK
from planar.results import Status, Sweep
from planar.solver import ALONG_TANGENT, GAP, REENTRY, least_squares_gap, newton
from planar.sweep.anchors import CHUNK
from planar.sweep.branch import final_step, input_scale
from planar.sweep.located import EVENT_TOL
from planar.sweep.periods import add_periods

BRANCH_H = 4e-2  # scaled input radius around a bifurcation where values come from the branch


def _asked_order(model, U, order, events, u0):
    """The events of values solved in the order of the input (``U``, one input, in that order;
    ``order`` their asked positions), indexed in the asked order: the first value asked at or
    past each singular position seen from the start's input ``u0`` (a near-singular stretch:
    its closest value)."""
    N, tol = len(U), EVENT_TOL / float(input_scale(model)[0])
    out = []
    for e in events:
        i = int(order[min(e.index, N - 1)])
        d = np.sign(float(e.input) - float(u0[0]))
        if e.kind != "near_singular" and d != 0:
            at = np.flatnonzero((U[:, 0] - float(e.input)) * d >= -tol)
            i = int(order[at].min()) if at.size else i
        out.append(replace(e, index=i))
    return sorted(out, key=lambda e: e.index)


def _mark_jumps(status, stops, prev=None):
    """JUMPED for the first value past each limit the walk stopped at (``stops``: the events'
    indices) where it is valid and the value before it posed: the branch was re-entered past the
    limit with no unassemblable value between to show the gap (a pair of limits inside one step).
    With ``prev`` (values solved out of the asked order: the index of the value asked before
    each, -1 for none), ``stops`` are the values with a limit between them and that value."""
    posed, valid = POSED_MASK[status], VALID_MASK[status]
    for j in stops:
        if prev is not None:
            if valid[j] and posed[prev[j]]:
                status[j] = Status.JUMPED
            continue
        j += int(j < status.size and status[j] == Status.LIMIT)
        if 0 < j < status.size and valid[j] and posed[j - 1]:
            status[j] = Status.JUMPED


class Out:
    """Per-point results filled chunk by chunk: allocated, not filled (the bulk pass writes
    nearly every row, on all cores in the compiled engine; :meth:`blank` fills the rest)."""

    def __init__(self, N, n, rates=True):
        # without rates, one read-only NaN that takes no memory (the result's arrays are
        # read-only)
        self.rates = rates
        if rates:
            self.qd, self.qdd = np.empty((N, n)), np.empty((N, n))
        else:
            self.qd = self.qdd = np.broadcast_to(np.nan, (N, n))
        self.residual, self.sing, self.branch = np.empty(N), np.empty(N), np.empty(N)
        self.iters = np.empty(N, int)
        self.status = np.empty(N, dtype=np.int8)

    def put(self, i, r, sel=slice(None)):
        if self.rates:
            self.qd[i], self.qdd[i] = r["qd"][sel], r["qdd"][sel]
        self.residual[i], self.iters[i] = r["res"][sel], r["iters"][sel]
        self.sing[i], self.branch[i], self.status[i] = r["sing"][sel], r["branch"][sel], r["status"][sel]

    def blank(self, rows):
        """The rows nothing was put for: NaN rates, residual and singularity, no iterations,
        no mode, status NOT_CONVERGED (until said otherwise)."""
        if self.rates:
            self.qd[rows] = self.qdd[rows] = np.nan
        self.residual[rows] = self.sing[rows] = np.nan
        self.iters[rows], self.branch[rows], self.status[rows] = 0, 0.0, Status.NOT_CONVERGED


def finish(model, br, U, Ud, Udd, q, solved, done, out, q_pred, events, at_event, beyond, jumps, U_in, shift,
            order=None, u0=None):
    """The results of the solved values; ``jumps`` (stops, prev) for :func:`_mark_jumps`;
    ``shift`` (k, (P, D)): value i was solved k[i] periods P back (the input values ``U_in``),
    its pose shifted back by k[i] D; ``order`` (values solved in the order of the input from
    the start's input ``u0``): the asked position of each, where the results are put back."""
    N, n = q.shape
    p = br.p
    idx = np.flatnonzero(solved & ~done)
    for lo in range(0, idx.size, CHUNK):
        i = idx[lo : lo + CHUNK]
        r = final_step(br, q[i], U[i], Ud[i], Udd[i])
        q[i] = r["q"]
        out.put(i, r)
    # every solved value has been put but those on events, which get their values there
    unset = ~solved
    unset[list(at_event)] = True
    out.blank(unset)
    lost = ~solved & ~beyond
    lost[list(at_event)] = False
    solved[_on_events(model, br, U, Ud, Udd, q, out, events, at_event, lost)] = True
    status = out.status
    q[~POSED_MASK[status]] = np.nan
    if p.cols.size < n:
        drop = np.setdiff1d(np.arange(n), p.cols)
        q[:, drop] = np.nan
        if out.rates:
            out.qd[:, drop] = out.qdd[:, drop] = np.nan

    # unreached points: the assembly gap from the best guess at hand
    miss = np.flatnonzero(~solved)
    gap = np.full(N, np.nan) if miss.size else np.broadcast_to(np.nan, N)  # (read-only, as every result array)
    for lo in range(0, miss.size, CHUNK):
        i = miss[lo : lo + CHUNK]
        guess = np.array([q_pred.get(k, model.q0) for k in i.tolist()]).reshape(i.size, n)
        guess = np.where(np.isnan(guess), model.q0, guess)
        ql, g = least_squares_gap(model, guess, U[i])
        # least squares stalls above zero in the valley of a near-singular mechanism: Newton
        # from where it stopped tells a value that assembles (not reached: NOT_CONVERGED)
        s = np.flatnonzero((g > GAP) & ~beyond[i])
        if s.size:
            g[s] = np.fmin(g[s], newton(model, ql[s], U[i][s], tol=br.tol, max_iter=REENTRY)[2])
        gap[i] = g
        status[i] = np.where((g > GAP) | beyond[i], Status.NOT_ASSEMBLABLE, Status.NOT_CONVERGED)
    _mark_jumps(status, *jumps)
    events = tuple(events) + tuple(near_stretches(model, U, out.sing, status, events))
    events = tuple(sorted(events, key=lambda e: e.index))
    residual, iters, sing, branch = out.residual, out.iters, out.sing, out.branch
    qd, qdd = out.qd, out.qdd
    if order is not None:
        events = tuple(_asked_order(model, U, order, events, u0))
        inv = np.empty_like(order)
        inv[order] = np.arange(N)
        q, status, residual, iters, sing, branch = (a[inv] for a in (q, status, residual, iters, sing, branch))
        U, Ud, Udd, U_in, gap = U[inv], Ud[inv], Udd[inv], U_in[inv], gap[inv]
        if out.rates:
            qd, qdd = qd[inv], qdd[inv]
        shift = None if shift is None else (shift[0][inv], shift[1])
    if shift is not None:
        k, (P, D) = shift
        q[:] = add_periods(q, k[:, None], D)
        at = lambda e: k[min(e.index, N - 1)]  # noqa: E731
        events = tuple(replace(e, input=add_periods(e.input, at(e), P),
                               q=None if e.q is None else add_periods(e.q, at(e), D)) for e in events)
        U = U_in
    return Sweep(model, U, Ud, Udd, q, qd, qdd, status, residual, iters, sing, branch, gap, events)


def _on_events(model, br, U, Ud, Udd, q, out, events, at_event, lost):
    """Values at and around located singular positions. A value on a limit keeps the located
    pose (status LIMIT, rates NaN). Around a bifurcation every value within BRANCH_H takes its
    values from the smooth branch interpolated from regular points (the direct solves lose
    accuracy like 1/distance there, or fail next to it: ``lost``, the values the walk reached
    but did not solve); the values on it get status BRANCH_EVENT. Returns the lost values
    solved here."""
    for i, ev in at_event.items():
        q[i] = ev.q
        if out.rates:
            out.qd[i] = out.qdd[i] = np.nan
        out.sing[i], out.residual[i] = ev.singularity, np.nan
        out.status[i] = Status.LIMIT if ev.kind == "limit" else Status.SINGULAR
    s = input_scale(model)
    found = []
    for ev in events:
        if ev.kind not in ("bifurcation", "singular") or U.shape[1] != 1:
            continue
        dist = np.abs(U[:, 0] - ev.input) * s[0]
        near = np.flatnonzero((dist < BRANCH_H / 4) & (POSED_MASK[out.status] | lost))
        if near.size == 0 or "other branch" in ev.note or not ev.tangents:  # no tangent: no branch to follow
            continue
        got = _on_branch(model, br, ev, U[near, 0], Ud[near, 0], Udd[near, 0])
        if got is None:
            continue
        # the interpolated pose replaces the direct solve only where it holds the constraints
        # to tolerance (its residual is the one reported): never a valid status on a bad pose
        Phi, _, _ = br.p.evaluate(got[0], U[near])
        res = np.max(np.abs(Phi * model.row_scale[br.p.rows]), axis=1)
        fits = res <= 1e2 * br.tol
        near, res = near[fits], res[fits]
        q[near] = got[0][fits]
        if out.rates:
            out.qd[near], out.qdd[near] = got[1][fits], got[2][fits]
        out.residual[near] = res
        new = near[~POSED_MASK[out.status[near]]]
        if new.size:  # a lost value: its modes and status at the pose from the branch
            signs, out.sing[new] = br.modes(q[new], U[new])
            out.branch[new], out.status[new] = np.prod(signs, axis=1), status_of(out.sing[new])
            found.append(new)
        # a value on the event, or one the direct solve found singular, now has rates from
        # the branch: valid, flagged as at a branch event
        on = (dist[near] <= EVENT_TOL) | (out.status[near] == Status.SINGULAR)
        out.status[near[on]] = Status.BRANCH_EVENT
    return np.concatenate(found) if found else np.zeros(0, int)


def _on_branch(model, br, ev, u, ud, udd):
    """Position, velocity and acceleration at inputs u (one input) on the smooth branch through
    the singular position ``ev``: degree-7 interpolation of eight regular points at
    u* +- k h (k = 1..4, h = BRANCH_H / 4 scaled), each solved from the branch tangent with its
    own rates. Direct solves lose digits like 1/distance (positions), 1/distance^2
    (velocities) and 1/distance^3 (accelerations) there; these nodes are far enough not to."""
    T = ev.tangents[0]
    us = float(ev.input)
    h = BRANCH_H / 4 / float(input_scale(model)[0])
    nodes = us + h * np.array([-4.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 4.0])
    guess = ev.q[None] + (nodes - us)[:, None] * T[None]
    qn, conv, _, _ = br.solve(guess, nodes[:, None], max_iter=ALONG_TANGENT)
    if not conv.all():
        return None
    qu, quu, _, _ = br.state(qn, nodes[:, None], np.ones((nodes.size, 1)))
    K = nodes.size
    W = np.array([[np.prod([(x - nodes[k]) / (nodes[j] - nodes[k]) for k in range(K) if k != j])
                   for j in range(K)] for x in u])
    q_u = W @ qu
    return W @ qn, q_u * ud[:, None], q_u * udd[:, None] + (W @ quu) * (ud**2)[:, None]


def near_stretches(model, U, sing, status, events):
    """One near-singular event per run of valid values closer to another branch than
    NEAR_CURVE (the singularity measure), at its closest value, unless another event lies
    within the run or next to it (a limit or a crossing explains it)."""
    out = []
    with np.errstate(invalid="ignore"):
        flag = VALID_MASK[status] & (sing < NEAR_CURVE)
    if not flag.any():
        return out
    known = [e.index for e in events]
    edges = np.flatnonzero(np.diff(np.r_[0, flag.astype(int), 0]))
    for a, b in zip(edges[::2], edges[1::2]):
        k = a + int(np.nanargmin(sing[a:b]))
        if any(a - 1 <= i <= b + 1 for i in known):
            continue
        near = int(np.sum(status[a:b] == Status.NEAR_SINGULAR))
        out.append(Event("near_singular", U[k, 0] if U.shape[1] == 1 else U[k].copy(), int(k),
                         singularity=float(sing[k]),
                         error=float(np.finfo(float).eps / sing[k]) if sing[k] > 0 else np.inf,
                         note=f"{b - a} value(s) close to another branch (an avoided crossing or a close approach, "
                              f"singularity down to {sing[k]:.2g}; {near} of them NEAR_SINGULAR): valid but sensitive; "
                              "the branch was kept"))
    return out
