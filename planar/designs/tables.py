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

from dataclasses import dataclass, replace

import numpy as np

from planar.designs.assembly import assemble
from planar.geometry import rotate
from planar.joints.base import SketchFrames, wrap
from planar.model import GROUND
from planar.model.compile import compile_sketch
from planar.model.resolve import (PLACES, char_length, frame_origins, mode_triangles, resolve, rule_line, site_key,
                                  sites)
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
    points = {}  # every part's named points, NaN where a part has none (points are no joints: one structure)
    for p in parts:
        for n, (b, _) in p.points.items():
            points.setdefault(n, b)
    points = {n: (b, np.concatenate([p.points[n][1] if n in p.points and p.points[n][0] == b
                                     else np.full((len(p.index), 2), np.nan) for p in parts]))
              for n, b in points.items()}
    return Tables(first.model, cat("index"), System(first.system.n_bodies, first.system.m, groups), cat("q0"),
                  cat("u0"), cat("L"), points)


def _extent(pos, joints, D):
    """The designs' characteristic lengths (D,), as :func:`planar.model.resolve.char_length`."""
    every = [np.broadcast_to(p, (2, D)) for p in pos.values()]
    every += [np.broadcast_to(p, (2, D)) for c in joints for _, p in c.touch_points()]
    radii = [np.broadcast_to(c.data[k], (D,)) for c in joints for k in ("radius", "radius_a", "radius_b")
             if k in c.data]
    L = np.zeros(D)
    if every:
        every = np.stack(every, axis=2)
        L = np.max(every, axis=2) - np.min(every, axis=2)
        L = np.maximum(L[0], L[1])
    for r in radii:
        L = np.maximum(L, r)
    return np.where(L > np.sqrt(np.finfo(float).tiny), L, 1.0)


def _numeric(v):
    return not isinstance(v, (bool, str, np.bool_)) and v is not None and np.asarray(v).dtype.kind in "iuf"


def _signature(mech):
    """Everything of a mechanism but its numbers."""
    sk = mech.sketch()

    def data(c):
        return tuple((k, ("number", np.shape(v)) if _numeric(v) else v) for k, v in c.data.items())
    return (tuple((b, s if not isinstance(s, float) else float) for b, s in sk.bodies.items()),
            tuple((type(c), c.name, c.bodies, data(c)) for c in sk.joints + sk.drivers),
            tuple((n, b) for n, (b, _) in sk.points.items()), tuple((d.a, d.b) for d in sk.dimensions),
            tuple(sk.sides), tuple(sk.starts))


class _Template:
    """What the template's mechanism says about every design of its structure."""

    def __init__(self, mech, model):
        self.model = model
        self.sk = sk = mech.sketch()
        self.signature = _signature(mech)
        self.cons = sk.joints + sk.drivers
        self.names = list(sk.points)
        self.keys = [(i, k) for i, c in enumerate(self.cons) for k, v in c.data.items() if _numeric(v)]
        self.spec_bodies = [b for b, s in list(sk.bodies.items())[1:] if isinstance(s, float)]
        L = char_length(sk.points, sk.joints)
        X0, site, bases = sites(sk.points, sk.joints, L)
        self.site = site
        # each site's place in a design: a named point, or a joint's datum (the first met)
        self.sources = {}
        for n in sk.points:
            self.sources.setdefault(site[n], ("point", n))
        for i, j in enumerate(sk.joints):
            for key in PLACES:
                if j.data.get(key) is not None and not j.pin:
                    self.sources.setdefault(site[site_key(j.data[key])], ("datum", i, key))
        # and its motion in the assembly: free, held, or along a line (a slider's on the ground,
        # or the frame's direction from the first pivot) that a design may turn
        pivots = list(dict.fromkeys(site[j.name] for j in sk.joints if GROUND in j.bodies
                                    and j.pin))
        self.bases = []
        for i, B in enumerate(bases):
            if B.shape[1] != 1:
                self.bases.append(B.shape[1])
            elif len(pivots) > 1 and i == pivots[1]:
                self.bases.append(("pivot", pivots[0]))
            else:
                k = next((k for k, j in enumerate(sk.joints) if j.slides and j.bodies[0] == GROUND
                          and site[site_key(j.data["at"])] == i), None)
                self.bases.append(("slot", k) if k is not None else None)
        self.triangles = [(a, b, c) for a, b, c, _ in mode_triangles(sk, site)]
        self.lines = {}  # body -> the names (p, q) of its line, or None
        for b, spec in list(sk.bodies.items())[1:]:
            self.lines[b] = spec if isinstance(spec, tuple) else rule_line(sk, b, lambda p, q: site[p] != site[q])
        self.starts = list(sk.starts)
        self.P = np.array([[sk.points[n][1] for n in self.names]], float).reshape(1, -1, 2)
        self.L = np.array([L])
        self.lengths = np.concatenate([np.array(c.length_rows, bool) for c in self.cons])
        self.n_joint_rows = model.row_adr[len(sk.joints)] if sk.drivers else model.m
        # the model's constraints are the mechanism's in order: its rows and sketch rows
        self.sketch_rows = [(i, r) for i, c in enumerate(self.cons) for r in c.sketch_rows]


def _apart(P, L):
    """(D, P, P) True where two named points are more than 1e-12 L apart (other places)."""
    return np.hypot(*(P[:, :, None] - P[:, None, :]).transpose(3, 0, 1, 2)) > 1e-12 * L[:, None, None]


def tables(mech, model, mechs, engine="numpy"):
    """(:class:`Tables` of the designs ``mechs`` taken, the positions of the others): ``model``
    is ``mech`` compiled (the template; ``mech`` may be among ``mechs``); sketches assembled by
    ``engine`` (:func:`planar.designs.assembly.assemble`)."""
    t = _Template(mech, model)
    take = [k for k, m in enumerate(mechs) if m is not None and _signature(m) == t.signature]
    rest = sorted(set(range(len(mechs))) - set(take) - {k for k, m in enumerate(mechs) if m is None})
    if not take:
        return None, rest
    ms = [mechs[k] for k in take]
    D = len(ms)
    sks = [m.sketch() for m in ms]
    P = np.array([[sk.points[n][1] for n in t.names] for sk in sks], float).reshape(D, len(t.names), 2)
    data = {key: np.array([_data(sk, *key) for sk in sks], float) for key in t.keys}
    spec = {b: np.array([sk.bodies[b] for sk in sks], float) for b in t.spec_bodies}
    dims = np.array([[d.length for d in sk.dimensions] for sk in sks], float).reshape(D, -1)
    starts = {s: np.array([sk.starts[s] for sk in sks], float) for s in t.starts}
    out, bad = _build(t, P, data, spec, dims, starts, next((k for k, m in enumerate(ms) if m is mech), None), engine)
    return out and replace(out, index=np.array(take)[out.index]), sorted(rest + [take[k] for k in bad])


def varied(mech, model, numbers, engine="numpy"):
    """(:class:`Tables`, the positions of the designs it does not take) of the designs of
    ``mech`` (``model`` its compiled model) that differ from it by the ``numbers`` (D,
    dicts): its stated distances "a-b" and its drivers' starts (by the driver's name), the
    others as ``mech`` has them. Its sketch as drawn is every design's first guess, assembled by
    ``engine`` (:func:`planar.designs.assembly.assemble`)."""
    t = _Template(mech, model)
    sk, D = t.sk, len(numbers)
    col = lambda name, v: [x.get(name, v) for x in numbers]  # noqa: E731
    try:
        dims = np.array([col(f"{d.a}-{d.b}", d.length) for d in sk.dimensions], float).T.reshape(D, -1)
        starts = {s: np.array(col(s, sk.starts[s]), float) for s in t.starts}
    except (TypeError, ValueError):  # not numbers: each design alone says which
        return None, list(range(D))
    ok = np.all(np.isfinite(dims) & (dims > 0), axis=1) & np.all([np.isfinite(v) for v in starts.values()] or
                                                                [np.ones(D, bool)], axis=0)
    P = np.repeat(t.P, D, axis=0)
    data = {key: np.repeat(np.asarray(_data(sk, *key), float)[None], D, axis=0) for key in t.keys}
    spec = {b: np.full(D, sk.bodies[b]) for b in t.spec_bodies}
    out, bad = _build(t, P, data, spec, dims, starts, None, engine)
    bad = sorted(set(bad) | set(np.flatnonzero(~ok).tolist()))
    return (out.take(np.flatnonzero(np.isin(out.index, bad, invert=True))) if out is not None else None), bad


def _build(t, P, data, spec, dims, starts, at, engine):
    """(:class:`Tables` of the designs it takes, indexed 0..D-1; the others) from the designs'
    numbers: named points ``P`` (D, points, 2), joint data ``data`` {(constraint, key): (D, ...)},
    bodies' given angles ``spec``, stated lengths ``dims`` (D, stated), drivers' ``starts``;
    ``at`` the position of the template among them, or None; sketches assembled by ``engine``."""
    sk, model = t.sk, t.model
    D = len(P)
    # the constraints with every design's numbers, designs last (components first)
    cons = [type(c)(c.name, c.bodies, **{k: (np.moveaxis(data[(i, k)], 0, -1) if (i, k) in data else v)
                                         for k, v in c.data.items()}) for i, c in enumerate(t.cons)]
    pos = {n: P[:, k].T.copy() for k, n in enumerate(t.names)}  # (2, D)
    L = _extent(pos, cons[: len(sk.joints)], D)
    # the same points coincide as in the template (so its lines and sites are every design's)
    good = np.all(_apart(P, L) == _apart(t.P, t.L), axis=(1, 2))

    # 1. the sketch assembled to hold its dimensions and starts, where it does not as drawn
    def direction(p, q):
        d = pos[q] - pos[p]
        return np.arctan2(d[1], d[0])
    drawn = {GROUND: np.zeros(D)}
    for b, line in t.lines.items():
        s = sk.bodies[b]
        drawn[b] = spec[b] if isinstance(s, float) else (0.0 + direction(*line) if line is not None else np.zeros(D))
    off = np.zeros(D)
    for k, d in enumerate(sk.dimensions):
        off = np.maximum(off, np.abs(np.hypot(*(pos[d.b] - pos[d.a])) - dims[:, k]) / L)
    for c, cv in zip(sk.drivers, cons[len(sk.joints):]):
        if c.name not in starts:
            continue
        if c.relative_angle:
            a, b = c.bodies
            off = np.maximum(off, np.abs(wrap(drawn[b] - drawn[a] - starts[c.name])))
        elif "at" in c.data and (len(c.bodies) == 1 or c.bodies[0] == GROUND):
            u = cv.data["direction"] if "direction" in c.data else cv.data["axis"]
            o = cv.data.get("origin", np.zeros((2, 1)))
            off = np.maximum(off, np.abs(np.sum((cv.data["at"] - o) * u, axis=0) - starts[c.name]) / L)
    if sk.dimensions:
        need = np.flatnonzero(good & (off > 5e-15))  # (below, compiling moves nothing: as drawn, bit for bit)
        if need.size:
            before = {n: p[:, need] for n, p in pos.items()}
            good[need] &= assemble(t, pos, cons, spec, dims, starts, L, need, engine)
            for b, line in t.lines.items():  # a body's angle given: turned with its line, if that moved
                if isinstance(sk.bodies[b], float) and line is not None:
                    d0 = before[line[1]] - before[line[0]]
                    moved = np.any((pos[line[0]][:, need] != before[line[0]]) |
                                   (pos[line[1]][:, need] != before[line[1]]), axis=0)
                    turn = direction(*line)[need] - np.arctan2(d0[1], d0[0])
                    drawn[b][need] = np.where(moved, spec[b][need] + turn, spec[b][need])
                elif line is not None:
                    drawn[b] = 0.0 + direction(*line)
            L = _extent(pos, cons[: len(sk.joints)], D)
    else:
        good &= off <= 1e-9

    # 2. angles and frames as compiling sets them, the starts' turns included
    angles = dict(drawn)
    for c in sk.drivers:
        start = starts.get(c.name)
        if start is None or not c.relative_angle:
            continue
        a, b = c.bodies
        if b != GROUND:
            angles[b] = start + angles[a] if a == GROUND else angles[b] + 2 * np.pi * np.round(
                (start - angles[b] + angles[a]) / (2 * np.pi))
        else:
            angles[a] = angles[a] - 2 * np.pi * np.round((start + angles[a]) / (2 * np.pi))
    origins = frame_origins(cons[: len(sk.joints)], {n: (b, pos[n]) for n, (b, _) in sk.points.items()})
    origins[GROUND] = np.zeros((2, 1))
    frames = SketchFrames(origins, angles)
    bodies = model.body_names
    q0 = np.stack([np.concatenate([np.broadcast_to(origins[b], (2, D)), angles[b][None]]) for b in bodies[1:]],
                  axis=1).T.reshape(D, -1) if len(bodies) > 1 else np.zeros((D, 0))

    # the model's scale, as compiling takes it: the constraints' own points, not the named ones
    L = _extent({}, cons, D)

    # 3. each constraint's body-fixed parameters, over the designs
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
    f = len(sk.drivers)
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
        system = System(system.n_bodies, system.m, tuple(replace(g) for g in system.groups))  # (the constants set)
        if model.redundant_rows.size:
            Phi, _ = system.evaluate(q0, np.concatenate([u0, ids], axis=1), jacobian=False)
            red = model.redundant_rows
            good &= np.all(np.abs(Phi[:, red] * rs[:, red]) <= 1e-9, axis=1)
        good &= np.all(np.isfinite(q0), axis=1) & np.all(np.isfinite(u0), axis=1)
    points = {}
    for n, (b, _) in model.points.items():
        name = bodies[b]
        d = pos[n] - np.broadcast_to(origins[name], (2, D))
        points[n] = (b, rotate(-angles[name], d.T))  # world to body-fixed
    out = Tables(model, np.arange(D), system, q0, u0, L, points)
    keep = np.flatnonzero(good)
    return (out.take(keep) if keep.size else None), np.flatnonzero(~good).tolist()


def _data(sk, i, k):
    """Constraint i's (joints, then drivers) data ``k`` in the drawn sketch ``sk``."""
    n = len(sk.joints)
    return (sk.joints[i] if i < n else sk.drivers[i - n]).data[k]


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


def compile_unplanned(mechanism):
    """``mechanism.compile()`` but for its block plan: designs of one structure share one."""
    return compile_sketch(mechanism.name, resolve(mechanism.sketch()), plan=False)
