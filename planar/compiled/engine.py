"""The compiled engine's machine code: one loop over values in groups (the lanes), reading a
plan's tables (:class:`planar.compiled.Tables`), compiled once and cached on disk by numba.

Imported on the first ``engine="numba"`` sweep (it imports numba). :func:`ready` compiles the
loop, or loads it from numba's cache, saying so on stderr when it compiles.

One module of more than 400 lines because it is one compilation unit: numba's on-disk cache is
keyed on this file alone, so the loop, its stages and the pieces it inlines live here, and what
it compiles in from elsewhere (the joints' kernels, the shared rules) is hashed by :func:`_stamp`.
"""

import hashlib
import inspect
import os
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
from numba.extending import register_jitable

from planar.acceptance import CERT, JUMP, ROUND, certified, on_course
from planar.compiled import CHUNK, D_BODIES, D_DESIGN, D_JBODIES, D_JROWS, D_KMAX, D_M, D_N, D_NNZ, D_NV, D_RMAX
from planar.compiled import MIN_CHUNK, kinds
from planar.compiled import B_ANGLE, B_CO, B_FO, B_K, B_LENGTHS, B_LO, B_NF, B_NL, B_NS, B_NV, B_NW, B_O, B_R
from planar.compiled import B_RO, B_SO, B_UO, B_VO, B_WEIGHTED
from planar.events import HELD, NEAR, NEAR_CURVE, SINGULAR, status_of
from planar.joints import scalar
from planar.lu import lu
from planar.results import Status

NEAR_ANGLE = 0.05  # a bulk value's angles within this of its anchor's: cos and sin from the anchor's
CLOSE = 1e-4  # a batch value takes more Newton steps while its last one (scaled) is below this
ST_SOLVED = int(Status.SOLVED)
ST_BRANCH_EVENT = int(Status.BRANCH_EVENT)  # the last status with rates
ST_NEAR_SINGULAR = int(Status.NEAR_SINGULAR)  # the last status of a value reached on its branch with no event
# where the loop's values start from (its ``mode``): poses given (Newton to its tolerances:
# planar.compiled.final), a sweep's quintic Hermite guesses between anchors (planar.compiled.fill),
# the Taylor predictor from the nearest pose known on the branch (planar.compiled.Compiled.direct), or a
# design's walk, each lane a design stepping through its stations (planar.compiled.walk)
FINAL, BULK, KNOWN, WALK = 0, 1, 2, 3
LANES = 32  # values the loop takes together (fewer in a smaller chunk)

# fast-math's "contract" only: LLVM may fuse a * b + c into one fused multiply-add (one rounding
# instead of two); no other fast-math licence (the NaN and inf tests stay exact, nothing is
# reassociated)
_JIT: dict = dict(cache=True, error_model="numpy", nogil=True, fastmath={"contract"})
# the joints' kernels and their pieces (plain functions: numba compiles them where the loop calls
# them) and the loop's small pieces, inlined by numba (as separate functions they took 2-3x the time)
_piece = register_jitable(inline="always", error_model="numpy")
_inline = numba.njit(inline="always", error_model="numpy")
# the loop's stages (evaluation, gamma, factorisation, solve), each compiled once and called:
# inlined, the solve is compiled three times into the loop (Newton's and both rates'), for nearly
# twice the compile and no faster loop (docs/engine.md, the compiled engine)
_stage = numba.njit(**dict(_JIT, _nrt=False))

# the rules both engines share: planar.acceptance's test, planar.events' status rule
SHARED = (certified, on_course, status_of)
for _fn in dict.fromkeys(scalar.PIECES + SHARED + tuple(f for cls in kinds() for f in cls.scalar_kernels[1:])):
    _piece(_fn)


def _dispatch(fns):
    """rows(code, p, c, f, s, phi, jac): fns[code](p, c, f, s, phi, jac), as a chain of branches
    (explicit arguments: a chain passing ``*args`` cost twice the time per joint)."""
    head = fns[0]
    if len(fns) == 1:
        def rows(code, p, c, f, s, phi, jac):
            head(p, c, f, s, phi, jac)
    else:
        tail = _dispatch(fns[1:])

        def rows(code, p, c, f, s, phi, jac):
            if code == 0:
                head(p, c, f, s, phi, jac)
            else:
                tail(code - 1, p, c, f, s, phi, jac)
    return _piece(rows)


def _dispatch_gamma(fns):
    """gamma(code, p, c, f, s, g): fns[code](p, c, f, s, g), as :func:`_dispatch`."""
    head = fns[0]
    if len(fns) == 1:
        def gamma(code, p, c, f, s, g):
            head(p, c, f, s, g)
    else:
        tail = _dispatch_gamma(fns[1:])

        def gamma(code, p, c, f, s, g):
            if code == 0:
                head(p, c, f, s, g)
            else:
                tail(code - 1, p, c, f, s, g)
    return _piece(gamma)


_rows = _dispatch([cls.scalar_kernels[1] for cls in kinds()])
_gamma = _dispatch_gamma([cls.scalar_kernels[2] for cls in kinds()])


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
def _pick(c, a, b):
    return a if c else b


@_inline
def _swap_rows(A, perm, j, i, c, k):
    if c:
        for col in range(k):
            A[j, col], A[i, col] = A[i, col], A[j, col]
        perm[j], perm[i] = perm[i], perm[j]


@_inline
def _permute(z, perm, y, k):
    for i in range(k):
        y[i] = z[perm[i]]


@_inline
def _unpermute(w, perm, y, k):
    for i in range(k):
        y[perm[i]] = w[i]


# planar.lu's factorisation and solve, on one pose's numbers (the loop needs no transposed solve)
_factor_one, _solve_one, _ = lu(_pick, _swap_rows, _permute, _unpermute)
_lu_det, _lu_solve = _inline(_factor_one), _inline(_solve_one)


@_inline
def _frames(q, qd, rates, fb, ref, near, L):
    """The bodies' rows of ``fb`` (lane, body, row): x, y, angle, its cos and sin (and with
    ``rates`` the body's velocity). cos and sin by ``_cos_sin``; ``near`` (bulk values: within
    NEAR_ANGLE of their anchor's angles ``ref``): by the angle-addition formulas from the
    anchor's cos and sin, with the Taylor series of the difference d to d^9 (the first term
    left out, d^10 / 10!, is below 1e-19 there): half the time of a tan, and as accurate. The
    series runs on every lane (no branch in the loop); the rare lanes too far take the tan."""
    for b in range(1, fb.shape[1]):
        x = 3 * b - 3
        a = x + 2
        for l in range(L):
            fb[l, b, 0], fb[l, b, 1], fb[l, b, 2] = q[x, l], q[x + 1, l], q[a, l]
        far = not near
        if near:
            for l in range(L):
                d = q[a, l] - ref[b, 0, l]
                d2 = d * d
                sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0)
                                                                                 * (1.0 - d2 * (1.0 / 72.0)))))
                cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))))
                fb[l, b, 3], fb[l, b, 4] = ref[b, 1, l] * cd - ref[b, 2, l] * sd, ref[b, 2, l] * cd + ref[b, 1, l] * sd
                far |= not abs(d) <= NEAR_ANGLE
        if far:
            for l in range(L):
                if not (near and abs(q[a, l] - ref[b, 0, l]) <= NEAR_ANGLE):
                    fb[l, b, 3], fb[l, b, 4] = _cos_sin(q[a, l])
        if rates:
            for l in range(L):
                fb[l, b, 5], fb[l, b, 6], fb[l, b, 7] = qd[x, l], qd[x + 1, l], qd[a, l]


@_inline
def _design(T, u):
    """The design of the value at inputs u: its index in u's last column for designs of one
    structure swept together, else 0."""
    return int(u[T.dims[D_DESIGN]]) if T.dims[D_DESIGN] >= 0 else 0


@_inline
def _row_constants(T, d, j, u, c):
    """Joint j's row constants of design d into c: the sketch's, a driver's first its input value."""
    for r in range(c.size):
        c[r] = T.jc[d, j, r]
    if T.inp[j] >= 0:
        c[0] = u[T.inp[j]]


@_stage
def _evaluate(T, q, U, I, des, act, fb, Phi, Jv, c, phi, jac, ref, near, L):
    """Phi at q, and the Jacobian entries factor and solve read into Jv (of the active lanes
    only: the others keep their last step's): each joint's kernel, lane by lane."""
    _frames(q, q, False, fb, ref, near, L)
    for j in range(T.code.size):
        code, s = T.code[j], T.slots[j]
        for l in range(L):
            if act[l]:
                _row_constants(T, des[l], j, U[I[l]], c)
                _rows(code, T.par[des[l], j], c, fb[l], s, phi[l], jac[l])
        for r in range(T.nr[j]):
            row = T.jrows[j, r]
            for l in range(L):
                Phi[row, l] = phi[l, r]
        for e in range(T.jac_at[j], T.jac_at[j + 1]):
            to, r, col = T.jac_to[e], T.jac_r[e], T.jac_c[e]
            for l in range(L):
                Jv[to, l] = _pick(act[l], jac[l, r, col], Jv[to, l])


@_stage
def _gammas(T, q, qd, U, I, des, want, fb, Phi, c, g, ref, near, L):
    """gamma at q and the velocities qd into Phi (of the lanes ``want``): each joint's gamma
    kernel."""
    _frames(q, qd, True, fb, ref, near, L)
    for j in range(T.code.size):
        code, s = T.code[j], T.slots[j]
        for l in range(L):
            if want[l]:
                _row_constants(T, des[l], j, U[I[l]], c)
                _gamma(code, T.par[des[l], j], c, fb[l], s, g[l])
        for r in range(T.nr[j]):
            row = T.jrows[j, r]
            for l in range(L):
                Phi[row, l] = g[l, r]


@_inline
def _forms(T, b, Jv, act, A, P, E, V, w, det, L):
    """Block b's variables' scaled values into V, its forms' values into E (the Schur
    complement's into A too) and the LU of the Schur complement, its det into ``det``: of
    the active lanes (the others keep their last step's)."""
    B = T.blk[b]
    vo, fo, r = B[B_VO], B[B_FO], B[B_R]
    for i in range(B[B_NV]):
        v, sc = T.var[vo + i], T.vscale[vo + i]
        for l in range(L):
            V[i, l] = Jv[v, l] * sc
    for f in range(fo, fo + B[B_NF]):
        e0 = T.form0[f]
        for l in range(L):
            w[l] = e0
        for t in range(T.form_at[f], T.form_at[f + 1]):
            v, tc = T.term_v[t], T.term_c[t]
            for l in range(L):
                w[l] += V[v, l] * tc
        for l in range(L):
            E[f, l] = _pick(act[l], w[l], E[f, l])
    for l in range(L):
        det[l] = 1.0
        if act[l] and r:
            for i in range(r):
                for j in range(r):
                    A[b, l, i, j] = E[fo + i * r + j, l]
            det[l] = _lu_det(A[b, l], P[b, l], r)


@_inline
def _constants(T, A, P, E, V, w, det, act):
    """The factors of the blocks of constants (no variables), once per buffer (all lanes
    active)."""
    for b in range(T.blk.shape[0]):
        if T.blk[b, B_NV] == 0:
            _forms(T, b, E, act, A, P, E, V, w, det, act.size)  # (no variable reads Jv)


@_stage
def _factor(T, Jv, act, A, P, dets, E, V, fw, sing, L):
    """Each block by its elimination program (planar.elimination.Program._factor): the
    variables' scaled values, the forms' values, the LU of the Schur complement and the det's
    normalisation; the blocks of constants were factored once (:func:`_constants`). The
    singularity measure into ``sing``: the smallest normalised |det|, kept as sn / sd (the
    blocks' squared normalised dets dd / nm; NaN stays NaN), so one square root and one
    division per value. ``fw``: the lanes' work rows."""
    sn, sd, dd, nm, lam, det, s0, s1, w = fw[0], fw[1], fw[2], fw[3], fw[4], fw[5], fw[6], fw[7], fw[8]
    for l in range(L):
        sn[l], sd[l] = 1.0, 1.0
    for b in range(T.blk.shape[0]):
        B = T.blk[b]
        if B[B_NV] == 0:  # a block of constants: its det was normalised once
            dc = T.det_c[b]
            for l in range(L):
                dets[b, l] = dc
                dd[l], nm[l] = dc * dc, 1.0
        else:
            _forms(T, b, Jv, act, A, P, E, V, w, det, L)
            d0 = T.det0[b]
            for l in range(L):
                det[l] = d0 * det[l]
                lam[l] = 1.0
            if B[B_ANGLE]:  # the largest angle-column entry, at least lam's constant part, at most 1
                lc = T.lam_c[b]
                for l in range(L):
                    lam[l] = lc
                for t in range(B[B_LO], B[B_LO] + B[B_NL]):
                    v = T.lam_v[t]
                    for l in range(L):
                        lam[l] = _mx(lam[l], abs(V[v, l]))
                for l in range(L):
                    lam[l] = -_mx(-lam[l], -1.0)
            for l in range(L):
                nm[l] = 1.0
            for i in range(B[B_O], B[B_O] + B[B_K]):
                c0 = T.nc0[i]
                for l in range(L):
                    s0[l] = c0
                for t in range(T.n0_at[i], T.n0_at[i + 1]):
                    v = T.n0_v[t]
                    for l in range(L):
                        s0[l] += V[v, l] * V[v, l]
                if B[B_WEIGHTED]:
                    c1 = T.nc1[i]
                    for l in range(L):
                        s1[l] = c1
                    for t in range(T.n1_at[i], T.n1_at[i + 1]):
                        v = T.n1_v[t]
                        for l in range(L):
                            s1[l] += V[v, l] * V[v, l]
                    for l in range(L):
                        s0[l] += s1[l] * lam[l] * lam[l]
                for l in range(L):
                    nm[l] *= s0[l]
            # the normalised det nd = det / sqrt(nm) * lam**lengths, capped by lam, as its square
            # dd / nm (the sign in dets; nm <= 0 reads 0 as in planar.elimination)
            for l in range(L):
                dd[l] = det[l] * det[l] if nm[l] > 0 else 0.0
            for _ in range(B[B_LENGTHS]):
                for l in range(L):
                    dd[l] *= lam[l] * lam[l]
            for l in range(L):
                capped = dd[l] > lam[l] * lam[l] * nm[l]
                dd[l], nm[l] = _pick(capped, lam[l] * lam[l], dd[l]), _pick(capped, 1.0, nm[l])
                dets[b, l] = det[l] if dd[l] > 0 else 0.0
        for l in range(L):
            less = dd[l] * sd[l] < sn[l] * nm[l] or dd[l] != dd[l]
            sn[l], sd[l] = _pick(less, dd[l], sn[l]), _pick(less, nm[l], sd[l])
    for l in range(L):
        sing[l] = np.sqrt(sn[l] / sd[l])


@_stage
def _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L):
    """x = J^-1 rhs forward through the blocks (planar.elimination.Program.solve each), every
    lane; the Schur complements' LU solves lane by lane."""
    zero = T.dims[D_NNZ] - 1  # the structural zero's slot
    for b in range(T.blk.shape[0]):
        B = T.blk[b]
        k, o, nw, uo, co, fo, r, ro, so, ns = B[B_K], B[B_O], B[B_NW], B[B_UO], B[B_CO], B[B_FO], B[B_R], B[B_RO], \
            B[B_SO], B[B_NS]
        if k == 1:  # most blocks (pivots, driven coordinates): one row, by its pivot or its 1x1 LU
            eq, col, rs, cs = T.eqs[o], T.cols[o], T.brs[o], T.bcs[o]
            for l in range(L):
                w[l] = rhs[eq, l]
            for v in range(nw):
                e = T.coup[co + v]
                if e != zero:
                    u = T.up[uo + v]
                    for l in range(L):
                        w[l] -= Jv[e, l] * x[u, l]
            if ns:
                piv = T.st_inv[so]
                for l in range(L):
                    x[col, l] = w[l] * rs * piv * cs
            else:
                for l in range(L):
                    x[col, l] = w[l] * rs * A[b, l, 0, 0] * cs
            continue
        for i in range(k):
            eq = T.eqs[o + i]
            for l in range(L):
                z[i, l] = rhs[eq, l]
            for v in range(nw):
                e = T.coup[co + i * nw + v]
                if e != zero:
                    u = T.up[uo + v]
                    for l in range(L):
                        z[i, l] -= Jv[e, l] * x[u, l]
            rs = T.brs[o + i]
            for l in range(L):
                z[i, l] *= rs
        for st in range(so, so + ns):  # the constant columns' steps
            p = T.st_p[st]
            for t in range(T.mul_at[st], T.mul_at[st + 1]):
                mi, mm = T.mul_i[t], T.mul_m[t]
                for l in range(L):
                    z[mi, l] -= mm * z[p, l]
        if r:  # the Schur complement
            for l in range(L):
                for j in range(r):
                    zs[j] = z[T.srows[ro + j], l]
                _lu_solve(A[b, l], P[b, l], zs, y, r)
                for j in range(r):
                    xl[T.scols[ro + j], l] = y[j]
        for st in range(so + ns - 1, so - 1, -1):
            p = T.st_p[st]
            for l in range(L):
                w[l] = z[p, l]
            for t in range(T.us_at[st], T.us_at[st + 1]):
                f, j = fo + T.us_f[t], T.us_j[t]
                for l in range(L):
                    w[l] -= E[f, l] * xl[j, l]
            c, inv = T.st_c[st], T.st_inv[st]
            for l in range(L):
                xl[c, l] = w[l] * inv
        for i in range(k):
            col, cs = T.cols[o + i], T.bcs[o + i]
            for l in range(L):
                x[col, l] = xl[i, l] * cs


@_inline
def _rate(T, base, inputs, I, want, out, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L):
    """Solve for a rate into out's rows of the lanes ``want``: right-hand side ``base`` on the
    plan's rows (Phi holding gamma; None: zeros), the input's rate of that order added on the
    driver rows."""
    for r in range(T.prow.size):
        if base is None:
            for l in range(L):
                rhs[r, l] = 0.0
        else:
            pr = T.prow[r]
            for l in range(L):
                rhs[r, l] = base[pr, l]
    every = inputs.shape[0] > 1  # (else one row of rates: the same for every value)
    for d in range(T.drv.size):
        dr, di = T.drv[d], T.drv_inp[d]
        for l in range(L):
            rhs[dr, l] += inputs[I[l] if every else 0, di]
    _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L)
    for l in range(L):
        if want[l]:
            for k in range(out.shape[1]):
                out[I[l], k] = x[k, l]


# the rows of the lanes' numbers lv (each (L,)): what each value's last step left, this step's, then
# the work rows of _factor (the last also the running sums of _forms and _solve)
(LV_RES, LV_RED, LV_SING, LV_BRANCH, LV_STEP, LV_OFF, LV_MOVE, LV_NEW_RES, LV_NEW_RED, LV_NEW_SING, LV_NEW_STEP,
 LV_NEW_OFF, LV_FACTOR) = range(13)
LV_ROWS = LV_FACTOR + 9


@numba.njit(**dict(_JIT, _nrt=False))
def _values(lo, hi, rows, mode, steps, ADJ, G, HQ, KU, SA, tol, step_tol, reach, Q, U, Ud, Udd, rates, QD, QDD, RES,
            SIGNS, SING, BRANCH, STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE, T, W):
    """Values rows[lo:hi] (value m of this call is row i of the arrays it writes; STEP, OFF,
    RED, OK: value m) of the plan's tables T, started as ``mode``
    says: FINAL from the poses Q; BULK from the Hermite guesses between the anchors G (HQ their
    coefficients, ADJ, SA: see :func:`planar.compiled.fill`); KNOWN from the Taylor predictor
    of the pose known at the input in KU nearest each value (HQ: its q, dq/du, d2q/du2; SA:
    the branch's modes; a value further than ``reach`` from every known input, or whose
    nearest is as near as another with a lower input, the lower's); WALK: rows[lo:hi] are
    designs, each a lane stepping through its G.size stations (design d's station s: row
    d * G.size + s of the arrays it writes), the first from its sketch in Q, each later one
    from the Taylor predictor of the station before (its q, and its rates at a unit input rate
    in QD and QDD), accepted while it is SOLVED, clear of other solution curves and on its
    branch (the first station's modes, written into SA[d]); OK[m]: design rows[m] walked every
    station. With the buffers W of :func:`_buffers`, in groups of L (the lanes):
    every table entry is read once per group, and the innermost loops run over the lanes. A
    group steps while any of its values does; a value that has stopped keeps its last step's
    numbers. Allocates nothing, so it is compiled without numba's reference counting
    (``_nrt``): with it, each array passed to a helper and each view took an atomic increment
    and decrement per value, on counters the threads share."""
    fb, c, phi, jac, g, Phi, Jv, rhs, x, z, y, A, P, q, qg, sg, dets, ref, aref, E, V, zs, xl, ics, lv, I, des, anc, \
        its, sts, live, act = W
    L = q.shape[1]
    near = mode == BULK  # (cos and sin from the anchor's: _frames)
    n = T.dims[D_N]
    res, red, sing, branch, step, off, move = lv[LV_RES], lv[LV_RED], lv[LV_SING], lv[LV_BRANCH], lv[LV_STEP], \
        lv[LV_OFF], lv[LV_MOVE]
    new_res, new_red, new_sing, new_step, new_off = lv[LV_NEW_RES], lv[LV_NEW_RED], lv[LV_NEW_SING], \
        lv[LV_NEW_STEP], lv[LV_NEW_OFF]
    fw = lv[LV_FACTOR:]
    w = fw[8]
    a_prev, a_ref = -1, -1  # the previous value's anchor interval, and that of aref, u0 and iu
    u0, iu = 0.0, 0.0
    S = G.size if mode == WALK else 1  # a group's stations
    for gs in range((hi - lo + L - 1) // L * S):  # each group of values, at each station
        m0, station = lo + gs // S * L, gs % S
        for l in range(L):  # the group's values into the lanes: guesses (bulk) or poses
            m = m0 + l
            live[l] = act[l] = False
            if m >= hi or (mode == WALK and station > 0 and not OK[m]):
                continue
            i = rows[m] * S + station
            I[l], des[l] = i, _design(T, U[i])
            if mode == BULK:
                # the anchors around the value: G[a] < i <= G[a + 1], by binary search; the rows
                # come sorted, so first whether the value lies in the previous value's interval
                lo_, hi_ = 0, G.size
                if a_prev >= 0 and G[a_prev] < i:
                    lo_ = a_prev + 1
                    if lo_ < hi_ and G[lo_] >= i:
                        hi_ = lo_
                while lo_ < hi_:
                    mid = (lo_ + hi_) // 2
                    if G[mid] < i:
                        lo_ = mid + 1
                    else:
                        hi_ = mid
                a = lo_ - 1
                if a < 0 and G.size > 1 and G[0] == i:  # the first anchor: its interval's start (t = 0)
                    a = 0
                a_prev = a
                if a < 0 or a + 1 >= G.size or not ADJ[a]:  # no interval to interpolate in: the general path
                    OK[m] = False
                    if not SOLVED[i]:
                        Q[i, :] = np.nan
                    continue
                anc[l] = a
                # the quintic Hermite guess between anchors a and a + 1 (HQ: planar.sweep.anchors.quintic
                # and _horner), and the predicted move from a
                if a != a_ref:  # the interval's start and 1 / length; the anchor's angles, their cos
                    # and sin: the reference of _frames
                    u0 = U[G[a], 0]
                    iu = 1.0 / (U[G[a + 1], 0] - u0)
                    for b in range(1, aref.shape[0]):
                        aref[b, 0] = HQ[a, 0, 3 * b - 1]
                        aref[b, 1], aref[b, 2] = _cos_sin(aref[b, 0])
                    a_ref = a
                for b in range(1, aref.shape[0]):
                    ref[b, 0, l], ref[b, 1, l], ref[b, 2, l] = aref[b, 0], aref[b, 1], aref[b, 2]
                t = (U[i, 0] - u0) * iu
                for j in range(HQ.shape[2]):  # Horner's rule, highest power first
                    v = HQ[a, 5, j]
                    for k in range(4, -1, -1):
                        v = HQ[a, k, j] + t * v
                    q[j, l] = qg[j, l] = v
                mv = 0.0
                for k in range(T.pcols.size):
                    col = T.pcols[k]
                    mv = _mx(mv, abs((q[col, l] - HQ[a, 0, col]) * ics[k]))
                move[l] = mv
            elif mode == KNOWN:
                u, k, best = U[i, 0], -1, np.inf
                for j in range(KU.size):  # the nearest known input (as planar.tracking.Poses.nearest)
                    d = abs(u - KU[j])
                    if d < best or (d == best and KU[j] < KU[k]):
                        k, best = j, d
                if not best <= reach:  # (NaN: no pose is near)
                    OK[m] = False
                    continue
                du, anc[l], mv = u - KU[k], 0, 0.0
                for j in range(n):
                    q[j, l] = qg[j, l] = HQ[k, 0, j] + HQ[k, 1, j] * du + 0.5 * HQ[k, 2, j] * du**2
                for k2 in range(T.pcols.size):
                    col = T.pcols[k2]
                    mv = _mx(mv, abs((q[col, l] - HQ[k, 0, col]) * ics[k2]))
                move[l] = mv
            elif mode == WALK and station > 0:
                # the cubic Taylor predictor from the station before (p): its third derivative
                # from the change of the second over the step before that (none at the first)
                p, anc[l], mv = i - 1, rows[m], 0.0
                pp = p - 1 if station > 1 else p
                du, back = U[i, 0] - U[p, 0], U[p, 0] - U[pp, 0]
                c3 = du / (6.0 * back) if back != 0.0 else 0.0
                for j in range(n):
                    q[j, l] = qg[j, l] = Q[p, j] + du * (QD[p, j] + du * (0.5 * QDD[p, j] + c3 * (QDD[p, j] -
                                                                                              QDD[pp, j])))
                for k in range(T.pcols.size):
                    col = T.pcols[k]
                    mv = _mx(mv, abs((q[col, l] - Q[p, col]) * ics[k]))
                move[l] = mv
            else:
                for j in range(n):
                    q[j, l] = qg[j, l] = Q[i, j]
                anc[l], move[l] = rows[m], 0.0
                if mode == WALK:
                    OK[m] = True
            live[l] = act[l] = True
        for it in range(1, steps + 1):
            _evaluate(T, q, U, I, des, act, fb, Phi, Jv, c, phi, jac, ref, near, L)
            for l in range(L):
                new_res[l], new_red[l] = 0.0, 0.0
            for r in range(T.prow.size):
                pr, rs = T.prow[r], T.rs[r]
                for l in range(L):
                    rhs[r, l] = Phi[pr, l]
                    new_res[l] = _mx(new_res[l], abs(rhs[r, l] * rs))
            for r in range(T.red.size):
                pr, rs = T.red[r], T.red_scale[r]
                for l in range(L):
                    new_red[l] = _mx(new_red[l], abs(Phi[pr, l] * rs))
            # the singularity measure and the modes
            _factor(T, Jv, act, A, P, dets, E, V, fw, new_sing, L)
            _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L)
            for l in range(L):
                new_step[l], new_off[l] = 0.0, 0.0
            # the step's size, and the distance the pose moves (its finite components)
            for k in range(T.pcols.size):
                col, ic = T.pcols[k], ics[k]
                for l in range(L):
                    s = abs(x[col, l] * ic)
                    new_step[l] = _mx(new_step[l], s)
                    new_off[l] = _pick(np.isfinite(s), _mx(new_off[l], s), new_off[l])
            for k in range(n):
                for l in range(L):
                    q[k, l] -= _pick(act[l] and np.isfinite(x[k, l]), x[k, l], 0.0)
            more = False
            for l in range(L):  # the active values keep this step's numbers
                if not act[l]:
                    continue
                res[l], red[l], sing[l], step[l], off[l], its[l] = new_res[l], new_red[l], new_sing[l], new_step[l], \
                    new_off[l], it
                br = 1.0
                for b in range(dets.shape[0]):
                    sg[b, l] = 1 if dets[b, l] > 0 else (-1 if dets[b, l] < 0 else 0)  # NaN: 0, as planar.blocks
                    br *= sg[b, l]
                branch[l] = br
                # a batch value whose guess is off by more than rounding (but little) takes more
                # steps; otherwise, Newton (planar.solver.newton) to its tolerances, while the
                # pose is finite
                if mode == BULK:
                    act[l] = ROUND < step[l] <= CLOSE
                else:
                    act[l] = not ((res[l] <= tol and step[l] <= step_tol) or not (step[l] < np.inf and res[l] < np.inf))
                more |= act[l]
            if not more:
                break
        for l in range(L):  # the values out of the lanes
            if not live[l]:
                continue
            m, i = m0 + l, I[l]
            RES[i], SING[i], BRANCH[i] = res[l], sing[l], branch[l]
            sts[l] = 0
            if mode != FINAL:
                o = 0.0  # how far the steps moved the guess
                for k in range(T.pcols.size):
                    col = T.pcols[k]
                    o = _mx(o, abs((q[col, l] - qg[col, l]) * ics[k]))
                # planar.sweep's acceptance of a batch value: converged, the source anchor's modes,
                # no further from the guess than JUMP times the predicted move, certified on its
                # branch; from a known pose, with no event at it (status SOLVED or NEAR_SINGULAR)
                sts[l] = status_of(sing[l], red[l], tol)
                if mode == WALK and station == 0:  # a design's sketch: its modes are its branch's
                    for b in range(sg.shape[0]):
                        SA[anc[l], b] = sg[b, l]
                ok = res[l] <= tol and step[l] <= ROUND and on_course(o, move[l]) and certified(o, sing[l])
                for b in range(sg.shape[0]):
                    ok = ok and sg[b, l] == SA[anc[l], b]
                if mode == KNOWN:
                    ok = ok and sts[l] <= ST_NEAR_SINGULAR
                elif mode == WALK:  # a design batched only where every station is regular
                    ok = ok and sts[l] == ST_SOLVED and sing[l] >= NEAR_CURVE
                OK[m] = ok
                if not ok:  # left for the general path: no pose here yet (or the anchor's own, with its modes)
                    live[l] = False
                    if mode == BULK and not SOLVED[i]:
                        Q[i, :] = np.nan
                        for b in range(sg.shape[0]):
                            SIGNS[i, b] = sg[b, l]
                    continue
                STATUS[i] = sts[l]
                if mode == BULK:
                    SOLVED[i], DONE[i] = True, True
            else:
                STEP[m], OFF[m], RED[m] = step[l], off[l], red[l]
            for j in range(n):
                Q[i, j] = q[j, l]
            for b in range(sg.shape[0]):
                SIGNS[i, b] = sg[b, l]
            ITERS[i] = its[l]
        if not rates:
            continue
        # velocities: the input rates on the driver rows; accelerations: gamma at the corrected
        # pose and the velocities (x, as the first solve left them), input accelerations added
        _rate(T, None, Ud, I, live, QD, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L)
        _gammas(T, q, x, U, I, des, live, fb, Phi, c, g, ref, near, L)
        _rate(T, Phi, Udd, I, live, QDD, Jv, A, P, E, rhs, x, z, y, zs, xl, w, L)
        for l in range(L):
            if live[l] and sts[l] > ST_BRANCH_EVENT:  # no rates on a singular or inconsistent pose
                QD[I[l], :] = np.nan
                QDD[I[l], :] = np.nan


@numba.njit(**_JIT)
def _buffers(T, L):
    """The work arrays of one chunk's values (:func:`_values`) in L lanes: the last axis, but
    for the kernels' arrays (each lane's contiguous, as a kernel reads it). Compiled apart from
    the loop, with numba's reference counting (it allocates)."""
    D = T.dims
    nb, kmax, rmax, n = T.blk.shape[0], D[D_KMAX], D[D_RMAX], D[D_N]
    fb = np.zeros((L, D[D_BODIES], 8))  # (lane first: each lane's is a kernel's contiguous array)
    fb[:, 0, 3] = 1.0  # the ground: at the origin, unrotated
    # (a row order in P from the start: the solves run on every lane, factored or not)
    A, P, E, V = np.empty((nb, L, rmax, rmax)), np.zeros((nb, L, rmax), np.int64), np.empty((T.form0.size + 1, L)), \
        np.empty((D[D_NV] + 1, L))
    lv = np.empty((LV_ROWS, L))
    act = np.ones(L, np.bool_)
    _constants(T, A, P, E, V, lv[LV_FACTOR + 8], lv[LV_FACTOR], act)
    jr = D[D_JROWS]  # a joint's row constants, rows, Jacobian block and gamma
    return (fb, np.empty(jr), np.empty((L, jr)), np.empty((L, jr, 3 * D[D_JBODIES])), np.empty((L, jr)),
            np.zeros((D[D_M], L)), np.zeros((D[D_NNZ], L)), np.empty((T.prow.size, L)), np.zeros((n + 1, L)),
            np.empty((kmax, L)), np.empty(rmax), A, P, np.empty((n, L)), np.empty((n, L)), np.empty((nb, L), np.int8),
            np.empty((nb, L)), np.zeros((D[D_BODIES], 3, L)), np.zeros((D[D_BODIES], 3)), E, V, np.empty(rmax),
            np.empty((kmax, L)), 1.0 / T.cs, lv, np.zeros(L, np.int64), np.zeros(L, np.int64), np.zeros(L, np.int64),
            np.zeros(L, np.int64), np.zeros(L, np.int64), np.zeros(L, np.bool_), act)


def chunk(N, least=MIN_CHUNK):
    """Values per task of :func:`loop` for a call of N values: CHUNK, fewer to give every thread
    one, down to ``least``."""
    if N <= least:
        return least
    threads = numba.get_num_threads()
    return min(CHUNK, max(least, (N + threads - 1) // threads))


def loop(C, size, rows, *args):
    """The values (``args``: :func:`_values`' after rows, up to the tables) of the plan C
    (:class:`planar.compiled.Compiled`) in chunks of ``size`` (:func:`chunk`) on numba's number
    of threads (:func:`spread`), each chunk with its thread's buffers."""
    def run(lo, hi):
        _values(lo, hi, rows, *args, C.T, C.work(min(LANES, hi - lo)))

    spread(rows.shape[0], size, run)


def spread(N, size, run):
    """run(lo, hi) over 0..N in chunks of ``size`` on numba's number of threads; a chunk or
    less on the calling thread. Python's threads (the machine code releases the GIL): numba's
    parallel loop compiled the loop twice more, for twice the compile time."""
    threads = numba.get_num_threads()
    if N <= size or threads == 1:
        for lo in range(0, N, size):
            run(lo, min(N, lo + size))
        return
    if threads not in _POOLS:
        _POOLS[threads] = ThreadPoolExecutor(threads, thread_name_prefix="planar")
    for _ in _POOLS[threads].map(lambda lo: run(lo, min(N, lo + size)), range(0, N, size)):
        pass


_POOLS: dict = {}  # number of threads -> their pool, kept for the process's later sweeps


_ready = False


def ready():
    """Compile the engine (once per installation: numba caches it on disk) or load it, saying
    so on stderr, with the time it has taken every 10 s, while it compiles."""
    global _ready
    if _ready:
        return
    _ready = True
    stamp = _stamp()
    if not _missing(stamp):
        return
    start = time.perf_counter()
    _say("planar: compiling the numba engine, once per installation (about half a minute; every later sweep, of any "
         "mechanism, loads it)")
    done = threading.Event()

    def tick():
        while not done.wait(10.0):
            _say(f"planar: compiling the numba engine: {time.perf_counter() - start:.0f} s")

    threading.Thread(target=tick, daemon=True).start()
    try:
        _compile(stamp)
    finally:
        done.set()
    _say(f"planar: compiled the numba engine in {time.perf_counter() - start:.0f} s")


def _say(line):
    sys.stderr.write(line + "\n")
    sys.stderr.flush()


def _stamp_file():
    return os.path.join(_values._cache._cache_path, "engine.planar-stamp")


def _missing(stamp):
    """Whether the machine code on disk is missing or stale: numba keys its cache on this file
    only, so a stamp of the rest (:func:`_stamp`) is kept beside it."""
    try:
        with open(_stamp_file()) as f:
            same = f.read() == stamp
    except OSError:
        same = False
    return not (same and all(fn._cache._cache_file._load_index() for fn in _ENTRIES))


def _compile(stamp):
    """Drop the cached code (the designs' assembly's too: it compiles in the LU), compile
    afresh (numba caches it) and stamp it."""
    from planar.compiled import assembly

    for fn in _ENTRIES + (assembly._follow,):
        fn._cache.flush()
    _warm()
    try:
        with open(_stamp_file(), "w") as f:
            f.write(stamp)
    except OSError:  # an unwritable cache: this process keeps what it compiled
        pass


def _warm():
    """Compile the loop and its buffers (one signature each) by a call on the sketch of a four-bar."""
    from planar.blocks import plan
    from planar.compiled import final
    from planar.mechanisms import four_bar

    model = four_bar().compile()
    q, U = model.q0[None].copy(), model.u0[None].copy()
    final(model, plan(model), q, U, np.ones_like(U), np.zeros_like(U))


_ENTRIES = (_values, _buffers, _evaluate, _gammas, _factor, _solve)  # the functions compiled and cached


def _stamp():
    """A hash of what the cached machine code compiles in besides this file: every joint type's
    kernels and their shared pieces, the LU, the acceptance and status rules and the constants."""
    modules = {sys.modules[cls.__module__] for cls in kinds()} | {scalar, sys.modules[lu.__module__]}
    text = "".join(sorted(inspect.getsource(m) for m in modules)) + "".join(map(inspect.getsource, SHARED))
    text += repr(([c.__name__ for c in kinds()], CERT, JUMP, ROUND, NEAR, NEAR_CURVE, SINGULAR, HELD, list(Status)))
    return hashlib.sha1(text.encode()).hexdigest()
