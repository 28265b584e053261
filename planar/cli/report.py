"""What ``planar info`` and ``planar run`` print: the mechanism, its mobility and Grashof class,
motion ranges, strokes, the sweep's statuses and events, masses and forces."""

import math

import numpy as np

from planar.analysis import four_bar_links, grashof, mobility, motion_range, output, outputs, stroke, swept_ranges
from planar.errors import PlanarError
from planar.results import POSED, Status

TURN_SAMPLES = 180  # sweep steps over a turn for the strokes and the motion range (every 2 degrees)
MOTIONLESS = 1e-9  # an output whose range is this small (relative to the mechanism's size, or radians) stays put


def fmt(v):
    return f"{float(v):.6g}"


def length_text(v, units):
    return f"{fmt(v)} {units.length}".rstrip()


def summary(res, units, settings, circuit=False):
    """Lines describing a sweep (or a ``circuit``): statuses, motion ranges met, output
    ranges, events."""
    from planar.draw import input_axis

    model = res.model
    x, xlabel = input_axis(res, units)
    counts = {Status(s).name.lower().replace("_", " "): int(c) for s, c in zip(*np.unique(res.status, return_counts=True))}
    turns = sum(e.kind == "limit" for e in res.events)
    head = (f"circuit: {xlabel} from {fmt(x[0])} to {fmt(x[-1])} turning back at {turns} limit(s)" if circuit else
            f"sweep: {xlabel} from {fmt(settings.start[0])} to {fmt(settings.stop[0])}")
    lines = [f"{head}, {len(res)} values" + (", there and back" if settings.rocking else "") + ": "
             + ", ".join(f"{c} {n}" for n, c in counts.items())]
    is_len = bool(model.input_lengths[0])
    if not POSED[np.asarray(res.status)].all():
        spans = "; ".join(f"{fmt(units.input_from_internal(a, is_len))} to {fmt(units.input_from_internal(b, is_len))}"
                          for a, b in swept_ranges(res))
        lines.append(f"assembles over {spans} ({xlabel}) on the sketched branch")
    for b in model.body_names[1:]:
        a = units.angle_from_internal(res.angle(b))
        w = units.rate_from_internal(res.omega(b))
        if np.any(np.isfinite(a)):
            lines.append(f"  {b}: angle {fmt(np.nanmin(a))} to {fmt(np.nanmax(a))} {units.angle}, "
                         f"largest |rate| {fmt(np.nanmax(np.abs(w)) if np.any(np.isfinite(w)) else math.nan)} {units.rate}")
    for j in outputs.names_of(model, "length coordinate"):
        t = res.coordinate(j)
        if np.any(np.isfinite(t)):
            lines.append(f"  {j}: travel {length_text(np.nanmin(t), units)} to {length_text(np.nanmax(t), units)}")
    if res.events:
        name, unit = model.input_names[0], units.input_label(bool(model.input_lengths[0]))
        lines.append("events:")
        for e in res.events:
            at = units.input_from_internal(np.ravel(e.input)[0], bool(model.input_lengths[0]))
            lines.append(f"  {e.kind.replace('_', '-')} position at {name} = {fmt(at)} {unit}".rstrip()
                         + (f": {e.note}" if e.note else ""))
    else:
        lines.append("events: no limit or singular position met")
    return lines


def mass_lines(model, units):
    """The bodies' mass properties, the gravity and the number of loads (nothing when none)."""
    lines = [f"  {b}: mass {fmt(model.mass[i])} {units.label('mass')}, inertia {fmt(model.inertia[i])} "
             f"{units.label('inertia')} about its centre of mass" for i, b in enumerate(model.body_names) if model.mass[i]]
    if model.gravity.any():
        lines.append(f"  gravity ({fmt(model.gravity[0])}, {fmt(model.gravity[1])}) {units.label('accel')}")
    if model.loads:
        lines.append(f"  {len(model.loads)} external load(s)")
    return ["mass properties and loads:"] + lines if lines else ["mass properties and loads: none (all bodies massless)"]


def force_lines(forces, units):
    """The range of each driver's effort and the largest force on each joint."""
    model = forces.sweep.model
    lines = ["forces:"]
    for d, ln in zip(model.input_names, model.input_lengths):
        e = forces.driver_effort(d)
        if np.any(np.isfinite(e)):
            unit = units.label("force" if ln else "moment")
            lines.append(f"  effort of {d}: {fmt(np.nanmin(e))} to {fmt(np.nanmax(e))} {unit}")
    for j in forces.reactions:
        size = np.hypot(*forces.reaction(j).T)
        if np.any(np.isfinite(size)):
            lines.append(f"  {j}: largest reaction force {fmt(np.nanmax(size))} {units.label('force')}")
    return lines


def _grashof_line(model):
    found = four_bar_links(model)
    if found is None:
        return "Grashof class: does not apply (not a single loop of four revolutes)"
    (r1, r2, r3, r4), role = found
    g = grashof(r1, r2, r3, r4, driver=role or "crank")
    turns = f"; the input {'turns fully' if g.input_turns else 'cannot turn fully'}" if role else ""
    return (f"Grashof class: {g.kind} (links {fmt(r1)}, {fmt(r2)}, {fmt(r3)}, {fmt(r4)}: "
            f"s + l - p - q = {fmt(g.excess)}){turns}")


def stroke_lines(model, units):
    """Stroke and time ratio of every slider and every link that goes back and forth while the
    one input angle turns (nothing when the input does not turn fully)."""
    if len(model.drivers) != 1 or model.input_lengths[0]:
        return []
    turn = model.sweep(model.u0[0] + np.linspace(0.0, 2 * math.pi, TURN_SAMPLES + 1))
    if not turn.ok.all():
        return []
    lines = []
    for spec in outputs.specs(model, ("travel", "angle")):
        kind, name = spec.split(":", 1)
        values = output(turn, spec)
        if np.ptp(values) <= MOTIONLESS * (model.L if kind == "travel" else 1.0):
            continue  # it does not move: no stroke
        try:
            s = stroke(turn, spec)
        except PlanarError:
            continue  # it turns with the input rather than going back and forth
        size = length_text(s.stroke, units) if kind == "travel" else f"{fmt(units.angle_from_internal(s.stroke))} {units.angle}"
        lines.append(f"  {name}: stroke {size}, time ratio {s.time_ratio:.6f}")
    return ["strokes over one turn of the input:"] + lines if lines else []


def range_lines(model, units):
    """The motion range of a one-input mechanism on its sketched branch, ends located by the
    solver (planar.analysis.motion_range)."""
    if len(model.drivers) != 1:
        return []
    ranges = motion_range(model, samples=TURN_SAMPLES)
    name, is_len = model.input_names[0], bool(model.input_lengths[0])
    unit = units.input_label(is_len)
    if not is_len and len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 2 * math.pi:
        return [f"motion range of {name}: a full turn"]
    shown = "; ".join(f"{fmt(units.input_from_internal(lo, is_len))} to {fmt(units.input_from_internal(hi, is_len))}"
                      for lo, hi in ranges)
    return [f"motion range of {name}: {shown} {unit}".rstrip()]


def info_lines(doc, path):
    model = doc.mechanism.compile()
    kinds = {}
    for j in model.joints:
        kind = type(j).__name__.lower()
        kinds[kind] = kinds.get(kind, 0) + 1
    inputs = ", ".join(f"{n} ({'length' if ln else 'angle'})" for n, ln in zip(model.input_names, model.input_lengths))
    lines = [f"file: {path}",
             f"mechanism: {model.name}: {len(model.body_names) - 1} moving bodies, {len(model.joints)} joints ("
             + ", ".join(f"{c} {k}" for k, c in kinds.items()) + f"), {len(model.drivers)} input(s): {inputs or 'none'}",
             f"mobility: {mobility(model)}",
             _grashof_line(model)]
    return model, lines
