"""The drawings' style: colours, event marks, and the axes every drawing starts and ends with."""

import numpy as np

from planar.arguments import finite_number
from planar.errors import InputError
from planar.results import Status
from planar.units import given


def _palette(first, total, saturations, value):
    """``first``, then colours of hues spaced by the golden angle up to ``total``: no two alike,
    so that bodies, paths and curves keep distinct colours however many there are (up to
    ``total``, more than a mechanism has)."""
    from colorsys import hsv_to_rgb

    extra = [hsv_to_rgb((0.07 + 0.6180339887 * k) % 1.0, saturations[k % 2], value)
             for k in range(total - len(first))]
    return tuple(first) + tuple("#" + "".join(f"{round(255 * c):02x}" for c in rgb) for rgb in extra)


EDGE = "#262626"
FILLS = _palette(("#a6cee3", "#fdbf6f", "#b2df8a", "#cab2d6", "#fb9a99", "#ffff99", "#8dd3c7", "#d9d9d9",
                  "#bebada", "#80b1d3"), 100, (0.25, 0.4), 0.97)
VELOCITY, ACCELERATION = "#1f5fbf", "#c0282d"
PATH_COLOURS = _palette(("#6a3d9a", "#1b9e77", "#d95f02", "#e7298a", "#66a61e", "#e6ab02"), 100, (0.8, 0.6), 0.7)
# the kinds of planar.events.Event: marker and colour
FORCE = "#2a7f3f"  # reaction arrows
# relative to a drawing's size: points closer than SAME are one point, a path spanning less than
# STILL does not move; TINY keeps a division by a length that may be zero finite
SAME, STILL, TINY = 1e-9, 1e-6, 1e-300
EVENT_MARK = {"limit": ("s", "#d62728"), "bifurcation": ("D", "#9467bd"), "singular": ("X", "#000000"),
              "near_singular": ("^", "#ff7f0e")}


def pyplot():
    import matplotlib.pyplot as plt

    return plt


def new_axes(ax):
    """``ax``, or a new figure's axes for None."""
    if ax is None:
        _, ax = pyplot().subplots(figsize=(7, 5), layout="constrained")
    return as_axes(ax)


def as_axes(ax):
    """``ax`` where it is a matplotlib Axes of x and y, else an InputError (polar or 3-D axes
    cannot keep x and y at one scale)."""
    from matplotlib.axes import Axes

    if not isinstance(ax, Axes) or ax.name != "rectilinear":
        raise InputError(f"ax must be matplotlib axes of x and y (such as plt.subplots()[1]) or None, got {ax!r}")
    return ax


def figure_size(size, who):
    """``size`` where it is (width, height) in inches, each from 0.5 to 50, else an InputError
    naming ``who``."""
    if not (isinstance(size, (tuple, list)) and len(size) == 2
            and all(finite_number(x) and 0.5 <= x <= 50 for x in size)):
        raise InputError(f"{who} size must be (width, height) in inches, each from 0.5 to 50, got {size!r}")
    return tuple(float(x) for x in size)


def flag(value, name):
    """``value`` where it is True or False, else an InputError naming ``name`` (an array's truth
    is ambiguous)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def finish(ax, units=None):
    units = given(units)
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.08)
    ax.autoscale_view()
    unit = f" [{units.length}]" if units.length else ""
    ax.set_xlabel(f"x{unit}")
    ax.set_ylabel(f"y{unit}")
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    ax.grid(True, color="#e6e6e6", lw=0.6, zorder=0)
    ax.set_axisbelow(True)
    return ax


DRAWN = 10_000  # values a curve draws at most (a figure is ~1,000 pixels across); beyond, every k-th


def thinned(finite, keep=()):
    """Indices of the values a curve of ``finite.size`` values draws (``finite``: (N,) whether
    each value is finite): all of them up to DRAWN; beyond, every k-th for at most DRAWN, the
    last, those in ``keep``, and at each run of values not finite its first (the line's break)
    and the finite values either side (so the line stops and starts again where it does).

    >>> i = thinned(np.isfinite(np.r_[np.arange(50_000.0), np.nan, np.nan, np.arange(50_000.0)]), keep=[7])
    >>> int(i.size), i[:3].tolist(), i[-1].item(), [k for k in i.tolist() if 49_995 < k < 50_005]
    (9096, [0, 7, 11], 100001, [49999, 50000, 50002])
    """
    N = finite.size
    if N <= DRAWN:
        return np.arange(N)
    on = np.zeros(N, bool)
    on[:: -(-N // DRAWN)] = True
    on[-1] = True
    on[np.asarray(keep, int)] = True
    bad = ~finite
    on[0] |= bad[0]
    on[1:] |= bad[1:] & finite[:-1]  # the first of each run not finite
    on[:-1] |= finite[:-1] & bad[1:]  # the finite value before it
    on[1:] |= finite[1:] & bad[:-1]  # and the one after the run
    return np.flatnonzero(on)


def drawn(res, *series):
    """The (N,) series of sweep ``res`` as a line draws them: a NaN put before each JUMPED
    value, so that the line is not drawn across the jump, and thinned (:func:`thinned`).

    >>> from types import SimpleNamespace
    >>> drawn(SimpleNamespace(status=np.array([0, 0, Status.JUMPED])), np.arange(3.0))[0].tolist()
    [0.0, 1.0, nan, 2.0]
    """
    at = np.flatnonzero(np.asarray(res.status) == Status.JUMPED)
    series = [np.insert(np.asarray(v, float), at, np.nan) for v in series]
    i = thinned(np.all([np.isfinite(v) for v in series], axis=0))
    return [v[i] for v in series]
