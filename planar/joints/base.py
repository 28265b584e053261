"""The joint contract: residual rows, Jacobian blocks and gamma, batched.

A joint class couples ``n_bodies`` bodies and adds ``n_rows`` rows to the constraint system.
Its three kernels work on a whole *group* of K joints of that class at once, over any
trailing batch axes (configurations, ...). Arrays are *components first, configurations
last* (structure of arrays), so that every numpy operation runs over whole rows of
configurations, never an inner loop over the 2 components of a vector or a few joints:

- ``Phi(P, F)``            -> (n_rows, K, ...)              residual rows
- ``Phi_q(P, F, out=None, constants=True)`` -> (n_rows, 3*n_bodies, K, ...)  Jacobian blocks,
  (x, y, phi) per body slot; written into ``out`` (every entry of it) when given, so that the
  system writes the blocks straight into its array of Jacobian values. With
  ``constants=False`` a kernel may leave unwritten the entries that are the same numbers for
  every joint of its class at every pose (a revolute's +-1 and 0 on the x and y columns, a
  locked angle's row): the caller holds their values (the block solves take constants from
  the plan, :mod:`planar.elimination`), and these are ~2/3 of a revolute's entries
- ``gamma(P, F)``          -> (n_rows, K, ...)              acceleration right-hand side,
  ``Phi_q qdd = gamma``, i.e. minus the part of the second time derivative free of qdd.

``Phi_and_Phi_q(P, F, out=None, constants=True)`` returns both of the first two; a class
implements either it or ``Phi_q`` and the base class derives the other.

``F`` is a :class:`planar.geometry.Frames` of the bodies' poses and rates (slot axis before
K). ``P`` holds the group's parameters as :func:`kernel_params` lays them out: a parameter
of per-joint shape (a, b) (as ``local_params`` returns it, e.g. the body-fixed points
``s`` (slots, 2)) comes as (b, a, K, 1): vector components first, and a trailing axis of
length 1 that broadcasts over the configurations (or of length N for parameters that vary
per configuration, e.g. a batch of designs). Every class keeps its rows in the form
``f(q) - c`` with ``c = P["c"]`` (n_rows, K, 1): for rows listed in ``sketch_rows`` the
model sets ``c`` so the row holds at the assembled sketch (rolling contacts, locked relative
angles), and for a driver the solver puts the input values there. The solver never asks a
joint's type; it only calls these kernels.
"""

from typing import ClassVar

import numpy as np

from planar.errors import FileFormatError, InputError
from planar.geometry import cross_cf, dot_cf, perp_cf, rotate


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
    # what resolving a sketch asks of a joint: is its point one place of both its bodies (a
    # pin), does it slide along a line of its first body (a pin in a slot, a slider), is it a
    # driver of the angle between its two bodies
    pin: ClassVar[bool] = False
    slides: ClassVar[bool] = False
    relative_angle: ClassVar[bool] = False
    # whether its rows tie its bodies' angles as they are, by a ratio (a gear, a rack, a wheel
    # rolling): a linkage with one closes in the same assembly modes at many poses, far apart
    rolls: ClassVar[bool] = False
    # the scalar kernels of the compiled engine (planar.joints.scalar): (the parameters they read,
    # kernel, gamma kernel); None: engine="numba" refuses the type
    scalar_kernels: ClassVar[tuple | None] = None

    def __init__(self, name, bodies, **data):
        self.name = name
        self.bodies = tuple(bodies)
        self.data = data

    def __repr__(self):
        return f"{type(self).__name__}({self.name!r}, bodies={self.bodies})"

    def local_params(self, sketch):
        raise NotImplementedError

    @classmethod
    def Phi_and_Phi_q(cls, P, F, out=None, constants=True):
        """(Phi, Phi_q) in one call. A class implements this or :meth:`Phi_q` (the other
        follows): this when the two share their world vectors."""
        return cls.Phi(P, F), cls.Phi_q(P, F, out, constants)

    @classmethod
    def Phi_q(cls, P, F, out=None, constants=True):
        return cls.Phi_and_Phi_q(P, F, out, constants)[1]

    @classmethod
    def block(cls, F, out=None):
        """``out``, or a new array for the Jacobian blocks (n_rows, 3*n_bodies, K, ...)."""
        return np.empty((cls.n_rows, 3 * cls.n_bodies) + F.shape) if out is None else out

    @classmethod
    def force_rows(cls, P, F):
        """The rows (n_rows, 3*n_bodies, K, ...) whose transpose carries the joint's forces: the
        joint acts on its bodies with ``-force_rows^T lam`` for its Lagrange multipliers lam.
        Its Jacobian, unless its rows stand in for a contact elsewhere (gears on a carrier)."""
        return cls.Phi_q(P, F)

    @classmethod
    def reaction(cls, P, F, lam):
        """Named reaction components (K, ...) on the second body from the first, besides the
        force, from the multipliers ``lam`` (n_rows, K, ...): a normal force, a moment."""
        return {}

    @classmethod
    def contact_load(cls, P, F, lam):
        """Generalised forces (3*n_bodies, K, ...) the joint puts on its bodies besides
        ``-force_rows^T lam``, from its multipliers ``lam``; or None. Only forces that do no
        work in the motions the other joints allow (a tooth force's radial part)."""
        return None

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

    # ---- the file form (planar.io reads and writes it) ----------------------------------------

    # file entry "type" -> {field: (field kind, required)} besides "type", "name" and "bodies";
    # the builder method of a type is Mechanism.add_<type>; an "angle" field is in the file's
    # angle unit, or in radians as "<field>_rad"
    file_types: ClassVar[dict] = {}

    def file_entry(self):
        """The file entry that builds this joint: {"type", "name", "bodies", fields...} with
        angles in radians as "<field>_rad"."""
        raise FileFormatError(f"joint {self.name!r} of type {type(self).__name__} has no file form: "
                              f"give its class file_types and file_entry")

    def driver_entry(self, joints, points):
        """For a driver: its file entry in "drivers" ({"joint"}, {"body"} or {"point", "axis"},
        and "name" when not the default), given the sketch's ``joints`` and ``points``."""
        raise FileFormatError(f"driver {self.name!r} of type {type(self).__name__} has no file form")

    def measures(self, driver):
        """Whether ``driver`` drives this joint's own coordinate (as ``drive(joint=)`` makes it)."""
        c = self.coordinate()
        return (c is not None and type(c) is type(driver) and c.bodies == driver.bodies
                and c.data.keys() == driver.data.keys()
                and all(np.array_equal(c.data[k], driver.data[k]) for k in c.data))

    # ---- the drawing part (planar.draw's Scene calls these) ------------------------------------
    # ``scene`` gives body ids (scene.ids), world points (scene.world, scene.turn, scene.local)
    # and the drawing primitives; ``P`` is the joint's body-fixed parameters, as the system holds
    # them; ``q`` a pose.

    labelled: ClassVar[bool] = True  # a drawing names the joint's point (pins, sliders)

    def attach(self, scene, P):
        """[(body id, body-fixed point)] where the bodies' bars and plates hold on to the joint."""
        raise InputError(f"joint {self.name!r}: planar.draw has no picture for {type(self).__name__}; "
                         f"give its class attach and draw_part")

    def guide_line(self, scene, P):
        """(body id of the line, point, direction, (body id, point) that runs on it, padding)
        for a joint with a guide line or rack, else None."""
        return None

    def draw_part(self, scene, P, q, ax):
        """The artists that draw the joint at pose ``q`` on the axes ``ax``."""
        raise InputError(f"joint {self.name!r}: planar.draw has no picture for {type(self).__name__}; "
                         f"give its class attach and draw_part")

    # the marks of a drawing made of points alone (planar.app): pins, slider blocks, gear circles

    def pin_point(self, scene, P):
        """(body id, body-fixed point) of the joint's pin, or None."""
        return None

    def block_point(self, scene, P):
        """(body id, body-fixed point) of the joint's slider block, or None."""
        return None

    def wheel_centres(self, scene, P):
        """[(body id, body-fixed centre)] of the joint's pitch circles (radii ``P["R"]``)."""
        return []


def xy(p):
    """A point or vector as a file writes it: [x, y] of floats."""
    return [float(p[0]), float(p[1])]


class SketchFrames:
    """Body frames at the sketch: converts world sketch data into body-fixed vectors.

    Points and vectors have their components first: (2,) for one sketch, or (2, D) for D
    designs at once, with origins (2,) or (2, D) and angles float or (D,).

    >>> F = SketchFrames({"arm": np.array([1.0, 0.0])}, {"arm": np.pi / 2})
    >>> F.local_point("arm", np.array([1.0, 2.0])).round(12).tolist()
    [2.0, 0.0]
    >>> F = SketchFrames({"arm": np.zeros((2, 1))}, {"arm": np.array([0.0, np.pi / 2])})
    >>> F.local_point("arm", np.array([[1.0, 1.0], [2.0, 2.0]])).round(12).tolist()
    [[1.0, 2.0], [2.0, -1.0]]
    """

    def __init__(self, origins, angles):
        self.origins = origins  # name -> (2,) or (2, D)
        self.angles = angles  # name -> float or (D,)

    def _to_body(self, body, v):
        # rotate works on the last axis: components moved there and back
        return np.moveaxis(rotate(-self.angles[body], np.moveaxis(v, 0, -1)), -1, 0)

    def local_point(self, body, p):
        return self._to_body(body, np.asarray(p, dtype=float) - self.origins[body])

    def local_direction(self, body, v):
        v = np.asarray(v, dtype=float)
        return self._to_body(body, v / np.hypot(v[0], v[1]))


def kernel_params(P):
    """The kernels' layout of stacked parameters ``P`` (K, a, b): (b, a, K, 1), as views, so
    that a change to ``P`` (the model setting the sketch constants) reaches the kernels.

    >>> kernel_params({"s": np.zeros((4, 2, 2))})["s"].shape
    (2, 2, 4, 1)
    """
    return {key: v.T[..., None] for key, v in P.items()}


# ---- shared pieces: two body points, and a point against a line ------------------------

# d(P_b - P_a)/d(x, y) of slots a, b: -I and +I; d/dphi of slot k is sign_k perp(S_k), i.e.
# the swapped components of S_k times _PAIR_PHI[component, slot]
_PAIR_R = np.array([[[-1.0], [0.0]], [[0.0], [-1.0]]])[..., None]  # (2, 2, 1, 1)
_PAIR_PHI = np.array([[1.0, -1.0], [-1.0, 1.0]])[..., None, None]


def point_pair(F, s):
    """d = P_b - P_a (2, K, ...) between body-fixed points s (2, 2, K, 1) of slots 0 and 1,
    and the world vectors S (2, 2, K, ...) of both (S[:, 0] = S_a, S[:, 1] = S_b)."""
    Pw, S = F.points(s)
    return Pw[:, 1] - Pw[:, 0], S


def pair_rates(F, S):
    """(d_dot, d_ddot without the qdd terms) for d = P_b - P_a, S as :func:`point_pair` gives."""
    V = F.rd + perp_cf(S) * F.phid
    Sw2 = S * F.phid**2
    return V[:, 1] - V[:, 0], Sw2[:, 0] - Sw2[:, 1]


def pair_blocks(S, out, constants=True):
    """Write the Jacobian (2, 6, K, ...) of d = P_b - P_a w.r.t. (x, y, phi) of slots a, b
    (with ``constants=False`` only the angle columns: the x and y columns are -I and I)."""
    if constants:
        out[:, 0:2] = _PAIR_R
        np.negative(_PAIR_R, out=out[:, 3:5])
    np.multiply(S[::-1], _PAIR_PHI, out=out[:, 2::3])
    return out


def pair_row(out, g, g_pa, g_pb):
    """Write the gradient (6, K, ...) of a scalar function of d = P_b - P_a (and the angles):
    -g and g on the positions of slots a and b, g_pa and g_pb on their angles."""
    np.negative(g, out=out[0:2])
    out[3:5] = g
    out[2] = g_pa
    out[5] = g_pb
    return out


class Line:
    """A point (slot 1) against a line fixed in slot 0: through s[:, 0] with direction u'.

    ``h = n.d`` is the signed normal distance (n = perp(u), left of the direction positive),
    ``t = u.d`` the travel along the line from s[:, 0].
    """

    def __init__(self, F, s, u_local, rates=False):
        self.d, S = point_pair(F, s)
        self.Sa, self.Sb = S[:, 0], S[:, 1]
        self.u = F.vec(0, u_local)
        self.n = perp_cf(self.u)
        if rates:
            self.dd, self.ddq = pair_rates(F, S)
            self.wa = F.phid[0]

    @property
    def h(self):
        return dot_cf(self.n, self.d)

    @property
    def t(self):
        return dot_cf(self.u, self.d)

    def h_grad(self, out):
        # dn/dphi_a = -u, and n.perp(S) = u.S
        return pair_row(out, self.n, -dot_cf(self.u, self.d + self.Sa), dot_cf(self.u, self.Sb))

    def t_grad(self, out):
        # du/dphi_a = n, n.d = u x d, and u.perp(S) = -(u x S)
        return pair_row(out, self.u, cross_cf(self.u, self.d + self.Sa), cross_cf(self.Sb, self.u))

    def h_gamma(self):
        w = self.wa
        return w**2 * dot_cf(self.n, self.d) + 2 * w * dot_cf(self.u, self.dd) - dot_cf(self.n, self.ddq)

    def t_gamma(self):
        w = self.wa
        return w**2 * dot_cf(self.u, self.d) - 2 * w * dot_cf(self.n, self.dd) - dot_cf(self.u, self.ddq)


def wrap(a):
    """Wrap angles into [-pi, pi)."""
    return (a + np.pi) % (2 * np.pi) - np.pi


def line_params(joint, sketch):
    """The parameters of a line fixed in body a (through ``origin``, along ``direction``) and
    the point ``at`` of body b: for sliders, slots and travel inputs."""
    a, b = joint.bodies
    d = joint.data
    return {
        "s": np.stack((sketch.local_point(a, d["origin"]), sketch.local_point(b, d["at"]))),
        "u": sketch.local_direction(a, d["direction"]),
    }


def line_of(P, F, rates=False):
    """The :class:`Line` of a slider's parameters at poses F."""
    return Line(F, P["s"], P["u"], rates=rates)


# the locked relative angle phi_b - phi_a: its constant gradient row (6, 1, 1)
LOCK = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 1.0])[:, None, None]


__all__ = ["Joint", "SketchFrames", "Line", "kernel_params", "point_pair", "pair_rates", "pair_blocks",
           "pair_row", "wrap", "line_params", "line_of", "LOCK"]
