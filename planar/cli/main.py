"""The parser of the ``planar`` command line, its exit codes, and :func:`main`."""

import argparse
import math
import sys

from planar.animate import DPI, FPS, MAX_FRAMES
from planar.errors import InputError, PlanarError
from planar.units import LENGTH_UNITS, RATE_UNITS

EXIT_OK, EXIT_INPUT, EXIT_USAGE, EXIT_OUTPUT = 0, 1, 2, 3
MAX_ROWS = 1_000_000  # table rows a run writes: a million take ~50 s and 0.4 GB of CSV; the API sweeps more
DEFAULT_NUM = 73  # sweep values of a turn when neither the file nor the command line says: every 5 degrees


class UsageError(InputError):
    """The command line is wrong (exit code 2): the message names the option and the fix."""


class OutputError(Exception):
    """An output could not be written (exit code 3)."""


def write_output(what, fn, *args, **kwargs):
    """``fn(*args, **kwargs)``, an OSError turned into an :class:`OutputError` naming ``what``."""
    try:
        return fn(*args, **kwargs)
    except OSError as e:
        raise OutputError(f"cannot write {what}: {e.strerror or e}") from None


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


def _names(text):
    """An argparse type: comma-separated names, at least one."""
    names = [x.strip() for x in text.split(",") if x.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"{text!r} names no point: give names such as A,C")
    return names


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
    p.add_argument("--points", type=_names, default=None,
                   help="points to trace and draw arrows on, comma separated (default: the named points)")


def _length_unit(p):
    p.add_argument("--length-unit", choices=tuple(LENGTH_UNITS),
                   help="restate the file's lengths (its units.length: m, cm, mm or in) in this unit")


def parser():
    from planar import __version__
    from planar.cli.commands import cmd_app, cmd_demo, cmd_example, cmd_info, cmd_run

    p = _Parser(prog="planar", description="Planar mechanism kinematics from the command line.",
                epilog="Exit codes: 0 done, 1 bad mechanism/file/sweep, 2 bad command line, 3 cannot write.")
    p.add_argument("--version", action="version", version=f"planar {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    d = sub.add_parser("demo", help="sweep a four-bar with a coupler point; write plots, animation, CSV")
    _outputs(d, "planar-demo")
    d.add_argument("--num", type=_bounded(2, MAX_ROWS), default=DEFAULT_NUM,
                   help=f"sweep values over the turn (default {DEFAULT_NUM})")
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
                   help="numba: the compiled engine for long sweeps (the fast extra; compiled once per "
                        "installation, about half a minute, then loaded from its cache)")
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
    except OutputError as e:
        print(f"planar: error: {_one_line(e)}", file=sys.stderr)
        return EXIT_OUTPUT
    except MemoryError:  # (what fits was checked against the machine's memory: a tighter limit of the process)
        print("planar: error: out of memory: this process may use less memory than the machine has; ask for "
              "fewer values", file=sys.stderr)
        return EXIT_INPUT


def _one_line(e):
    return " ".join(str(e).split())
