"""``planar synth``: path, motion or function generation from a CSV file of targets.

    planar synth path TARGETS.csv [--six-bar] [--timing] [--min-transmission A] [--seed S] [--designs N] [--tol T]
    planar synth motion POSITIONS.csv --beta B2 B3 --gamma G2 G3 [-o FILE]
    planar synth function TABLE.csv --input-range A0 A1 --output-range B0 B1 [--points N] [--slider] [-o FILE]

The CSV has a header row. Path targets: columns ``x``, ``y`` (and ``input``, the crank angle
at each target, used with ``--timing``); motion positions: ``x``, ``y``, ``angle``; a function:
``x``, ``y`` = f(x) (x increasing; f is interpolated linearly between rows, and x runs from the
first row to the last). Angles are in ``--angle-unit`` (deg by default), in the file and on
the command line; ``--slider`` makes a slider-crank whose travel (a length) is the output. It
prints the design, the error at each target and the defects, and writes the mechanism file
(default FILE-synth.json, swept from the first target's input to the last) and a picture.
"""

import csv
from pathlib import Path

import numpy as np

from planar.errors import FileFormatError


def add_parser(sub):
    """The ``synth`` subcommand on the subparsers ``sub`` of the ``planar`` command."""
    s = sub.add_parser("synth", help="design a four-bar for target points (path), positions (motion) or y = f(x) "
                                     "(function) in a CSV")
    s.add_argument("problem", choices=("path", "motion", "function"),
                   help="path: points x,y; motion: poses x,y,angle; function: a table x,y")
    s.add_argument("file", help="CSV with a header row: x,y[,input] (path), x,y,angle (motion), x,y (function)")
    s.add_argument("--timing", action="store_true", help="path: prescribe the crank angles of the CSV's input column")
    s.add_argument("--seed", type=int, default=0, help="path: seed of the search (default 0)")
    s.add_argument("--designs", type=int, help="path: designs searched (default 20000, six-bar 100000)")
    s.add_argument("--tol", type=float, default=1e-6, help="path: largest error relative to the targets' size")
    s.add_argument("--min-transmission", type=float, help="path: smallest transmission angle allowed")
    s.add_argument("--six-bar", action="store_true", help="path: a Stephenson six-bar (tracer P on link 5)")
    s.add_argument("--beta", type=float, nargs=2, help="motion: the crank's rotations to positions 2 and 3")
    s.add_argument("--gamma", type=float, nargs=2, help="motion: the rocker's rotations to positions 2 and 3")
    s.add_argument("--input-range", type=float, nargs=2, help="function: crank angles at the first and last x")
    s.add_argument("--output-range", type=float, nargs=2,
                   help="function: rocker angles (slider travels with --slider) at the first and last x")
    s.add_argument("--points", type=int, default=3, help="function: precision points (3 exact, more least squares)")
    s.add_argument("--spacing", choices=("chebyshev", "even"), default="chebyshev", help="function: of the points")
    s.add_argument("--slider", action="store_true", help="function: a slider-crank (default a four-bar)")
    s.add_argument("--angle-unit", choices=("deg", "rad"), default="deg", help="angles in the CSV and options")
    s.add_argument("-o", "--output", help="mechanism file to write (default FILE-synth.json)")
    s.add_argument("--no-plot", action="store_true", help="do not write the PNG picture")
    s.set_defaults(func=cmd_synth)


def read_targets(path, columns, optional=()):
    """The named columns of a CSV file with a header row, as floats: {name: (N,) array}."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except OSError as e:
        raise FileFormatError(f"{path}: cannot read the file: {e.strerror or e}") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise FileFormatError(f"{path}: not a CSV text file ({e})") from None
    if not rows:
        raise FileFormatError(f"{path}: no rows: give a header row ({','.join(columns)}) and one row per target")
    for k, row in enumerate(rows, start=2):
        if None in row:  # (csv puts a row's values past the header's columns under None)
            raise FileFormatError(f"{path}: line {k} has more values than the header has columns")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in columns if c not in header]
    if missing:
        raise FileFormatError(f"{path}: no column {', '.join(missing)}: the header is {header}")
    out = {}
    for c in list(columns) + [c for c in optional if c in header]:
        vals = []
        for k, row in enumerate(rows, start=2):
            raw = {key.strip(): v for key, v in row.items()}.get(c)
            try:
                vals.append(float(raw))
            except (TypeError, ValueError, OverflowError):
                raise FileFormatError(f"{path}: line {k}, column {c}: {raw!r} is not a number") from None
            if not np.isfinite(vals[-1]):  # (nan, inf, 1e400)
                raise FileFormatError(f"{path}: line {k}, column {c}: {raw!r} is not a finite number")
        out[c] = np.array(vals)
    return out


def check_options(args):
    """The command line's numbers, checked before any work: a bad one is a usage error (exit 2)
    naming the option."""
    from planar.cli.main import UsageError
    from planar.synthesis.function import MAX_POINTS
    from planar.synthesis.path import MAX_DESIGNS

    if args.seed < 0:
        raise UsageError(f"--seed {args.seed}: give a whole number of at least 0")
    if args.designs is not None and not 1 <= args.designs <= MAX_DESIGNS:
        raise UsageError(f"--designs {args.designs}: give a whole number from 1 to {MAX_DESIGNS:g}")
    if not (np.isfinite(args.tol) and args.tol > 0):
        raise UsageError(f"--tol {args.tol}: give a positive error relative to the targets' size (default 1e-6)")
    turn = 90.0 if args.angle_unit == "deg" else np.pi / 2
    if args.min_transmission is not None and not 0 <= args.min_transmission <= turn:
        raise UsageError(f"--min-transmission {args.min_transmission}: give an angle from 0 to {turn:g} "
                         f"({args.angle_unit})")
    if not 3 <= args.points <= MAX_POINTS:  # (three fix the three constants)
        raise UsageError(f"--points {args.points}: give a whole number from 3 to {MAX_POINTS}")
    for name in ("beta", "gamma", "input_range", "output_range"):
        v = getattr(args, name)
        if v is not None and not np.all(np.isfinite(v)):
            raise UsageError(f"--{name.replace('_', '-')} {' '.join(map(str, v))}: give two finite numbers")
    for name in ("beta", "gamma"):  # (rotations: a turn more is the same one)
        v = getattr(args, name)
        if v is not None and not np.all(np.abs(v) <= 4 * turn):
            raise UsageError(f"--{name} {' '.join(map(str, v))}: give rotations within a turn (+-{4 * turn:g} "
                             f"{args.angle_unit})")


def cmd_synth(args):
    from planar.cli import EXIT_OK, write_output
    from planar.cli.main import UsageError
    from planar.progress import Progress
    from planar.synthesis import (function_four_bar, function_slider_crank, motion_four_bar, path_four_bar,
                                  path_six_bar)
    from planar.units import Units

    units = Units(angle=args.angle_unit)
    check_options(args)
    if args.problem == "path":
        cols = read_targets(args.file, ("x", "y"), ("input",))
        if args.timing and "input" not in cols:
            raise FileFormatError(f"{args.file}: --timing needs an input column (the crank angle at each target)")
        timing = units.angle_to_internal(cols["input"]) if args.timing else None
        mu = None if args.min_transmission is None else units.angle_to_internal(args.min_transmission)
        budget = {} if args.designs is None else {"designs": args.designs}
        s = (path_six_bar if args.six_bar else path_four_bar)(
            np.column_stack((cols["x"], cols["y"])), timing=timing, tol=args.tol, min_transmission=mu,
            seed=args.seed, progress=Progress("search step"), **budget)
    elif args.problem == "function":
        if args.input_range is None or args.output_range is None:
            raise UsageError("function generation needs --input-range A0 A1 and --output-range B0 B1")
        cols = read_targets(args.file, ("x", "y"))
        x, y = cols["x"], cols["y"]
        if len(x) < 2 or np.any(x[1:] <= x[:-1]):  # (not np.diff: it overflows between far values)
            raise FileFormatError(f"{args.file}: the x column must increase from row to row (two rows at least)")
        build = function_slider_crank if args.slider else function_four_bar
        out = args.output_range if args.slider else units.angle_to_internal(args.output_range)
        s = build(lambda v: np.interp(v, x, y), (x[0], x[-1]), units.angle_to_internal(args.input_range), out,
                  points=args.points, spacing=args.spacing)
    else:
        if args.beta is None or args.gamma is None:
            raise UsageError("motion generation needs the free choices --beta B2 B3 and --gamma G2 G3")
        cols = read_targets(args.file, ("x", "y", "angle"))
        P = np.column_stack((cols["x"], cols["y"], units.angle_to_internal(cols["angle"])))
        s = motion_four_bar(P, beta=units.angle_to_internal(args.beta), gamma=units.angle_to_internal(args.gamma))
    for line in report(s, units):
        print(line)
    stem = Path(args.file).with_suffix("")
    path = Path(args.output or f"{stem}-synth.json")
    write_output(path, s.save, path, units)
    written = [path]
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ax = s.draw()
        png = path.with_suffix(".png")
        write_output(png, ax.figure.savefig, png, dpi=90)
        plt.close(ax.figure)
        written.append(png)
    print("wrote " + ", ".join(str(p) for p in written))
    return EXIT_OK


def report(s, units):
    """Lines that say what was found: the design, the error at each target, the defects."""
    parts = []
    for k, v in s.design.items():
        if k == "frame_angle":
            parts.append(f"frame angle {units.angle_from_internal(v):.6g} {units.angle}")
        elif k not in ("name", "start") and not k.startswith("crossed"):
            parts.append(f"{k.replace('_', ' ')} " + (f"{v:.6g}" if np.ndim(v) == 0 else
                                                     str(tuple(round(float(c), 6) for c in v))))
    lines = [f"{s.mechanism.name}: " + ", ".join(parts)]
    # which errors are angles: a rocker's output, a coupler's angle (motion generation's second column)
    angle = [s.targets.ndim == 1 and "rocker" in s.design, s.targets.ndim == 2 and s.targets.shape[1] == 3]
    for k, (u, e) in enumerate(zip(s.inputs, np.atleast_2d(s.errors.T).T)):
        err = ", ".join(f"{units.angle_from_internal(v):.3g} {units.angle}" if a else f"{v:.3g}"
                        for v, a in zip(np.atleast_1d(e), angle))
        lines.append(f"  target {k + 1}: crank {units.angle_from_internal(u):.6g} {units.angle}, error {err}")
    lines += [f"  defect: {m}" for m in s.defects] or ["  no defects"]
    return lines
