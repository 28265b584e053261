"""``planar synth``: path or motion generation from a CSV file of targets.

    planar synth path TARGETS.csv [--timing] [--min-transmission A] [--seed S] [--designs N] [--tol T] [-o FILE]
    planar synth motion POSITIONS.csv --beta B2 B3 --gamma G2 G3 [-o FILE]

The CSV has a header row. Path targets: columns ``x``, ``y`` (and ``input``, the crank angle
at each target, used with ``--timing``); motion positions: ``x``, ``y``, ``angle``. Angles are
in ``--angle-unit`` (deg by default), in the file and on the command line. It prints the error
at each target and the defects, and writes the mechanism file (default TARGETS-synth.json,
swept from the first target's input to the last) and a picture with the targets.
"""

import csv
from pathlib import Path

import numpy as np

from planar.errors import FileFormatError, InputError


def add_parser(sub):
    """The ``synth`` subcommand on the subparsers ``sub`` of the ``planar`` command."""
    s = sub.add_parser("synth", help="design a four-bar for target points (path) or positions (motion) in a CSV")
    s.add_argument("problem", choices=("path", "motion"), help="path: points x,y; motion: poses x,y,angle")
    s.add_argument("file", help="CSV with a header row: x,y[,input] (path) or x,y,angle (motion)")
    s.add_argument("--timing", action="store_true", help="path: prescribe the crank angles of the CSV's input column")
    s.add_argument("--seed", type=int, default=0, help="path: seed of the search (default 0)")
    s.add_argument("--designs", type=int, default=20000, help="path: random designs searched (default 20000)")
    s.add_argument("--tol", type=float, default=1e-6, help="path: largest error relative to the targets' size")
    s.add_argument("--min-transmission", type=float, help="path: smallest transmission angle allowed")
    s.add_argument("--beta", type=float, nargs=2, help="motion: the crank's rotations to positions 2 and 3")
    s.add_argument("--gamma", type=float, nargs=2, help="motion: the rocker's rotations to positions 2 and 3")
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
    if not rows:
        raise FileFormatError(f"{path}: no rows: give a header row ({','.join(columns)}) and one row per target")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in columns if c not in header]
    if missing:
        raise FileFormatError(f"{path}: no column {', '.join(missing)}: the header is {header}")
    out = {}
    for c in list(columns) + [c for c in optional if c in header]:
        vals = []
        for k, row in enumerate(rows, start=2):
            raw = {key.strip(): v for key, v in row.items() if key is not None}.get(c)
            try:
                vals.append(float(raw))
            except (TypeError, ValueError):
                raise FileFormatError(f"{path}: line {k}, column {c}: {raw!r} is not a number") from None
        out[c] = np.array(vals)
    return out


def cmd_synth(args):
    from planar.cli import EXIT_OK, _Progress, _write
    from planar.synthesis import motion_four_bar, path_four_bar
    from planar.units import Units

    units = Units(angle=args.angle_unit)
    if args.problem == "path":
        cols = read_targets(args.file, ("x", "y"), ("input",))
        if args.timing and "input" not in cols:
            raise FileFormatError(f"{args.file}: --timing needs an input column (the crank angle at each target)")
        timing = units.angle_to_internal(cols["input"]) if args.timing else None
        mu = None if args.min_transmission is None else units.angle_to_internal(args.min_transmission)
        s = path_four_bar(np.column_stack((cols["x"], cols["y"])), timing=timing, designs=args.designs,
                          tol=args.tol, min_transmission=mu, seed=args.seed, progress=_Progress("search step"))
    else:
        if args.beta is None or args.gamma is None:
            raise InputError("motion generation needs the free choices --beta B2 B3 and --gamma G2 G3")
        cols = read_targets(args.file, ("x", "y", "angle"))
        P = np.column_stack((cols["x"], cols["y"], units.angle_to_internal(cols["angle"])))
        s = motion_four_bar(P, beta=units.angle_to_internal(args.beta), gamma=units.angle_to_internal(args.gamma))
    for line in report(s, units):
        print(line)
    stem = Path(args.file).with_suffix("")
    path = Path(args.output or f"{stem}-synth.json")
    _write(path, s.save, path, units)
    written = [path]
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ax = s.draw()
        png = path.with_suffix(".png")
        _write(png, ax.figure.savefig, png, dpi=90)
        plt.close(ax.figure)
        written.append(png)
    print("wrote " + ", ".join(str(p) for p in written))
    return EXIT_OK


def report(s, units):
    """Lines that say what was found: the design, the error at each target, the defects."""
    d = s.design
    lines = [f"{s.mechanism.name}: ground {d['ground']:.6g}, crank {d['crank']:.6g}, coupler {d['coupler']:.6g}, "
             f"rocker {d['rocker']:.6g}, coupler point {tuple(round(v, 6) for v in d['coupler_point'])}, "
             f"pivot O2 {tuple(round(v, 6) for v in d['pivot'])}, frame angle "
             f"{units.angle_from_internal(d['frame_angle']):.6g} {units.angle}"]
    for k, (u, e) in enumerate(zip(s.inputs, np.atleast_2d(s.errors.T).T)):
        err = ", ".join(f"{v:.3g}" for v in np.atleast_1d(e))
        lines.append(f"  target {k + 1}: crank {units.angle_from_internal(u):.6g} {units.angle}, error {err}")
    lines += [f"  defect: {m}" for m in s.defects] or ["  no defects"]
    return lines
