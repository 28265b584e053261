"""Gear pairs (pitch circles rolling without slip), external (s = +1) or internal (s = -1).

All rows are linear in the unwrapped body angles, so angles are never reduced modulo 2 pi.
"""

from typing import ClassVar

import numpy as np

from planar.geometry import cross_cf, dot_cf, perp_cf
from planar.joints.base import Joint, pair_rates, pair_row, point_pair, wrap


class CarrierGear(Joint):
    """Gears i and j whose centres are fixed on one carrier body a (or both on the ground).

    Row ``R_i (phi_i - phi_a) + s R_j (phi_j - phi_a) - c`` (a length), gamma = 0; ``c`` is
    taken at the assembled sketch, so the gears mesh as drawn.
    """

    n_rows = 1
    n_bodies = 3
    length_rows = (True,)
    sketch_rows = (0,)

    def local_params(self, sketch):
        d = self.data
        return {"R": np.array([d["radius_a"], d["sign"] * d["radius_b"]])}

    @staticmethod
    def Phi(P, F):
        Ri, Rj = P["R"]
        pa = F.phi[2]
        return Ri * (F.phi[0] - pa) + Rj * (F.phi[1] - pa) - P["c"]

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        out = cls.block(F, out)
        Ri, Rj = P["R"]
        out[0] = 0.0
        out[0, 2] = Ri
        out[0, 5] = Rj
        out[0, 8] = -(Ri + Rj)
        return out

    @staticmethod
    def gamma(P, F):
        return np.zeros((1,) + F.shape)

    def touch_points(self):
        return [(self.bodies[0], self.data["centre_a"]), (self.bodies[1], self.data["centre_b"])]

    def anchor(self):
        return self.bodies[1], self.data["centre_b"]


def _rolling(P, F, rates=False):
    """Rolling row pieces for centres s[:, 0] on slot 0 and s[:, 1] on slot 1."""
    d, S = point_pair(F, P["s"])
    Si, Sj = S[:, 0], S[:, 1]
    Ri, Rj = P["R"]
    K = Ri + Rj
    L2 = dot_cf(d, d)
    theta = np.arctan2(d[1], d[0])
    # the line-of-centres angle is taken on the 2 pi branch nearest the one the row predicts
    # from the (unwrapped) gear angles, so no state is needed to unwrap it
    theta_est = (Ri * F.phi[0] + Rj * F.phi[1] - P["c"][-1]) / K
    out = {"d": d, "Si": Si, "Sj": Sj, "K": K, "L2": L2, "Phi": -K * wrap(theta - theta_est)}
    if rates:
        dd, ddq = pair_rates(F, S)
        theta_dot = cross_cf(d, dd) / L2
        out["dd"], out["ddq"] = dd, ddq
        out["gamma"] = K * (cross_cf(d, ddq) / L2 - 2 * theta_dot * dot_cf(d, dd) / L2)
    return out


def _rolling_grad(r, P, out):
    """Write the gradient (6, K, ...) of the rolling row: d theta/d d = perp(d) / L2, and
    perp(d).perp(S) = d.S."""
    Ri, Rj = P["R"]
    KL = r["K"] / r["L2"]
    return pair_row(out, -KL * perp_cf(r["d"]), Ri + KL * dot_cf(r["d"], r["Si"]),
                    Rj - KL * dot_cf(r["d"], r["Sj"]))


def _gear_params(joint, sketch):
    a, b = joint.bodies
    d = joint.data
    return {
        "s": np.stack((sketch.local_point(a, d["centre_a"]), sketch.local_point(b, d["centre_b"]))),
        "R": np.array([d["radius_a"], d["sign"] * d["radius_b"]]),
    }


class Gear(Joint):
    """Gears on two different moving bodies whose centre distance other joints hold.

    Row ``R_i phi_i + s R_j phi_j - (R_i + s R_j) theta - c``, theta the angle of the line of
    centres (no-slip at the pitch point). Reduces to :class:`CarrierGear` when the centres
    sit on one arm.
    """

    n_rows = 1
    n_bodies = 2
    length_rows: ClassVar[tuple] = (True,)
    sketch_rows = (0,)
    local_params = _gear_params

    @staticmethod
    def Phi(P, F):
        return _rolling(P, F)["Phi"][None]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        r, out = _rolling(P, F), cls.block(F, out)
        _rolling_grad(r, P, out[0])
        return r["Phi"][None], out

    @staticmethod
    def gamma(P, F):
        return _rolling(P, F, rates=True)["gamma"][None]

    def touch_points(self):
        return [(self.bodies[0], self.data["centre_a"]), (self.bodies[1], self.data["centre_b"])]

    def anchor(self):
        return self.bodies[1], self.data["centre_b"]


class RollingContact(Gear):
    """A circle rolling on (or inside) another with no arm: the :class:`Gear` row plus the
    contact row ``(d.d - D^2) / (2 D) = 0`` that holds the centre distance D = |R_i + s R_j|."""

    n_rows = 2
    length_rows = (True, True)
    sketch_rows = (1,)

    @staticmethod
    def _D(P):
        return np.abs(P["R"][0] + P["R"][1])

    @staticmethod
    def Phi(P, F):
        r = _rolling(P, F)
        D = RollingContact._D(P)
        return np.stack(((r["L2"] - D**2) / (2 * D) - P["c"][0], r["Phi"]))

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        r, out = _rolling(P, F), cls.block(F, out)
        D = RollingContact._D(P)
        d = r["d"]
        # d dist/d d = d / D, and d.perp(S) = S x d
        pair_row(out[0], d / D, cross_cf(d, r["Si"]) / D, cross_cf(r["Sj"], d) / D)
        _rolling_grad(r, P, out[1])
        return np.stack(((r["L2"] - D**2) / (2 * D) - P["c"][0], r["Phi"])), out

    @staticmethod
    def gamma(P, F):
        r = _rolling(P, F, rates=True)
        D = RollingContact._D(P)
        dist = -(dot_cf(r["dd"], r["dd"]) + dot_cf(r["d"], r["ddq"])) / D
        return np.stack((dist, r["gamma"]))
