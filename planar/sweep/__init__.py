"""Sweeps: continuation along the branch drawn in the sketch, batched where it can be.

1. Anchors: a predictor-corrector walk from the assembled sketch through the input values in
   order, in steps no longer than ``max_step`` (scaled input units). Anchors are tried in
   batched waves (each solved from the Taylor predictor at the wave's start, then checked as
   one walk step from the anchor before it; one that stops part way is followed by a new wave
   from its last anchor). Values further apart than a wave reaches are reached through
   stations ``max_step`` apart between them, solved in the same waves, many gaps a batch.
   Where a wave accepts none, the walk goes step by step, halving a step whose solution
   changes assembly mode (the sign of a block det) or lands far from its predictor. Where that
   fails a singular position lies ahead:
   :func:`planar.events.crossing.cross` follows the branch by arclength, locates it and says
   what it is (a limit stops the branch; at a bifurcation the sweep goes on along the smooth
   branch, or the other one if asked).
2. Every other value is solved in batch from the anchors of its own stretch (no event in
   between): by quintic Hermite interpolation between two anchors in the kinematic
   coefficients ``q_u``, ``q_uu`` (the velocity and acceleration solutions at unit input rate),
   or the Taylor predictor ``q + q_u du + 1/2 q_uu du^2`` from the nearer one, and passes the
   same acceptance test; failures are walked to one by one. A finer level of anchors
   (``FINER`` per interval) comes first, so that for the rest the interpolation is at rounding
   level and one evaluation and one factorisation give the pose, its certificate and its rates.
3. Velocities and accelerations by forward substitution through the blocks with the final
   Jacobian. Points on a limit position keep their positions (status LIMIT, rates NaN); points
   on a bifurcation get their values from the smooth branch around them; points that cannot
   be reached get NaN everywhere, their status, the assembly gap and the nearest limit.

Only the blocks the asked-for ``outputs`` need are solved; the other coordinates are NaN.

The rooms: :mod:`~planar.sweep.branch` (solves on one plan, the final step; the acceptance test
itself is :mod:`planar.acceptance`, shared with the compiled engine), :mod:`~planar.sweep.walk`
(the sequential walk and its events), :mod:`~planar.sweep.reentry` (re-entry past a gap),
:mod:`~planar.sweep.periods` (the input's period, whole turns), :mod:`~planar.sweep.anchors` (anchors, waves,
the bulk from them), :mod:`~planar.sweep.located` (values against located events),
:mod:`~planar.sweep.finish` (the results), :mod:`~planar.sweep.run` (the entry point and its
passes), :mod:`~planar.sweep.entries` (entering the branch where the walk cannot go),
:mod:`~planar.sweep.gaps` (where to look past a gap), :mod:`~planar.sweep.order` (the order of
the values) and :mod:`~planar.sweep.checks` (what a sweep asks of the model first).
"""

from planar.sweep.anchors import CHUNK, sweep_anchors
from planar.sweep.branch import Branch, final_step, input_scale
from planar.sweep.finish import near_stretches
from planar.sweep.checks import check_sketch, output_columns
from planar.sweep.run import FAR, ROCKING, SPARSE, run_sweep
from planar.sweep.walk import Walker

__all__ = ["CHUNK", "FAR", "ROCKING", "SPARSE", "Branch", "Walker", "check_sketch", "final_step", "input_scale",
           "near_stretches", "output_columns", "run_sweep", "sweep_anchors"]
