"""Animations of a sweep: GIF through pillow (always there with matplotlib), MP4 when ffmpeg is
installed; the paths of chosen points are traced as the mechanism moves.

>>> import numpy as np, tempfile, pathlib
>>> from planar.mechanisms import four_bar
>>> from planar.animate import animate
>>> res = four_bar(coupler_point=(2.0, 0.5)).sweep(np.linspace(0, 2 * np.pi, 13))
>>> out = animate(res, pathlib.Path(tempfile.mkdtemp()) / "four_bar.gif", fps=10)
>>> out.stat().st_size > 0
True
"""

import os
from numbers import Real
from pathlib import Path

import numpy as np

from planar.draw.pose import path_points, pose_title
from planar.draw.scene import Scene
from planar.draw.style import PATH_COLOURS, SAME, TINY, figure_size, finish, flag, thinned
from planar.errors import InputError, WriteError
from planar.results import as_sweep
from planar.units import given


MAX_FRAMES, DPI, FPS = 2000, (20, 1200), (1, 100)  # the bounds of max_frames, dpi and fps


def ffmpeg_available():
    """True when matplotlib finds an ffmpeg to write MP4 files with."""
    from matplotlib import animation

    return animation.writers.is_available("ffmpeg")


def frame_indices(res, max_frames=120, rocking=False):
    """Indices of the poses to show: the poses with valid positions, every k-th of them for the
    smallest k that gives at most ``max_frames`` (evenly spaced in the sweep's values), the last
    left out when it repeats the first (a whole turn: the animation loops back to it); with
    ``rocking``, forwards then back (an input that swings to and fro).

    >>> from planar.mechanisms import four_bar
    >>> res = four_bar().sweep(np.radians(np.arange(0.0, 361.0, 5.0)))   # 73 values, 0 to 360 deg
    >>> np.degrees(res.inputs[frame_indices(res, 60), 0]).round(6)[[0, 1, 2, -1]].tolist()
    [0.0, 10.0, 20.0, 350.0]
    """
    if isinstance(max_frames, bool) or not isinstance(max_frames, (int, np.integer)) or max_frames < 1:
        raise InputError(f"max_frames must be a whole number of at least 1, got {max_frames!r}")
    rocking = flag(rocking, "rocking")
    q = np.asarray(res.q)
    drawable = np.flatnonzero(np.all(np.isfinite(q), axis=1))
    if drawable.size == 0:
        raise InputError("no pose of this sweep solved: nothing to animate (check the input range)")
    if drawable.size > 2 and not rocking and _same_pose(res.model, q[drawable[0]], q[drawable[-1]]):
        drawable = drawable[:-1]
    drawable = drawable[:: -(-drawable.size // max_frames)]
    if rocking and drawable.size > 2:
        drawable = np.r_[drawable, drawable[-2:0:-1]]
    return drawable


def animate(res, path, *, points=None, fps=20, max_frames=120, rocking=False, trace=True, dpi=80,
            size=(7.0, 5.0), units=None, progress=None):
    """Write an animation of sweep ``res`` to ``path`` (.gif, or .mp4 when ffmpeg exists).

    Parameters
    ----------
    points : list of str, optional
        Points whose paths are traced (default: the user-named points, or every moving point).
    fps, max_frames, dpi, size :
        Frames per second, at most this many frames (the sweep is thinned evenly), resolution
        and figure size in inches.
    rocking : bool
        Play the poses forwards and then back, for inputs that swing rather than turn.
    trace : bool
        Draw each path up to the current pose over a faint full path.
    units : planar.units.Units, optional
        Axis and title units.
    progress : callable, optional
        Called as ``progress(done, total)`` after each frame.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    import matplotlib.pyplot as plt
    from matplotlib import animation

    res, units = as_sweep(res, "animate"), given(units)
    for name, v, (lo, hi) in (("fps", fps, FPS), ("dpi", dpi, DPI), ("max_frames", max_frames, (2, MAX_FRAMES))):
        whole = isinstance(v, (int, np.integer)) or name != "max_frames"
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, Real) or not whole or not lo <= v <= hi:
            raise InputError(f"animate {name} must be a {'whole ' if name == 'max_frames' else ''}number from {lo} "
                             f"to {hi}, got {v!r}")
    size, trace = figure_size(size, "animate"), flag(trace, "animate trace")
    if progress is not None and not callable(progress):
        raise InputError(f"animate progress must be a function progress(done, total), got {progress!r}")
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"animate writes to a file path (.gif or .mp4), got {path!r}")
    path = Path(path)
    if "\x00" in str(path):  # (no system names a file so: checked before the frames are drawn)
        raise InputError(f"cannot write an animation to {str(path)!r}: a file name cannot hold a NUL byte "
                         f"('\\x00'); name the file without it")
    kind = path.suffix.lower()
    if kind not in (".gif", ".mp4"):
        raise InputError(f"cannot write an animation to {path.name!r}: use a .gif or .mp4 file name")
    if kind == ".mp4" and not ffmpeg_available():
        raise InputError("writing .mp4 needs ffmpeg, which was not found: install it, or write a .gif")
    frames = frame_indices(res, max_frames, rocking)
    scene = Scene(res)
    names = path_points(res, points) if trace else []
    paths = [res.position(n) for n in names]
    # the paths as drawn: at most DRAWN values, every frame's among them (a trace ends at its pose)
    kept = thinned(np.all([np.isfinite(p).all(axis=1) for p in paths], axis=0), keep=frames) if paths else None
    paths = [p[kept] for p in paths]

    fig, ax = plt.subplots(figsize=size, layout="constrained")
    for k, (n, p) in enumerate(zip(names, paths)):
        ax.plot(p[:, 0], p[:, 1], color=PATH_COLOURS[k % len(PATH_COLOURS)], lw=0.8, alpha=0.35, zorder=1.7)
    _fix_limits(ax, scene, frames)
    finish(ax, units)
    _fit_figure(fig, ax, size)
    ax.set_aspect("equal", adjustable="box")
    ax.set_autoscale_on(False)
    ax.set_axis_off()  # as the seeds' animations: the mechanism alone, and faster frames
    traces = [ax.plot([], [], color=PATH_COLOURS[k % len(PATH_COLOURS)], lw=1.8, zorder=1.8,
                      label=f"path of {n}")[0] for k, n in enumerate(names)]
    if 0 < len(names) <= 8:
        ax.legend(loc="upper right", fontsize=8, frameon=False)
    shown = []

    def update(f):
        for a in shown:
            a.remove()
        shown.clear()
        i = frames[f]
        shown.extend(scene.draw(ax, i))
        ax.set_title(pose_title(scene, i, units))
        # the trace: every pose of the sweep up to the furthest one shown so far
        upto = np.searchsorted(kept, frames[: f + 1].max() + 1) if paths else 0
        for line, p in zip(traces, paths):
            line.set_data(p[:upto, 0], p[:upto, 1])

    writer = animation.PillowWriter(fps=fps) if kind == ".gif" else animation.FFMpegWriter(fps=fps)
    try:
        with writer.saving(fig, path, dpi):
            for f in range(len(frames)):
                update(f)
                writer.grab_frame()
                if f == 0:  # the layout is settled: keep it rather than redo it every frame
                    fig.set_layout_engine("none")
                if progress:
                    progress(f + 1, len(frames))
    except OSError as e:  # (a missing folder, no permission, a full disk)
        raise WriteError(e.errno, e.strerror or str(e), str(path)) from None
    finally:
        plt.close(fig)
    return path


def _same_pose(model, a, b):
    """Whether poses a and b (n,) put every body at the same place (angles modulo a turn)."""
    d = (b - a).reshape(-1, 3)
    d[:, 2] = np.angle(np.exp(1j * d[:, 2]))
    return bool(np.all(np.abs(d[:, :2]) <= SAME * model.L) and np.all(np.abs(d[:, 2]) <= SAME))


def _fit_figure(fig, ax, size):
    """Keep the width, and make the height fit the drawing's proportions (no wide margins)."""
    box = ax.dataLim
    pad = 0.06 * max(box.width, box.height)
    ax.set_xlim(box.x0 - pad, box.x1 + pad)
    ax.set_ylim(box.y0 - pad, box.y1 + pad)
    ratio = (box.height + 2 * pad) / max(box.width + 2 * pad, TINY)
    fig.set_size_inches(size[0], float(np.clip(size[0] * ratio + 0.5, 0.4 * size[0], 1.2 * size[0])))


def _fix_limits(ax, scene, frames):
    """Axis limits that hold every frame: draw a few poses spread over the sweep, keep the
    data limits, remove them."""
    picks = frames[np.unique(np.linspace(0, len(frames) - 1, min(len(frames), 9)).round().astype(int))]
    for i in picks:
        for a in scene.draw(ax, i):
            a.remove()
    # removing artists does not shrink the data limits: they now hold every pose drawn
