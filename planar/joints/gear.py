"""Gear pairs (pitch circles rolling without slip), external (s = +1) or internal (s = -1).

All rows are linear in the unwrapped body angles, so angles are never reduced modulo 2 pi.
"""

from typing import ClassVar

import numpy as np

from planar.geometry import Frames, cross_cf, dot_cf, perp_cf
from planar.joints.base import Joint, pair_rates, pair_row, point_pair, wrap, xy
from planar.joints import scalar


# ---- the scalar kernels (planar.joints.scalar): one joint at one configuration, for the
# compiled engine


def carrier_gear(p, c, f, s, phi, jac):
    Ri, Rj = p[0], p[1]
    phi[0] = Ri * (f[s[0], 2] - f[s[2], 2]) + Rj * (f[s[1], 2] - f[s[2], 2]) - c[0]
    for k in range(9):
        jac[0, k] = 0.0
    jac[0, 2], jac[0, 5], jac[0, 8] = Ri, Rj, -(Ri + Rj)


def gear(p, c, f, s, phi, jac):
    phi[0] = scalar.rolling(p, c[0], f, s, jac, 0)[0]


def gear_gamma(p, c, f, s, g):
    g[0] = scalar.rolling_gamma(p, f, s)[0]


def rolling_contact(p, c, f, s, phi, jac):
    row, dx, dy, sax, say, sbx, sby = scalar.rolling(p, c[1], f, s, jac, 1)
    D = abs(p[4] + p[5])
    phi[0], phi[1] = (dx * dx + dy * dy - D * D) / (2 * D) - c[0], row
    scalar.pair_row(jac, 0, dx / D, dy / D, (dx * say - dy * sax) / D, (sbx * dy - sby * dx) / D)


def rolling_contact_gamma(p, c, f, s, g):
    roll, dx, dy, ddx, ddy, qx, qy = scalar.rolling_gamma(p, f, s)
    g[0] = -(ddx * ddx + ddy * ddy + dx * qx + dy * qy) / abs(p[4] + p[5])
    g[1] = roll


class CarrierGear(Joint):
    """Gears i and j whose centres are fixed on one carrier body a (or both on the ground).

    Row ``R_i (phi_i - phi_a) + s R_j (phi_j - phi_a) - c`` (a length), gamma = 0; ``c`` is
    taken at the assembled sketch, so the gears mesh as drawn. Its force is the tooth force at
    the pitch point, as :class:`Gear`'s row gives it (the row's own transpose would put it on
    the carrier as torques, past the pins that carry it).
    """

    rolls = True
    n_rows = 1
    scalar_kernels = (("R",), carrier_gear, scalar.linear_gamma)
    n_bodies = 3
    length_rows = (True,)
    sketch_rows = (0,)

    def local_params(self, sketch):
        return _gear_params(self, sketch)

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

    @classmethod
    def force_rows(cls, P, F):
        out = np.zeros((1, 9) + F.shape)
        _rolling_grad(_rolling(P, _gears(F)), P, out[0, :6])
        return out

    @classmethod
    def reaction(cls, P, F, lam):
        return _mesh_reaction(P, _gears(F), lam[0])

    @classmethod
    def contact_load(cls, P, F, lam):
        radial = _radial_load(P, _gears(F), lam[0])
        return None if radial is None else np.concatenate((radial, np.zeros((3,) + F.shape)))

    def touch_points(self):
        return [(self.bodies[0], self.data["centre_a"]), (self.bodies[1], self.data["centre_b"])]

    def anchor(self):
        return self.bodies[1], self.data["centre_b"]

    # ---- the file form and the drawing part (a "gear" entry with a carrier) -------------------

    labelled = False  # its point is a gear centre, named by the pin there

    def file_entry(self):
        return _gear_entry(self, carrier=self.bodies[2])

    def wheel_centres(self, scene, P):
        """(body id, body-fixed centre) of both gears: the sketch centres in the gears' frames
        at the assembled sketch (a carrier's mesh keeps no centres among its parameters)."""
        q0 = scene.model.q0
        return [(b, scene.local(q0, b, np.asarray(self.data[key], float)))
                for b, key in zip(scene.ids(self)[:2], ("centre_a", "centre_b"))]

    attach = wheel_centres

    def draw_part(self, scene, P, q, ax):
        return _draw_wheels(self, scene, P, q, ax)


# the file fields of a "gear" entry (Mechanism.add_gear)
GEAR_FIELDS = {"radius_a": ("positive", True), "radius_b": ("positive", True), "internal": ("bool", False),
               "carrier": ("name", False), "centre_a": ("point", False), "centre_b": ("point", False),
               "hold_distance": ("bool", False), "pressure_angle": ("angle", False)}


def _gear_entry(joint, carrier=None, hold_distance=False):
    d = joint.data
    e = {"type": "gear", "name": joint.name, "bodies": list(joint.bodies[:2]), "radius_a": float(d["radius_a"]),
         "radius_b": float(d["radius_b"]), "internal": bool(d["sign"] < 0)}
    if carrier is not None:
        e["carrier"] = carrier
    return e | {"centre_a": xy(d["centre_a"]), "centre_b": xy(d["centre_b"]), "hold_distance": hold_distance,
                "pressure_angle_rad": float(d["pressure_angle"])}


def _draw_wheels(joint, scene, P, q, ax):
    """Both pitch circles; an internal gear's larger one as a ring."""
    R = np.abs(P["R"])
    internal = P["R"][1] < 0
    arts = []
    for k, (b, s) in enumerate(joint.wheel_centres(scene, P)):
        arts += scene.wheel(ax, q, b, s, R[k], ring=internal and R[k] > R[1 - k])
    return arts


def _gears(F):
    """The frames of the two gears (slots 0 and 1) of a carrier's mesh."""
    return Frames(F.r[:, :2], F.phi[:2], F.c[:2], F.s[:2])


def _radial_load(P, F, lam):
    """The radial part of the tooth force, |F_t| tan alpha along the line of centres, pushing
    the pitch circles apart: on b along s d (s = -1 inside a ring), on a the opposite."""
    if not np.any(P["alpha"]):
        return None
    d, S, Ft = _tangential(P, F, lam)
    f = d * (np.abs(Ft) * np.tan(P["alpha"]) * np.sign(P["R"][1]) / np.sqrt(dot_cf(d, d)))
    out = np.zeros((6,) + F.shape)
    out[0:2], out[2] = -f, -cross_cf(S[:, 0], f)
    out[3:5], out[5] = f, cross_cf(S[:, 1], f)
    return out


def _tangential(P, F, lam):
    """d from centre a to centre b, the centres' world vectors S, and the no-slip row's force on
    b along perp(d), K / |d| lam."""
    d, S = point_pair(F, P["s"])
    return d, S, lam * (P["R"][0] + P["R"][1]) / np.sqrt(dot_cf(d, d))


def _mesh_reaction(P, F, lam):
    """The tooth force on gear b: ``tangential`` along perp(d) (:func:`_tangential`), and along the pressure line of pressure angle
    alpha the ``contact`` force |F_t| / cos alpha, whose ``radial`` part |F_t| tan alpha
    pushes the gears apart (carried by whatever holds their centre distance)."""
    Ft = _tangential(P, F, lam)[2]
    return {"tangential": Ft, "radial": np.abs(Ft) * np.tan(P["alpha"]), "contact": np.abs(Ft) / np.cos(P["alpha"])}


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
    a, b = joint.bodies[:2]
    d = joint.data
    return {
        "s": np.stack((sketch.local_point(a, d["centre_a"]), sketch.local_point(b, d["centre_b"]))),
        "R": np.array([d["radius_a"], d["sign"] * d["radius_b"]]),
        "alpha": np.array(d["pressure_angle"]),
    }


class Gear(Joint):
    """Gears on two different moving bodies whose centre distance other joints hold.

    Row ``R_i phi_i + s R_j phi_j - (R_i + s R_j) theta - c``, theta the angle of the line of
    centres (no-slip at the pitch point). Reduces to :class:`CarrierGear` when the centres
    sit on one arm.
    """

    rolls = True
    n_rows = 1
    scalar_kernels = (("s", "R"), gear, gear_gamma)
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

    @classmethod
    def reaction(cls, P, F, lam):
        return _mesh_reaction(P, F, lam[0])

    @classmethod
    def contact_load(cls, P, F, lam):
        return _radial_load(P, F, lam[0])

    def touch_points(self):
        return [(self.bodies[0], self.data["centre_a"]), (self.bodies[1], self.data["centre_b"])]

    def anchor(self):
        return self.bodies[1], self.data["centre_b"]

    # ---- the file form and the drawing part ---------------------------------------------------

    file_types = {"gear": GEAR_FIELDS}  # with a carrier a CarrierGear, with hold_distance a RollingContact
    labelled = False  # its point is a gear centre

    def file_entry(self):
        return _gear_entry(self)

    def wheel_centres(self, scene, P):
        """(body id, body-fixed centre) of both gears."""
        return list(zip(scene.ids(self), P["s"]))

    attach = wheel_centres

    def draw_part(self, scene, P, q, ax):
        return _draw_wheels(self, scene, P, q, ax)


class RollingContact(Gear):
    """A circle rolling on (or inside) another with no arm: the :class:`Gear` row plus the
    contact row ``(d.d - D^2) / (2 D) = 0`` that holds the centre distance D = |R_i + s R_j|."""

    n_rows = 2
    scalar_kernels = (("s", "R"), rolling_contact, rolling_contact_gamma)
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

    @classmethod
    def reaction(cls, P, F, lam):
        """``normal``: the push of a on b at the contact, positive when they press together (along
        d for an external contact, against d inside a circle); ``friction``: along perp(d), as
        :class:`Gear`'s tangential force."""
        d, _, friction = _tangential(P, F, lam[1])
        inside = np.sign(P["R"][1])  # -1 for a circle rolling inside another
        return {"normal": -lam[0] * inside * np.sqrt(dot_cf(d, d)) / RollingContact._D(P), "friction": friction}

    @classmethod
    def contact_load(cls, P, F, lam):
        return None  # a smooth contact: its normal row carries the push

    def file_entry(self):
        return _gear_entry(self, hold_distance=True)
