"""The compiled engine's machine code: one loop over values, reading a plan's tables
(:class:`planar.compiled.Tables`), compiled once and cached on disk by numba.

Imported on the first ``engine="numba"`` sweep (it imports numba). :func:`ready` compiles the
loop, or loads it from numba's cache, saying so on stderr when it compiles.

One module of more than 400 lines because it is one compilation unit: numba's on-disk cache is
keyed on this file alone, so the loop and the pieces it inlines live here, and what it compiles
in from elsewhere (the joints' kernels, the shared rules) is hashed by :func:`_stamp`.
"""

import hashlib
import inspect
import os
import sys
import threading
import time

import numba
import numpy as np
from numba.extending import register_jitable

from planar.acceptance import CERT, JUMP, ROUND, certified, on_course
from planar.compiled import CHUNK, D_BODIES, D_DESIGN, D_JBODIES, D_JROWS, D_KMAX, D_M, D_N, D_NNZ, D_NV, D_RMAX
from planar.compiled import MIN_CHUNK, kinds
from planar.compiled import B_ANGLE, B_CO, B_FO, B_K, B_LENGTHS, B_LO, B_NF, B_NL, B_NS, B_NV, B_NW, B_O, B_R
from planar.compiled import B_RO, B_SO, B_UO, B_VO, B_WEIGHTED
from planar.events import HELD, NEAR, SINGULAR, status_of
from planar.joints import scalar
from planar.lu import lu
from planar.results import Status

NEAR_ANGLE = 0.05  # a bulk value's angles within this of its anchor's: cos and sin from the anchor's
CLOSE = 1e-4  # a batch value takes more Newton steps while its last one (scaled) is below this
ST_BRANCH_EVENT = int(Status.BRANCH_EVENT)  # the last status with rates

# fast-math's "contract" only: LLVM may fuse a * b + c into one fused multiply-add (one rounding
# instead of two); no other fast-math licence (the NaN and inf tests stay exact, nothing is
# reassociated)
_JIT: dict = dict(cache=True, error_model="numpy", nogil=True, fastmath={"contract"})
# the joints' kernels and their pieces (plain functions: numba compiles them where the loop calls
# them) and the loop's own pieces, inlined by numba (as separate functions they took 2-3x the time)
_piece = register_jitable(inline="always", error_model="numpy")
_inline = numba.njit(inline="always", error_model="numpy")

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
def _frames(q, qd, rates, fb, ref, near):
    """The bodies' rows of ``fb``: x, y, angle, its cos and sin (and with ``rates`` the body's
    velocity). cos and sin by ``_cos_sin``; ``near`` (a bulk value: within NEAR_ANGLE of its
    anchor's angles ``ref``): by the angle-addition formulas from the anchor's cos and sin, with
    the Taylor series of the difference d to d^9 (the first term left out, d^10 / 10!, is below
    1e-19 there): half the time of a tan, and as accurate."""
    for b in range(1, fb.shape[0]):
        x = 3 * b - 3
        a = x + 2
        d = q[a] - ref[b, 0]
        if near and abs(d) <= NEAR_ANGLE:
            d2 = d * d
            sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0)
                                                                             * (1.0 - d2 * (1.0 / 72.0)))))
            cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))))
            co, si = ref[b, 1] * cd - ref[b, 2] * sd, ref[b, 2] * cd + ref[b, 1] * sd
        else:
            co, si = _cos_sin(q[a])
        fb[b, 0], fb[b, 1], fb[b, 2], fb[b, 3], fb[b, 4] = q[x], q[x + 1], q[a], co, si
        if rates:
            fb[b, 5], fb[b, 6], fb[b, 7] = qd[x], qd[x + 1], qd[a]


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


@_inline
def _evaluate(T, q, u, fb, Phi, Jv, c, phi, jac, ref, near):
    """Phi at q, and the Jacobian entries factor and solve read into Jv: each joint's kernel."""
    _frames(q, q, False, fb, ref, near)
    d = _design(T, u)
    for j in range(T.code.size):
        _row_constants(T, d, j, u, c)
        _rows(T.code[j], T.par[d, j], c, fb, T.slots[j], phi, jac)
        for r in range(T.nr[j]):
            Phi[T.jrows[j, r]] = phi[r]
        for e in range(T.jac_at[j], T.jac_at[j + 1]):
            Jv[T.jac_to[e]] = jac[T.jac_r[e], T.jac_c[e]]


@_inline
def _gammas(T, q, qd, u, fb, Phi, c, g, ref, near):
    """gamma at q and the velocities qd into Phi: each joint's gamma kernel."""
    _frames(q, qd, True, fb, ref, near)
    d = _design(T, u)
    for j in range(T.code.size):
        _row_constants(T, d, j, u, c)
        _gamma(T.code[j], T.par[d, j], c, fb, T.slots[j], g)
        for r in range(T.nr[j]):
            Phi[T.jrows[j, r]] = g[r]


@_inline
def _forms(T, b, Jv, A, P, E, V):
    """Block b's variables' scaled values into V, its forms' values into E (the Schur
    complement's into A too) and the LU of the Schur complement: its det."""
    B = T.blk[b]
    vo, fo, r = B[B_VO], B[B_FO], B[B_R]
    for i in range(B[B_NV]):
        V[i] = Jv[T.var[vo + i]] * T.vscale[vo + i]
    for f in range(fo, fo + B[B_NF]):
        e = T.form0[f]
        for t in range(T.form_at[f], T.form_at[f + 1]):
            e += V[T.term_v[t]] * T.term_c[t]
        E[f] = e
    for i in range(r):
        for j in range(r):
            A[b, i, j] = E[fo + i * r + j]
    return _lu_det(A[b], P[b], r) if r else 1.0


@_inline
def _constants(T, A, P, E, V):
    """The factors of the blocks of constants (no variables), once per buffer."""
    for b in range(T.blk.shape[0]):
        if T.blk[b, B_NV] == 0:
            _forms(T, b, E, A, P, E, V)  # (no variable reads Jv)


@_inline
def _factor(T, Jv, A, P, dets, E, V):
    """Each block by its elimination program (planar.elimination.Program._factor): the
    variables' scaled values, the forms' values, the LU of the Schur complement and the det's
    normalisation; the blocks of constants were factored once (:func:`_constants`). Returns the
    singularity measure: the smallest normalised |det|, kept as sn / sd (the blocks' squared
    normalised dets dd / nm; NaN stays NaN), so one square root and one division per value."""
    sn, sd = 1.0, 1.0
    for b in range(T.blk.shape[0]):
        B = T.blk[b]
        if B[B_NV] == 0:  # a block of constants: its det was normalised once
            dets[b] = T.det_c[b]
            dd, nm = dets[b] * dets[b], 1.0
        else:
            det = T.det0[b] * _forms(T, b, Jv, A, P, E, V)
            lam = 1.0
            if B[B_ANGLE]:  # the largest angle-column entry, at least lam's constant part, at most 1
                lam = T.lam_c[b]
                for t in range(B[B_LO], B[B_LO] + B[B_NL]):
                    lam = _mx(lam, abs(V[T.lam_v[t]]))
                lam = -_mx(-lam, -1.0)
            nm = 1.0
            for i in range(B[B_O], B[B_O] + B[B_K]):
                s0 = T.nc0[i]
                for t in range(T.n0_at[i], T.n0_at[i + 1]):
                    s0 += V[T.n0_v[t]] * V[T.n0_v[t]]
                if B[B_WEIGHTED]:
                    s1 = T.nc1[i]
                    for t in range(T.n1_at[i], T.n1_at[i + 1]):
                        s1 += V[T.n1_v[t]] * V[T.n1_v[t]]
                    s0 += s1 * lam * lam
                nm *= s0
            # the normalised det nd = det / sqrt(nm) * lam**lengths, capped by lam, as its square
            # dd / nm (the sign in dets; nm <= 0 reads 0 as in planar.elimination)
            dd = det * det if nm > 0 else 0.0
            for _ in range(B[B_LENGTHS]):
                dd *= lam * lam
            if dd > lam * lam * nm:
                dd, nm = lam * lam, 1.0
            dets[b] = det if dd > 0 else 0.0
        if dd * sd < sn * nm or dd != dd:
            sn, sd = dd, nm
    return np.sqrt(sn / sd)


@_inline
def _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl):
    """x = J^-1 rhs forward through the blocks (planar.elimination.Program.solve each)."""
    zero = T.dims[D_NNZ] - 1  # the structural zero's slot
    for b in range(T.blk.shape[0]):
        B = T.blk[b]
        k, o, nw, uo, co, fo, r, ro, so, ns = B[B_K], B[B_O], B[B_NW], B[B_UO], B[B_CO], B[B_FO], B[B_R], B[B_RO], \
            B[B_SO], B[B_NS]
        if k == 1:  # most blocks (pivots, driven coordinates): one row, by its pivot or its 1x1 LU
            s = rhs[T.eqs[o]]
            for w in range(nw):
                e = T.coup[co + w]
                if e != zero:
                    s -= Jv[e] * x[T.up[uo + w]]
            x[T.cols[o]] = s * T.brs[o] * (T.st_inv[so] if ns else A[b, 0, 0]) * T.bcs[o]
            continue
        for i in range(k):
            s = rhs[T.eqs[o + i]]
            for w in range(nw):
                e = T.coup[co + i * nw + w]
                if e != zero:
                    s -= Jv[e] * x[T.up[uo + w]]
            z[i] = s * T.brs[o + i]
        for st in range(so, so + ns):  # the constant columns' steps
            p = T.st_p[st]
            for t in range(T.mul_at[st], T.mul_at[st + 1]):
                z[T.mul_i[t]] -= T.mul_m[t] * z[p]
        if r:  # the Schur complement
            for j in range(r):
                zs[j] = z[T.srows[ro + j]]
            _lu_solve(A[b], P[b], zs, y, r)
            for j in range(r):
                xl[T.scols[ro + j]] = y[j]
        for st in range(so + ns - 1, so - 1, -1):
            s = z[T.st_p[st]]
            for t in range(T.us_at[st], T.us_at[st + 1]):
                s -= E[fo + T.us_f[t]] * xl[T.us_j[t]]
            xl[T.st_c[st]] = s * T.st_inv[st]
        for i in range(k):
            x[T.cols[o + i]] = xl[i] * T.bcs[o + i]


@_inline
def _rate(T, base, inputs, i, out, Jv, A, P, E, rhs, x, z, y, zs, xl):
    """Solve for a rate into out[i]: right-hand side ``base`` on the plan's rows (Phi holding
    gamma; None: zeros), the input's rate of that order added on the driver rows."""
    for r in range(T.prow.size):
        rhs[r] = 0.0 if base is None else base[T.prow[r]]
    at = i if inputs.shape[0] > 1 else 0  # (one row of rates: the same for every value)
    for d in range(T.drv.size):
        rhs[T.drv[d]] += inputs[at, T.drv_inp[d]]
    _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl)
    for k in range(out.shape[1]):
        out[i, k] = x[k]


@numba.njit(**dict(_JIT, _nrt=False))
def _values(lo, hi, rows, interp, steps, ADJ, G, HQ, SA, tol, step_tol, Q, U, Ud, Udd, rates, QD, QDD, RES, SIGNS,
            SING, BRANCH, STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE, T, W):
    """Values rows[lo:hi] (value m of this call is row i of the arrays it writes; STEP, OFF,
    RED, OK: value m), with the buffers W of :func:`_buffers`. Allocates nothing, so it is
    compiled without numba's reference counting (``_nrt``): with it, each array passed to a
    helper and each view took an atomic increment and decrement per value, on counters the
    threads share."""
    fb, c, phi, jac, g, Phi, Jv, rhs, x, z, y, A, P, qg, qo, so, dets, ref, E, V, zs, xl, ics = W
    n = T.dims[D_N]
    a_prev, a_ref = -1, -1  # the previous value's anchor interval, and that of ref, u0 and iu
    u0, iu = 0.0, 0.0
    for m in range(lo, hi):
        i = rows[m]
        q = Q[i]
        a, move, st = 0, 0.0, 0
        if interp:
            # the anchors around the value: G[a] < i <= G[a + 1], by binary search; the rows come
            # sorted, so first whether the value lies in the previous value's interval
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
                    q[:] = np.nan
                continue
            if SOLVED[i]:  # a solved anchor keeps its pose and modes if this fails
                for j in range(qo.size):
                    qo[j] = q[j]
                for j in range(so.size):
                    so[j] = SIGNS[i, j]
            # the quintic Hermite guess between anchors a and a + 1 (HQ: planar.sweep.anchors.quintic and
            # _horner), and the predicted move from a
            if a != a_ref:  # the interval's start and 1 / length; the anchor's angles, their cos and
                # sin: the reference of _frames
                u0 = U[G[a], 0]
                iu = 1.0 / (U[G[a + 1], 0] - u0)
                for b in range(1, ref.shape[0]):
                    ref[b, 0] = HQ[a, 0, 3 * b - 1]
                    ref[b, 1], ref[b, 2] = _cos_sin(ref[b, 0])
                a_ref = a
            t = (U[i, 0] - u0) * iu
            for j in range(HQ.shape[2]):  # Horner's rule, highest power first
                v = HQ[a, 5, j]
                for k in range(4, -1, -1):
                    v = HQ[a, k, j] + t * v
                q[j] = v
            move = 0.0
            for k in range(T.pcols.size):
                col = T.pcols[k]
                move = _mx(move, abs((q[col] - HQ[a, 0, col]) * ics[k]))
            for j in range(n):
                qg[j] = q[j]
        for it in range(1, steps + 1):
            _evaluate(T, q, U[i], fb, Phi, Jv, c, phi, jac, ref, interp)
            res = 0.0
            for r in range(T.prow.size):
                rhs[r] = Phi[T.prow[r]]
                res = _mx(res, abs(rhs[r] * T.rs[r]))
            red = 0.0
            for r in range(T.red.size):
                red = _mx(red, abs(Phi[T.red[r]] * T.red_scale[r]))
            # the singularity measure and the branch (the product of the signs)
            sing = _factor(T, Jv, A, P, dets, E, V)
            branch = 1.0
            for b in range(dets.size):
                SIGNS[i, b] = 1 if dets[b] > 0 else (-1 if dets[b] < 0 else 0)  # NaN: 0, as planar.blocks
                branch *= SIGNS[i, b]
            _solve(T, Jv, A, P, E, rhs, x, z, y, zs, xl)
            # the step's size, and the distance the pose moves (its finite components)
            step, off = 0.0, 0.0
            for k in range(T.pcols.size):
                s = abs(x[T.pcols[k]] * ics[k])
                step = _mx(step, s)
                if np.isfinite(s):
                    off = _mx(off, s)
            for k in range(n):
                if np.isfinite(x[k]):
                    q[k] -= x[k]
            # a batch value whose guess is off by more than rounding (but little) takes more steps;
            # otherwise, Newton (planar.solver.newton) to its tolerances, while the pose is finite
            if interp:
                if not (ROUND < step <= CLOSE):
                    break
            elif (res <= tol and step <= step_tol) or not (step < np.inf and res < np.inf):
                break
        RES[i], SING[i], BRANCH[i] = res, sing, branch
        if interp:
            off = 0.0  # how far the steps moved the guess
            for k in range(T.pcols.size):
                col = T.pcols[k]
                off = _mx(off, abs((q[col] - qg[col]) * ics[k]))
            # planar.sweep's acceptance of a batch value: converged, the source anchor's modes, no
            # further from the guess than JUMP times the predicted move, certified on its branch
            ok = res <= tol and step <= ROUND and on_course(off, move) and certified(off, sing)
            for b in range(dets.size):
                ok = ok and SIGNS[i, b] == SA[a, b]
            OK[m] = ok
            if not ok:  # left for the general path: no pose here yet (or the anchor's own)
                if SOLVED[i]:
                    for j in range(n):
                        q[j] = qo[j]
                    for j in range(so.size):
                        SIGNS[i, j] = so[j]
                else:
                    q[:] = np.nan
                continue
            st = status_of(sing, red, tol)
            STATUS[i], SOLVED[i], DONE[i] = st, True, True
        else:
            STEP[m], OFF[m], RED[m] = step, off, red
        ITERS[i] = it
        if not rates:
            continue
        # velocities: the input rates on the driver rows; accelerations: gamma at the corrected
        # pose and the velocities, input accelerations added
        _rate(T, None, Ud, i, QD, Jv, A, P, E, rhs, x, z, y, zs, xl)
        _gammas(T, q, QD[i], U[i], fb, Phi, c, g, ref, interp)
        _rate(T, Phi, Udd, i, QDD, Jv, A, P, E, rhs, x, z, y, zs, xl)
        if st > ST_BRANCH_EVENT:  # no rates on a singular or inconsistent pose
            QD[i, :] = np.nan
            QDD[i, :] = np.nan


@numba.njit(**_JIT)
def _buffers(T):
    """The work arrays of one thread's values (:func:`_values`). Compiled apart: inlined into the
    parallel loop, its array expressions would each start the threads, even for a chunk or less."""
    D = T.dims
    nb, kmax, rmax = T.blk.shape[0], D[D_KMAX], D[D_RMAX]
    fb = np.zeros((D[D_BODIES], 8))
    fb[0, 3] = 1.0  # the ground: at the origin, unrotated
    A, P, E, V = np.empty((nb, rmax, rmax)), np.empty((nb, rmax), np.int64), np.empty(T.form0.size + 1), \
        np.empty(D[D_NV] + 1)
    _constants(T, A, P, E, V)
    jr = D[D_JROWS]  # a joint's row constants, rows, Jacobian block and gamma
    return (fb, np.empty(jr), np.empty(jr), np.empty((jr, 3 * D[D_JBODIES])), np.empty(jr), np.zeros(D[D_M]),
            np.zeros(D[D_NNZ]), np.empty(T.prow.size), np.zeros(D[D_N] + 1), np.empty(kmax), np.empty(rmax), A, P,
            np.empty(D[D_N]), np.empty(D[D_N]), np.empty(nb, np.int8), np.empty(nb), np.zeros((D[D_BODIES], 3)), E,
            V, np.empty(rmax), np.empty(kmax), 1.0 / T.cs)


def chunk(N):
    """Values per task of :func:`loop` for a call of N values: CHUNK, fewer to give every thread
    one, down to MIN_CHUNK (asked here: numba cannot cache a loop that asks the thread count)."""
    threads = numba.get_num_threads()
    return min(CHUNK, max(MIN_CHUNK, (N + threads - 1) // threads))


@numba.njit(**dict(_JIT, parallel=True))
def loop(size, rows, interp, steps, ADJ, G, HQ, SA, tol, step_tol, Q, U, Ud, Udd, rates, QD, QDD, RES, SIGNS, SING,
         BRANCH, STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE, T):
    """The values in chunks of ``size`` (:func:`chunk`) on all cores, each chunk with its own
    buffers; a chunk or less on the calling thread (no threads to start)."""
    N = rows.shape[0]
    if N <= size:
        # lo as an int64 variable: the literal 0 would compile _values a second time, for Literal[int]
        _values(np.int64(0), N, rows, interp, steps, ADJ, G, HQ, SA, tol, step_tol, Q, U, Ud, Udd, rates, QD, QDD, RES, SIGNS,
                SING, BRANCH, STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE, T, _buffers(T))
        return
    for chunk in numba.prange((N + size - 1) // size):
        _values(chunk * size, min(N, (chunk + 1) * size), rows, interp, steps, ADJ, G, HQ, SA, tol, step_tol, Q,
                U, Ud, Udd, rates, QD, QDD, RES, SIGNS, SING, BRANCH, STEP, OFF, RED, OK, STATUS, ITERS, SOLVED, DONE,
                T, _buffers(T))


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
    return os.path.join(loop._cache._cache_path, "engine.planar-stamp")


def _missing(stamp):
    """Whether the machine code on disk is missing or stale: numba keys its cache on this file
    only, so a stamp of the rest (:func:`_stamp`) is kept beside it."""
    try:
        with open(_stamp_file()) as f:
            same = f.read() == stamp
    except OSError:
        same = False
    return not (same and all(fn._cache._cache_file._load_index() for fn in (_values, loop)))


def _compile(stamp):
    """Drop the cached code, compile afresh (numba caches it) and stamp it."""
    for fn in (_values, loop):
        fn._cache.flush()
    _warm()
    try:
        with open(_stamp_file(), "w") as f:
            f.write(stamp)
    except OSError:  # an unwritable cache: this process keeps what it compiled
        pass


def _warm():
    """Compile the loop (its one signature) by a call on the sketch of a four-bar."""
    from planar.blocks import plan
    from planar.compiled import final
    from planar.mechanisms import four_bar

    model = four_bar().compile()
    q, U = model.q0[None].copy(), model.u0[None].copy()
    final(model, plan(model), q, U, np.ones_like(U), np.zeros_like(U))


def _stamp():
    """A hash of what the cached machine code compiles in besides this file: every joint type's
    kernels and their shared pieces, the LU, the acceptance and status rules and the constants."""
    modules = {sys.modules[cls.__module__] for cls in kinds()} | {scalar, sys.modules[lu.__module__]}
    text = "".join(sorted(inspect.getsource(m) for m in modules)) + "".join(map(inspect.getsource, SHARED))
    text += repr(([c.__name__ for c in kinds()], CERT, JUMP, ROUND, NEAR, SINGULAR, HELD, list(Status)))
    return hashlib.sha1(text.encode()).hexdigest()
