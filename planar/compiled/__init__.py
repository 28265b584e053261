"""The compiled engine (``engine="numba"``, the ``fast`` extra): a sweep's per-value work in one
loop of machine code, compiled once per installation.

The numpy engine evaluates, factors and solves a whole batch of configurations per numpy call;
its floor is the calls' passes over memory. Here the same plan (the block-triangular form of
:mod:`planar.blocks`, with the same scaling, elimination programs and singularity measure)
runs on groups of up to 32 configurations, the lanes: every work array has a last axis over
the group, so each table entry is read once per group and the innermost loops run over the
lanes (a group takes a further Newton step while any of its values does; a value that has
stopped keeps its numbers). The loop is ordinary source, generic over the plan:
:func:`tables` flattens a plan into arrays (each joint's type code, parameters, bodies and
where its Jacobian entries go; each block's size, couplings and elimination program), and the
loop reads them. Each joint type's scalar kernel comes from its class (``scalar_kernels``, see
:mod:`planar.joints.scalar`); the loop picks it by the joint's type code, its index in
:func:`kinds`, so the solver still never asks a joint's type (a kernel runs lane by lane).
The blocks' Schur complements are factored by :mod:`planar.lu`'s LU, lane by lane.

Four entries: :func:`final` (one Newton step from given poses, with modes and rates: the
anchors' Newton iterations and kinematic coefficients), :func:`fill` (the bulk of a sweep:
each value's Hermite guess, up to STEPS Newton steps, the acceptance test, status and rates,
written in place into the sweep's arrays), :meth:`Compiled.direct` (poses on
demand: each value from the pose known nearest it, the whole direct path of
:mod:`planar.tracking`) and :func:`walk`
(designs of one structure swept together: each design's whole walk, a design a lane). All
call the one loop (chunks of values on numba's number of threads, Python's: the loop releases
the GIL; a chunk or less on the calling thread), each thread with work buffers kept for the
plan.

numba caches the machine code on disk (``cache=True``: in ``__pycache__`` beside
:mod:`planar.compiled.engine`, or where ``NUMBA_CACHE_DIR`` says, or numba's user cache
directory when the installed package is not writable): the first sweep of an installation
compiles (saying so on stderr), every later one, of any mechanism, loads it. numba keys the
cache on the engine's file; a stamp of the kernels' source beside it drops it when a kernel
changes.

Results agree with the numpy engine to rounding (the same operations per step; but for a bulk
value's cos and sin, taken from its anchor's by angle addition, reciprocals where the numpy
engine divides, the singularity measure from the blocks' squared normalised dets, one square
root per value, and products and sums fused into multiply-adds where the compiler finds them;
the numpy engine takes a value's further Newton steps in its general solver; the tests compare
the two on every joint type and on random linkages).
"""

import importlib.util
import threading
import weakref
from collections import namedtuple

import numpy as np

from planar.acceptance import ROUND
from planar.errors import InputError

_TABLES = weakref.WeakKeyDictionary()
CHUNK = 1024  # values per task of the loop's threads, at most
# values per task at least: a call of fewer than twice this many runs on the calling thread (a
# task of these takes ~50 us, several times what starting the threads costs)
MIN_CHUNK = 128
STEPS = 4  # Newton steps a batch value may take in the loop (while its last step is below engine.CLOSE)

Tables = namedtuple("Tables", [
    # joints: type code, number of rows, input column (-1: none), parameters and row constants
    # (per design: (D, joints, ...), D = 1 but for designs swept together), the plan's rows
    # they write, their bodies; the Jacobian entries read: joint j's are
    # jac_at[j]:jac_at[j + 1], each entry (row, column) of its block to Jv[jac_to]
    "code", "nr", "inp", "par", "jc", "jrows", "slots", "jac_at", "jac_r", "jac_c", "jac_to",
    # the plan's rows and their scales; its driver rows and their input columns; the columns
    # solved and their scales; the redundant rows and their scales
    "prow", "rs", "drv", "drv_inp", "pcols", "cs", "red", "red_scale",
    # blocks: per block its fields (the B_ columns below); flat: equations, columns and their
    # scales; upstream columns; coupling entries
    "blk", "eqs", "cols", "brs", "bcs", "up", "coup",
    # the elimination programs (planar.elimination.Program), flat: the variables' value slots
    # and scales; per form its constant and terms (form_at: where each form's terms start);
    # the Schur complement's rows and columns; per constant-column step its pivot row and
    # column, 1 / pivot and the ranges of its multipliers (row, multiplier) and its pivot row's
    # (column, form); per row of the det's norm its constants and squared variables
    # (unweighted and weighted); lam's variables
    "var", "vscale", "form0", "form_at", "term_v", "term_c", "srows", "scols",
    "st_p", "st_c", "st_inv", "mul_at", "mul_i", "mul_m", "us_at", "us_j", "us_f",
    "nc0", "nc1", "n0_at", "n0_v", "n1_at", "n1_v", "lam_v",
    # per block: det0, lam's constant part, and a block of constants' normalised det
    "det0", "lam_c", "det_c",
    # sizes: bodies, rows, coordinates, Jacobian values (the last a zero), the largest block,
    # the largest Schur complement, the most variables of a block, the most rows and bodies of a
    # joint; the inputs' column holding each value's design (-1: one design)
    "dims",
])
# the blk columns: size, offset into eqs/cols/brs/bcs and the norm's rows, upstream count and
# offset, offset of coup, variables' count and offset, forms' count and offset, Schur size and
# offset, steps' count and offset, lam's variables' count and offset, flags
(B_K, B_O, B_NW, B_UO, B_CO, B_NV, B_VO, B_NF, B_FO, B_R, B_RO, B_NS, B_SO, B_NL, B_LO, B_ANGLE, B_LENGTHS,
 B_WEIGHTED) = range(18)
D_BODIES, D_M, D_N, D_NNZ, D_KMAX, D_RMAX, D_NV, D_JROWS, D_JBODIES, D_DESIGN = range(10)


def check(plan):
    """Raise :class:`InputError` unless the compiled engine can run ``plan``."""
    if importlib.util.find_spec("numba") is None:
        raise InputError("engine='numba' needs numba: pip install 'planar-kinematics[fast]', or use engine='numpy'")
    missing = sorted({g.kind.__name__ for g in plan.system.groups if g.kind.scalar_kernels is None})
    if missing:
        raise InputError(f"engine='numba': joint type(s) {missing} have no scalar kernels (the class's "
                         f"scalar_kernels, planar/joints/scalar.py); use engine='numpy'")


def kinds():
    """The joint types the engine compiles, in the order of their type codes."""
    from planar.joints import JOINT_TYPES

    return tuple(cls for cls in JOINT_TYPES if cls.scalar_kernels is not None)


def final(model, plan, q, U, Ud, Udd, rates=True, steps=1, tol=0.0, step_tol=0.0):
    """One Newton step from guesses q (N, n) and, at the corrected poses, the rates with the
    factorisation at the guesses, as the numpy engine's ``planar.sweep.branch._step`` computes them: a
    dict of q, qd, qdd, the scaled residual at the guess ``res``, the scaled ``step`` and
    ``off`` (the same over its finite components: how far the pose moved), the blocks' det
    ``signs``, the largest scaled redundant row ``red``, the singularity measure ``sing``, the
    ``branch`` (the product of the signs) and ``iters``. With ``steps`` > 1, Newton: up to that
    many steps, each value until its residual is below ``tol`` and its step below ``step_tol``
    (or its pose is no longer finite), the dict's values those of its last step."""
    N = q.shape[0]
    C, engine = _compiled(model, plan)
    n, nb = C.T.dims[D_N], C.T.blk.shape[0]
    q = np.array(q, dtype=float, order="C")
    qd, qdd = (np.empty((N, n)), np.empty((N, n))) if rates else (np.empty((0, n)), np.empty((0, n)))
    res, step, off, red, sing, branch = (np.empty(N) for _ in range(6))
    signs, iters = np.empty((N, nb), np.int8), np.empty(N, np.int64)
    no_i, no_b, no_f = np.zeros(0, np.int64), np.zeros(0, bool), np.zeros(0)
    engine.loop(C, engine.chunk(N), np.arange(N), engine.FINAL, int(steps), no_b, no_i, np.zeros((0, 6, n)), no_f,
                np.zeros((0, nb), np.int8), float(tol), float(step_tol), 0.0, q, np.require(U, float, ("C", "W")),
                _rates_in(Ud), _rates_in(Udd), bool(rates), qd, qdd, res, signs, sing, branch, step, off, red, no_b,
                np.zeros(0, np.int8), iters, no_b, no_b)
    if not rates:  # as the numpy engine: one read-only NaN
        qd = qdd = np.broadcast_to(np.nan, q.shape)
    return dict(q=q, qd=qd, qdd=qdd, res=res, step=step, off=off, signs=signs, red=red, sing=sing, branch=branch,
                iters=iters)


def fill(model, plan, rows, adj, G, P, SA, tol, rates, sweep):
    """Values ``rows`` of a sweep solved in place from quintic Hermite guesses between the
    anchors around each, G[a] < row <= G[a + 1] (an anchor among them from the interval before
    it, the first from the one after it), where ``adj[a]`` says the two bound one stretch (G
    sorted; P the interpolants' coefficients of ``planar.sweep.anchors.quintic``, SA the anchors'
    modes), with ``planar.sweep``'s final step and acceptance test: where a value passes, its
    pose, rates, residual, modes, singularity, branch and status are written into the sweep's arrays
    (``sweep``: a dict of q, U, Ud, Udd, qd, qdd, res, signs, sing, branch, status, iters,
    solved, done). Returns (M,) True where it passed; the others are left unposed (NaN) for
    the general path, but for solved anchors among them, which keep their poses and modes."""
    C, engine = _compiled(model, plan)
    ok = np.empty(rows.size, bool)
    no = np.zeros(0)
    S = sweep
    engine.loop(C, engine.chunk(rows.size), np.ascontiguousarray(rows, np.int64), engine.BULK, STEPS,
                np.ascontiguousarray(adj, bool), np.ascontiguousarray(G, np.int64), np.ascontiguousarray(P, float), no,
                np.ascontiguousarray(SA, np.int8), float(tol), 0.0, 0.0, S["q"], S["U"], _rates_in(S["Ud"]),
                _rates_in(S["Udd"]), bool(rates), S["qd"], S["qdd"], S["res"], S["signs"], S["sing"], S["branch"], no,
                no, no, ok, S["status"], S["iters"], S["solved"], S["done"])
    return ok


def walk(model, plan, U, q0, tol, steps):
    """The walks of designs of one structure through their stations U (D, S, 2: each
    station's input, and the design's index in the plan's tables), each from its sketch q0[d]
    at station 0 (its input the sketch's), every later station from the cubic Taylor
    predictor of the one before, by Newton to ``tol`` (up to ``steps`` steps) and the final step
    of :func:`final`, with the sweep's acceptance test (:mod:`planar.acceptance`; the sketch's
    modes), every station SOLVED and clear of other solution curves, in one call of the loop:
    a design a lane. A dict: ``ok`` (D,) whether design d walked every station, and per
    station (D, S, ...) its pose ``q``, ``qu`` and ``quu`` (dq/du and d2q/du2), ``status``,
    ``res``, ``iters``, ``sing`` and ``branch`` (read only where ``ok``)."""
    C, engine = _compiled(model, plan)
    D, S = U.shape[:2]
    n, nb = C.T.dims[D_N], C.T.blk.shape[0]
    Q = np.empty((D, S, n))
    Q[:, 0] = q0
    qu, quu = np.empty((D * S, n)), np.empty((D * S, n))
    res, sing, branch = np.empty(D * S), np.empty(D * S), np.empty(D * S)
    status, iters = np.empty(D * S, np.int8), np.empty(D * S, np.int64)
    ok = np.zeros(D, bool)
    no_b, no_f = C.none[1], C.none[2]
    # (the designs' modes: written by each design's first station, read by the later ones)
    engine.loop(C, engine.chunk(D, engine.LANES), np.arange(D), engine.WALK, int(steps), no_b, np.arange(S),
                np.zeros((0, 6, n)), no_f, np.zeros((D, nb), np.int8), float(tol), ROUND, 0.0, Q.reshape(D * S, n),
                np.require(U, float, ("C", "W")).reshape(D * S, -1), C.one, C.zero, True, qu, quu, res,
                np.empty((D * S, nb), np.int8), sing, branch, no_f, no_f, no_f, ok, status, iters, no_b, no_b)
    shape = lambda a: a.reshape((D, S) + a.shape[1:])  # noqa: E731
    return dict(ok=ok, q=Q, qu=shape(qu), quu=shape(quu), status=shape(status), res=shape(res), iters=shape(iters),
                sing=shape(sing), branch=shape(branch))


def _rates_in(a):
    """Input rates (N, f) as the loop reads them, C-contiguous and writeable (numba compiles
    read-only arrays apart): their one row where they repeat one row (a rate given once:
    ``planar.Model.as_inputs``), which the loop reads for every value."""
    if a.ndim == 2 and a.shape[0] > 1 and a.strides[0] == 0:
        a = a[:1]
    return np.require(a, float, ("C", "W"))


class Compiled:
    """A plan as the loop takes it: its :class:`Tables` ``T``, the ``engine`` module that runs
    it, and the loop's work buffers, made once per thread and number of lanes and kept (a call
    reuses them as a call's groups of values do: each group writes what it reads)."""

    def __init__(self, T, engine):
        self.T, self.engine = T, engine
        self._work = {}
        self._known = None
        # a unit input rate, no input acceleration, and the loop's arrays a call does not use
        self.one, self.zero = np.ones((1, 1)), np.zeros((1, 1))
        self.none = (np.zeros(0, np.int64), np.zeros(0, bool), np.zeros(0))
        self.rows = np.arange(MIN_CHUNK)  # (the rows of a call on the calling thread)

    def direct(self, KU, HQ, signs, U, tol, reach, steps):
        """Values U (M, 1) of a one-input model, each from the Taylor predictor of the pose
        known at the input in KU (K,) nearest it (HQ (K, 3, n): each known pose q, dq/du,
        d2q/du2; ``signs`` (1, blocks): the branch's modes), by Newton to ``tol`` (up to
        ``steps`` steps) and the final step of :func:`final`, accepted by the sweep's test
        (:mod:`planar.acceptance`; the branch's modes; status SOLVED or NEAR_SINGULAR), in one
        call of the loop. A tuple of read-only arrays (rows (3, M, n): q, dq/du and d2q/du2;
        status, residual, iterations, singularity, branch), or None where a value is further
        than ``reach`` from every known input or not accepted (``planar.tracking.Direct`` then
        leaves them all to the sweep). Made for a tracker's moves: one value costs the loop's
        call and little more (U is taken as it is where it is a writable C-ordered float array)."""
        engine, M = self.engine, U.shape[0]
        rows, fl, ok = np.empty((3, M, self.T.dims[D_N])), np.empty((3, M)), np.empty(M, bool)
        status, iters = np.empty(M, np.int8), np.empty(M, np.int64)
        no_i, no_b, no_f = self.none
        if not (U.dtype == float and U.flags.c_contiguous and U.flags.writeable):
            U = np.require(U, float, ("C", "W"))
        args = (engine.KNOWN, int(steps), no_b, no_i, HQ, KU, signs, float(tol), ROUND, float(reach), rows[0], U,
                self.one, self.zero, True, rows[1], rows[2], fl[0], np.empty((M, self.T.blk.shape[0]), np.int8), fl[1],
                fl[2], no_f, no_f, no_f, ok, status, iters, no_b, no_b)
        if M <= MIN_CHUNK:  # (a few poses: the loop's machine code called as it was compiled, on this thread)
            self.known(args)(0, M, self.rows, *args, self.T, self.work(min(engine.LANES, M)))
        else:
            engine.loop(self, engine.chunk(M), np.arange(M), *args)
        if not (ok[0] if M == 1 else ok.all()):
            return None
        for a in (rows, fl, status, iters):  # (results: their views read only too)
            a.setflags(write=False)
        return rows, status, fl[0], iters, fl[1], fl[2]

    def known(self, args):
        """The loop's machine code for :meth:`direct`'s arguments ``args`` (those after rows, up
        to the tables), called without numba's dispatcher, which works out the types of every
        argument at every call; :meth:`direct` gives them the same types at every call (HQ and
        KU: ``planar.tracking.Poses``' arrays)."""
        if self._known is None:
            engine = self.engine
            full = (0, 0, self.rows) + args + (self.T, self.work(1))
            engine._values(0, 0, *full[2:])  # (compiled, or loaded from the cache, for these types)
            self._known = engine._values.overloads[tuple(engine._values.typeof_pyval(a) for a in full)].entry_point
        return self._known

    def work(self, L):
        key = (threading.get_ident(), L)
        if key not in self._work:
            if len(self._work) > 256:  # (threads come and go)
                self._work.clear()
            self._work[key] = self.engine._buffers(self.T, L)
        return self._work[key]


def plan_of(model, plan):
    """The plan as the loop takes it (:class:`Compiled`: :meth:`Compiled.direct` is the direct
    path's entry), its loop ready."""
    return _compiled(model, plan)[0]


def _compiled(model, plan):
    """The plan as the loop takes it (:class:`Compiled`) and the engine's module, its loop ready."""
    C = _TABLES.get(plan)
    if C is None:
        from planar.compiled import engine

        C = _TABLES[plan] = Compiled(tables(model, plan), engine)
    C.engine.ready()
    return C, C.engine


def tables(model, plan):
    """The plan flattened into the arrays the loop reads (:class:`Tables`)."""
    sysm = plan.system
    nnz = sysm.entries[0].size + 1
    B = plan.blocks
    read = set()  # the Jacobian entries factor and solve read (the others are constants of the programs)
    progs = [None] * len(B)
    for st in plan.stages:
        for g, b in enumerate(st.index):
            progs[b] = (st.program, g)
            read |= {int(v) for v in st.program.var[:, g]}
    for blk in B:
        read |= {int(e) for e in blk.coup}
    read.discard(nnz - 1)
    J = {k: [] for k in ("code", "nr", "inp", "par", "jc", "jrows", "slots", "jac")}
    # designs of one structure (planar.system.System.over_designs): each joint's parameters and
    # row constants per design, read by the design index in the inputs' last column
    D = max([next(iter(g.P.values())).shape[0] for g in sysm.groups if g.per_design and g.P] + [1])
    for g, (start, _, (n_rows, _, K)) in zip(sysm.groups, sysm.block_spans):
        def per_design(a):  # (D, K, w): the joints' numbers, per design
            a = np.asarray(a, float).reshape(D if g.per_design else 1, K, -1)
            return np.broadcast_to(a, (D,) + a.shape[1:])

        flat = [per_design(g.P[key]) for key in g.kind.scalar_kernels[0]]
        flat = np.concatenate(flat, axis=2) if flat else np.zeros((D, K, 0))
        c = per_design(g.P["c"])
        nc = 3 * g.bodies.shape[1]
        for k in range(K):
            J["code"].append(kinds().index(g.kind))
            J["nr"].append(n_rows)
            J["inp"].append(int(g.inputs[k]))
            J["par"].append(flat[:, k])
            J["jc"].append(c[:, k])
            J["jrows"].append([int(r) for r in g.rows[k]])
            J["slots"].append([int(b) for b in g.bodies[k]])
            J["jac"].append([(r, col, e) for r in range(n_rows) for col in range(nc)
                             if (e := start + k + (r * nc + col) * K) in read])
    nj = len(J["code"])
    par = np.zeros((D, nj, max([p.shape[1] for p in J["par"]] + [1])))
    jr, jb = max(J["nr"] + [1]), max([len(b) for b in J["slots"]] + [1])
    jc, jrows, slots = np.zeros((D, nj, jr)), np.zeros((nj, jr), np.int64), np.zeros((nj, jb), np.int64)
    for j in range(nj):
        par[:, j, : J["par"][j].shape[1]], jc[:, j, : J["jc"][j].shape[1]] = J["par"][j], J["jc"][j]
        jrows[j, : len(J["jrows"][j])], slots[j, : len(J["slots"][j])] = J["jrows"][j], J["slots"][j]
    jac = [e for entries in J["jac"] for e in entries]
    red = np.asarray(model.redundant_rows, int)
    L = {k: [] for k in Tables._fields}
    blk = np.zeros((len(B), 18), np.int64)
    det0, lam_c, det_c = np.zeros(len(B)), np.zeros(len(B)), np.zeros(len(B))
    for b, (block, (P, g)) in enumerate(zip(B, progs)):
        nv, r = P.var.shape[0], len(P.rows)
        blk[b, [B_K, B_O, B_NW, B_UO, B_CO]] = block.size, len(L["eqs"]), block.up.size, len(L["up"]), len(L["coup"])
        blk[b, [B_NV, B_VO, B_NF, B_FO, B_R, B_RO]] = nv, len(L["var"]), P.form0.size, len(L["form0"]), r, len(L["srows"])
        L["eqs"] += list(block.eqs)
        L["cols"] += list(block.cols)
        L["brs"] += list(block.rscale)
        L["bcs"] += list(block.cscale)
        L["up"] += list(block.up)
        L["coup"] += list(block.coup)
        L["var"] += list(P.var[:, g])
        L["vscale"] += list(P.vscale[:, g, 0])
        for f in range(P.form0.size):
            L["form_at"].append(len(L["term_v"]))
            L["form0"].append(P.form0[f])
            ks = np.flatnonzero(P.forms[f])
            L["term_v"] += list(ks)
            L["term_c"] += list(P.forms[f, ks])
        L["srows"] += list(P.rows)
        L["scols"] += list(P.cols)
        blk[b, [B_NS, B_SO]] = len(P.steps), len(L["st_p"])
        for p, c, d, mults, us in P.steps:
            L["st_p"].append(p)
            L["st_c"].append(c)
            L["st_inv"].append(1.0 / d)
            L["mul_at"].append(len(L["mul_i"]))
            L["mul_i"] += [i for i, _ in mults]
            L["mul_m"] += [m for _, m in mults]
            L["us_at"].append(len(L["us_j"]))
            L["us_j"] += [j for j, _ in us]
            L["us_f"] += [f for _, f in us]
        lam_cb, lam_vb, any_angle, lengths = P.lam
        for i in range(P.k):
            L["nc0"].append(P.c0[i])
            L["nc1"].append(P.c1[i])
            L["n0_at"].append(len(L["n0_v"]))
            L["n0_v"] += list(np.flatnonzero(P.M0[i]))
            L["n1_at"].append(len(L["n1_v"]))
            L["n1_v"] += list(np.flatnonzero(P.M1[i]))
        blk[b, [B_NL, B_LO, B_ANGLE, B_LENGTHS, B_WEIGHTED]] = (len(lam_vb), len(L["lam_v"]), any_angle, lengths,
                                                                 P.weighted)
        L["lam_v"] += list(lam_vb)
        det0[b], lam_c[b] = P.det0, lam_cb
        if nv == 0:  # a block of constants: its normalised det once (as the numpy engine factors it)
            det_c[b] = P.constant[3][g, 0]
    # the range ends, so that item i's run is at[i]:at[i + 1]
    for at, items in (("form_at", "term_v"), ("mul_at", "mul_i"), ("us_at", "us_j"), ("n0_at", "n0_v"),
                      ("n1_at", "n1_v")):
        L[at].append(len(L[items]))
    ints = ("eqs", "cols", "up", "coup", "var", "form_at", "term_v", "srows", "scols", "st_p", "st_c", "mul_at",
            "mul_i", "us_at", "us_j", "us_f", "n0_at", "n0_v", "n1_at", "n1_v", "lam_v")
    flat = {k: np.array(L[k], np.int64 if k in ints else float) for k in ints + (
        "brs", "bcs", "vscale", "form0", "term_c", "st_inv", "mul_m", "nc0", "nc1")}
    kmax = max([b.size for b in B] + [1])
    rmax = max([len(P.rows) for P, _ in progs] + [1])
    i64 = (lambda a: np.array(a, np.int64))
    return Tables(
        i64(J["code"]), i64(J["nr"]), i64(J["inp"]), par, jc, jrows, slots,
        i64(np.cumsum([0] + [len(e) for e in J["jac"]])), i64([r for r, _, _ in jac]), i64([c for _, c, _ in jac]),
        i64([e for _, _, e in jac]),
        i64(plan.rows), model.row_scale[plan.rows].astype(float), i64(plan.drivers), i64(plan.driver_inputs),
        i64(plan.cols), model.col_scale[plan.cols].astype(float), i64(red), model.row_scale[red].astype(float),
        blk, **flat, det0=det0, lam_c=lam_c, det_c=det_c,
        dims=i64([sysm.n_bodies, sysm.m, model.n, nnz, kmax, rmax, max([P.var.shape[0] for P, _ in progs] + [1]), jr,
                  jb, model.u0.size if any(g.per_design for g in sysm.groups) else -1]))


__all__ = ["check", "final", "fill", "plan_of", "tables", "Tables", "walk"]
