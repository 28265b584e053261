"""LU with partial pivoting of the small dense blocks left after elimination (a loop's Schur
complement, :mod:`planar.elimination`), written once for both engines.

:func:`lu` makes the factorisation and its solves for one kind of entry: the numpy engine's,
where an entry ``A[i, j]`` is an array over a stage's blocks and poses (``A`` (k, k, G, N)),
and the compiled engine's (:mod:`planar.compiled.engine`), where it is one pose's number. The
algorithm reads values only through ``pick`` (a selection, never a branch on a value); what
moves data (a masked row swap, a gather by the row order) is the engine's own. The pivot is
the first of the largest entries of its column on or below the diagonal; the factors keep
L's multipliers below the diagonal and U's pivots as their reciprocals on it, which the solves
multiply by.

>>> import numpy as np
>>> A = np.array([[1.0, 2.0], [3.0, 4.0]]).reshape(2, 2, 1, 1)
>>> perm = np.empty((2, 1, 1), np.intp)
>>> float(factor(A, perm, 2)[0, 0])                       # the det
-2.0
>>> x = np.empty((2, 1, 1))
>>> solve(A, perm, np.array([5.0, 6.0]).reshape(2, 1, 1), x, 2)
>>> np.round(x.ravel(), 12).tolist()                        # x = A^-1 (5, 6)
[-4.0, 4.5]
"""

import numpy as np


def lu(pick, swap_rows, permute, unpermute):
    """(factor, solve, solve_transpose) for entries that ``pick(c, a, b)`` (a where c, else b)
    selects between; ``swap_rows(A, perm, j, i, c, k)`` exchanges rows j and i of A and perm
    where c; ``permute(z, perm, y, k)`` sets y[i] = z[perm[i]] and ``unpermute(w, perm, y, k)``
    y[perm[i]] = w[i]."""

    def factor(A, perm, k):
        """LU of the leading k x k block of A in place, with partial pivoting (P A = L U, row
        order ``perm``): its det (1 for k = 0). A zero pivot gives non-finite factors and a
        zero det, never an exception."""
        det = 1.0
        for i in range(k):
            perm[i] = i
        for j in range(k):
            piv, best = j, abs(A[j, j])
            for i in range(j + 1, k):
                a = abs(A[i, j])
                larger = a > best
                piv, best = pick(larger, i, piv), pick(larger, a, best)
            for i in range(j + 1, k):
                swap = piv == i
                swap_rows(A, perm, j, i, swap, k)
                det = pick(swap, -det, det)
            det = det * A[j, j]
            r = 1.0 / A[j, j]
            for i in range(j + 1, k):
                m = A[i, j] * r
                A[i, j] = m
                for col in range(j + 1, k):
                    A[i, col] -= m * A[j, col]
            A[j, j] = r
        return det

    def solve(A, perm, z, y, k):
        """y with A y = z for the factors of ``factor``: z taken in the row order, L forward,
        U backward."""
        permute(z, perm, y, k)
        for i in range(1, k):
            for j in range(i):
                y[i] -= A[i, j] * y[j]
        for i in range(k - 1, -1, -1):
            for j in range(i + 1, k):
                y[i] -= A[i, j] * y[j]
            y[i] *= A[i, i]

    def solve_transpose(A, perm, z, y, k):
        """y with A^T y = z (z is overwritten): U^T forward, L^T backward, then the rows put
        back in place."""
        for i in range(k):
            for j in range(i):
                z[i] -= A[j, i] * z[j]
            z[i] *= A[i, i]
        for i in range(k - 1, -1, -1):
            for j in range(i + 1, k):
                z[i] -= A[j, i] * z[j]
        unpermute(z, perm, y, k)

    return factor, solve, solve_transpose


def _swap_rows(A, perm, j, i, c, k):
    # masked copies of whole rows: passes over all poses, where gathers at the swapped poses
    # walk the few rows pose by pose
    if c.any():
        for M in (A, perm):
            top = M[j].copy()
            np.copyto(M[j], M[i], where=c)
            np.copyto(M[i], top, where=c)


def _permute(z, perm, y, k):
    y[:k] = np.take_along_axis(z[:k], perm[:k], axis=0)


def _unpermute(w, perm, y, k):
    np.put_along_axis(y[:k], perm[:k], w[:k], axis=0)


# the numpy engine's: entries (G, N) over a stage's blocks and poses
factor, solve, solve_transpose = lu(np.where, _swap_rows, _permute, _unpermute)
