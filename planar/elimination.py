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

A stage's blocks share one :class:`Program` (the stages are grouped by its structure); its
arrays carry the stage's block axis G, and the runtime arrays put the poses last.

>>> from planar.mechanisms import four_bar
>>> from planar.blocks import plan
>>> p = plan(four_bar(4, 2, 3.5, 3).compile())
>>> [(st.program.k, len(st.program.rows)) for st in p.stages]  # block size, size left to factor
[(1, 0), (1, 0), (4, 2)]
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

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


@dataclass
class _BlockProgram:
    """One block's elimination: the structure (compared between blocks) and its constants."""

    k: int
    var: list  # value slots of the variables
    vscale: list  # their scales (row times column scale)
    steps: list  # (p, c, pivot, [(i, multiplier)], [(j, form)])
    rows: list  # rows and columns of the Schur complement
    cols: list
    forms: np.ndarray  # (nf, nv + 1): the Schur complement's entries (row-major), then the pivot rows'
    det0: float  # the static part of the det: the permutations' signs times the pivots
    norm: list  # per row: (constant, [(var, weighted)]) of its squared entries; see _norm_terms
    lam: tuple  # (constant, [angle vars], any angle, length columns)

    def signature(self):
        return (self.k, tuple((p, c, tuple(i for i, _ in ms), tuple(j for j, _ in us))
                              for p, c, _, ms, us in self.steps), tuple(self.rows), tuple(self.cols))


def block_program(blk, kinds, values, upscale):
    """The :class:`_BlockProgram` of block ``blk`` (a :class:`planar.blocks.Block`), from the
    kinds (ZERO, CONST, VAR) and sampled values of the plan's value slots; ``upscale`` (w,):
    the column scales of its upstream columns."""
    k = blk.size
    var, vscale = [], []

    def entry(slot, scale):
        """A form (dict: var -> coefficient, and the constant under key None) of one entry."""
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
    coup = [[entry(blk.coup[i * w + j], blk.rscale[i] * upscale[j]) for j in range(w)] for i in range(k)] if k == 1 else None
    # the norms (Hadamard's ratio) read the original entries, before any elimination
    norm, ang = _norm_terms(F, coup, blk.cols % 3 == 2)
    rows, cols, steps = list(range(k)), list(range(k)), []
    while True:
        c = next((c for c in cols if all(set(F[i][c]) <= {None} for i in rows) and any(F[i][c] for i in rows)), None)
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
        steps.append((p, c, d, mults, [(j, F[p][j]) for j in cols if F[p][j]]))
    nv = len(var)

    def dense(form):
        out = np.zeros(nv + 1)
        for key, a in form.items():
            out[nv if key is None else key] = a
        return out

    forms = [dense(F[i][j]) for i in rows for j in cols] + [dense(f) for s in steps for _, f in s[4]]
    # number the pivot rows' forms after the Schur complement's, in step order
    at, numbered = len(rows) * len(cols), []
    for p, c, d, mults, us in steps:
        numbered.append((p, c, d, mults, [(j, at + n) for n, (j, _) in enumerate(us)]))
        at += len(us)
    det0 = _parity([s[0] for s in steps] + rows) * _parity([s[1] for s in steps] + cols) * np.prod([s[2] for s in steps])
    return _BlockProgram(k, var, vscale, numbered, rows, cols, np.array(forms).reshape(-1, nv + 1), float(det0),
                         norm, ang)


def _norm_terms(F, coup, angle):
    """The normalisation of the det (as the dense factorisation had it): per row, the sum of
    its squared entries, x and y columns weighted by the block's largest lever arm lam (its
    largest angle-column entry, capped at 1); a 1x1 block's row also counts its coupling
    entries and has no weighting. Returns (per row: (constant part, constant part of the
    weighted entries, [variables], [weighted variables])) and (constant lam, angle variables,
    any angle column, the number of length columns)."""
    k = len(F)
    weighted = k > 1
    norm = []
    for i in range(k):
        entries = [(f, weighted and not angle[j]) for j, f in enumerate(F[i])]
        entries += [(f, False) for f in (coup[i] if coup else [])]
        norm.append((sum(f.get(None, 0.0) ** 2 for f, wt in entries if not wt),
                     sum(f.get(None, 0.0) ** 2 for f, wt in entries if wt),
                     [key for f, wt in entries if not wt for key in f if key is not None],
                     [key for f, wt in entries if wt for key in f if key is not None]))
    if not weighted:
        return norm, (1.0, [], False, 0)
    cols = [j for j in range(k) if angle[j]]
    lam_c = max((abs(F[i][j].get(None, 0.0)) for i in range(k) for j in cols), default=0.0)
    lam_v = sorted({key for i in range(k) for j in cols for key in F[i][j] if key is not None})
    return norm, (lam_c, lam_v, bool(cols), k - len(cols))


@dataclass(frozen=True, eq=False)
class Program:
    """The elimination of a stage's G blocks (one structure): the :class:`_BlockProgram`
    fields stacked over G, poses last, padded with the always-zero value slot; ``coup`` the
    coupling entries the solve subtracts: (i, j, constant (G, 1) or None, slots (G,))."""

    k: int
    var: np.ndarray  # (nv, G)
    vscale: np.ndarray  # (nv, G, 1)
    steps: tuple  # (p, c, pivot (G, 1), ((i, multiplier (G, 1)), ...), ((j, form), ...))
    rows: list
    cols: list
    forms: np.ndarray  # (nf, nv, G) coefficients
    form0: np.ndarray  # (nf, G, 1) constants
    det0: np.ndarray  # (G, 1)
    norm: tuple  # (constant (k, G, 1), weighted constant (k, G, 1), indicator (k, nv, G), weighted (k, nv, G))
    lam: tuple  # (constant (G, 1), angle variables (nv, G, 1), any angle (G, 1), length columns (G, 1))
    coup: tuple

    @staticmethod
    def stack(bps, coup, kinds, values, zero):
        """The stage's program from its blocks' (one signature) and its padded coupling slots
        ``coup`` (G, k, w)."""
        G, k, nv = len(bps), bps[0].k, max(len(b.var) for b in bps)
        var = np.full((nv, G), zero, int)
        vscale = np.zeros((nv, G))
        nf = bps[0].forms.shape[0]
        forms, form0 = np.zeros((nf, nv, G)), np.zeros((nf, G))
        nrm = np.zeros((2, k, G)), np.zeros((2, k, nv, G))
        lam_c, lam_v, any_a, lengths = np.zeros(G), np.zeros((nv, G)), np.zeros(G, bool), np.zeros(G)
        for g, b in enumerate(bps):
            n = len(b.var)
            var[:n, g], vscale[:n, g] = b.var, b.vscale
            forms[:, :n, g], form0[:, g] = b.forms[:, :n], b.forms[:, n]
            for i, (c0, c1, v0, v1) in enumerate(b.norm):
                nrm[0][:, i, g] = c0, c1
                nrm[1][0, i, v0, g] = 1.0
                nrm[1][1, i, v1, g] = 1.0
            lam_c[g], any_a[g], lengths[g] = b.lam[0], b.lam[2], b.lam[3]
            lam_v[b.lam[1], g] = 1.0
        steps = tuple((p, c, np.array([b.steps[s][2] for b in bps])[:, None],
                       tuple((i, np.array([b.steps[s][3][n][1] for b in bps])[:, None]) for n, (i, _) in enumerate(ms)),
                       tuple(us))
                      for s, (p, c, _, ms, us) in enumerate(bps[0].steps))
        terms = []
        for i in range(k):
            for j in range(coup.shape[2]):
                slots = coup[:, i, j]
                if np.all(kinds[slots] == ZERO):
                    continue
                const = np.all(kinds[slots] != VAR)
                terms.append((i, j, values[slots][:, None] if const else None, slots))
        return Program(k, var, vscale[..., None], steps, bps[0].rows, bps[0].cols, forms, form0[..., None],
                       np.array([b.det0 for b in bps])[:, None], (nrm[0][0][..., None], nrm[0][1][..., None],
                                                                  nrm[1][0], nrm[1][1]),
                       (lam_c[:, None], lam_v[..., None], any_a[:, None], lengths[:, None]), tuple(terms))

    def factor(self, Jv):
        """(factors, normalised det (G, N)) at the poses of the Jacobian values ``Jv``: the
        det over the product of the row norms (a 1x1 block's row with its coupling entries;
        larger blocks weight their x and y columns by lam), capped by lam; 0 where the norms
        are. A block of constants is factored once (its det broadcasts over the poses)."""
        A, perm, E, det = self._constant if self.var.shape[0] == 0 else self._factor(Jv[self.var] * self.vscale)
        C = [None if c is not None else Jv[slots] for _, _, c, slots in self.coup]
        return (A, perm, E, C), det

    @cached_property
    def _constant(self):
        return self._factor(np.zeros((0,) + self.var.shape[1:] + (1,)))

    def _factor(self, v):
        """(LU factors and permutation of the Schur complement, the forms' values, det) from
        the variables' scaled values ``v`` (nv, G, N)."""
        E = self.form0 + np.einsum("fkg,kgn->fgn", self.forms, v) if v.size else self.form0
        r = len(self.rows)
        S = E[: r * r].reshape((r, r) + E.shape[1:]).copy()
        c0, c1, i0, i1 = self.norm
        sq = v * v
        lam_c, lam_v, any_a, lengths = self.lam
        lam = np.maximum(lam_c, np.max(np.abs(v) * lam_v, axis=0)) if v.size else lam_c
        lam = np.where(any_a, np.minimum(lam, 1.0), 1.0)
        norms = np.prod(np.sqrt(c0 + np.einsum("ikg,kgn->ign", i0, sq)
                                + lam**2 * (c1 + np.einsum("ikg,kgn->ign", i1, sq))), axis=0) / lam**lengths
        A, perm, det = _dense_lu(S)
        det = self.det0 * det
        nd = np.where(norms > 0, det / norms, 0.0)
        return A, perm, E, np.sign(nd) * np.minimum(np.abs(nd), lam)

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
            x[self.cols] = _lu_solve(A, perm, rhs[self.rows])
        for p, c, d, mults, us in reversed(self.steps):
            t = rhs[p]
            for j, f in us:
                t = t - E[f] * x[j]
            x[c] = t / d
        return x


def _dense_lu(A):
    """In-place LU with partial pivoting of (k, k, G, N) blocks: (factors, row permutation
    (k, G, N) or None, det (G, N); 1 for k = 0)."""
    k = A.shape[0]
    perm = None
    sign = np.ones(A.shape[2:])
    for j in range(k - 1):
        # the row swaps as masked copies: whole-array passes, where gathers at the swapped
        # poses walk the few rows pose by pose
        piv = np.argmax(np.abs(A[j:, j]), axis=0)  # (G, N), relative to j
        for r in range(1, k - j):
            swap = piv == r
            if not swap.any():
                continue
            if perm is None:
                perm = np.broadcast_to(np.arange(k)[:, None, None], A.shape[1:]).copy()
            top = A[j].copy()
            np.copyto(A[j], A[j + r], where=swap)
            np.copyto(A[j + r], top, where=swap)
            top = perm[j].copy()
            np.copyto(perm[j], perm[j + r], where=swap)
            np.copyto(perm[j + r], top, where=swap)
            np.negative(sign, out=sign, where=swap)
        l = A[j + 1 :, j] / A[j, j]
        A[j + 1 :, j] = l
        A[j + 1 :, j + 1 :] -= l[:, None] * A[j, j + 1 :][None]
    return A, perm, sign * np.prod(A[np.arange(k), np.arange(k)], axis=0)


def _lu_solve(A, perm, b):
    """x (k, G, N) with (P A) x = P b for the factors of :func:`_dense_lu`."""
    k = A.shape[0]
    b = np.take_along_axis(b, perm, axis=0) if perm is not None else b.copy()
    for i in range(1, k):
        b[i] -= np.einsum("jgn,jgn->gn", A[i, :i], b[:i])
    for i in range(k - 1, -1, -1):
        if i + 1 < k:
            b[i] -= np.einsum("jgn,jgn->gn", A[i, i + 1 :], b[i + 1 :])
        b[i] /= A[i, i]
    return b
