"""Reading mechanism files: JSON text or a parsed document to a :class:`MechanismFile`, every
field checked and named when wrong; lengths restated in another unit."""

import json
import math
import os
from pathlib import Path

from planar.errors import FileFormatError, InputError, ModelError, PlanarError, shown
from planar.io.document import NUM, MechanismFile, SweepSettings
from planar.io.schema import LOAD_FIELDS, MASS_FIELDS, SWEEP_FIELDS, TOP_FIELDS, VERSION, Checker, valid
from planar.joints import FILE_TYPES
from planar.model import Mechanism
from planar.units import Units, convert_length


def _tuple(v):
    return tuple(float(x) for x in v) if isinstance(v, list) else (float(v),)


def from_dict(data, source="<mechanism file>", length_unit=None):
    """Validate a document (parsed JSON) and build it, its lengths restated in ``length_unit``
    when given; see the module doc for the format."""
    if length_unit is not None:
        data = convert_lengths(from_dict(data, source).data, length_unit, source)
    c = Checker(source)
    if _depth(data) > MAX_DEPTH:
        c.fail("file", f"lists or objects nested more than {MAX_DEPTH} levels deep: a mechanism file nests 4 "
                       f"(file, joints, a joint, its point)")
    bad = _not_json(data)
    if bad is not None:
        c.fail(bad[0], f"must be JSON (numbers, text, true, false, null, lists and objects), got {bad[1]}: give "
                       f"plain Python numbers, strings, lists and dicts")
    c.mapping(data, "file", TOP_FIELDS)
    if data.get("version", VERSION) != VERSION or isinstance(data.get("version"), bool):  # (true == 1)
        c.fail("version", f"this planar reads version {VERSION} files, got {json.dumps(data['version'])}")
    name = data.get("name", "mechanism")
    if not (isinstance(name, str) and (name == "" or valid("name", name))):
        c.fail("name", f"must be a string of text, got {json.dumps(name)}")
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
        c.mapping(b, where, ("name", "line", "angle", "angle_rad", "offset", "offset_rad", *MASS_FIELDS))
        bname = c.field(b, "name", "name", where)
        line = c.field(b, "line", "pair", where, False)
        keys = [k for k in ("angle", "angle_rad", "offset", "offset_rad") if k in b]
        if len(keys) > 1 or (line and keys and keys[0].startswith("angle")):
            c.fail(where, f"give one of 'line', 'angle', 'offset' (or 'line' with 'offset'), got {keys + ['line'] * bool(line)}")
        if keys:
            v = c.field(b, keys[0], "number", where)
            given[bname] = (f"{where}.{keys[0]}", keys[0].split("_")[0],
                            float(v if keys[0].endswith("_rad") else units.angle_to_internal(v)))
        mass = {k: c.field(b, k, kind, where, req) for k, (kind, req) in MASS_FIELDS.items() if k in b or req} \
            if any(k in b for k in MASS_FIELDS) else {}
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
        if not (isinstance(bodies, list) and len(bodies) == 2 and all(valid("name", b) for b in bodies)):
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
        c.mapping(ld, where, LOAD_FIELDS)
        kwargs = {k: c.field(ld, k, kind, where, req) for k, (kind, req) in LOAD_FIELDS.items() if k in ld or req}
        _build(c, where, m.add_load, kwargs.pop("body"), **kwargs)

    sweep = None
    if "sweep" in data:
        s = data["sweep"]
        c.mapping(s, "sweep", SWEEP_FIELDS)
        got = {k: c.field(s, k, kind, "sweep", k in ("start", "stop")) for k, kind in SWEEP_FIELDS.items()}
        sweep = SweepSettings(
            start=_tuple(got["start"]), stop=_tuple(got["stop"]), num=got["num"] or NUM,
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
    _build(c, where, m.set_angle, body, value)


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
    if not isinstance(data, dict):
        raise FileFormatError(f"{source}: a mechanism document is a JSON object, got {type(data).__name__}")
    if not isinstance(unit, str):
        raise FileFormatError(f"{source}: a length unit is a name ('m', 'cm', 'mm' or 'in'), got {unit!r}")
    built = from_dict(data, source)  # (every field checked before the lengths are walked)
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
    lengths = [bool(d.length_rows[0]) for d in built.mechanism.sketch().drivers]
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


def loads(text, source="<string>", length_unit=None):
    """Read a mechanism document from JSON text: a :class:`MechanismFile` (its lengths in
    ``length_unit`` when given)."""
    if not isinstance(text, (str, bytes, bytearray)):
        raise FileFormatError(f"{source}: a mechanism document is JSON text, got {type(text).__name__}")
    try:
        data = json.loads(text, object_pairs_hook=_once)
    except _Twice as e:
        raise FileFormatError(f"{source}: the field {e.args[0]!r} is given twice in one object: give it once") from None
    except json.JSONDecodeError as e:
        raise FileFormatError(f"{source}: not valid JSON at line {e.lineno}, column {e.colno}: {e.msg}") from None
    except RecursionError:
        raise FileFormatError(f"{source}: lists or objects nested too deeply for a mechanism file "
                              f"(at most {MAX_DEPTH} levels)") from None
    except ValueError as e:  # (an integer of more digits than Python converts)
        raise FileFormatError(f"{source}: not a readable JSON number: {e}".split(";")[0]) from None
    return from_dict(data, source, length_unit)


class _Twice(Exception):
    """A JSON object that gives a field twice (json keeps the last without a word)."""


def _once(pairs):
    out = dict(pairs)
    if len(out) < len(pairs):
        seen = set()
        raise _Twice(next(k for k, _ in pairs if k in seen or seen.add(k)))
    return out


MAX_BYTES = 64 * 2**20  # a mechanism file's size: thousands of bodies take a few MiB
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


def _not_json(data):
    """(where, what) of the first value or field name in ``data`` that JSON cannot hold (a complex
    number, an array, an integer of more digits than Python writes), or None; ``data`` nests at
    most MAX_DEPTH levels."""
    try:
        json.dumps(data)  # (one pass in C for the usual document: the walk only finds the culprit)
        return None
    except (TypeError, ValueError):
        pass
    todo = [("", data)]
    while todo:
        where, v = todo.pop()
        if isinstance(v, dict):
            names = [k for k in v if not isinstance(k, str)]
            if names:
                return where or "file", f"the field name {shown(names[0])}"
            todo.extend((f"{where}.{k}" if where else k, x) for k, x in reversed(v.items()))
        elif isinstance(v, (list, tuple)):
            todo.extend((f"{where}[{i}]", x) for i, x in reversed(list(enumerate(v))))
        else:
            try:
                json.dumps(v)
            except (TypeError, ValueError):
                return where or "file", shown(v)
    return None


def load(path, length_unit=None):
    """Read a mechanism file: a :class:`MechanismFile` (``.mechanism``, ``.units``, ``.sweep``),
    its lengths restated in ``length_unit`` ("m", "cm", "mm" or "in") when given."""
    if not isinstance(path, (str, os.PathLike)):
        raise FileFormatError(f"a mechanism file is named by a path, got {path!r}")
    path = Path(path)
    if "\x00" in str(path):  # (no system names a file so)
        raise FileFormatError(f"{str(path)!r}: a file name cannot hold a NUL byte ('\\x00'); name the file without it")
    try:
        # (only a regular file of at most MAX_BYTES: a device or a pipe may never end)
        if path.exists() and not path.is_file():
            raise FileFormatError(f"{path}: not a regular file (a mechanism file is UTF-8 JSON)")
        if path.stat().st_size > MAX_BYTES:
            raise FileFormatError(f"{path}: {path.stat().st_size / 2**20:.0f} MiB, more than a mechanism file's "
                                  f"limit of {MAX_BYTES / 2**20:.0f} MiB")
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise FileFormatError(f"{path}: cannot read the file: {e.strerror or e}") from None
    except UnicodeDecodeError:
        raise FileFormatError(f"{path}: not a text file (a mechanism file is UTF-8 JSON)") from None
    return loads(text, str(path), length_unit)
