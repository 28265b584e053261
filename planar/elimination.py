"""LU of the plan's diagonal blocks, structure first: what is constant is eliminated once.

Each Jacobian entry of a block is, at plan time, a structural zero, a constant (the same at
every sampled pose: the +-1 of a revolute's x and y columns, a driver's 1, a gear's radii) or
a variable. A column whose entries are all constants is eliminated first, with its largest as
pivot (the pivot partial pivoting picks), so its multipliers are constants and every entry it
updates stays a linear form in the block's variables with constant coefficients. What is left,
the Schur complement, is factored at each pose with partial pivoting. This is LU with partial
pivoting of the block with its columns reordered (constant ones first): as stable as the
dense one, at a fraction of the work. A four-bar loop's 4x4 block leaves a 2x2; pinned
coordinates and driven angles leave nothing to factor.

The blocks of a stage share one :class:`Program`: the same structure and constants (stages
are grouped by it), each block with its own value slots. Its runtime arrays put the stage's
G blocks second and the poses last.

>>> from planar.mechanisms import four_bar
>>> from planar.blocks import plan
>>> p = plan(four_bar(4, 2, 3.5, 3).compile())
>>> [(st.program.k, len(st.program.rows)) for st in p.stages]  # block size, size left to factor
[(1, 0), (1, 0), (4, 2)]
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from planar import lu

ZERO, CONST, VAR = 0, 1, 2


def _parity(order):
    """+1 or -1: the sign of the permutation ``order`` of range(len(order))."""
    order, sign = list(order), 1
    for i in range(len(order)):
        while order[i] != i:
            j = order[i]
            order[i], order[j] = order[j], order[i]
            sign = -sign
    return sign


@dataclass(frozen=True, eq=False)
class Program:
    """The elimination of blocks of size ``k``: the constant columns' ``steps`` (pivot row p,
    column c, pivot d, the rows i it updates with their multipliers, and the pivot row's
    entries j as forms), the Schur complement's ``rows`` and ``cols``, the linear ``forms``
    (nf, nv) and ``form0`` (nf,) of its entries (row-major) and then of the pivot rows', the
    static part of the det ``det0`` (the permutations' signs times the pivots), and the
    normalisation of the det: per row, the constant parts ``c0``, ``c1`` (k,) and indicator
    matrices ``M0``, ``M1`` (k, nv) of the squared entries (``1``: x and y columns, weighted
    by lam), and lam's constant part, variables, whether there is an angle column and the
    number of length columns. For a stage, ``var`` (nv, G) are the blocks' value slots of the
    variables and ``vscale`` (nv, G, 1) their scales; ``coup`` the coupling entries the solve
    subtracts: (i, j, constant (G, 1) or None, slots (G,))."""

    k: int
    steps: tuple
    rows: tuple
    cols: tuple
    forms: np.ndarray
    form0: np.ndarray
    det0: float
    c0: np.ndarray
    c1: np.ndarray
    M0: np.ndarray
    M1: np.ndarray
    lam: tuple
    var: np.ndarray | None = None
    vscale: np.ndarray | None = None
    coup: tuple = ()

    def signature(self):
        """What blocks must share to be one stage."""
        arrays = (self.forms, self.form0, self.c0, self.c1, self.M0, self.M1)
        steps = tuple((p, c, d, tuple(ms), tuple(us)) for p, c, d, ms, us in self.steps)
        return (self.k, steps, self.rows, self.cols, self.det0, self.lam[0], tuple(self.lam[1]), self.lam[2],
                self.lam[3]) + tuple(a.tobytes() for a in arrays) + tuple(a.shape for a in arrays)

    @classmethod
    def of_block(cls, blk, kinds, values, upscale):
        """The program of block ``blk`` (a :class:`planar.blocks.Block`) from the kinds
        (ZERO, CONST, VAR) and sampled values of the plan's value slots; ``upscale`` (w,):
        the column scales of its upstream columns. Its ``var`` (nv,) and ``vscale`` (nv,)."""
        k = blk.size
        var, vscale = [], []

        def entry(slot, scale):
            """A form (dict: variable -> coefficient, the constant under key None) of one entry."""
            if kinds[slot] == ZERO:
                return {}
            if kinds[slot] == CONST:
                return {None: values[slot] * scale}
            var.append(int(slot))
            vscale.append(scale)
            return {len(var) - 1: 1.0}

        dscale = blk.rscale[:, None] * blk.cscale[None, :]
        F = [[entry(blk.diag[i * k + j], dscale[i, j]) for j in range(k)] for i in range(k)]
        w = blk.up.size
        coup = [[entry(blk.coup[j], blk.rscale[0] * upscale[j]) for j in range(w)]] if k == 1 else None
        # the norms (Hadamard's ratio) read the original entries, before any elimination
        norm, lam = _norm_terms(F, coup, blk.cols % 3 == 2, len(var))
        rows, cols, steps = list(range(k)), list(range(k)), []
        while True:
            c = next((c for c in cols if all(set(F[i][c]) <= {None} for i in rows) and any(F[i][c] for i in rows)),
                     None)
            if c is None:
                break
            p = max(rows, key=lambda i: abs(F[i][c].get(None, 0.0)))  # the first of the largest
            d = F[p][c][None]
            rows.remove(p)
            cols.remove(c)
            mults = []
            for i in rows:
                if F[i][c]:
                    m = F[i][c][None] / d
                    for j in cols:
                        for key, a in F[p][j].items():
                            F[i][j][key] = F[i][j].get(key, 0.0) - m * a
                        F[i][j] = {key: a for key, a in F[i][j].items() if a != 0.0}  # what cancels is a zero
                    F[i][c] = {}
                    mults.append((i, m))
            steps.append((p, c, d, mults, [j for j in cols if F[p][j]]))
        nv = len(var)

        def dense(form):
            out = np.zeros(nv + 1)
            for key, a in form.items():
                out[nv if key is None else key] = a
            return out

        forms = [dense(F[i][j]) for i in rows for j in cols] + [dense(F[p][j]) for p, _, _, _, js in steps for j in js]
        forms = np.array(forms).reshape(-1, nv + 1)
        # the pivot rows' forms are numbered after the Schur complement's, in step order
        at, numbered = len(rows) * len(cols), []
        for p, c, d, mults, js in steps:
            numbered.append((p, c, d, tuple(mults), tuple((j, at + n) for n, j in enumerate(js))))
            at += len(js)
        det0 = _parity([s[0] for s in steps] + rows) * _parity([s[1] for s in steps] + cols) * np.prod(
            [s[2] for s in steps])
        return cls(k, tuple(numbered), tuple(rows), tuple(cols), forms[:, :nv], forms[:, nv], float(det0), *norm, lam,
                   np.array(var, int), np.array(vscale))

    @classmethod
    def stack(cls, programs, coup, kinds, values):
        """The program of a stage: blocks' ``programs`` of one signature, with their padded
        coupling slots ``coup`` (G, k, w)."""
        P = programs[0]
        terms = []
        for i in range(P.k):
            for j in range(coup.shape[2]):
                slots = coup[:, i, j]
                if np.all(kinds[slots] == ZERO):
                    continue
                const = np.all(kinds[slots] != VAR)
                terms.append((i, j, values[slots][:, None] if const else None, slots))
        var = np.array([p.var for p in programs]).T.reshape(-1, len(programs))
        vscale = np.array([p.vscale for p in programs]).T.reshape(var.shape)[..., None]
        return cls(P.k, P.steps, P.rows, P.cols, P.forms, P.form0, P.det0, P.c0, P.c1, P.M0, P.M1, P.lam, var,
                   vscale, tuple(terms))

    def factor(self, Jv, dets=True):
        """(factors, normalised det (G, N)) at the poses of the Jacobian values ``Jv``: the
        det over the product of the row norms (a 1x1 block's row with its coupling entries;
        larger blocks weight their x and y columns by lam), capped by lam; 0 where the norms
        are (None without ``dets``: a Newton iteration only solves). A block of constants is
        factored once (its det broadcasts over the poses, +-1: :attr:`constant`)."""
        if self.var.shape[0] == 0:
            A, perm, E, det = self.constant
        else:
            A, perm, E, det = self._factor(Jv[self.var] * self.vscale, dets)
        C = [None if c is not None else Jv[slots] for _, _, c, slots in self.coup]
        return (A, perm, E, C), det

    @cached_property
    def _rows(self):
        return np.array(self.rows)

    @cached_property
    def _cols(self):
        return np.array(self.cols)

    @cached_property
    def weighted(self):
        """Whether any row norm has weighted (x and y column) terms."""
        return bool(self.M1.any() or self.c1.any())

    @cached_property
    def constant(self):
        """The factors of a block of constants (no variables), once: (A, perm, E, det), its
        normalised det +-1 (0 if singular): a block that is the same at every pose comes no
        closer to a singular position anywhere (a small gear's rolling row, its entry 1/100 of
        the coupling one's, is as regular as any)."""
        A, perm, E, det = self._factor(np.zeros((0,) + self.var.shape[1:] + (1,)))
        return A, perm, E, np.sign(det)

    def _factor(self, v, dets=True):
        """(LU factors and permutation of the Schur complement, the forms' values, det or
        None) from the variables' scaled values ``v`` (nv, G, N)."""
        shape = v.shape[1:]
        flat = v.reshape(v.shape[0], shape[0] * shape[1])
        E = (self.forms @ flat + self.form0[:, None]).reshape((-1,) + shape)
        r = len(self.rows)
        A = E[: r * r].reshape((r, r) + shape).copy()
        perm = np.empty((r,) + shape, np.intp)
        det = lu.factor(A, perm, r)
        if not dets:
            return A, perm, E, None
        sq = flat * flat
        lam_c, lam_v, any_angle, lengths = self.lam
        if not any_angle:
            lam = 1.0
        else:
            lam = np.abs(v[lam_v]).max(axis=0) if lam_v else np.full(shape, lam_c)
            lam = np.minimum(np.maximum(lam, lam_c), 1.0)
        rows = self.M0 @ sq + self.c0[:, None]
        if self.weighted:
            rows = rows + (self.M1 @ sq + self.c1[:, None]) * np.reshape(lam, (1, -1)) ** 2
        norms = np.sqrt(np.prod(rows, axis=0)).reshape(shape)
        if lengths:
            norms = norms / lam**lengths
        det = self.det0 * det
        nd = np.where(norms > 0, det / norms, 0.0)
        return A, perm, E, np.clip(nd, -lam, lam)

    def solve(self, fac, rhs, xu, rscale):
        """x (k, G, N) of the stage's blocks for right-hand sides ``rhs`` (k, G, N) (a copy: it
        is overwritten), the upstream solution ``xu`` (G, w, N) and the row scales (k, G, 1)."""
        A, perm, E, C = fac
        for (i, j, c, _), Cv in zip(self.coup, C):
            rhs[i] -= (c if Cv is None else Cv) * xu[:, j]
        rhs *= rscale
        for p, c, d, mults, us in self.steps:
            for i, m in mults:
                rhs[i] -= m * rhs[p]
        x = np.empty(rhs.shape)
        if self.rows:
            y = np.empty((len(self.rows),) + rhs.shape[1:])
            lu.solve(A, perm, rhs[self._rows], y, len(self.rows))
            x[self._cols] = y
        for p, c, d, mults, us in reversed(self.steps):
            t = rhs[p]
            for j, f in us:
                t = t - E[f] * x[j]
            x[c] = t / d
        return x

    def solve_transpose(self, fac, rhs):
        """z (k, G, N) with the blocks' transposed (scaled) systems F^T z = ``rhs`` (k, G, N),
        one right-hand side per column (a copy: it is overwritten). The elimination read
        backwards: the pivot rows' forms first, the Schur complement's transpose, then the
        constant row operations in reverse (the coupling is the caller's: it goes upstream)."""
        A, perm, E, _ = fac
        z = np.zeros(rhs.shape)
        for p, c, d, mults, us in self.steps:
            z[p] = rhs[c] / d
            for j, f in us:
                rhs[j] -= E[f] * z[p]
        if self.rows:
            y = np.empty((len(self.rows),) + rhs.shape[1:])
            lu.solve_transpose(A, perm, rhs[self._cols], y, len(self.rows))
            z[self._rows] = y
        for p, c, d, mults, us in reversed(self.steps):
            for i, m in mults:
                z[p] -= m * z[i]
        return z


def _norm_terms(F, coup, angle, nv):
    """The normalisation of the det: |det| over the product of the row norms (Hadamard's
    ratio) with the block's own length scale, x and y columns weighted by its largest lever arm
    lam (its largest angle-column entry, relative to the model's length L, capped at 1), so one
    loop of a long chain does not look singular; and the ratio at most lam itself, so a block
    whose lever arms are all negligible against L (its angles fixed only to eps L / lever)
    still reads near-singular. A 1x1 block's row counts its coupling entries too, unweighted:
    the block is singular where the row no longer depends on the coordinate it computes.
    Returns per row the constant parts and indicators of the squared entries, unweighted and
    weighted, (c0, c1, M0, M1), and (constant part of lam, its variables, any angle column,
    the number of length columns)."""
    k = len(F)
    weighted = k > 1
    c, M = np.zeros((2, k)), np.zeros((2, k, nv))
    for i in range(k):
        entries = [(f, int(weighted and not angle[j])) for j, f in enumerate(F[i])]
        entries += [(f, 0) for f in (coup[i] if coup else [])]
        for f, wt in entries:
            for key, a in f.items():
                if key is None:
                    c[wt, i] += a**2
                else:
                    M[wt, i, key] = 1.0
    if not weighted:
        return (c[0], c[1], M[0], M[1]), (1.0, [], False, 0)
    cols = [j for j in range(k) if angle[j]]
    lam_c = max((abs(F[i][j].get(None, 0.0)) for i in range(k) for j in cols), default=0.0)
    lam_v = sorted({key for i in range(k) for j in cols for key in F[i][j] if key is not None})
    return (c[0], c[1], M[0], M[1]), (lam_c, lam_v, bool(cols), k - len(cols))
