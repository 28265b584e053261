"""Analyses over mechanisms, models and sweep results (no per-mechanism formulas; Grashof is a
classification of four link lengths).

>>> from planar.analysis import grashof
>>> grashof(4, 2, 3, 4).kind
'crank-rocker'
"""

from planar.analysis.centres import instant_centre, instant_centres
from planar.analysis.grashof import Grashof, grashof
from planar.analysis.mobility import Mobility, mobility
from planar.analysis.outputs import output
from planar.analysis.ranges import motion_range, swept_ranges
from planar.analysis.stroke import Stroke, stroke
from planar.analysis.topology import four_bar_links
from planar.analysis.transmission import transmission_angle

__all__ = ["Grashof", "Mobility", "Stroke", "four_bar_links", "grashof", "instant_centre", "instant_centres", "mobility",
           "motion_range", "output", "stroke", "swept_ranges", "transmission_angle"]
