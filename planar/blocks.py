"""Block-triangular form of the driven constraint system: solve small blocks in order.

The square Newton system (independent joint rows plus drivers, one column per coordinate) is
decomposed by its structure: a maximum matching pairs each row with the coordinate it computes
(Hopcroft-Karp), and the strongly connected components of the resulting dependency graph, in
topological order, are the blocks. With body frames at joints this leaves 1x1 explicit blocks
(pivot coordinates, driven angles) and one small block per loop (an Assur group), so a Newton
step, a velocity and an acceleration are each a forward substitution through small dense
solves instead of one n x n solve. Only the blocks upstream of the asked-for coordinates are
kept: asking for the first loop of a Watt six-bar does not solve the second.

>>> from planar.mechanisms import watt_six_bar
>>> model = watt_six_bar().compile()
>>> [b.size for b in plan(model).blocks]  # pivots and angles 1x1, one block per loop
[1, 1, 1, 1, 1, 4, 1, 1, 4]
>>> rocker = 3 * model.body_id("rocker") - 1
>>> [b.size for b in plan(model, [rocker]).blocks]  # the first loop only
[1, 1, 1, 1, 1, 4]
"""

import weakref
from dataclasses import dataclass, replace

import numpy as np

from planar.elimination import CONST, VAR, ZERO, Program
from planar.errors import MobilityError


@dataclass(frozen=True, eq=False)
class Block:
    """One diagonal block: ``eqs`` (positions among the plan's rows) compute ``cols``.

    ``diag`` (b*b) and ``coup`` (b*w) index the Jacobian values of the plan's system (the
    last index is a structural zero); ``up`` (w,) are the upstream columns the rows also use;
    ``rscale`` and ``cscale`` (b,) scale its rows and columns (the model's row and column
    scales): the blocks are factored scaled.
    """

    eqs: np.ndarray
    cols: np.ndarray
    diag: np.ndarray
    up: np.ndarray
    coup: np.ndarray
    rscale: np.ndarray
    cscale: np.ndarray

    @property
    def size(self):
        return self.cols.size


@dataclass(frozen=True, eq=False)
class Stage:
    """G blocks of the same size b and structure whose upstream columns are all solved by
    earlier stages, solved in one stacked operation: the :class:`Block` fields the solve reads
    with a leading G axis (``up`` padded with the always-zero column n), ``index`` (G,), the
    blocks' positions in the plan, and their elimination ``program``
    (:class:`planar.elimination.Program`, which holds their value slots)."""

    eqs: np.ndarray
    cols: np.ndarray
    up: np.ndarray
    rscale: np.ndarray
    cscale: np.ndarray
    index: np.ndarray
    program: Program


def _stages(blocks, n, zero, col_scale, kinds, values):
    """Group the blocks by (level, size, elimination structure): a block's level is one more
    than the highest level among the blocks computing its upstream columns. One Python step
    per stage instead of per block (a chain of k loops has ~3 stages per loop level, not 3k
    blocks)."""
    level_of_col = {}
    levels = []
    for blk in blocks:
        lv = 1 + max((level_of_col[int(c)] for c in blk.up), default=-1)
        levels.append(lv)
        for c in blk.cols:
            level_of_col[int(c)] = lv
    programs = [Program.of_block(blk, kinds, values, col_scale[blk.up]) for blk in blocks]
    groups = {}
    for k, (blk, lv) in enumerate(zip(blocks, levels)):
        groups.setdefault((lv, blk.size, programs[k].signature()), []).append(k)
    stages = []
    for (lv, b, _), ks in sorted(groups.items(), key=lambda item: item[0][:2]):
        w = max(blocks[k].up.size for k in ks)
        up = np.full((len(ks), w), n, int)
        coup = np.full((len(ks), b, w), zero, int)
        for g, k in enumerate(ks):
            blk = blocks[k]
            up[g, : blk.up.size] = blk.up
            coup[g, :, : blk.up.size] = blk.coup.reshape(b, blk.up.size)
        stages.append(Stage(np.array([blocks[k].eqs for k in ks]), np.array([blocks[k].cols for k in ks]), up,
                            np.array([blocks[k].rscale for k in ks]), np.array([blocks[k].cscale for k in ks]),
                            np.array(ks), Program.stack([programs[k] for k in ks], coup, kinds, values)))
    return tuple(stages)


@dataclass(frozen=True, eq=False)
class Plan:
    """Blocks of the square system restricted to what some columns need.

    ``system`` holds only the constraints that own a kept row; ``rows`` are the kept global
    rows (a subset of the model's active rows, in that order); ``cols`` the columns solved.
    """

    system: object
    rows: np.ndarray
    drivers: np.ndarray  # positions of the driver rows among ``rows``
    driver_inputs: np.ndarray  # input column of each of them
    cols: np.ndarray
    blocks: tuple
    n: int
    stages: tuple
    kinds: np.ndarray  # ZERO, CONST or VAR per Jacobian value slot of ``system``
    values: np.ndarray  # the slots' values at a sample pose (those of the CONST slots held by the stages)

    def over_designs(self, system, q, u, col_scale):
        """(plan, same): this plan for designs of its structure (``system``: its parameters per
        design, :meth:`planar.system.System.over_designs`; ``u`` carries the design index in its
        last column; ``col_scale``: the model's column scales). Entries constant in this plan but not
        the same in every design are left variable (a ground pivot's place in the Jacobian
        varies with the ground length); ``same`` (D,) is False for a design with a non-zero
        where this plan has a structural zero (it needs a plan of its own). Both are read at
        the designs' sketches ``q`` (D, n) and at poses off them."""
        system = system.restrict(self.rows)  # the constraints this plan keeps, as it keeps them
        # at the sketches and at poses off them, as the plan's kinds were sampled
        off = q + np.random.default_rng(1).normal(size=q.shape[1]) * col_scale
        with np.errstate(all="ignore"):
            Jv = np.concatenate([system.values(q, u)[1], system.values(off, u)[1]], axis=1).reshape(-1, 2, len(q))
        zero = self.kinds == ZERO
        real = np.r_[self.system.entries[1] < self.n, False]  # (not the ground's dump column)
        same = np.all(Jv[zero & real] == 0.0, axis=(0, 1))
        kinds = np.where(np.any(Jv != self.values[:, None, None], axis=(1, 2)) & ~zero, VAR, self.kinds)
        stages = _stages(self.blocks, self.n, self.kinds.size - 1, col_scale, kinds, self.values)
        return replace(self, system=system, stages=stages, kinds=kinds), same

    def evaluate(self, q, u):
        """Phi of the kept rows (N, len(rows)), all rows (N, m) and the Jacobian values that
        vary (the kernels' constant entries are left unset: the programs hold them)."""
        Phi, Jv = self.system.values(q, u, constants=False)
        return Phi[:, self.rows], Phi, Jv

    def factor(self, Jv, dets=True):
        """The LU factors of every diagonal block at the poses of ``Jv``: a :class:`Factors`
        that solves, and gives the assembly modes, with no further factorisation (without
        ``dets``, only solves: a Newton iteration)."""
        return Factors(self, Jv, dets)


class Factors:
    """LU factors (partial pivoting, constant columns first: :mod:`planar.elimination`) of a
    plan's row- and column-scaled diagonal blocks at N poses, stored block entry first and
    pose last so that each elimination step is one whole-array operation over all poses and
    all blocks of a stage (LAPACK's batched solve costs ~0.2 us per 4x4 system; this is ~20x
    less).

    ``solve(b)`` forward-substitutes through the stages; ``signs`` (N, blocks) are the signs
    of the blocks' dets (the assembly mode; int8, 0 where a det is 0 or not finite) and
    ``sing`` (N,) the smallest normalised |det| (|det| of a block over the product of its row
    norms, its x and y columns weighted by its largest lever arm, in [0, 1]; 1 for a block
    that is the same at every pose; 0 at a singular position). A singular block gives
    non-finite solutions, never an exception. Without ``dets`` the three are None.
    """

    def __init__(self, plan, Jv, dets=True):
        self.p, self.N = plan, Jv.shape[1]
        self.lu = []
        with np.errstate(all="ignore"):
            if not dets:
                self.lu = [st.program.factor(Jv, False)[0] for st in plan.stages]
                self.dets = self.signs = self.sing = None
                return
            dets = np.ones((len(plan.blocks), self.N))
            for st in plan.stages:
                fac, dets[st.index] = st.program.factor(Jv)
                self.lu.append(fac)
        self.dets = dets.T
        # the modes as int8 (a sweep keeps one per value and block): a NaN det reads 0, as a
        # singular block's, and neither matches a regular block's mode (whole rows of poses
        # first, then the transposed view)
        self.signs = np.subtract(dets > 0, dets < 0, dtype=np.int8).T
        self.sing = np.min(np.abs(dets), axis=0)

    def solve(self, b):
        """x (N, n) with ``J x = b`` on the plan's rows (``b`` (N, len(rows))); columns the
        plan does not solve are 0."""
        p, N = self.p, self.N
        x = np.zeros((p.n + 1, N))  # row n stays 0: the padding of ``up``
        bT = b.T
        with np.errstate(all="ignore"):
            for st, fac in zip(p.stages, self.lu):
                xb = st.program.solve(fac, bT[st.eqs.T], x[st.up], st.rscale.T[..., None])
                x[st.cols.T] = xb * st.cscale.T[..., None]
        return x[: p.n].T

    def solve_transpose(self, c):
        """y (N, len(rows)) with ``J^T y = c`` (``c`` (N, n), one value per column: generalised
        forces; the plan's columns only are read): the same blocks transposed, solved in
        reverse order, each block's coupling passed on to the upstream columns it reads."""
        p, N = self.p, self.N
        r = np.zeros((p.n + 1, N))  # row n: where the padding of ``up`` sends its zeros
        r[p.cols] = c.T[p.cols]
        y = np.zeros((p.rows.size, N))
        with np.errstate(all="ignore"):
            for st, fac in zip(reversed(p.stages), reversed(self.lu)):
                z = st.program.solve_transpose(fac, r[st.cols.T] * st.cscale.T[..., None]) * st.rscale.T[..., None]
                y[st.eqs.T] = z
                for (i, j, const, _), Cv in zip(st.program.coup, fac[3]):
                    up, t = st.up[:, j], (const if Cv is None else Cv) * z[i]
                    if np.unique(up).size == up.size:
                        r[up] -= t
                    else:  # blocks of the stage share the column: each one's share counts
                        np.subtract.at(r, up, t)
        return y.T


_PLANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def plan(model, cols=None):
    """The block plan of ``model`` for the coordinates ``cols`` (all when None), cached."""
    key = None if cols is None else tuple(sorted(set(int(c) for c in cols)))
    cache = _PLANS.setdefault(model, {})
    if key not in cache:
        cache[key] = _build(model, key)
    return cache[key]


def _samples(model, system):
    """The Jacobian values of ``system`` (one of the model's) at three random poses."""
    rng = np.random.default_rng(1)
    q = model.q0[None] + rng.normal(size=(3, model.n)) * np.tile([model.L, model.L, 1.0], model.n // 3)
    u = model.u0[None] + rng.normal(size=(3, model.u0.size))
    return system.values(q, u)[1]


def _kinds(Jv):
    """(kinds, values) of the value slots sampled in ``Jv`` (slots, samples): ZERO where zero
    at every sample (exact zeros of a kernel, e.g. a pivot at a body's frame origin, are
    structural), CONST where the same at every sample (no kernel is piecewise), else VAR."""
    kinds = np.where(np.all(Jv == Jv[:, :1], axis=1), CONST, VAR)
    kinds[np.all(Jv == 0, axis=1)] = ZERO
    return kinds, Jv[:, 0]


def _build(model, key):
    # imported here, on the first compile: ``import planar`` stays light
    import networkx as nx
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import maximum_bipartite_matching

    sysm = model.system
    n = model.n
    rows_all = np.asarray(model.active_rows)
    erow, ecol = sysm.entries
    nz = (_kinds(_samples(model, sysm))[0][:-1] != ZERO) & (ecol < n)
    pos = {int(r): i for i, r in enumerate(rows_all)}
    S = np.zeros((rows_all.size, n), bool)
    for r, c in zip(erow[nz], ecol[nz]):
        if int(r) in pos:
            S[pos[int(r)], c] = True
    match = maximum_bipartite_matching(csr_matrix(S.astype(np.int8)), perm_type="column")
    if np.any(match < 0):
        c = min(set(range(n)) - set(match[match >= 0].tolist()))
        body, coord = model.body_names[c // 3 + 1], ("x", "y", "angle")[c % 3]
        raise MobilityError(f"model {model.name!r} cannot be driven: the {coord} of body {body!r} is in no "
                            f"independent constraint row with the drivers (a link of zero length spins freely, "
                            f"or the joints lock what a driver moves): give the link a length, or drive "
                            f"another coordinate")
    # eq i computes column match[i]; eq i depends on eq j when it uses column match[j]
    owner = np.empty(n, int)
    owner[match] = np.arange(rows_all.size)
    G = nx.DiGraph()
    G.add_nodes_from(range(rows_all.size))
    for i in range(rows_all.size):
        for c in np.flatnonzero(S[i]):
            j = owner[c]
            if j != i:
                G.add_edge(j, i)
    C = nx.condensation(G)
    order = list(nx.topological_sort(C))
    if key is not None:
        need = {C.graph["mapping"][owner[c]] for c in key}
        need |= {a for b in need for a in nx.ancestors(C, b)}
        order = [b for b in order if b in need]
    eqs_kept = np.sort(np.concatenate([np.array(sorted(C.nodes[b]["members"]), int) for b in order]))
    rows = rows_all[eqs_kept]
    sub = sysm.restrict(rows)
    srow, scol = sub.entries
    snz = np.zeros(srow.size, bool)
    index = {}
    # map (row, col) -> value slot in the restricted system (structural non-zeros only)
    full_idx = {(int(r), int(c)): k for k, (r, c) in enumerate(zip(erow, ecol)) if c < n and nz[k]}
    for k, (r, c) in enumerate(zip(srow, scol)):
        if (int(r), int(c)) in full_idx:
            index[(int(r), int(c))] = k
            snz[k] = True
    zero = srow.size
    where = {int(r): i for i, r in enumerate(rows)}
    rs, cs = model.row_scale, model.col_scale
    blocks = []
    for b in order:
        eq = np.array(sorted(C.nodes[b]["members"]), int)
        grow = rows_all[eq]
        cols = match[eq]
        used = sorted({int(c) for i in eq for c in np.flatnonzero(S[i])} - set(int(c) for c in cols))
        diag = np.array([index.get((int(r), int(c)), zero) for r in grow for c in cols], int)
        coup = np.array([index.get((int(r), int(c)), zero) for r in grow for c in used], int)
        blocks.append(Block(np.array([where[int(r)] for r in grow]), cols.astype(int), diag,
                            np.array(used, int), coup, rs[grow], cs[cols]))
    drivers = np.flatnonzero(np.isin(rows, rows_all[np.asarray(model.driver_rows_active)]))
    driver_inputs = np.searchsorted(rows_all[np.asarray(model.driver_rows_active)], rows[drivers])
    cols = np.sort(np.concatenate([blk.cols for blk in blocks])) if blocks else np.zeros(0, int)
    kinds, values = _kinds(_samples(model, sub))
    kinds[~np.r_[snz, False]] = ZERO  # (the last slot is the structural zero)
    return Plan(sub, rows, drivers, driver_inputs, cols, tuple(blocks), n, _stages(blocks, n, zero, cs, kinds, values),
                kinds, values)
