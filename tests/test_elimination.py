"""The structured LU of :mod:`planar.elimination` against numpy's dense LU.

Blocks are made up here, any pattern of structural zeros, constants and variables: the program
(constant columns eliminated first, the Schur complement with partial pivoting) must give
numpy's solution, the sign of numpy's determinant and the normalised determinant (Hadamard's
ratio) computed from its definition. Then the plans of the catalogue mechanisms at poses far
from their sketches, a four-bar at its limit position (where the measure must read singular)
and the dense kernels on their own.
"""

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from planar.blocks import plan
from planar import lu
from planar.elimination import CONST, VAR, ZERO, Program
from planar.mechanisms import four_bar

N = 6  # poses


def made_up_blocks(k, kinds_ij, G, rng):
    """G blocks of size k sharing the entry kinds ``kinds_ij`` (k, k) and the constants, each
    with its own variable slots: (blocks, kinds, values, Jv (slots + 1, N)). All columns are
    angle columns (cols % 3 == 2), so the row norms are unweighted."""
    consts = rng.choice([-2.0, -1.0, 0.5, 1.0, 3.0], size=(k, k))
    rscale = rng.uniform(0.5, 2, k)  # one for all: the constants, scaled, are the stage's
    slots, kinds, Jv, blocks = [], [], [], []
    for g in range(G):
        diag = []
        for i in range(k):
            for j in range(k):
                kind = kinds_ij[i, j]
                if kind == ZERO:
                    diag.append(-1)  # the structural zero, numbered below
                    continue
                diag.append(len(kinds))
                kinds.append(kind)
                Jv.append(np.full(N, consts[i, j]) if kind == CONST else rng.normal(size=N))
        slots.append(diag)
    zero = len(kinds)
    kinds = np.array(kinds + [ZERO])
    Jv = np.array(Jv + [np.zeros(N)])
    for g in range(G):
        diag = np.array([zero if d < 0 else d for d in slots[g]])
        blocks.append(SimpleNamespace(size=k, diag=diag, up=np.zeros(0, int), coup=np.zeros(0, int),
                                      rscale=rscale, cscale=np.ones(k), cols=3 * np.arange(k) + 2))
    return blocks, kinds, Jv[:, 0].copy(), Jv


def stage_of(blocks, kinds, values):
    programs = [Program.of_block(b, kinds, values, np.zeros(0)) for b in blocks]
    assert len({p.signature() for p in programs}) == 1
    return Program.stack(programs, np.zeros((len(blocks), blocks[0].size, 0), int), kinds, values)


def dense(blocks, Jv):
    """(G, N, k, k) row-scaled dense blocks, as the program factors them."""
    k = blocks[0].size
    return np.array([np.moveaxis(Jv[b.diag].reshape(k, k, -1), -1, 0) * b.rscale[:, None] for b in blocks])


kinds_patterns = st.integers(1, 5).flatmap(
    lambda k: st.lists(st.sampled_from([ZERO, CONST, VAR]), min_size=k * k, max_size=k * k).map(
        lambda ks: np.array(ks).reshape(k, k)))


@settings(max_examples=60, deadline=None)
@given(kinds_patterns, st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_structured_lu_solves_and_dets_equal_numpys(kinds_ij, G, seed):
    k = kinds_ij.shape[0]
    rng = np.random.default_rng(seed)
    blocks, kinds, values, Jv = made_up_blocks(k, kinds_ij, G, rng)
    D = dense(blocks, Jv)
    det = np.linalg.det(D)
    # structurally singular patterns, or an unlucky draw: nothing to compare a solution with
    assume(np.all(np.abs(det) > 1e-6 * np.prod(np.linalg.norm(D, axis=3), axis=2)))
    stage = stage_of(blocks, kinds, values)
    fac, nd = stage.factor(Jv)
    nd = np.broadcast_to(nd, det.shape)  # a block of constants: one det for every pose
    b = rng.normal(size=(k, G, N))
    x = stage.solve(fac, b.copy(), np.zeros((G, 0, N)), np.array([blk.rscale for blk in blocks]).T[..., None])
    want = np.linalg.solve(D, np.moveaxis(b, 0, -1)[..., None] * np.array([blk.rscale for blk in blocks])[:, None, :,
                                                                                                        None])
    np.testing.assert_allclose(np.moveaxis(x, 0, -1), want[..., 0], rtol=1e-9, atol=1e-9 * np.abs(want).max())
    # the normalised det: det over the product of the row norms, capped (above 1x1) by the
    # largest entry; +-1 for a block of constants (the same at every pose: as regular anywhere)
    lam = np.minimum(np.abs(D).max(axis=(2, 3)), 1.0) if k > 1 else 1.0
    ratio = det / (np.prod(np.linalg.norm(D, axis=3), axis=2) if (kinds_ij == VAR).any() else np.abs(det))
    np.testing.assert_allclose(nd, np.clip(ratio, -lam, lam), rtol=1e-9, atol=1e-14)
    assert np.all(np.sign(nd) == np.sign(det)) and np.all(np.abs(nd) <= 1.0)


@settings(max_examples=40, deadline=None)
@given(kinds_patterns, st.integers(0, 2**32 - 1))
def test_constant_columns_go_first_with_the_largest_constant_as_pivot(kinds_ij, seed):
    """Partial pivoting among constants: every multiplier at most 1 in size; what is left to
    factor at each pose are the columns that hold a variable, so a block of constants leaves
    nothing (and is factored once)."""
    k = kinds_ij.shape[0]
    blocks, kinds, values, Jv = made_up_blocks(k, kinds_ij, 1, np.random.default_rng(seed))
    prog = stage_of(blocks, kinds, values)
    for p, c, d, mults, us in prog.steps:
        assert d != 0 and all(abs(m) <= 1.0 + 1e-15 for _, m in mults)
    assert len(prog.rows) == len(prog.cols) == k - len(prog.steps)
    if not (kinds_ij == VAR).any():
        assert prog.var.shape[0] == 0
        with np.errstate(all="ignore"):  # (a pattern may be structurally singular)
            f1, d1 = prog.factor(Jv)
            assert prog.factor(Jv)[0][0] is f1[0]  # the cached factors


def test_four_bar_loop_leaves_a_two_by_two_whose_det_is_numpys():
    """The plan's 4x4 loop block of a four-bar, at poses along its motion."""
    model = four_bar(4, 2, 3.5, 3).compile()
    p = plan(model)
    res = model.sweep(np.linspace(0, 2 * np.pi, 9))
    _, _, Jv = p.evaluate(np.array(res.q), np.array(res.inputs))
    Jfull = p.system.values(np.array(res.q), np.array(res.inputs))[1]
    (stage,) = [st for st in p.stages if st.program.k == 4]
    assert len(stage.program.rows) == 2
    _, nd = stage.program.factor(Jv)
    (blk,) = [p.blocks[i] for i in stage.index]
    A = np.moveaxis(Jfull[blk.diag].reshape(4, 4, -1), -1, 0) * (blk.rscale[:, None] * blk.cscale[None, :])
    assert np.all(np.sign(nd[0]) == np.sign(np.linalg.det(A)))


def test_a_limit_position_reads_singular():
    """A triple rocker at its limit (crank 117.28 deg): the loop block's normalised det is at
    rounding level, as numpy's det of the scaled block; the solve is non-finite or huge, and
    nothing raises."""
    model = four_bar(4, 3, 3, 3).compile()
    res = model.circuit(samples=41)
    limits = [e.index for e in res.events if e.kind == "limit"]
    assert limits
    p = plan(model)
    q, u = np.array(res.q)[limits], np.array(res.inputs)[limits]
    _, _, Jv = p.evaluate(q, u)
    lu = p.factor(Jv)
    assert np.all(lu.sing < 1e-6)
    _, J = model.system.evaluate(q, u)
    A = J[:, p.rows][:, :, p.cols] * model.row_scale[p.rows][:, None] * model.col_scale[p.cols]
    assert np.all(np.abs(np.linalg.det(A)) < 1e-6)
    x = lu.solve(np.ones((len(limits), p.rows.size)))
    assert np.all(~np.isfinite(x).all(axis=1) | (np.abs(x).max(axis=1) > 1e5))
    # away from the limit the measure is of order one
    ok = np.array(res.status) == 0
    far = p.factor(p.evaluate(np.array(res.q)[ok], np.array(res.inputs)[ok])[2]).sing
    assert far.max() > 0.1


def _factored(A):
    """planar.lu's factors of the (k, k, G, N) blocks A (a copy): (factors, row order, det)."""
    k = A.shape[0]
    A = A.copy()
    perm = np.empty(A.shape[1:], np.intp)
    return A, perm, lu.factor(A, perm, k)


@pytest.mark.parametrize("k", [0, 1, 2, 3, 5, 8])
def test_the_lu_and_its_solves_are_numpys(k):
    rng = np.random.default_rng(k)
    G = 3
    A = rng.normal(size=(k, k, G, N))
    if k > 1:
        A[0, 0, :, ::2] = 0.0  # a zero first pivot at every other pose: rows must swap
    b = rng.normal(size=(k, G, N))
    M = np.moveaxis(A, (0, 1), (-2, -1))  # (G, N, k, k)
    fac, perm, det = _factored(A)
    np.testing.assert_allclose(det * np.ones((G, N)), np.linalg.det(M) if k else np.ones((G, N)), rtol=1e-10,
                               atol=1e-12)
    if k == 0:
        return
    lower = np.tril(np.ones((k, k), bool), -1)
    assert np.all(np.abs(fac[lower]) <= 1.0)  # partial pivoting: no multiplier above 1 in size
    x, z = np.empty_like(b), np.empty_like(b)
    lu.solve(fac, perm, b, x, k)
    lu.solve_transpose(fac, perm, b.copy(), z, k)
    rhs = np.moveaxis(b, 0, -1)[..., None]
    for got, want in ((x, np.linalg.solve(M, rhs)), (z, np.linalg.solve(np.swapaxes(M, -1, -2), rhs))):
        np.testing.assert_allclose(np.moveaxis(got, 0, -1), want[..., 0], rtol=1e-9, atol=1e-9)


def test_the_lu_of_a_singular_block_gives_a_zero_det_and_no_exception():
    A = np.zeros((3, 3, 1, 2))
    A[:, :, 0, 0] = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]]
    A[:, :, 0, 1] = np.eye(3)
    x = np.empty((3, 1, 2))
    with np.errstate(all="ignore"):
        fac, perm, det = _factored(A)
        lu.solve(fac, perm, np.ones((3, 1, 2)), x, 3)
    assert det[0, 0] == 0.0 and det[0, 1] == 1.0
    assert not np.isfinite(x[:, 0, 0]).all()
    np.testing.assert_array_equal(x[:, 0, 1], np.ones(3))


@pytest.mark.numba
@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_the_compiled_engine_runs_the_same_lu_to_the_bit(k):
    """One definition, two kinds of entry: the compiled engine's factors, det and solve, pose
    by pose, equal the numpy engine's on all poses at once, bit for bit."""
    import numba

    from planar.compiled import engine

    @numba.njit
    def one_pose(A, perm, b, x, k):
        det = engine._lu_det(A, perm, k)
        engine._lu_solve(A, perm, b, x, k)
        return det

    rng = np.random.default_rng(10 + k)
    A = rng.normal(size=(k, k, 1, N))
    A[0, 0, :, ::2] *= 1e-3  # (rows swap at every other pose)
    b = rng.normal(size=(k, 1, N))
    fac, perm, det = _factored(A)
    x = np.empty_like(b)
    lu.solve(fac, perm, b, x, k)
    for n in range(N):
        An, pn, xn = A[:, :, 0, n].copy(), np.empty(k, np.int64), np.empty(k)
        assert one_pose(An, pn, b[:, 0, n].copy(), xn, k) == det[0, n]
        assert np.array_equal(An, fac[:, :, 0, n]) and np.array_equal(pn, perm[:, 0, n])
        assert np.array_equal(xn, x[:, 0, n])
