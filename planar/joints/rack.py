"""Rack and pinion, and a wheel rolling on a line: a circle rolling on a straight line."""

import numpy as np

from planar.joints.base import Joint, line_of, xy
from planar.joints import scalar


# ---- the scalar kernels (planar.joints.scalar): one joint at one configuration, for the
# compiled engine


def rack_pinion(p, c, f, s, phi, jac):
    sR = p[6]
    phi[0] = scalar.h_row(p, f, s, jac, 0) - c[0]
    phi[1] = scalar.t_row(p, f, s, jac, 1) + sR * (f[s[1], 2] - f[s[0], 2]) - c[1]
    jac[1, 2] -= sR
    jac[1, 5] += sR


def rack_pinion_gamma(p, c, f, s, g):
    g[0], g[1] = scalar.line_gammas(p, f, s)


# the file fields of a circle rolling on a line: its radius and centre, the line, and the side
CONTACT_FIELDS = {"radius": ("positive", True), "centre": ("point", True), "through": ("point", True),
                  "direction": ("vector", True), "side": ("side", False)}


class RackPinion(Joint):
    """Pitch circle (radius R, centre on the pinion) rolling without slip on a pitch line
    fixed in the rack body (ground or moving). Bodies are (rack, pinion).

    Rows ``n.d - sigma R`` (tangency) and ``u.d + sigma R (phi_pinion - phi_rack) - c`` (no
    slip), d from the line's origin to the pinion centre, sigma = +1 when the centre is left of
    the directed line. A wheel rolling to the right on a floor turns clockwise.
    """

    rolls = True
    n_rows = 2
    scalar_kernels = (("s", "u", "sR"), rack_pinion, rack_pinion_gamma)
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
            "alpha": np.array(d["pressure_angle"]),
        }

    @staticmethod
    def Phi(P, F):
        ln = line_of(P, F)
        return np.stack((ln.h, ln.t + P["sR"] * (F.phi[1] - F.phi[0]))) - P["c"]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        ln, out = line_of(P, F), cls.block(F, out)
        ln.h_grad(out[0])
        ln.t_grad(out[1])
        out[1, 2] -= P["sR"]
        out[1, 5] += P["sR"]
        return np.stack((ln.h, ln.t + P["sR"] * (F.phi[1] - F.phi[0]))) - P["c"], out

    @staticmethod
    def gamma(P, F):
        ln = line_of(P, F, rates=True)
        return np.stack((ln.h_gamma(), ln.t_gamma()))

    @classmethod
    def reaction(cls, P, F, lam):
        """At the contact point, on the pinion: ``normal`` the line's push towards its centre
        (positive presses the two together), ``tangential`` along the line's direction (the
        friction of a rolling wheel), and ``contact`` |tangential| / cos alpha, the tooth force
        along the pressure line."""
        Ft = -lam[1]
        return {"normal": -lam[0] * np.sign(P["sR"]), "tangential": Ft, "contact": np.abs(Ft) / np.cos(P["alpha"])}

    def touch_points(self):
        from planar.model import GROUND  # (here: the model imports the joints)

        # a ground line's point only says where the line lies (as a slot's origin): far along
        # it, it is no part of the drawing, nor of the sketch's size
        line = [] if self.bodies[0] == GROUND else [(self.bodies[0], self.data["through"])]
        return line + [(self.bodies[1], self.data["centre"])]

    def anchor(self):
        return self.bodies[1], self.data["centre"]

    # ---- the file form and the drawing part ---------------------------------------------------

    # bodies [pinion, rack] in a file, as Mechanism.add_rack_pinion and add_rolling take them; a
    # contact without teeth (pressure angle 0) is a "rolling" one
    file_types = {"rack_pinion": CONTACT_FIELDS | {"pressure_angle": ("angle", False)}, "rolling": CONTACT_FIELDS}
    labelled = False  # its point is the pinion's centre

    def file_entry(self):
        rack, pinion = self.bodies
        d = self.data
        e = {"type": "rack_pinion" if d["pressure_angle"] else "rolling", "name": self.name,
             "bodies": [pinion, rack], "radius": float(d["radius"]), "centre": xy(d["centre"]),
             "through": xy(d["through"]), "direction": xy(d["direction"]), "side": "left" if d["side"] > 0 else "right"}
        return e | ({"pressure_angle_rad": float(d["pressure_angle"])} if d["pressure_angle"] else {})

    def guide_line(self, scene, P):
        rack, pinion = scene.ids(self)
        return rack, P["s"][0], P["u"], (pinion, P["s"][1]), abs(float(P["sR"])) + scene.size

    def attach(self, scene, P):
        rack, pinion = scene.ids(self)
        ends = scene.line_ends(self.name)
        return [(pinion, P["s"][1])] + ([(rack, 0.5 * (ends[0] + ends[1]))] if rack != 0 else [])

    def draw_part(self, scene, P, q, ax):
        """A toothed pitch line (hatched on the ground) and the pinion's pitch circle."""
        rack, pinion = scene.ids(self)
        ends = [scene.world(q, rack, e) for e in scene.line_ends(self.name)]
        arts = scene.rack(ax, ends, float(np.sign(P["sR"])), hatch=rack == 0)
        return arts + scene.wheel(ax, q, pinion, P["s"][1], abs(float(P["sR"])))
