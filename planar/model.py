"""The mutable builder :class:`Mechanism` and the immutable compiled :class:`Model`.

A mechanism is sketched in world coordinates: every point and joint is placed where it is in
one assembled pose (the sketch). The sketch fixes the link lengths, is the first guess of
every solve and picks the assembly mode; lengths stated with :meth:`Mechanism.distance` make
it a rough guess that compile assembles exactly (see :mod:`planar.dimensions`).

A body's angle is the world direction of the line from its joint nearest the ground to its
next joint (joints ordered by the graph distance from the ground of the body they lead to, then
by order of addition; its named points follow its joints), unless ``angle=`` is given: so the
angles of a four-bar are the textbook's theta2, theta3 and theta4. Angles are radians.

>>> import numpy as np, planar
>>> m = planar.Mechanism()
>>> crank, coupler, rocker = m.add_body("crank"), m.add_body("coupler"), m.add_body("rocker")
>>> m.add_revolute("O2", m.ground, crank, at=(0, 0))
>>> m.add_revolute("A", crank, coupler, at=(1, 1.7320508075688772))
>>> m.add_revolute("B", coupler, rocker, at=(3.0809504341380123, 3.8929870145543637))
>>> m.add_revolute("O4", rocker, m.ground, at=(4, 0))
>>> m.drive("O2")
>>> res = m.sweep(np.radians([60.0, 90.0]))
>>> res.ok.tolist()
[True, True]
>>> np.degrees([res.angle(b)[0] for b in ("crank", "coupler", "rocker")]).round(2).tolist()
[60.0, 46.08, 103.28]
"""

import itertools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from planar.dimensions import Dimension, Dyad, Row, assemble
from planar.errors import (AssemblyError, ConnectivityError, InputError, MobilityError,
                           ModelError, RedundancyError)
from planar.joints import (AngleDriver, CarrierGear, CoordinateDriver, Gear, Prismatic,
                           RackPinion, Revolute, RollingContact, Slot)
from planar.joints.base import SketchFrames
from planar.mass import compile_mass
from planar.blocks import plan as block_plan
from planar.system import build_system

if TYPE_CHECKING:
    from planar.results import Sweep
    from planar.tracking import Tracker

GROUND = "ground"


@dataclass(frozen=True)
class Body:
    """Handle of a body in a :class:`Mechanism` (anywhere a body is asked for, its name works too)."""

    name: str

    def __str__(self):
        return self.name


def _finite(value, what, shape=None):
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"{what} must be numeric, got {value!r}") from None
    if shape is not None and a.shape != shape:
        raise ModelError(f"{what} must have shape {shape}, got {value!r}")
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{what} must be finite, got {value!r}")
    return a


def _point(value, what):
    return _finite(value, what, (2,))


def _positive(value, what):
    v = float(_finite(value, what, ()))
    if v <= 0:
        raise ModelError(f"{what} must be positive, got {value!r}")
    return v


def _pressure_angle(value, joint):
    a = float(_finite(value, f"joint {joint!r} pressure_angle", ()))
    if not 0 <= a < np.pi / 2:
        raise ModelError(f"joint {joint!r}: pressure_angle must be in [0, pi/2) radians, got {a!r}")
    return a


def _direction(value, what):
    v = _point(value, what)
    if np.hypot(*v) == 0:
        raise ModelError(f"{what} must be a non-zero vector, got {value!r}")
    return v / np.hypot(*v)


class Mechanism:
    """Mutable, named description of a planar mechanism; compiles to a :class:`Model`.

    Bodies, points and joints share one namespace; drivers have their own.
    """

    def __init__(self, name: str = "mechanism") -> None:
        self.name = name
        self._bodies: dict[str, Any] = {GROUND: 0.0}  # name -> angle as given: None (the rule), a number or a line (p, q)
        self._points: dict = {}  # name -> (body, world point)
        self._joints: list = []
        self._drivers: list = []
        self._dimensions: list = []
        self._starts: dict = {}  # driver name -> start value
        self._sides: list = []  # (name, a, b, side) of each joint or point placed by a Dyad
        self._names = {GROUND}
        self._model: Model | None = None
        self._mass: dict = {}  # body -> (mass, sketch centre of mass, inertia about it)
        self._loads: list = []  # (body, sketch point, force, torque, fixed)
        self._gravity: tuple | None = None

    def __repr__(self) -> str:
        return (f"<Mechanism {self.name!r}: {len(self._bodies) - 1} moving bodies, {len(self._joints)} joints, "
                f"{len(self._drivers)} driver(s)>")

    def sketch(self) -> "Sketch":
        """What has been drawn so far, read-only: a :class:`Sketch` (positions as drawn; the
        assembled ones are ``compile().sketch``). Its ``bodies`` hold the angles as given.

        >>> m = Mechanism("m")
        >>> crank = m.add_body("crank", angle=0.5)
        >>> m.sketch().bodies
        {'ground': 0.0, 'crank': 0.5}
        """
        return Sketch(dict(self._bodies), dict(self._points), tuple(self._joints), tuple(self._drivers),
                      tuple(self._dimensions), dict(self._starts), dict(self._mass), tuple(self._loads),
                      self._gravity)

    # ---- building ------------------------------------------------------------------------

    @property
    def ground(self) -> Body:
        """The fixed body (frame), at the origin with angle 0."""
        return Body(GROUND)

    def _new_name(self, name, what):
        if not isinstance(name, str) or not name:
            raise ModelError(f"{what} name must be a non-empty string, got {name!r}")
        if name in self._names:
            raise ModelError(f"the name {name!r} is already used: give the {what} another name")
        self._names.add(name)
        self._model = None
        return name

    def _body(self, body, what="body"):
        name = body.name if isinstance(body, Body) else body
        if name not in self._bodies:
            known = ", ".join(repr(b) for b in self._bodies)
            raise ModelError(f"unknown {what} {name!r}: the bodies are {known}; add it with add_body first")
        return name

    def _pair(self, a, b, joint):
        a, b = self._body(a), self._body(b)
        if a == b:
            raise ModelError(f"joint {joint!r} joins body {a!r} to itself: a joint needs two different bodies")
        return a, b

    def add_body(self, name: str, angle: float | tuple[str, str] | None = None, *, mass: float | None = None,
                 com: ArrayLike | None = None, inertia: float = 0.0) -> Body:
        """Add a moving body. Its angle (what results report as ``angle(body)``) is the world
        direction of its reference line: by default the line from its joint nearest the
        ground to its next joint (see :meth:`reference_line`); ``angle=(p, q)`` names another
        line, from joint or point ``p`` to ``q`` of the body; ``angle=`` a number (radians)
        gives the body's angle in the sketch instead (for a body with no line, like a gear on
        its axle alone). ``mass``, ``com`` and ``inertia``: see :meth:`set_mass` (``planar.bar``,
        ``disc`` and ``plate`` give them for simple shapes)."""
        what = f"angle of body {name!r}"
        spec: float | tuple[str, str] | None = None
        if isinstance(angle, (tuple, list)) and len(angle) == 2 and all(isinstance(p, str) for p in angle):
            if angle[0] == angle[1]:
                raise ModelError(f"the {what} is the line {angle[0]} -> {angle[1]}: name two different joints "
                                 f"or points")
            spec = (angle[0], angle[1])
        elif angle is not None:
            spec = float(_finite(angle, f"{what} (a number, or a line (p, q) of two point names)", ()))
        self._bodies[self._new_name(name, "body")] = spec
        if mass is not None:
            self.set_mass(name, mass, com, inertia)
        return Body(name)

    def set_mass(self, body: Body | str, mass: float, com: ArrayLike | None, inertia: float = 0.0) -> None:
        """Give ``body`` its ``mass``, centre of mass ``com`` (a sketch point, like ``at``) and
        moment of inertia about it, for :meth:`planar.Sweep.forces` (bodies without are massless).

        >>> import planar
        >>> m = planar.Mechanism()
        >>> link = m.add_body("link", **planar.bar(2.0, (0, 0), (1, 0)))
        >>> m.set_mass("link", 3.0, (0.5, 0), 0.25)
        """
        b = self._body(body)
        if b == GROUND:
            raise ModelError("the ground does not move: give mass to a moving body")
        mass, inertia = _finite(mass, f"mass of body {b!r}", ()), _finite(inertia, f"inertia of body {b!r}", ())
        if mass < 0 or inertia < 0:
            raise ModelError(f"body {b!r}: mass and inertia must be >= 0, got {float(mass)!r} and {float(inertia)!r}")
        if com is None:
            raise ModelError(f"body {b!r}: give com, the sketch point of its centre of mass")
        self._mass[b] = (float(mass), _point(com, f"com of body {b!r}"), float(inertia))
        self._model = None

    @property
    def gravity(self):
        """Gravitational acceleration, a world 2-vector such as (0, -9.81), or None (none)."""
        return self._gravity

    @gravity.setter
    def gravity(self, g):
        self._gravity = None if g is None else tuple(_point(g, "gravity").tolist())
        self._model = None

    def add_load(self, body: Body | str, force: Any = (0.0, 0.0), at: ArrayLike | None = None, torque: Any = 0.0, *,
                 fixed: str = "world") -> None:
        """An external ``force`` at sketch point ``at`` of ``body`` and a ``torque`` on it. Each is
        a constant, or a function of the sweep's input values (N, f) giving (N, 2) or (N,).
        ``fixed="world"`` keeps the force's direction; ``"body"`` turns it with the body (it is
        then given as it acts at the sketch). ``at`` may be left out for a torque alone."""
        b = self._body(body)
        if b == GROUND:
            raise ModelError("a load on the ground moves nothing: put it on a moving body")
        if fixed not in ("world", "body"):
            raise ModelError(f"load on {b!r}: fixed must be 'world' or 'body', got {fixed!r}")
        if not callable(force):
            force = _point(force, f"load force on {b!r}")
        if not callable(torque):
            torque = _finite(torque, f"load torque on {b!r}", ())
        if at is None and (callable(force) or np.any(force != 0)):
            raise ModelError(f"load on {b!r}: give at, the sketch point the force acts at")
        self._loads.append((b, np.zeros(2) if at is None else _point(at, f"load on {b!r} at"), force, torque, fixed))
        self._model = None

    def add_point(self, name: str, body: Body | str, at: ArrayLike | str | Dyad) -> None:
        """Name the point of ``body`` that is at ``at`` in the sketch: (x, y), the name of a joint
        or point placed before, or a :class:`planar.Dyad`."""
        body = self._body(body)
        dyad = at if isinstance(at, Dyad) else None
        at = self._place(name, at, {body})
        self._points[self._new_name(name, "point")] = (body, at)
        self._dyad_dimensions(name, dyad)

    def _place(self, name, at, bodies):
        """``at`` as a sketch point: a point, the name of a joint or point placed before (the
        same place), or a :class:`Dyad` placed from its two joints or points, whose bodies must
        be among ``bodies`` (a distance joins two points of one body)."""
        if isinstance(at, str):
            return self._position(at)
        if not isinstance(at, Dyad):
            return _point(at, f"{name!r} at")
        for ref in (at.a, at.b):
            if not self._bodies_of(ref) & bodies:
                raise ModelError(f"{name!r} is placed from {ref!r}, which is on none of its bodies {sorted(bodies)}: "
                                 f"a dyad's distances join points of one body")
        return at.place(self._position(at.a), self._position(at.b), f"the dyad placing {name!r}")

    def _dyad_dimensions(self, name, dyad):
        if dyad is not None:
            self.distance(dyad.a, name, dyad.length_a)
            self.distance(dyad.b, name, dyad.length_b)
            self._sides.append((name, dyad.a, dyad.b, dyad.side))

    def _position(self, name):
        if name not in self._points:
            raise ModelError(f"unknown joint or point {name!r}: the named positions are {sorted(self._points)}")
        return self._points[name][1]

    def _bodies_of(self, name):
        """The bodies a joint or point is on: a revolute's two, the body of any other's anchor."""
        self._position(name)
        for j in self._joints:
            if j.name == name and isinstance(j, Revolute):
                return set(j.bodies)
        return {self._points[name][0]}

    def distance(self, a: str, b: str, length: float) -> None:
        """State the length between joints or points ``a`` and ``b`` of one body. The sketch
        positions become rough guesses: compile assembles them exactly (see
        :mod:`planar.dimensions`), and :attr:`Model.sketch` holds the assembled positions.

        >>> m = Mechanism()
        >>> crank = m.add_body("crank")
        >>> m.add_revolute("O", m.ground, crank, at=(0, 0))
        >>> m.add_point("P", crank, at=(0.98, 0.02))
        >>> m.distance("O", "P", 1.0)
        >>> m.drive("O", start=0.0)
        >>> m.compile().sketch.position("P").round(12).tolist()
        [1.0, 0.0]
        """
        length = _positive(length, f"distance {a}-{b}")
        shared = self._bodies_of(a) & self._bodies_of(b)
        if not shared:
            raise ModelError(f"distance {a}-{b}: {a!r} is on {sorted(self._bodies_of(a))} and {b!r} on "
                             f"{sorted(self._bodies_of(b))}: a distance joins two joints or points of one body")
        if a == b:
            raise ModelError(f"distance {a}-{b}: name two different joints or points")
        for d in self._dimensions:
            if {d.a, d.b} == {a, b}:
                raise ModelError(f"{d} is stated already: state each length once")
        self._dimensions.append(Dimension(a, b, length))
        self._model = None

    def _add(self, joint):
        self._joints.append(joint)
        anchor = joint.anchor()
        if anchor is not None:
            self._points[joint.name] = anchor

    def add_revolute(self, name: str, body_a: Body | str, body_b: Body | str, at: ArrayLike | str | Dyad) -> None:
        """Pin joint between two bodies at sketch point ``at``: (x, y), the name of a joint or
        point placed before (a third body on the same pin), or a :class:`planar.Dyad`. Its
        coordinate is the angle of b relative to a."""
        a, b = self._pair(body_a, body_b, name)
        dyad = at if isinstance(at, Dyad) else None
        at = self._place(name, at, {a, b})
        self._new_name(name, "joint")
        self._add(Revolute(name, (a, b), at=at))
        self._dyad_dimensions(name, dyad)

    def _line_data(self, name, at, direction, origin):
        at = _point(at, f"joint {name!r} at")
        return dict(at=at, direction=_direction(direction, f"joint {name!r} direction"),
                    origin=at if origin is None else _point(origin, f"joint {name!r} origin"))

    def add_prismatic(self, name: str, body_a: Body | str, body_b: Body | str, at: ArrayLike, direction: ArrayLike,
                      origin: ArrayLike | None = None) -> None:
        """Slider: the point ``at`` of ``body_b`` moves along the line of ``body_a`` through
        ``origin`` (default ``at``) with ``direction``; no relative rotation. Its coordinate is
        the travel along the line from ``origin``."""
        a, b = self._pair(body_a, body_b, name)
        data = self._line_data(name, at, direction, origin)
        self._check_on_line(name, data)
        self._new_name(name, "joint")
        self._add(Prismatic(name, (a, b), **data))

    def add_slot(self, name: str, body_a: Body | str, body_b: Body | str, at: ArrayLike, direction: ArrayLike,
                 origin: ArrayLike | None = None) -> None:
        """Pin in slot: as :meth:`add_prismatic` but the bodies turn freely."""
        a, b = self._pair(body_a, body_b, name)
        data = self._line_data(name, at, direction, origin)
        self._check_on_line(name, data)
        self._new_name(name, "joint")
        self._add(Slot(name, (a, b), **data))

    @staticmethod
    def _check_on_line(name, data):
        d = data["at"] - data["origin"]
        off = abs(d[0] * data["direction"][1] - d[1] * data["direction"][0])
        if off > 1e-9 * max(1.0, np.hypot(*d)):
            raise ModelError(f"joint {name!r}: the origin {data['origin'].tolist()} is not on the line "
                             f"through {data['at'].tolist()} along {data['direction'].tolist()}: "
                             f"give an origin on that line")

    def add_gear(self, name: str, gear_a: Body | str, gear_b: Body | str, radius_a: float, radius_b: float, *,
                 internal: bool = False, carrier: Body | str | None = None, centre_a: ArrayLike | None = None,
                 centre_b: ArrayLike | None = None, hold_distance: bool = False,
                 pressure_angle: float = np.radians(20)) -> None:
        """Two pitch circles in mesh (external, or ``internal`` with one inside the other).

        With ``carrier`` (a body, or the ground) both centres are fixed on it: the row is linear
        in the angles. Without, the centres (on the gears, sketch points ``centre_a``,
        ``centre_b``) may sit on different moving bodies; their distance must then be held by
        other joints, or by the gear itself with ``hold_distance=True`` (a wheel rolling on or
        inside a circle with no arm). The gears mesh as drawn in the sketch. ``pressure_angle``
        (radians) sets the direction of the tooth force (:meth:`planar.Sweep.forces`).
        """
        a, b = self._pair(gear_a, gear_b, name)
        data = dict(radius_a=_positive(radius_a, f"gear {name!r} radius_a"),
                    radius_b=_positive(radius_b, f"gear {name!r} radius_b"),
                    sign=-1.0 if internal else 1.0, pressure_angle=_pressure_angle(pressure_angle, name))
        if internal and data["radius_a"] == data["radius_b"]:
            raise ModelError(f"gear {name!r}: an internal mesh needs different radii")
        for key, value in (("centre_a", centre_a), ("centre_b", centre_b)):
            data[key] = None if value is None else _point(value, f"gear {name!r} {key}")
        cls: type
        bodies: tuple
        if carrier is not None:
            c = self._body(carrier, "carrier")
            if c in (a, b):
                raise ModelError(f"gear {name!r}: the carrier {c!r} must differ from both gears")
            for key, g in (("centre_a", a), ("centre_b", b)):
                if data[key] is None:
                    data[key] = self._pin_between(g, c, name)
            cls, bodies = CarrierGear, (a, b, c)
        else:
            for key, g in (("centre_a", a), ("centre_b", b)):
                if data[key] is None:
                    raise ModelError(f"gear {name!r}: give {key} (the sketch centre of {g!r}) or a carrier")
            cls, bodies = (RollingContact if hold_distance else Gear), (a, b)
        need = data["radius_a"] + data["sign"] * data["radius_b"]
        dist = np.hypot(*(data["centre_b"] - data["centre_a"]))
        if not math.isclose(dist, abs(need), rel_tol=1e-6, abs_tol=1e-9):
            raise ModelError(f"gear {name!r}: centres are {dist:.12g} apart in the sketch but the radii "
                             f"need {abs(need):.12g}: move a centre or change a radius")
        self._new_name(name, "joint")
        self._add(cls(name, bodies, **data))

    def _pin_between(self, gear, carrier, name):
        """The gear's centre: its pin on the carrier, or a pin of the gear at the same point as
        a pin of the carrier (both pivoting on a third body there)."""
        pins = [j for j in self._joints if isinstance(j, Revolute)]
        for j in pins:
            if set(j.bodies) == {gear, carrier}:
                return j.data["at"]
        for j in pins:
            for k in pins:
                if gear in j.bodies and carrier in k.bodies and np.allclose(j.data["at"], k.data["at"]):
                    return j.data["at"]
        raise ModelError(f"gear {name!r}: no revolute puts the centre of {gear!r} on the carrier {carrier!r}; "
                         f"add it first or give the centre")

    def add_rack_pinion(self, name: str, pinion: Body | str, rack: Body | str, radius: float, *, centre: ArrayLike,
                        through: ArrayLike, direction: ArrayLike, side: str = "left",
                        pressure_angle: float = np.radians(20)) -> None:
        """Pinion (pitch ``radius``, centre ``centre`` on the pinion) rolling without slip on the
        rack's pitch line through ``through`` along ``direction`` (fixed in ``rack``, any body).
        ``side`` says where the pinion centre is: left or right of the directed line;
        ``pressure_angle`` (radians) that of the teeth."""
        p, r = self._pair(pinion, rack, name)
        if side not in ("left", "right"):
            raise ModelError(f"joint {name!r}: side must be 'left' or 'right', got {side!r}")
        data = dict(radius=_positive(radius, f"joint {name!r} radius"), centre=_point(centre, f"joint {name!r} centre"),
                    through=_point(through, f"joint {name!r} through"),
                    direction=_direction(direction, f"joint {name!r} direction"),
                    side=1.0 if side == "left" else -1.0, pressure_angle=_pressure_angle(pressure_angle, name))
        d = data["centre"] - data["through"]
        h = data["direction"][0] * d[1] - data["direction"][1] * d[0]
        if not math.isclose(h, data["side"] * data["radius"], rel_tol=1e-6, abs_tol=1e-9):
            raise ModelError(f"joint {name!r}: the centre is {h:.12g} left of the line in the sketch but "
                             f"radius {data['radius']:.12g} on the {side} needs {data['side'] * data['radius']:.12g}: "
                             f"move the centre or the line, or change the side")
        self._new_name(name, "joint")
        self._add(RackPinion(name, (r, p), **data))

    def add_rolling(self, name: str, wheel: Body | str, body: Body | str, radius: float, *, centre: ArrayLike,
                    through: ArrayLike, direction: ArrayLike, side: str = "left") -> None:
        """A wheel rolling without slip on a straight line fixed in ``body`` (the ground or a
        moving body): the same contact as :meth:`add_rack_pinion`."""
        self.add_rack_pinion(name, wheel, body, radius, centre=centre, through=through,
                             direction=direction, side=side, pressure_angle=0.0)

    def drive(self, joint: str | None = None, *, body: Body | str | None = None, point: str | None = None,
              axis: str | None = None, name: str | None = None, start: float | None = None) -> None:
        """Make one input. Exactly one of: ``joint`` (a revolute's relative angle, a slider's or
        slot's travel), ``body`` (its absolute angle), ``point`` with ``axis`` "x" or "y" (a
        world coordinate of a named point). Inputs are in the order they are added.

        ``start`` is the input's value in the sketch (radians or length): with stated
        distances, compile assembles the sketch there; without, it must be the value drawn,
        and picks the turn an angle starts on (420 degrees rather than 60)."""
        given = [k for k, v in (("joint", joint), ("body", body), ("point", point)) if v is not None]
        if len(given) != 1:
            raise ModelError("drive needs exactly one of joint=, body= or point=")
        if joint is not None:
            target = next((j for j in self._joints if j.name == joint), None)
            if target is None:
                raise ModelError(f"unknown joint {joint!r}: the joints are {[j.name for j in self._joints]}")
            drv = target.coordinate()
            if drv is None:
                raise ModelError(f"joint {joint!r} ({type(target).__name__}) has no coordinate to drive: "
                                 f"drive one of the bodies it joins instead")
        elif body is not None:
            drv = AngleDriver(str(body), (GROUND, self._body(body)))
        else:
            if point not in self._points:
                raise ModelError(f"unknown point {point!r}: the points are {sorted(self._points)}")
            if axis not in ("x", "y"):
                raise ModelError(f"driving point {point!r} needs axis='x' or axis='y', got {axis!r}")
            b, at = self._points[point]
            drv = CoordinateDriver(f"{point}.{axis}", (b,), at=at, axis=(1.0, 0.0) if axis == "x" else (0.0, 1.0))
        drv.name = name or drv.name
        if any(d.name == drv.name for d in self._drivers):
            raise ModelError(f"a driver named {drv.name!r} exists already: pass name= to tell them apart")
        if start is not None:
            self._starts[drv.name] = float(_finite(start, f"start of driver {drv.name!r}", ()))
        self._drivers.append(drv)
        self._model = None

    def reference_line(self, body: Body | str) -> tuple[str, str] | None:
        """The (p, q) names of the line whose direction is ``body``'s angle by default, or None
        for a body with fewer than two named positions (its angle is then the sketch's x axis
        turned with it): p is its joint nearest the ground (graph distance of the body the joint
        leads to, ties by order of addition), q the next of its joints, then points, at another
        place. Named positions on a body: its revolutes, the anchors of its other joints on it,
        its points.

        >>> from planar.mechanisms import four_bar
        >>> m = four_bar()
        >>> m.reference_line("crank"), m.reference_line("coupler"), m.reference_line("rocker")
        (('O2', 'A'), ('A', 'B'), ('O4', 'B'))
        """
        body = self._body(body)
        if body == GROUND:
            return None
        return _rule_line(self, body, lambda p, q: not np.array_equal(self._points[p][1], self._points[q][1]))

    # ---- compiling -----------------------------------------------------------------------

    def compile(self) -> "Model":
        """Check and freeze the mechanism into a :class:`Model` (cached until the next change)."""
        if self._model is None:
            self._model = _compile(self.name, _resolve(self))
        return self._model

    def sweep(self, values: ArrayLike, velocity: ArrayLike = 1.0, acceleration: ArrayLike = 0.0,
              **options: Any) -> "Sweep":
        """Solve positions, velocities and accelerations over input ``values``; see
        :meth:`Model.sweep`."""
        return self.compile().sweep(values, velocity, acceleration, **options)

    def track(self, **options: Any) -> "Tracker":
        """A tracker for moving the input by hand; see :meth:`Model.track`."""
        return self.compile().track(**options)

    def circuit(self, samples: int = 361, velocity: float = 1.0, acceleration: float = 0.0,
                **options: Any) -> "Sweep":
        """The whole circuit through the sketch, the input reversing at each limit; see
        :meth:`Model.circuit`."""
        return self.compile().circuit(samples, velocity, acceleration, **options)


@dataclass(frozen=True)
class Sketch:
    """A mechanism as drawn or as assembled: ``bodies`` name -> angle (the ground first; as
    given when drawn, in radians when assembled), ``points`` name -> (body, world point)
    (joints' points included), ``joints`` and ``drivers`` in the order they were added, the
    stated ``dimensions`` and the drivers' ``starts`` (name -> value); ``mass`` body -> (mass,
    sketch centre of mass, inertia), ``loads`` (body, sketch point, force, torque, fixed) and
    ``gravity`` as given to the builder (centres and load points carried with their bodies when
    assembled)."""

    bodies: dict
    points: dict
    joints: tuple
    drivers: tuple
    dimensions: tuple = ()
    starts: dict | None = None
    mass: dict | None = None
    loads: tuple = ()
    gravity: tuple | None = None

    def position(self, name):
        """World position (2,) of a joint or point."""
        if name not in self.points:
            raise ModelError(f"unknown joint or point {name!r}: known are {sorted(self.points)}")
        return self.points[name][1]


# ---- the compiled model ---------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Model:
    """Immutable compiled mechanism: index arrays, joint tables and the assembled sketch.

    Attributes give the mobility report: ``n`` coordinates, ``m`` rows, ``rank`` of the joint
    Jacobian at the sketch, ``dof = n - rank``, ``grubler = n - (rows of the joints)`` and the
    names of ``redundant_joints`` (rows kept out of Newton but checked after every solve).
    ``sketch`` is the :class:`Sketch` as assembled: every stated distance holds there, and
    ``sketch.bodies`` are the bodies' angles in radians. ``mass``, ``com``, ``inertia``,
    ``gravity`` and ``loads`` are what :meth:`planar.Sweep.forces` balances (read-only).
    """

    name: str
    body_names: tuple
    body_angles0: np.ndarray  # sketch angle per body
    points: dict  # name -> (body id, local vector)
    joints: tuple
    drivers: tuple
    system: object
    row_adr: np.ndarray
    q0: np.ndarray  # assembled sketch (n,)
    u0: np.ndarray  # input values at the sketch (f,)
    L: float  # characteristic length
    row_scale: np.ndarray  # (m,)
    col_scale: np.ndarray  # (n,)
    active_rows: np.ndarray  # rows of the Newton system (independent joint rows, then drivers)
    driver_rows_active: np.ndarray  # positions of the driver rows inside active_rows
    redundant_rows: np.ndarray
    input_lengths: np.ndarray  # (f,) True where the input is a length
    rank: int
    grubler: int
    redundant_joints: tuple
    coordinates: dict  # joint name -> (system of its coordinate rows, row)
    sketch: Sketch
    mass: np.ndarray | None = None  # (n_bodies,) masses (0: massless)
    com: np.ndarray | None = None  # (n_bodies, 2) centres of mass in the body frames
    inertia: np.ndarray | None = None  # (n_bodies,) moments of inertia about the centres of mass
    gravity: np.ndarray | None = None  # (2,) world gravitational acceleration
    loads: tuple = ()  # planar.mass.Load
    # poses solved on the branch, per branch option (planar.tracking): a private mutable cache
    # made with the model; the model's fields stay as built
    _poses: dict = field(default_factory=dict, init=False, repr=False)

    def __repr__(self) -> str:
        return (f"<Model {self.name!r}: {len(self.body_names) - 1} moving bodies, {len(self.joints)} joints, "
                f"dof {self.dof}, inputs {list(self.input_names)}>")

    @property
    def n(self):
        return self.system.n

    @property
    def m(self):
        return self.system.m

    @property
    def dof(self) -> int:
        return self.n - self.rank

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(d.name for d in self.drivers)

    def body_id(self, body: Body | str) -> int:
        name = body.name if isinstance(body, Body) else body
        try:
            return self.body_names.index(name)
        except ValueError:
            raise ModelError(f"unknown body {name!r}: the bodies are {list(self.body_names)}") from None

    def point(self, name):
        try:
            return self.points[name]
        except (KeyError, TypeError):
            raise ModelError(f"unknown point or joint {name!r}: known are {sorted(self.points)}") from None

    def joint(self, name):
        for j in self.joints:
            if j.name == name:
                return j
        raise ModelError(f"unknown joint {name!r}: the joints are {[j.name for j in self.joints]}")

    def sweep(self, values: ArrayLike, velocity: ArrayLike = 1.0, acceleration: ArrayLike = 0.0,
              **options: Any) -> "Sweep":
        """Positions, velocities and accelerations for each row of input ``values``.

        ``values`` is (N,) for one input or (N, f); ``velocity`` and ``acceleration`` are the
        input rates (scalars, (f,), (N,) or (N, f)); the default unit velocity makes the rates
        kinematic coefficients. The solve follows the branch drawn in the sketch through the
        values in order; a one-input model starts it from the nearest pose it has solved on
        the branch before, with the same results as from the sketch (:mod:`planar.tracking`).
        Returns a frozen :class:`planar.results.Sweep`.
        Options: ``tol`` (scaled residual, 1e-12), ``max_step`` (largest input step between
        continuation anchors: radians, or lengths / L; 0.05), ``outputs`` (names of the
        bodies, points or joints wanted: only the blocks they need are solved), ``branch``
        ("smooth" or "other" at a bifurcation), ``rates`` (False: positions only, velocities
        and accelerations NaN: the velocity and acceleration solves are skipped), ``engine``
        ("numpy", or "numba": the per-value work in a loop compiled for the mechanism's
        structure, 4-6x faster at large N; needs the ``fast`` extra; the first sweep of a
        structure compiles for 10-65 s, then it is cached on disk; see :mod:`planar.compiled`).
        """
        from planar import arguments, tracking
        from planar.sweep import run_sweep

        if not self.drivers:
            raise MobilityError(f"mechanism {self.name!r} has no driver: add {self.dof} with drive()")
        options = arguments.sweep_options(options, run_sweep)
        U = self._inputs(values, "values")
        arguments.values(self, U, options["max_step"])
        N = U.shape[0]
        Ud, Udd = self._inputs(velocity, "velocity", N), self._inputs(acceleration, "acceleration", N)
        arguments.rates(self, Ud, Udd)
        return tracking.sweep(self, U, Ud, Udd, **options)

    def track(self, **options: Any) -> "Tracker":
        """A :class:`planar.tracking.Tracker` for moving the input by hand: ``tracker.move(value)``
        returns the pose at ``value`` as a one-value :class:`planar.results.Sweep`, going on from
        the last pose; ``tracker.pose`` is the last. ``options`` are the sweep's.

        >>> from planar.mechanisms import four_bar
        >>> tracker = four_bar().track(branch="smooth")
        >>> [bool(tracker.move(u).ok[0]) for u in (0.5, 0.6, 0.7)], bool(tracker.pose.ok[0])
        ([True, True, True], True)
        """
        from planar.tracking import Tracker

        if not self.drivers:
            raise MobilityError(f"mechanism {self.name!r} has no driver: add {self.dof} with drive()")
        return Tracker(self, **options)

    def circuit(self, samples: int = 361, velocity: float = 1.0, acceleration: float = 0.0, tol: float = 1e-12,
                max_step: float = 0.05) -> "Sweep":
        """The whole circuit through the assembled sketch of a one-input model, in one sweep.

        The input starts at the sketch and rises; where it cannot go further (a limit
        position) it turns back, and the mechanism goes on in the other assembly mode, until
        it is back at the sketch's pose: for an input that turns fully, one turn (or the
        whole turns it takes to come back); for a triple rocker, up to one limit, down to the
        other and back up. ``samples`` values in all, evenly spaced along the circuit (so the
        coupler curve is as fine at a limit as elsewhere); both ends and the limits are among
        them (status LIMIT: positions valid, rates NaN). ``velocity`` and ``acceleration`` (scalars) are the
        input's rate and acceleration along its motion: their sign follows the input's
        direction on each stretch. ``events`` lists the limits (kind "limit", with the index
        of their value) and any bifurcation met (the circuit keeps to the smooth branch).
        Returns a frozen :class:`planar.results.Sweep`; see :mod:`planar.circuit`.

        >>> import numpy as np
        >>> from planar.mechanisms import four_bar
        >>> res = four_bar(4, 3, 3, 3).circuit(samples=101)   # a triple rocker: +-117.28 deg
        >>> np.degrees([e.input for e in res.events]).round(6).tolist()
        [117.279613, -117.279613]
        """
        from planar import arguments
        from planar.circuit import circuit

        arguments.size(self, samples, "the circuit")
        return circuit(self, samples, velocity, acceleration, tol=arguments.tolerance(tol),
                       max_step=arguments.max_step(max_step))

    def _inputs(self, values, what, N=None):
        """``values`` as a new C-contiguous (N, f) array (the sweep keeps it: a copy, so the
        caller's array can change later; one memory layout, so the compiled loop is compiled
        for one), or, for a rate given once for every value (a number, or one per input), that
        one row broadcast to N rows: read-only and no N-sized copy (the compiled loop reads
        the row itself)."""
        f = len(self.drivers)
        try:
            a = np.array(values, dtype=float, order="C")
        except (TypeError, ValueError):
            raise InputError(f"sweep {what} must be numbers, got {type(values).__name__}") from None
        if a.ndim == 0:
            if N is None:
                raise InputError(f"sweep {what} must be a sequence of input values, got a scalar")
            a = np.broadcast_to(np.full((1, f), float(a)), (N, f))
        elif a.ndim == 1 and f == 1 and (N is None or a.shape[0] == N):
            a = a[:, None]
        elif a.ndim == 1 and a.shape[0] == f and N is not None:
            a = np.broadcast_to(a[None], (N, f))
        if a.ndim != 2 or a.shape[1] != f or (N is not None and a.shape[0] != N):
            want = f"({N}, {f})" if N is not None else f"(N,) or (N, {f})"
            raise InputError(f"sweep {what} have shape {np.shape(values)} but {f} input(s) "
                             f"{list(self.input_names)} need {want}")
        if not np.all(np.isfinite(a)):
            raise InputError(f"sweep {what} must be finite; found NaN or infinity")
        return a


def _compile(name, sk, plan=True):
    """The Model of an assembled :class:`Sketch` (body angles in radians); without ``plan``,
    not yet checked drivable (a study of designs plans one of each structure)."""
    joints = list(sk.joints)
    drivers = list(sk.drivers)
    bodies = list(sk.bodies)

    origins = _origins(joints, sk.points)
    sketch = SketchFrames(origins, dict(sk.bodies))

    constraints = joints + drivers
    params = [c.params(sketch) for c in constraints]
    body_index = {b: i for i, b in enumerate(bodies)}
    inputs = [-1] * len(joints) + list(range(len(drivers)))
    system, row_adr = build_system(constraints, params, body_index, len(bodies), inputs)
    n, m = system.n, system.m
    q0 = np.concatenate([np.r_[origins[b], sk.bodies[b]] for b in bodies[1:]]) if n else np.zeros(0)

    L = _char_length(sk.points, joints)
    lengths = np.concatenate([np.array(c.length_rows, bool) for c in constraints]) if m else np.zeros(0, bool)
    row_scale = np.where(lengths, 1.0 / L, 1.0)
    col_scale = np.tile([L, L, 1.0], len(bodies) - 1)
    joint_rows = np.arange(row_adr[len(joints)] if drivers else m)
    driver_rows = np.arange(joint_rows.size, m)
    sketch_rows = np.array([row_adr[i] + r for i, c in enumerate(joints) for r in c.sketch_rows], int)
    geometric = np.setdiff1d(joint_rows, sketch_rows)

    # independent rows first (the rank does not depend on the constants), then assemble the
    # sketch on the independent geometric rows and take the rolling constants there
    rank, independent = _joint_rank(system, q0, joint_rows, geometric, row_scale, col_scale)
    redundant = np.setdiff1d(joint_rows, independent)
    names = lambda rows: sorted({_owner(int(i), row_adr, constraints).name for i in rows})  # noqa: E731
    q0 = _assemble(system, q0, np.intersect1d(geometric, independent), row_scale, col_scale, joints, row_adr)
    Phi, _ = system.evaluate(q0[None], np.zeros((1, len(drivers))), jacobian=False)
    for g in system.groups:
        for k, i in enumerate(g.members):
            for r in constraints[i].sketch_rows:
                g.P["c"][k, r] = Phi[0, row_adr[i] + r]
    u0 = Phi[0, driver_rows].copy()
    Phi, _ = system.evaluate(q0[None], u0[None], jacobian=False)
    r = np.abs(Phi[0, redundant] * row_scale[redundant])
    if redundant.size and r.max() > 1e-9:
        worst = _owner(int(redundant[np.argmax(r)]), row_adr, constraints)
        raise RedundancyError(f"{worst.describe()} contradicts the other joints (off by {r.max():.3g} x L) "
                              f"where it repeats what they already hold: make its dimensions agree with "
                              f"theirs, or remove it (redundant: {names(redundant)})")
    redundant_joints = tuple(sorted(names(redundant), key=[j.name for j in joints].index))

    dof = n - rank
    if drivers and len(drivers) != dof:
        raise MobilityError(f"mechanism {name!r} has {dof} degree(s) of freedom but {len(drivers)} "
                            f"driver(s) {[d.name for d in drivers]}: "
                            + (f"add {dof - len(drivers)} driver(s)" if len(drivers) < dof
                               else f"remove {len(drivers) - dof} driver(s), or a joint that locks the "
                                    f"mechanism (a pivot declared twice, an extra link)"))
    active = np.concatenate([independent, driver_rows])
    if drivers:
        _check_drivers(system, q0, u0, active, joint_rows.size - redundant.size, drivers, row_scale, col_scale)
    coord = [(j.name, j.coordinate()) for j in joints if j.coordinate() is not None]
    csys, _ = build_system([d for _, d in coord], [d.params(sketch) for _, d in coord], body_index,
                           len(bodies), [-1] * len(coord))
    model = Model(
        coordinates={name: (csys, k) for k, (name, _) in enumerate(coord)},
        name=name, body_names=tuple(bodies), body_angles0=np.array([sk.bodies[b] for b in bodies]),
        points={k: (body_index[b], sketch.local_point(b, p)) for k, (b, p) in sk.points.items()}, sketch=sk,
        joints=tuple(joints), drivers=tuple(drivers), system=system, row_adr=row_adr, q0=q0, u0=u0, L=L,
        row_scale=row_scale, col_scale=col_scale, active_rows=active,
        driver_rows_active=np.arange(len(independent), len(active)), redundant_rows=redundant,
        input_lengths=np.array([d.length_rows[0] for d in drivers], bool), rank=rank,
        grubler=n - joint_rows.size, redundant_joints=redundant_joints,
        **compile_mass(sk.mass or {}, sk.loads, sk.gravity, sketch, bodies))
    if drivers and plan:
        block_plan(model)  # a model the drivers cannot drive is refused here, not at sweep time
    return model


def _origins(joints, points):
    """Body frames' origins: each body's first joint or point (its angle is as sketched)."""
    origins = {GROUND: np.zeros(2)}
    for j in joints:
        for b, p in j.touch_points():
            origins.setdefault(b, p)
    for b, p in points.values():
        origins.setdefault(b, p)
    return origins


def _ground_distance(bodies, joints):
    """Graph distance of each body from the ground (bodies linked by a joint are neighbours)."""
    import networkx as nx  # here, not at import: ``import planar`` stays light

    G = nx.Graph()
    G.add_nodes_from(bodies)
    G.add_edges_from((a, b) for j in joints for a in j.bodies for b in j.bodies if a != b)
    return nx.single_source_shortest_path_length(G, GROUND)


def _rule_line(mech, body, apart, dist=None):
    """The default reference line (p, q) of ``body`` (see :meth:`Mechanism.reference_line`);
    ``apart(p, q)`` says whether two names are at different places."""
    dist = dist or _ground_distance(list(mech._bodies), mech._joints)
    ranked = []
    for k, j in enumerate(mech._joints):
        on = set(j.bodies) if isinstance(j, Revolute) else {mech._points[j.name][0]} if j.name in mech._points else set()
        if body in on:
            others = [dist.get(b, np.inf) for b in j.bodies if b != body]
            ranked.append((0, min(others, default=np.inf), k, j.name))
    ranked += [(1, 0, k, n) for k, (n, (b, _)) in enumerate(mech._points.items())
               if b == body and n not in {j.name for j in mech._joints}]
    names = [r[3] for r in sorted(ranked)]
    for q in names[1:]:
        if apart(names[0], q):
            return names[0], q
    return None


def _resolve(mech):
    """The assembled :class:`Sketch`: positions holding every stated distance (when there are
    any) and every body's angle in radians, each angle driver's start on its turn."""
    bodies, joints, drivers, points = list(mech._bodies), list(mech._joints), list(mech._drivers), mech._points
    _check_connected(bodies, joints)
    L = _char_length(points, joints)
    X0, site, bases = _sites(points, joints, L)
    lines = _body_lines(mech, site, X0)
    rows = _driver_rows(mech, lines, site, X0, L)
    X = X0
    if mech._dimensions:
        dims = [Row("length", ((site[d.a], site[d.b]),), d.length, str(d)) for d in mech._dimensions]
        X = assemble(X0, bases, dims + rows, _mode_triangles(mech, site), L)
        # the named positions that moved, and the joint and driver data that follow them
        moved = lambda p: X[site[_key(p)]] if not np.array_equal(X[site[_key(p)]], p) else p  # noqa: E731
        points = {n: (b, moved(p)) for n, (b, p) in points.items()}
        follow = lambda j: type(j)(j.name, j.bodies, **{**j.data, "at": moved(j.data["at"])}) if "at" in j.data else j  # noqa: E731
        joints, drivers = [follow(j) for j in joints], [follow(d) for d in drivers]

    angles = {}
    for b, (ij, offset) in lines.items():
        spec = mech._bodies[b]
        if isinstance(spec, float) and (ij is None or all(np.array_equal(X[i], X0[i]) for i in ij)):
            angles[b] = spec  # the angle given, bit for bit
        else:
            angles[b] = offset + (_direction_of(X, *ij) if ij is not None else 0.0)
    for d in drivers:  # an angle input starts on the turn of its start value
        start = mech._starts.get(d.name)
        if start is not None and isinstance(d, AngleDriver):
            a, b = d.bodies
            if b != GROUND:
                angles[b] = start + angles[a] if a == GROUND else angles[b] + 2 * np.pi * round(
                    (start - angles[b] + angles[a]) / (2 * np.pi))
            else:
                angles[a] -= 2 * np.pi * round((start + angles[a]) / (2 * np.pi))
    mass, loads = dict(mech._mass), tuple(mech._loads)
    if mech._dimensions:  # centres of mass and load points move with their bodies' assembly
        o0, o1 = _origins(mech._joints, mech._points), _origins(joints, points)

        def carry(b, p):
            ij = lines[b][0]
            turn = _direction_of(X, *ij) - _direction_of(X0, *ij) if ij is not None else 0.0
            c, s = np.cos(turn), np.sin(turn)
            return o1[b] + np.array([[c, -s], [s, c]]) @ (p - o0[b])
        mass = {b: (mb, carry(b, com), ib) for b, (mb, com, ib) in mass.items()}
        loads = tuple((b, carry(b, at), f, t, fixed) for b, at, f, t, fixed in loads)
    return Sketch(angles, points, tuple(joints), tuple(drivers), tuple(mech._dimensions), dict(mech._starts),
                  mass, loads, mech._gravity)


_PLACES = ("at", "origin", "centre", "centre_a", "centre_b", "through")  # joint data that are world points


def _key(p):
    return (float(p[0]), float(p[1]))


def _sites(points, joints, L):
    """The distinct places of the sketch (X0 (S, 2)), ``site``: name or place (x, y) -> index,
    and the basis of each site's motion: free (I), along a slider's line on the ground (u) or
    held (none): the data of sliders on moving bodies, gears and rolling contacts stay as drawn,
    the first pivot on the ground too (the sketch's origin), and the next pivot apart stays on
    the line drawn from it (the frame's direction)."""
    X0, site = [], {}

    def place(p):
        for i, x in enumerate(X0):
            if np.hypot(*(x - p)) <= 1e-12 * L:
                return i
        X0.append(np.asarray(p, float))
        return len(X0) - 1

    for n, (_, p) in points.items():
        site[n] = site[_key(p)] = place(p)
    bases = {}
    for j in joints:
        for key in _PLACES:
            v = j.data.get(key)
            if v is None or isinstance(j, Revolute):
                continue
            i = site[_key(v)] = place(v)
            B = bases.get(i, np.eye(2))
            u = j.data["direction"][:, None] if key == "at" and isinstance(j, Slot) and j.bodies[0] == GROUND else None
            along = u is not None and (B.shape[1] == 2 or (B.shape[1] == 1 and abs(B[:, 0] @ u[:, 0]) > 1 - 1e-12))
            bases[i] = u if along else np.zeros((2, 0))
    pivots = list(dict.fromkeys(site[j.name] for j in joints if GROUND in j.bodies and isinstance(j, Revolute)))
    for k, i in enumerate(pivots[:2]):
        if k == 0 or bases.get(i, np.eye(2)).shape[1] < 2:
            bases[i] = np.zeros((2, 0))
        else:
            d = X0[i] - X0[pivots[0]]
            bases[i] = (d / np.hypot(*d))[:, None]
    return np.array(X0).reshape(-1, 2), site, [bases.get(i, np.eye(2)) for i in range(len(X0))]


def _body_lines(mech, site, X0):
    """Each body's angle as (sites (i, j) of its line or None, offset): the angle is the
    offset plus the line's direction (the offset alone without a line)."""
    dist = _ground_distance(list(mech._bodies), mech._joints)
    lines = {GROUND: (None, 0.0)}
    for b, spec in list(mech._bodies.items())[1:]:
        if isinstance(spec, tuple):
            for n in spec:
                if n not in mech._points or b not in mech._bodies_of(n):
                    raise ModelError(f"the angle of body {b!r} is the line {spec[0]} -> {spec[1]}, but {n!r} is no "
                                     f"joint or point of {b!r}: name two of its joints or points")
            if site[spec[0]] == site[spec[1]]:
                raise ModelError(f"the angle of body {b!r} is the line {spec[0]} -> {spec[1]}, but both are at "
                                 f"one place: name two joints or points of {b!r} apart")
            lines[b] = ((site[spec[0]], site[spec[1]]), 0.0)
            continue
        rule = _rule_line(mech, b, lambda p, q: site[p] != site[q], dist)
        if rule is None:
            lines[b] = (None, 0.0 if spec is None else spec)
        else:
            ij = (site[rule[0]], site[rule[1]])
            lines[b] = (ij, 0.0 if spec is None else spec - _direction_of(X0, *ij))
    return lines


def _driver_rows(mech, lines, site, X0, L):
    """The drivers as rows on the sites, held at their start (or drawn) values; without
    dimensions a start must be the value drawn."""
    rows = []
    for d in mech._drivers:
        label, start = f"the start of driver {d.name!r}", mech._starts.get(d.name)
        if isinstance(d, AngleDriver):
            a, b = d.bodies
            terms = tuple((s, *lines[x][0]) for s, x in ((1, b), (-1, a)) if lines[x][0] is not None)
            row = Row("angle", terms, 0.0, label, lines[b][1] - lines[a][1])
        elif "at" in d.data and (len(d.bodies) == 1 or d.bodies[0] == GROUND):
            u = d.data["direction"] if "direction" in d.data else d.data["axis"]
            row = Row("travel", ((site[_key(d.data["at"])], d.data.get("origin", np.zeros(2)), u),), 0.0, label)
        else:
            continue  # a travel along a moving line: held by the sketch as drawn
        drawn = row.value(X0)
        rows.append(Row(row.kind, row.terms, drawn if start is None else start, label, row.offset))
        if start is not None and not mech._dimensions:
            if abs(rows[-1].residual(X0, start)) > 1e-9 * (1.0 if row.kind == "angle" else L):
                raise ModelError(f"driver {d.name!r} starts at {start:.12g} but the sketch has {drawn:.12g}: draw "
                                 f"the sketch at its start, or state the dimensions with distance() so that "
                                 f"compile assembles it there")
    return rows


def _mode_triangles(mech, site):
    """The assembly mode drawn, as triangles (sites a, b, c, what) whose turn must stay: every
    triangle of three stated lengths, and every dyad's side (the rest follows the drawing, step
    by step)."""
    stated = {frozenset((d.a, d.b)) for d in mech._dimensions}
    names = sorted({n for d in mech._dimensions for n in (d.a, d.b)})
    triangles = [(site[a], site[b], site[c], f"the triangle {a}, {b}, {c}")
                 for a, b, c in itertools.combinations(names, 3)
                 if {frozenset((a, b)), frozenset((b, c)), frozenset((a, c))} <= stated]
    return triangles + [(site[a], site[b], site[n], f"{n}, {side} of the line {a} -> {b} (its dyad),")
                        for n, a, b, side in mech._sides]


def _direction_of(X, i, j):
    d = X[j] - X[i]
    return float(np.arctan2(d[1], d[0]))


def _char_length(points, joints):
    """The extent of the sketch (or its largest radius): the scale of the scaled Jacobian,
    so it moves with the sketch, never with where the world origin happens to be."""
    P = np.array([p for _, p in points.values()] + [p for j in joints for _, p in j.touch_points()]).reshape(-1, 2)
    radii = [j.data[k] for j in joints for k in ("radius", "radius_a", "radius_b") if k in j.data]
    L = max(float(np.max(np.ptp(P, axis=0))) if len(P) else 0.0, max(radii, default=0.0))
    # an extent so small that 1/L or L**2 leave the float range is no length (all points coincide)
    return L if L > np.sqrt(np.finfo(float).tiny) else 1.0


def _check_connected(bodies, joints):
    import networkx as nx  # here, not at import: ``import planar`` stays light

    G = nx.Graph()
    G.add_nodes_from(bodies)
    for j in joints:
        for a in j.bodies:
            for b in j.bodies:
                if a != b:
                    G.add_edge(a, b)
    loose = sorted(set(bodies) - nx.node_connected_component(G, GROUND))
    if loose:
        raise ConnectivityError(f"bod{'ies' if len(loose) > 1 else 'y'} {loose} not connected to the ground: "
                                f"add a joint between {loose[0]!r} and the ground or a body connected to it")


def _owner(row, row_adr, constraints):
    return constraints[int(np.searchsorted(row_adr, row, side="right") - 1)]


def _assemble(system, q, rows, rs, cs, joints, row_adr, iterations=50):
    """Minimum-norm Gauss-Newton on ``rows`` from q: the assembled pose nearest the sketch."""
    q = q.copy()
    if rows.size == 0:
        return q
    for _ in range(iterations):
        Phi, J = system.evaluate(q[None])
        r = Phi[0, rows] * rs[rows]
        if np.max(np.abs(r)) <= 1e-14:
            return q
        Js = J[0][rows] * rs[rows, None] * cs[None, :]
        dx = np.linalg.lstsq(Js, r, rcond=None)[0]
        dx *= min(1.0, 0.3 / max(np.max(np.abs(dx)), 1e-300))
        q -= dx * cs
    Phi, _ = system.evaluate(q[None], jacobian=False)
    r = np.abs(Phi[0, rows] * rs[rows])
    if r.max() > 1e-9:
        worst = _owner(int(rows[np.argmax(r)]), row_adr, joints)
        raise AssemblyError(f"the sketch does not assemble: {worst.describe()} stays off by {r.max():.3g} x L; "
                            f"check its points and dimensions")
    return q


def _joint_rank(system, q0, rows, geometric, rs, cs):
    """Rank of the joint rows and the independent ones, at the sketch or, if the sketch is
    a singular pose, at a nearby assembled pose where the rank is higher."""
    best = None
    rng = np.random.default_rng(0)
    q = q0
    for trial in range(3):
        _, J = system.evaluate(q[None])
        Js = J[0][rows] * rs[rows, None] * cs[None, :]
        if Js.size == 0:
            return 0, rows
        import scipy.linalg  # here, not at import: ``import planar`` stays light

        _, R, piv = scipy.linalg.qr(Js.T, pivoting=True, mode="economic")
        diag = np.abs(np.diag(R))
        rank = int(np.sum(diag > 1e-9 * max(diag[0], 1e-300))) if diag.size else 0
        if best is None or rank > best[0]:
            best = (rank, _first_independent(Js, rows, rank, 1e-9 * max(diag[0], 1e-300), piv))
        if rank == min(len(rows), system.n) or trial == 2:  # every row independent: no higher rank
            break
        # move along the free motion and reassemble, to leave a possibly singular sketch
        _, s, Vt = np.linalg.svd(Js)
        null = Vt[rank:]
        q = q + (null.T @ rng.normal(size=null.shape[0])) * 0.05 * cs
        try:
            q = _assemble(system, q, np.intersect1d(best[1], geometric), rs, cs, [], np.zeros(0))
        except (AssemblyError, IndexError):
            break
    return best


def _first_independent(Js, rows, rank, tol, piv):
    """The ``rank`` independent rows met first in the order the joints were added, so the
    joints called redundant are the later ones whatever the rounding (the pivoted order ``piv``
    where rounding leaves the greedy pick short)."""
    Q = np.zeros((Js.shape[1], 0))
    keep = []
    for k, v in enumerate(Js):
        r = v - Q @ (Q.T @ v)
        r -= Q @ (Q.T @ r)  # twice is enough (Kahan)
        size = np.linalg.norm(r)
        if size > tol:
            Q = np.column_stack([Q, r / size])
            keep.append(k)
            if len(keep) == rank:
                return rows[keep]
    return np.sort(rows[piv[:rank]])


def _check_drivers(system, q0, u0, active, n_joint_rows, drivers, rs, cs):
    _, J = system.evaluate(q0[None], u0[None])
    Js = J[0][active] * rs[active, None] * cs[None, :]
    # unpivoted QR of the rows in order: |R_ii| is row i's distance from the span of the rows
    # before it, so one factorisation says which driver depends on the rows before it
    import scipy.linalg  # here, not at import: ``import planar`` stays light

    R = scipy.linalg.qr(Js.T, mode="r")[0]
    reach = np.abs(np.diagonal(R))
    for k, d in enumerate(drivers):
        i = n_joint_rows + k
        if i >= reach.size or reach[i] <= 1e-9 * max(1.0, np.abs(Js).max()):
            raise MobilityError(f"driver {d.name!r} depends on the joints or on the drivers before it at the "
                                f"sketch: either it cannot move independently (for example both gears of one "
                                f"mesh driven: drive another coordinate, or remove it), or the sketch is a dead "
                                f"centre of this driver (sketch the mechanism at another input value)")
