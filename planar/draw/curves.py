"""Curves against the input: panels of outputs ("kind:name", :data:`planar.analysis.outputs.OUTPUTS`),
driving efforts and joint forces."""

import numpy as np

from planar.analysis.outputs import OUTPUTS, output_values, specs
from planar.analysis.ranges import runs
from planar.draw.style import EVENT_MARK, PATH_COLOURS, as_axes, drawn, flag, pyplot
from planar.errors import InputError
from planar.kinetostatics import as_forces
from planar.model import Model
from planar.results import POSED, as_sweep
from planar.units import given


def default_outputs(model):
    """Outputs worth plotting for any mechanism ("kind:name", :data:`planar.analysis.outputs.OUTPUTS`):
    every moving body's angle, rate and acceleration, every slider's or slot's travel and its
    rates, and the speed and acceleration of the user-named points."""
    if not isinstance(model, Model):
        raise InputError(f"default_outputs needs a Model (Mechanism.compile(), or a sweep's .model), got "
                         f"{type(model).__name__}")
    joint_names = {j.name for j in model.joints}
    named = [n for n in model.points if n not in joint_names]
    return (specs(model, ("angle", "omega", "alpha", "travel", "travel_rate", "travel_accel"))
            + specs(model, ("speed", "accel"), named))


def input_axis(res, units=None):
    """The first input over the sweep in display units, and its axis label."""
    res, units = as_sweep(res, "input_axis"), given(units)
    m = res.model
    is_len = bool(m.input_lengths[0])
    x = units.input_from_internal(np.asarray(res.inputs[:, 0]), is_len)
    unit = units.input_label(is_len)
    return np.asarray(x, float), f"input {m.input_names[0]}" + (f" [{unit}]" if unit else "")


def plot_outputs(res, outputs=None, *, ax=None, units=None, events=True):
    """Panels of outputs against the input: one panel per kind of output (angles, angular
    velocities, slider travel, point speeds, ...), one curve per body, joint or point.

    ``outputs`` lists ``"kind:name"`` specs (default :func:`default_outputs`); ``ax`` is a
    sequence with one axes per panel, or None for a new figure. Inputs that do not assemble are
    shaded; the sweep's events (limit and singular positions) are marked with vertical lines.
    Returns the list of axes, one per panel.
    """
    res, units = as_sweep(res, "plot_outputs"), given(units)
    events = flag(events, "plot_outputs events")
    if isinstance(outputs, str):  # (one output: not its letters)
        outputs = [outputs]
    try:
        outputs = list(outputs) if outputs is not None else default_outputs(res.model)
    except TypeError:  # (no list: refused below, by name)
        outputs = [outputs]
    if not outputs:
        raise InputError("plot_outputs needs at least one output 'kind:name'")
    panels = {}
    for spec in outputs:
        if not isinstance(spec, str) or spec.partition(":")[0] not in OUTPUTS:
            raise InputError(f"unknown output {spec!r}: outputs are 'kind:name', the kinds {', '.join(OUTPUTS)}")
        panels.setdefault(spec.partition(":")[0], []).append(spec)
    if ax is None:
        # at most 9 inches tall, to fit a screen whatever the number of panels
        fig, ax = pyplot().subplots(len(panels), 1, sharex=True, figsize=(7, min(1.9 * len(panels) + 0.8, 9.0)),
                                     layout="constrained", squeeze=False)
        fig.suptitle(f"{res.model.name}: outputs against the input", fontsize=11)
    axes = np.array([as_axes(a) for a in np.asarray(ax, dtype=object).ravel()], dtype=object)
    if axes.size != len(panels):
        raise InputError(f"plot_outputs needs {len(panels)} axes (one per kind of output), got {axes.size}")
    x, xlabel = input_axis(res, units)
    m = res.model
    events_at = [(float(units.input_from_internal(np.ravel(e.input)[0], bool(m.input_lengths[0]))), e.kind)
                 for e in res.events] if events else []
    bad = ~POSED[np.asarray(res.status)]
    for a, (kind, panel) in zip(axes, panels.items()):
        title, unit_kind = OUTPUTS[kind].title, OUTPUTS[kind].unit
        for k, spec in enumerate(panel):
            a.plot(*drawn(res, x, output_values(res, spec, units)), lw=1.6,
                   color=PATH_COLOURS[k % len(PATH_COLOURS)], label=spec.partition(":")[2])
        unit = units.label(unit_kind)
        a.set_ylabel(f"{title}" + (f"\n[{unit}]" if unit else ""), fontsize=9)
        for at, kind in events_at:
            a.axvline(at, color=EVENT_MARK[kind][1], lw=0.9, ls=":")
        for lo, hi in runs(bad):
            a.axvspan(x[lo], x[hi], color="#bbbbbb", alpha=0.35, lw=0)
        a.grid(True, color="#e6e6e6", lw=0.6)
        a.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
        for side in ("top", "right"):
            a.spines[side].set_visible(False)
    axes[-1].set_xlabel(xlabel)
    return list(axes)


def plot_forces(forces, *, units=None):
    """Two panels against the first input: each driver's effort (torque or force), and the
    size of each joint's reaction force. Returns the array of the two axes."""
    res, units = as_forces(forces, "plot_forces").sweep, given(units)
    m = res.model
    fig, axes = pyplot().subplots(2, 1, sharex=True, figsize=(7, 5.0), layout="constrained")
    fig.suptitle(f"{m.name}: driving efforts and joint forces against the input", fontsize=11)
    x, xlabel = input_axis(res, units)
    for k, (d, is_len) in enumerate(zip(m.input_names, m.input_lengths)):
        unit = units.label("force" if is_len else "moment")
        axes[0].plot(*drawn(res, x, forces.driver_effort(d)), lw=1.6, color=PATH_COLOURS[k % len(PATH_COLOURS)],
                     label=f"{d} [{unit}]")
    for k, j in enumerate(forces.reactions):
        axes[1].plot(*drawn(res, x, np.hypot(*forces.reaction(j).T)), lw=1.4, color=PATH_COLOURS[k % len(PATH_COLOURS)],
                     ls="-" if k < len(PATH_COLOURS) else "--", label=j)
    axes[0].set_ylabel("driver effort", fontsize=9)
    axes[1].set_ylabel(f"reaction force\n[{units.label('force')}]", fontsize=9)
    for a in axes:
        a.grid(True, color="#e6e6e6", lw=0.6)
        a.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
        for side in ("top", "right"):
            a.spines[side].set_visible(False)
    axes[1].set_xlabel(xlabel)
    return axes
