"""The compiled tables of many designs of one structure, built at once from their numbers.

A study's designs share one structure: the same bodies, joints, drivers, points, stated
distances and assembly sides, with other numbers. One design (the *template*) is compiled as
usual; that gives everything the numbers do not change (the constraint groups and their rows,
the rank and the independent rows, the plan). The other designs' numbers (points, joint data
such as radii and directions, stated lengths, body angles, starts) are read into arrays, and
what compiling does with them is done once over all designs: the check that the sketch holds
its dimensions and starts, the bodies' angles and frames, the joints' body-fixed parameters
(each joint class's own ``local_params``, given arrays of designs where it takes numbers),
the sketch pose ``q0``, the sketch constants and the inputs ``u0``, the redundant rows' check.

A design this does not take (another structure, a sketch that needs assembling to hold its
dimensions, a joint class whose parameters do not broadcast, an assembly off at rounding
level, a redundant joint that disagrees) is compiled alone, exactly as before; one that
cannot be compiled keeps its error.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> mechs = [four_bar(crank=c, coupler_point=(1.0, 0.5)) for c in (1.0, 1.2, 1.4)]
>>> model = mechs[0].compile()
>>> t, alone = tables(mechs[0], model, mechs)
>>> t.index.tolist(), alone
([0, 1, 2], [])
>>> bool(np.allclose(t.q0[2], mechs[2].compile().q0, rtol=0, atol=1e-12))
True
"""

from dataclasses import dataclass

import numpy as np

from planar.dimensions import _wrap
from planar.joints import AngleDriver
from planar.joints.base import SketchFrames
from planar.model import GROUND, _char_length, _origins, _rule_line, _sites
from planar.system import Group, System


@dataclass(frozen=True, eq=False)
class Tables:
    """What compiling gives each of the designs ``index`` (positions in the list given to
    :func:`tables`), design axis first: ``system`` (its groups' parameters (D, K, ...),
    :meth:`planar.system.System.over_designs`), ``q0`` (D, n), ``u0`` (D, f), ``L`` (D,) and
    ``points`` name -> (body id, (D, 2) body-fixed point); ``model`` is the template."""

    model: object
    index: np.ndarray
    system: System
    q0: np.ndarray
    u0: np.ndarray
    L: np.ndarray
    points: dict

    def take(self, k):
        """The tables of designs ``k`` (positions in ``index``)."""
        groups = tuple(Group(g.kind, g.members, g.bodies, {key: v[k] for key, v in g.P.items()}, g.rows, g.cols,
                             g.inputs, True) for g in self.system.groups)
        return Tables(self.model, self.index[k], System(self.system.n_bodies, self.system.m, groups), self.q0[k],
                      self.u0[k], self.L[k], {n: (b, s[k]) for n, (b, s) in self.points.items()})


def from_models(models, index):
    """The :class:`Tables` of compiled ``models`` (one structure; the first is the template)."""
    ref = models[0]
    return Tables(ref, np.asarray(index, int), ref.system.over_designs([m.system for m in models]),
                  np.stack([m.q0 for m in models]), np.stack([m.u0 for m in models]), np.array([m.L for m in models]),
                  {n: (b, np.stack([m.points[n][1] for m in models])) for n, (b, _) in ref.points.items()})


def join(parts):
    """One :class:`Tables` of several of one template's structure, in the order given."""
    first = parts[0]
    groups = tuple(Group(g.kind, g.members, g.bodies, {k: np.concatenate([p.system.groups[i].P[k] for p in parts])
                                                       for k in g.P}, g.rows, g.cols, g.inputs, True)
                   for i, g in enumerate(first.system.groups))
    cat = lambda f: np.concatenate([getattr(p, f) for p in parts])  # noqa: E731
    return Tables(first.model, cat("index"), System(first.system.n_bodies, first.system.m, groups), cat("q0"),
                  cat("u0"), cat("L"), {n: (b, np.concatenate([p.points[n][1] for p in parts]))
                                        for n, (b, _) in first.points.items()})


def _numeric(v):
    return not isinstance(v, (bool, str, np.bool_)) and v is not None and np.asarray(v).dtype.kind in "iuf"


def _signature(mech):
    """Everything of a mechanism but its numbers."""
    def data(c):
        return tuple((k, ("number", np.shape(v)) if _numeric(v) else v) for k, v in c.data.items())
    return (tuple((b, s if not isinstance(s, float) else float) for b, s in mech._bodies.items()),
            tuple((type(c), c.name, c.bodies, data(c)) for c in mech._joints + mech._drivers),
            tuple((n, b) for n, (b, _) in mech._points.items()), tuple((d.a, d.b) for d in mech._dimensions),
            tuple(mech._sides), tuple(mech._starts))


class _Template:
    """What the template's mechanism says about every design of its structure."""

    def __init__(self, mech, model):
        self.mech, self.model = mech, model
        self.signature = _signature(mech)
        self.cons = mech._joints + mech._drivers
        self.names = list(mech._points)
        self.keys = [(i, k) for i, c in enumerate(self.cons) for k, v in c.data.items() if _numeric(v)]
        self.spec_bodies = [b for b, s in list(mech._bodies.items())[1:] if isinstance(s, float)]
        L = _char_length(mech._points, mech._joints)
        _, site, _ = _sites(mech._points, mech._joints, L)
        self.lines = {}  # body -> the names (p, q) of its line, or None
        for b, spec in list(mech._bodies.items())[1:]:
            self.lines[b] = spec if isinstance(spec, tuple) else _rule_line(mech, b, lambda p, q: site[p] != site[q])
        self.starts = list(mech._starts)
        self.P = np.array([[mech._points[n][1] for n in self.names]], float).reshape(1, -1, 2)
        self.L = np.array([L])
        self.lengths = np.concatenate([np.array(c.length_rows, bool) for c in self.cons])
        self.n_joint_rows = model.row_adr[len(mech._joints)] if mech._drivers else model.m
        # the model's constraints are the mechanism's in order: its rows and sketch rows
        self.sketch_rows = [(i, r) for i, c in enumerate(self.cons) for r in c.sketch_rows]


def _apart(P, L):
    """(D, P, P) True where two named points are more than 1e-12 L apart (other places)."""
    return np.hypot(*(P[:, :, None] - P[:, None, :]).transpose(3, 0, 1, 2)) > 1e-12 * L[:, None, None]


def tables(mech, model, mechs):
    """(:class:`Tables` of the designs ``mechs`` taken, the positions of the others): ``model``
    is ``mech`` compiled (the template; ``mech`` may be among ``mechs``)."""
    t = _Template(mech, model)
    take = [k for k, m in enumerate(mechs) if m is not None and _signature(m) == t.signature]
    rest = sorted(set(range(len(mechs))) - set(take) - {k for k, m in enumerate(mechs) if m is None})
    if not take:
        return None, rest
    ms = [mechs[k] for k in take]
    D = len(ms)
    P = np.array([[m._points[n][1] for n in t.names] for m in ms], float).reshape(D, len(t.names), 2)
    data = {key: np.array([_data(m, *key) for m in ms], float) for key in t.keys}
    spec = {b: np.array([m._bodies[b] for m in ms], float) for b in t.spec_bodies}
    dims = np.array([[d.length for d in m._dimensions] for m in ms], float).reshape(D, -1)
    starts = {s: np.array([m._starts[s] for m in ms], float) for s in t.starts}
    # the constraints with every design's numbers, designs last (components first)
    cons = [type(c)(c.name, c.bodies, **{k: (np.moveaxis(data[(i, k)], 0, -1) if (i, k) in data else v)
                                         for k, v in c.data.items()}) for i, c in enumerate(t.cons)]
    pos = {n: P[:, k].T for k, n in enumerate(t.names)}  # (2, D)
    touch = [p for c in cons[: len(mech._joints)] for _, p in c.touch_points()]
    every = np.concatenate([P.transpose(2, 0, 1)] + [np.broadcast_to(p[:, :, None], (2, D, 1)) for p in touch], axis=2)
    radii = [np.broadcast_to(c.data[k], (D,)) for c in cons[: len(mech._joints)]
             for k in ("radius", "radius_a", "radius_b") if k in c.data]
    L = np.max(np.concatenate([np.ptp(every, axis=2).T] + [r[:, None] for r in radii], axis=1), axis=1) \
        if every.shape[2] else np.zeros(D)
    L = np.where(L > np.sqrt(np.finfo(float).tiny), L, 1.0)
    # the same points coincide as in the template (so its lines and sites are every design's)
    good = np.all(_apart(P, L) == _apart(t.P, t.L), axis=(1, 2))

    # 1. the drawn sketch must hold its dimensions and starts (compiling would move it)
    def direction(p, q):
        d = pos[q] - pos[p]
        return np.arctan2(d[1], d[0])
    drawn = {GROUND: np.zeros(D)}
    for b, line in t.lines.items():
        s = mech._bodies[b]
        drawn[b] = spec[b] if isinstance(s, float) else (0.0 + direction(*line) if line is not None else np.zeros(D))
    off = np.zeros(D)
    for k, d in enumerate(mech._dimensions):
        off = np.maximum(off, np.abs(np.hypot(*(pos[d.b] - pos[d.a])) - dims[:, k]) / L)
    for c, cv in zip(mech._drivers, cons[len(mech._joints):]):
        if c.name not in starts:
            continue
        if isinstance(c, AngleDriver):
            a, b = c.bodies
            off = np.maximum(off, np.abs(_wrap(drawn[b] - drawn[a] - starts[c.name])))
        elif "at" in c.data and (len(c.bodies) == 1 or c.bodies[0] == GROUND):
            u = cv.data["direction"] if "direction" in c.data else cv.data["axis"]
            o = cv.data.get("origin", np.zeros((2, 1)))
            off = np.maximum(off, np.abs(np.sum((cv.data["at"] - o) * u, axis=0) - starts[c.name]) / L)
    good &= off <= (5e-15 if mech._dimensions else 1e-9)

    # 2. angles and frames as compiling sets them, the starts' turns included
    angles = dict(drawn)
    for c in mech._drivers:
        start = starts.get(c.name)
        if start is None or not isinstance(c, AngleDriver):
            continue
        a, b = c.bodies
        if b != GROUND:
            angles[b] = start + angles[a] if a == GROUND else angles[b] + 2 * np.pi * np.round(
                (start - angles[b] + angles[a]) / (2 * np.pi))
        else:
            angles[a] = angles[a] - 2 * np.pi * np.round((start + angles[a]) / (2 * np.pi))
    origins = _origins(cons[: len(mech._joints)], {n: (b, pos[n]) for n, (b, _) in mech._points.items()})
    origins[GROUND] = np.zeros((2, 1))
    frames = SketchFrames(origins, angles)
    bodies = model.body_names
    q0 = np.stack([np.concatenate([np.broadcast_to(origins[b], (2, D)), angles[b][None]]) for b in bodies[1:]],
                  axis=1).T.reshape(D, -1) if len(bodies) > 1 else np.zeros((D, 0))

    # 3. each constraint's body-fixed parameters, over the designs
    at = next((k for k, m in enumerate(ms) if m is mech), None)
    Ps = []
    for i, (c, cv) in enumerate(zip(t.cons, cons)):
        ref = _ref_params(model, i)
        try:
            P = {k: _designs_first(v, ref[k], D) for k, v in cv.params(frames).items()}
            ok = P.keys() == ref.keys() and (at is None or all(
                np.allclose(P[k][at], ref[k], rtol=1e-12, atol=1e-12 * L[at]) for k in ref if k != "c"))
        except (TypeError, ValueError, IndexError):
            ok = False
        if not ok:  # a class whose parameters take numbers only: design by design
            P = _one_by_one(c, cv, origins, angles, D)
        Ps.append(P)
    groups = []
    for g in model.system.groups:
        groups.append(Group(g.kind, g.members, g.bodies, {k: np.stack([Ps[i][k] for i in g.members], axis=1)
                                                         for k in g.P}, g.rows, g.cols, g.inputs, True))
    system = System(model.system.n_bodies, model.system.m, tuple(groups))

    # 4. the sketch constants, the inputs at the sketch, the assembly and redundancy checks
    f = len(mech._drivers)
    ids = np.arange(D, dtype=float)[:, None]
    rs = np.where(t.lengths, 1.0 / L[:, None], 1.0)
    with np.errstate(all="ignore"):
        Phi, _ = system.evaluate(q0, np.concatenate([np.zeros((D, f)), ids], axis=1), jacobian=False)
        act = model.active_rows
        geo = np.setdiff1d(act[act < t.n_joint_rows], _rows(model, t.sketch_rows))
        good &= np.all(np.abs(Phi[:, geo] * rs[:, geo]) <= 1e-14, axis=1)  # assembled: compiling moves nothing
        for g in system.groups:
            for k, i in enumerate(g.members):
                for r in t.cons[i].sketch_rows:
                    g.P["c"][:, k, r] = Phi[:, model.row_adr[i] + r]
        u0 = np.ascontiguousarray(Phi[:, t.n_joint_rows:])
        if model.redundant_rows.size:
            Phi, _ = system.evaluate(q0, np.concatenate([u0, ids], axis=1), jacobian=False)
            red = model.redundant_rows
            good &= np.all(np.abs(Phi[:, red] * rs[:, red]) <= 1e-9, axis=1)
        good &= np.all(np.isfinite(q0), axis=1) & np.all(np.isfinite(u0), axis=1)
    points = {}
    for n, (b, _) in model.points.items():
        name = bodies[b]
        d = pos[n] - np.broadcast_to(origins[name], (2, D))
        c, s = np.cos(angles[name]), np.sin(angles[name])
        points[n] = (b, np.stack([c * d[0] + s * d[1], -s * d[0] + c * d[1]], axis=1))
    out = Tables(model, np.array(take), system, q0, u0, L, points)
    keep = np.flatnonzero(good)
    return (out.take(keep) if keep.size else None), sorted(rest + [take[k] for k in np.flatnonzero(~good)])


def _data(m, i, k):
    """Constraint i's (joints, then drivers) data ``k`` in mechanism ``m``."""
    n = len(m._joints)
    return (m._joints[i] if i < n else m._drivers[i - n]).data[k]


def _rows(model, pairs):
    return np.array([model.row_adr[i] + r for i, r in pairs], int)


def _ref_params(model, i):
    """The template's parameters of constraint i, one joint's (as its class gives them)."""
    g = next(g for g in model.system.groups if i in g.members)
    k = int(np.flatnonzero(g.members == i)[0])
    return {key: v[k] for key, v in g.P.items()}


def _designs_first(v, ref, D):
    """A parameter computed over the designs (shape of one joint's, then D, or one joint's
    for one the numbers do not change) as (D, shape of one joint's)."""
    v = np.asarray(v, float)
    if v.shape == ref.shape + (D,):
        return np.moveaxis(v, -1, 0)
    if v.shape == ref.shape:
        return np.broadcast_to(v, (D,) + ref.shape).copy()
    raise ValueError(f"parameter of shape {v.shape}, not {ref.shape} (+ ({D},))")


def _one_by_one(c, cv, origins, angles, D):
    """Constraint ``c``'s parameters design by design (``cv``: its data over the designs)."""
    out = []
    for d in range(D):
        data = {k: (np.asarray(v)[..., d] if k in cv.data and _numeric(c.data[k]) else v) for k, v in cv.data.items()}
        frames = SketchFrames({b: np.broadcast_to(o, (2, D))[:, d] for b, o in origins.items()},
                              {b: float(np.broadcast_to(a, (D,))[d]) for b, a in angles.items()})
        out.append(type(c)(c.name, c.bodies, **data).params(frames))
    return {k: np.stack([p[k] for p in out]) for k in out[0]}
