"""Revolute (pin) joint: a point of one body stays on a point of another."""

import numpy as np

from planar.joints.base import Joint, pair_blocks, point_pair


class Revolute(Joint):
    """Pin at world point ``at`` of the sketch, between bodies a and b.

    Rows ``P_b - P_a = 0`` (2 length rows); gamma = S_b w_b^2 - S_a w_a^2.
    Its coordinate is the relative angle phi_b - phi_a.
    """

    n_rows = 2
    n_bodies = 2
    length_rows = (True, True)

    def local_params(self, sketch):
        a, b = self.bodies
        at = self.data["at"]
        return {"s": np.stack((sketch.local_point(a, at), sketch.local_point(b, at)))}

    @staticmethod
    def Phi(P, F):
        d, _, _ = point_pair(F, P["s"][..., 0, :], P["s"][..., 1, :])
        return d - P["c"]

    @staticmethod
    def Phi_q(P, F):
        return pair_blocks(F.vec(0, P["s"][..., 0, :]), F.vec(1, P["s"][..., 1, :]))

    @staticmethod
    def Phi_and_Phi_q(P, F):
        d, Sa, Sb = point_pair(F, P["s"][..., 0, :], P["s"][..., 1, :])
        return d - P["c"], pair_blocks(Sa, Sb)

    @staticmethod
    def gamma(P, F):
        # the centripetal terms only: -(S_a w_a^2 - S_b w_b^2)
        Sa, Sb = F.vec(0, P["s"][..., 0, :]), F.vec(1, P["s"][..., 1, :])
        return Sb * F.phid[..., 1, None] ** 2 - Sa * F.phid[..., 0, None] ** 2

    def touch_points(self):
        return [(b, self.data["at"]) for b in self.bodies]

    def anchor(self):
        return self.bodies[1], self.data["at"]

    def coordinate(self):
        from planar.joints.driver import AngleDriver

        return AngleDriver(self.name, self.bodies)
