"""Prismatic joint (slider) and pin-in-slot: a point of body b on a line fixed in body a."""

import numpy as np

from planar.joints.base import Joint, Line


def _line_params(joint, sketch):
    a, b = joint.bodies
    d = joint.data
    return {
        "s": np.stack((sketch.local_point(a, d["origin"]), sketch.local_point(b, d["at"]))),
        "u": sketch.local_direction(a, d["direction"]),
    }


def _line(P, F, rates=False):
    return Line(F, P["s"][..., 0, :], P["u"], P["s"][..., 1, :], rates=rates)


class Slot(Joint):
    """Pin-in-slot: the point ``at`` of body b stays on the line of body a through ``origin``
    along ``direction``; rotation free. One row, the normal distance n.d.
    Its coordinate is the travel along the line from ``origin``.
    """

    n_rows = 1
    n_bodies = 2
    length_rows = (True,)

    local_params = _line_params

    @staticmethod
    def Phi(P, F):
        return _line(P, F).h[..., None] - P["c"]

    @staticmethod
    def Phi_q(P, F):
        return _line(P, F).h_grad()[..., None, :]

    @staticmethod
    def gamma(P, F):
        return _line(P, F, rates=True).h_gamma()[..., None]

    def touch_points(self):
        return [(self.bodies[0], self.data["origin"]), (self.bodies[1], self.data["at"])]

    def anchor(self):
        return self.bodies[1], self.data["at"]

    def coordinate(self):
        from planar.joints.driver import TravelDriver

        return TravelDriver(self.name, self.bodies, **self.data)


class Prismatic(Slot):
    """Slider: as :class:`Slot`, and the relative rotation phi_b - phi_a is locked at its
    sketch value (second row, an angle)."""

    n_rows = 2
    length_rows = (True, False)
    sketch_rows = (1,)

    @staticmethod
    def Phi(P, F):
        h = _line(P, F).h
        rel = F.phi[..., 1] - F.phi[..., 0]
        return np.stack((h, rel), axis=-1) - P["c"]

    @staticmethod
    def Phi_q(P, F):
        g = _line(P, F).h_grad()
        lock = np.zeros_like(g)
        lock[..., 2] = -1.0
        lock[..., 5] = 1.0
        return np.stack((g, lock), axis=-2)

    @staticmethod
    def gamma(P, F):
        h = _line(P, F, rates=True).h_gamma()
        return np.stack((h, np.zeros_like(h)), axis=-1)
