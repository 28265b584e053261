"""A file's sweep settings with the command line's overrides, checked before any work, and the
sweep (or circuit) they ask for."""

import math
from dataclasses import replace

from planar.cli.main import DEFAULT_NUM, MAX_ROWS, UsageError
from planar.errors import FileFormatError, InputError, PlanarError
from planar.units import LENGTH_RATE_UNITS, RATE_UNITS, Units, convert_length, parse_rate


def default_sweep(model, units):
    """Sweep settings when a file has none: from the sketch, one turn of an angle input
    (73 values, every 5 deg) or half the mechanism's size either way for a length input."""
    from planar.io import SweepSettings

    start, stop = [], []
    for u0, is_len in zip(model.u0, model.input_lengths):
        if is_len:
            start.append(float(u0 - 0.25 * model.L))
            stop.append(float(u0 + 0.25 * model.L))
        else:
            a = float(units.angle_from_internal(u0))
            start.append(a)
            stop.append(a + float(units.angle_from_internal(2 * math.pi)))
    return SweepSettings(start=tuple(start), stop=tuple(stop), num=DEFAULT_NUM)


def file_settings(doc, args):
    """Units and sweep settings of a file with the command line's overrides."""
    speed = getattr(args, "speed", None)
    speed_unit = _parse_speed(speed)[1] if speed is not None else None
    # outputs' rates: in --rate-unit, else in the unit --speed names, else in the file's
    rate = getattr(args, "rate_unit", None) or (speed_unit if speed_unit in RATE_UNITS else doc.units.rate)
    units = replace(doc.units, angle=getattr(args, "angle_unit", None) or doc.units.angle, rate=rate)
    model = doc.mechanism.compile()
    sweep = doc.sweep or default_sweep(model, doc.units)
    if units != doc.units:  # the file's numbers are in its own units: restate them
        sweep = _restate(sweep, model, doc.units, units)
    changes = {}
    for key in ("start", "stop", "acceleration"):
        v = getattr(args, key, None)
        if v is not None:
            changes[key] = tuple(v)
    if getattr(args, "num", None) is not None:
        if args.num < 2:
            raise UsageError(f"--num must be at least 2, got {args.num}")
        changes["num"] = args.num
    if speed is not None:
        changes["speed"] = _speed(speed, model, units)
    if getattr(args, "rocking", False):
        changes["rocking"] = True
    if getattr(args, "circuit", False):
        changes["rocking"] = False  # the circuit reverses by itself, at the limits
    return model, units, replace(sweep, **changes)


def _restate_inputs(values, model, old, new, d):
    """Input values (``d`` 0), rates (1) or accelerations (2) of each input in ``old`` units
    restated in ``new`` units."""
    out = []
    for k, v in enumerate(values):
        is_len = bool(model.input_lengths[min(k, len(model.input_lengths) - 1)])
        out.append(float(new.input_from_internal(old.input_to_internal(v, is_len, d), is_len, d)))
    return tuple(out)


def _restate(sweep, model, old, new):
    return replace(sweep, **{key: _restate_inputs(getattr(sweep, key), model, old, new, d)
                             for key, d in (("start", 0), ("stop", 0), ("speed", 1), ("acceleration", 2))})


def _parse_speed(text):
    try:
        return parse_rate(text)
    except InputError as e:
        raise UsageError(f"--speed: {e}") from None


def _speed(text, model, units):
    """``--speed``: one speed for every input, in ``units`` (the run's) when it names no unit of
    its own, else converted from its unit (an angular rate for angle inputs, length/s for
    sliding and point inputs)."""
    value, unit = _parse_speed(text)
    if unit is None:
        return (value,)
    out = []
    for name, is_len in zip(model.input_names, model.input_lengths):
        if bool(is_len) != (unit in LENGTH_RATE_UNITS):
            want = "a length per second, like 40mm/s" if is_len else "an angular rate, like 120rpm or 10rad/s"
            raise UsageError(f"--speed {text}: input {name!r} is {'a length' if is_len else 'an angle'}: give {want}")
        if is_len:
            out.append(float(convert_length(value, LENGTH_RATE_UNITS[unit], units.length)))
        else:
            out.append(float(units.rate_from_internal(Units(rate=unit).rate_to_internal(value))))
    return tuple(out)


def sweep_values(model, units, settings, source, args=None):
    """The settings' input values and rates, checked before any work: a sweep too long, too far
    or with the wrong number of values is blamed on the command line's sweep options when it
    gave some (:class:`UsageError`), else on the file."""
    from planar import arguments
    from planar.sweep import run_sweep as walk

    try:
        if settings.num * (2 if settings.rocking else 1) > MAX_ROWS:
            raise InputError(f"{settings.num} sweep values: a run writes at most {MAX_ROWS:,} rows; "
                             f"sweep fewer values (or call Model.sweep from Python)")
        U, Ud, Udd = settings.values(model, units)
        arguments.values(model, U, arguments.sweep_options({}, walk)["max_step"])
        arguments.rates(model, Ud, Udd)
    except PlanarError as e:
        given = [f"--{k}" for k in ("start", "stop", "num", "speed", "acceleration") if getattr(args, k, None) is not None]
        if given:
            raise UsageError(f"{', '.join(given)}: {e}") from None
        raise FileFormatError(f"{source}: {e}") from None
    return U, Ud, Udd


def sweep_or_circuit(model, units, settings, circuit=False, engine="numpy", values=None):
    """The sweep the settings ask for (on ``engine``), over ``values`` (U, Ud, Udd) when given;
    with ``circuit``, the whole circuit through the sketch instead (``num`` values, the
    settings' speed and acceleration along the motion)."""
    U, Ud, Udd = values or settings.values(model, units)
    if circuit:
        return model.circuit(samples=settings.num, velocity=abs(float(Ud[0, 0])), acceleration=float(Udd[0, 0]))
    return model.sweep(U, velocity=Ud, acceleration=Udd, engine=engine)
