"""Anchors and the bulk: where the walk stops (:func:`sweep_anchors`), anchors solved in batched
waves (:func:`solve_wave`), and every other value solved in batch from the anchors of its stretch
(:func:`from_anchors`: quintic Hermite interpolation in the kinematic coefficients)."""

import bisect

import numpy as np

from planar.events import NEAR
from planar.progress import Progress
from planar.sweep.branch import final_step, input_scale, scaled_norm

CHUNK = 16384  # values solved in one batch of the bulk pass
WAVE, MAX_WAVE = 16, 256  # anchors tried in one batch: first, and at most (doubled while all pass)


def sweep_anchors(model, U, max_step):
    """Indices of the values where the sequential walk stops: the first, the last, values no
    further than ``max_step`` apart (:func:`walk_anchors`, so each is one walk step) and (one
    input) each value where the input turns back, so the walk covers every value."""
    idx, monotone = walk_anchors(U, input_scale(model), max_step)
    turns = np.zeros(0, int)
    if not monotone and U.shape[1] == 1:
        d = np.sign(np.diff(U[:, 0]))
        nz = np.flatnonzero(d)
        turns = nz[1:][d[nz[1:]] != d[nz[:-1]]]
    return np.unique(np.r_[idx, turns, len(U) - 1]).astype(int)


def walk_anchors(U, scale, max_step):
    """(indices, monotone): value 0 and values after it, each within ``max_step`` (scaled) of
    the one before where the values allow; ``monotone``: one input that never turns back.

    One monotone input whose values lie closer than max_step / 2: the last value at or before
    each point of a grid of spacing max_step - g (g the largest gap between values), so
    consecutive picks lie less than max_step apart, in a few whole-array passes. Otherwise
    greedily, the last value within max_step of the previous pick.
    """
    if U.shape[1] == 1:
        v = U[:, 0]
        step = max_step / scale[0]
        d = np.diff(v)
        lo, hi = (d.min(), d.max()) if d.size else (0.0, 0.0)
        if lo >= 0 or hi <= 0:
            v, gap = (v, hi) if lo >= 0 else (-v, -lo)
            if gap < step / 2:
                grid = v[0] + (step - gap) * np.arange(1, np.ceil((v[-1] - v[0]) / (step - gap)) + 1)
                return np.unique(np.r_[0, np.searchsorted(v, grid, side="right") - 1]), True
            # (fewer than two values per max_step: a short list, searched with bisect)
            vl, idx, i = v.tolist(), [0], 0
            while True:
                j = bisect.bisect_right(vl, vl[i] + step)
                if j >= len(vl):
                    return np.array(idx), True
                i = max(i + 1, j - 1)
                idx.append(i)
    V = U * scale
    idx, i, span = [0], 0, 64
    while True:
        far = np.flatnonzero(np.max(np.abs(V[i + 1 : i + 1 + span] - V[i]), axis=1) > max_step)
        if far.size:
            i += max(1, int(far[0]))
            idx.append(i)
        elif i + 1 + span >= len(V):
            return np.array(idx), False
        else:
            span *= 2


def from_anchors(br, U, Ud, Udd, q, signs, solved, done, out, q_pred, cuts, kin, anchors, targets):
    """Solve ``targets`` in batch from the solved anchors of their own stretch (no event in
    between): one input interpolates between two consecutive anchors (quintic Hermite in the
    kinematic coefficients), or extrapolates from the nearer one (second-order Taylor); the
    result passes the walk's acceptance test or is left for the sequential walk."""
    n = q.shape[1]
    one = U.shape[1] == 1
    good = anchors[solved[anchors]]
    rest = targets
    if one and good.size:  # kinematic coefficients at the anchors; singular ones are no source
        QU, QUU, sg = kin.at(br, q, U, good)
        regular = sg >= NEAR
        good, QU, QUU = good[regular], QU[regular], QUU[regular]
    if not (good.size and rest.size):
        return
    # consecutive anchors of one stretch (no failed or singular anchor, no located event between,
    # some input between): the values between them interpolate rather than extrapolate
    seg_of = np.searchsorted(cuts, good, side="right")
    adj = np.zeros(good.size, bool)
    if one:
        adj[:-1] = (np.diff(np.searchsorted(anchors, good)) == 1) & (np.diff(U[good, 0]) != 0) & (np.diff(seg_of) == 0)
    P = quintic(q[good], QU, QUU, np.diff(U[good, 0])) if one else None
    if br.compiled is not None and adj.any():
        # the interpolated values in one compiled pass, in place; the rest as below
        qd, qdd = (out.qd, out.qdd) if out.rates else (np.empty((0, n)), np.empty((0, n)))
        arrays = dict(q=q, U=U, Ud=Ud, Udd=Udd, qd=qd, qdd=qdd, res=out.residual, signs=signs,
                      sing=out.sing, branch=out.branch, status=out.status, iters=out.iters, solved=solved, done=done)
        ok = br.compiled.fill(br.m, br.p, rest, adj, good, P, signs[good], br.tol, br.rates, arrays)
        rest = rest[~ok & ~solved[rest]]  # (a solved anchor it left gets its final step at the end)
    # each target's anchors before and after (positions in good), and whether each lies in the
    # target's stretch
    pos = np.searchsorted(good, rest) - 1
    prev_k, next_k = np.maximum(pos, 0), np.minimum(pos + 1, good.size - 1)
    same_prev, same_next = pos >= 0, pos + 1 < good.size
    if cuts.size:
        seg = np.searchsorted(cuts, rest, side="right")
        same_prev &= seg_of[prev_k] == seg
        same_next &= seg_of[next_k] == seg
    where = np.where(same_prev, prev_k, next_k)  # the source anchor
    has = same_prev | same_next
    both = same_prev & same_next & adj[prev_k]
    rest, where, both = rest[has], where[has], both[has]
    src = good[where]
    if one and len(P) and rest.size:
        # columns no polynomial moves (pinned coordinates) keep the anchors' common value
        moving = np.any(P[:, 1:] != 0, axis=(0, 1))
        fixed = P[0, 0, ~moving]
        PL = np.ascontiguousarray(P[:, :, moving].transpose(1, 2, 0))  # :func:`_horner`'s table
    progress = Progress("sweep: values")  # (on a terminal, for a bulk over 2 s)
    for a in range(0, rest.size, CHUNK):
        i, s_ = rest[a : a + CHUNK], src[a : a + CHUNK]
        at = slice(i[0], i[-1] + 1) if i[-1] - i[0] + 1 == i.size else i  # i, as a slice when it is a run
        # (np.take gathers rows of a few values ~4x faster than indexing does)
        du = U[at] - np.take(U, s_, axis=0)
        if one:
            k, b = where[a : a + CHUNK], both[a : a + CHUNK]
            qp = np.empty((i.size, n))
            if b.any():
                kb = k[b]
                h = U[good[kb + 1], 0] - U[good[kb], 0]
                qp[:, ~moving] = fixed
                qp[slice(None) if b.all() else np.flatnonzero(b)[:, None], moving] = _horner(PL, kb, du[b, 0] / h)
            if not b.all():
                k, s1, d1 = k[~b], s_[~b], du[~b]
                qp[~b] = q[s1] + QU[k] * d1 + 0.5 * QUU[k] * d1**2
        else:
            qp, _ = br.predict(q[s_], U[s_], du)
        r = final_step(br, qp, U[at], Ud[at], Udd[at])
        ok = br.accept(r["q"], qp, lambda k: q[s_[k]], r["conv"], r["signs"], np.take(signs, s_, axis=0), r["sing"],
                       r["off"])
        if ok.all():
            ok, put = slice(None), at
        else:
            q_pred.update(zip(i[~ok].tolist(), qp[~ok]))
            put = i[ok]
        out.put(put, r, ok)
        q[put], solved[put], signs[put], done[put] = r["q"][ok], True, r["signs"][ok], True
        progress(min(a + CHUNK, rest.size), rest.size)


def solve_wave(br, state, U, idx, coef=None):
    """Anchors ``idx`` solved in one batch from ``state`` (q, u, signs), each from the Taylor
    predictor at the state, then checked as the sequential walk checks a step: against the
    predictor from the anchor before it, with the same modes. Returns (a, poses, kin) for the
    accepted prefix idx[:a]: a batch of M costs about one sequential step. One input: ``coef``
    are the state's kinematic coefficients (q_u, q_uu) when known, and ``kin`` (q_u, q_uu,
    singularity) those of the accepted anchors (the next wave's and the bulk's); else None."""
    if idx.size == 0:
        return 0, None, None
    q0, u0, s0 = state
    M, f = idx.size, U.shape[1]
    Ut = U[idx]
    with np.errstate(all="ignore"):  # a singular state reads non-finite rates: rejected below
        if f == 1:
            qu, quu = br.state(q0[None], u0[None], np.ones((1, 1)))[:2] if coef is None else coef
            du = Ut - u0
            q_pred = q0 + qu * du + 0.5 * quu * du**2
            qn, conv, _, _ = br.solve(q_pred, Ut)
            # one factorisation at the solutions gives their modes and kinematic coefficients:
            # the walk's predictor from each to the next
            QU, QUU, sn, sg = br.state(qn, Ut, np.ones((M, 1)))
            h = Ut[1:] - Ut[:-1]
            q_step = np.vstack((q_pred[:1], qn[:-1] + QU[:-1] * h + 0.5 * QUU[:-1] * h**2))
        else:
            q_pred, _ = br.predict(np.repeat(q0[None], M, 0), np.repeat(u0[None], M, 0), Ut - u0)
            qn, conv, _, _ = br.solve(q_pred, Ut)
            qd, qdd, sn, sg = br.state(qn, Ut, np.vstack((Ut[1:] - Ut[:-1], np.zeros((1, f)))))
            q_step = np.vstack((q_pred[:1], (qn + qd + 0.5 * qdd)[:-1]))
    q_from = np.vstack((q0[None], qn[:-1]))
    ok = br.accept(qn, q_step, lambda k: q_from[k], conv, sn, s0[None], sg)
    a = M if ok.all() else int(np.argmin(ok))
    return a, qn[:a], ((QU[:a], QUU[:a], sg[:a]) if f == 1 else None)


class Kin:
    """The kinematic coefficients q_u, q_uu (and the singularity measure) of solved anchors of
    a one-input sweep, kept where they were computed (the waves' acceptance tests, the finer
    pass) so that each anchor's are computed once."""

    def __init__(self):
        self.idx, self.parts = [], []

    def add(self, idx, QU, QUU, sg):
        self.idx.append(idx)
        self.parts.append((QU, QUU, sg))

    def at(self, br, q, U, good):
        """(QU, QUU, sg) at the anchors ``good`` (sorted): kept, or computed now (and kept)."""
        n = q.shape[1]
        QU, QUU, sg = np.empty((good.size, n)), np.empty((good.size, n)), np.empty(good.size)
        have = np.zeros(good.size, bool)
        if self.idx:
            idx = np.concatenate(self.idx)
            pos = np.minimum(np.searchsorted(good, idx), good.size - 1)
            hit = good[pos] == idx
            for out, part in zip((QU, QUU, sg), zip(*self.parts)):
                out[pos[hit]] = np.concatenate(part)[hit]
            have[pos[hit]] = True
        miss = np.flatnonzero(~have)
        for a in range(0, miss.size, CHUNK):
            m = miss[a : a + CHUNK]
            QU[m], QUU[m], _, sg[m] = br.state(q[good[m]], U[good[m]], np.ones((m.size, 1)))
        if miss.size:
            self.add(good[miss], QU[miss], QUU[miss], sg[miss])
        return QU, QUU, sg


def quintic(Q, D, DD, h):
    """Coefficients (K - 1, 6, n) of t^0 .. t^5 of the quintic Hermite interpolants between
    consecutive poses Q (K, n), with their first and second derivatives D and DD in the input
    and h (K - 1,) the input steps (t = (u - u_k) / h in [0, 1]): its error is O(h^6) where the
    one-sided Taylor predictor's is O(h^3), so one Newton step lands at rounding level. Both
    engines evaluate them by Horner's rule (:func:`_horner`), from the table, without gathering
    the two anchors' rows per value.

    >>> x = np.array([0.0, 0.3])[:, None]
    >>> P = quintic(np.sin(x), np.cos(x), -np.sin(x), np.array([0.3]))
    >>> PL = np.ascontiguousarray(P.transpose(1, 2, 0))
    >>> bool(abs(_horner(PL, np.array([0]), np.array([0.5]))[0, 0] - np.sin(0.15)) < 1e-8)  # h^6 sin^(6) / 6! ~ 1e-9
    True
    """
    hh = h[:, None]
    q0, dq = Q[:-1], Q[1:] - Q[:-1]
    D0, D1, E0, E1 = hh * D[:-1], hh * D[1:], hh**2 * DD[:-1], hh**2 * DD[1:]
    return np.stack((q0, D0, 0.5 * E0, 10 * dq - 6 * D0 - 4 * D1 - 1.5 * E0 + 0.5 * E1,
                     -15 * dq + 8 * D0 + 7 * D1 + 1.5 * E0 - E1, 6 * dq - 3 * D0 - 3 * D1 - 0.5 * E0 + 0.5 * E1), axis=1)


def _horner(PL, k, t):
    """(M, n) the polynomials of intervals k (M,, non-decreasing) of :func:`quintic`'s
    table, transposed to PL (6, n, K - 1), at t (M,), highest power first (the compiled
    engine's loop evaluates them in the same order). One coefficient at a time, poses last,
    each interval's repeated over its run of values (a repeat costs ~1/3 of a gather; gathering
    whole (M, 6, n) rows and broadcasting t over rows of n cost ~4x more than gathers)."""
    runs = np.bincount(k - k[0])
    at = slice(k[0], k[0] + runs.size)
    q = np.repeat(PL[5][:, at], runs, axis=1)
    for j in range(4, -1, -1):
        q *= t
        q += np.repeat(PL[j][:, at], runs, axis=1)
    return q.T


def stations(steps):
    """The stations of K intervals each cut into ``steps`` (K,) equal parts (at least one):
    (gap, frac, end), per station its interval and its fraction along it (1 / parts ... 1), and
    per interval the index of its last station (its end).

    >>> gap, frac, end = stations(np.array([2.0, 1.0]))
    >>> gap.tolist(), frac.tolist(), end.tolist()
    ([0, 0, 1], [0.5, 1.0, 1.0], [1, 2])
    """
    parts = np.maximum(1, steps).astype(int)
    gap, end = np.repeat(np.arange(parts.size), parts), np.cumsum(parts) - 1
    return gap, (np.arange(gap.size) - (end - parts)[gap]) / parts[gap], end


def solve_stations(br, state, U, idx, max_step, coef=None):
    """Anchors ``idx`` (consecutive, each within half a turn of the one before, the first of
    them beyond a wave's reach of ``state``) reached through stations at most ``max_step``
    apart (scaled) between them, solved in waves from ``state`` as the walk solves its own
    steps: the stations of many gaps in a batch, where walking to each anchor costs a batch a
    gap. Returns (b, poses, kin, last): the anchors idx[:b] reached, their poses and (one
    input) kinematic coefficients (as :func:`solve_wave`'s), and ``last`` the last station
    solved ((q, u), with its coefficients), None if none was. Where a wave stops (a limit,
    a singular position, another branch near), the walk goes on from ``last``."""
    if idx.size == 0:
        return 0, None, None, None
    P = np.vstack((state[1][None], U[idx]))
    d = P[1:] - P[:-1]
    gap, frac, real = stations(np.ceil(scaled_norm(br.m, d) / max_step))
    S = P[gap] + d[gap] * frac[:, None]
    S[real] = U[idx]  # (each value as given)
    Q, K = [], []
    at, wave = 0, WAVE
    while at < S.shape[0]:
        run = np.arange(at, min(at + wave, S.shape[0]))
        a, qa, ka = solve_wave(br, state, S, run, coef)
        if a:
            Q.append(qa)
            K.append(ka)
            state, at = (qa[-1], S[at + a - 1], state[2]), at + a
            coef = None if ka is None else (ka[0][-1], ka[1][-1])
        if a < run.size:
            break
        wave = min(2 * wave, MAX_WAVE)
    if not Q:
        return 0, None, None, None
    b = int(np.searchsorted(real, at))  # anchors whose station was reached
    Q = np.concatenate(Q)
    kin = None if K[0] is None else tuple(np.concatenate(part)[real[:b]] for part in zip(*K))
    return b, Q[real[:b]], kin, (state[0], state[1], coef)
