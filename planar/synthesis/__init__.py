"""Synthesis: design a linkage for a job, as an ordinary :class:`planar.Mechanism`.

- function generation (:mod:`planar.synthesis.function`): a four-bar or a slider-crank whose
  output follows y = f(x), exactly through three precision points or in the least squares
  sense through more (Chebyshev spacing offered);
- motion generation (:mod:`planar.synthesis.motion`): a four-bar whose coupler passes three
  prescribed positions, both dyads in closed form with the free choices exposed; four and
  five positions by Burmester's compatibility equation;
- path generation (:mod:`planar.synthesis.path`): a four-bar (or a Stephenson six-bar) whose
  coupler point passes N target points, with or without prescribed timing, by a seeded global
  search over batches of designs (:mod:`planar.synthesis.families`: the linkages in closed
  form) and local refinement;
- ``planar synth`` (:mod:`planar.synthesis.command`): the three from a CSV file.

Every result is a :class:`Synthesis`: the mechanism, built with the catalogue's builders, and
its error at each target, read from planar's own sweep of it, with the defects found on the
way (not assemblable over the range, branch events, change of circuit, wrong order).
"""

from planar.errors import SynthesisError
from planar.synthesis.function import (freudenstein, function_four_bar, function_slider_crank,
                                       four_bar_lengths, precision_points, slider_crank_dimensions)
from planar.synthesis.families import stephenson_tracer
from planar.synthesis.motion import burmester_curves, burmester_points, compatible, dyad, motion_four_bar
from planar.synthesis.path import path_check, path_four_bar, path_six_bar
from planar.synthesis.result import Synthesis

__all__ = ["Synthesis", "SynthesisError", "precision_points", "freudenstein", "four_bar_lengths",
           "slider_crank_dimensions", "function_four_bar", "function_slider_crank", "dyad", "compatible",
           "burmester_curves", "burmester_points", "motion_four_bar", "path_four_bar", "path_six_bar",
           "stephenson_tracer", "path_check"]
