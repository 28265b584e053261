"""Batched planar vector helpers: the "markers" every joint is built from.

Two layouts. Results, analyses and drawing hold vectors as (..., 2) arrays: ``perp``, ``dot``
and ``cross`` work on those. The joint kernels hold them *components first, configurations
last* (structure of arrays): a vector is (2, ..., N), so that every operation is one numpy
call over whole contiguous rows of N configurations, never an inner loop of 2 elements;
``perp_cf``, ``dot_cf``, ``cross_cf`` and ``rotate_cf`` work on those (``rotate`` is the first
layout's body-point rotation), and :class:`Frames`
holds the body poses in that layout.

``perp(v)`` is the rotation by +90 degrees, so ``d(A(phi) s)/dphi = perp(A(phi) s)``.

>>> import numpy as np
>>> perp(np.array([1.0, 2.0])), perp_cf(np.array([[1.0], [2.0]])).ravel()
(array([-2.,  1.]), array([-2.,  1.]))
"""

import numpy as np


_PERP = np.array([-1.0, 1.0])


def perp(v):
    """Rotate (..., 2) vectors by +90 degrees: (x, y) -> (-y, x)."""
    return v[..., ::-1] * _PERP


def rotate(phi, v):
    """A(phi) v: (..., 2) vectors ``v`` turned counter-clockwise by the angles ``phi`` (...),
    broadcast against each other; ``rotate(-phi, v)`` turns them back (world to body-fixed).

    >>> rotate(np.pi / 2, np.array([1.0, 0.0])).round(12).tolist()
    [0.0, 1.0]
    """
    c, s = np.cos(phi), np.sin(phi)
    return np.stack((c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]), -1)


def dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def cross(a, b):
    """Scalar cross product a_x b_y - a_y b_x of (..., 2) vectors."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


# ---- components first: (2, ...) ------------------------------------------------------------

_PERP_CF = tuple(_PERP.reshape((2,) + (1,) * k) for k in range(8))


def perp_cf(v):
    """Rotate (2, ...) vectors by +90 degrees: one multiply of the swapped components."""
    return v[::-1] * _PERP_CF[v.ndim - 1]


def dot_cf(a, b):
    return a[0] * b[0] + a[1] * b[1]


def cross_cf(a, b):
    """Scalar cross product a_x b_y - a_y b_x of (2, ...) vectors."""
    return a[0] * b[1] - a[1] * b[0]


def rotate_cf(c, s, v):
    """A(phi) v = c v + s perp(v) for cos ``c`` and sin ``s`` (broadcast against v[0]): with v
    a body-fixed parameter (2, K, 1), three whole-array operations."""
    return c * v + s * perp_cf(v)


def cos_sin(phi, c, s):
    """Write cos ``phi`` into ``c`` and sin ``phi`` into ``s`` through the half-angle tangent
    t = tan(phi / 2): cos = 2 / (1 + t^2) - 1, sin = t 2 / (1 + t^2).

    numpy's float64 ``tan`` is vectorised (SIMD) where ``cos`` and ``sin`` are not: this is
    ~4x faster than calling both, and within 4e-16 of them (absolute; at phi = pi, t is large
    but finite, 1.6e16, so no inf arises).

    >>> c, s = np.empty(3), np.empty(3)
    >>> cos_sin(np.array([0.0, np.pi / 2, np.pi]), c, s)
    >>> np.allclose(c, [1, 0, -1], atol=1e-15), np.allclose(s, [0, 1, 0], atol=1e-15)
    (True, True)
    """
    t = np.multiply(phi, 0.5)
    np.tan(t, out=t)
    w = np.multiply(t, t)
    w += 1.0
    np.divide(2.0, w, out=w)
    np.subtract(w, 1.0, out=c)
    np.multiply(t, w, out=s)


class Frames:
    """Poses (and optionally rates) of the body slots of one joint group, components first.

    ``r`` is (2, nb, K, ...), ``phi``, ``c``, ``s`` are (nb, K, ...) with the configurations on
    the trailing axes; ``rd`` and ``phid`` the same shapes for the rates. Slot ``k`` of a joint
    is its k-th body: ``r[:, k]`` is (2, K, ...). :meth:`gather` makes them from the bodies'
    rows, each field on first use.
    """

    # each field's rows in the bodies' array of :meth:`gather`
    _ROWS = {"r": slice(0, 2), "phi": 2, "c": 3, "s": 4, "rd": slice(5, 7), "phid": 7}

    def __init__(self, r, phi, c, s, rd=None, phid=None):
        self.r, self.phi, self.c, self.s, self.rd, self.phid = r, phi, c, s, rd, phid

    @classmethod
    def gather(cls, full, slots):
        """The frames of the bodies ``slots`` (nb, K) in ``full`` (5 or 8 rows x, y, phi, cos,
        sin[, xd, yd, phid], bodies, ...). A field is gathered when a kernel first reads it:
        a kernel reads few of them (a revolute's gamma only the angles' cos, sin and rates, a
        driver of a constant's none), and each gather is a pass over the configurations.

        >>> full = np.arange(5 * 3 * 2, dtype=float).reshape(5, 3, 2)  # no rates; 3 bodies, 2 poses
        >>> F = Frames.gather(full, np.array([[0], [2]]))  # one joint, between bodies 0 and 2
        >>> F.shape, F.r.shape, F.c[1].tolist(), F.rd
        ((1, 2), (2, 2, 1, 2), [[22.0, 23.0]], None)
        """
        F = cls.__new__(cls)
        F._full, F._slots = full, slots
        return F

    def __getattr__(self, name):  # (only for a field not gathered yet)
        rows = Frames._ROWS.get(name)
        full = self.__dict__.get("_full")
        if rows is None or full is None:
            raise AttributeError(name)
        if isinstance(rows, slice):
            v = full[rows][:, self._slots] if rows.stop <= len(full) else None
        else:
            v = full[rows, self._slots] if rows < len(full) else None
        setattr(self, name, v)
        return v

    @property
    def shape(self):
        """(K, ...): the joints and configurations of one row."""
        if "_full" in self.__dict__:
            return self._slots.shape[1:] + self._full.shape[2:]
        return self.phi.shape[1:]

    def vec(self, k, s_local):
        """World vector A_k s' (2, K, ...) of a body-fixed vector ``s_local`` (2, K, 1) on slot k."""
        return rotate_cf(self.c[k], self.s[k], s_local)

    def vecs(self, s_local):
        """World vectors A s' (2, nb, K, ...) of one body-fixed vector per slot, ``s_local``
        (2, nb, K, 1): all slots in one pass."""
        return rotate_cf(self.c, self.s, s_local)

    def points(self, s_local):
        """World positions r + A s' and vectors S = A s' of one body-fixed point per slot
        (as :meth:`vecs`)."""
        S = self.vecs(s_local)
        return self.r + S, S

    def point(self, k, s_local):
        """World position r_k + A_k s' and the vector S = A_k s' on slot k."""
        S = self.vec(k, s_local)
        return self.r[:, k] + S, S

    def point_rate(self, k, S):
        """Velocity of the body point of slot k whose world vector is S."""
        return self.rd[:, k] + perp_cf(S) * self.phid[k]
