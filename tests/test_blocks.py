"""Block-triangular decomposition: structure, and solves equal to the dense ones."""

import numpy as np

from planar.blocks import plan
from planar.elimination import VAR
from planar.mechanisms import four_bar, geared_five_bar, watt_six_bar


def test_loops_become_blocks_and_outputs_prune_them():
    model = watt_six_bar().compile()
    sizes = [b.size for b in plan(model).blocks]
    assert sorted(sizes)[-2:] == [4, 4] and sum(sizes) == model.n
    rocker = 3 * model.body_id("rocker") - 1
    first = plan(model, [rocker])
    assert [b.size for b in first.blocks].count(4) == 1
    assert 3 * model.body_id("link5") - 1 not in first.cols


def _factored(m, rng, N):
    """(model, plan, q, u, Phi, Jv, factors) at N poses near the sketch of mechanism m: Jv
    every Jacobian value, the factors from the plan's own evaluation (its variable values)."""
    model = m.compile()
    p = plan(model)
    q = model.q0[None] + 1e-2 * rng.normal(size=(N, model.n))
    u = np.repeat(model.u0[None], N, 0)
    Phi, _, Jv = p.evaluate(q, u)
    return model, p, q, u, Phi, p.system.values(q, u)[1], p.factor(Jv)


def test_block_solve_and_dets_match_the_dense_system():
    rng = np.random.default_rng(3)
    for m in (four_bar(4, 2, 3, 4), watt_six_bar(), geared_five_bar()):
        model, p, q, u, Phi, Jv, lu = _factored(m, rng, 5)
        x = lu.solve(Phi)
        Pd, J = model.system.evaluate(q, u)
        A = J[:, model.active_rows]
        xd = np.linalg.solve(A, Pd[:, model.active_rows][..., None])[..., 0]
        np.testing.assert_allclose(x, xd, atol=1e-12)
        # the det is the product of the blocks' dets, up to the sign of the matching's permutation
        ratio = np.prod(lu.signs, axis=1) * np.sign(np.linalg.det(A))
        assert np.all(ratio == ratio[0])


def _dense_dets(p, model, Jv):
    """The normalised det of every block, straight from its definition on the dense scaled
    block (np.linalg.det): |det| over the product of the row norms (a 1x1 block's row with
    its coupling entries; larger blocks weight their x and y columns by the largest lever
    arm lam, capped at 1, and divide by lam per length column), capped by lam; +-1 for a
    block of constants, a 1x1 block's coupling entries with them (the same at every pose: as
    regular anywhere)."""
    out = []
    for b in p.blocks:
        k = b.size
        A = np.moveaxis(Jv[b.diag].reshape(k, k, -1), -1, 0) * (b.rscale[:, None] * b.cscale[None, :])
        det = np.linalg.det(A)
        if not np.any(p.kinds[np.r_[b.diag, b.coup if k == 1 else []].astype(int)] == VAR):
            norms, cap = np.abs(det), 1.0
        elif k == 1:
            C = Jv[b.coup].T * (b.rscale[0] * model.col_scale[b.up])
            norms, cap = np.sqrt(A[:, 0, 0] ** 2 + np.sum(C**2, axis=1)), 1.0
        else:
            ang = b.cols % 3 == 2
            lam = np.minimum(np.abs(A[:, :, ang]).max(axis=(1, 2)), 1.0) if ang.any() else np.ones(len(A))
            W = A * np.where(ang, 1.0, lam[:, None, None])
            norms = np.prod(np.sqrt(np.sum(W**2, axis=2)), axis=1) / lam ** (k - ang.sum())
            cap = lam
        out.append(np.sign(det) * np.minimum(np.abs(det / norms), cap))
    return np.array(out).T


def test_the_structured_lu_gives_the_dense_blocks_dets_and_solves():
    # constant columns eliminated first (planar.elimination), the rest with partial pivoting:
    # the same dets, singularity measure and solutions as the dense blocks, on every joint type
    from planar.mechanisms import (inverted_slider_crank, planetary_gear_train, rack_and_pinion, rolling_wheel,
                                   slider_crank, stephenson_six_bar)

    rng = np.random.default_rng(5)
    for m in (four_bar(4, 2, 3, 4), slider_crank(2, 5, offset=1), inverted_slider_crank(), stephenson_six_bar(),
              geared_five_bar(), rack_and_pinion(), rolling_wheel(), planetary_gear_train()):
        model, p, q, u, Phi, Jv, lu = _factored(m, rng, 7)
        np.testing.assert_allclose(lu.dets, _dense_dets(p, model, Jv), rtol=1e-12, atol=1e-15, err_msg=model.name)
        b = rng.normal(size=Phi.shape)
        Pd, J = model.system.evaluate(q, u)
        A = J[:, p.rows][:, :, p.cols]
        np.testing.assert_allclose(lu.solve(b)[:, p.cols], np.linalg.solve(A, b[..., None])[..., 0], atol=1e-10,
                                   err_msg=model.name)


def test_constant_columns_leave_a_four_bar_loop_a_two_by_two():
    # the loop's x and y columns hold +-1 only: eliminated by the plan, two columns left per pose
    p = plan(four_bar(4, 2, 3, 4).compile())
    loop = [st.program for st in p.stages if st.program.k == 4]
    assert len(loop) == 1 and len(loop[0].rows) == 2 and len(loop[0].steps) == 2
