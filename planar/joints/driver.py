"""Drivers: the input rows ``g(q) - u``.

The solver writes the input values ``u`` into ``P["c"]``; the velocity right-hand side of a
driver row is the input rate, and its gamma gets the input acceleration added.
"""

import numpy as np

from planar.errors import FileFormatError
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

    def driver_entry(self, joints, points):
        """A body's absolute angle as {"body"}, a revolute's angle as {"joint"}."""
        from planar.model import GROUND

        own = sorted((j for j in joints if j.measures(self)), key=lambda j: j.name != self.name)
        if self.bodies[0] == GROUND and (self.name == self.bodies[1] or not own):
            return _named({"body": self.bodies[1]}, self.name, self.bodies[1])
        return _joint_entry(self, own)


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

    def driver_entry(self, joints, points):
        """A slider's or slot's travel as {"joint"}."""
        return _joint_entry(self, sorted((j for j in joints if j.measures(self)), key=lambda j: j.name != self.name))


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

    def driver_entry(self, joints, points):
        """A named point's world coordinate as {"point", "axis"}."""
        axis = "x" if self.data["axis"][0] == 1.0 else "y"
        (body,) = self.bodies
        named = [n for n, (b, p) in points.items() if b == body and np.array_equal(p, self.data["at"])]
        point = ([n for n in named if f"{n}.{axis}" == self.name] or named)[0]
        return _named({"point": point, "axis": axis}, self.name, f"{point}.{axis}")


# ---- the file form: each driver's entry in a file's "drivers" (the drive() call that makes it)


def _joint_entry(driver, own):
    """{"joint"} of the first joint whose coordinate ``driver`` drives (``own``)."""
    if not own:
        raise FileFormatError(f"driver {driver.name!r} matches no joint coordinate or body angle")
    return _named({"joint": own[0].name}, driver.name, own[0].name)


def _named(entry, name, default):
    """The entry with the driver's ``name`` when it is not the one drive() gives by default."""
    return entry if name == default else entry | {"name": name}


__all__ = ["AngleDriver", "TravelDriver", "CoordinateDriver"]
