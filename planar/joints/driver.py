"""Drivers: the input rows ``g(q) - u``.

The solver writes the input values ``u`` into ``P["c"]``; the velocity right-hand side of a
driver row is the input rate, and its gamma gets the input acceleration added.
"""

import numpy as np

from planar.geometry import cross_cf, dot_cf
from planar.joints.base import LOCK, Joint, line_of, line_params


class AngleDriver(Joint):
    """Relative angle phi_b - phi_a (a revolute's angle; with a = ground, b's absolute angle)."""

    n_rows = 1
    n_bodies = 2
    length_rows = (False,)
    is_driver = True

    def local_params(self, sketch):
        return {}

    @staticmethod
    def Phi(P, F):
        return F.phi[1] - F.phi[0] - P["c"]

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        out = cls.block(F, out)
        if constants:
            out[0] = LOCK
        return out

    @staticmethod
    def gamma(P, F):
        return np.zeros((1,) + F.shape)


class TravelDriver(Joint):
    """Travel u.d of a point of body b along a line of body a, from the line's origin."""

    n_rows = 1
    n_bodies = 2
    length_rows = (True,)
    is_driver = True

    local_params = line_params

    @staticmethod
    def Phi(P, F):
        return line_of(P, F).t - P["c"]

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        out = cls.block(F, out)
        line_of(P, F).t_grad(out[0])
        return out

    @staticmethod
    def gamma(P, F):
        return line_of(P, F, rates=True).t_gamma()[None]


class CoordinateDriver(Joint):
    """World coordinate e.P of a body point along the fixed unit axis e (x or y)."""

    n_rows = 1
    n_bodies = 1
    length_rows = (True,)
    is_driver = True

    def local_params(self, sketch):
        (b,) = self.bodies
        return {"s": sketch.local_point(b, self.data["at"]), "e": np.asarray(self.data["axis"], float)}

    @staticmethod
    def Phi(P, F):
        p, _ = F.point(0, P["s"])
        return dot_cf(p, P["e"]) - P["c"]

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        out = cls.block(F, out)
        out[0, 0:2] = P["e"]
        # e.perp(S) = S x e
        out[0, 2] = cross_cf(F.vec(0, P["s"]), P["e"])
        return out

    @staticmethod
    def gamma(P, F):
        return (dot_cf(F.vec(0, P["s"]), P["e"]) * F.phid[0] ** 2)[None]


__all__ = ["AngleDriver", "TravelDriver", "CoordinateDriver"]
