"""The compiled path (``engine="numba"``, the ``fast`` extra): a sweep's per-value work in one
loop of machine code generated for the plan.

The numpy path evaluates, factors and solves a whole batch of configurations per numpy call;
its floor is the calls' passes over memory. Here the same plan (the block-triangular form of
:mod:`planar.blocks`, with the same scaling and singularity measure) runs one
configuration at a time through the scalar joint kernels of :mod:`planar.joints.scalar`. The
loop is *generated* per plan structure: which kernel each joint calls, which bodies it reads,
where each Jacobian entry goes and every block's size and couplings are literals of its source,
so the compiler unrolls the small loops and drops the branches (a table-driven loop over the
same plan was measured 3x slower: loops of varying trip count per block and joint). Nothing in
it is written for a mechanism; the parameters, scales and sketch constants stay data, so designs
of one structure share one compiled loop.

Two entries: :func:`final` (one Newton step from given poses, with modes and rates: the
anchors' Newton iterations and kinematic coefficients) and :func:`fill` (the bulk of a sweep:
each value's Hermite guess, up to STEPS Newton steps, the acceptance test, status and rates,
written in place into the sweep's arrays).

The generated module is written to a cache directory (``PLANAR_CACHE_DIR``, else
``~/.cache/planar``) under a name hashing its source and the kernels' source, and numba caches
its machine code beside it: the first sweep of a new structure compiles (10-65 s), later ones
and later processes load it (a fraction of a second). Results agree with the numpy path to
rounding (the same operations per step, among them each block's elimination program of
:mod:`planar.elimination`, its constants taken from the plan as data; but for a bulk value's cos
and sin, taken from its anchor's by angle addition, reciprocals where the numpy path divides,
the singularity measure from the blocks' squared normalised dets, one square root per value,
and products and sums fused into multiply-adds where the compiler finds them;
the numpy path takes a value's further Newton steps in its general solver; the tests
compare the two on every joint type and on random linkages).
"""

import functools
import hashlib
import importlib.util
import inspect
import os
import sys
import tempfile
import weakref
from collections import namedtuple
from pathlib import Path

import numpy as np

from planar.errors import InputError
from planar.events import NEAR, SINGULAR
from planar.results import Status
from planar.sweep import CERT, JUMP, ROUND, certified

_TABLES = weakref.WeakKeyDictionary()
CHUNK = 1024  # values per task of the parallel loop (a call with fewer runs on one thread)
NEAR_ANGLE = 0.05  # a bulk value's angles within this of its anchor's: cos and sin from the anchor's
STEPS = 4  # Newton steps a batch value may take in the loop ...
CLOSE = 1e-4  # ... while its last step (scaled) is below this: a guess off by little

Tables = namedtuple("Tables", [
    # joints: kernel names, parameters, row constants, rows, bodies, input column (-1: none),
    # and where the Jacobian entry (r, col) of joint j goes: e0[j] + (r * 3 nb + col) * stride[j]
    "kernel", "gamma", "par", "c", "nr", "rows", "nb", "slots", "inp", "e0", "stride",
    # the plan's rows and their scales; its driver rows and their input columns
    "prow", "rs", "drv", "drv_inp",
    # blocks: size, and per block its equations, columns and their scales, the upstream columns
    # ``up`` and the Jacobian entries coupling to them; per block the structure of its
    # elimination program (:func:`_program`), whose constants are in ``pc``
    "bk", "eqs", "cols", "brs", "bcs", "up", "coup", "prog", "pc",
    # the coordinates solved with their scales; redundant rows with theirs; sizes
    "pcols", "cs", "red", "red_scale", "n_bodies", "m", "n", "nnz",
])


def check(plan):
    """Raise :class:`InputError` unless the compiled path can run ``plan``."""
    if importlib.util.find_spec("numba") is None:
        raise InputError("engine='numba' needs numba: pip install 'planar-kinematics[fast]', or use engine='numpy'")
    from planar.joints.scalar import KERNELS

    missing = sorted({g.kind.__name__ for g in plan.system.groups if g.kind not in KERNELS})
    if missing:
        raise InputError(f"engine='numba': joint type(s) {missing} have no scalar kernels "
                         f"(planar/joints/scalar.py); use engine='numpy'")


def final(model, plan, q, U, Ud, Udd, rates=True, steps=1, tol=0.0, step_tol=0.0):
    """One Newton step from guesses q (N, n) and, at the corrected poses, the rates with the
    factorisation at the guesses, as the numpy path of ``planar.sweep._step`` computes them: a
    dict of q, qd, qdd, the scaled residual at the guess ``res``, the scaled ``step`` and
    ``off`` (the same over its finite components: how far the pose moved), the blocks' det
    ``signs``, the largest scaled redundant row ``red``, the singularity measure ``sing``, the
    ``branch`` (the product of the signs) and ``iters``. With ``steps`` > 1, Newton: up to that
    many steps, each value until its residual is below ``tol`` and its step below ``step_tol``
    (or its pose is no longer finite), the dict's values those of its last step."""
    N = q.shape[0]
    T, loop = _compiled(model, plan, N)
    q = np.array(q, dtype=float, order="C")
    qd, qdd = (np.empty((N, T.n)), np.empty((N, T.n))) if rates else (np.empty((0, T.n)), np.empty((0, T.n)))
    res, step, off, red, sing, branch = (np.empty(N) for _ in range(6))
    signs, iters = np.empty((N, len(T.bk)), np.int8), np.empty(N, np.int64)
    no_i, no_b = np.zeros(0, np.int64), np.zeros(0, bool)
    as_c = np.ascontiguousarray
    loop(np.arange(N), False, int(steps), no_b, no_i, np.zeros((0, 6, T.n)), np.zeros((0, len(T.bk)), np.int8),
         float(tol), float(step_tol), q, as_c(U, float), _rates_in(Ud), _rates_in(Udd), bool(rates), qd, qdd, res,
         signs, sing, branch, step, off, red, no_b, np.zeros(0, np.int8), iters, no_b, no_b, *_data(T))
    if not rates:  # as the numpy path: one read-only NaN
        qd = qdd = np.broadcast_to(np.nan, q.shape)
    return dict(q=q, qd=qd, qdd=qdd, res=res, step=step, off=off, signs=signs, red=red, sing=sing, branch=branch,
                iters=iters)


def fill(model, plan, rows, adj, G, P, SA, tol, rates, sweep):
    """Values ``rows`` of a sweep solved in place from quintic Hermite guesses between the
    anchors around each, G[a] < row <= G[a + 1] (an anchor among them from the interval before
    it, the first from the one after it), where ``adj[a]`` says the two bound one stretch (G
    sorted; P the interpolants' coefficients of ``planar.sweep._quintic``, SA the anchors'
    modes), with ``planar.sweep``'s final step and acceptance test: where a value passes, its
    pose, rates, residual, modes, singularity, branch and status are written into the sweep's arrays
    (``sweep``: a dict of q, U, Ud, Udd, qd, qdd, res, signs, sing, branch, status, iters,
    solved, done). Returns (M,) True where it passed; the others are left unposed (NaN) for
    the general path, but for solved anchors among them, which keep their poses and modes."""
    T, loop = _compiled(model, plan, rows.size)
    ok = np.empty(rows.size, bool)
    no = np.zeros(0)
    S = sweep
    loop(rows, True, STEPS, adj, G, P, SA, float(tol), 0.0, S["q"], S["U"], _rates_in(S["Ud"]), _rates_in(S["Udd"]),
         bool(rates), S["qd"], S["qdd"], S["res"], S["signs"], S["sing"], S["branch"], no, no, no, ok, S["status"],
         S["iters"], S["solved"], S["done"], *_data(T))
    return ok


def _rates_in(a):
    """Input rates (N, f) as the loop reads them, C-contiguous and writeable (numba compiles
    read-only arrays apart): their one row where they repeat one row (a rate given once:
    ``planar.Model._inputs``), which the loop reads for every value."""
    if a.ndim == 2 and a.shape[0] > 1 and a.strides[0] == 0:
        a = a[:1]
    return np.require(a, float, ("C", "W"))


def _data(T):
    return T.par, T.c, T.rs, T.brs, T.bcs, T.cs, T.red_scale, T.pc


def _compiled(model, plan, n):
    """The tables and the driver for n values: the parallel loop, or one thread for a chunk."""
    module = _module(model, plan)
    return _TABLES[plan][0], (module.loop if n > CHUNK else module.serial)


def _module(model, plan):
    if plan not in _TABLES:
        T = tables(model, plan)
        _TABLES[plan] = (T, _load(source(T)))
    return _TABLES[plan][1]


def tables(model, plan):
    """The plan flattened: structure (literals of the generated source) and data."""
    from planar.joints.scalar import KERNELS

    sysm = plan.system
    J = {k: [] for k in ("kernel", "gamma", "par", "c", "nr", "rows", "nb", "slots", "inp", "e0", "stride")}
    for g, (start, _, (n_rows, _, K)) in zip(sysm.groups, sysm._blocks):
        keys, kernel, gamma = KERNELS[g.kind]
        flat = [np.asarray(g.P[key], float).reshape(K, -1) for key in keys]
        flat = np.concatenate(flat, axis=1) if flat else np.zeros((K, 0))
        for k in range(K):
            for name, v in (("kernel", kernel), ("gamma", gamma), ("par", flat[k]),
                            ("c", np.asarray(g.P["c"][k], float).reshape(-1)), ("nr", n_rows),
                            ("rows", tuple(int(r) for r in g.rows[k])), ("nb", g.bodies.shape[1]),
                            ("slots", tuple(int(b) for b in g.bodies[k])), ("inp", int(g.inputs[k])),
                            ("e0", start + k), ("stride", K)):
                J[name].append(v)
    width = max([len(p) for p in J["par"]] + [1])
    par = np.zeros((len(J["par"]), width))
    c = np.zeros((len(J["c"]), 2))
    for j, (p, cj) in enumerate(zip(J["par"], J["c"])):
        par[j, : len(p)], c[j, : len(cj)] = p, cj
    B = plan.blocks
    red = np.asarray(model.redundant_rows, int)
    tup = (lambda a: tuple(int(v) for v in a))
    prog, pc = [None] * len(B), []
    for st in plan.stages:
        for g, b in enumerate(st.index):
            prog[b] = _program(st.program, g, pc)
    return Tables(
        tuple(J["kernel"]), tuple(J["gamma"]), par, c, tuple(J["nr"]), tuple(J["rows"]), tuple(J["nb"]),
        tuple(J["slots"]), tuple(J["inp"]), tuple(J["e0"]), tuple(J["stride"]),
        tup(plan.rows), model.row_scale[plan.rows].astype(float), tup(plan.drivers), tup(plan.driver_inputs),
        tuple(b.size for b in B), tuple(tup(b.eqs) for b in B), tuple(tup(b.cols) for b in B),
        _cat([b.rscale for b in B]), _cat([b.cscale for b in B]), tuple(tup(b.up) for b in B),
        tuple(tup(b.coup) for b in B), tuple(prog), np.array(pc + [0.0]), tup(plan.cols),
        model.col_scale[plan.cols].astype(float), tup(red),
        model.row_scale[red].astype(float), sysm.n_bodies, sysm.m, model.n, sysm.entries[0].size + 1,
    )


def _program(P, g, pc):
    """The structure of block g of a stage's elimination program P
    (:class:`planar.elimination.Program`) for the generated factor and solve, its constants
    appended to ``pc`` (the structure holds their offsets there, so designs of one structure
    share the source): the variables' value slots and scales; per form (the Schur complement's
    entries, row-major, then the pivot rows') its constant and (variable, coefficient); the
    Schur complement's rows and columns; per constant column's step the pivot row and column,
    1 / pivot, the rows it updates with their multipliers and the pivot row's (column, form);
    the det's normalisation (per row its constant and squared variables, unweighted and
    weighted; lam's constant, variables, whether any column is an angle, the number of length
    columns); the det's static part."""

    def const(v):
        pc.append(float(v))
        return len(pc) - 1

    nv = P.var.shape[0]
    var = tuple((int(P.var[i, g]), const(P.vscale[i, g, 0])) for i in range(nv))
    forms = tuple((const(P.form0[f]), tuple((int(k), const(P.forms[f, k])) for k in np.flatnonzero(P.forms[f])))
                  for f in range(P.form0.size))
    steps = tuple((p, c, const(1.0 / d), tuple((i, const(m)) for i, m in mults), tuple(us))
                  for p, c, d, mults, us in P.steps)
    lam_c, lam_v, any_angle, lengths = P.lam
    weighted = P.weighted
    rows = tuple((const(P.c0[i]), tuple(int(k) for k in np.flatnonzero(P.M0[i])),
                  const(P.c1[i]) if weighted else None, tuple(int(k) for k in np.flatnonzero(P.M1[i])))
                 for i in range(P.k))
    norm = (rows, const(lam_c), tuple(int(k) for k in lam_v), bool(any_angle), int(lengths), weighted)
    if nv == 0:  # a block of constants: its normalised det too, once (as the numpy path factors it)
        norm = const(P.constant[3][g, 0])
    return var, forms, tuple(P.rows), tuple(P.cols), steps, norm, const(P.det0)


def _cat(arrays):
    return np.concatenate(arrays).astype(float) if arrays else np.zeros(0)


# ---- the generated source ---------------------------------------------------------------------

_HELPERS = '''"""Generated by planar.compiled for one plan structure: do not edit."""
import numpy as np
import numba

from planar.joints.scalar import {kernels}
from planar.sweep import certified

_inline = numba.njit(inline="always", error_model="numpy")
_certified = _inline(certified)


@_inline
def _cos_sin(phi):
    """cos and sin of phi through t = tan(phi / 2), as planar.geometry.cos_sin."""
    t = np.tan(0.5 * phi)
    wt = 2.0 / (1.0 + t * t)
    return wt - 1.0, t * wt


@_inline
def _mx(a, b):
    """max that propagates NaN, as numpy's max does (a pose that reads NaN never passes)."""
    return b if (b > a or b != b) else a


@_inline
def _lu_det(A, perm, k):
    """LU with partial pivoting of a k x k block in place, as planar.elimination._dense_lu: its
    det. U's diagonal is left as its reciprocals, which _lu_solve multiplies by."""
    det = 1.0
    for i in range(k):
        perm[i] = i
    for j in range(k - 1):
        piv, big = j, abs(A[j, j])
        for i in range(j + 1, k):
            if abs(A[i, j]) > big:
                piv, big = i, abs(A[i, j])
        if piv != j:
            for col in range(k):
                A[j, col], A[piv, col] = A[piv, col], A[j, col]
            perm[j], perm[piv] = perm[piv], perm[j]
            det = -det
        r = 1.0 / A[j, j]
        for i in range(j + 1, k):
            l = A[i, j] * r
            A[i, j] = l
            for col in range(j + 1, k):
                A[i, col] -= l * A[j, col]
        det *= A[j, j]
        A[j, j] = r  # (the pivot's reciprocal: the solves multiply)
    det *= A[k - 1, k - 1]
    A[k - 1, k - 1] = 1.0 / A[k - 1, k - 1]
    return det


@_inline
def _lu_solve(A, perm, z, y, k):
    for i in range(k):
        y[i] = z[perm[i]]
    for i in range(1, k):
        for j in range(i):
            y[i] -= A[i, j] * y[j]
    for i in range(k - 1, -1, -1):
        for j in range(i + 1, k):
            y[i] -= A[i, j] * y[j]
        y[i] *= A[i, i]


'''


# fast-math's "contract" only: LLVM may fuse a * b + c into one fused multiply-add (one rounding
# instead of two); no other fast-math licence (the NaN and inf tests stay exact, nothing is
# reassociated). The four-bar's sweep at N = 1e5 on one thread: 3-4 % less time for positions,
# 5-8 % with rates
_JIT = '@numba.njit(cache=True, error_model="numpy", nogil=True, fastmath={"contract"})'
# ``values`` allocates nothing (its buffers come from ``loop`` and ``serial``), so it is compiled
# without numba's reference counting (``_nrt``): with it, each array passed to an inlined helper
# (evaluate, factor, solve, a joint kernel) and each view took an atomic increment and decrement
# per value, on counters the threads share (~10% of the four-bar's loop on one thread)
_JIT_VALUES = _JIT.replace("nogil=True", "nogil=True, _nrt=False")


def source(T):
    """The generated module for the plan tables ``T``: ``loop`` takes, per value, the Newton
    step from the guess (or, for :func:`fill`, from the Hermite guess it makes), factors, and
    solves the rates (as :func:`final`). The per-value work is split into functions (evaluate, factor, solve, gammas,
    values), each compiled once, so that compiling a large plan stays in seconds; the parallel
    driver ``loop`` only calls ``values`` on each chunk of values."""
    kmax = max(T.bk, default=1)
    L = [_HELPERS.replace("{kernels}", ", ".join(sorted(set(T.kernel + T.gamma)))).rstrip("\n")]

    def function(header, lines, jit="@_inline"):
        L.extend(["", "", jit, header] + ["    " + line for line in lines])

    body = []
    w = body.append
    _frames(T, w, rates=False)
    _joints(T, w, "kernel", "phi, jac")
    function("def evaluate(q, u, fb, Phi, Jv, c, phi, jac, par, jc, ref, near):", body)
    body = []
    w = body.append
    _frames(T, w, rates=True)
    _joints(T, w, "gamma", "g")
    function("def gammas(q, qd, u, fb, Phi, c, g, par, jc, ref, near):", body)
    body = []
    for b, prog in enumerate(T.prog):
        _factor(prog, b, body.append)
    function("def factor(Jv, A, P, dets, pc, EB):", ["sn, sd = 1.0, 1.0"] + body + ["return np.sqrt(sn / sd)"])
    body = []
    _solve(T, body.append)
    function("def solve(Jv, A, P, rhs, x, z, y, brs, bcs, pc, EB, zs, xl):", body)

    body = []
    w = body.append
    w("# value m of this call is row i of the arrays it writes (STEP, OFF, RED, OK: value m)")
    w("i = rows[m]")
    w("q = Q[i]")
    w("a, move, st = 0, 0.0, 0")
    w("if interp:")
    w("    # the anchors around the value: G[a] < i <= G[a + 1], by binary search; the rows come")
    w("    # sorted, so first whether the value lies in the previous value's interval")
    w("    lo_, hi_ = 0, G.size")
    w("    if a_prev >= 0 and G[a_prev] < i:")
    w("        lo_ = a_prev + 1")
    w("        if lo_ < hi_ and G[lo_] >= i:")
    w("            hi_ = lo_")
    w("    while lo_ < hi_:")
    w("        mid = (lo_ + hi_) // 2")
    w("        if G[mid] < i:")
    w("            lo_ = mid + 1")
    w("        else:")
    w("            hi_ = mid")
    w("    a = lo_ - 1")
    w("    if a < 0 and G.size > 1 and G[0] == i:  # the first anchor: its interval's start (t = 0)")
    w("        a = 0")
    w("    a_prev = a")
    w("    if a < 0 or a + 1 >= G.size or not ADJ[a]:  # no interval to interpolate in: the general path")
    w("        OK[m] = False")
    w("        if not SOLVED[i]:")
    w("            q[:] = np.nan")
    w("        continue")
    w("    if SOLVED[i]:  # a solved anchor keeps its pose and modes if this fails")
    w("        for j in range(qo.size):")
    w("            qo[j] = q[j]")
    w("        for j in range(so.size):")
    w("            so[j] = SIGNS[i, j]")
    w("    # the quintic Hermite guess between anchors a and a + 1 (HQ: planar.sweep._quintic and")
    w("    # _horner), and the predicted move from a")
    w("    if a != a_ref:  # the interval's start and 1 / length; the anchor's angles, their cos and")
    w("        # sin: the reference of _frames")
    w("        u0 = U[G[a], 0]")
    w("        iu = 1.0 / (U[G[a + 1], 0] - u0)")
    for b in range(1, T.n_bodies):
        w(f"        ref[{b}, 0] = HQ[a, 0, {3 * b - 1}]")
        w(f"        ref[{b}, 1], ref[{b}, 2] = _cos_sin(ref[{b}, 0])")
    w("        a_ref = a")
    w("    t = (U[i, 0] - u0) * iu")
    w("    for j in range(HQ.shape[2]):  # Horner's rule, highest power first")
    w("        v = HQ[a, 5, j]")
    w("        for k in range(4, -1, -1):")
    w("            v = HQ[a, k, j] + t * v")
    w("        q[j] = v")
    w("    move = 0.0")
    for k, col in enumerate(T.pcols):
        w(f"    move = _mx(move, abs((q[{col}] - HQ[a, 0, {col}]) * ics[{k}]))")
    w("    for j in range(qg.size):")
    w("        qg[j] = q[j]")
    w("for it in range(1, steps + 1):")
    step_start = len(body)
    w("evaluate(q, U[i], fb, Phi, Jv, c, phi, jac, par, jc, ref, interp)")
    w("res = 0.0")
    for r, row in enumerate(T.prow):
        w(f"rhs[{r}] = Phi[{row}]")
        w(f"res = _mx(res, abs(rhs[{r}] * rs[{r}]))")
    w("red = 0.0")
    for r, row in enumerate(T.red):
        w(f"red = _mx(red, abs(Phi[{row}] * red_scale[{r}]))")
    w("# the singularity measure (the smallest normalised |det|, at most 1) and the branch (the")
    w("# product of the signs)")
    w("sing = factor(Jv, A, P, dets, pc, EB)")
    w("branch = 1.0")
    for b in range(len(T.bk)):
        w(f"SIGNS[i, {b}] = 1 if dets[{b}] > 0 else (-1 if dets[{b}] < 0 else 0)  # NaN: 0, as planar.blocks")
        w(f"branch *= SIGNS[i, {b}]")
    w("solve(Jv, A, P, rhs, x, z, y, brs, bcs, pc, EB, zs, xl)")
    w("# the step's size, and the distance the pose moves (its finite components)")
    w("step, off = 0.0, 0.0")
    for k, col in enumerate(T.pcols):
        w(f"step = _mx(step, abs(x[{col}] * ics[{k}]))")
        w(f"if np.isfinite(x[{col}]):")
        w(f"    off = _mx(off, abs(x[{col}] * ics[{k}]))")
    for k in range(T.n):
        w(f"if np.isfinite(x[{k}]):")
        w(f"    q[{k}] -= x[{k}]")
    w("# a batch value whose guess is off by more than rounding (but little) takes more steps;")
    w("# otherwise, Newton (planar.solver.newton) to its tolerances, while the pose is finite")
    w("if interp:")
    w(f"    if not ({ROUND!r} < step <= {CLOSE!r}):")
    w("        break")
    w("elif (res <= tol and step <= step_tol) or not (step < np.inf and res < np.inf):")
    w("    break")
    body[step_start:] = ["    " + line for line in body[step_start:]]
    w("RES[i], SING[i], BRANCH[i] = res, sing, branch")
    w("if interp:")
    w("    off = 0.0  # how far the steps moved the guess")
    for k, col in enumerate(T.pcols):
        w(f"    off = _mx(off, abs((q[{col}] - qg[{col}]) * ics[{k}]))")
    w("    # planar.sweep's acceptance of a batch value: converged, the source anchor's modes, no")
    w("    # further from the guess than JUMP times the predicted move, certified on its branch")
    w(f"    ok = res <= tol and step <= {ROUND!r} and (off <= 1e-9 or off <= {JUMP!r} * move + 1e-9)")
    w("    ok = ok and _certified(off, sing)")
    for b in range(len(T.bk)):
        w(f"    ok = ok and SIGNS[i, {b}] == SA[a, {b}]")
    w("    OK[m] = ok")
    w("    if not ok:  # left for the general path: no pose here yet (or the anchor's own)")
    w("        if SOLVED[i]:")
    w("            for j in range(qo.size):")
    w("                q[j] = qo[j]")
    w("            for j in range(so.size):")
    w("                SIGNS[i, j] = so[j]")
    w("        else:")
    w("            q[:] = np.nan")
    w("        continue")
    w("    # its status, as planar.events.status_of and planar.sweep._final give a converged value")
    w(f"    st = {int(Status.SINGULAR)} if sing < {SINGULAR!r} else ({int(Status.NEAR_SINGULAR)} if sing < {NEAR!r} "
      f"else {int(Status.SOLVED)})")
    if T.red:
        w(f"    if red > {1e3!r} * tol:")
        w(f"        st = {int(Status.INCONSISTENT)}")
    w("    STATUS[i], SOLVED[i], DONE[i] = st, True, True")
    w("else:")
    w("    STEP[m], OFF[m], RED[m] = step, off, red")
    w("ITERS[i] = it")
    w("if not rates:")
    w("    continue")
    w("# velocities: the input rates on the driver rows")
    _rate(T, w, None, "Ud", "QD")
    w("# accelerations: gamma at the corrected pose and the velocities, input accelerations added")
    w("gammas(q, QD[i], U[i], fb, Phi, c, g, par, jc, ref, interp)")
    _rate(T, w, "Phi", "Udd", "QDD")
    w(f"if st > {int(Status.BRANCH_EVENT)}:  # no rates on a singular or inconsistent pose")
    w("    QD[i, :] = np.nan")
    w("    QDD[i, :] = np.nan")
    args = ("rows, interp, steps, ADJ, G, HQ, SA, tol, step_tol, Q, U, Ud, Udd, rates, QD, QDD, RES, SIGNS, SING, BRANCH, "
            "STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE, par, jc, rs, brs, bcs, cs, red_scale, pc")
    buffers = "fb, c, phi, jac, g, Phi, Jv, rhs, x, z, y, A, P, qg, qo, so, dets, ref, EB, zs, xl, ics"
    n_eb = max([len(p[1]) - len(p[2]) ** 2 for p in T.prog] + [1])  # the pivot rows' forms
    head = ["a_prev, a_ref = -1, -1  # the previous value's anchor interval, and that of ref, u0 and iu",
            "u0, iu = 0.0, 0.0",
            "for m in range(lo, hi):"]
    function(f"def values(lo, hi, {args}, {buffers}):", head + ["    " + b for b in body], _JIT_VALUES)
    alloc = [f"fb = np.zeros(({T.n_bodies}, 8))",
             "fb[0, 3] = 1.0",
             "c, phi, jac, g = np.empty(2), np.empty(2), np.empty((2, 9)), np.empty(2)",
             f"Phi, Jv, rhs = np.zeros({T.m}), np.zeros({T.nnz}), np.empty({len(T.prow)})",
             f"x, z, y, qg, qo = np.zeros({T.n + 1}), np.empty({kmax}), np.empty({kmax}), np.empty({T.n}), np.empty({T.n})",
             f"so, dets, ref = np.empty({len(T.bk)}, np.int8), np.empty({len(T.bk)}), np.empty(({T.n_bodies}, 3))",
             f"A, P = np.empty(({len(T.bk)}, {kmax}, {kmax})), np.empty(({len(T.bk)}, {kmax}), np.int64)",
             f"EB, zs, xl = np.empty(({len(T.bk)}, {n_eb})), np.empty({kmax}), np.empty({kmax})",
             "ics = 1.0 / cs  # the column scales' reciprocals: a multiplication costs less than a division"]
    function(f"def loop({args}):", ["N = rows.shape[0]",
             f"for chunk in numba.prange((N + {CHUNK - 1}) // {CHUNK}):  # chunks on all cores, each its own buffers"]
             + ["    " + a for a in alloc]
             + [f"    values(chunk * {CHUNK}, min(N, (chunk + 1) * {CHUNK}), {args}, {buffers})"],
             _JIT.replace("nogil=True", "nogil=True, parallel=True"))
    function(f"def serial({args}):", ["# one chunk or less: no threads to start"] + alloc
             + [f"values(0, rows.shape[0], {args}, {buffers})"], _JIT)
    return "\n".join(L) + "\n"


def _rate(T, w, base, inputs, out):
    """Solve for a rate into row i of ``out``: right-hand side ``base`` on the plan's rows (Phi
    holding gamma, or zeros), the input's rate of that order added on the driver rows."""
    for r, row in enumerate(T.prow):
        w(f"rhs[{r}] = {'0.0' if base is None else f'{base}[{row}]'}")
    for r, col in zip(T.drv, T.drv_inp):  # (one row of rates: the same for every value)
        w(f"rhs[{r}] += {inputs}[i if {inputs}.shape[0] > 1 else 0, {col}]")
    w("solve(Jv, A, P, rhs, x, z, y, brs, bcs, pc, EB, zs, xl)")
    for k in range(T.n):
        w(f"{out}[i, {k}] = x[{k}]")


def _frames(T, w, rates):
    """The bodies' rows of ``fb``: x, y, angle, its cos and sin (and with ``rates`` the body's
    velocity). cos and sin by ``_cos_sin``; ``near`` (a bulk value: within NEAR_ANGLE of its
    anchor's angles ``ref``): by the angle-addition formulas from the anchor's cos and sin, with
    the Taylor series of the difference d to d^9 (the first term left out, d^10 / 10!, is below
    1e-19 there): half the time of a tan, and as accurate."""
    for b in range(1, T.n_bodies):
        x, y, a = 3 * b - 3, 3 * b - 2, 3 * b - 1
        w(f"d = q[{a}] - ref[{b}, 0]")
        w(f"if near and abs(d) <= {NEAR_ANGLE!r}:")
        w("    d2 = d * d")
        w("    sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0)"
          " * (1.0 - d2 * (1.0 / 72.0)))))")
        w("    cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0)"
          " * (1.0 - d2 * (1.0 / 56.0))))")
        w(f"    co, si = ref[{b}, 1] * cd - ref[{b}, 2] * sd, ref[{b}, 2] * cd + ref[{b}, 1] * sd")
        w("else:")
        w(f"    co, si = _cos_sin(q[{a}])")
        w(f"fb[{b}, 0], fb[{b}, 1], fb[{b}, 2], fb[{b}, 3], fb[{b}, 4] = q[{x}], q[{y}], q[{a}], co, si")
        if rates:
            w(f"fb[{b}, 5], fb[{b}, 6], fb[{b}, 7] = qd[{x}], qd[{y}], qd[{a}]")


def _joints(T, w, which, out):
    """Each joint's kernel (``which``: "kernel" or "gamma") and the scatter of its rows (and
    of the Jacobian entries that factor and solve read) into Phi (and Jv)."""
    read = _read(T)
    for j, name in enumerate(getattr(T, which)):
        for r in range(T.nr[j]):
            w(f"c[{r}] = jc[{j}, {r}]")
        if T.inp[j] >= 0:
            w(f"c[0] = u[{T.inp[j]}]")
        w(f"{name}(par[{j}], c, fb, {T.slots[j]!r}, {out})")
        nc = 3 * T.nb[j]
        for r in range(T.nr[j]):
            w(f"Phi[{T.rows[j][r]}] = {out.split(',')[0]}[{r}]")
            if which == "kernel":
                for col in range(nc):
                    e = T.e0[j] + (r * nc + col) * T.stride[j]
                    if e in read:
                        w(f"Jv[{e}] = jac[{r}, {col}]")


def _read(T):
    """The Jacobian entries factor and solve read: the blocks' variables and their coupling
    entries but the zero slot (the others are constants of the elimination programs)."""
    read = {slot for prog in T.prog for slot, _ in prog[0]} | {e for coup in T.coup for e in coup}
    return read - {T.nnz - 1}


def _factor(prog, b, w):
    """Block b by its elimination program (planar.elimination.Program._factor): the variables'
    scaled values, the forms' values (the Schur complement's into A, the pivot rows' into EB,
    for the solve), the LU of the Schur complement and the det's normalisation."""
    var, forms, rows, cols, steps, norm, det0 = prog
    r = len(rows)
    for i, (slot, scale) in enumerate(var):
        w(f"v{i} = Jv[{slot}] * pc[{scale}]")
    for f, (c0, terms) in enumerate(forms):
        value = f"pc[{c0}]" + "".join(f" + v{k} * pc[{coef}]" for k, coef in terms)
        w(f"A[{b}, {f // r}, {f % r}] = {value}" if f < r * r else f"EB[{b}, {f - r * r}] = {value}")
    if not var:  # a block of constants: its det was normalised once
        if r:
            w(f"_lu_det(A[{b}], P[{b}], {r})")
        w(f"dets[{b}] = pc[{norm}]")
        w(f"dd, nm = dets[{b}] * dets[{b}], 1.0")
        _smallest(w)
        return
    nrm, lam_c, lam_v, any_angle, lengths, weighted = norm
    if not any_angle:
        w("lam = 1.0")
    else:  # the largest angle-column entry, at least lam's constant part, at most 1 (NaN stays NaN)
        w(f"lam = pc[{lam_c}]")
        for k in lam_v:
            w(f"lam = _mx(lam, abs(v{k}))")
        w("lam = -_mx(-lam, -1.0)")
    w("nm = 1.0")
    for c0, m0, c1, m1 in nrm:
        w(f"nm *= pc[{c0}]" + "".join(f" + v{k} * v{k}" for k in m0)
          + (f" + (pc[{c1}]" + "".join(f" + v{k} * v{k}" for k in m1) + ") * lam * lam" if weighted else ""))
    w(f"det = pc[{det0}]" + (f" * _lu_det(A[{b}], P[{b}], {r})" if r else ""))
    w(f"# the normalised det nd = det / sqrt(nm){' * lam**' + str(lengths) if lengths else ''}, capped by lam, as "
      "its square dd / nm (the")
    w("# sign in dets; NaN stays NaN, and nm <= 0 reads 0 as in planar.elimination)")
    w("dd = det * det" + (f" * lam**{2 * lengths}" if lengths else "") + " if nm > 0 else 0.0")
    w("if dd > lam * lam * nm:")
    w("    dd, nm = lam * lam, 1.0")
    w(f"dets[{b}] = det if dd > 0 else 0.0")
    _smallest(w)


def _smallest(w):
    """The smallest |nd| so far, as sn / sd with the block's dd / nm (NaN stays NaN): the
    singularity measure takes one square root and one division, not one of each per block."""
    w("if dd * sd < sn * nm or dd != dd:")
    w("    sn, sd = dd, nm")


def _solve(T, w):
    """x = J^-1 rhs forward through the blocks."""
    o = 0
    for b, k in enumerate(T.bk):
        nw = len(T.up[b])
        for i in range(k):
            terms = "".join(f" - Jv[{T.coup[b][i * nw + u]}] * x[{T.up[b][u]}]" for u in range(nw)
                            if T.coup[b][i * nw + u] != T.nnz - 1)  # (not the zero slot)
            w(f"z[{i}] = (rhs[{T.eqs[b][i]}]{terms}) * brs[{o + i}]")
        # planar.elimination.Program.solve: the constant columns' steps, the Schur complement
        _, _, rows, cols, steps, _, _ = T.prog[b]
        r = len(rows)
        for p, _, _, mults, _ in steps:
            for i, m in mults:
                w(f"z[{i}] -= pc[{m}] * z[{p}]")
        if r:
            for jj, row in enumerate(rows):
                w(f"zs[{jj}] = z[{row}]")
            w(f"_lu_solve(A[{b}], P[{b}], zs, y, {r})")
            for jj, col in enumerate(cols):
                w(f"xl[{col}] = y[{jj}]")
        for p, c, inv_d, _, us in reversed(steps):
            terms = "".join(f" - EB[{b}, {f - r * r}] * xl[{j}]" for j, f in us)
            w(f"xl[{c}] = (z[{p}]{terms}) * pc[{inv_d}]")
        for i in range(k):
            w(f"x[{T.cols[b][i]}] = xl[{i}] * bcs[{o + i}]")
        o += k


# ---- loading: a module file in the cache directory, so numba can cache its machine code --------


def _load(src):
    from planar.joints import scalar

    # the source of what the loop compiles in: a change to it is a new module (numba's cache
    # keys on the module's own file only)
    key = hashlib.sha1((src + inspect.getsource(scalar) + inspect.getsource(certified) + repr((CERT, ROUND))).encode()
                       ).hexdigest()[:20]
    path = _cache_dir() / f"plan_{key}.py"
    if not path.exists():
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(src)
        os.replace(tmp, path)  # atomic: a concurrent process reads a whole file or none
    name = f"planar_plan_{key}"
    if name not in sys.modules and not any((path.parent / "__pycache__").glob(f"{path.stem}.*.nbi")):
        # numba has no machine code of this structure on disk: the first sweep compiles it
        sys.stderr.write("planar: compiling the numba engine for this mechanism structure (once, 10-65 s; "
                         "later sweeps and new processes reuse it)\n")
        sys.stderr.flush()
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # numba's on-disk cache finds the module again by name
        spec.loader.exec_module(module)
    return sys.modules[name]


@functools.cache
def _cache_dir():
    base = os.environ.get("PLANAR_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "planar")
    path = Path(base) / "compiled"
    try:
        path.mkdir(parents=True, exist_ok=True)
        return path
    except OSError:  # no writable home: a directory of this process
        return Path(tempfile.mkdtemp(prefix="planar-compiled-"))


__all__ = ["check", "final", "fill", "tables", "source"]
