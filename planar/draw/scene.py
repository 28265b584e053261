"""A mechanism ready to draw at any pose: body-fixed points to world coordinates, the joints'
parameters, body outlines, and the drawing primitives the joints' parts are made of
(:meth:`planar.joints.Joint.draw_part`)."""

import numpy as np

from planar.errors import InputError
from planar.geometry import cross, rotate
from planar.results import Status
from planar.draw.style import EDGE, FILLS, SAME, STILL, TINY


# ---- poses: body-fixed vectors to world coordinates ------------------------------------------


def _frame(q, b):
    """(r, phi) of body b over q (..., n); the ground is the identity."""
    if b == 0:
        return np.zeros(q.shape[:-1] + (2,)), np.zeros(q.shape[:-1])
    return q[..., 3 * b - 3: 3 * b - 1], q[..., 3 * b - 1]


def world(q, b, s):
    """World position of the body-fixed point s (2,) of body b at poses q (..., n)."""
    r, phi = _frame(q, b)
    return r + rotate(phi, np.asarray(s, float))


def turn(q, b, u):
    """World direction of the body-fixed vector u of body b."""
    return rotate(_frame(q, b)[1], np.asarray(u, float))


def local(q, b, p):
    """Body-fixed coordinates in body b of the world point p at poses q."""
    r, phi = _frame(q, b)
    return rotate(-phi, p - r)


def joint_params(model):
    """Each joint's body-fixed parameters, exactly as the compiled system holds them."""
    out = {}
    for g in model.system.groups:
        for k, i in enumerate(g.members):
            if i < len(model.joints):
                out[model.joints[i].name] = {key: v[k] for key, v in g.P.items()}
    return out


# ---- the scene: one mechanism, any pose ------------------------------------------------------


def pose_index(sweep, i):
    """``i`` where it indexes a value of ``sweep``, else an InputError."""
    N = len(sweep.q)
    if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)) or not -N <= i < N:
        raise InputError(f"pose index {i!r}: a whole number from 0 to {N - 1} (the sweep's values; from the end "
                         f"-1 to -{N})")
    return i


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
        self.params = joint_params(m)
        qs = self.poses()
        finite = qs[np.all(np.isfinite(qs), axis=1)]
        # size of the drawing: the span of every named point over the sweep
        pts = np.concatenate([world(finite, b, s) for b, s in m.points.values()]) if m.points else np.zeros((1, 2))
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
        q = np.asarray(self.sweep.q[pose_index(self.sweep, i)])
        if not np.all(np.isfinite(q)):
            raise InputError(f"pose {i} did not solve (status {Status(self.sweep.status[i]).name}): "
                             f"draw a pose where the sweep is valid")
        return q

    def _extent(self, qs, a, s_a, u, runner, pad):
        """Body-fixed ends of a guide line of body a: where the runner goes over the sweep, padded."""
        b, s_b = runner
        t = np.einsum("...i,i->...", local(qs, a, world(qs, b, s_b)) - s_a, u)
        lo, hi = (float(t.min()), float(t.max())) if t.size else (0.0, 0.0)
        lo, hi = lo - pad - self.size, hi + pad + self.size
        return (s_a + lo * u, s_a + hi * u)

    def line_ends(self, name):
        """Body-fixed ends of the guide line or rack of joint ``name``."""
        return self._ends[name]

    def ids(self, joint):
        """Body ids of a joint's bodies."""
        return [self.model.body_id(b) for b in joint.bodies]

    world, turn, local = staticmethod(world), staticmethod(turn), staticmethod(local)

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
        d = (e1 - e0) / max(np.hypot(*(e1 - e0)), TINY)
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
        d = (e1 - e0) / max(np.hypot(*(e1 - e0)), TINY)
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
        c = world(q, b, s)
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
        mark = world(q, b, s + R * np.array([np.cos(a), np.sin(a)]))
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
        d = (e1 - e0) / max(length, TINY)
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
        pts = np.array([world(q, b, s) for s in self.attach[b]]) if self.attach[b] else np.zeros((0, 2))
        pts = _distinct(pts, SAME * self.L)
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
            p = world(q, b, s)
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
        pts = [world(q, *self.model.points[n]) for n in names]
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
            same = np.flatnonzero(np.linalg.norm(pts - pts[k], axis=1) <= STILL * self.L)
            done[same] = True
            text = ", ".join(names[s] for s in same)
            half = np.array([0.33 * h * len(text) + 0.2 * h, 0.5 * h])
            d = pts[k] - centre
            out = np.arctan2(d[1], d[0]) if np.hypot(*d) > SAME * self.L else np.pi / 2
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
