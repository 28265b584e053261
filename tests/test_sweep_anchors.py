"""The anchors of a sweep (:mod:`planar.sweep.anchors`): the quintic Hermite interpolants the
bulk is predicted from reproduce quintic polynomials exactly and converge as h^6 on a smooth
function; the walk's anchors lie no more than one walk step apart and cover every value, and
the sweep stops where its one input turns back.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planar.mechanisms import four_bar
from planar.sweep.anchors import quintic, sweep_anchors, walk_anchors
from planar.sweep.branch import input_scale


def evaluate(P, k, t):
    """(M, n) the interpolant of interval k (M,) at t (M,) from quintic's table, by powers."""
    return np.einsum("mjn,mj->mn", P[k], t[:, None] ** np.arange(6))


# ----------------------------------------------------------------------------- quintic


@given(
    coef=st.lists(st.floats(-10, 10), min_size=12, max_size=12),
    steps=st.lists(st.floats(0.05, 2.0), min_size=1, max_size=5),
    u0=st.floats(-3, 3),
)
def test_quintic_hermite_reproduces_quintic_polynomials_exactly(coef, steps, u0):
    c = np.array(coef).reshape(6, 2)  # two columns, each a quintic in u
    u = u0 + np.r_[0.0, np.cumsum(steps)]
    powers = np.arange(6)

    def p(x, d):  # the d-th derivative of the polynomials at x (m,): (m, 2)
        fall = np.array([np.prod(np.arange(j - d + 1, j + 1)) if j >= d else 0.0 for j in powers])
        return (fall[None, :] * x[:, None] ** np.maximum(powers - d, 0)) @ c

    P = quintic(p(u, 0), p(u, 1), p(u, 2), np.diff(u))
    t = np.linspace(0.0, 1.0, 7)
    k = np.repeat(np.arange(len(steps)), t.size)
    tt = np.tile(t, len(steps))
    x = u[k] + tt * np.diff(u)[k]
    scale = np.max(np.abs(p(x, 0))) + np.abs(c).sum() * max(1.0, np.abs(u).max()) ** 5
    assert np.allclose(evaluate(P, k, tt), p(x, 0), rtol=0, atol=1e-12 * scale)


def test_quintic_hermite_meets_the_poses_and_their_derivatives_at_both_ends():
    u = np.array([0.0, 0.4, 0.5, 1.3])
    Q = np.c_[np.sin(u), np.exp(u)]
    D = np.c_[np.cos(u), np.exp(u)]
    DD = np.c_[-np.sin(u), np.exp(u)]
    h = np.diff(u)
    P = quintic(Q, D, DD, h)
    assert P.shape == (3, 6, 2)
    j = np.arange(6)[None, :, None]
    at1 = P.sum(axis=1)  # the interpolant at t = 1, and its derivatives in t below
    assert np.allclose(P[:, 0], Q[:-1], atol=1e-15) and np.allclose(at1, Q[1:], atol=1e-14)
    assert np.allclose(P[:, 1] / h[:, None], D[:-1], atol=1e-14)
    assert np.allclose((j * P).sum(axis=1) / h[:, None], D[1:], atol=1e-13)
    assert np.allclose(2 * P[:, 2] / h[:, None] ** 2, DD[:-1], atol=1e-13)
    assert np.allclose((j * (j - 1) * P).sum(axis=1) / h[:, None] ** 2, DD[1:], atol=1e-12)


def test_quintic_hermite_error_falls_as_h_to_the_sixth_on_a_smooth_function():
    def worst(n):
        u = np.linspace(0.0, 1.0, n + 1)
        P = quintic(np.sin(3 * u)[:, None], 3 * np.cos(3 * u)[:, None], -9 * np.sin(3 * u)[:, None], np.diff(u))
        t = np.linspace(0.0, 1.0, 11)
        k = np.repeat(np.arange(n), t.size)
        tt = np.tile(t, n)
        x = u[k] + tt * np.diff(u)[k]
        return np.max(np.abs(evaluate(P, k, tt)[:, 0] - np.sin(3 * x)))

    errors = [worst(n) for n in (2, 4, 8, 16)]
    orders = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all((orders > 5.6) & (orders < 6.4)), orders
    # the constant of the leading term: h^6 max|f^(6)| / (6! 2^6) for the Hermite quintic
    assert errors[-1] < (1 / 16) ** 6 * 3**6 / (720 * 64) * 1.01


# ----------------------------------------------------------------------------- walk_anchors


values = st.lists(st.floats(1e-6, 0.5), min_size=1, max_size=60).map(lambda d: np.r_[0.0, np.cumsum(d)])


def check_anchors(V, idx, step):
    """idx starts at 0, increases, and each anchor lies within step of the one before (or is
    the next value, where the values are further apart); the last value is within step of
    the last anchor."""
    assert idx[0] == 0 and np.all(np.diff(idx) > 0) and idx[-1] < len(V)
    jumps = np.max(np.abs(V[idx[1:]] - V[idx[:-1]]), axis=-1)
    assert np.all((jumps <= step * (1 + 1e-12)) | (np.diff(idx) == 1))
    assert np.max(np.abs(V[-1] - V[idx[-1]])) <= step * (1 + 1e-12)


@given(v=values, step=st.floats(0.01, 2.0), backwards=st.booleans())
def test_walk_anchors_of_a_monotone_input_lie_within_one_step(v, step, backwards):
    v = -v if backwards else v
    idx, monotone = walk_anchors(v[:, None], np.ones(1), step)
    assert monotone
    check_anchors(v[:, None], idx, step)


@given(d=st.lists(st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3)), min_size=1, max_size=60),
       step=st.floats(0.01, 1.0), scale=st.floats(0.1, 10))
def test_walk_anchors_of_two_inputs_lie_within_one_scaled_step(d, step, scale):
    U = np.r_[np.zeros((1, 2)), np.cumsum(np.array(d), axis=0)]
    idx, monotone = walk_anchors(U, np.array([1.0, scale]), step)
    assert not monotone
    check_anchors(U * [1.0, scale], idx, step)


def test_walk_anchors_of_a_rocking_input_and_the_sweep_anchors_at_its_turns():
    U = np.array([0.0, 0.1, 0.2, 0.3, 0.2, 0.1, 0.2])[:, None]
    idx, monotone = walk_anchors(U, np.ones(1), 10.0)
    assert not monotone and idx.tolist() == [0]
    model = four_bar().compile()
    assert input_scale(model).tolist() == [1.0]
    assert sweep_anchors(model, U, 10.0).tolist() == [0, 3, 5, 6]


@pytest.mark.parametrize("n", [2, 5, 1000])
def test_sweep_anchors_keep_the_first_and_last_values(n):
    U = np.linspace(0.0, 1.0, n)[:, None]
    got = sweep_anchors(four_bar().compile(), U, 0.25)
    assert got[-1] == n - 1
    check_anchors(U, got, 0.25)
