"""The sketches of many designs assembled in machine code (``engine="numba"``): the steps and
tests of :func:`planar.designs.assembly.follow`, design by design, on the same
:class:`planar.designs.assembly.Rows`; J J^T factored by :mod:`planar.lu`'s LU, the compiled
engine's (a rank-deficient J, redundant lengths, by numpy's pseudo-inverse).

Results agree with the numpy engine's to rounding (the LU's det where numpy's is LAPACK's).
Compiled on the first study of dimensioned designs in the compiled engine, and cached on disk
by numba beside the engine (:func:`planar.compiled.engine.ready` drops it with the engine's
when the LU changes).

>>> import numpy as np
>>> from planar.designs.assembly import LENGTH, Rows
>>> X0 = np.array([[[0.0, 0.0], [1.0, 0.0]]])                  # one design, two sites
>>> B = np.array([[[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]])  # the second free
>>> one, none = np.ones((1, 1), int), np.zeros((1, 2))
>>> rows = Rows(X0, B, np.array([LENGTH]), one[0] * 0, one[0], one[0] * 0, none, none.astype(int),
...             none.astype(int), np.zeros((1, 1)), np.zeros((1, 1, 2)), np.zeros((1, 1, 2)), np.ones(1))
>>> z, alive = np.zeros((1, 2)), np.ones(1, bool)
>>> follow(rows, np.ones((1, 1)), np.full((1, 1), 2.0), z, alive)  # the length from 1 to 2
>>> bool(alive[0]), np.round(z, 12).tolist()
(True, [[1.0, 0.0]])
"""

import numba
import numpy as np

from planar.compiled import engine
from planar.designs.assembly import ANGLE, CLOSED, FIRST, FULL_RANK, GROW, HELD, ITERATIONS, LENGTH, LONGEST, MOVE


def follow(rows, start, goal, z, alive):
    """As :func:`planar.designs.assembly.follow`: z (D, c) and ``alive`` (D,) in place."""
    engine.ready()
    r, start, goal = rows, np.ascontiguousarray(start), np.ascontiguousarray(goal)

    def run(lo, hi):
        _follow(lo, hi, r.X0, r.B, r.kind, r.a, r.b, r.terms, r.sign, r.i, r.j, r.offset, r.origin, r.direction,
                r.L, start, goal, z, alive)

    engine.spread(z.shape[0], engine.chunk(z.shape[0]), run)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _follow(lo, hi, X0, B, kind, a, b, terms, sign, i, j, offset, origin, direction, L, start, goal, z, alive):
    """Designs lo..hi."""
    S = X0.shape[1]
    m, c = kind.size, B.shape[2]
    X, r, target = np.empty((S, 2)), np.empty(m), np.empty(m)
    G, J, A = np.empty((m, 2 * S)), np.empty((m, c)), np.empty((m, m))
    perm, y, dx = np.empty(m, np.int64), np.empty(m), np.empty(c)
    for d in range(lo, hi):
        t, dt = 0.0, FIRST
        while t < 1.0:
            step = min(dt, 1.0 - t)
            for k in range(m):
                target[k] = start[d, k] + (t + step) * (goal[d, k] - start[d, k])
            for _ in range(ITERATIONS):
                _sites(X0[d], B[d], z[d], X)
                if not _residuals(X, d, kind, a, b, terms, sign, i, j, offset, origin, direction, L, target, r) > HELD:
                    break
                _jacobian(X, B[d], d, kind, a, b, terms, sign, i, j, direction, L, G, J)
                _min_norm(J, r, A, perm, y, dx)
                big = 0.0
                for k in range(c):
                    big = max(big, abs(dx[k]))
                f = min(1.0, MOVE / max(big, 1e-300))
                for k in range(c):
                    z[d, k] -= dx[k] * f * L[d]
            _sites(X0[d], B[d], z[d], X)
            if not _residuals(X, d, kind, a, b, terms, sign, i, j, offset, origin, direction, L, target, r) <= CLOSED:
                alive[d] = False
                break
            t, dt = t + step, min(GROW * step, LONGEST)


@numba.njit(inline="always")
def _sites(X0, B, z, X):
    for s in range(X0.shape[0]):
        for e in range(2):
            v = 0.0
            for k in range(z.size):
                if B[2 * s + e, k] != 0.0:  # (most are: a site moves along one or two of the coordinates)
                    v += B[2 * s + e, k] * z[k]
            X[s, e] = X0[s, e] + v


@numba.njit(inline="always")
def _residuals(X, d, kind, a, b, terms, sign, i, j, offset, origin, direction, L, target, r):
    """The scaled residuals into r, and their largest magnitude (NaN if any is)."""
    big = 0.0
    for k in range(kind.size):
        if kind[k] == LENGTH:
            v = np.hypot(X[b[k], 0] - X[a[k], 0], X[b[k], 1] - X[a[k], 1]) - target[k]
        elif kind[k] == ANGLE:
            s = 0.0
            for n in range(terms[k]):
                p, q = i[k, n], j[k, n]
                s += sign[k, n] * np.arctan2(X[q, 1] - X[p, 1], X[q, 0] - X[p, 0])
            v = offset[d, k] + s - target[k]
            v = (v + np.pi) % (2 * np.pi) - np.pi
        else:
            v = (X[a[k], 0] - origin[d, k, 0]) * direction[d, k, 0] + (X[a[k], 1] - origin[d, k, 1]) * direction[d, k, 1]
            v -= target[k]
        r[k] = v if kind[k] == ANGLE else v * (1.0 / L[d])
        big = engine._mx(big, abs(r[k]))
    return big


@numba.njit(inline="always")
def _jacobian(X, B, d, kind, a, b, terms, sign, i, j, direction, L, G, J):
    """d residuals / dz times L into J, through the sites' G (m, 2S)."""
    G[:] = 0.0
    for k in range(kind.size):
        if kind[k] == LENGTH:
            ex, ey = X[b[k], 0] - X[a[k], 0], X[b[k], 1] - X[a[k], 1]
            h = max(np.hypot(ex, ey), 1e-300)
            ex, ey = ex / h, ey / h
            G[k, 2 * a[k]] -= ex
            G[k, 2 * a[k] + 1] -= ey
            G[k, 2 * b[k]] += ex
            G[k, 2 * b[k] + 1] += ey
        elif kind[k] == ANGLE:
            for n in range(terms[k]):
                p, q = i[k, n], j[k, n]
                ex, ey = X[q, 0] - X[p, 0], X[q, 1] - X[p, 1]
                h = max(ex * ex + ey * ey, 1e-300)
                gx, gy = sign[k, n] * -ey / h, sign[k, n] * ex / h
                G[k, 2 * p] -= gx
                G[k, 2 * p + 1] -= gy
                G[k, 2 * q] += gx
                G[k, 2 * q + 1] += gy
        else:
            G[k, 2 * a[k]] += direction[d, k, 0]
            G[k, 2 * a[k] + 1] += direction[d, k, 1]
    for k in range(kind.size):
        s = L[d] if kind[k] == ANGLE else (1.0 / L[d]) * L[d]
        J[k] = 0.0
        for e in range(G.shape[1]):
            if G[k, e] != 0.0:  # (a row moves two to four sites)
                for col in range(J.shape[1]):
                    J[k, col] += G[k, e] * B[e, col]
        for col in range(J.shape[1]):
            J[k, col] *= s


@numba.njit(inline="always")
def _min_norm(J, r, A, perm, y, dx):
    """dx = J+ r: J^T (J J^T)^-1 r where J's rows are independent, else by the pseudo-inverse."""
    m, c = J.shape
    diag = 1.0
    for p in range(m):
        for q in range(p + 1):
            v = 0.0
            for k in range(c):
                v += J[p, k] * J[q, k]
            A[p, q], A[q, p] = v, v
        diag *= A[p, p]
    if engine._lu_det(A, perm, m) / diag > FULL_RANK:
        engine._lu_solve(A, perm, r, y, m)
        for k in range(c):
            v = 0.0
            for p in range(m):
                v += J[p, k] * y[p]
            dx[k] = v
    else:
        dx[:] = np.linalg.pinv(J) @ r
