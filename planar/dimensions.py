"""Dimensions: lengths stated between joints and points, and the assembly that makes them hold.

With :meth:`planar.Mechanism.distance` the sketch positions are rough guesses: compile moves
the joints and points to the pose nearest them where every stated length holds exactly, with
the drivers at their start values. The first pivot on the ground stays where drawn and the next
one stays on the line drawn from it (the frame's origin and direction); a slider's point stays
on its line on the ground; the data of other joints (lines on moving bodies, gear centres,
rolling contacts) stay as drawn. The assembly follows the lengths from the drawn ones to the
stated ones in small steps, so it keeps the assembly mode drawn, never the mirror image; the
sides of dyads and the turn of triangles of three stated lengths are checked. Where that way is
blocked (a joint drawn far from its place: the loop cannot close on the way), it goes round:
the other dimensions first, then the one left out, kept where every two stated lengths from
one joint turn as drawn. A drawing too far from the dimensions for double precision to follow
(1e10 across for links of 2) is refused.

:class:`Dyad` places a joint or point at given distances from two known ones, on a named side,
and states both distances: a linkage is a few lines from its published dimensions.

>>> import numpy as np, planar
>>> m = planar.Mechanism("four-bar")
>>> crank, coupler, rocker = m.add_body("crank"), m.add_body("coupler"), m.add_body("rocker")
>>> m.add_revolute("O2", m.ground, crank, at=(0, 0))
>>> m.add_revolute("O4", rocker, m.ground, at=(4, 0))
>>> m.add_revolute("A", crank, coupler, at=(1, 1.7))                # roughly 2 at 60 degrees
>>> m.add_revolute("B", coupler, rocker, at=planar.Dyad("A", 3, "O4", 4, side="left"))
>>> m.distance("O2", "A", 2)
>>> m.distance("O2", "O4", 4)                                       # the ground link too
>>> m.drive("O2", start=np.radians(60))
>>> model = m.compile()
>>> model.sketch.position("A").round(6).tolist(), model.sketch.position("B").round(6).tolist()
([1.0, 1.732051], [3.08095, 3.892987])
>>> np.degrees([model.sketch.bodies[b] for b in ("crank", "coupler", "rocker")]).round(2).tolist()
[60.0, 46.08, 103.28]
"""

from dataclasses import dataclass

import numpy as np

from planar.errors import AssemblyError, ModelError
from planar.joints.base import wrap

# Newton solves one following of the targets may take (the hardest in the tests take under 100):
# a follow that halves and doubles its step without getting on (a joint drawn 1e29 away) stops
MAX_SOLVES = 250
STALLS = 4  # Gauss-Newton steps that do not halve the least residual before a solve is given up
HELD = 1e-9  # a length or travel holds to this, relative to itself,
ROUNDING = 1e-15  # or to this relative to the largest stated (the rounding of the coordinates)


def circle_circle(c1, r1, c2, r2, what="the two circles"):
    """Both intersections of circle(c1, r1) and circle(c2, r2): (left, right) of the directed
    line c1 -> c2. Raises :class:`planar.AssemblyError` naming ``what`` when they do not meet.

    >>> left, right = circle_circle((0, 0), 5, (8, 0), 5)
    >>> left.tolist(), right.tolist()
    ([4.0, 3.0], [4.0, -3.0])
    """
    c1, c2 = np.asarray(c1, dtype=float), np.asarray(c2, dtype=float)
    d = c2 - c1
    L = float(np.hypot(*d))
    if L == 0 or L > r1 + r2 or L < abs(r1 - r2):
        raise AssemblyError(f"{what} cannot be placed: circles of radii {r1:.12g} and {r2:.12g} with "
                            f"centres {L:.12g} apart do not meet; choose a start inside the motion range "
                            f"or other dimensions")
    # the chord's foot from the centre of the smaller circle (radius r, the other R), with
    # L^2 - R^2 as (L - R)(L + R) and h^2 as (r - a)(r + a): no large squares cancel (radii of
    # 1e8 and 1.5 meet to the rounding of their coordinates)
    u = d / L
    r, R, c, s = (r1, r2, c1, 1.0) if r1 <= r2 else (r2, r1, c2, -1.0)
    a = ((L - R) * (L + R) + r**2) / (2 * L)  # along c1 -> c2 (s = 1) or back
    h = np.sqrt(max((r - a) * (r + a), 0.0))
    n = np.array([-u[1], u[0]])
    foot = c + s * a * u
    return foot + h * n, foot - h * n


@dataclass(frozen=True)
class Dyad:
    """The point ``length_a`` from joint or point ``a`` and ``length_b`` from ``b``, on the
    ``side`` ("left" or "right") of the directed line a -> b. Give it as the ``at=`` of
    :meth:`planar.Mechanism.add_revolute` or :meth:`~planar.Mechanism.add_point`: the new joint
    or point is placed there and both distances are stated (each must join two joints or
    points of one body).

    >>> Dyad("A", 3.0, "O4", 4.0, side="left").place((0, 0), (5, 0)).tolist()
    [1.8, 2.4]
    """

    a: str
    length_a: float
    b: str
    length_b: float
    side: str = "left"

    def __post_init__(self):
        if not (isinstance(self.side, str) and self.side in ("left", "right")):
            raise ModelError(f"a dyad's side must be 'left' or 'right' of the line {self.a} -> {self.b}, "
                             f"got {self.side!r}")
        for key in ("length_a", "length_b"):
            v = getattr(self, key)
            # (a float32 compared with 1e308 would be cast to it, overflowing)
            x = float(v) if isinstance(v, np.floating) else v
            if not (isinstance(v, (int, float, np.floating, np.integer)) and -1e308 < x < 1e308 and np.isfinite(x)
                    and v > 0):  # (an integer beyond any float fails the bounds before isfinite)
                raise ModelError(f"a dyad's {key} must be a positive number, got {v!r}")

    def place(self, pa, pb, what="the dyad"):
        """The point, given the positions of ``a`` and ``b``."""
        return circle_circle(pa, float(self.length_a), pb, float(self.length_b), what)[self.side == "right"]


@dataclass(frozen=True)
class Dimension:
    """A stated length between two joints or points of one body."""

    a: str
    b: str
    length: float

    def __str__(self):
        return f"distance {self.a}-{self.b} = {self.length:.12g}"


# ---- the assembly: rows on the positions of the sketch's sites ------------------------------

@dataclass(frozen=True)
class Row:
    """One equation on the site positions X (S, 2): ``value(X) = target``.

    ``kind`` "length": |X[j] - X[i]| (``terms`` ((i, j),)); "angle": the sum of the world
    directions of the lines i -> j in ``terms``, each with its sign, plus ``offset`` (compared
    modulo 2 pi); "travel": (X[i] - origin) . u with ``terms`` ((i, origin, u),)."""

    kind: str
    terms: tuple
    target: float
    label: str
    offset: float = 0.0

    def value(self, X):
        if self.kind == "length":
            (i, j), = self.terms
            return float(np.hypot(*(X[j] - X[i])))
        if self.kind == "angle":
            return self.offset + sum(s * np.arctan2(*(X[j] - X[i])[::-1]) for s, i, j in self.terms)
        (i, origin, u), = self.terms
        return float(np.dot(X[i] - origin, u))

    def residual(self, X, target):
        r = self.value(X) - target
        return wrap(r) if self.kind == "angle" else r

    def grad(self, X):
        """[(site, d value / d X[site])]."""
        if self.kind == "length":
            (i, j), = self.terms
            d = X[j] - X[i]
            e = d / max(np.hypot(*d), 1e-300)
            return [(i, -e), (j, e)]
        if self.kind == "angle":
            out = []
            for s, i, j in self.terms:
                d = X[j] - X[i]
                g = s * np.array([-d[1], d[0]]) / max(d @ d, 1e-300)
                out += [(i, -g), (j, g)]
            return out
        (i, _, u), = self.terms
        return [(i, np.asarray(u, float))]


class _Problem:
    """Rows on sites; each site free (basis I), on a line (basis u) or fixed (no basis)."""

    def __init__(self, X0, bases, rows, L):
        self.X0 = np.asarray(X0, float)
        self.bases, self.rows, self.L = bases, rows, L
        self.cols = np.cumsum([0] + [B.shape[1] for B in bases])
        self.lengths = np.array([r.kind != "angle" for r in rows], bool)
        self.scale = np.where(self.lengths, 1.0 / L, 1.0)

    def X(self, z):
        X = self.X0.copy()
        for s, B in enumerate(self.bases):
            X[s] += B @ z[self.cols[s]:self.cols[s + 1]]
        return X

    def residuals(self, z, targets, rows=None):
        X = self.X(z)
        rows = range(len(self.rows)) if rows is None else rows
        return np.array([self.rows[k].residual(X, targets[k]) * self.scale[k] for k in rows])

    def jacobian(self, z):
        X = self.X(z)
        J = np.zeros((len(self.rows), self.cols[-1]))
        for k, row in enumerate(self.rows):
            for s, g in row.grad(X):
                J[k, self.cols[s]:self.cols[s + 1]] += g @ self.bases[s] * self.scale[k]
        return J * self.L  # unknowns in units of L

    def newton(self, z, targets, iterations=30):
        """Minimum-norm Gauss-Newton from z: (z, converged). Its tolerance and largest step
        grow with the lengths asked for, where they outgrow the sketch's size L."""
        size = max(1.0, np.max(np.abs(targets[self.lengths]), initial=0.0) / self.L)
        best, best_z, full, stalls = np.inf, z, False, 0
        with np.errstate(over="ignore", invalid="ignore"):  # (lengths whose squares overflow: refused below)
            for _ in range(iterations):
                r = self.residuals(z, targets)
                now = np.max(np.abs(r), initial=0.0)
                if now <= 1e-14 * size:
                    return z, True
                if now < best:
                    best_z, stalls = z, (0 if now < 0.5 * best else stalls + full)
                    best = now
                else:
                    stalls += full
                # full steps that no longer halve the least residual: a target past a limit
                # (the follow then tries a shorter step), or rounding's floor; no root to wait for
                if stalls == STALLS:
                    return best_z, best <= 1e-12 * size
                J = self.jacobian(z)
                if not (np.all(np.isfinite(r)) and np.all(np.isfinite(J))):
                    return z, False
                dx = np.linalg.lstsq(J, r, rcond=None)[0]
                if not np.all(np.isfinite(dx)):
                    return z, False
                big = np.max(np.abs(dx), initial=0.0)
                full = big <= 0.25 * size
                dx *= min(1.0, 0.25 * size / max(big, 1e-300))  # at most size/4 a step
                z = z - dx * self.L
            return z, np.max(np.abs(self.residuals(z, targets)), initial=0.0) <= 1e-12 * size


def assemble(X0, bases, rows, triangles, L):
    """Site positions X (S, 2) nearest X0 where every row holds, the lengths and angles
    followed from their drawn values to the targets in steps (lengths by equal ratios); raises AssemblyError naming the
    row that cannot hold (drivers first, then the dimensions, the last stated first) and by
    how much, or the triangle (sites a, b, c, what) that would have to turn over."""
    p = _Problem(X0, bases, rows, L)
    z0 = np.zeros(p.cols[-1])
    z, t = _follow(p, z0, *_path(rows, p.X0))
    if t < 1.0:  # (the straight way from the drawing is blocked: the diagnosis may find another)
        z = _diagnose(X0, bases, rows, L)
    X = p.X(z)
    _check_held(X, rows, L)
    if t < 1.0:
        _check_turns(p.X0, X, rows, L)
    for a, b, c, what in triangles:
        before, after = _turn(p.X0, a, b, c), _turn(X, a, b, c)
        if abs(before) > 1e-9 * L**2 and np.sign(before) != np.sign(after):
            raise AssemblyError(f"{what} would have to turn over to hold the dimensions (the assembly mode "
                                f"drawn cannot be kept): draw the sketch closer to the dimensions")
    return X


def _path(rows, X):
    """Row values at X and the targets, reached the short way round for angles."""
    now = np.array([r.value(X) for r in rows])
    change = np.array([r.residual(X, r.target) for r in rows])
    return now, now - change


def _follow(p, z, a, b, smallest=1.0 / 4096):
    """Follow the row targets from a (held at z) to b in steps that halve where Newton fails,
    down to ``smallest``, in at most MAX_SOLVES Newton solves: (z, how far it got, 0 to 1)."""
    # lengths change by equal ratios: a link stated 1e5 times its drawing takes tens of steps, not thousands
    ratio = np.array([r.kind == "length" for r in p.rows]) & (a > 0) & (b > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(ratio, np.log(b / a), 0.0)

    def target(t):
        return np.where(ratio, a * np.exp(t * log), a + t * (b - a))

    t, dt = 0.0, 0.125
    for _ in range(MAX_SOLVES):
        if t >= 1.0:
            break
        step = min(dt, 1.0 - t)
        z_new, ok = p.newton(z, target(t + step))
        if ok:
            z, t, dt = z_new, t + step, min(2 * step, 0.25)
        elif step > smallest:
            dt = step / 2
        else:
            break
    return z, t


def _turn(X, a, b, c):
    d, e = X[b] - X[a], X[c] - X[a]
    return d[0] * e[1] - d[1] * e[0]


def holds(off, target, largest):
    """Whether a length or travel off by ``off`` from ``target`` holds: to HELD of itself, or to
    the rounding of the ``largest`` stated (numbers or arrays alike)."""
    return off <= HELD * abs(target) + ROUNDING * largest


def _check_held(X, rows, L):
    """Raise the AssemblyError for the first length or travel that does not hold at X to its
    own size, or to the rounding of the largest stated (a sketch drawn 1e20 across for links
    of 2 meets the assembly's tolerance, relative to the drawing, where it stands; a crank of 2
    beside a rod of 1e13 fell to 0, within 1e-9 of the rod; angles are held to their own)."""
    lengths = [r for r in rows if r.kind != "angle"]
    size = max([abs(r.target) for r in lengths] + [1e-300])
    for r in lengths:
        off = r.residual(X, r.target)
        if not holds(abs(off), r.target, size):
            why = (f"it is too small beside the largest dimension, {size:.3g}, to hold in double precision; give "
                   "lengths nearer in size" if HELD * abs(r.target) < ROUNDING * size else
                   f"the sketch is drawn {L:.3g} across for dimensions of {size:.3g}, too far from them to follow in "
                   "double precision; draw the joints nearer their places")
            raise AssemblyError(f"{r.label} is off by {abs(off):.3g} where the drawing assembles: {why}")


def _check_turns(X0, X, rows, L):
    """Raise the AssemblyError where two stated lengths from one site turn the other way at X
    than drawn at X0: an assembly found the way round (not followed from the drawing) keeps
    the mode drawn, never the mirror image."""
    ends = [(k, r.terms[0]) for k, r in enumerate(rows) if r.kind == "length"]
    for n, (k, (a, b)) in enumerate(ends):
        for m, (c, d) in ends[n + 1:]:
            shared = {a, b} & {c, d}
            if len(shared) != 1:
                continue
            s, = shared
            i, j = ({a, b} - shared).pop(), ({c, d} - shared).pop()
            before, after = _turn(X0, s, i, j), _turn(X, s, i, j)
            if abs(before) > 1e-9 * L**2 and np.sign(before) != np.sign(after):
                raise AssemblyError(f"the dimensions hold together only with {rows[k].label} and {rows[m].label} "
                                    f"turned over from the drawing (the mirror image of the mode drawn: the lengths "
                                    f"cannot be followed from the drawing): draw the sketch closer to the dimensions")


def _diagnose(X0, bases, rows, L):
    """The sites' coordinates z of an assembly the way round the drawing blocked the follow
    from: the first row (drivers, then dimensions, last stated first) without which the others
    hold, followed from there to its target. Where it cannot get there, raise the
    AssemblyError: that row, with the value nearest its target the others let it reach."""
    order = [k for k in reversed(range(len(rows))) if rows[k].kind != "length"]
    order += [k for k in reversed(range(len(rows))) if rows[k].kind == "length"]
    for k in order:
        others = _Problem(X0, bases, rows[:k] + rows[k + 1:], L)
        z, t = _follow(others, np.zeros(others.cols[-1]), *_path(others.rows, others.X0))
        if t < 1.0:
            continue
        p = _Problem(X0, bases, rows, L)
        a, b = _path(rows, p.X(z))
        a[np.arange(len(rows)) != k] = b[np.arange(len(rows)) != k]
        z, t = _follow(p, z, a, b, smallest=1e-12)
        if t >= 1.0:
            return z
        row = rows[k]
        got, off = row.value(p.X(z)), row.residual(p.X(z), row.target)
        unit = f" rad ({np.degrees(got):.6g} deg)" if row.kind == "angle" else ""
        raise AssemblyError(f"{row.label} cannot hold with the others: the nearest assembly has "
                            f"{got:.6g}{unit}, {abs(off):.3g}{' rad' if unit else ''} "
                            f"{'more' if off > 0 else 'less'} than stated; change it or the dimensions it "
                            f"closes a loop with")
    raise AssemblyError(f"the dimensions cannot all hold together, and no one of them alone is at fault "
                        f"({', '.join(r.label for r in rows)}): check them against the published values")
