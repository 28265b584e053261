"""The designs of one structure swept together on their template's plan: the walk over the
anchors and the values' final steps, every design a row of one batch."""

from dataclasses import dataclass

import numpy as np

from planar.blocks import plan as block_plan
from planar.events import NEAR_CURVE
from planar.results import Status
from planar.sweep import CHUNK, Branch, final_step, output_columns, sweep_anchors


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


def sweep_batch(t, out, Ud, Udd, tol, max_step, outputs):
    """Sweep the designs of tables ``t`` (:class:`planar.designs.tables.Tables`) together on
    their template's plan, writing their rows ``t.index`` of ``out``. Returns (ok, fits), each
    (D,): ``ok`` for the designs every value of which was certified regular, ``fits`` for
    those the plan holds (a design with a non-zero where the template has a structural zero,
    as a slider along x, needs another)."""
    ref, rows = t.model, t.index
    D = len(rows)
    U = out.U[rows]
    N, n = U.shape[1], ref.n
    q, u = t.q0.copy(), t.u0.copy()
    every = np.arange(D)
    ids = np.arange(D, dtype=float)[:, None]

    def at(u, d):  # inputs with the design index of each configuration in a last column
        return np.concatenate([u, ids[d]], axis=1)

    p, fits = block_plan(ref, output_columns(ref, outputs)).over_designs(t.system, q, at(u, every), ref.col_scale)
    br = Branch(ref, p, tol)
    with np.errstate(all="ignore"):
        ref_signs, sing = br.modes(q, at(u, every))
    ok = fits & (sing >= NEAR_CURVE)
    scale = np.where(ref.input_lengths, 1.0 / t.L[:, None], 1.0)

    # 1. the walk over the anchors of every design, all designs a step at a time
    found = {}  # the anchors depend on the values and the input scales only: once per pair
    for d in range(D):
        key = (U[d].tobytes(), scale[d].tobytes())
        if key not in found:
            found[key] = sweep_anchors(_Scales(ref.input_lengths, t.L[d]), U[d], max_step)
    anchors = np.unique(np.concatenate(list(found.values())))
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
            q_pred, _ = br.predict(q[act], at(u[act], act), nxt - u[act])
            qn, conv, _, _ = br.solve(q_pred, at(nxt, act))
            sn, sg = br.modes(qn, at(nxt, act))
            start = q[act]
            good = br.accept(qn, q_pred, lambda r: start[r], conv, sn, ref_signs[act], sg) & (sg >= NEAR_CURVE)
            q[act[good]], u[act[good]] = qn[good], nxt[good]
            ok[act[~good]] = False
            act = act[good]
        Qa[k] = q

    # 2. every value from the anchor before it (a Taylor predictor), its final Newton step,
    # certificate and rates in one pass over (design, value) rows
    k_of = np.searchsorted(anchors, np.arange(N), side="right") - 1
    flat = (act[:, None] * N + np.arange(N)[None]).ravel()
    for lo in range(0, flat.size, CHUNK):
        r = flat[lo : lo + CHUNK]
        d, i = r // N, r % N
        qa, ua = Qa[k_of[i], d], U[d, anchors[k_of[i]]]
        du = U[d, i] - ua
        q_pred = qa.copy()  # (an anchor's value is its pose)
        move = np.flatnonzero(np.any(du != 0.0, axis=1))
        if move.size:
            q_pred[move] = br.predict(qa[move], at(ua[move], d[move]), du[move])[0]
        f = final_step(br, q_pred, at(U[d, i], d), Ud[i], Udd[i])
        good = br.accept(f["q"], q_pred, lambda s: qa[s], f["conv"], f["signs"], ref_signs[d], f["sing"], off=f["off"])
        good &= (f["status"] == Status.SOLVED) & (f["sing"] >= NEAR_CURVE)
        ok[np.unique(d[~good])] = False
        g = rows[d]
        out.q[g, i], out.qd[g, i], out.qdd[g, i] = f["q"], f["qd"], f["qdd"]
        out.residual[g, i], out.singularity[g, i], out.branch[g, i] = f["res"], f["sing"], f["branch"]
        out.iterations[g, i], out.status[g, i] = f["iters"], f["status"]
    if p.cols.size < n:  # coordinates the outputs do not need: not solved
        drop = np.setdiff1d(np.arange(n), p.cols)
        for a in (out.q, out.qd, out.qdd):
            a[np.ix_(rows[ok], np.arange(N), drop)] = np.nan
    return ok, fits


@dataclass(frozen=True)
class _Scales:
    """What the anchors of a design's walk depend on (as :func:`planar.sweep.sweep_anchors` reads a model)."""

    input_lengths: np.ndarray
    L: float
