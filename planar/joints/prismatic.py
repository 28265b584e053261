"""Prismatic joint (slider) and pin-in-slot: a point of body b on a line fixed in body a."""

from typing import ClassVar

import numpy as np

from planar.joints.base import LOCK, Joint, line_of, line_params, xy
from planar.joints import scalar
from planar.joints.driver import TravelDriver

# the file fields of a line joint: the pin's sketch point, the line's direction and origin
LINE_FIELDS = {"at": ("point", True), "direction": ("vector", True), "origin": ("point", False)}


# ---- the scalar kernels (planar.joints.scalar): one joint at one configuration, for the
# compiled engine


def slot(p, c, f, s, phi, jac):
    phi[0] = scalar.h_row(p, f, s, jac, 0) - c[0]  # the normal distance n.d


def slot_gamma(p, c, f, s, g):
    g[0] = scalar.line_gammas(p, f, s)[0]


def prismatic(p, c, f, s, phi, jac):
    slot(p, c, f, s, phi, jac)  # and the relative angle locked
    scalar.lock_row(jac, 1)
    phi[1] = f[s[1], 2] - f[s[0], 2] - c[1]


def prismatic_gamma(p, c, f, s, g):
    g[0], g[1] = scalar.line_gammas(p, f, s)[0], 0.0


class Slot(Joint):
    """Pin-in-slot: the point ``at`` of body b stays on the line of body a through ``origin``
    along ``direction``; rotation free. One row, the normal distance n.d.
    Its coordinate is the travel along the line from ``origin``.
    """

    n_rows = 1
    scalar_kernels = (("s", "u"), slot, slot_gamma)
    n_bodies = 2
    length_rows: ClassVar[tuple] = (True,)
    slides = True

    local_params = line_params

    @staticmethod
    def Phi(P, F):
        return line_of(P, F).h - P["c"]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        ln, out = line_of(P, F), cls.block(F, out)
        ln.h_grad(out[0])
        return ln.h - P["c"], out

    @staticmethod
    def gamma(P, F):
        return line_of(P, F, rates=True).h_gamma()[None]

    @classmethod
    def reaction(cls, P, F, lam):
        """``normal``: the force on b along the line's left normal (it acts at b's point)."""
        return {"normal": -lam[0]}

    def touch_points(self):
        from planar.model import GROUND  # (here: the model imports the joints)

        # a ground line's origin only names where travel counts from: far off, it is no part of
        # the drawing, and the sketch's size (the Jacobian's scale) must not take it in
        line = [] if self.bodies[0] == GROUND else [(self.bodies[0], self.data["origin"])]
        return line + [(self.bodies[1], self.data["at"])]

    def anchor(self):
        return self.bodies[1], self.data["at"]

    def coordinate(self):
        return TravelDriver(self.name, self.bodies, **self.data)

    # ---- the file form and the drawing part ---------------------------------------------------

    file_types = {"slot": LINE_FIELDS}

    def file_entry(self):
        d = self.data
        return {"type": next(iter(self.file_types)), "name": self.name, "bodies": list(self.bodies),
                "at": xy(d["at"]), "direction": xy(d["direction"]), "origin": xy(d["origin"])}

    def guide_line(self, scene, P):
        a, b = scene.ids(self)
        return a, P["s"][0], P["u"], (b, P["s"][1]), self.runner_length(scene)

    @staticmethod
    def runner_length(scene):
        """How far the line runs past the pin's travel: the pin's size."""
        return scene.size

    def attach(self, scene, P):
        a, b = scene.ids(self)
        # a moving guide is part of its body: the body's bar runs along it
        return [(b, P["s"][1])] + ([(a, e) for e in scene.line_ends(self.name)] if a != 0 else [])

    def draw_part(self, scene, P, q, ax):
        """A slot along the line, with the pin in it."""
        a, b = scene.ids(self)
        ends = [scene.world(q, a, e) for e in scene.line_ends(self.name)]
        return scene.slot(ax, ends) + scene.pin(ax, scene.world(q, b, P["s"][1]))


class Prismatic(Slot):
    """Slider: as :class:`Slot`, and the relative rotation phi_b - phi_a is locked at its
    sketch value (second row, an angle)."""

    n_rows = 2
    scalar_kernels = (("s", "u"), prismatic, prismatic_gamma)
    length_rows = (True, False)
    sketch_rows = (1,)

    @staticmethod
    def Phi(P, F):
        return np.stack((line_of(P, F).h, F.phi[1] - F.phi[0])) - P["c"]

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        ln, out = line_of(P, F), cls.block(F, out)
        ln.h_grad(out[0])
        if constants:
            out[1] = LOCK
        return np.stack((ln.h, F.phi[1] - F.phi[0])) - P["c"], out

    @staticmethod
    def gamma(P, F):
        h = line_of(P, F, rates=True).h_gamma()
        return np.stack((h, np.zeros_like(h)))

    @classmethod
    def reaction(cls, P, F, lam):
        """``normal`` as :class:`Slot`, and ``moment``: the couple on b (counter-clockwise)."""
        return {"normal": -lam[0], "moment": -lam[1]}

    file_types = {"prismatic": LINE_FIELDS}

    @staticmethod
    def runner_length(scene):
        """How far the line runs past the slider's travel: half a block."""
        return scene.block[0]

    def block_point(self, scene, P):
        return scene.ids(self)[1], P["s"][1]

    def draw_part(self, scene, P, q, ax):
        """A block on the line; a ground guide hatched (a moving one is its body's bar)."""
        a, b = scene.ids(self)
        p = scene.world(q, b, P["s"][1])
        guide = scene.guide(ax, [scene.world(q, a, e) for e in scene.line_ends(self.name)]) if a == 0 else []
        return guide + scene.block_at(ax, p, scene.turn(q, a, P["u"]), scene.colour(b)) + scene.pin(ax, p)
