"""Textbook figures of any mechanism, drawn from its compiled model and a sweep.

Nothing here knows a mechanism by name. A body is drawn as a bar between its joint points (two
points) or a plate over them (three or more); each joint class draws its own part
(:meth:`planar.joints.Joint.draw_part`: pins, hatched ground pivots, slider blocks on guide
lines, slots, gears as pitch circles with a mark that turns with them, racks as toothed lines)
from the body-fixed numbers the solver uses, with the primitives of a :class:`Scene`.

- :mod:`planar.draw.scene`: a mechanism ready to draw at any pose, and the primitives;
- :mod:`planar.draw.pose`: pictures of poses (the mechanism, paths, arrows, instant centres);
- :mod:`planar.draw.curves`: outputs, efforts and forces against the input;
- :mod:`planar.draw.style`: colours and the axes every drawing starts and ends with.

Every function takes ``ax=None`` (a new figure when None) and returns the axes it drew on.
matplotlib is imported when a function runs, not when planar is imported.

>>> import numpy as np, matplotlib
>>> matplotlib.use("Agg")
>>> from planar.mechanisms import four_bar
>>> from planar import draw
>>> res = four_bar(coupler_point=(2.0, 0.5)).sweep(np.linspace(0, 2 * np.pi, 73))
>>> ax = draw.draw(res, 10)
>>> ax = draw.draw_paths(res, ["C"], ax=ax)
>>> len(ax.lines) > 0
True
"""

from planar.draw.curves import default_outputs, input_axis, plot_forces, plot_outputs
from planar.draw.pose import (draw, draw_event_poses, draw_forces, draw_instant_centres, draw_paths, draw_vectors,
                              figure, path_points)
from planar.draw.scene import Scene, world
from planar.draw.style import ACCELERATION, EDGE, EVENT_MARK, FILLS, FORCE, PATH_COLOURS, VELOCITY

__all__ = ["ACCELERATION", "EDGE", "EVENT_MARK", "FILLS", "FORCE", "PATH_COLOURS", "Scene", "VELOCITY",
           "default_outputs", "draw", "draw_event_poses", "draw_forces", "draw_instant_centres", "draw_paths",
           "draw_vectors", "figure", "input_axis", "path_points", "plot_forces", "plot_outputs", "world"]
