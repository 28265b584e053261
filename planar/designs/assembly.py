"""The sketches of many designs assembled at once, as compiling assembles one
(:func:`planar.dimensions.assemble`): the stated lengths and starts followed from their drawn
values to their own in the same steps for every design.

The rows (lengths between sites, angles of body lines, travels along a line) are tables of
numbers (:class:`Rows`) that both engines read: the numpy engine follows every design's
targets together, array by array (:func:`follow`); the compiled engine design by design in
machine code (:func:`planar.compiled.assembly.follow`), with the same steps and tests."""

from dataclasses import dataclass

import numpy as np

from planar import dimensions
from planar.joints.base import wrap
from planar.model import GROUND
from planar.model.resolve import site_key

LENGTH, ANGLE, TRAVEL = 0, 1, 2  # the kinds of rows
FIRST, GROW, LONGEST = 0.125, 2.0, 0.25  # the steps along the targets' path: the first, its growth, the longest
ITERATIONS = 30  # Gauss-Newton steps at most, per step along the path
HELD, CLOSED = 1e-14, 1e-12  # a step's iterations stop at this residual (scaled); the step holds at this
MOVE = 0.25  # a Gauss-Newton step moves no coordinate more than this (scaled)
FULL_RANK = 1e-10  # J J^T is solved where |det| / the product of its diagonal is above this, else J's pseudo-inverse


@dataclass(frozen=True)
class Rows:
    """The rows of D designs' assembly over S sites at coordinates z (c,): the sites are
    X0 + (B z) (D, S, 2); row k is of ``kind[k]``: a LENGTH between sites ``a[k]`` and
    ``b[k]``, an ANGLE ``offset[:, k]`` + the sum over its ``terms[k]`` terms t of sign
    ``sign[k, t]`` times the direction of site ``i[k, t]`` to ``j[k, t]``, or a TRAVEL of site
    ``a[k]`` from ``origin[:, k]`` along ``direction[:, k]``; followed from ``start`` (D, m) to
    ``goal`` (D, m), scaled by the designs' lengths L (D,) but the angles."""

    X0: np.ndarray
    B: np.ndarray
    kind: np.ndarray
    a: np.ndarray
    b: np.ndarray
    terms: np.ndarray
    sign: np.ndarray
    i: np.ndarray
    j: np.ndarray
    offset: np.ndarray
    origin: np.ndarray
    direction: np.ndarray
    L: np.ndarray

    def values(self, X, d):
        """The rows' values (len(d), m) at sites X of designs d."""
        out = np.empty((len(X), self.kind.size))
        for k, kind in enumerate(self.kind):
            if kind == LENGTH:
                out[:, k] = np.hypot(*(X[:, self.b[k]] - X[:, self.a[k]]).T)
            elif kind == ANGLE:
                out[:, k] = self.offset[d, k] + sum(self.sign[k, t] * _directions(X, self.i[k, t], self.j[k, t])
                                                    for t in range(self.terms[k]))
            else:
                out[:, k] = np.sum((X[:, self.a[k]] - self.origin[d, k]) * self.direction[d, k], axis=1)
        return out

    def jacobian(self, X, d):
        """d values / dz (len(d), m, c), scaled as the residuals, times the designs' L."""
        S = X.shape[1]
        G = np.zeros((len(X), self.kind.size, S, 2))
        for k, kind in enumerate(self.kind):
            a, b = self.a[k], self.b[k]
            if kind == LENGTH:
                e = X[:, b] - X[:, a]
                e /= np.maximum(np.hypot(e[:, :1], e[:, 1:]), 1e-300)
                G[:, k, a] -= e
                G[:, k, b] += e
            elif kind == ANGLE:
                for t in range(self.terms[k]):
                    i, j = self.i[k, t], self.j[k, t]
                    e = X[:, j] - X[:, i]
                    g = self.sign[k, t] * np.stack([-e[:, 1], e[:, 0]], axis=1) / np.maximum(
                        np.sum(e * e, axis=1), 1e-300)[:, None]
                    G[:, k, i] -= g
                    G[:, k, j] += g
            else:
                G[:, k, a] += self.direction[d, k]
        L = self.L[d, None]
        return (G.reshape(len(X), self.kind.size, 2 * S) @ self.B[d]) * (self.scale(L) * L)[:, :, None]

    def scale(self, L):
        """The rows' scales (len(L), m) for designs' lengths L (len, 1): 1 for angles, 1 / L else."""
        return np.where(self.kind == ANGLE, 1.0, 1.0 / L)

    def residuals(self, X, d, goal):
        r = self.values(X, d) - goal
        return np.where(self.kind == ANGLE, wrap(r), r) * self.scale(self.L[d, None])

    def sites(self, d, z):
        return self.X0[d] + (self.B[d] @ z[:, :, None]).reshape(self.X0[d].shape)


def assemble(t, pos, cons, spec, dims, starts, L, need, engine="numpy"):
    """Assemble the sketches of designs ``need`` as compiling does (:func:`planar.dimensions.assemble`),
    all at once: the stated lengths and the starts followed from their drawn values to their
    own in the same steps, a minimum-norm Gauss-Newton solve at each (``engine``: the numpy
    engine's arrays or the compiled engine's machine code); the named points in ``pos`` and the
    joints' "at" in ``cons`` moved there. (D,) False for a design whose steps do not all
    converge or whose triangles would turn over (compiled alone, it gets the reason)."""
    rows, driven = _rows(t, pos, cons, spec, L, need)
    if rows is None:  # a motion of a site it does not know: compiled alone
        return np.zeros(need.size, bool)
    d = np.arange(need.size)
    now = rows.values(rows.X0, d)
    angle = rows.kind == ANGLE
    target = now.copy()
    target[:, : dims.shape[1]] = dims[need]
    for k, name in driven.items():
        if name in starts:
            target[:, k] = starts[name][need]
    start, goal = now, now - np.where(angle, wrap(now - target), now - target)
    z, alive = np.zeros((need.size, rows.B.shape[2])), np.ones(need.size, bool)
    if engine == "numba":
        from planar.compiled import assembly

        assembly.follow(rows, start, goal, z, alive)
    else:
        follow(rows, start, goal, z, alive)
    X = rows.sites(d, z)
    alive &= _held(rows, X, d, target)
    Ls = L[need]
    for i, j, k in t.triangles:  # the assembly mode drawn is kept
        before, after = _turns(rows.X0, i, j, k), _turns(X, i, j, k)
        alive &= ~((np.abs(before) > 1e-9 * Ls**2) & (np.sign(before) != np.sign(after)))
    for n in pos:
        pos[n][:, need] = X[:, t.site[n]].T
    for c, cv in zip(t.cons, cons):
        if "at" in c.data:
            cv.data["at"][:, need] = X[:, t.site[site_key(c.data["at"])]].T
    return alive


def follow(rows, start, goal, z, alive):
    """Follow every design's rows from ``start`` to ``goal`` (D, m), its coordinates z (D, c)
    from the sketch's (zeros), in steps along the path, Gauss-Newton at each: z in place, and
    ``alive`` False for the designs a step fails."""
    t, dt = 0.0, FIRST
    while t < 1.0 and alive.any():
        step = min(dt, 1.0 - t)
        d = np.flatnonzero(alive)
        target = start[d] + (t + step) * (goal[d] - start[d])
        zs, L = z[d], rows.L[d, None]
        for _ in range(ITERATIONS):  # as planar.dimensions._Problem.newton, design by design
            X = rows.sites(d, zs)
            r = rows.residuals(X, d, target)
            go = np.max(np.abs(r), axis=1, initial=0.0) > HELD
            if not go.any():
                break
            dx = _min_norm(rows.jacobian(X, d), r)
            dx *= np.minimum(1.0, MOVE / np.maximum(np.max(np.abs(dx), axis=1, initial=0.0), 1e-300))[:, None]
            zs = np.where(go[:, None], zs - dx * L, zs)
        r = rows.residuals(rows.sites(d, zs), d, target)
        ok = np.max(np.abs(r), axis=1, initial=0.0) <= CLOSED
        z[d] = zs
        alive[d[~ok]] = False
        t, dt = t + step, min(GROW * step, LONGEST)


def _held(rows, X, d, target):
    """(D,) whether every length and travel holds at X to its own size or to the rounding of
    the largest, as :func:`planar.dimensions.assemble` holds them (the step's test is scaled by
    the design's size alone: a short length held only to that)."""
    length = rows.kind != ANGLE
    off, size = np.abs(rows.values(X, d) - target), np.abs(target)
    big = np.max(np.where(length, size, 0.0), axis=1, initial=0.0)[:, None]
    return np.all(~length | dimensions.holds(off, size, big), axis=1)


def _rows(t, pos, cons, spec, L, need):
    """(:class:`Rows` of designs ``need``, {row: the name of its driver}): the stated lengths,
    then the drivers' rows (angles of body lines, travels); (None, {}) where a site moves in a
    way it does not know."""
    sk, D, S = t.sk, need.size, len(t.sources)
    if None in t.bases or S != len(t.bases):
        return None, {}
    X0 = np.empty((D, S, 2))
    for i, src in t.sources.items():
        at = pos[src[1]] if src[0] == "point" else np.broadcast_to(cons[src[1]].data[src[2]], (2, L.size))
        X0[:, i] = at.T[need]
    widths = [b if isinstance(b, int) else 1 for b in t.bases]
    cols = np.cumsum([0] + widths)
    B = np.zeros((D, S, 2, cols[-1]))
    for i, b in enumerate(t.bases):
        if b == 2:
            B[:, i, :, cols[i]:cols[i] + 2] = np.eye(2)
        elif not isinstance(b, int):
            u = (X0[:, i] - X0[:, b[1]]) if b[0] == "pivot" else np.broadcast_to(
                cons[b[1]].data["direction"], (2, L.size)).T[need]
            B[:, i, :, cols[i]] = u / np.hypot(u[:, :1], u[:, 1:]) if b[0] == "pivot" else u
    site = t.site
    line = {b: (site[ln[0]], site[ln[1]]) for b, ln in t.lines.items() if ln is not None}
    m = len(sk.dimensions) + len(sk.drivers)  # at most
    kind, ab = np.zeros(m, int), np.zeros((m, 2), int)
    terms, sign, i, j = np.zeros(m, int), np.zeros((m, 2)), np.zeros((m, 2), int), np.zeros((m, 2), int)
    offset, origin, direction = np.zeros((D, m)), np.zeros((D, m, 2)), np.zeros((D, m, 2))
    for k, dm in enumerate(sk.dimensions):
        kind[k], ab[k] = LENGTH, (site[dm.a], site[dm.b])
    k, driven = len(sk.dimensions), {}
    for c, cv in zip(sk.drivers, cons[len(sk.joints):]):
        if c.relative_angle:
            kind[k] = ANGLE
            for sg, x in ((1, c.bodies[1]), (-1, c.bodies[0])):
                if x in line:
                    sign[k, terms[k]], (i[k, terms[k]], j[k, terms[k]]) = sg, line[x]
                    terms[k] += 1
                if x != GROUND and isinstance(sk.bodies[x], float):
                    offset[:, k] += sg * (spec[x][need] - (_directions(X0, *line[x]) if x in line else 0.0))
        elif "at" in c.data and (len(c.bodies) == 1 or c.bodies[0] == GROUND):
            kind[k], ab[k, 0] = TRAVEL, site[site_key(c.data["at"])]
            u = cv.data["direction"] if "direction" in c.data else cv.data["axis"]
            direction[:, k] = np.broadcast_to(u, (2, L.size)).T[need]
            origin[:, k] = np.broadcast_to(cv.data.get("origin", np.zeros((2, 1))), (2, L.size)).T[need]
        else:
            continue
        driven[k] = c.name
        k += 1
    rows = Rows(X0, B.reshape(D, 2 * S, cols[-1]), kind[:k], ab[:k, 0].copy(), ab[:k, 1].copy(), terms[:k],
                sign[:k], i[:k], j[:k], offset[:, :k].copy(), origin[:, :k].copy(), direction[:, :k].copy(), L[need])
    return rows, driven


def _min_norm(J, r):
    """The least-squares step of least norm, J+ r, per design: J^T (J J^T)^-1 r where the rows
    of J are independent (cheap), the pseudo-inverse where they are not (redundant lengths)."""
    Jt = J.swapaxes(1, 2)
    A = J @ Jt
    with np.errstate(all="ignore"):  # |det| over the product of the diagonal (Hadamard): 1 for orthogonal rows
        full = np.linalg.det(A) / np.prod(np.diagonal(A, axis1=1, axis2=2), axis=1) > FULL_RANK
    dx = np.empty(J.shape[::2])
    if full.any():
        dx[full] = (Jt[full] @ np.linalg.solve(A[full], r[full][:, :, None]))[:, :, 0]
    if not full.all():
        dx[~full] = (np.linalg.pinv(J[~full]) @ r[~full][:, :, None])[:, :, 0]
    return dx


def _directions(X, i, j):
    d = X[:, j] - X[:, i]
    return np.arctan2(d[:, 1], d[:, 0])


def _turns(X, a, b, c):
    d, e = X[:, b] - X[:, a], X[:, c] - X[:, a]
    return d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0]
