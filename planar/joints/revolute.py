"""Revolute (pin) joint: a point of one body stays on a point of another."""

import numpy as np

from planar.joints.base import Joint, pair_blocks, pair_rates, point_pair


class Revolute(Joint):
    """Pin at world point ``at`` of the sketch, between bodies a and b.

    Rows ``P_b - P_a = 0`` (2 length rows); gamma = S_a w_a^2 - S_b w_b^2.
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
        _, Sa, Sb = point_pair(F, P["s"][..., 0, :], P["s"][..., 1, :])
        return pair_blocks(Sa, Sb)

    @staticmethod
    def gamma(P, F):
        _, Sa, Sb = point_pair(F, P["s"][..., 0, :], P["s"][..., 1, :])
        return -pair_rates(F, Sa, Sb)[1]

    def touch_points(self):
        return [(b, self.data["at"]) for b in self.bodies]

    def anchor(self):
        return self.bodies[1], self.data["at"]

    def coordinate(self):
        from planar.joints.driver import AngleDriver

        return AngleDriver(self.name, self.bodies)
