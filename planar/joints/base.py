"""The joint contract: residual rows, Jacobian blocks and gamma, batched.

A joint class couples ``n_bodies`` bodies and adds ``n_rows`` rows to the constraint system.
Its three kernels work on a whole *group* of K joints of that class at once, over any
leading batch axes (configurations, designs):

- ``Phi(P, F)``      -> (..., K, n_rows)             residual rows
- ``Phi_q(P, F)``    -> (..., K, n_rows, 3*n_bodies)  Jacobian blocks, (x, y, phi) per body slot
- ``gamma(P, F)``    -> (..., K, n_rows)             acceleration right-hand side,
  ``Phi_q qdd = gamma``, i.e. minus the part of the second time derivative free of qdd.

``Phi_and_Phi_q(P, F)`` returns both of the first two; the base class calls them in turn, a
class may override it to share the world vectors between them.

``P`` holds the group's stacked parameters (arrays with a leading K axis); ``F`` is a
:class:`planar.geometry.Frames` of the bodies' poses and rates. Every class keeps its rows in
the form ``f(q) - c`` with ``c = P["c"]`` (K, n_rows): for rows listed in ``sketch_rows`` the
model sets ``c`` so the row holds at the assembled sketch (rolling contacts, locked relative
angles), and for a driver the solver puts the input values there. The solver never asks a
joint's type; it only calls these kernels.
"""

from typing import ClassVar

import numpy as np

from planar.geometry import cross, dot, perp, point_block


class Joint:
    """Base of every joint and driver.

    Subclasses set the class attributes and implement the three kernels, plus
    ``local_params(sketch)`` that turns the world-coordinate sketch data into body-fixed
    parameters (``sketch`` is the model's :class:`SketchFrames`).
    """

    n_rows: ClassVar[int]
    n_bodies: ClassVar[int]
    length_rows: ClassVar[tuple]  # per row: True for a length, False for an angle
    sketch_rows: ClassVar[tuple] = ()  # rows whose constant c comes from the assembled sketch
    is_driver: ClassVar[bool] = False

    def __init__(self, name, bodies, **data):
        self.name = name
        self.bodies = tuple(bodies)
        self.data = data

    def __repr__(self):
        return f"{type(self).__name__}({self.name!r}, bodies={self.bodies})"

    def local_params(self, sketch):
        raise NotImplementedError

    @classmethod
    def Phi_and_Phi_q(cls, P, F):
        """(Phi, Phi_q) in one call; classes whose two kernels share work override it."""
        return cls.Phi(P, F), cls.Phi_q(P, F)

    def params(self, sketch):
        """Body-fixed parameters with the constant ``c`` (zero until the model sets it)."""
        P = {k: np.asarray(v, dtype=float) for k, v in self.local_params(sketch).items()}
        P.setdefault("c", np.zeros(self.n_rows))
        return P

    def anchor(self):
        """(body, world point at the sketch) that names the joint's position, or None."""
        return None

    def touch_points(self):
        """[(body, world point)] where the joint attaches in the sketch (body frame origins)."""
        return []

    def coordinate(self):
        """A driver that measures this joint's own coordinate, or None if it has none."""
        return None

    def describe(self):
        kind = type(self).__name__.lower()
        return f"{kind} '{self.name}' between {', '.join(repr(b) for b in self.bodies)}"


class SketchFrames:
    """Body frames at the sketch: converts world sketch data into body-fixed vectors."""

    def __init__(self, origins, angles):
        self.origins = origins  # name -> (2,)
        self.angles = angles  # name -> float

    def local_point(self, body, p):
        c, s = np.cos(self.angles[body]), np.sin(self.angles[body])
        d = np.asarray(p, dtype=float) - self.origins[body]
        return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])

    def local_direction(self, body, v):
        v = np.asarray(v, dtype=float)
        v = v / np.hypot(v[0], v[1])
        c, s = np.cos(self.angles[body]), np.sin(self.angles[body])
        return np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1]])


# ---- shared pieces: two body points, and a point against a line ------------------------


def point_pair(F, s_a, s_b, a=0, b=1):
    """d = P_b - P_a between points s_a on slot a and s_b on slot b: (d, S_a, S_b)."""
    Pa, Sa = F.point(a, s_a)
    Pb, Sb = F.point(b, s_b)
    return Pb - Pa, Sa, Sb


def pair_rates(F, Sa, Sb, a=0, b=1):
    """(d_dot, d_ddot without the qdd terms) for d = P_b - P_a."""
    dd = F.point_rate(b, Sb) - F.point_rate(a, Sa)
    wa, wb = F.phid[..., a, None], F.phid[..., b, None]
    return dd, Sa * wa**2 - Sb * wb**2


def scalar_blocks(g_ra, g_pa, g_rb, g_pb):
    """Stack the gradient of a scalar row into (..., 6) for slots (a, b)."""
    return np.concatenate(
        (g_ra, g_pa[..., None], g_rb, g_pb[..., None]), axis=-1
    )


def pair_blocks(Sa, Sb):
    """Jacobian (..., 2, 6) of d = P_b - P_a with respect to (x, y, phi) of slots a, b."""
    out = np.zeros(Sa.shape[:-1] + (2, 6))
    point_block(Sa, -1.0, out[..., :3])
    point_block(Sb, 1.0, out[..., 3:])
    return out


class Line:
    """A point (slot b) against a line fixed in slot a: through s_a with direction u'.

    ``h = n.d`` is the signed normal distance (n = perp(u), left of the direction positive),
    ``t = u.d`` the travel along the line from s_a.
    """

    def __init__(self, F, s_a, u_local, s_b, a=0, b=1, rates=False):
        self.d, self.Sa, self.Sb = point_pair(F, s_a, s_b, a, b)
        self.u = F.vec(a, u_local)
        self.n = perp(self.u)
        if rates:
            self.dd, self.ddq = pair_rates(F, self.Sa, self.Sb, a, b)
            self.wa = F.phid[..., a]

    @property
    def h(self):
        return dot(self.n, self.d)

    @property
    def t(self):
        return dot(self.u, self.d)

    def h_grad(self):
        n, u, d = self.n, self.u, self.d
        return scalar_blocks(-n, -dot(u, d) - dot(n, perp(self.Sa)), n, dot(n, perp(self.Sb)))

    def t_grad(self):
        n, u, d = self.n, self.u, self.d
        return scalar_blocks(-u, dot(n, d) - dot(u, perp(self.Sa)), u, dot(u, perp(self.Sb)))

    def h_gamma(self):
        w = self.wa
        return w**2 * dot(self.n, self.d) + 2 * w * dot(self.u, self.dd) - dot(self.n, self.ddq)

    def t_gamma(self):
        w = self.wa
        return w**2 * dot(self.u, self.d) - 2 * w * dot(self.n, self.dd) - dot(self.u, self.ddq)


def wrap(a):
    """Wrap angles into [-pi, pi)."""
    return (a + np.pi) % (2 * np.pi) - np.pi


__all__ = ["Joint", "SketchFrames", "Line", "point_pair", "pair_rates", "pair_blocks",
           "scalar_blocks", "wrap", "cross", "dot", "perp"]
