"""Units at the edges: planar computes in radians and seconds; files, the command line and plots
speak the units their user names.

Lengths are in whatever unit the user sketched in: ``length`` names it, and lengths convert
between "m", "cm", "mm" and "in" (:func:`convert_length`; any other label, or "" for none, only
labels them). Angles are "deg" or "rad"; angular rates "rad/s", "deg/s" or "rpm"; angular
accelerations are in deg/s^2 when rates are in deg/s, else in rad/s^2.

>>> u = Units(length="mm", angle="deg", rate="rpm")
>>> float(u.rate_to_internal(60.0))        # 60 rpm in rad/s
6.283185307179586
>>> float(u.angle_from_internal(3.141592653589793))
180.0
>>> parse_rate("120rpm"), parse_rate("2.5"), parse_rate("40mm/s")
((120.0, 'rpm'), (2.5, None), (40.0, 'mm/s'))
>>> float(convert_length(25.4, "mm", "in")), convert_length([1.5, 2.0], "m", "mm").tolist()
(1.0, [1500.0, 2000.0])
"""

import math
import re
from dataclasses import dataclass

import numpy as np

from planar.errors import InputError, shown

ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
RATE_UNITS = {"rad/s": 1.0, "deg/s": math.pi / 180.0, "rpm": 2.0 * math.pi / 60.0}
# lengths in micrometres: integers, so that a whole number of units converts exactly
LENGTH_UNITS = {"m": 1_000_000, "cm": 10_000, "mm": 1_000, "in": 25_400}
LENGTH_RATE_UNITS = {f"{u}/s": u for u in LENGTH_UNITS}


def convert_length(value, source, target):
    """Lengths ``value`` in ``source`` units restated in ``target`` units (each one of m, cm,
    mm, in; unchanged when both are the same label)."""
    if source == target:
        return value
    for unit in (source, target):
        if not isinstance(unit, str) or unit not in LENGTH_UNITS:
            raise InputError(f"cannot convert lengths from {source or 'no unit'!r} to {target or 'no unit'!r}: "
                             f"lengths convert between {', '.join(LENGTH_UNITS)}; name the length unit as one of them")
    return _converted(value, LENGTH_UNITS[source], LENGTH_UNITS[target], "lengths", source, target)


def _order(derivative):
    if isinstance(derivative, bool) or derivative not in (0, 1, 2):
        raise InputError(f"derivative must be 0 (values), 1 (rates) or 2 (accelerations), got {derivative!r}")
    return int(derivative)


def _converted(value, times, over, what, source, target):
    """``value`` times ``times`` over ``over`` (integers stay exact: whole micrometres): real
    numbers (bools, text and integers beyond any float refused), none beyond float64 after
    (an InputError naming ``what`` and the units)."""
    try:
        a = np.asarray(value)
    except (TypeError, ValueError, OverflowError):  # (ragged)
        a = np.asarray(None)
    if a.dtype.kind not in "iuf":
        raise InputError(f"{what} to convert must be real numbers, got {repr(value)[:40]}")
    if times == over == 1:  # (radians stay as given)
        return value
    if a.dtype.kind in "iu" and a.size and float(np.abs(a.astype(float)).max()) * times >= 2.0**62:
        a = a.astype(float)  # (the integers' product would wrap round: 1e13 m was -8.4e15 mm)
    with np.errstate(over="ignore"):
        out = np.multiply(a, times) / over
    if np.any(np.isinf(out) & np.isfinite(a)):
        raise InputError(f"{repr(value)[:40]} {source} is beyond float64 in {target}: give it in another unit")
    return out


def given(units):
    """``units`` where it is a :class:`Units`; ``Units()`` (degrees, rad/s, no length unit) for None."""
    if units is None:
        return Units()
    if not isinstance(units, Units):
        raise InputError(f"units must be a planar.units.Units, such as Units(length='mm', angle='deg'), got {units!r}")
    return units


def _check(unit, table, what):
    if not isinstance(unit, str) or unit not in table:
        raise InputError(f"unknown {what} unit {shown(unit)}: use one of {', '.join(table)}")
    return unit


@dataclass(frozen=True)
class Units:
    """The units a user reads and writes: ``length`` (a label: "mm", "cm", "in", or "" for
    none), ``angle`` ("deg" or "rad") and ``rate`` ("rad/s", "deg/s" or "rpm")."""

    length: str = ""
    angle: str = "deg"
    rate: str = "rad/s"

    def __init__(self, length="", angle="deg", rate="rad/s", **unknown):
        # (the dataclass keeps this constructor: an unknown keyword is the user's InputError)
        if unknown:
            raise InputError(f"Units takes length, angle and rate, got {', '.join(map(repr, unknown))}: "
                             f"such as Units(length='mm', angle='deg', rate='rpm')")
        for name, value in (("length", length), ("angle", angle), ("rate", rate)):
            object.__setattr__(self, name, value)
        self.__post_init__()

    def __post_init__(self):
        # (printable: a lone surrogate cannot be written out, a NUL not drawn)
        if (not isinstance(self.length, str) or len(self.length) > 16 or not self.length.isprintable()
                or not re.fullmatch(r"[^\s\[\]]*", self.length)):
            raise InputError(f"length unit must be a short label without spaces, like 'mm', got {shown(self.length)}")
        _check(self.angle, ANGLE_UNITS, "angle")
        _check(self.rate, RATE_UNITS, "rate")

    # ---- conversions (internal = radians, rad/s, rad/s^2) ----------------------------------

    def angle_to_internal(self, value):
        return _converted(value, ANGLE_UNITS[self.angle], 1, "angles", self.angle, "rad")

    def angle_from_internal(self, value):
        return _converted(value, 1, ANGLE_UNITS[self.angle], "angles", "rad", self.angle)

    def rate_to_internal(self, value):
        return _converted(value, RATE_UNITS[self.rate], 1, "rates", self.rate, "rad/s")

    def rate_from_internal(self, value):
        return _converted(value, 1, RATE_UNITS[self.rate], "rates", "rad/s", self.rate)

    @property
    def acceleration(self):
        """Unit of angular accelerations: deg/s^2 with rates in deg/s, else rad/s^2."""
        return "deg/s^2" if self.rate == "deg/s" else "rad/s^2"

    def acceleration_to_internal(self, value):
        return _converted(value, RATE_UNITS[self.rate] if self.rate == "deg/s" else 1, 1, "accelerations",
                          self.acceleration, "rad/s^2")

    def acceleration_from_internal(self, value):
        return _converted(value, 1, RATE_UNITS[self.rate] if self.rate == "deg/s" else 1, "accelerations",
                          "rad/s^2", self.acceleration)

    # ---- an input that is an angle or a length ---------------------------------------------

    def input_to_internal(self, value, is_length, derivative=0):
        """Input value (``derivative`` 0), rate (1) or acceleration (2) to internal units;
        lengths pass through."""
        if is_length:
            return value
        return (self.angle_to_internal, self.rate_to_internal, self.acceleration_to_internal)[_order(derivative)](value)

    def input_from_internal(self, value, is_length, derivative=0):
        if is_length:
            return value
        return (self.angle_from_internal, self.rate_from_internal,
                self.acceleration_from_internal)[_order(derivative)](value)

    # ---- labels ----------------------------------------------------------------------------

    def label(self, kind):
        """Unit label of a quantity kind: "length", "speed", "accel" (of points), "angle",
        "rate", "angular_accel", and "mass", "inertia", "force", "moment" (masses are taken in
        kg and times in s: N and N m with lengths in m or unlabelled).

        >>> Units("m").label("moment"), Units("mm").label("force"), Units("mm").label("inertia")
        ('N m', 'kg mm/s^2', 'kg mm^2')
        """
        L = self.length or "length"
        si = self.length in ("", "m")
        return {
            "length": self.length,
            "speed": f"{L}/s",
            "accel": f"{L}/s^2",
            "angle": self.angle,
            "rate": self.rate,
            "angular_accel": self.acceleration,
            "mass": "kg",
            "inertia": "kg m^2" if si else f"kg {L}^2",
            "force": "N" if si else f"kg {L}/s^2",
            "moment": "N m" if si else f"kg {L}^2/s^2",
        }[kind]

    def input_label(self, is_length, derivative=0):
        if is_length:
            return self.label(("length", "speed", "accel")[derivative])
        return self.label(("angle", "rate", "angular_accel")[derivative])


def parse_rate(text):
    """Split "120rpm", "2 rad/s", "90deg/s", "40mm/s" (a sliding input's speed) or "3" into
    (value, unit or None)."""
    units = "|".join(re.escape(u) for u in [*RATE_UNITS, *LENGTH_RATE_UNITS])
    m = re.fullmatch(rf"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*({units})?\s*", str(text))
    if not m or not math.isfinite(float(m.group(1))):
        raise InputError(f"cannot read the speed {text!r}: give a finite number with an optional unit, "
                         f"like 120rpm, 2rad/s, 90deg/s or, for a sliding input, 40mm/s")
    return float(m.group(1)), m.group(2)
