"""The commands: ``run``, ``info``, ``example``, ``app`` and ``demo``."""

import math
import warnings
from pathlib import Path

import numpy as np

from planar.cli.main import EXIT_OK, UsageError, write_output
from planar.cli.report import force_lines, info_lines, mass_lines, range_lines, stroke_lines, summary
from planar.cli.settings import default_sweep, file_settings, sweep_or_circuit, sweep_values
from planar.cli.tables import force_table, table, write_csv, write_json
from planar.errors import FileFormatError, IndeterminateWarning, InputError, PlanarError
from planar.progress import Progress
from planar.units import Units


def run_file(doc, source, args, out):
    """Sweep a loaded file and write its outputs into ``out``; prints what it did."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from planar import animate, draw

    model, units, settings = file_settings(doc, args)
    unknown = [p for p in args.points or () if p not in model.points]
    if unknown:
        raise UsageError(f"--points: no point or joint {unknown[0]!r} in {model.name!r}: the names are "
                         f"{', '.join(sorted(model.points))}")
    formats = [f.strip() for f in (args.tables or "csv").split(",") if f.strip()]
    if not formats:
        raise UsageError(f"--tables {args.tables!r} names no table format: use csv, json or csv,json")
    for fmt in formats:
        if fmt not in ("csv", "json"):
            raise UsageError(f"--tables: unknown table format {fmt!r}: use csv, json or csv,json")
    circuit = getattr(args, "circuit", False)
    values = sweep_values(model, units, settings, source, args)
    res = sweep_or_circuit(model, units, settings, circuit, getattr(args, "engine", "numpy"), values)
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
    write_output(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    stem = _stem(model.name)
    written = []
    cols = table(res, units) + (force_table(forces, units) if forces is not None else [])
    for fmt in formats:
        p = out / f"{stem}.{fmt}"
        write_output(p, write_csv if fmt == "csv" else (lambda c, q: write_json(c, q, model.name)), cols, p)
        written.append(p)
    posed = np.flatnonzero(np.all(np.isfinite(np.asarray(res.q)), axis=1))
    if not args.no_plot and posed.size:
        ax = draw.figure(res, int(posed[len(posed) // 6]), args.points, units=units)
        p = out / f"{stem}.png"
        write_output(p, ax.figure.savefig, p, dpi=args.dpi)
        plt.close(ax.figure)
        written.append(p)
        figures = [(draw.plot_outputs(res, units=units)[0], "outputs")]
        if forces is not None:
            figures += [(draw.draw_forces(forces, int(posed[len(posed) // 6]), units=units), "forces"),
                        (draw.plot_forces(forces, units=units)[0], "efforts")]
        for ax, what in figures:
            p = out / f"{stem}_{what}.png"
            write_output(p, ax.figure.savefig, p, dpi=args.dpi)
            plt.close(ax.figure)
            written.append(p)
    if not args.no_animation and posed.size:
        kind = args.animation
        if kind == "mp4" and not animate.ffmpeg_available():
            print("note: ffmpeg not found, writing a GIF instead of MP4")
            kind = "gif"
        p = out / f"{stem}.{kind}"
        write_output(p, lambda: animate.animate(res, p, points=args.points, fps=args.fps, max_frames=args.frames,
                                          rocking=settings.rocking, dpi=max(args.dpi * 3 // 4, animate.DPI[0]), units=units,
                                          progress=Progress(f"writing {p.name}: frames")))
        written.append(p)
    print("wrote " + ", ".join(str(p) for p in written))
    return res


def _stem(name):
    keep = "".join(c if c.isalnum() or c in "-_" else "_" for c in name).strip("_")
    return keep or "mechanism"


def load_file(args):
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
    doc = load_file(args)
    out = Path(args.out) if args.out else Path(f"{Path(args.file).stem}-out")
    run_file(doc, args.file, args, out)
    return EXIT_OK


def cmd_info(args):
    doc = load_file(args)
    model, lines = info_lines(doc, args.file)
    units = doc.units
    settings = doc.sweep or default_sweep(model, units)
    res = sweep_or_circuit(model, units, settings, values=sweep_values(model, units, settings, args.file))
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
    write_output(path, io.save, mech, path, units, sweep)
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
    write_output(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    path = out / "four_bar.json"
    write_output(path, io.save, mech, path, units, sweep)
    print("planar demo: the four-bar of the seeds (ground 4, crank 2, coupler 3, rocker 4 cm) with coupler "
          "point C, crank at 10 rad/s")
    run_file(io.load(path), path, args, out)
    # the seeds' worked example: the crank at 60 deg
    res = mech.sweep([math.radians(60.0)], velocity=10.0)
    th3, th4 = (math.degrees(res.angle(b)[0]) for b in ("coupler", "rocker"))
    print(f"at crank 60 deg: th3 = {th3:.6f} deg, th4 = {th4:.6f} deg, w3 = {res.omega('coupler')[0]:.6f}, "
          f"w4 = {res.omega('rocker')[0]:.6f} rad/s, a3 = {res.alpha('coupler')[0]:.6f}, "
          f"a4 = {res.alpha('rocker')[0]:.6f} rad/s^2")
    print(f"mechanism file {path}: try  planar info {path}  or  planar run {path} --speed 60rpm")
    return EXIT_OK
