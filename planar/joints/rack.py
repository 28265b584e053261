"""Rack and pinion, and a wheel rolling on a line: a circle rolling on a straight line."""

import numpy as np

from planar.joints.base import Joint, Line


class RackPinion(Joint):
    """Pitch circle (radius R, centre on the pinion) rolling without slip on a pitch line
    fixed in the rack body (ground or moving). Bodies are (rack, pinion).

    Rows ``n.d - sigma R`` (tangency) and ``u.d + sigma R (phi_pinion - phi_rack) - c`` (no
    slip), d from the line's origin to the pinion centre, sigma = +1 when the centre is left of
    the directed line. A wheel rolling to the right on a floor turns clockwise.
    """

    n_rows = 2
    n_bodies = 2
    length_rows = (True, True)
    sketch_rows = (1,)

    def local_params(self, sketch):
        rack, pinion = self.bodies
        d = self.data
        sR = d["side"] * d["radius"]
        return {
            "s": np.stack((sketch.local_point(rack, d["through"]), sketch.local_point(pinion, d["centre"]))),
            "u": sketch.local_direction(rack, d["direction"]),
            "sR": np.array(sR),
            "c": np.array([sR, 0.0]),
        }

    @staticmethod
    def _line(P, F, rates=False):
        return Line(F, P["s"][..., 0, :], P["u"], P["s"][..., 1, :], rates=rates)

    @staticmethod
    def Phi(P, F):
        ln = RackPinion._line(P, F)
        roll = ln.t + P["sR"] * (F.phi[..., 1] - F.phi[..., 0])
        return np.stack((ln.h, roll), axis=-1) - P["c"]

    @staticmethod
    def Phi_q(P, F):
        ln = RackPinion._line(P, F)
        roll = ln.t_grad()
        roll[..., 2] -= P["sR"]
        roll[..., 5] += P["sR"]
        return np.stack((ln.h_grad(), roll), axis=-2)

    @staticmethod
    def gamma(P, F):
        ln = RackPinion._line(P, F, rates=True)
        return np.stack((ln.h_gamma(), ln.t_gamma()), axis=-1)

    def touch_points(self):
        return [(self.bodies[0], self.data["through"]), (self.bodies[1], self.data["centre"])]

    def anchor(self):
        return self.bodies[1], self.data["centre"]
