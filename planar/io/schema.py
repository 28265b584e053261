"""The schema of mechanism files: the kinds of field, the fields of each part of a document
(a joint type's own come from its class: :data:`planar.joints.FILE_TYPES`), and the checker
that names the field at fault."""

import json

from planar.arguments import finite_number
from planar.errors import FileFormatError

VERSION = 1

KINDS = {
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

MASS_FIELDS = {"mass": ("number", True), "com": ("point", True), "inertia": ("number", False)}
LOAD_FIELDS = {"body": ("name", True), "force": ("point", False), "at": ("point", False), "torque": ("number", False),
         "fixed": ("fixed", False)}
TOP_FIELDS = {"version", "name", "units", "bodies", "points", "joints", "drivers", "dimensions", "sweep", "gravity", "loads"}
SWEEP_FIELDS = {"start": "numbers", "stop": "numbers", "num": "count", "speed": "numbers",
          "acceleration": "numbers", "rocking": "bool"}


is_number = finite_number


def _utf8(s):
    try:
        s.encode("utf-8")
        return True
    except UnicodeEncodeError:
        return False


def valid(kind, v):
    if kind == "name":  # (a lone surrogate is no text: it cannot be written out)
        return isinstance(v, str) and v != "" and _utf8(v)
    if kind in ("point", "vector"):
        ok = isinstance(v, list) and len(v) == 2 and all(is_number(x) for x in v)
        return ok and (kind == "point" or any(x != 0 for x in v))
    if kind == "positive":
        return is_number(v) and v > 0
    if kind == "number":
        return is_number(v)
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
        return isinstance(v, list) and len(v) == 2 and all(valid("name", x) for x in v) and v[0] != v[1]
    if kind == "numbers":
        return is_number(v) or (isinstance(v, list) and len(v) > 0 and all(is_number(x) for x in v))
    raise AssertionError(kind)


class Checker:
    """Field-by-field validation that names the field at fault (``joints[2].radius_a``)."""

    def __init__(self, source):
        self.source = source

    def fail(self, where, what):
        raise FileFormatError(f"{self.source}: {where}: {what}")

    def field(self, obj, key, kind, where, required=True):
        if key not in obj:
            if required:
                self.fail(where, f"missing field {key!r} ({KINDS[kind]})")
            return None
        if not valid(kind, obj[key]):
            self.fail(f"{where}.{key}", f"must be {KINDS[kind]}, got {json.dumps(obj[key])}")
        return obj[key]

    def mapping(self, obj, where, known):
        if not isinstance(obj, dict):
            self.fail(where, f"must be a JSON object {{...}}, got {json.dumps(obj)[:60]}")
        unknown = sorted(set(obj) - set(known), key=str)  # (a dict's keys may be other than text)
        if unknown:
            self.fail(where, f"unknown field {unknown[0]!r}: the fields here are {', '.join(sorted(known))}")

    def items(self, obj, key, where):
        v = obj.get(key, [])
        if not isinstance(v, list):
            self.fail(f"{where}{key}", f"must be a list [...], got {json.dumps(v)[:60]}")
        return v
