"""The mutable builder :class:`Mechanism`: bodies, points, joints, drivers, stated distances,
masses and loads, each checked as it is added; :meth:`Mechanism.compile` freezes it into a
:class:`~planar.model.frozen.Model`.

One module over 400 lines because it is one class, the builder's whole public API read in one
place; its argument checks live in :mod:`planar.model.checks`, compiling in
:mod:`planar.model.resolve` and :mod:`planar.model.compile`."""

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from planar.dimensions import Dimension, Dyad
from planar.errors import ModelError
from planar.joints import (AngleDriver, CarrierGear, CoordinateDriver, Gear, Prismatic, RackPinion, Revolute,
                           RollingContact, Slot)
import planar.model.checks as checks
from planar.model.compile import compile_sketch
from planar.model.frozen import GROUND, Body, Model, Sketch
from planar.model.resolve import bodies_of, resolve, rule_line

if TYPE_CHECKING:
    from planar.results import Sweep
    from planar.tracking import Tracker


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
                      self._gravity, tuple(self._sides))

    # ---- building ------------------------------------------------------------------------

    @property
    def name(self) -> str:
        """The mechanism's name (in files, plots and messages): a string."""
        return self._name

    @name.setter
    def name(self, name: str) -> None:
        if not isinstance(name, str):
            raise ModelError(f"a mechanism's name must be a string, got {name!r}")
        self._name = name
        self._model = None  # (a model carries its mechanism's name)

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
        if not isinstance(name, str) or name not in self._bodies:
            known = ", ".join(repr(b) for b in self._bodies)
            raise ModelError(f"unknown {what} {name!r}: the bodies are {known}; add it with add_body first")
        return name

    def _pair(self, a, b, joint):
        a, b = self._body(a), self._body(b)
        if a == b:
            raise ModelError(f"joint {joint!r} joins body {a!r} to itself: a joint needs two different bodies")
        return a, b

    def add_body(self, name: str, angle: float | tuple[str, str] | None = None, *, mass: float | None = None,
                 com: ArrayLike | None = None, inertia: float | None = None) -> Body:
        """Add a moving body. Its angle (what results report as ``angle(body)``) is the world
        direction of its reference line: by default the line from its joint nearest the
        ground to its next joint (see :meth:`reference_line`); ``angle=(p, q)`` names another
        line, from joint or point ``p`` to ``q`` of the body; ``angle=`` a number (radians)
        gives the body's angle in the sketch instead (for a body with no line, like a gear on
        its axle alone). ``mass``, ``com`` and ``inertia``: see :meth:`set_mass` (``planar.bar``,
        ``disc`` and ``plate`` give them for simple shapes)."""
        spec = self._angle_spec(name, angle)
        if mass is None and (com is not None or inertia is not None):  # (else dropped unread)
            raise ModelError(f"body {name!r}: com and inertia come with its mass: give mass too")
        # (checked before the body is added)
        given = None if mass is None else _mass(name, mass, com, 0.0 if inertia is None else inertia)
        self._bodies[self._new_name(name, "body")] = spec
        if given is not None:
            self._mass[name] = given
        return Body(name)

    def set_angle(self, body: Body | str, angle: float | tuple[str, str] | None) -> None:
        """Give ``body`` its angle as :meth:`add_body` takes it: a number (radians, the body's
        angle in the sketch), a line (p, q) of its joints or points, or None (the default line).

        >>> m = Mechanism()
        >>> wheel = m.add_body("wheel")
        >>> m.set_angle(wheel, 0.5)
        >>> m.sketch().bodies["wheel"]
        0.5
        """
        b = self._body(body)
        if b == GROUND:
            raise ModelError("the ground's angle is 0: give an angle to a moving body")
        self._bodies[b] = self._angle_spec(b, angle)
        self._model = None

    @staticmethod
    def _angle_spec(name, angle):
        what = f"angle of body {name!r}"
        spec: float | tuple[str, str] | None = None
        if isinstance(angle, (tuple, list)) and len(angle) == 2 and all(isinstance(p, str) for p in angle):
            if angle[0] == angle[1]:
                raise ModelError(f"the {what} is the line {angle[0]} -> {angle[1]}: name two different joints "
                                 f"or points")
            spec = (angle[0], angle[1])
        elif angle is not None:
            spec = float(checks.finite(angle, f"{what} (a number, or a line (p, q) of two point names)", ()))
            if not abs(spec) <= checks.MAX_ANGLE:  # (a body with a line took it as the turn it counts from)
                raise ModelError(f"the {what} is {spec:.6g} rad, beyond +-{checks.MAX_ANGLE:.6g} rad (float64 rounds "
                                 "it by more than the rows' tolerance): give it within a turn")
        return spec

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
        self._mass[b] = _mass(b, mass, com, inertia)
        self._model = None

    @property
    def gravity(self):
        """Gravitational acceleration, a world 2-vector such as (0, -9.81), or None (none)."""
        return self._gravity

    @gravity.setter
    def gravity(self, g):
        self._gravity = None if g is None else tuple(checks.point(g, "gravity").tolist())
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
        if not (isinstance(fixed, str) and fixed in ("world", "body")):
            raise ModelError(f"load on {b!r}: fixed must be 'world' or 'body', got {fixed!r}")
        if not callable(force):
            force = checks.point(force, f"load force on {b!r}")
        if not callable(torque):
            torque = checks.finite(torque, f"load torque on {b!r}", ())
            if abs(torque) > checks.SCALE:  # (its forces overflowed to inf under a valid status)
                raise ModelError(f"load torque on {b!r} = {float(torque):g} is beyond the numbers a sketch holds "
                                 f"(+-{checks.SCALE:g}): give it in another unit")
        if at is None and (callable(force) or np.any(force != 0)):
            raise ModelError(f"load on {b!r}: give at, the sketch point the force acts at")
        self._loads.append((b, np.zeros(2) if at is None else checks.point(at, f"load on {b!r} at"), force, torque, fixed))
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
            return checks.point(at, f"{name!r} at")
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
        if not isinstance(name, str):
            raise ModelError(f"a joint or point is named by a string, got {name!r}")
        if name not in self._points:
            raise ModelError(f"unknown joint or point {name!r}: the named positions are {sorted(self._points)}")
        return self._points[name][1]

    def _bodies_of(self, name):
        """The bodies a joint or point is on: a revolute's two, the body of any other's anchor."""
        self._position(name)
        return bodies_of(self._joints, self._points, name)

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
        length = checks.length(length, f"distance {a}-{b}")
        shared = self._bodies_of(a) & self._bodies_of(b)
        if not shared:
            raise ModelError(f"distance {a}-{b}: {a!r} is on {sorted(self._bodies_of(a))} and {b!r} on "
                             f"{sorted(self._bodies_of(b))}: a distance joins two joints or points of one body")
        if a == b:
            raise ModelError(f"distance {a}-{b}: name two different joints or points")
        for d in self._dimensions:
            if {d.a, d.b} == {a, b}:
                raise ModelError(f"{d} is stated already: state each length once")
        # (restate and Vary name it "a-b": one name for two numbers would change the other)
        taken = [f"{d.a}-{d.b}" for d in self._dimensions] + [d.name for d in self._drivers if d.name in self._starts]
        if f"{a}-{b}" in taken:
            raise ModelError(f"distance {a}-{b}: that name is another number's of the mechanism already (names with "
                             f"'-' in them): rename a joint or point")
        self._dimensions.append(Dimension(a, b, length))
        self._model = None

    def restate(self, name: str, value: float) -> None:
        """Change one of the mechanism's numbers: a stated distance, named "a-b" as
        :meth:`distance` stated it (it becomes the last stated, the first an assembly that
        fails names), or a driver's start, named as the driver.

        >>> m = Mechanism()
        >>> crank = m.add_body("crank")
        >>> m.add_revolute("O", m.ground, crank, at=(0, 0))
        >>> m.add_point("P", crank, at=(1, 0))
        >>> m.distance("O", "P", 1.0)
        >>> m.drive("O", start=0.0)
        >>> m.restate("O-P", 2.0)
        >>> m.restate("O", 0.5)
        >>> m.compile().sketch.position("P").round(12).tolist()
        [1.755165123781, 0.958851077208]
        """
        if not isinstance(name, str):
            raise ModelError(f"restate takes a stated distance 'a-b' or a driver's name, got {name!r}")
        for k, d in enumerate(self._dimensions):
            if f"{d.a}-{d.b}" == name:
                # stated anew, it is the last stated: the first an assembly that fails suspects
                new = Dimension(d.a, d.b, checks.length(value, f"distance {name}"))
                del self._dimensions[k]
                self._dimensions.append(new)
                break
        else:
            if name not in self._starts:
                raise ModelError(f"{name!r} is no number of mechanism {self.name!r}: it has "
                                 f"{[f'{d.a}-{d.b}' for d in self._dimensions] + list(self._starts)} "
                                 f"(stated distances 'a-b' and drivers' starts)")
            self._starts[name] = float(checks.finite(value, f"start of driver {name!r}", ()))
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
        at = checks.point(at, f"joint {name!r} at")
        return dict(at=at, direction=checks.direction(direction, f"joint {name!r} direction"),
                    origin=at if origin is None else checks.point(origin, f"joint {name!r} origin"))

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
        internal = checks.flag(internal, f"gear {name!r} internal")
        hold_distance = checks.flag(hold_distance, f"gear {name!r} hold_distance")
        data = dict(radius_a=checks.length(radius_a, f"gear {name!r} radius_a"),
                    radius_b=checks.length(radius_b, f"gear {name!r} radius_b"),
                    sign=-1.0 if internal else 1.0, pressure_angle=checks.pressure_angle(pressure_angle, name))
        checks.gear_radii(data["radius_a"], data["radius_b"], internal, name)
        for key, value in (("centre_a", centre_a), ("centre_b", centre_b)):
            data[key] = None if value is None else checks.point(value, f"gear {name!r} {key}")
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
        pins = [j for j in self._joints if j.pin]
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
        if not (isinstance(side, str) and side in ("left", "right")):
            raise ModelError(f"joint {name!r}: side must be 'left' or 'right', got {side!r}")
        data = dict(radius=checks.length(radius, f"joint {name!r} radius"), centre=checks.point(centre, f"joint {name!r} centre"),
                    through=checks.point(through, f"joint {name!r} through"),
                    direction=checks.direction(direction, f"joint {name!r} direction"),
                    side=1.0 if side == "left" else -1.0, pressure_angle=checks.pressure_angle(pressure_angle, name))
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
        if name is not None and not isinstance(name, str):
            raise ModelError(f"a driver's name must be a string, got {name!r}")
        given = [k for k, v in (("joint", joint), ("body", body), ("point", point)) if v is not None]
        if len(given) != 1:
            raise ModelError("drive needs exactly one of joint=, body= or point=")
        for k, v in (("joint", joint), ("point", point)):
            if v is not None and not isinstance(v, str):
                raise ModelError(f"drive {k}= takes a {k}'s name, got {v!r}")
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
            if not (isinstance(axis, str) and axis in ("x", "y")):
                raise ModelError(f"driving point {point!r} needs axis='x' or axis='y', got {axis!r}")
            b, at = self._points[point]
            drv = CoordinateDriver(f"{point}.{axis}", (b,), at=at, axis=(1.0, 0.0) if axis == "x" else (0.0, 1.0))
        drv.name = name or drv.name
        if any(d.name == drv.name for d in self._drivers):
            raise ModelError(f"a driver named {drv.name!r} exists already: pass name= to tell them apart")
        if start is not None:
            if drv.name in (f"{d.a}-{d.b}" for d in self._dimensions):  # (see distance)
                raise ModelError(f"driver {drv.name!r}: its start would have a stated distance's name: pass another name=")
            self._starts[drv.name] = float(checks.finite(start, f"start of driver {drv.name!r}", ()))
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
        return rule_line(self.sketch(), body, lambda p, q: not np.array_equal(self._points[p][1], self._points[q][1]))

    # ---- compiling -----------------------------------------------------------------------

    def compile(self) -> "Model":
        """Check and freeze the mechanism into a :class:`Model` (cached until the next change)."""
        if self._model is None:
            self._model = compile_sketch(self.name, resolve(self.sketch()))
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


def _mass(b, mass, com, inertia):
    """Body ``b``'s (mass, com, inertia), checked."""
    mass, inertia = checks.finite(mass, f"mass of body {b!r}", ()), checks.finite(inertia, f"inertia of body {b!r}", ())
    if mass < 0 or inertia < 0:
        raise ModelError(f"body {b!r}: mass and inertia must be >= 0, got {float(mass)!r} and {float(inertia)!r}")
    if max(mass, inertia) > checks.SCALE:  # (its forces overflowed to inf)
        raise ModelError(f"body {b!r}: mass {float(mass):g} or inertia {float(inertia):g} is beyond the numbers "
                         f"a sketch holds (+-{checks.SCALE:g}): give it in another unit")
    if com is None:
        raise ModelError(f"body {b!r}: give com, the sketch point of its centre of mass")
    return float(mass), checks.point(com, f"com of body {b!r}"), float(inertia)
