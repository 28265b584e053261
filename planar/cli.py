"""The ``planar`` command line: run mechanism files, inspect them, write catalogue examples.

    planar demo [--out DIR]            a four-bar with a coupler point: summary, plots, animation, CSV
    planar run FILE [options]          sweep a mechanism file; write tables, plots and an animation
    planar info FILE                   mobility, redundancy, Grashof class, motion ranges, events
    planar example NAME [-o FILE]      write a catalogue mechanism to a file (no NAME: list them)
    planar synth path|motion|function CSV  design a four-bar for target points, positions or y = f(x)

Exit codes: 0 done; 1 the mechanism, file or sweep is wrong (the message says which field or
joint and what to do); 2 the command line is wrong; 3 an output could not be written.
"""

import argparse
import csv
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

from planar.analysis import four_bar_links, grashof, mobility, motion_range, output, outputs, stroke, swept_ranges
from planar.errors import FileFormatError, IndeterminateWarning, InputError, PlanarError
from planar.progress import Progress
from planar.results import POSED, Status
from planar.units import LENGTH_RATE_UNITS, LENGTH_UNITS, RATE_UNITS, Units, convert_length, parse_rate

EXIT_OK, EXIT_INPUT, EXIT_USAGE, EXIT_OUTPUT = 0, 1, 2, 3
MAX_ROWS = 10_000_000  # table rows a run writes: beyond, the CSV alone takes many minutes and gigabytes
MAX_FRAMES, DPI, FPS = 2000, (20, 1200), (1, 100)


class UsageError(InputError):
    """The command line is wrong (exit code 2): the message names the option and the fix."""


# ---- tables ----------------------------------------------------------------------------------


def table(res, units):
    """Columns of a sweep as [(name, unit, values (N,))]: inputs, status, every body's angle,
    rate and acceleration, every slider's or slot's travel and rates, every named point's
    position, velocity and acceleration."""
    model = res.model
    cols = []
    for k, (name, is_len) in enumerate(zip(model.input_names, model.input_lengths)):
        x = units.input_from_internal(np.asarray(res.inputs[:, k]), bool(is_len))
        cols.append((f"input:{name}", units.input_label(bool(is_len)), np.asarray(x, float)))
    cols.append(("status", "", np.array([Status(s).name for s in res.status])))
    moving = [p for p, (b, _) in model.points.items() if b != 0]
    columns = [s for b in model.body_names[1:] for s in outputs.specs(model, ("angle", "omega", "alpha"), [b])]
    columns += [s for j in model.coordinates
                for s in outputs.specs(model, ("travel", "travel_rate", "travel_accel"), [j])]
    columns += [s for p in moving for s in outputs.specs(model, ("x", "y", "vx", "vy", "ax", "ay"), [p])]
    for spec in columns:
        cols.append((spec, outputs.label(spec, units), outputs.output_values(res, spec, units)))
    return cols


def force_table(forces, units):
    """Columns of a sweep's kinetostatics: each driver's effort, each joint's reaction on its
    second body from its first (x, y, and the components it carries), the shaking force and
    moment (about the origin)."""
    model = forces.sweep.model
    F, M = units.label("force"), units.label("moment")
    cols = [(f"effort:{d}", F if ln else M, forces.driver_effort(d)) for d, ln in zip(model.input_names, model.input_lengths)]
    for j, comps in forces.reactions.items():
        cols += [(f"Fx:{j}", F, comps["force"][:, 0]), (f"Fy:{j}", F, comps["force"][:, 1])]
        cols += [(f"{c}:{j}", M if c == "moment" else F, v) for c, v in comps.items() if c != "force"]
    S = forces.shaking_force()
    return cols + [("shaking:Fx", F, S[:, 0]), ("shaking:Fy", F, S[:, 1]), ("shaking:moment", M, forces.shaking_moment())]


def _header(name, unit):
    return f"{name} [{unit}]" if unit else name


def csv_rows(cols):
    """The header, then one row per sweep value: unsolved values empty."""
    yield [_header(n, u) for n, u, _ in cols]
    for row in zip(*(v for _, _, v in cols)):
        yield [v if isinstance(v, str) else ("" if not math.isfinite(v) else repr(float(v))) for v in row]


def write_csv(cols, path):
    progress, N = Progress(f"writing {Path(path).name}: rows"), len(cols[0][2]) if cols else 0
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        for i, row in enumerate(csv_rows(cols)):
            w.writerow(row)
            if i and (i % 4096 == 0 or i == N):
                progress(i, N)


def write_json(cols, path, name):
    def clean(v):
        return v if isinstance(v, str) else (float(v) if math.isfinite(v) else None)

    data = {"mechanism": name, "units": {n: u for n, u, _ in cols if u},
            "columns": {n: [clean(x) for x in v] for n, _, v in cols}}
    Path(path).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")


# ---- sweeps ----------------------------------------------------------------------------------


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
    return SweepSettings(start=tuple(start), stop=tuple(stop), num=73)


def _settings(doc, args):
    """Units and sweep settings of a file with the command line's overrides."""
    from dataclasses import replace

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
    from dataclasses import replace

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


def run_sweep(model, units, settings, circuit=False, engine="numpy", values=None):
    """The sweep the settings ask for (on ``engine``), over ``values`` (U, Ud, Udd) when given;
    with ``circuit``, the whole circuit through the sketch instead (``num`` values, the
    settings' speed and acceleration along the motion)."""
    U, Ud, Udd = values or settings.values(model, units)
    if circuit:
        return model.circuit(samples=settings.num, velocity=abs(float(Ud[0, 0])), acceleration=float(Udd[0, 0]))
    return model.sweep(U, velocity=Ud, acceleration=Udd, engine=engine)


# ---- reports ---------------------------------------------------------------------------------


def _fmt(v):
    return f"{float(v):.6g}"


def _length(v, units):
    return f"{_fmt(v)} {units.length}".rstrip()


def summary(res, units, settings, circuit=False):
    """Lines describing a sweep (or a ``circuit``): statuses, motion ranges met, output
    ranges, events."""
    from planar.draw import input_axis

    model = res.model
    x, xlabel = input_axis(res, units)
    counts = {Status(s).name.lower().replace("_", " "): int(c) for s, c in zip(*np.unique(res.status, return_counts=True))}
    turns = sum(e.kind == "limit" for e in res.events)
    head = (f"circuit: {xlabel} from {_fmt(x[0])} to {_fmt(x[-1])} turning back at {turns} limit(s)" if circuit else
            f"sweep: {xlabel} from {_fmt(settings.start[0])} to {_fmt(settings.stop[0])}")
    lines = [f"{head}, {len(res)} values" + (", there and back" if settings.rocking else "") + ": "
             + ", ".join(f"{c} {n}" for n, c in counts.items())]
    is_len = bool(model.input_lengths[0])
    if not POSED[np.asarray(res.status)].all():
        spans = "; ".join(f"{_fmt(units.input_from_internal(a, is_len))} to {_fmt(units.input_from_internal(b, is_len))}"
                          for a, b in swept_ranges(res))
        lines.append(f"assembles over {spans} ({xlabel}) on the sketched branch")
    for b in model.body_names[1:]:
        a = units.angle_from_internal(res.angle(b))
        w = units.rate_from_internal(res.omega(b))
        if np.any(np.isfinite(a)):
            lines.append(f"  {b}: angle {_fmt(np.nanmin(a))} to {_fmt(np.nanmax(a))} {units.angle}, "
                         f"largest |rate| {_fmt(np.nanmax(np.abs(w)) if np.any(np.isfinite(w)) else math.nan)} {units.rate}")
    for j in outputs.names_of(model, "length coordinate"):
        t = res.coordinate(j)
        if np.any(np.isfinite(t)):
            lines.append(f"  {j}: travel {_length(np.nanmin(t), units)} to {_length(np.nanmax(t), units)}")
    if res.events:
        name, unit = model.input_names[0], units.input_label(bool(model.input_lengths[0]))
        lines.append("events:")
        for e in res.events:
            at = units.input_from_internal(np.ravel(e.input)[0], bool(model.input_lengths[0]))
            lines.append(f"  {e.kind.replace('_', '-')} position at {name} = {_fmt(at)} {unit}".rstrip()
                         + (f": {e.note}" if e.note else ""))
    else:
        lines.append("events: no limit or singular position met")
    return lines


def mass_lines(model, units):
    """The bodies' mass properties, the gravity and the number of loads (nothing when none)."""
    lines = [f"  {b}: mass {_fmt(model.mass[i])} {units.label('mass')}, inertia {_fmt(model.inertia[i])} "
             f"{units.label('inertia')} about its centre of mass" for i, b in enumerate(model.body_names) if model.mass[i]]
    if model.gravity.any():
        lines.append(f"  gravity ({_fmt(model.gravity[0])}, {_fmt(model.gravity[1])}) {units.label('accel')}")
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
            lines.append(f"  effort of {d}: {_fmt(np.nanmin(e))} to {_fmt(np.nanmax(e))} {unit}")
    for j in forces.reactions:
        size = np.hypot(*forces.reaction(j).T)
        if np.any(np.isfinite(size)):
            lines.append(f"  {j}: largest reaction force {_fmt(np.nanmax(size))} {units.label('force')}")
    return lines


def _grashof_line(model):
    found = four_bar_links(model)
    if found is None:
        return "Grashof class: does not apply (not a single loop of four revolutes)"
    (r1, r2, r3, r4), role = found
    g = grashof(r1, r2, r3, r4, driver=role or "crank")
    turns = f"; the input {'turns fully' if g.input_turns else 'cannot turn fully'}" if role else ""
    return (f"Grashof class: {g.kind} (links {_fmt(r1)}, {_fmt(r2)}, {_fmt(r3)}, {_fmt(r4)}: "
            f"s + l - p - q = {_fmt(g.excess)}){turns}")


def stroke_lines(model, units):
    """Stroke and time ratio of every slider and every link that goes back and forth while the
    one input angle turns (nothing when the input does not turn fully)."""
    if len(model.drivers) != 1 or model.input_lengths[0]:
        return []
    turn = model.sweep(model.u0[0] + np.linspace(0.0, 2 * math.pi, 181))
    if not turn.ok.all():
        return []
    lines = []
    for spec in outputs.specs(model, ("travel", "angle")):
        kind, name = spec.split(":", 1)
        values = output(turn, spec)
        if np.ptp(values) <= 1e-9 * (model.L if kind == "travel" else 1.0):
            continue  # it does not move: no stroke
        try:
            s = stroke(turn, spec)
        except PlanarError:
            continue  # it turns with the input rather than going back and forth
        size = _length(s.stroke, units) if kind == "travel" else f"{_fmt(units.angle_from_internal(s.stroke))} {units.angle}"
        lines.append(f"  {name}: stroke {size}, time ratio {s.time_ratio:.6f}")
    return ["strokes over one turn of the input:"] + lines if lines else []


def range_lines(model, units):
    """The motion range of a one-input mechanism on its sketched branch, ends located by the
    solver (planar.analysis.motion_range)."""
    if len(model.drivers) != 1:
        return []
    ranges = motion_range(model, samples=180)
    name, is_len = model.input_names[0], bool(model.input_lengths[0])
    unit = units.input_label(is_len)
    if not is_len and len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 2 * math.pi:
        return [f"motion range of {name}: a full turn"]
    shown = "; ".join(f"{_fmt(units.input_from_internal(lo, is_len))} to {_fmt(units.input_from_internal(hi, is_len))}"
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


# ---- commands --------------------------------------------------------------------------------


def _write(what, fn, *args, **kwargs):
    try:
        return fn(*args, **kwargs)
    except OSError as e:
        raise _OutputError(f"cannot write {what}: {e.strerror or e}") from None


class _OutputError(Exception):
    pass


def _run(doc, source, args, out):
    """Sweep a loaded file and write its outputs into ``out``; prints what it did."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from planar import animate, draw

    model, units, settings = _settings(doc, args)
    unknown = [p for p in args.points or () if p not in model.points]
    if unknown:
        raise UsageError(f"--points: no point or joint {unknown[0]!r} in {model.name!r}: the names are "
                         f"{', '.join(sorted(model.points))}")
    formats = [f.strip() for f in (args.tables or "csv").split(",") if f.strip()]
    for fmt in formats:
        if fmt not in ("csv", "json"):
            raise UsageError(f"--tables: unknown table format {fmt!r}: use csv, json or csv,json")
    circuit = getattr(args, "circuit", False)
    values = sweep_values(model, units, settings, source, args)
    res = run_sweep(model, units, settings, circuit, getattr(args, "engine", "numpy"), values)
    _, lines = info_lines(doc, source)
    for line in lines[1:]:
        print(line)
    for line in summary(res, units, settings, circuit) + stroke_lines(model, units):
        print(line)
    forces = None
    if getattr(args, "forces", False):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", IndeterminateWarning)
            forces = res.forces()
        for line in [f"note: {w.message}" for w in caught] + mass_lines(model, units) + force_lines(forces, units):
            print(line)
    _write(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    stem = _stem(model.name)
    written = []
    cols = table(res, units) + (force_table(forces, units) if forces is not None else [])
    for fmt in formats:
        p = out / f"{stem}.{fmt}"
        _write(p, write_csv if fmt == "csv" else (lambda c, q: write_json(c, q, model.name)), cols, p)
        written.append(p)
    posed = np.flatnonzero(np.all(np.isfinite(np.asarray(res.q)), axis=1))
    if not args.no_plot and posed.size:
        ax = draw.figure(res, int(posed[len(posed) // 6]), args.points, units=units)
        p = out / f"{stem}.png"
        _write(p, ax.figure.savefig, p, dpi=args.dpi)
        plt.close(ax.figure)
        written.append(p)
        figures = [(draw.plot_outputs(res, units=units)[0], "outputs")]
        if forces is not None:
            figures += [(draw.draw_forces(forces, int(posed[len(posed) // 6]), units=units), "forces"),
                        (draw.plot_forces(forces, units=units)[0], "efforts")]
        for ax, what in figures:
            p = out / f"{stem}_{what}.png"
            _write(p, ax.figure.savefig, p, dpi=args.dpi)
            plt.close(ax.figure)
            written.append(p)
    if not args.no_animation and posed.size:
        kind = args.animation
        if kind == "mp4" and not animate.ffmpeg_available():
            print("note: ffmpeg not found, writing a GIF instead of MP4")
            kind = "gif"
        p = out / f"{stem}.{kind}"
        _write(p, lambda: animate.animate(res, p, points=args.points, fps=args.fps, max_frames=args.frames,
                                          rocking=settings.rocking, dpi=args.dpi * 3 // 4, units=units,
                                          progress=Progress(f"writing {p.name}: frames")))
        written.append(p)
    print("wrote " + ", ".join(str(p) for p in written))
    return res


def _stem(name):
    keep = "".join(c if c.isalnum() or c in "-_" else "_" for c in name).strip("_")
    return keep or "mechanism"


def _load(args):
    """The file of the command line, read and compiled (the model is cached for later calls);
    an error names the file."""
    from planar import io

    doc = io.load(args.file, args.length_unit)
    try:
        doc.mechanism.compile()
    except PlanarError as e:
        raise FileFormatError(f"{args.file}: {e}") from None
    return doc


def cmd_run(args):
    if args.circuit and (args.start is not None or args.stop is not None):
        raise UsageError("--circuit starts at the sketch and ends back there: drop --start and --stop")
    doc = _load(args)
    out = Path(args.out) if args.out else Path(f"{Path(args.file).stem}-out")
    _run(doc, args.file, args, out)
    return EXIT_OK


def cmd_info(args):
    doc = _load(args)
    model, lines = info_lines(doc, args.file)
    units = doc.units
    settings = doc.sweep or default_sweep(model, units)
    res = run_sweep(model, units, settings, values=sweep_values(model, units, settings, args.file))
    for line in lines + range_lines(model, units) + summary(res, units, settings) + stroke_lines(model, units):
        print(line)
    return EXIT_OK


def _example_doc(name):
    """A catalogue mechanism with its default demonstration dimensions, in degrees, and a sweep
    of one turn (or half its size either way) from its sketch."""
    from planar.mechanisms import CATALOGUE

    mech = CATALOGUE[name]()
    units = Units()
    return mech, units, default_sweep(mech.compile(), units)


def cmd_example(args):
    from planar import io
    from planar.mechanisms import CATALOGUE

    if args.name is None:
        print("catalogue mechanisms (write one with: planar example NAME):")
        for name, fn in CATALOGUE.items():
            first = " ".join((fn.__doc__ or "").strip().split("\n\n")[0].split())  # the opening paragraph
            print(f"  {name:24s} {first.split('. ')[0].rstrip('.')}")
        return EXIT_OK
    if args.name not in CATALOGUE:
        raise UsageError(f"no catalogue mechanism {args.name!r}: the names are {', '.join(CATALOGUE)}")
    mech, units, sweep = _example_doc(args.name)
    path = Path(args.output or f"{args.name}.json")
    _write(path, io.save, mech, path, units, sweep)
    print(f"wrote {path}: run it with: planar run {path}")
    return EXIT_OK


DEMO_COUPLER_POINT = (2 * math.cos(math.radians(30)), 2 * math.sin(math.radians(30)))


def cmd_app(args):
    """Serve the interactive page until Ctrl-C."""
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise InputError('planar app needs Bokeh: pip install "planar-kinematics[app]"') from None
    from planar.app.forms import FileDesign
    from planar.app.page import serve

    start = None
    if args.file is not None:
        from planar import io

        mf = io.load(args.file)
        start = FileDesign(mf.data, str(args.file))
        start.build().compile()  # refuse a file that does not build before serving it
    try:
        return serve(args.port, not args.no_browser, start)
    except OSError as e:
        raise UsageError(f"--port {args.port}: cannot serve on 127.0.0.1:{args.port}: {e.strerror or e}; "
                         f"pick another port") from None


def cmd_demo(args):
    """The seeds' four-bar (4, 2, 3, 4) with a coupler point 2 from A at 30 deg off A->B, its crank
    turned once at 10 rad/s."""
    from planar import io
    from planar.io import SweepSettings
    from planar.mechanisms import four_bar

    out = Path(args.out)
    mech = four_bar(4.0, 2.0, 3.0, 4.0, coupler_point=DEMO_COUPLER_POINT)
    units = Units(length="cm", angle="deg", rate="rad/s")
    sweep = SweepSettings(start=(0.0,), stop=(360.0,), num=args.num, speed=(10.0,))
    _write(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    path = out / "four_bar.json"
    _write(path, io.save, mech, path, units, sweep)
    print("planar demo: the four-bar of the seeds (ground 4, crank 2, coupler 3, rocker 4 cm) with coupler "
          "point C, crank at 10 rad/s")
    _run(io.load(path), path, args, out)
    # the seeds' worked example: the crank at 60 deg
    res = mech.sweep([math.radians(60.0)], velocity=10.0)
    th3, th4 = (math.degrees(res.angle(b)[0]) for b in ("coupler", "rocker"))
    print(f"at crank 60 deg: th3 = {th3:.6f} deg, th4 = {th4:.6f} deg, w3 = {res.omega('coupler')[0]:.6f}, "
          f"w4 = {res.omega('rocker')[0]:.6f} rad/s, a3 = {res.alpha('coupler')[0]:.6f}, "
          f"a4 = {res.alpha('rocker')[0]:.6f} rad/s^2")
    print(f"mechanism file {path}: try  planar info {path}  or  planar run {path} --speed 60rpm")
    return EXIT_OK


# ---- argument parsing ------------------------------------------------------------------------


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(EXIT_USAGE, f"planar: error: {message} (see {self.prog} --help)\n")


def _bounded(lo, hi):
    """An argparse type: an integer from ``lo`` to ``hi``."""
    def read(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{v} is not from {lo} to {hi}")
        return v
    return read


def _finite(text):
    """An argparse type: a finite number."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


def _outputs(p, out_default=None):
    p.add_argument("--out", default=out_default, help="output folder" + (
        f" (default {out_default})" if out_default else " (default FILE-out next to where you run)"))
    p.add_argument("--tables", default="csv", help="table formats: csv, json or csv,json (default csv)")
    p.add_argument("--no-plot", action="store_true", help="do not write the PNG figures")
    p.add_argument("--no-animation", action="store_true", help="do not write the animation")
    p.add_argument("--animation", choices=("gif", "mp4"), default="gif", help="animation format (mp4 needs ffmpeg)")
    p.add_argument("--frames", type=_bounded(2, MAX_FRAMES), default=60,
                   help=f"most frames in the animation, 2 to {MAX_FRAMES} (default 60)")
    p.add_argument("--fps", type=_bounded(*FPS), default=15,
                   help=f"animation frames per second, {FPS[0]} to {FPS[1]} (default 15)")
    p.add_argument("--dpi", type=_bounded(*DPI), default=90, help=f"figure resolution, {DPI[0]} to {DPI[1]} (default 90)")
    p.add_argument("--points", type=lambda s: [x for x in s.split(",") if x], default=None,
                   help="points to trace and draw arrows on, comma separated (default: the named points)")


def _length_unit(p):
    p.add_argument("--length-unit", choices=tuple(LENGTH_UNITS),
                   help="restate the file's lengths (its units.length: m, cm, mm or in) in this unit")


def parser():
    from planar import __version__

    p = _Parser(prog="planar", description="Planar mechanism kinematics from the command line.",
                epilog="Exit codes: 0 done, 1 bad mechanism/file/sweep, 2 bad command line, 3 cannot write.")
    p.add_argument("--version", action="version", version=f"planar {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    d = sub.add_parser("demo", help="sweep a four-bar with a coupler point; write plots, animation, CSV")
    _outputs(d, "planar-demo")
    d.add_argument("--num", type=_bounded(2, MAX_ROWS), default=73, help="sweep values over the turn (default 73)")
    d.set_defaults(func=cmd_demo)

    r = sub.add_parser("run", help="sweep a mechanism file and write tables, plots and an animation")
    r.add_argument("file", help="mechanism file (JSON; see planar example)")
    r.add_argument("--start", type=_finite, nargs="+", help="input value(s) at the start, in the file's units")
    r.add_argument("--stop", type=_finite, nargs="+", help="input value(s) at the end, in the file's units")
    r.add_argument("--num", type=_bounded(2, MAX_ROWS), help=f"number of sweep values, 2 to {MAX_ROWS:,}")
    r.add_argument("--speed", help="input speed: a number in the file's rate unit, or with a unit: "
                                   "10rad/s, 90deg/s, 120rpm (length/s for sliding inputs)")
    r.add_argument("--acceleration", type=_finite, nargs="+", help="input acceleration(s)")
    motion = r.add_mutually_exclusive_group()
    motion.add_argument("--rocking", action="store_true", help="sweep start -> stop -> start")
    motion.add_argument("--circuit", action="store_true",
                        help="the whole circuit from the sketch, the input turning back at each limit position "
                             "(--num values in all; no --start or --stop)")
    r.add_argument("--engine", choices=("numpy", "numba"), default="numpy",
                   help="numba: the compiled engine for long sweeps (the fast extra; compiles once per mechanism "
                        "structure, 10-65 s, then cached)")
    r.add_argument("--angle-unit", choices=("deg", "rad"), help="angle unit of the outputs and of --start/--stop")
    r.add_argument("--rate-unit", choices=tuple(RATE_UNITS), help="unit of angular rates in the outputs")
    r.add_argument("--forces", action="store_true",
                   help="kinetostatics from the file's masses, gravity and loads: driver efforts and joint reactions "
                        "in the tables, NAME_forces.png and NAME_efforts.png")
    _length_unit(r)
    _outputs(r)
    r.set_defaults(func=cmd_run)

    i = sub.add_parser("info", help="mobility, redundancy, Grashof class, motion ranges and events of a file")
    i.add_argument("file", help="mechanism file (JSON)")
    _length_unit(i)
    i.set_defaults(func=cmd_info)

    e = sub.add_parser("example", help="write a catalogue mechanism to a file (no NAME: list the catalogue)")
    e.add_argument("name", nargs="?", help="catalogue name, e.g. four_bar")
    e.add_argument("-o", "--output", help="file to write (default NAME.json)")
    e.set_defaults(func=cmd_example)

    a = sub.add_parser("app", help="an interactive simulator in the browser (needs the app extra: Bokeh)")
    a.add_argument("file", nargs="?", help="a mechanism file to open (default: pick from the catalogue in the page)")
    a.add_argument("--port", type=_bounded(1, 65535), default=5006, help="port on 127.0.0.1 (default 5006)")
    a.add_argument("--no-browser", action="store_true", help="do not open a browser tab")
    a.set_defaults(func=cmd_app)

    from planar.synthesis.command import add_parser

    add_parser(sub)
    return p


def main(argv=None):
    """Run the command line; returns the exit code."""
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except PlanarError as e:
        print(f"planar: error: {_one_line(e)}", file=sys.stderr)
        return EXIT_USAGE if isinstance(e, UsageError) else EXIT_INPUT
    except _OutputError as e:
        print(f"planar: error: {_one_line(e)}", file=sys.stderr)
        return EXIT_OUTPUT


def _one_line(e):
    return " ".join(str(e).split())


if __name__ == "__main__":
    sys.exit(main())
