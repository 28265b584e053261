"""Parameter studies: one sweep over many designs (dimension sets) of one structure, as a batch.

A *design* is one set of keyword arguments to a builder (a catalogue function such as
:func:`planar.mechanisms.four_bar`, or any function of yours returning a
:class:`planar.Mechanism`: lengths, points, starts, the numbers of ``Mechanism.distance``),
or one mechanism's numbers (:class:`Vary`: no Mechanism is built per design).
:func:`sweep_designs` compiles one design of each structure and builds the others' tables
from their numbers at once (:mod:`planar.designs.tables`), then sweeps all of them at once: the
design axis is folded into the solver's batch axis (each configuration reads its own design's
joint parameters, :meth:`planar.system.System.over_designs`), so one continuation and one
Newton loop serve every design. The results are (D, N, ...) arrays.

The batch takes the *regular* designs: every step of the walk and every value certified as
the per-design sweep certifies them, no value near a singular position. A design it cannot
certify (a limit, a branch event, a value out of range) is swept alone by
:meth:`planar.Model.sweep`, which locates its events and gives each value its status; a
design that cannot be built or assembled is kept, with NaN outputs, status NOT_ASSEMBLABLE
and the error's message in ``errors``. One bad design never loses a study.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> study = sweep_designs(four_bar, {"crank": [1.0, 1.5, 2.0]}, np.radians(np.arange(0, 360, 45)),
...                       fixed=dict(ground=4.0, coupler=3.5, rocker=3.0))
>>> study.position("B").shape, study.ok.all(), study.batched.tolist()
((3, 8, 2), np.True_, [True, True, True])
>>> study.designs[1]
{'crank': 1.5}
"""

from planar.designs.results import DesignSweep
from planar.designs.study import (BATCH, Vary, check_fixed, design_table, join, study_options, sweep_designs,
                                  sweep_part, values_of)

__all__ = ["BATCH", "DesignSweep", "Vary", "check_fixed", "design_table", "join", "study_options", "sweep_designs",
           "sweep_part", "values_of"]
