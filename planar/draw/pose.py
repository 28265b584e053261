"""Pictures of poses: the mechanism, paths of points, velocity, acceleration and force arrows,
instant centres, and the poses of a sweep's events."""

import numpy as np

from planar.draw.scene import Scene, pose_index, world
from planar.draw.style import (ACCELERATION, EVENT_MARK, FORCE, PATH_COLOURS, SAME, STILL, VELOCITY, drawn, figure_size,
                               finish, flag, new_axes, pyplot)
from planar.arguments import finite_number
from planar.errors import InputError
from planar.kinetostatics import as_forces
from planar.results import as_sweep
from planar.units import given


# ---- public drawing functions -----------------------------------------------------------------


def draw(source, i=0, *, ax=None, labels=True, units=None, title=None):
    """Draw a mechanism in one pose.

    Parameters
    ----------
    source : Sweep, Model or Mechanism
        A sweep result (pose ``i``), or a model or mechanism (its assembled sketch).
    i : int
        Index of the pose in the sweep.
    labels : bool
        Label the named points and joints.
    units : planar.units.Units, optional
        Labels the axes with the length unit.
    title : str, optional
        Defaults to the mechanism's name and the input values of the pose.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax)
    scene = source if isinstance(source, Scene) else Scene(source, labels=flag(labels, "draw labels"))
    scene.draw(ax, i)
    ax.set_title(title if title is not None else pose_title(scene, i, given(units)))
    return finish(ax, units)


def figure(res, i=0, points=None, *, paths=True, vectors=True, ax=None, units=None, size=(7.0, 5.5)):
    """The usual picture of a sweep: pose ``i``, the paths of ``points`` over the sweep and
    their velocity and acceleration arrows at pose i (see :func:`draw`, :func:`draw_paths`,
    :func:`draw_vectors`). Returns the axes; save it with ``ax.figure.savefig(...)``."""
    size, paths, vectors = figure_size(size, "figure"), flag(paths, "figure paths"), flag(vectors, "figure vectors")
    if ax is None:
        _, ax = pyplot().subplots(figsize=size, layout="constrained")
    draw(res, i, ax=ax, units=units)
    if paths:
        draw_paths(res, points, ax=ax, units=units)
    if vectors:
        draw_vectors(res, i, points, ax=ax, units=units)
    return ax


def pose_title(scene, i, units):
    m = scene.model
    u = m.u0 if scene.sweep is None else scene.sweep.inputs[i]
    parts = [f"{n} = {_fmt(units.input_from_internal(v, ln))} {units.input_label(ln)}".rstrip()
             for n, v, ln in zip(m.input_names, u, m.input_lengths)]
    return f"{m.name}: " + ", ".join(parts) if parts else m.name


def _fmt(v):
    return f"{float(v):.4g}"


def path_points(res, points):
    """The points to trace: as given, else the user-named points, else every labelled joint
    point that moves over the sweep."""
    if points is not None:
        return _names(points, res.model.points, "points to trace")
    model = res.model
    joint_names = {j.name for j in model.joints}
    own = [n for n in model.points if n not in joint_names]
    if own:
        return own
    shown = {j.name for j in model.joints if j.labelled}
    scale = Scene(res, labels=False).L
    return [n for n in model.points if n in shown and model.points[n][0] != 0
            and _span(res.position(n)) > STILL * scale]


def _names(given, known, what):
    """``given`` (a name or a list of names) as a list, each one of ``known``, else an InputError
    headed ``what``."""
    try:
        names = [given] if isinstance(given, str) else list(given)
    except TypeError:
        names = [given]
    if not names or not all(isinstance(n, str) and n in known for n in names):
        raise InputError(f"{what}: name one or more of {sorted(known)}, got {names!r}")
    return names


def _span(p):
    """Largest coordinate range of the finite rows of p (N, 2); 0 when none."""
    p = p[np.all(np.isfinite(p), axis=1)]
    return float(np.ptp(p, axis=0).max()) if len(p) else 0.0


def draw_paths(res, points=None, *, ax=None, events=True, units=None):
    """Paths of named points over a sweep (coupler curves), with limit and singular positions
    marked on them.

    ``points`` defaults to the user-named points (or, when there are none, every point on a
    moving body). Unsolved stretches of the sweep leave gaps. Returns the axes.
    """
    res, ax, events = as_sweep(res, "draw_paths"), new_axes(ax), flag(events, "draw_paths events")
    for k, name in enumerate(path_points(res, points)):
        p = res.position(name)
        ax.plot(*drawn(res, p[:, 0], p[:, 1]), color=PATH_COLOURS[k % len(PATH_COLOURS)], lw=1.5, ls="--",
                label=f"path of {name}", zorder=1.8)
        if events:
            b, s = res.model.points[name]
            for e in _posed_events(res):
                marker, colour = EVENT_MARK[e.kind]
                ax.plot(*world(np.asarray(e.q), b, s), marker, ms=7, color=colour, mec="white", zorder=6)
    if events:
        for kind in sorted({e.kind for e in _posed_events(res)}):
            marker, colour = EVENT_MARK[kind]
            ax.plot([], [], marker, ms=7, color=colour, mec="white", ls="none", label=kind.replace("_", "-") + " position")
    _legend_below(ax)
    return finish(ax, units)


def _posed_events(res):
    """The sweep's events (limit positions, bifurcations, singular positions, near-singular
    stretches: :class:`planar.events.Event`) that carry their pose."""
    return [e for e in res.events if e.q is not None and np.all(np.isfinite(e.q))]


def arrow_scale(vectors, L):
    """Length units per unit of the quantity: the longest arrow a quarter of the drawing."""
    mags = np.hypot(vectors[..., 0], vectors[..., 1])
    top = np.nanmax(mags) if np.any(np.isfinite(mags)) else 0.0
    with np.errstate(over="ignore"):  # (subnormal arrows: drawn at 1 rather than an infinite scale)
        s = 0.25 * L / top if top > 0 else 1.0
    return float(s) if np.isfinite(s) else 1.0


def draw_vectors(res, i=0, points=None, *, ax=None, velocity=True, acceleration=True, scale=None,
                 units=None):
    """Velocity (blue) and acceleration (red) arrows on named points at pose ``i``, as the seeds
    draw them on open chains.

    ``points`` defaults to every named point on a moving body. ``scale`` is
    (velocity scale, acceleration scale) in drawing lengths per unit of the quantity; by
    default the longest arrow of each kind is a quarter of the drawing. The legend states the
    scales. Returns the axes.
    """
    ax = new_axes(ax)
    res, units = as_sweep(res, "draw_vectors"), given(units)
    i = pose_index(res, i)
    if scale is not None and not (isinstance(scale, (tuple, list)) and len(scale) == 2
                                  and all(_scale(s) for s in scale)):
        raise InputError(f"draw_vectors scale must be (velocity scale, acceleration scale), two positive numbers, "
                         f"got {scale!r}")
    velocity, acceleration = flag(velocity, "draw_vectors velocity"), flag(acceleration, "draw_vectors acceleration")
    names = (_names(points, res.model.points, "draw_vectors points") if points is not None
             else [n for n, (b, _) in res.model.points.items() if b != 0])
    P = np.array([res.position(n)[i] for n in names]).reshape(-1, 2)
    L = Scene(res, labels=False).L
    length = units.length or "length unit"
    kinds = [(velocity, res.velocity, VELOCITY, "velocity", units.label("speed")),
             (acceleration, res.acceleration, ACCELERATION, "acceleration", units.label("accel"))]
    for k, (on, get, colour, what, unit) in enumerate(kinds):
        if not on:
            continue
        V = np.array([get(n)[i] for n in names]).reshape(-1, 2)
        s = scale[k] if scale is not None else arrow_scale(V, L)
        _arrows(ax, P, V, s, "draw_vectors", colour, f"{what}: 1 {length} = {_fmt(1 / s)} {unit}")
    _legend_below(ax)
    return finish(ax, units)


def _arrows(ax, P, V, s, who, colour, label):
    """Arrows ``V * s`` from points ``P`` (each (k, 2)); an InputError naming ``who``'s scale where
    it takes them beyond float64."""
    with np.errstate(over="ignore", invalid="ignore"):  # (checked just below)
        D = V * s
        tips = P + D
    if np.any(np.isinf(tips) & np.isfinite(V)):
        raise InputError(f"{who} scale {s!r} draws arrows beyond float64's largest number: give a smaller scale")
    ax.quiver(P[:, 0], P[:, 1], D[:, 0], D[:, 1], angles="xy", scale_units="xy", scale=1, color=colour, width=0.006,
              zorder=7, label=label)
    ax.update_datalim(tips[np.all(np.isfinite(tips), axis=1)])


def _scale(s):
    """Whether ``s`` is an arrow scale: a positive finite number."""
    return finite_number(s) and s > 0


def _legend_below(ax):
    """The legend under the drawing, out of the mechanism's way."""
    n = len(ax.get_legend_handles_labels()[1])
    if 0 < n <= 8:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=min(n, 2), fontsize=8, frameon=False)


def draw_instant_centres(source, i=0, *, ax=None, loci=False, units=None):
    """Instant centres as labelled crossed circles.

    ``source`` is a sweep result (every centre of every pair of bodies at pose ``i``, from
    :func:`planar.analysis.instant_centres`, labelled the textbook way: I13 for the ground,
    numbered 1, and the second moving body, numbered 3) or a mapping of labels to points
    (x, y). Centres at infinity (relative translation) are listed in a note. With ``loci``
    (sweeps only), the paths of the centres that move are drawn too. Returns the axes.
    """
    ax, loci = new_axes(ax), flag(loci, "draw_instant_centres loci")
    paths = {}
    if not isinstance(source, dict):
        from planar.analysis import instant_centres

        source = as_sweep(source, "draw_instant_centres (or a dict of labels to points)")
        i = pose_index(source, i)
        names = source.model.body_names
        paths = {f"I{names.index(a) + 1}{names.index(b) + 1}": p for (a, b), p in instant_centres(source).items()}
        centres = {k: p[i] for k, p in paths.items()}
    else:
        centres = source
    far = []
    # loci run off to infinity where lines turn parallel: keep them near what is drawn already
    box = ax.dataLim if np.all(np.isfinite(ax.dataLim.bounds)) else None
    for label, p in centres.items():
        p = np.asarray(p, float)
        if loci and label in paths and _span(paths[label]) > SAME:  # (no scene here: a centre that moves at all)
            path = paths[label]
            if box is not None:
                pad = max(box.width, box.height)
                out = ((path[:, 0] < box.x0 - pad) | (path[:, 0] > box.x1 + pad)
                       | (path[:, 1] < box.y0 - pad) | (path[:, 1] > box.y1 + pad))
                path = np.where(out[:, None], np.nan, path)
            ax.plot(*drawn(source, *path.T), color="#7b3294", lw=0.9, ls="-.", alpha=0.6, zorder=1.6)
        if not np.all(np.isfinite(p)):
            far.append(label)
            continue
        ax.plot(*p, "o", ms=9, mfc="none", mec="#7b3294", mew=1.5, zorder=6)
        ax.plot(*p, "+", ms=9, color="#7b3294", mew=1.5, zorder=6)
        ax.annotate(label, p, textcoords="offset points", xytext=(6, -12), color="#7b3294", fontsize=9, zorder=6)
        ax.update_datalim([p])
    if far:
        ax.text(0.01, 0.01, "at infinity: " + ", ".join(far), transform=ax.transAxes, fontsize=8, color="#7b3294")
    return finish(ax, units)


def draw_event_poses(res, *, ax=None, units=None):
    """The mechanism drawn in dotted outline at each event of a sweep (limit positions,
    bifurcations, singular positions, in the colours of :data:`EVENT_MARK`). Returns the axes."""
    res, ax = as_sweep(res, "draw_event_poses"), new_axes(ax)
    scene = Scene(res, labels=False)
    for e in _posed_events(res):
        q = np.asarray(e.q)
        for b in range(1, len(res.model.body_names)):
            pts = scene.body_outline(q, b)
            if len(pts) >= 2:
                closed = np.vstack([pts, pts[:1]]) if len(pts) > 2 else pts
                ax.plot(*closed.T, color=EVENT_MARK[e.kind][1], lw=1.2, ls=":", zorder=1.6)
    return finish(ax, units)



def draw_forces(forces, i=0, joints=None, *, ax=None, scale=None, units=None):
    """Pose ``i`` of a sweep's kinetostatics (:meth:`planar.Sweep.forces`) with the reaction
    force of each joint on its second body as an arrow at the joint's point.

    ``joints`` defaults to every joint with a point; ``scale`` is in drawing lengths per unit of
    force (by default the longest arrow is a quarter of the drawing); the legend states it.
    Returns the axes.
    """
    res, units = as_forces(forces, "draw_forces").sweep, given(units)
    if scale is not None and not _scale(scale):
        raise InputError(f"draw_forces scale must be a positive number (drawing lengths per unit of force), got {scale!r}")
    pointed = [j for j in forces.reactions if j in res.model.points]  # (joints with a point to draw at)
    names = _names(joints, pointed, "draw_forces joints") if joints is not None else pointed
    ax = draw(res, i, ax=ax, units=units)
    P = np.array([res.position(n)[i] for n in names]).reshape(-1, 2)
    V = np.array([forces.reaction(n)[i] for n in names]).reshape(-1, 2)
    s = scale if scale is not None else arrow_scale(V, Scene(res, labels=False).L)
    _arrows(ax, P, V, s, "draw_forces", FORCE,
            f"joint reactions: 1 {units.length or 'length unit'} = {_fmt(1 / s)} {units.label('force')}")
    _legend_below(ax)
    return finish(ax, units)
