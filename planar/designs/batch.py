"""The designs of one structure swept together on their template's plan: the walk over the
anchors and the values' final steps, every design a row of one batch."""

from dataclasses import dataclass

import numpy as np

from planar.blocks import plan as block_plan
from planar.events import NEAR_CURVE
from planar.results import Status
from planar.solver import PREDICTED
from planar.sweep import CHUNK, Branch, final_step, output_columns, sweep_anchors
from planar.sweep.anchors import stations

WALK_BYTES = 1 << 28  # the compiled walk's stations of a call (its designs' poses and rates), at most


class Results:
    """The (D, N, ...) arrays of a study, NaN and NOT_ASSEMBLABLE until a design is put."""

    def __init__(self, D, N, n, f):
        self.U = np.full((D, N, f), np.nan)
        self.q, self.qd, self.qdd = (np.full((D, N, n), np.nan) for _ in range(3))
        self.residual, self.singularity, self.branch, self.gap = (np.full((D, N), np.nan) for _ in range(4))
        self.iterations = np.zeros((D, N), int)
        self.status = np.full((D, N), Status.NOT_ASSEMBLABLE, np.int8)

    def put(self, d, s):
        """Rows d from a :class:`planar.Sweep` or a :class:`Results` of those rows."""
        for k in ("q", "qd", "qdd", "residual", "singularity", "branch", "gap", "iterations", "status"):
            getattr(self, k)[d] = getattr(s, k)
        if isinstance(s, Results):
            self.U[d] = s.U

    def arrays(self):
        return {k: v for k, v in vars(self).items() if k != "U"} | {"inputs": self.U}


def sweep_batch(t, out, Ud, Udd, tol, max_step, outputs, engine="numpy"):
    """Sweep the designs of tables ``t`` (:class:`planar.designs.tables.Tables`) together on
    their template's plan, writing their rows ``t.index`` of ``out`` (``engine``: as a sweep's,
    the compiled one reading each configuration's design from its inputs' last column).
    Returns (ok, fits), each (D,): ``ok`` for the designs every value of which was certified
    regular, ``fits`` for those the plan holds (a design with a non-zero where the template
    has a structural zero, as a slider along x, needs another)."""
    ref, rows = t.model, t.index
    D = len(rows)
    U = out.U[rows]
    N, n, f = U.shape[1], ref.n, U.shape[2]
    q, u = t.q0.copy(), t.u0.copy()
    every = np.arange(D)
    ids = np.arange(D, dtype=float)[:, None]

    def at(u, d):  # inputs with the design index of each configuration in a last column
        return np.concatenate([u, ids[d]], axis=1)

    p, fits = block_plan(ref, output_columns(ref, outputs)).over_designs(t.system, q, at(u, every), ref.col_scale)
    if engine == "numba" and f == 1:
        ok = _walk(t, p, out, U, Ud, Udd, tol, max_step, fits)
        _drop(out, rows[ok], p, n, N)
        return ok, fits
    br = Branch(ref, p, tol, engine=engine)
    with np.errstate(all="ignore"):
        ref_signs, sing = br.modes(q, at(u, every))
    ok = fits & (sing >= NEAR_CURVE)
    scale = np.where(ref.input_lengths, 1.0 / t.L[:, None], 1.0)

    # 1. the walk over the anchors of every design, all designs a step at a time: each step
    # the predictor from the pose before, then Newton and the final step in one call (the pose,
    # its certificate, modes and rates); one input: the rates at a unit input rate, the
    # kinematic coefficients of the next step's predictor, and the anchor's value's rates follow
    # from them linearly
    found = {}  # the anchors depend on the values and the input scales only: once per pair
    for d in range(D):
        key = (U[d].tobytes(), scale[d].tobytes())
        if key not in found:
            found[key] = sweep_anchors(_Scales(ref.input_lengths, t.L[d]), U[d], max_step)
    anchors = np.unique(np.concatenate(list(found.values())))
    one = f == 1
    if one:
        # q_u, q_uu and q_uuu: the last from the change of q_uu over the step before (none at the
        # first): the predictor's error then falls from ~h^3 to ~h^4, and Newton takes a step less
        qu, quu = br.state(q, at(u, every), np.ones((D, 1)))[:2]
        quuu = np.zeros_like(qu)
        Ka = np.empty((anchors.size, 3, D, n))
    Qa = np.empty((anchors.size, D, n))
    act = np.flatnonzero(ok)
    for k, a in enumerate(anchors):
        target = U[:, a]
        span = np.max(np.abs(target - u)[act] * scale[act], initial=0.0)
        parts = max(1, int(np.ceil(span / max_step)))
        for j in range(parts):
            if not act.size:
                break
            nxt = u[act] + (target[act] - u[act]) / (parts - j)
            du = nxt - u[act]
            if one:
                q_pred = q[act] + du * (qu[act] + du * (0.5 * quu[act] + du * quuu[act] / 6))
                rin = np.ones((act.size, 1)), np.zeros((act.size, 1))
            else:
                q_pred = br.predict(q[act], at(u[act], act), du)[0]
                rin = Ud[a][None].repeat(act.size, 0), Udd[a][None].repeat(act.size, 0)
            r = final_step(br, q_pred, at(nxt, act), *rin, steps=PREDICTED)
            start = q[act]
            good = br.accept(r["q"], q_pred, lambda s: start[s], r["conv"], r["signs"], ref_signs[act], r["sing"])
            good &= (r["status"] == Status.SOLVED) & (r["sing"] >= NEAR_CURVE)
            g = act[good]
            q[g], u[g] = r["q"][good], nxt[good]
            if one:
                with np.errstate(all="ignore"):
                    quuu[g] = np.where(du[good] != 0, (r["qdd"][good] - quu[g]) / du[good], 0.0)
                qu[g], quu[g] = r["qd"][good], r["qdd"][good]
            ok[act[~good]] = False
            act = g
        Qa[k] = q
        if one:
            Ka[k] = qu, quu, quuu
        if act.size:  # the anchor's value, of the designs still walking: its last step's
            if not good.all():
                r = {key: v[good] for key, v in r.items()}
            if one:
                r["qd"], r["qdd"] = r["qd"] * Ud[a], r["qdd"] * Ud[a] ** 2 + r["qd"] * Udd[a]
            _put(out, _rows(rows, act), a, r)

    # 2. every other value from the anchor before it (a Taylor predictor), Newton, its final
    # step, certificate and rates in one pass over (design, value) rows
    k_of = np.searchsorted(anchors, np.arange(N), side="right") - 1
    rest = np.setdiff1d(np.arange(N), anchors)
    flat = (act[:, None] * N + rest[None]).ravel()
    for lo in range(0, flat.size, CHUNK):
        d, i = np.divmod(flat[lo : lo + CHUNK], N)
        qa, ua = Qa[k_of[i], d], U[d, anchors[k_of[i]]]
        du = U[d, i] - ua
        if one:
            K = Ka[k_of[i], :, d]
            q_pred = qa + du * (K[:, 0] + du * (0.5 * K[:, 1] + du * K[:, 2] / 6))
        else:
            q_pred = br.predict(qa, at(ua, d), du)[0]
        r = final_step(br, q_pred, at(U[d, i], d), Ud[i], Udd[i], steps=PREDICTED)
        good = br.accept(r["q"], q_pred, lambda s: qa[s], r["conv"], r["signs"], ref_signs[d], r["sing"],
                         off=r["off"])
        good &= (r["status"] == Status.SOLVED) & (r["sing"] >= NEAR_CURVE)
        ok[np.unique(d[~good])] = False
        _put(out, rows[d], i, r)
    _drop(out, rows[ok], p, n, N)
    return ok, fits


def _walk(t, p, out, U, Ud, Udd, tol, max_step, fits):
    """The walks of one-input designs in the compiled engine (:func:`planar.compiled.walk`), a
    design a lane: every value a station, from the sketch's input on, with stations between
    values further apart than ``max_step`` (scaled) for any design; as many designs a call as
    WALK_BYTES of stations hold. Writes the rows of the designs that walked every value and
    returns (D,) True for those."""
    from planar import compiled

    ref, rows = t.model, t.index
    D, N = U.shape[:2]
    V = np.concatenate([t.u0[:, :1], U[:, :, 0]], axis=1)  # the sketch's input, then the values
    scale = 1.0 / t.L if ref.input_lengths[0] else np.ones(D)
    span = np.max(np.abs(np.diff(V, axis=1))[fits] * scale[fits, None], axis=0, initial=0.0)
    gap, frac, at = stations(np.ceil(span / max_step))  # the steps to each value
    at = at + 1  # (each value's station, after the sketch's)
    plain = gap.size == N  # (no station between values: a value's is a slice)
    ok = np.zeros(D, bool)
    todo = np.flatnonzero(fits)
    per = max(1, WALK_BYTES // ((1 + gap.size) * 8 * (3 * ref.n + 8)))
    for lo in range(0, todo.size, per):
        d = todo[lo : lo + per]
        S = np.empty((d.size, 1 + gap.size, 2))  # each design's stations
        S[:, 0, 0], S[:, :, 1] = V[d, 0], d[:, None]
        S[:, 1:, 0] = V[d][:, gap] + (V[d][:, gap + 1] - V[d][:, gap]) * frac
        S[:, at, 0] = V[d, 1:]  # (each value as given)
        w = compiled.walk(ref, p, S, t.q0[d], tol, PREDICTED)
        ok[d] = w["ok"]
        k = np.flatnonzero(w["ok"])
        every = k.size == d.size and np.array_equal(d, np.arange(D))  # (most studies: views)

        def pick(a):
            return a[:, 1:] if every and plain else (a[:, at] if every else a[k][:, at])

        g = rows if every else rows[d[k]]
        qu, quu = pick(w["qu"]), pick(w["quu"])
        out.q[g], out.residual[g], out.singularity[g] = pick(w["q"]), pick(w["res"]), pick(w["sing"])
        out.branch[g], out.iterations[g], out.status[g] = pick(w["branch"]), pick(w["iters"]), pick(w["status"])
        if np.all(Ud == 1.0) and not np.any(Udd):  # (a unit input rate: the rates are the coefficients)
            out.qd[g], out.qdd[g] = qu, quu
        else:
            out.qd[g], out.qdd[g] = qu * Ud, quu * Ud**2 + qu * Udd
    return ok


def _drop(out, g, p, n, N):
    """NaN in the coordinates of designs (rows) g the outputs do not need (not solved)."""
    if p.cols.size < n:
        drop = np.setdiff1d(np.arange(n), p.cols)
        for a in (out.q, out.qd, out.qdd):
            a[np.ix_(g, np.arange(N), drop)] = np.nan


def _rows(rows, act):
    """rows[act], a slice where that is all of them in order (a view, not a gather)."""
    if act.size == rows.size and np.array_equal(rows, np.arange(rows[0], rows[0] + rows.size)):
        return slice(rows[0], rows[0] + rows.size)
    return rows[act]


def _put(out, g, i, r):
    """Values i of designs (rows) g of ``out`` from a final step's results r."""
    out.q[g, i], out.qd[g, i], out.qdd[g, i] = r["q"], r["qd"], r["qdd"]
    out.residual[g, i], out.singularity[g, i], out.branch[g, i] = r["res"], r["sing"], r["branch"]
    out.iterations[g, i], out.status[g, i] = r["iters"], r["status"]


@dataclass(frozen=True)
class _Scales:
    """What the anchors of a design's walk depend on (as :func:`planar.sweep.sweep_anchors` reads a model)."""

    input_lengths: np.ndarray
    L: float
