"""The vector helpers and :class:`Frames` against numpy and the identities they stand for.

Both layouts: (..., 2) vectors (perp, dot, cross) and components first (2, ..., N) vectors
(perp_cf, dot_cf, cross_cf, rotate_cf), which must agree component for component.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from planar.geometry import Frames, cos_sin, cross, cross_cf, dot, dot_cf, perp, perp_cf, rotate, rotate_cf

finite = st.floats(-1e3, 1e3, allow_nan=False)
vectors = st.integers(1, 6).flatmap(lambda n: arrays(float, (n, 2), elements=finite))


def rotation(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


@settings(max_examples=50, deadline=None)
@given(vectors)
def test_perp_is_the_rotation_by_a_quarter_turn(v):
    np.testing.assert_allclose(perp(v), v @ rotation(np.pi / 2).T, atol=1e-12 * (1 + np.abs(v).max()))
    np.testing.assert_array_equal(perp(perp(v)), -v)
    np.testing.assert_array_equal(dot(perp(v), v), np.zeros(len(v)))


@settings(max_examples=50, deadline=None)
@given(vectors, st.data())
def test_dot_and_cross_are_numpys(a, data):
    b = data.draw(arrays(float, a.shape, elements=finite))
    np.testing.assert_allclose(dot(a, b), np.einsum("ni,ni->n", a, b), rtol=1e-12, atol=1e-9)
    a3, b3 = np.pad(a, ((0, 0), (0, 1))), np.pad(b, ((0, 0), (0, 1)))
    np.testing.assert_allclose(cross(a, b), np.cross(a3, b3)[:, 2], rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(cross(a, b), dot(perp(a), b))  # the same products, the same order
    np.testing.assert_array_equal(cross(a, b), -cross(b, a))


def test_components_first_helpers_equal_the_last_axis_ones():
    rng = np.random.default_rng(1)
    for shape in [(7,), (3, 7), (2, 3, 7)]:
        a, b = rng.normal(size=(2, 2) + shape)  # components first
        last = lambda v: np.moveaxis(v, 0, -1)  # noqa: E731
        np.testing.assert_array_equal(perp_cf(a), np.moveaxis(perp(last(a)), -1, 0))
        np.testing.assert_array_equal(dot_cf(a, b), dot(last(a), last(b)))
        np.testing.assert_array_equal(cross_cf(a, b), cross(last(a), last(b)))


@settings(max_examples=50, deadline=None)
@given(st.floats(-50, 50), arrays(float, (2,), elements=finite))
def test_rotate_cf_is_the_rotation_matrix_and_its_derivative_is_perp(phi, v):
    A = rotation(phi)
    got = rotate_cf(np.cos(phi), np.sin(phi), v[:, None])[:, 0]
    np.testing.assert_allclose(got, A @ v, atol=1e-12 * (1 + np.abs(v).max()))
    # d(A(phi) s)/dphi = perp(A(phi) s): the identity every Jacobian column of an angle uses
    h = 1e-6
    fd = (rotation(phi + h) @ v - rotation(phi - h) @ v) / (2 * h)
    np.testing.assert_allclose(perp(A @ v), fd, atol=1e-7 * (1 + np.abs(v).max()))


@settings(max_examples=50, deadline=None)
@given(arrays(float, st.tuples(st.integers(1, 4), st.integers(1, 5)), elements=st.floats(-1e4, 1e4)))
def test_cos_sin_writes_numpys_cos_and_sin_into_the_given_arrays(phi):
    c, s = np.full(phi.shape, np.nan), np.full(phi.shape, np.nan)
    assert cos_sin(phi, c, s) is None
    np.testing.assert_allclose(c, np.cos(phi), rtol=0, atol=4e-16)
    np.testing.assert_allclose(s, np.sin(phi), rtol=0, atol=4e-16)


def _full(rng, nbodies, N, rates=True):
    """Bodies' rows x, y, phi, cos, sin[, xd, yd, phid] at N configurations."""
    full = rng.normal(size=(8 if rates else 5, nbodies, N))
    full[3], full[4] = np.cos(full[2]), np.sin(full[2])
    return full


def test_gathered_frames_are_the_bodies_rows_of_their_slots():
    rng = np.random.default_rng(2)
    full = _full(rng, 4, 6)
    slots = np.array([[0, 3], [2, 1]])  # two joints: bodies (0, 2) and (3, 1)
    F = Frames.gather(full, slots)
    assert F.shape == (2, 6)
    for k in range(2):
        for j in range(2):
            b = slots[k, j]
            np.testing.assert_array_equal(F.r[:, k, j], full[:2, b])
            np.testing.assert_array_equal(F.phi[k, j], full[2, b])
            np.testing.assert_array_equal(F.c[k, j], full[3, b])
            np.testing.assert_array_equal(F.s[k, j], full[4, b])
            np.testing.assert_array_equal(F.rd[:, k, j], full[5:7, b])
            np.testing.assert_array_equal(F.phid[k, j], full[7, b])
    F = Frames.gather(full[:5], slots)
    assert F.rd is None and F.phid is None  # no rates given: none read
    with pytest.raises(AttributeError):
        F.omega


def test_frame_points_and_their_rates_against_finite_differences():
    """r + A s' of a body-fixed point, and its velocity rd + perp(S) phid, along a motion."""
    rng = np.random.default_rng(3)
    nb, K, N = 2, 3, 4
    q, qd = rng.normal(size=(2, 3, nb, K, N))
    s_local = rng.normal(size=(2, nb, K, 1))

    def frames(t):
        x = q + t * qd
        return Frames(x[:2], x[2], np.cos(x[2]), np.sin(x[2]), qd[:2], qd[2])

    F = frames(0.0)
    P, S = F.points(s_local)
    for k in range(nb):
        Pk, Sk = F.point(k, s_local[:, k])
        np.testing.assert_allclose(Pk, P[:, k], rtol=0, atol=1e-15)
        np.testing.assert_allclose(Sk, F.vec(k, s_local[:, k]), rtol=0, atol=1e-15)
        np.testing.assert_allclose(Sk, S[:, k], rtol=0, atol=1e-15)
        np.testing.assert_allclose(Sk, np.einsum("ijkn,jk->ikn", rotation(q[2, k]), s_local[:, k, :, 0]),
                                   atol=1e-14)
        h = 1e-6
        fd = (frames(h).point(k, s_local[:, k])[0] - frames(-h).point(k, s_local[:, k])[0]) / (2 * h)
        np.testing.assert_allclose(F.point_rate(k, Sk), fd, atol=1e-8)
    np.testing.assert_allclose(F.vecs(s_local), S, rtol=0, atol=0)
    assert F.shape == (K, N)


def test_rotate_turns_body_points_and_back():
    rng = np.random.default_rng(3)
    phi, v = rng.uniform(-7, 7, 50), rng.normal(size=(50, 2))
    w = rotate(phi, v)
    np.testing.assert_allclose(np.hypot(*w.T), np.hypot(*v.T), rtol=1e-14)
    np.testing.assert_allclose(rotate(-phi, w), v, atol=1e-14)
    np.testing.assert_allclose(rotate(np.pi / 2, v), perp(v), atol=1e-15)
    assert rotate(phi, np.array([1.0, 0.0])).shape == (50, 2)  # one body point over many poses
