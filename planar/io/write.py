"""Writing mechanism files: a :class:`planar.Mechanism` (or a loaded file) to its document and
to JSON text, one line per body, point, joint or driver; never a file that cannot be read back."""

import errno
import inspect
import json
import math
import os
from pathlib import Path

from planar.errors import FileFormatError, WriteError
from planar.io.document import MechanismFile, SweepSettings
from planar.io.read import from_dict
from planar.io.schema import VERSION
from planar.joints import FILE_TYPES
from planar.joints.base import xy
from planar.model import GROUND, Mechanism
from planar.units import given


def _angle_entry(key, angle, units):
    """{key: angle in the file's unit}, or {key_rad: radians} where that unit would not give
    back the same radians."""
    shown = float(units.angle_from_internal(angle))
    return {key: shown} if float(units.angle_to_internal(shown)) == angle else {f"{key}_rad": angle}


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
    if sweep is not None and not isinstance(sweep, (dict, SweepSettings)):
        raise FileFormatError(f"sweep must be a SweepSettings or a dict of sweep fields, got {sweep!r}")
    units = given(units)
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


def save(obj, path, units=None, sweep=None):
    """Write a mechanism (or a loaded :class:`MechanismFile`) to ``path`` as JSON; returns the path."""
    if not isinstance(path, (str, os.PathLike)):
        raise FileFormatError(f"a mechanism file is named by a path, got {path!r}")
    path = Path(path)
    if "\x00" in str(path):  # (no system names a file so)
        raise WriteError(errno.EINVAL, "a file name cannot hold a NUL byte ('\\x00'); name the file without it",
                         str(path))
    text = dumps(obj, units, sweep)
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as e:
        raise WriteError(e.errno, e.strerror or str(e), str(path)) from None
    return path
