"""Named scalar outputs of a sweep, written ``"kind:name"``: the one way planar names an output,
in tables, plots, the command line and the analyses.

:data:`OUTPUTS` lists the kinds: a body's ``angle``, ``omega``, ``alpha``; a revolute's
relative ``joint_angle``, ``joint_omega``, ``joint_alpha``; a slider's or slot's ``travel``,
``travel_rate``, ``travel_accel``; a point's ``x``, ``y``, ``vx``, ``vy``, ``ax``, ``ay``,
``speed``, ``accel``.

>>> import numpy as np
>>> from planar.mechanisms import slider_crank
>>> res = slider_crank(2, 5, offset=1).sweep([0.0, np.pi / 2])
>>> output(res, "x:B").round(6).tolist(), output(res, "travel:slide", 1).round(6).tolist()
([6.898979, 4.898979], [0.408248, -2.0])
>>> output_values(res, "angle:crank").round(6).tolist()   # display units: degrees by default
[0.0, 90.0]
"""

from dataclasses import dataclass

import numpy as np

from planar.errors import InputError
from planar.results import as_sweep, is_derivative
from planar.units import given


@dataclass(frozen=True)
class Output:
    """One kind of output: its panel ``title``, the quantity kind of its ``unit`` (as
    :meth:`planar.units.Units.label` names it), what its name names (``of``: "body", "angle
    coordinate", "length coordinate" or "point"), ``get(res, name)`` its (N,) values in
    internal units, and ``rate`` the kind of its time derivative (None when it has none)."""

    title: str
    unit: str
    of: str
    get: object
    rate: str | None = None


def _point(what, axis):
    return lambda r, n: getattr(r, what)(n)[:, axis]


OUTPUTS = {
    "angle": Output("angle", "angle", "body", lambda r, n: r.angle(n), "omega"),
    "omega": Output("angular velocity", "rate", "body", lambda r, n: r.omega(n), "alpha"),
    "alpha": Output("angular acceleration", "angular_accel", "body", lambda r, n: r.alpha(n)),
    "joint_angle": Output("joint angle", "angle", "angle coordinate", lambda r, n: r.coordinate(n, 0), "joint_omega"),
    "joint_omega": Output("joint angular velocity", "rate", "angle coordinate", lambda r, n: r.coordinate(n, 1),
                          "joint_alpha"),
    "joint_alpha": Output("joint angular acceleration", "angular_accel", "angle coordinate",
                          lambda r, n: r.coordinate(n, 2)),
    "travel": Output("slider travel", "length", "length coordinate", lambda r, n: r.coordinate(n, 0), "travel_rate"),
    "travel_rate": Output("slider velocity", "speed", "length coordinate", lambda r, n: r.coordinate(n, 1),
                          "travel_accel"),
    "travel_accel": Output("slider acceleration", "accel", "length coordinate", lambda r, n: r.coordinate(n, 2)),
    "x": Output("point x", "length", "point", _point("position", 0), "vx"),
    "y": Output("point y", "length", "point", _point("position", 1), "vy"),
    "vx": Output("point velocity x", "speed", "point", _point("velocity", 0), "ax"),
    "vy": Output("point velocity y", "speed", "point", _point("velocity", 1), "ay"),
    "ax": Output("point acceleration x", "accel", "point", _point("acceleration", 0)),
    "ay": Output("point acceleration y", "accel", "point", _point("acceleration", 1)),
    "speed": Output("point speed", "speed", "point", lambda r, n: np.hypot(*r.velocity(n).T)),
    "accel": Output("point acceleration", "accel", "point", lambda r, n: np.hypot(*r.acceleration(n).T)),
}


def names_of(model, of):
    """The names an output kind's ``of`` ("body", "angle coordinate", "length coordinate",
    "point") takes in ``model``: moving bodies, joints with such a coordinate, points."""
    if of == "body":
        return list(model.body_names[1:])
    if of == "point":
        return list(model.points)
    length = of == "length coordinate"
    return [j for j in model.coordinates if bool(model.joint(j).coordinate().length_rows[0]) == length]


def specs(model, kinds, names=None):
    """Every ``"kind:name"`` of ``kinds`` that ``model`` has (or of the given ``names`` only),
    kind by kind and name by name in the model's order."""
    out, wanted = [], None if names is None else set(names)
    for kind in kinds:
        have = names_of(model, OUTPUTS[kind].of)
        out += [f"{kind}:{n}" for n in have if wanted is None or n in wanted]
    return out


def parse(model, spec):
    """(kind, name) of the output ``spec``, checked against ``model``; an error names the fix."""
    text = str(spec)
    kind, sep, name = text.partition(":")
    if not sep:
        raise InputError(f"unknown output {text!r}: outputs are written kind:name, {_hint(model, text)}")
    if kind not in OUTPUTS:
        raise InputError(f"unknown output {text!r}: write kind:name with kind one of {', '.join(OUTPUTS)}")
    of = OUTPUTS[kind].of
    # (a point looked up by name: a file may name thousands)
    if not (name in model.points if of == "point" else name in names_of(model, of)):
        have = names_of(model, of)
        raise InputError(f"unknown output {text!r}: {kind} is an output of a {of}, and {model.name!r} has "
                         f"{', '.join(repr(n) for n in have) or 'none'}")
    return kind, name


def _hint(model, text):
    """The kind:name spelling of an unprefixed name (a body, a joint, or "P.x")."""
    point, _, axis = text.rpartition(".")
    if axis in ("x", "y") and point in model.points:
        return f"here {axis}:{point}"
    if text in model.body_names:
        return f"here angle:{text}"
    if text in model.coordinates:
        kind = "travel" if model.joint(text).coordinate().length_rows[0] else "joint_angle"
        return f"here {kind}:{text}"
    return f"kind one of {', '.join(OUTPUTS)}"


def output(res, spec, derivative=0):
    """(N,) values of the output ``spec`` ("kind:name", see :data:`OUTPUTS`) over the sweep
    ``res`` in internal units (radians, rad/s, rad/s^2, lengths), or of its first or second time
    derivative (``derivative`` 1 or 2: ``output(res, "x:B", 1)`` is ``vx:B``).

    With the sweep's default unit input rate and zero input acceleration the derivatives are
    the first and second kinematic coefficients d(output)/du and d2(output)/du2.
    """
    res = as_sweep(res, "output")
    if not is_derivative(derivative):
        raise InputError(f"derivative must be 0, 1 or 2, got {derivative!r}")
    kind, name = parse(res.model, spec)
    for _ in range(derivative):
        if OUTPUTS[kind].rate is None:
            raise InputError(f"output {spec!r} has no derivative {derivative}: "
                             f"{', '.join(k for k, o in OUTPUTS.items() if o.rate)} have one")
        kind = OUTPUTS[kind].rate
    return np.asarray(OUTPUTS[kind].get(res, name), float)


def to_display(values, unit, units):
    """Values of a quantity kind ``unit`` (:attr:`Output.unit`) from internal units to ``units``
    (angles and angular rates convert; lengths are the user's own)."""
    convert = {"angle": units.angle_from_internal, "rate": units.rate_from_internal,
               "angular_accel": units.acceleration_from_internal}.get(unit)
    return np.asarray(values if convert is None else convert(values), float)


def output_values(res, spec, units=None):
    """(N,) values of the output ``spec`` in ``units`` (default :class:`planar.units.Units`:
    degrees, rad/s)."""
    kind, _ = parse(res.model, spec)
    return to_display(output(res, spec), OUTPUTS[kind].unit, given(units))


def label(spec, units):
    """The unit label of output ``spec`` in ``units`` ("" for none)."""
    return units.label(OUTPUTS[str(spec).partition(":")[0]].unit)
