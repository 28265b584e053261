"""The sketches of many designs assembled at once, as compiling assembles one
(:func:`planar.dimensions.assemble`): the stated lengths and starts followed from their drawn
values to their own in the same steps for every design."""

import numpy as np

from planar.joints.base import wrap
from planar.model import GROUND
from planar.model.resolve import site_key


def assemble(t, pos, cons, spec, dims, starts, L, need):
    """Assemble the sketches of designs ``need`` as compiling does (:func:`planar.dimensions.assemble`),
    all at once: the stated lengths and the starts followed from their drawn values to their
    own in the same steps, a minimum-norm Gauss-Newton solve at each; the named points in
    ``pos`` and the joints' "at" in ``cons`` moved there. (D,) False for a design whose steps
    do not all converge or whose triangles would turn over (compiled alone, it gets the reason)."""
    sk, D, S = t.sk, need.size, len(t.sources)
    if None in t.bases or S != len(t.bases):  # a motion of a site it does not know: compiled alone
        return np.zeros(D, bool)
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
    # the rows: lengths between sites, then the drivers' (angles of body lines, travels)
    site, Ls = t.site, L[need]
    rows = [("length", site[d.a], site[d.b], dims[need, k]) for k, d in enumerate(sk.dimensions)]
    line = {b: (site[ln[0]], site[ln[1]]) for b, ln in t.lines.items() if ln is not None}
    for c, cv in zip(sk.drivers, cons[len(sk.joints):]):
        start = starts.get(c.name)
        if c.relative_angle:
            terms = [(sg, *line[x]) for sg, x in ((1, c.bodies[1]), (-1, c.bodies[0])) if x in line]
            offset = np.zeros(D)
            for sg, x in ((1, c.bodies[1]), (-1, c.bodies[0])):
                if x != GROUND and isinstance(sk.bodies[x], float):
                    offset += sg * (spec[x][need] - (_directions(X0, *line[x]) if x in line else 0.0))
            rows.append(("angle", terms, offset, None if start is None else start[need]))
        elif "at" in c.data and (len(c.bodies) == 1 or c.bodies[0] == GROUND):
            u = np.broadcast_to(cv.data["direction"] if "direction" in c.data else cv.data["axis"], (2, L.size)).T[need]
            o = np.broadcast_to(cv.data.get("origin", np.zeros((2, 1))), (2, L.size)).T[need]
            rows.append(("travel", site[site_key(c.data["at"])], (o, u), None if start is None else start[need]))

    B = B.reshape(D, 2 * S, cols[-1])

    def X(X0, B, z):  # the sites at coordinates z
        return X0 + (B @ z[:, :, None]).reshape(X0.shape)

    def values(X):
        out = np.empty((len(X), len(rows)))
        for k, (kind, a, b, _) in enumerate(rows):
            if kind == "length":
                out[:, k] = np.hypot(*(X[:, b] - X[:, a]).T)
            elif kind == "angle":
                out[:, k] = b[sel] + sum(sg * _directions(X, i, j) for sg, i, j in a)
            else:
                out[:, k] = np.sum((X[:, a] - b[0][sel]) * b[1][sel], axis=1)
        return out

    def jacobian(X, B):
        G = np.zeros((len(X), len(rows), S, 2))
        for k, (kind, a, b, _) in enumerate(rows):
            if kind == "length":
                d = X[:, b] - X[:, a]
                e = d / np.maximum(np.hypot(d[:, :1], d[:, 1:]), 1e-300)
                G[:, k, a] -= e
                G[:, k, b] += e
            elif kind == "angle":
                for sg, i, j in a:
                    d = X[:, j] - X[:, i]
                    g = sg * np.stack([-d[:, 1], d[:, 0]], axis=1) / np.maximum(np.sum(d * d, axis=1), 1e-300)[:, None]
                    G[:, k, i] -= g
                    G[:, k, j] += g
            else:
                G[:, k, a] += b[1][sel]
        return (G.reshape(len(X), len(rows), 2 * S) @ B) * (scale * Ls[sel, None])[:, :, None]

    angle = np.array([r[0] == "angle" for r in rows])
    sel = np.arange(D)
    scale = np.where(angle, 1.0, 1.0 / Ls[:, None])
    now = values(X0)
    target = np.stack([r[3] if r[3] is not None else now[:, k] for k, r in enumerate(rows)], axis=1)
    change = np.where(angle, wrap(now - target), now - target)
    a, b = now, now - change

    def residuals(X, goal):
        r = values(X) - goal
        return np.where(angle, wrap(r), r) * scale

    z, alive, tt, dt = np.zeros((D, cols[-1])), np.ones(D, bool), 0.0, 0.125
    while tt < 1.0 and alive.any():
        step = min(dt, 1.0 - tt)
        sel = np.flatnonzero(alive)
        goal = a[sel] + (tt + step) * (b[sel] - a[sel])
        zs, scale = z[sel], np.where(angle, 1.0, 1.0 / Ls[sel, None])
        X0s, Bs = X0[sel], B[sel]
        for _ in range(30):  # Gauss-Newton, as planar.dimensions._Problem.newton, design by design
            Xs = X(X0s, Bs, zs)
            r = residuals(Xs, goal)
            go = np.max(np.abs(r), axis=1, initial=0.0) > 1e-14
            if not go.any():
                break
            J = jacobian(Xs, Bs)
            dx = _min_norm(J, r)
            dx *= np.minimum(1.0, 0.25 / np.maximum(np.max(np.abs(dx), axis=1, initial=0.0), 1e-300))[:, None]
            zs = np.where(go[:, None], zs - dx * Ls[sel, None], zs)
        r = residuals(X(X0s, Bs, zs), goal)
        ok = np.max(np.abs(r), axis=1, initial=0.0) <= 1e-12
        z[sel] = zs
        alive[sel[~ok]] = False
        tt, dt = tt + step, min(2 * step, 0.25)
    Xa = X(X0, B, z)
    for i, j, k in t.triangles:  # the assembly mode drawn is kept
        before, after = _turns(X0, i, j, k), _turns(Xa, i, j, k)
        alive &= ~((np.abs(before) > 1e-9 * Ls**2) & (np.sign(before) != np.sign(after)))
    for n in pos:
        pos[n][:, need] = Xa[:, site[n]].T
    for c, cv in zip(t.cons, cons):
        if "at" in c.data:
            cv.data["at"][:, need] = Xa[:, site[site_key(c.data["at"])]].T
    return alive


def _min_norm(J, r):
    """The least-squares step of least norm, J+ r, per design: J^T (J J^T)^-1 r where the rows
    of J are independent (cheap), the pseudo-inverse where they are not (redundant lengths)."""
    Jt = J.swapaxes(1, 2)
    A = J @ Jt
    with np.errstate(all="ignore"):  # |det| over the product of the diagonal (Hadamard): 1 for orthogonal rows
        full = np.linalg.det(A) / np.prod(np.diagonal(A, axis1=1, axis2=2), axis=1) > 1e-10
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
