"""Textbook figures of any mechanism, drawn from its compiled model and a sweep.

Nothing here knows a mechanism by name. A body is drawn as a bar between its joint points (two
points) or a plate over them (three or more); each joint draws its own parts from the body-fixed
numbers the solver uses (the model's joint parameters): pins, hatched ground pivots, slider blocks
on guide lines, slots, gears as pitch circles with a mark that turns with them, racks as toothed
lines: each joint class draws its own part (:meth:`planar.joints.Joint.draw_part`) with the
primitives of a :class:`Scene`.

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

import numpy as np

from planar.analysis.outputs import OUTPUTS, output_values, specs
from planar.analysis.ranges import runs
from planar.errors import InputError
from planar.geometry import cross, rotate
from planar.results import POSED, Status
from planar.units import Units



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
EVENT_MARK = {"limit": ("s", "#d62728"), "bifurcation": ("D", "#9467bd"), "singular": ("X", "#000000"),
              "near_singular": ("^", "#ff7f0e")}


def _pyplot():
    import matplotlib.pyplot as plt

    return plt


def _axes(ax):
    if ax is None:
        _, ax = _pyplot().subplots(figsize=(7, 5), layout="constrained")
    return ax


# ---- poses: body-fixed vectors to world coordinates ------------------------------------------


def _frame(q, b):
    """(r, phi) of body b over q (..., n); the ground is the identity."""
    if b == 0:
        return np.zeros(q.shape[:-1] + (2,)), np.zeros(q.shape[:-1])
    return q[..., 3 * b - 3: 3 * b - 1], q[..., 3 * b - 1]


def _world(q, b, s):
    """World position of the body-fixed point s (2,) of body b at poses q (..., n)."""
    r, phi = _frame(q, b)
    return r + rotate(phi, np.asarray(s, float))


def _turn(q, b, u):
    """World direction of the body-fixed vector u of body b."""
    return rotate(_frame(q, b)[1], np.asarray(u, float))


def _local(q, b, p):
    """Body-fixed coordinates in body b of the world point p at poses q."""
    r, phi = _frame(q, b)
    return rotate(-phi, p - r)


def _joint_params(model):
    """Each joint's body-fixed parameters, exactly as the compiled system holds them."""
    out = {}
    for g in model.system.groups:
        for k, i in enumerate(g.members):
            if i < len(model.joints):
                out[model.joints[i].name] = {key: v[k] for key, v in g.P.items()}
    return out


# ---- the scene: one mechanism, any pose ------------------------------------------------------


def _source(source):
    """(model, sweep or None) from a Sweep, a Model or a Mechanism."""
    if hasattr(source, "status") and hasattr(source, "model"):
        return source.model, source
    if hasattr(source, "compile"):
        source = source.compile()
    if hasattr(source, "q0") and hasattr(source, "system"):
        return source, None
    raise InputError(f"cannot draw a {type(source).__name__}: give a sweep result, a Model or a Mechanism")


class Scene:
    """A mechanism ready to draw at any pose of a sweep (or its sketch): joint parameters,
    body attachment points and guide-line extents are worked out once.

    ``Scene(source)`` takes a sweep result, a Model or a Mechanism; ``scene.draw(ax, i)`` draws
    pose i (the sketch when there is no sweep) and returns the artists it made.
    """

    def __init__(self, source, *, labels=True):
        self.model, self.sweep = _source(source)
        self.labels = labels
        m = self.model
        self.params = _joint_params(m)
        qs = self.poses()
        finite = qs[np.all(np.isfinite(qs), axis=1)]
        # size of the drawing: the span of every named point over the sweep
        pts = np.concatenate([_world(finite, b, s) for b, s in m.points.values()]) if m.points else np.zeros((1, 2))
        span = np.ptp(pts, axis=0).max() if len(pts) > 1 else 0.0
        self.L = float(span) if span > 0 else float(m.L)
        self.size = 0.035 * self.L
        self.block = (0.065 * self.L, 0.04 * self.L)  # half length, half height of slider blocks
        self.colours = {b: FILLS[(b - 1) % len(FILLS)] for b in range(1, len(m.body_names))}
        self._ends = {}
        for j in m.joints:
            line = j.guide_line(self, self.params[j.name])
            if line is not None:
                self._ends[j.name] = self._extent(finite, *line)
        self.attach = {b: [] for b in range(len(m.body_names))}
        for j in m.joints:
            for b, s in j.attach(self, self.params[j.name]):
                self.attach[b].append(np.asarray(s, float))
        joint_names = {j.name for j in m.joints}
        self.user_points = [n for n in m.points if n not in joint_names]
        unlabelled = {j.name for j in m.joints if not j.labelled}
        self.labelled = [n for n in m.points if n not in unlabelled]
        for n in self.user_points:
            b, s = m.points[n]
            self.attach[b].append(np.asarray(s, float))

    def poses(self):
        """(N, n) poses: the sweep's, or the sketch alone."""
        return self.model.q0[None] if self.sweep is None else np.asarray(self.sweep.q)

    def pose(self, i):
        if self.sweep is None:
            return self.model.q0
        q = np.asarray(self.sweep.q[i])
        if not np.all(np.isfinite(q)):
            raise InputError(f"pose {i} did not solve (status {Status(self.sweep.status[i]).name}): "
                             f"draw a pose where the sweep is valid")
        return q

    def _extent(self, qs, a, s_a, u, runner, pad):
        """Body-fixed ends of a guide line of body a: where the runner goes over the sweep, padded."""
        b, s_b = runner
        t = np.einsum("...i,i->...", _local(qs, a, _world(qs, b, s_b)) - s_a, u)
        lo, hi = (float(t.min()), float(t.max())) if t.size else (0.0, 0.0)
        lo, hi = lo - pad - self.size, hi + pad + self.size
        return (s_a + lo * u, s_a + hi * u)

    def line_ends(self, name):
        """Body-fixed ends of the guide line or rack of joint ``name``."""
        return self._ends[name]

    def ids(self, joint):
        """Body ids of a joint's bodies."""
        return [self.model.body_id(b) for b in joint.bodies]

    world, turn, local = staticmethod(_world), staticmethod(_turn), staticmethod(_local)

    def colour(self, b):
        return self.colours.get(b, "white")

    # ---- primitives (data units scale with the drawing) ------------------------------------

    def bar(self, ax, pts, colour):
        x, y = np.asarray(pts).T
        edge, = ax.plot(x, y, color=EDGE, lw=7.5, solid_capstyle="round", solid_joinstyle="round", zorder=3)
        fill, = ax.plot(x, y, color=colour, lw=5.0, solid_capstyle="round", solid_joinstyle="round", zorder=3.1)
        return [edge, fill]

    def plate(self, ax, pts, colour):
        from matplotlib.patches import Polygon

        poly = Polygon(pts, closed=True, facecolor=colour, edgecolor="none", alpha=0.55, zorder=2.9)
        ax.add_patch(poly)
        return [poly] + self.bar(ax, np.vstack([pts, pts[:1]]), colour)

    def pin(self, ax, p):
        art, = ax.plot(*p, "o", ms=6.5, mfc="white", mec=EDGE, mew=1.4, zorder=5)
        return [art]

    def ground_pivot(self, ax, p):
        """A triangle under the pin standing on a hatched base."""
        from matplotlib.patches import Polygon, Rectangle

        h = 1.6 * self.size
        tri = Polygon([p, p + (-0.7 * h, -h), p + (0.7 * h, -h)], closed=True, facecolor="white",
                      edgecolor=EDGE, lw=1.3, zorder=4)
        base = Rectangle(p + (-1.1 * h, -1.45 * h), 2.2 * h, 0.45 * h, facecolor="none", edgecolor=EDGE,
                         lw=0, hatch="////", zorder=1)
        top, = ax.plot([p[0] - 1.1 * h, p[0] + 1.1 * h], [p[1] - h] * 2, color=EDGE, lw=1.4, zorder=1.1)
        ax.add_patch(tri)
        ax.add_patch(base)
        return [tri, base, top]

    def guide(self, ax, ends):
        """A ground guide: the surface the block rides on, on the right of the line (under a
        line running +x), hatched beyond."""
        from matplotlib.patches import Polygon

        e0, e1 = ends
        d = (e1 - e0) / max(np.hypot(*(e1 - e0)), 1e-300)
        n = np.array([d[1], -d[0]])
        a, b = e0 + n * self.block[1], e1 + n * self.block[1]
        k = n * 0.7 * self.size
        line, = ax.plot(*np.array([a, b]).T, color=EDGE, lw=1.4, zorder=1.5)
        band = Polygon([a, b, b + k, a + k], closed=True, facecolor="none", edgecolor=EDGE, lw=0,
                       hatch="////", zorder=1)
        ax.add_patch(band)
        return [line, band]

    def block_at(self, ax, p, u, colour):
        from matplotlib.patches import Polygon

        a, h = self.block
        n = np.array([-u[1], u[0]])
        corners = [p - a * u - h * n, p + a * u - h * n, p + a * u + h * n, p - a * u + h * n]
        blk = Polygon(corners, closed=True, facecolor=colour, edgecolor=EDGE, lw=1.4, zorder=4)
        ax.add_patch(blk)
        return [blk]

    def slot(self, ax, ends):
        """A slot: a stadium outline along the line, as wide as a pin."""
        e0, e1 = ends
        d = (e1 - e0) / max(np.hypot(*(e1 - e0)), 1e-300)
        w = 0.45 * self.size
        n = np.array([-d[1], d[0]]) * w
        t = np.linspace(-np.pi / 2, np.pi / 2, 12)
        cap1 = e1 + np.outer(np.cos(t), d) * w + np.outer(np.sin(t), n / w) * w
        cap0 = e0 - np.outer(np.cos(t), d) * w - np.outer(np.sin(t), n / w) * w
        outline = np.vstack([e0 - n, e1 - n, cap1, e1 + n, e0 + n, cap0, e0 - n])
        art, = ax.plot(*outline.T, color=EDGE, lw=1.3, zorder=3.5)
        inner, = ax.plot(*np.array([e0, e1]).T, color="white", lw=3.0, zorder=3.4, solid_capstyle="round")
        return [inner, art]

    def wheel(self, ax, q, b, s, R, ring=False):
        """A pitch circle on body b centred at s, with a radius that turns with the body."""
        from matplotlib.patches import Circle

        key = (b, round(float(s[0]), 9), round(float(s[1]), 9), round(float(R), 9))
        if key in self._wheels:  # a gear meshing with several others is drawn once
            return []
        self._wheels.add(key)
        c = _world(q, b, s)
        arts = []
        if ring:  # an annulus: the internal gear, hatched outside its pitch circle
            band = Circle(c, R * 1.12, facecolor="none", edgecolor=EDGE, lw=0, hatch="////", zorder=1.2)
            inner = Circle(c, R, facecolor="white", edgecolor=EDGE, lw=1.6, zorder=1.3)
            arts += [band, inner]
        else:
            arts.append(Circle(c, R, facecolor=self.colour(b), edgecolor=EDGE, lw=1.6, alpha=0.45, zorder=2))
        for art in arts:
            ax.add_patch(art)
        if b == 0:  # a fixed wheel or ring does not turn: no mark
            return arts
        a = self._mark_angle(b)
        mark = _world(q, b, s + R * np.array([np.cos(a), np.sin(a)]))
        rad, = ax.plot(*np.array([c, mark]).T, color=EDGE, lw=1.4, zorder=2.1)
        tip, = ax.plot(*mark, "o", ms=4, color=EDGE, zorder=2.1)
        return arts + [rad, tip]

    def _mark_angle(self, b):
        """Body-fixed angle of the rotation mark: pointing up in the sketch."""
        return np.pi / 2 - self.model.q0[3 * b - 1]

    def rack(self, ax, ends, side, hatch):
        """A pitch line with teeth on the pinion's side (``side`` +1: left of e0 -> e1)."""
        from matplotlib.patches import Polygon

        e0, e1 = ends
        length = np.hypot(*(e1 - e0))
        d = (e1 - e0) / max(length, 1e-300)
        n = side * np.array([-d[1], d[0]])
        pitch = 0.6 * self.size
        k = max(int(length / pitch), 1)
        t = np.linspace(0, length, 2 * k + 1)
        hgt = np.where(np.arange(t.size) % 2 == 1, 0.45 * pitch, -0.25 * pitch)
        teeth = e0 + np.outer(t, d) + np.outer(hgt, n)
        art, = ax.plot(*teeth.T, color=EDGE, lw=1.1, zorder=2)
        back = [e0 - 0.6 * pitch * n, e1 - 0.6 * pitch * n]
        line, = ax.plot(*np.array(back).T, color=EDGE, lw=1.4, zorder=2)
        arts = [art, line]
        if hatch:
            band = Polygon([back[0], back[1], back[1] - 0.9 * pitch * n, back[0] - 0.9 * pitch * n], closed=True,
                           facecolor="none", edgecolor=EDGE, lw=0, hatch="////", zorder=1)
            ax.add_patch(band)
            arts.append(band)
        return arts

    # ---- a whole pose ----------------------------------------------------------------------

    def body_outline(self, q, b):
        """World points of body b's bar or plate at pose q ([] for none): two ends of a bar, or
        the corners of a plate (its convex hull)."""
        pts = np.array([_world(q, b, s) for s in self.attach[b]]) if self.attach[b] else np.zeros((0, 2))
        pts = _distinct(pts, 1e-9 * self.L)
        if len(pts) < 2:
            return pts[:0]
        hull = _hull(pts)
        if len(hull) >= 3 and _area(hull) > 1e-3 * self.L**2:
            return hull
        # collinear: a bar between the two points farthest apart
        d = np.linalg.norm(pts[:, None] - pts[None], axis=-1)
        i, k = np.unravel_index(np.argmax(d), d.shape)
        return pts[[i, k]]

    def draw(self, ax, i=0):
        """Draw pose i (the sketch without a sweep); returns the artists."""
        q = self.pose(i)
        self._wheels = set()
        arts = []
        for b in range(1, len(self.model.body_names)):
            pts = self.body_outline(q, b)
            if len(pts) == 2:
                arts += self.bar(ax, pts, self.colour(b))
            elif len(pts) > 2:
                arts += self.plate(ax, pts, self.colour(b))
        for j in self.model.joints:
            arts += j.draw_part(self, self.params[j.name], q, ax)
        for n in self.user_points:
            b, s = self.model.points[n]
            p = _world(q, b, s)
            art, = ax.plot(*p, "o", ms=5, color=EDGE, zorder=5)
            arts.append(art)
        if self.labels:
            arts += self.label_points(ax, q)
        return arts

    def label_points(self, ax, q):
        """Name every labelled point next to it, away from the drawing's centre where there is
        room: each label takes the first place around its point (outwards first, then turning
        either way, then farther out) where its box meets no label placed before and no point."""
        names = self.labelled
        pts = [_world(q, *self.model.points[n]) for n in names]
        if not pts:
            return []
        pts = np.array(pts)
        centre = pts.mean(axis=0)
        h = 1.2 * self.size  # a label's height in data units (fontsize 10 at the default scale)
        taken = [np.r_[p - 0.4 * self.size, p + 0.4 * self.size] for p in pts]  # the points' markers
        arts, done = [], np.zeros(len(pts), bool)
        for k in range(len(pts)):
            if done[k]:
                continue
            same = np.flatnonzero(np.linalg.norm(pts - pts[k], axis=1) <= 1e-6 * self.L)
            done[same] = True
            text = ", ".join(names[s] for s in same)
            half = np.array([0.33 * h * len(text) + 0.2 * h, 0.5 * h])
            d = pts[k] - centre
            out = np.arctan2(d[1], d[0]) if np.hypot(*d) > 1e-9 * self.L else np.pi / 2
            places = [pts[k] + r * u + u * half
                      for r in (1.0 * self.size, 2.2 * self.size, 3.6 * self.size)
                      for t in (0, 1, -1, 2, -2, 3, -3, 4)
                      for u in [np.array([np.cos(out + t * np.pi / 4), np.sin(out + t * np.pi / 4)])]]
            at = next((c for c in places if not any(_overlap(np.r_[c - half, c + half], b) for b in taken)),
                      places[0])
            taken.append(np.r_[at - half, at + half])
            arts.append(ax.text(*at, text, ha="center", va="center", fontsize=10, fontstyle="italic", zorder=6))
            ax.update_datalim([at - half, at + half])  # keep labels inside the axes
        return arts


def _overlap(a, b):
    """Whether boxes (x0, y0, x1, y1) a and b overlap."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _distinct(pts, tol):
    keep = []
    for p in pts:
        if all(np.hypot(*(p - k)) > tol for k in keep):
            keep.append(p)
    return np.array(keep).reshape(-1, 2)


def _hull(pts):
    """Convex hull (Andrew's monotone chain), counter-clockwise."""
    P = sorted(map(tuple, pts))
    if len(P) < 3:
        return np.array(P)

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and cross(np.subtract(out[-1], out[-2]), np.subtract(p, out[-2])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(P), half(P[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _area(poly):
    x, y = poly.T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _finish(ax, units=None):
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.08)
    ax.autoscale_view()
    unit = f" [{units.length}]" if units is not None and units.length else ""
    ax.set_xlabel(f"x{unit}")
    ax.set_ylabel(f"y{unit}")
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    ax.grid(True, color="#e6e6e6", lw=0.6, zorder=0)
    ax.set_axisbelow(True)
    return ax


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
    ax = _axes(ax)
    scene = source if isinstance(source, Scene) else Scene(source, labels=labels)
    scene.draw(ax, i)
    ax.set_title(title if title is not None else _pose_title(scene, i, units or Units()))
    return _finish(ax, units)


def figure(res, i=0, points=None, *, paths=True, vectors=True, ax=None, units=None, size=(7.0, 5.5)):
    """The usual picture of a sweep: pose ``i``, the paths of ``points`` over the sweep and
    their velocity and acceleration arrows at pose i (see :func:`draw`, :func:`draw_paths`,
    :func:`draw_vectors`). Returns the axes; save it with ``ax.figure.savefig(...)``."""
    if ax is None:
        _, ax = _pyplot().subplots(figsize=size, layout="constrained")
    draw(res, i, ax=ax, units=units)
    if paths:
        draw_paths(res, points, ax=ax, units=units)
    if vectors:
        draw_vectors(res, i, points, ax=ax, units=units)
    return ax


def _pose_title(scene, i, units):
    m = scene.model
    u = m.u0 if scene.sweep is None else scene.sweep.inputs[i]
    parts = [f"{n} = {_fmt(units.input_from_internal(v, ln))} {units.input_label(ln)}".rstrip()
             for n, v, ln in zip(m.input_names, u, m.input_lengths)]
    return f"{m.name}: " + ", ".join(parts) if parts else m.name


def _fmt(v):
    return f"{float(v):.4g}"


def _path_points(res, points):
    """The points to trace: as given, else the user-named points, else every labelled joint
    point that moves over the sweep."""
    if points is not None:
        return list(points)
    model = res.model
    joint_names = {j.name for j in model.joints}
    own = [n for n in model.points if n not in joint_names]
    if own:
        return own
    shown = {j.name for j in model.joints if j.labelled}
    scale = Scene(res, labels=False).L
    return [n for n in model.points if n in shown and model.points[n][0] != 0
            and _span(res.position(n)) > 1e-6 * scale]


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
    ax = _axes(ax)
    for k, name in enumerate(_path_points(res, points)):
        p = res.position(name)
        ax.plot(*_broken(res, p[:, 0], p[:, 1]), color=PATH_COLOURS[k % len(PATH_COLOURS)], lw=1.5, ls="--",
                label=f"path of {name}", zorder=1.8)
        if events:
            b, s = res.model.points[name]
            for e in _posed_events(res):
                marker, colour = EVENT_MARK[e.kind]
                ax.plot(*_world(np.asarray(e.q), b, s), marker, ms=7, color=colour, mec="white", zorder=6)
    if events:
        for kind in sorted({e.kind for e in _posed_events(res)}):
            marker, colour = EVENT_MARK[kind]
            ax.plot([], [], marker, ms=7, color=colour, mec="white", ls="none", label=kind.replace("_", "-") + " position")
    _legend_below(ax)
    return _finish(ax, units)


def _posed_events(res):
    """The sweep's events (limit positions, bifurcations, singular positions, near-singular
    stretches: :class:`planar.events.Event`) that carry their pose."""
    return [e for e in res.events if e.q is not None and np.all(np.isfinite(e.q))]


def _arrow_scale(vectors, L):
    """Length units per unit of the quantity: the longest arrow a quarter of the drawing."""
    mags = np.hypot(vectors[..., 0], vectors[..., 1])
    top = np.nanmax(mags) if np.any(np.isfinite(mags)) else 0.0
    return 0.25 * L / top if top > 0 else 1.0


def draw_vectors(res, i=0, points=None, *, ax=None, velocity=True, acceleration=True, scale=None,
                 units=None):
    """Velocity (blue) and acceleration (red) arrows on named points at pose ``i``, as the seeds
    draw them on open chains.

    ``points`` defaults to every named point on a moving body. ``scale`` is
    (velocity scale, acceleration scale) in drawing lengths per unit of the quantity; by
    default the longest arrow of each kind is a quarter of the drawing. The legend states the
    scales. Returns the axes.
    """
    ax = _axes(ax)
    units = units or Units()
    names = points if points is not None else [n for n, (b, _) in res.model.points.items() if b != 0]
    P = np.array([res.position(n)[i] for n in names])
    L = Scene(res, labels=False).L
    length = units.length or "length unit"
    kinds = [(velocity, res.velocity, VELOCITY, "velocity", units.label("speed")),
             (acceleration, res.acceleration, ACCELERATION, "acceleration", units.label("accel"))]
    for k, (on, get, colour, what, unit) in enumerate(kinds):
        if not on:
            continue
        V = np.array([get(n)[i] for n in names])
        s = scale[k] if scale is not None else _arrow_scale(V, L)
        ax.quiver(P[:, 0], P[:, 1], V[:, 0] * s, V[:, 1] * s, angles="xy", scale_units="xy", scale=1,
                  color=colour, width=0.006, zorder=7, label=f"{what}: 1 {length} = {_fmt(1 / s)} {unit}")
        tips = P + V * s
        ax.update_datalim(tips[np.all(np.isfinite(tips), axis=1)])
    _legend_below(ax)
    return _finish(ax, units)


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
    ax = _axes(ax)
    paths = {}
    if hasattr(source, "model"):
        from planar.analysis import instant_centres

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
        if loci and label in paths and _span(paths[label]) > 1e-9:
            path = paths[label]
            if box is not None:
                pad = max(box.width, box.height)
                out = ((path[:, 0] < box.x0 - pad) | (path[:, 0] > box.x1 + pad)
                       | (path[:, 1] < box.y0 - pad) | (path[:, 1] > box.y1 + pad))
                path = np.where(out[:, None], np.nan, path)
            ax.plot(*path.T, color="#7b3294", lw=0.9, ls="-.", alpha=0.6, zorder=1.6)
        if not np.all(np.isfinite(p)):
            far.append(label)
            continue
        ax.plot(*p, "o", ms=9, mfc="none", mec="#7b3294", mew=1.5, zorder=6)
        ax.plot(*p, "+", ms=9, color="#7b3294", mew=1.5, zorder=6)
        ax.annotate(label, p, textcoords="offset points", xytext=(6, -12), color="#7b3294", fontsize=9, zorder=6)
        ax.update_datalim([p])
    if far:
        ax.text(0.01, 0.01, "at infinity: " + ", ".join(far), transform=ax.transAxes, fontsize=8, color="#7b3294")
    return _finish(ax, units)


def draw_event_poses(res, *, ax=None, units=None):
    """The mechanism drawn in dotted outline at each event of a sweep (limit positions,
    bifurcations, singular positions, in the colours of :data:`EVENT_MARK`). Returns the axes."""
    ax = _axes(ax)
    scene = Scene(res, labels=False)
    for e in _posed_events(res):
        q = np.asarray(e.q)
        for b in range(1, len(res.model.body_names)):
            pts = scene.body_outline(q, b)
            if len(pts) >= 2:
                closed = np.vstack([pts, pts[:1]]) if len(pts) > 2 else pts
                ax.plot(*closed.T, color=EVENT_MARK[e.kind][1], lw=1.2, ls=":", zorder=1.6)
    return _finish(ax, units)


# ---- panels of outputs against the input ------------------------------------------------------


def default_outputs(model):
    """Outputs worth plotting for any mechanism ("kind:name", :data:`planar.analysis.outputs.OUTPUTS`):
    every moving body's angle, rate and acceleration, every slider's or slot's travel and its
    rates, and the speed and acceleration of the user-named points."""
    joint_names = {j.name for j in model.joints}
    named = [n for n in model.points if n not in joint_names]
    return (specs(model, ("angle", "omega", "alpha", "travel", "travel_rate", "travel_accel"))
            + specs(model, ("speed", "accel"), named))


def input_axis(res, units=None):
    """The first input over the sweep in display units, and its axis label."""
    units = units or Units()
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
    units = units or Units()
    outputs = list(outputs) if outputs is not None else default_outputs(res.model)
    panels = {}
    for spec in outputs:
        panels.setdefault(spec.partition(":")[0], []).append(spec)
    if ax is None:
        # at most 9 inches tall, to fit a screen whatever the number of panels
        fig, ax = _pyplot().subplots(len(panels), 1, sharex=True, figsize=(7, min(1.9 * len(panels) + 0.8, 9.0)),
                                     layout="constrained", squeeze=False)
        fig.suptitle(f"{res.model.name}: outputs against the input", fontsize=11)
    axes = np.asarray(ax, dtype=object).ravel()
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
            a.plot(*_broken(res, x, output_values(res, spec, units)), lw=1.6,
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


def _broken(res, *series):
    """The (N,) series with a NaN put before each JUMPED value, so a line is not drawn across
    the jump.

    >>> from types import SimpleNamespace
    >>> _broken(SimpleNamespace(status=np.array([0, 0, Status.JUMPED])), np.arange(3.0))[0].tolist()
    [0.0, 1.0, nan, 2.0]
    """
    at = np.flatnonzero(np.asarray(res.status) == Status.JUMPED)
    return [np.insert(np.asarray(v, float), at, np.nan) for v in series]


# ---- kinetostatics -----------------------------------------------------------------------------

FORCE = "#2a7f3f"


def draw_forces(forces, i=0, joints=None, *, ax=None, scale=None, units=None):
    """Pose ``i`` of a sweep's kinetostatics (:meth:`planar.Sweep.forces`) with the reaction
    force of each joint on its second body as an arrow at the joint's point.

    ``joints`` defaults to every joint with a point; ``scale`` is in drawing lengths per unit of
    force (by default the longest arrow is a quarter of the drawing); the legend states it.
    Returns the axes.
    """
    res = forces.sweep
    units = units or Units()
    ax = draw(res, i, ax=ax, units=units)
    names = list(joints) if joints is not None else [j for j in forces.reactions if j in res.model.points]
    P = np.array([res.position(n)[i] for n in names]).reshape(-1, 2)
    V = np.array([forces.reaction(n)[i] for n in names]).reshape(-1, 2)
    s = scale if scale is not None else _arrow_scale(V, Scene(res, labels=False).L)
    ax.quiver(P[:, 0], P[:, 1], V[:, 0] * s, V[:, 1] * s, angles="xy", scale_units="xy", scale=1, color=FORCE,
              width=0.006, zorder=7,
              label=f"joint reactions: 1 {units.length or 'length unit'} = {_fmt(1 / s)} {units.label('force')}")
    tips = P + V * s
    ax.update_datalim(tips[np.all(np.isfinite(tips), axis=1)])
    _legend_below(ax)
    return _finish(ax, units)


def plot_forces(forces, *, units=None):
    """Two panels against the first input: each driver's effort (torque or force), and the
    size of each joint's reaction force. Returns the array of the two axes."""
    units = units or Units()
    res = forces.sweep
    m = res.model
    fig, axes = _pyplot().subplots(2, 1, sharex=True, figsize=(7, 5.0), layout="constrained")
    fig.suptitle(f"{m.name}: driving efforts and joint forces against the input", fontsize=11)
    x, xlabel = input_axis(res, units)
    for k, (d, is_len) in enumerate(zip(m.input_names, m.input_lengths)):
        unit = units.label("force" if is_len else "moment")
        axes[0].plot(x, forces.driver_effort(d), lw=1.6, color=PATH_COLOURS[k % len(PATH_COLOURS)],
                     label=f"{d} [{unit}]")
    for k, j in enumerate(forces.reactions):
        axes[1].plot(x, np.hypot(*forces.reaction(j).T), lw=1.4, color=PATH_COLOURS[k % len(PATH_COLOURS)],
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
