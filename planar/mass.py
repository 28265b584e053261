"""Mass properties of bodies and the external loads on them, as the builder takes them.

A body's mass, centre of mass (a sketch point, like ``at``) and moment of inertia about its
centre of mass (kg, m, kg m^2 in SI, or any consistent units) go to
:meth:`planar.Mechanism.add_body` or :meth:`planar.Mechanism.set_mass`; :func:`bar`, :func:`disc`
and :func:`plate` give them for simple shapes. Loads are :class:`Load` entries of the model,
compiled from :meth:`planar.Mechanism.add_load`.

>>> import planar
>>> planar.bar(2.0, (0, 0), (3, 4))
{'mass': 2.0, 'com': (1.5, 2.0), 'inertia': 4.166666666666667}
>>> planar.disc(1.0, (0, 0), 0.5)["inertia"], planar.plate(12.0, (0, 0), 1.0, 2.0)["inertia"]
(0.125, 5.0)
"""

from dataclasses import dataclass

import numpy as np

from planar.errors import ModelError
from planar.geometry import rotate
from planar.model.checks import SCALE, is_complex


def _body_mass(mass, com, inertia):
    """The ``add_body`` keywords, each checked as :meth:`planar.Mechanism.set_mass` checks them."""
    from planar.model import checks

    if not 0 <= inertia <= checks.SCALE:  # (its square of a length overflowed)
        raise ModelError(f"the inertia {inertia:g} is beyond the numbers a sketch holds (+-{checks.SCALE:g}): give the "
                         f"body's sizes in another unit")
    return {"mass": mass, "com": tuple(com.tolist()), "inertia": inertia}


def _sizes(mass, points, lengths):
    """mass, the points (each (2,)) and the lengths checked: finite, within a sketch's numbers."""
    from planar.model import checks

    m = float(checks.finite(mass, "mass", ()))
    if m < 0:
        raise ModelError(f"mass must be >= 0, got {mass!r}")
    if m > checks.SCALE:
        raise ModelError(f"mass {m:g} is beyond the numbers a sketch holds (+-{checks.SCALE:g}): give it in another unit")
    P = [checks.point(p, what) for what, p in points]
    return m, P, [checks.length(v, what) for what, v in lengths]


def bar(mass, a, b):
    """A thin uniform bar from sketch point ``a`` to ``b``: centre at the middle, m L^2 / 12."""
    m, (a, b), _ = _sizes(mass, (("bar end a", a), ("bar end b", b)), ())
    L2 = float(np.sum((b - a) ** 2))
    return _body_mass(m, 0.5 * (a + b), m * L2 / 12.0)


def disc(mass, centre, radius):
    """A uniform disc of ``radius`` centred at sketch point ``centre``: m r^2 / 2."""
    m, (c,), (r,) = _sizes(mass, (("disc centre", centre),), (("disc radius", radius),))
    return _body_mass(m, c, m * r**2 / 2.0)


def plate(mass, centre, width, height):
    """A uniform rectangular plate ``width`` x ``height`` centred at ``centre``: m (w^2 + h^2) / 12."""
    m, (c,), (w, h) = _sizes(mass, (("plate centre", centre),), (("plate width", width), ("plate height", height)))
    return _body_mass(m, c, m * (w**2 + h**2) / 12.0)


@dataclass(frozen=True, eq=False)
class Load:
    """An external load on body ``body`` (id): a force at the body-fixed point ``s`` (its frame)
    and a torque. ``force`` is a 2-vector, or a function of the sweep's input values (N, f)
    giving (N, 2); ``torque`` a number or a function giving (N,). With ``fixed == "body"`` the
    force turns with the body (``force`` is then its world value at the sketch)."""

    body: int
    s: np.ndarray
    force: object
    torque: object
    fixed: str
    angle0: float  # the body's sketch angle: a body-fixed force is turned by phi - angle0

    def at(self, inputs, phi):
        """World force (N, 2) and torque (N,) at the input values ``inputs`` (N, f) and body
        angles ``phi`` (N,)."""
        N = inputs.shape[0]
        f = _per_value(self.force, inputs, (N, 2), "force")
        if self.fixed == "body":
            f = rotate(phi - self.angle0, f)
        return f, _per_value(self.torque, inputs, (N,), "torque")


def _per_value(value, inputs, shape, what):
    if callable(value):
        try:
            got = value(inputs)
        except TypeError as e:  # (a function that does not take the input values)
            raise ModelError(f"a load's {what} function must take the input values, an (N, f) array, and give "
                             f"shape {shape}; calling it raised TypeError: {e}") from None
        try:
            if is_complex(got):  # (numpy would drop the imaginary parts, with a warning)
                raise TypeError(got)
            out = np.asarray(got, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise ModelError(f"a load's {what} function gave {type(got).__name__} {got!r:.60}; it must give real numbers, "
                             f"shape {shape}") from None
        if out.shape != shape:
            raise ModelError(f"a load's {what} function gave shape {out.shape} for {inputs.shape[0]} input "
                             f"values; it must give {shape}")
        if not np.all(np.abs(out) <= SCALE):  # (else NaN or infinite forces with a valid status)
            raise ModelError(f"a load's {what} function gave NaN, infinity or a number beyond +-{SCALE:g}; it must "
                             f"give finite numbers within it (another unit for larger ones)")
        return out
    return np.broadcast_to(np.asarray(value, dtype=float), shape)


def compile_mass(mass, loads, gravity, sketch, bodies):
    """The Model's mass fields from the builder's: ``mass`` body -> (mass, com, inertia) in
    sketch coordinates, ``loads`` [(body, at, force, torque, fixed)], ``gravity`` or None."""
    index = {b: i for i, b in enumerate(bodies)}
    m, com, inertia = np.zeros(len(bodies)), np.zeros((len(bodies), 2)), np.zeros(len(bodies))
    for b, (mb, c, ib) in mass.items():
        m[index[b]], com[index[b]], inertia[index[b]] = mb, sketch.local_point(b, c), ib
    own = lambda v: v if callable(v) else np.array(v, float)  # noqa: E731  (a copy: frozen below)
    compiled = tuple(Load(index[b], sketch.local_point(b, at), own(force), own(torque), fixed, sketch.angles[b])
                     for b, at, force, torque, fixed in loads)
    g = np.zeros(2) if gravity is None else np.array(gravity, float)
    arrays = [m, com, inertia, g] + [v for ld in compiled for v in (ld.s, ld.force, ld.torque) if isinstance(v, np.ndarray)]
    for a in arrays:
        a.flags.writeable = False
    return dict(mass=m, com=com, inertia=inertia, gravity=g, loads=compiled)


__all__ = ["bar", "disc", "plate", "Load", "compile_mass"]
