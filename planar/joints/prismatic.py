"""Prismatic joint (slider) and pin-in-slot: a point of body b on a line fixed in body a."""

from typing import ClassVar

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
    return Line(F, P["s"], P["u"], rates=rates)


# the locked relative angle phi_b - phi_a: its constant gradient row (6, 1, 1)
_LOCK = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 1.0])[:, None, None]


class Slot(Joint):
    """Pin-in-slot: the point ``at`` of body b stays on the line of body a through ``origin``
    along ``direction``; rotation free. One row, the normal distance n.d.
    Its coordinate is the travel along the line from ``origin``.
    """

    n_rows = 1
    n_bodies = 2
    length_rows: ClassVar[tuple] = (True,)

    local_params = _line_params

    @staticmethod
    def Phi(P, F):
        return _line(P, F).h - P["c"]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        ln, out = _line(P, F), cls.block(F, out)
        ln.h_grad(out[0])
        return ln.h - P["c"], out

    @staticmethod
    def gamma(P, F):
        return _line(P, F, rates=True).h_gamma()[None]

    @classmethod
    def reaction(cls, P, F, lam):
        """``normal``: the force on b along the line's left normal (it acts at b's point)."""
        return {"normal": -lam[0]}

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
        return np.stack((_line(P, F).h, F.phi[1] - F.phi[0])) - P["c"]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        ln, out = _line(P, F), cls.block(F, out)
        ln.h_grad(out[0])
        if constants:
            out[1] = _LOCK
        return np.stack((ln.h, F.phi[1] - F.phi[0])) - P["c"], out

    @staticmethod
    def gamma(P, F):
        h = _line(P, F, rates=True).h_gamma()
        return np.stack((h, np.zeros_like(h)))

    @classmethod
    def reaction(cls, P, F, lam):
        """``normal`` as :class:`Slot`, and ``moment``: the couple on b (counter-clockwise)."""
        return {"normal": -lam[0], "moment": -lam[1]}
