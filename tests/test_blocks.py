"""Block-triangular decomposition: structure, and solves equal to the dense ones."""

import numpy as np

from planar.blocks import plan
from planar.mechanisms import four_bar, geared_five_bar, watt_six_bar


def test_loops_become_blocks_and_outputs_prune_them():
    model = watt_six_bar().compile()
    sizes = [b.size for b in plan(model).blocks]
    assert sorted(sizes)[-2:] == [4, 4] and sum(sizes) == model.n
    rocker = 3 * model.body_id("rocker") - 1
    first = plan(model, [rocker])
    assert [b.size for b in first.blocks].count(4) == 1
    assert 3 * model.body_id("link5") - 1 not in first.cols


def test_block_solve_and_dets_match_the_dense_system():
    rng = np.random.default_rng(3)
    for m in (four_bar(4, 2, 3, 4), watt_six_bar(), geared_five_bar()):
        model = m.compile()
        p = plan(model)
        q = model.q0[None] + 1e-2 * rng.normal(size=(5, model.n))
        u = np.repeat(model.u0[None], 5, 0)
        Phi, _, Jv = p.evaluate(q, u)
        lu = p.factor(Jv)
        x = lu.solve(Phi)
        Pd, J = model.system.evaluate(q, u)
        A = J[:, model.active_rows]
        xd = np.linalg.solve(A, Pd[:, model.active_rows][..., None])[..., 0]
        np.testing.assert_allclose(x, xd, atol=1e-12)
        # the det is the product of the blocks' dets, up to the sign of the matching's permutation
        ratio = np.prod(lu.signs, axis=1) * np.sign(np.linalg.det(A))
        assert np.all(ratio == ratio[0])
