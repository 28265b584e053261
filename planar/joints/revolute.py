"""Revolute (pin) joint: a point of one body stays on a point of another."""

import numpy as np

from planar.joints.base import Joint, pair_blocks, point_pair, xy
from planar.joints import scalar


# ---- the scalar kernels (planar.joints.scalar): one joint at one configuration, for the
# compiled engine


def revolute(p, c, f, s, phi, jac):
    dx, dy, sax, say, sbx, sby = scalar.pair(p, f, s)
    phi[0], phi[1] = dx - c[0], dy - c[1]
    jac[0, 0], jac[0, 1], jac[0, 2], jac[0, 3], jac[0, 4], jac[0, 5] = -1.0, 0.0, say, 1.0, 0.0, -sby
    jac[1, 0], jac[1, 1], jac[1, 2], jac[1, 3], jac[1, 4], jac[1, 5] = 0.0, -1.0, -sax, 0.0, 1.0, sbx


def revolute_gamma(p, c, f, s, g):
    sax, say = scalar.vec(f, s, 0, p[0], p[1])
    sbx, sby = scalar.vec(f, s, 1, p[2], p[3])
    wa2, wb2 = f[s[0], 7] * f[s[0], 7], f[s[1], 7] * f[s[1], 7]
    g[0], g[1] = sbx * wb2 - sax * wa2, sby * wb2 - say * wa2


class Revolute(Joint):
    """Pin at world point ``at`` of the sketch, between bodies a and b.

    Rows ``P_b - P_a = 0`` (2 length rows); gamma = S_b w_b^2 - S_a w_a^2.
    Its coordinate is the relative angle phi_b - phi_a.
    """

    n_rows = 2
    scalar_kernels = (("s",), revolute, revolute_gamma)
    n_bodies = 2
    length_rows = (True, True)
    pin = True

    def local_params(self, sketch):
        a, b = self.bodies
        at = self.data["at"]
        return {"s": np.stack((sketch.local_point(a, at), sketch.local_point(b, at)))}

    @staticmethod
    def Phi(P, F):
        d, _ = point_pair(F, P["s"])
        return d - P["c"]

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        return pair_blocks(F.vecs(P["s"]), cls.block(F, out), constants)

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        d, S = point_pair(F, P["s"])
        return d - P["c"], pair_blocks(S, cls.block(F, out), constants)

    @staticmethod
    def gamma(P, F):
        # the centripetal terms only: -(S_a w_a^2 - S_b w_b^2)
        Sw2 = F.vecs(P["s"]) * F.phid**2
        return Sw2[:, 1] - Sw2[:, 0]

    def touch_points(self):
        return [(b, self.data["at"]) for b in self.bodies]

    def anchor(self):
        return self.bodies[1], self.data["at"]

    def coordinate(self):
        from planar.joints.driver import AngleDriver

        return AngleDriver(self.name, self.bodies)

    # ---- the file form and the drawing part ---------------------------------------------------

    file_types = {"revolute": {"at": ("point", True)}}

    def file_entry(self):
        return {"type": "revolute", "name": self.name, "bodies": list(self.bodies), "at": xy(self.data["at"])}

    def attach(self, scene, P):
        return list(zip(scene.ids(self), P["s"]))

    def pin_point(self, scene, P):
        return scene.ids(self)[0], P["s"][0]

    def draw_part(self, scene, P, q, ax):
        """A pin; on the ground, standing on a hatched pivot."""
        a, b = scene.ids(self)
        p = scene.world(q, a, P["s"][0])
        return (scene.ground_pivot(ax, p) if 0 in (a, b) else []) + scene.pin(ax, p)
