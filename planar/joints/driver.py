"""Drivers: the input rows ``g(q) - u``.

The solver writes the input values ``u`` into ``P["c"]``; the velocity right-hand side of a
driver row is the input rate, and its gamma gets the input acceleration added.
"""

import numpy as np

from planar.joints.base import Joint, Line
from planar.joints.prismatic import _line, _line_params


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
        return (F.phi[..., 1] - F.phi[..., 0])[..., None] - P["c"]

    @staticmethod
    def Phi_q(P, F):
        g = np.zeros(F.phi.shape[:-1] + (1, 6))
        g[..., 0, 2] = -1.0
        g[..., 0, 5] = 1.0
        return g

    @staticmethod
    def gamma(P, F):
        return np.zeros(F.phi.shape[:-1] + (1,))


class TravelDriver(Joint):
    """Travel u.d of a point of body b along a line of body a, from the line's origin."""

    n_rows = 1
    n_bodies = 2
    length_rows = (True,)
    is_driver = True

    local_params = _line_params

    @staticmethod
    def Phi(P, F):
        return _line(P, F).t[..., None] - P["c"]

    @staticmethod
    def Phi_q(P, F):
        return _line(P, F).t_grad()[..., None, :]

    @staticmethod
    def gamma(P, F):
        return _line(P, F, rates=True).t_gamma()[..., None]


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
        return (p[..., 0] * P["e"][..., 0] + p[..., 1] * P["e"][..., 1])[..., None] - P["c"]

    @staticmethod
    def Phi_q(P, F):
        from planar.geometry import perp

        S = F.vec(0, P["s"])
        e = np.broadcast_to(P["e"], S.shape)
        g = np.stack((e[..., 0], e[..., 1], e[..., 0] * perp(S)[..., 0] + e[..., 1] * perp(S)[..., 1]), -1)
        return g[..., None, :]

    @staticmethod
    def gamma(P, F):
        S = F.vec(0, P["s"])
        w2 = F.phid[..., 0] ** 2
        return ((S[..., 0] * P["e"][..., 0] + S[..., 1] * P["e"][..., 1]) * w2)[..., None]


__all__ = ["AngleDriver", "TravelDriver", "CoordinateDriver", "Line"]
