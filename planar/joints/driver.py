"""Drivers: the input rows ``g(q) - u``.

The solver writes the input values ``u`` into ``P["c"]``; the velocity right-hand side of a
driver row is the input rate, and its gamma gets the input acceleration added.
"""

import numpy as np

from planar.errors import FileFormatError
from planar.geometry import cross_cf, dot_cf
from planar.joints.base import LOCK, Joint, line_of, line_params
from planar.joints import scalar


# ---- the scalar kernels (planar.joints.scalar): one joint at one configuration, for the
# compiled engine


def travel_driver(p, c, f, s, phi, jac):
    phi[0] = scalar.t_row(p, f, s, jac, 0) - c[0]  # the travel u.d


def travel_driver_gamma(p, c, f, s, g):
    g[0] = scalar.line_gammas(p, f, s)[1]


def angle_driver(p, c, f, s, phi, jac):
    scalar.lock_row(jac, 0)
    phi[0] = f[s[1], 2] - f[s[0], 2] - c[0]


def coordinate_driver(p, c, f, s, phi, jac):
    sx, sy = scalar.vec(f, s, 0, p[0], p[1])
    phi[0] = (f[s[0], 0] + sx) * p[2] + (f[s[0], 1] + sy) * p[3] - c[0]
    jac[0, 0], jac[0, 1], jac[0, 2] = p[2], p[3], sx * p[3] - sy * p[2]


def coordinate_driver_gamma(p, c, f, s, g):
    sx, sy = scalar.vec(f, s, 0, p[0], p[1])
    g[0] = (sx * p[2] + sy * p[3]) * f[s[0], 7] * f[s[0], 7]


class AngleDriver(Joint):
    """Relative angle phi_b - phi_a (a revolute's angle; with a = ground, b's absolute angle)."""

    n_rows = 1
    scalar_kernels = ((), angle_driver, scalar.linear_gamma)
    n_bodies = 2
    length_rows = (False,)
    is_driver = True
    relative_angle = True

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
    scalar_kernels = (("s", "u"), travel_driver, travel_driver_gamma)
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
    scalar_kernels = (("s", "e"), coordinate_driver, coordinate_driver_gamma)
    n_bodies = 1
    length_rows = (True,)
    is_driver = True

    def local_params(self, sketch):
        (b,) = self.bodies
        return {"s": sketch.local_point(b, self.data["at"]), "e": np.asarray(self.data["axis"], float)}

    def touch_points(self):
        return [(self.bodies[0], self.data["at"])]

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
