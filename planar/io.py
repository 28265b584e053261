"""Mechanism files: one JSON document holds a mechanism, its units and its sweep settings.

The format (version 1) mirrors the builder calls of :class:`planar.Mechanism`, so a file reads
like the script that would build it::

    {
      "version": 1,
      "name": "four-bar",
      "units": {"length": "mm", "angle": "deg", "rate": "rpm"},
      "bodies": [{"name": "crank", "mass": 0.5, "com": [0.5, 0.87], "inertia": 0.02}, {"name": "coupler"},
                 {"name": "rocker", "line": ["O4", "B"]}, {"name": "gear", "angle": 30}, {"name": "lever", "offset": 90}],
      "points": [{"name": "C", "body": "coupler", "at": [1.48, 3.67]}],
      "joints": [
        {"type": "revolute", "name": "O2", "bodies": ["ground", "crank"], "at": [0, 0]},
        {"type": "prismatic", "name": "S", "bodies": ["ground", "slider"], "at": [3, 1],
         "direction": [1, 0], "origin": [0, 1]},
        {"type": "slot", ...the same fields as prismatic...},
        {"type": "gear", "name": "g", "bodies": ["sun", "planet"], "radius_a": 2, "radius_b": 1,
         "internal": false, "carrier": "arm", "centre_a": [0, 0], "centre_b": [3, 0],
         "hold_distance": false, "pressure_angle": 20},
        {"type": "rack_pinion", "name": "rp", "bodies": ["pinion", "rack"], "radius": 1,
         "centre": [0, 1], "through": [0, 0], "direction": [1, 0], "side": "left",
         "pressure_angle": 20},
        {"type": "rolling", ...the same fields as rack_pinion, bodies [wheel, body]...}
      ],
      "dimensions": [{"between": ["O2", "A"], "length": 2}, {"between": ["A", "B"], "length": 3}],
      "drivers": [{"joint": "O2", "start": 60}, {"body": "crank"}, {"point": "C", "axis": "x", "name": "Cx"}],
      "gravity": [0, -9.81],
      "loads": [{"body": "rocker", "force": [0, -20], "at": [4, 1], "torque": 0, "fixed": "world"}],
      "sweep": {"start": 0, "stop": 360, "num": 73, "speed": 60, "acceleration": 0,
                "rocking": false}
    }

- Every joint entry is ``{"type", "name", "bodies"}`` plus the keyword arguments of the
  builder method ``add_<type>``; ``bodies`` are its two body arguments in order. Optional fields
  may be left out.
- A body's ``mass``, ``com`` (a sketch point) and ``inertia`` (about the centre of mass) are
  optional, as in :meth:`planar.Mechanism.add_body`; ``gravity`` (a world vector, default none)
  and ``loads`` (constant forces and torques: :meth:`planar.Mechanism.add_load`; ``torque`` and
  ``fixed``, "world" or "body", optional) are for :meth:`planar.Sweep.forces`. Mass, length and
  time units are the user's (kg, m, s give forces in N); only angles are converted.
- A gear's or rack's ``pressure_angle`` is in ``units.angle`` (``pressure_angle_rad`` in
  radians); default 20 degrees (a ``rolling`` contact has none).
- Points are world coordinates of the sketch, in ``units.length``: "m", "cm", "mm" or "in"
  convert (``load(path, length_unit="mm")`` restates every length of the file in mm, and the
  mass properties, gravity and loads with them), any other label only names them. With
  ``dimensions`` (each the length ``between`` two joints or points of one body, as
  :meth:`planar.Mechanism.distance`) they are rough guesses, and loading assembles them: editing
  a length re-assembles the mechanism.
- A body's angle comes from its coordinates: the direction of its reference line (by default
  from its joint nearest the ground to its next joint, see
  :meth:`planar.Mechanism.reference_line`; ``line`` names another, [p, q]), plus ``offset``
  (``units.angle``) if given. Only a body with no line (fewer than two named places, like a gear
  on its axle alone) takes an ``angle`` (its sketch angle, ``units.angle``). ``offset_rad`` and
  ``angle_rad`` give them in radians whatever the units (files written by planar use them where
  degrees would not round-trip).
- A driver's ``start`` is its input value in the sketch (``units.angle`` or length), as
  ``drive(start=)``: files written by planar give it with ``dimensions`` only (without, the
  coordinates show it).
- ``sweep``: ``start``/``stop`` of each input (a number, or a list with one per input) in
  ``units.angle`` for angle inputs and lengths for travel and coordinate inputs; ``num`` values;
  ``speed`` the input's speed (``units.rate``, or length/s; the rate points from start to stop)
  and ``acceleration`` (rad/s^2, or deg/s^2 when the rate unit is deg/s, or length/s^2); ``rocking`` sweeps start -> stop -> start (a back and forth motion).
- ``units``: ``length`` any short label ("" for none), ``angle`` "deg" or "rad", ``rate``
  "rad/s", "deg/s" or "rpm". Defaults: "", "deg", "rad/s".

Saving and loading are exact: a file read and written again is the same document, and a
mechanism written and read again has the same bodies, points, joints and drivers, bit for bit
(numbers are written with Python's shortest round-trip repr).

>>> import planar, planar.io
>>> m = planar.Mechanism("pendulum")
>>> _ = m.add_body("bob", angle=0.5)
>>> m.add_revolute("O", m.ground, "bob", at=(0, 0))
>>> m.add_point("P", "bob", at=(1.0, 0.0))
>>> m.drive("O")
>>> text = planar.io.dumps(m)
>>> doc = planar.io.loads(text)
>>> doc.mechanism.compile().dof, planar.io.dumps(doc) == text
(1, True)
"""

import inspect
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planar.errors import FileFormatError, InputError, ModelError, PlanarError
from planar.joints import FILE_TYPES
from planar.joints.base import xy
from planar.model import GROUND, Mechanism
from planar.units import Units, convert_length

VERSION = 1

# ---- the schema: field kinds, and the fields of each joint type ------------------------------

_KINDS = {
    "name": "a non-empty string",
    "point": "a list of two finite numbers [x, y]",
    "vector": "a list of two finite numbers, not both zero",
    "positive": "a positive number",
    "number": "a finite number",
    "bool": "true or false",
    "side": '"left" or "right"',
    "axis": '"x" or "y"',
    "count": "an integer of at least 2",
    "numbers": "a number or a list of numbers",
    "fixed": '"world" or "body"',
    "pair": "a list of two different names",
}

_MASS = {"mass": ("number", True), "com": ("point", True), "inertia": ("number", False)}
_LOAD = {"body": ("name", True), "force": ("point", False), "at": ("point", False), "torque": ("number", False),
         "fixed": ("fixed", False)}
_TOP = {"version", "name", "units", "bodies", "points", "joints", "drivers", "dimensions", "sweep", "gravity", "loads"}
_SWEEP = {"start": "numbers", "stop": "numbers", "num": "count", "speed": "numbers",
          "acceleration": "numbers", "rocking": "bool"}


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _valid(kind, v):
    if kind == "name":
        return isinstance(v, str) and v != ""
    if kind in ("point", "vector"):
        ok = isinstance(v, list) and len(v) == 2 and all(_is_number(x) for x in v)
        return ok and (kind == "point" or any(x != 0 for x in v))
    if kind == "positive":
        return _is_number(v) and v > 0
    if kind == "number":
        return _is_number(v)
    if kind == "bool":
        return isinstance(v, bool)
    if kind == "side":
        return v in ("left", "right")
    if kind == "axis":
        return v in ("x", "y")
    if kind == "fixed":
        return v in ("world", "body")
    if kind == "count":
        return isinstance(v, int) and not isinstance(v, bool) and v >= 2
    if kind == "pair":
        return isinstance(v, list) and len(v) == 2 and all(_valid("name", x) for x in v) and v[0] != v[1]
    if kind == "numbers":
        return _is_number(v) or (isinstance(v, list) and len(v) > 0 and all(_is_number(x) for x in v))
    raise AssertionError(kind)


class _Checker:
    """Field-by-field validation that names the field at fault (``joints[2].radius_a``)."""

    def __init__(self, source):
        self.source = source

    def fail(self, where, what):
        raise FileFormatError(f"{self.source}: {where}: {what}")

    def field(self, obj, key, kind, where, required=True):
        if key not in obj:
            if required:
                self.fail(where, f"missing field {key!r} ({_KINDS[kind]})")
            return None
        if not _valid(kind, obj[key]):
            self.fail(f"{where}.{key}", f"must be {_KINDS[kind]}, got {json.dumps(obj[key])}")
        return obj[key]

    def mapping(self, obj, where, known):
        if not isinstance(obj, dict):
            self.fail(where, f"must be a JSON object {{...}}, got {json.dumps(obj)[:60]}")
        unknown = sorted(set(obj) - set(known))
        if unknown:
            self.fail(where, f"unknown field {unknown[0]!r}: the fields here are {', '.join(sorted(known))}")

    def items(self, obj, key, where):
        v = obj.get(key, [])
        if not isinstance(v, list):
            self.fail(f"{where}{key}", f"must be a list [...], got {json.dumps(v)[:60]}")
        return v


# ---- the document ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SweepSettings:
    """Sweep settings of a file, in the file's units: one ``start``, ``stop``, ``speed`` and
    ``acceleration`` per input, ``num`` values, and ``rocking`` (start -> stop -> start)."""

    start: tuple
    stop: tuple
    num: int = 181
    speed: tuple = (1.0,)
    acceleration: tuple = (0.0,)
    rocking: bool = False

    def values(self, model, units):
        """Input values (N, f) and rates (N, f), (N, f) in internal units for ``model``."""
        from planar import arguments

        f = len(model.drivers)
        if f == 0:
            raise FileFormatError(f"drivers: the mechanism has no driver to sweep: add {model.dof} to drivers, "
                                  f'like {{"joint": "O2"}} or {{"body": "crank"}}')
        arguments.size(model, self.num * (2 if self.rocking else 1), "the sweep (sweep.num)")
        cols = []
        for name, key in (("start", self.start), ("stop", self.stop), ("speed", self.speed),
                          ("acceleration", self.acceleration)):
            if len(key) not in (1, f):
                raise FileFormatError(f"sweep.{name}: has {len(key)} values but the mechanism has {f} "
                                      f"input(s) {list(model.input_names)}")
            cols.append(np.broadcast_to(np.asarray(key, float), (f,)))
        start, stop, speed, acc = cols
        t = np.linspace(0.0, 1.0, self.num)
        sign = np.ones_like(t)
        if self.rocking:
            t, sign = np.r_[t, t[-2::-1]], np.r_[sign, -sign[-2::-1]]
        U, Ud, Udd = [], [], []
        for k, is_len in enumerate(model.input_lengths):
            U.append(units.input_to_internal(start[k] + t * (stop[k] - start[k]), is_len, 0))
            # speed is a size: the rate points from start to stop (and back when rocking)
            forward = 1.0 if stop[k] >= start[k] else -1.0
            Ud.append(forward * sign * units.input_to_internal(abs(speed[k]), is_len, 1))
            Udd.append(np.full(t.shape, units.input_to_internal(acc[k], is_len, 2)))
        return np.stack(U, 1), np.stack(Ud, 1), np.stack(Udd, 1)


@dataclass(frozen=True)
class MechanismFile:
    """A loaded mechanism file: the built :class:`planar.Mechanism`, its :class:`Units`, the
    :class:`SweepSettings` (or None) and ``data``, the canonical document (what :func:`save`
    writes back)."""

    mechanism: Mechanism
    units: Units
    sweep: SweepSettings | None
    data: dict = field(repr=False)


def _tuple(v):
    return tuple(float(x) for x in v) if isinstance(v, list) else (float(v),)


def from_dict(data, source="<mechanism file>", length_unit=None):
    """Validate a document (parsed JSON) and build it, its lengths restated in ``length_unit``
    when given; see the module doc for the format."""
    if length_unit is not None:
        data = convert_lengths(from_dict(data, source).data, length_unit, source)
    c = _Checker(source)
    c.mapping(data, "file", _TOP)
    if data.get("version", VERSION) != VERSION:
        c.fail("version", f"this planar reads version {VERSION} files, got {json.dumps(data['version'])}")
    name = data.get("name", "mechanism")
    if not isinstance(name, str):
        c.fail("name", f"must be a string, got {json.dumps(name)}")
    udata = data.get("units", {})
    c.mapping(udata, "units", ("length", "angle", "rate"))
    try:
        units = Units(**udata)
    except PlanarError as e:
        c.fail("units", str(e))

    m = Mechanism(name)
    given = {}  # body -> (where, key, radians) of an angle or offset, checked once the places are known
    for i, b in enumerate(c.items(data, "bodies", "")):
        where = f"bodies[{i}]"
        c.mapping(b, where, ("name", "line", "angle", "angle_rad", "offset", "offset_rad", *_MASS))
        bname = c.field(b, "name", "name", where)
        line = c.field(b, "line", "pair", where, False)
        keys = [k for k in ("angle", "angle_rad", "offset", "offset_rad") if k in b]
        if len(keys) > 1 or (line and keys and keys[0].startswith("angle")):
            c.fail(where, f"give one of 'line', 'angle', 'offset' (or 'line' with 'offset'), got {keys + ['line'] * bool(line)}")
        if keys:
            v = c.field(b, keys[0], "number", where)
            given[bname] = (f"{where}.{keys[0]}", keys[0].split("_")[0],
                            float(v if keys[0].endswith("_rad") else units.angle_to_internal(v)))
        mass = {k: c.field(b, k, kind, where, req) for k, (kind, req) in _MASS.items() if k in b or req} \
            if any(k in b for k in _MASS) else {}
        _build(c, where, m.add_body, bname, angle=tuple(line) if line else None, **mass)
    for i, p in enumerate(c.items(data, "points", "")):
        where = f"points[{i}]"
        c.mapping(p, where, ("name", "body", "at"))
        _build(c, where, m.add_point, c.field(p, "name", "name", where), c.field(p, "body", "name", where),
               at=c.field(p, "at", "point", where))
    for i, j in enumerate(c.items(data, "joints", "")):
        where = f"joints[{i}]"
        if not isinstance(j, dict):
            c.mapping(j, where, ())
        kind = j.get("type")
        if not isinstance(kind, str) or kind not in FILE_TYPES:
            c.fail(f"{where}.type", f"must be one of {', '.join(FILE_TYPES)}, got {json.dumps(kind)}")
        spec = FILE_TYPES[kind]
        angles = [k for k, (kind_, _) in spec.items() if kind_ == "angle"]
        c.mapping(j, where, {"type", "name", "bodies", *spec, *(f"{k}_rad" for k in angles)})
        jname = c.field(j, "name", "name", where)
        bodies = j.get("bodies")
        if not (isinstance(bodies, list) and len(bodies) == 2 and all(_valid("name", b) for b in bodies)):
            c.fail(f"{where}.bodies", f"must be a list of two body names, got {json.dumps(bodies)}")
        kwargs = {k: c.field(j, k, kind_, where, req) for k, (kind_, req) in spec.items()
                  if kind_ != "angle" and (k in j or req)}
        for k in angles:
            angle = _angle(c, j, k, where, units)
            if angle is not None:
                kwargs[k] = angle
        _build(c, f"{where} ({kind} {jname!r})", getattr(m, f"add_{kind}"), jname, *bodies, **kwargs)
    for bname, (where, key, value) in given.items():
        _body_angle(c, m, bname, where, key, value)
    for i, d in enumerate(c.items(data, "dimensions", "")):
        where = f"dimensions[{i}]"
        c.mapping(d, where, ("between", "length"))
        _build(c, where, m.distance, *c.field(d, "between", "pair", where), c.field(d, "length", "positive", where))
    for i, d in enumerate(c.items(data, "drivers", "")):
        where = f"drivers[{i}]"
        c.mapping(d, where, ("joint", "body", "point", "axis", "name", "start"))
        kwargs = {k: c.field(d, k, "name", where, False) for k in ("joint", "body", "point", "name")}
        if "axis" in d:
            kwargs["axis"] = c.field(d, "axis", "axis", where)
        start = c.field(d, "start", "number", where, False)
        if start is not None:
            turns = "body" in d or any(j.name == d.get("joint") and j.coordinate() is not None
                                       and not j.coordinate().length_rows[0] for j in m.sketch().joints)
            kwargs["start"] = float(units.angle_to_internal(start)) if turns else float(start)
        _build(c, where, m.drive, **{k: v for k, v in kwargs.items() if v is not None})

    if "gravity" in data:
        g = c.field(data, "gravity", "point", "file")
        m.gravity = g
    for i, ld in enumerate(c.items(data, "loads", "")):
        where = f"loads[{i}]"
        c.mapping(ld, where, _LOAD)
        kwargs = {k: c.field(ld, k, kind, where, req) for k, (kind, req) in _LOAD.items() if k in ld or req}
        _build(c, where, m.add_load, kwargs.pop("body"), **kwargs)

    sweep = None
    if "sweep" in data:
        s = data["sweep"]
        c.mapping(s, "sweep", _SWEEP)
        got = {k: c.field(s, k, kind, "sweep", k in ("start", "stop")) for k, kind in _SWEEP.items()}
        sweep = SweepSettings(
            start=_tuple(got["start"]), stop=_tuple(got["stop"]), num=got["num"] or 181,
            speed=_tuple(1.0 if got["speed"] is None else got["speed"]),
            acceleration=_tuple(0.0 if got["acceleration"] is None else got["acceleration"]),
            rocking=bool(got["rocking"]))
    return MechanismFile(m, units, sweep, _canonical(data))


def _angle(c, obj, key, where, units):
    """An angle field ``key`` (in the file's angle unit) or ``key_rad`` (radians), or None."""
    if key in obj and f"{key}_rad" in obj:
        c.fail(where, f"give {key!r} or '{key}_rad', not both")
    rad = c.field(obj, f"{key}_rad", "number", where, False)
    if rad is not None:
        return rad
    shown = c.field(obj, key, "number", where, False)
    return None if shown is None else float(units.angle_to_internal(shown))


def _angle_entry(key, angle, units):
    """{key: angle in the file's unit}, or {key_rad: radians} where that unit would not give
    back the same radians."""
    shown = float(units.angle_from_internal(angle))
    return {key: shown} if float(units.angle_to_internal(shown)) == angle else {f"{key}_rad": angle}


def _body_angle(c, m, body, where, key, value):
    """Set a body's angle from a file: an ``angle`` only where the coordinates give no line, an
    ``offset`` from its line (the line's direction in the sketch plus the offset)."""
    spec = m.sketch().bodies[body]
    line = spec or m.reference_line(body)
    if key == "angle" and line is not None:
        c.fail(where, f"body {body!r} has the reference line {line[0]} -> {line[1]}: its angle comes from its "
                      f"coordinates; remove the angle, or give an 'offset' from the line")
    if key == "offset" and line is None:
        c.fail(where, f"body {body!r} has fewer than two named places, so no line to offset from: give 'angle'")
    if key == "offset":
        pts = m.sketch().points
        if line[0] not in pts or line[1] not in pts:
            c.fail(where, f"the line {line[0]} -> {line[1]} of body {body!r} names no joint or point")
        d = pts[line[1]][1] - pts[line[0]][1]
        value += math.atan2(d[1], d[0])
    m._bodies[body] = value  # the builder's numeric angle: the body's angle in the sketch


def convert_lengths(data, unit, source="<mechanism file>"):
    """A valid document with every length (points, joint positions and radii, and the sweep's
    values of sliding and point inputs) restated in ``unit``, and ``units.length`` set to it.

    >>> doc = {"units": {"length": "cm"}, "bodies": [{"name": "b"}],
    ...        "joints": [{"type": "slot", "name": "s", "bodies": ["ground", "b"], "at": [2, 0], "direction": [1, 0]}],
    ...        "drivers": [{"joint": "s"}], "sweep": {"start": 0, "stop": 2.5}}
    >>> new = convert_lengths(doc, "mm")
    >>> new["joints"][0]["at"], new["sweep"], new["units"]
    ([20.0, 0.0], {'start': 0.0, 'stop': 25.0}, {'length': 'mm'})
    """
    have = data.get("units", {}).get("length", "")
    try:
        convert_length(1.0, have, unit)
    except InputError as e:
        raise FileFormatError(f"{source}: units.length: {e}") from None

    def conv(v):
        return [float(x) for x in convert_length(v, have, unit)] if isinstance(v, list) else float(convert_length(v, have, unit))

    out = json.loads(json.dumps(data))
    k = float(convert_length(1.0, have, unit))
    for p in out.get("points", []):
        p["at"] = conv(p["at"])
    for d in out.get("dimensions", []):
        d["length"] = conv(d["length"])
    # mass and time keep their units: com and gravity scale as lengths, forces too (mass x
    # length / time^2), inertia and torques as length^2
    for b in out.get("bodies", []):
        if "com" in b:
            b["com"] = conv(b["com"])
        if "inertia" in b:
            b["inertia"] = b["inertia"] * k * k
    if "gravity" in out:
        out["gravity"] = conv(out["gravity"])
    for ld in out.get("loads", []):
        for key in ("at", "force"):
            if key in ld:
                ld[key] = conv(ld[key])
        if "torque" in ld:
            ld["torque"] = ld["torque"] * k * k
    for j in out.get("joints", []):
        for key, (kind, _) in FILE_TYPES[j["type"]].items():
            if key in j and kind in ("point", "positive"):
                j[key] = conv(j[key])
    # which inputs are lengths (a slider's or slot's travel, a point's coordinate): the built drivers say
    lengths = [bool(d.length_rows[0]) for d in from_dict(data, source).mechanism.sketch().drivers]
    for d, is_len in zip(out.get("drivers", []), lengths):
        if is_len and "start" in d:
            d["start"] = conv(d["start"])
    s = out.get("sweep", {})
    for key in ("start", "stop", "speed", "acceleration"):
        if key in s and lengths:
            values = s[key] if isinstance(s[key], list) else [s[key]]
            if len(values) == 1:
                values = values * len(lengths)
            if len(values) == len(lengths):  # else the sweep is refused later, naming the field
                new = [conv(v) if is_len else v for v, is_len in zip(values, lengths)]
                s[key] = new[0] if not isinstance(s[key], list) and len(set(new)) == 1 else new
    out.setdefault("units", {})["length"] = unit
    return out


def _build(c, where, call, *args, **kwargs):
    try:
        call(*args, **kwargs)
    except ModelError as e:
        c.fail(where, str(e))


def _canonical(data):
    """The document with its version, so that saving a loaded file writes it back the same."""
    return {"version": VERSION, **{k: v for k, v in data.items() if k != "version"}}


# ---- from a Mechanism to a document ---------------------------------------------------------


def _joint_entry(j, units):
    """The builder call that makes joint ``j``: {"type", "name", "bodies", **kwargs}, its angles
    in the file's unit (left out at the builder's default)."""
    entry = j.file_entry()
    builder = inspect.signature(getattr(Mechanism, f"add_{entry['type']}")).parameters
    out = {}
    for key, v in entry.items():
        field_ = key.removesuffix("_rad")
        if key.endswith("_rad") and FILE_TYPES[entry["type"]].get(field_, ("",))[0] == "angle":
            out |= {} if v == builder[field_].default else _angle_entry(field_, v, units)
        else:
            out[key] = v
    return out


def _body_entry(mech, name, spec, units):
    """A body's entry: its line if named, an offset from its line for a numeric angle, or an
    angle for a body with no line; never an angle its coordinates could contradict."""
    entry = {"name": name}
    if isinstance(spec, tuple):
        entry["line"] = list(spec)
    elif spec is not None:
        line, key = mech.reference_line(name), "angle"
        if line is not None:
            pts = mech.sketch().points
            d = pts[line[1]][1] - pts[line[0]][1]
            spec, key = spec - math.atan2(d[1], d[0]), "offset"
        if spec != 0.0 or key == "angle":
            entry |= _angle_entry(key, spec, units)
    return entry


def _mass_entry(mass):
    return {} if mass is None else {"mass": mass[0], "com": xy(mass[1]), "inertia": mass[2]}


def _load_entry(body, at, force, torque, fixed):
    if callable(force) or callable(torque):
        raise FileFormatError(f"the load on {body!r} is given by a function of the inputs, which has no file "
                              f"form: give it as constants to save it")
    return {"body": body, "force": xy(force), "at": xy(at), "torque": float(torque), "fixed": fixed}


def _shown_angle(v, units):
    """An angle in the file's unit, as typed (60, not 59.99999999999999) when that is the same
    angle to rounding."""
    shown = float(units.angle_from_internal(v))
    typed = float(f"{shown:.12g}")
    return typed if abs(float(units.angle_to_internal(typed)) - v) <= 1e-15 * abs(v) else shown


def to_dict(obj, units=None, sweep=None):
    """The document of a :class:`planar.Mechanism` (with ``units``, default degrees and rad/s,
    and optional :class:`SweepSettings` or dict of sweep fields) or of a :class:`MechanismFile`."""
    if isinstance(obj, MechanismFile):
        return json.loads(json.dumps(obj.data))
    if not isinstance(obj, Mechanism):
        raise FileFormatError(f"can only save a planar.Mechanism or a MechanismFile, got {type(obj).__name__}")
    units = units or Units()
    sk = obj.sketch()
    joint_names = {j.name for j in sk.joints}
    points = {n: v for n, v in sk.points.items() if n not in joint_names}
    data = {"version": VERSION, "name": obj.name,
            "units": {"length": units.length, "angle": units.angle, "rate": units.rate},
            "bodies": [_body_entry(obj, n, a, units) | _mass_entry(sk.mass.get(n)) for n, a in sk.bodies.items()
                       if n != GROUND],
            "points": [{"name": n, "body": b, "at": xy(p)} for n, (b, p) in points.items()],
            "joints": [_joint_entry(j, units) for j in sk.joints]}
    if sk.dimensions:
        data["dimensions"] = [{"between": [d.a, d.b], "length": d.length} for d in sk.dimensions]
    data["drivers"] = [d.driver_entry(sk.joints, sk.points) for d in sk.drivers]
    for entry, d in zip(data["drivers"], sk.drivers):
        if d.name in sk.starts and sk.dimensions:  # without dimensions the sketch shows the start
            v = sk.starts[d.name]
            entry["start"] = v if d.length_rows[0] else _shown_angle(v, units)
    if sk.gravity is not None:
        data["gravity"] = list(sk.gravity)
    if sk.loads:
        data["loads"] = [_load_entry(*ld) for ld in sk.loads]
    if sweep is not None:
        s = sweep if isinstance(sweep, dict) else {
            "start": list(sweep.start), "stop": list(sweep.stop), "num": sweep.num,
            "speed": list(sweep.speed), "acceleration": list(sweep.acceleration), "rocking": sweep.rocking}
        data["sweep"] = {k: (v[0] if isinstance(v, list) and len(v) == 1 else v) for k, v in s.items()}
    return data


# ---- text and files ------------------------------------------------------------------------


def dumps(obj, units=None, sweep=None):
    """JSON text of a mechanism or a loaded file (see :func:`to_dict`)."""
    data = to_dict(obj, units, sweep)
    if not isinstance(obj, MechanismFile):
        from_dict(json.loads(json.dumps(data)), "<written document>")  # never write a file we cannot read
    return _format(data)


def _format(data):
    """JSON with one line per top-level field, and per body, point, joint or driver."""
    lines = []
    for key, value in data.items():
        if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            items = ",\n".join(f"    {json.dumps(v)}" for v in value)
            lines.append(f"  {json.dumps(key)}: [\n{items}\n  ]")
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def loads(text, source="<string>", length_unit=None):
    """Read a mechanism document from JSON text: a :class:`MechanismFile` (its lengths in
    ``length_unit`` when given)."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as e:
        raise FileFormatError(f"{source}: not valid JSON at line {e.lineno}, column {e.colno}: {e.msg}") from None
    except RecursionError:
        raise FileFormatError(f"{source}: lists or objects nested too deeply for a mechanism file "
                              f"(at most {MAX_DEPTH} levels)") from None
    depth = _depth(data)
    if depth > MAX_DEPTH:
        raise FileFormatError(f"{source}: lists or objects nested more than {MAX_DEPTH} levels deep: "
                              f"a mechanism file nests 4 (file, joints, a joint, its point)")
    return from_dict(data, source, length_unit)


MAX_DEPTH = 16  # the format nests 4 levels (file, "joints", a joint, "at"): room to grow, far from recursion


def _depth(data):
    """How deep lists and objects nest in ``data`` (without recursion: a file may nest deeply)."""
    deepest, todo = 0, [(data, 0)]
    while todo:
        v, d = todo.pop()
        if isinstance(v, (list, dict)):
            d += 1
            deepest = max(deepest, d)
            if deepest > MAX_DEPTH:
                break
            todo.extend((x, d) for x in (v.values() if isinstance(v, dict) else v))
    return deepest


def load(path, length_unit=None):
    """Read a mechanism file: a :class:`MechanismFile` (``.mechanism``, ``.units``, ``.sweep``),
    its lengths restated in ``length_unit`` ("m", "cm", "mm" or "in") when given."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise FileFormatError(f"{path}: cannot read the file: {e.strerror or e}") from None
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not a text file (a mechanism file is UTF-8 JSON)") from None
    return loads(text, str(path), length_unit)


def save(obj, path, units=None, sweep=None):
    """Write a mechanism (or a loaded :class:`MechanismFile`) to ``path`` as JSON; returns the path."""
    path = Path(path)
    path.write_text(dumps(obj, units, sweep), encoding="utf-8")
    return path
