"""The ``planar`` command line: run mechanism files, inspect them, write catalogue examples.

    planar demo [--out DIR]            a four-bar with a coupler point: summary, plots, animation, CSV
    planar run FILE [options]          sweep a mechanism file; write tables, plots and an animation
    planar info FILE                   mobility, redundancy, Grashof class, motion ranges, events
    planar example NAME [-o FILE]      write a catalogue mechanism to a file (no NAME: list them)
    planar synth path|motion|function CSV  design a four-bar for target points, positions or y = f(x)

Exit codes: 0 done; 1 the mechanism, file or sweep is wrong (the message says which field or
joint and what to do); 2 the command line is wrong; 3 an output could not be written.

- :mod:`planar.cli.main`: the parser, exit codes and :func:`main` (the ``planar`` entry point);
- :mod:`planar.cli.commands`: the commands;
- :mod:`planar.cli.settings`: sweep settings from a file and the command line;
- :mod:`planar.cli.report`: what ``info`` and ``run`` print;
- :mod:`planar.cli.tables`: the CSV and JSON tables.
"""

from planar.cli.main import EXIT_INPUT, EXIT_OK, EXIT_OUTPUT, EXIT_USAGE, UsageError, main, parser, write_output
from planar.cli.settings import default_sweep

__all__ = ["EXIT_INPUT", "EXIT_OK", "EXIT_OUTPUT", "EXIT_USAGE", "UsageError", "default_sweep", "main", "parser",
           "write_output"]
