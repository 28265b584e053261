"""Batched planar vector helpers: the "markers" every joint is built from.

Arrays carry any leading batch axes and a last axis of length 2 for vectors.
``perp(v)`` is the rotation by +90 degrees, so ``d(A(phi) s)/dphi = perp(A(phi) s)``.
"""

import numpy as np


_PERP = np.array([-1.0, 1.0])


def perp(v):
    """Rotate vectors by +90 degrees: (x, y) -> (-y, x)."""
    return v[..., ::-1] * _PERP


def dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def cross(a, b):
    """Scalar cross product a_x b_y - a_y b_x."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def rotate(c, s, v):
    """A(phi) v for cos ``c`` and sin ``s`` (broadcast against v[..., 0])."""
    # c v + s perp(v): three whole-array operations, no stacking copy
    return c[..., None] * v + s[..., None] * perp(v)


class Frames:
    """Poses (and optionally rates) of the body slots of one joint group.

    ``r`` is (..., K, nb, 2), ``phi``, ``c``, ``s`` are (..., K, nb); ``rd`` and ``phid`` the
    same shapes for the rates. Slot ``k`` of a joint is its k-th body.
    """

    __slots__ = ("r", "phi", "c", "s", "rd", "phid")

    def __init__(self, r, phi, c, s, rd=None, phid=None):
        self.r, self.phi, self.c, self.s, self.rd, self.phid = r, phi, c, s, rd, phid

    def vec(self, k, s_local):
        """World vector A_k s' of a body-fixed vector ``s_local`` (K, 2) on slot k."""
        return rotate(self.c[..., k], self.s[..., k], s_local)

    def point(self, k, s_local):
        """World position r_k + A_k s' and the vector S = A_k s'."""
        S = self.vec(k, s_local)
        return self.r[..., k, :] + S, S

    def point_rate(self, k, S):
        """Velocity of the body point whose world vector is S."""
        return self.rd[..., k, :] + perp(S) * self.phid[..., k, None]


def point_block(S, sign=1.0, out=None):
    """Jacobian block (..., 2, 3) of sign * (r + S) with respect to (x, y, phi) of its body,
    written into ``out`` (zeros elsewhere) when given."""
    if out is None:
        out = np.zeros(S.shape[:-1] + (2, 3))
    out[..., 0, 0] = out[..., 1, 1] = sign
    out[..., 0, 2] = -sign * S[..., 1]
    out[..., 1, 2] = sign * S[..., 0]
    return out
