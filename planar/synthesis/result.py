"""The result of a synthesis, and the checks every built design goes through.

A design is checked on the mechanism planar builds from it, not on the formula that made it:
the input is swept from the first target's value through every target's, in order, and the
sweep must stay assemblable and regular on one branch (no limit or change point, no change of
assembly mode) between the first and the last target.
"""

from dataclasses import dataclass, field

import numpy as np

from planar.errors import InputError, PlanarError
from planar.model.checks import is_complex
from planar.results import VALID, Status

STEP = np.radians(2.0)  # largest input step of the checking sweep between targets
MISSED = 1e-6  # a precision point's error, relative to the targets' size, that misses it (they hold to ~1e-12)
MAX_TRAVEL = 20 * np.pi  # input travel of the checking sweep, radians (ten turns: 1,800 values)
DEFECT_EVENTS = ("limit", "bifurcation", "singular")


@dataclass(frozen=True, eq=False)
class Synthesis:
    """A synthesised mechanism with its error at each target.

    ``mechanism`` is an ordinary :class:`planar.Mechanism`, ``builder(**design)`` builds it
    again (``design`` is the builder's keyword arguments). ``inputs`` (N,) are the input
    values at the targets (in target order); ``targets`` are what was asked for and
    ``achieved`` what planar's sweep of the built mechanism gives there (function generation:
    (N,) outputs; motion generation: (N, 3) poses x, y, angle; path generation: (N, 2)
    points); ``errors`` (N,) is the distance between them (motion generation: (N, 2), the
    point's distance and the angle's error). ``sweep`` is the checking sweep from the first
    target's input to the last (``index`` (N,) locates the targets in it), ``defects`` the
    reasons the design fails (empty when it is usable), ``size`` the targets' size (the
    scale of ``errors``), ``point`` the name of the traced point (or None) and ``notes`` what
    else the problem reports (each function says which).
    """

    mechanism: object
    builder: object
    design: dict
    inputs: np.ndarray
    targets: np.ndarray
    achieved: np.ndarray
    errors: np.ndarray
    sweep: object
    index: np.ndarray
    defects: tuple
    size: float
    point: str | None = None
    notes: dict = field(default_factory=dict)

    @property
    def ok(self):
        """True when the design has no defect."""
        return not self.defects

    @property
    def max_error(self):
        """The largest error over the targets (NaN where a target was not reached)."""
        e = np.asarray(self.errors, float)
        return float(np.max(e)) if np.all(np.isfinite(e)) else float("nan")

    def __repr__(self):
        state = "ok" if self.ok else f"{len(self.defects)} defect(s)"
        return f"Synthesis({self.mechanism.name!r}, targets={len(self.inputs)}, max error={self.max_error:.3g}, {state})"

    def save(self, path, units=None):
        """Write the mechanism to a mechanism file (see :mod:`planar.io`) with a sweep from the
        first target's input to the last (181 values), in ``units`` (default degrees); returns
        the path."""
        from planar import io
        from planar.units import given

        units = given(units)
        ends = [float(units.angle_from_internal(self.inputs[k])) for k in (0, -1)]
        return io.save(self.mechanism, path, units, io.SweepSettings(start=(ends[0],), stop=(ends[1],), num=181))

    def draw(self, ax=None, pose=0):
        """The mechanism at target ``pose`` (an index into the targets), the path of its
        traced point over the checking sweep and the targets (motion generation: with their
        angles as short strokes). Returns the matplotlib axes."""
        from planar import draw

        N = len(self.index)
        if isinstance(pose, (bool, np.bool_)) or not isinstance(pose, (int, np.integer)) or not -N <= pose < N:
            raise InputError(f"pose {pose!r}: a target's index, a whole number from 0 to {N - 1}")
        ax = draw.draw(self.sweep, int(self.index[pose]), ax=ax)
        if self.point is not None:
            draw.draw_paths(self.sweep, [self.point], ax=ax, events=False)
            T = np.asarray(self.targets, float)
            ax.plot(T[:, 0], T[:, 1], "o", ms=7, mfc="none", mec="#d62728", mew=1.6, ls="none",
                    label="targets", zorder=7)
            if T.shape[1] == 3:
                d = 0.06 * self.size * np.stack((np.cos(T[:, 2]), np.sin(T[:, 2])), axis=-1)
                for (x, y), (dx, dy) in zip(T[:, :2], d):
                    ax.plot([x - dx, x + dx], [y - dy, y + dy], color="#d62728", lw=1.6, zorder=7)
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, frameon=False, fontsize=8)
        return ax


def floats(value):
    """``value`` as a float array, or None where it is not real numbers (numpy would read
    complex ones as their real parts, with a warning)."""
    if is_complex(value):
        return None
    try:
        return np.asarray(value, float)
    except (TypeError, ValueError, OverflowError):
        return None


def ordered(inputs, period=None):
    """The inputs' offsets from the first along the direction of motion, and that direction
    (+1 or -1), or None when the targets do not come in order. With ``period`` (a crank's
    2 pi) the offsets are taken modulo it, in either direction, within one turn."""
    u = np.asarray(inputs, float)
    d = u - u[0]
    for sign in (1.0, -1.0):
        s = sign * d if period is None else np.mod(sign * d, period)
        if len(u) == 1 or (np.all(np.diff(s) > 0) and (period is None or s[-1] < period)):
            return sign * s, sign
    return None, 0.0


def check(mechanism, builder, design, inputs, targets, achieve, error, *, period=None, point=None, size=1.0,
          span=None, exact=False):
    """Sweep ``mechanism`` from the first target's input through every target's in order
    (with ``span`` = (start, end): from start, through the targets, to end) and return a
    :class:`Synthesis`. ``achieve(sweep, index)`` reads what the mechanism does at the
    targets, ``error(achieved, targets)`` the errors; ``exact``: the design passes every
    target in some assembly mode (precision points as many as its unknowns), so a target
    missed is one its branch does not reach (a circuit defect)."""
    inputs = np.asarray(inputs, float)
    offsets, sign = ordered(inputs, period)
    defects = []
    if offsets is None:
        defects.append(f"wrong order of the targets: the inputs {np.round(inputs, 6).tolist()} do not run one "
                       "way" + (" within one turn" if period else ""))
        offsets = inputs - inputs[0]
    way = inputs[0] + offsets
    start, end = (way[0], way[-1]) if span is None else span
    values, index = _values(start, np.append(way, end))
    try:
        res = mechanism.sweep(values)
    except PlanarError as e:
        raise type(e)(f"checking the design {design}: {e}") from None
    index = index[:-1]
    defects += _sweep_defects(res)
    achieved = achieve(res, index)
    errors = error(achieved, np.asarray(targets, float))
    if exact:
        off = np.max(np.asarray(errors, float).reshape(len(index), -1), axis=1) / size
        for k in np.flatnonzero(off > MISSED):
            defects.append(f"target {k + 1} missed by {off[k]:.3g} of the targets' size: the design reaches it "
                           f"only off the branch it is built on (another assembly mode: a circuit defect)")
    return Synthesis(mechanism, builder, dict(design), way, np.asarray(targets, float), achieved, errors, res,
                     index, tuple(defects), float(size), point)


def _values(u0, targets):
    """Input values from u0 through each target value in order, no step above STEP; and the
    index of each target among them."""
    travel = np.sum(np.abs(np.diff(np.r_[u0, targets])))
    if not travel <= MAX_TRAVEL:  # (inputs 1e9 rad apart asked for 1e10 values: a MemoryError, or a hang)
        raise InputError(f"the design is checked by a sweep from input {u0:.6g} rad through the targets' inputs in "
                         f"order, {travel:.3g} rad of travel, more than {MAX_TRAVEL / (2 * np.pi):g} turns: give "
                         f"inputs within a turn or two of each other")
    values, index, here = [np.array([u0])], [], u0
    for t in targets:
        n = max(1, int(np.ceil(abs(t - here) / STEP)))
        values.append(np.linspace(here, t, n + 1)[1:] if t != here else np.array([]))
        here = t
        index.append(sum(len(v) for v in values) - 1)
    return np.concatenate(values), np.array(index)


def _sweep_defects(res):
    """What makes the swept design useless over its required input range."""
    out = []
    bad = np.flatnonzero(~VALID[res.status])
    if bad.size:
        u = res.inputs[bad[0], 0]
        out.append(f"not assemblable over the required input range: {Status(res.status[bad[0]]).name} at input "
                   f"{u:.6g} rad ({bad.size} of {len(res)} values)")
    for e in res.events:
        if e.kind in DEFECT_EVENTS:
            out.append(f"branch event between the targets: a {e.kind} position at input {float(np.ravel(e.input)[0]):.6g} rad")
    branch = res.branch
    branch = branch[np.isfinite(branch) & (branch != 0)]
    if branch.size and np.any(np.sign(branch) != np.sign(branch[0])):
        out.append("change of circuit between the targets: the assembly mode flips")
    return out
