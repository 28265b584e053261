"""From a sketch as drawn to the sketch assembled: the distinct places of the drawing (sites),
each body's reference line and angle, the drivers' rows, the assembly mode drawn, and the
assembly on the stated distances (:func:`planar.dimensions.assemble`)."""

import itertools
import math

import numpy as np

from planar.dimensions import Row, assemble
from planar.errors import ConnectivityError, ModelError
from planar.geometry import rotate
from planar.model.frozen import GROUND, Sketch


def bodies_of(joints, points, name):
    """The bodies a joint or point is on: a revolute's two, the body of any other's anchor."""
    for j in joints:
        if j.name == name and j.pin:
            return set(j.bodies)
    return {points[name][0]}


def frame_origins(joints, points):
    """Body frames' origins: each body's first joint or point (its angle is as sketched)."""
    origins = {GROUND: np.zeros(2)}
    for j in joints:
        for b, p in j.touch_points():
            origins.setdefault(b, p)
    for b, p in points.values():
        origins.setdefault(b, p)
    return origins


def _ground_distance(bodies, joints):
    """Graph distance of each body from the ground (bodies linked by a joint are neighbours)."""
    import networkx as nx  # here, not at import: ``import planar`` stays light

    G = nx.Graph()
    G.add_nodes_from(bodies)
    G.add_edges_from((a, b) for j in joints for a in j.bodies for b in j.bodies if a != b)
    return nx.single_source_shortest_path_length(G, GROUND)


def rule_line(sk, body, apart, dist=None):
    """The default reference line (p, q) of ``body`` in the drawn sketch ``sk`` (see
    :meth:`Mechanism.reference_line`); ``apart(p, q)`` says whether two names are at different
    places."""
    dist = dist or _ground_distance(list(sk.bodies), sk.joints)
    ranked = []
    for k, j in enumerate(sk.joints):
        on = set(j.bodies) if j.pin else {sk.points[j.name][0]} if j.name in sk.points else set()
        if body in on:
            others = [dist.get(b, np.inf) for b in j.bodies if b != body]
            ranked.append((0, min(others, default=np.inf), k, j.name))
    ranked += [(1, 0, k, n) for k, (n, (b, _)) in enumerate(sk.points.items())
               if b == body and n not in {j.name for j in sk.joints}]
    names = [r[3] for r in sorted(ranked)]
    for q in names[1:]:
        if apart(names[0], q):
            return names[0], q
    return None


def resolve(sk):
    """The sketch ``sk`` as drawn (:meth:`Mechanism.sketch`), assembled: positions holding every
    stated distance (when there are any) and every body's angle in radians, each angle driver's
    start on its turn."""
    bodies, joints, drivers, points = list(sk.bodies), list(sk.joints), list(sk.drivers), sk.points
    _check_connected(bodies, joints)
    L = char_length(points, joints)
    X0, site, bases = sites(points, joints, L)
    lines = _body_lines(sk, site, X0)
    rows = _driver_rows(sk, lines, site, X0, L)
    X = X0
    if sk.dimensions:
        dims = [Row("length", ((site[d.a], site[d.b]),), d.length, str(d)) for d in sk.dimensions]
        X = assemble(X0, bases, dims + rows, mode_triangles(sk, site), L)
        # the named positions that moved, and the joint and driver data that follow them
        moved = lambda p: X[site[site_key(p)]] if not np.array_equal(X[site[site_key(p)]], p) else p  # noqa: E731
        points = {n: (b, moved(p)) for n, (b, p) in points.items()}
        follow = lambda j: type(j)(j.name, j.bodies, **{**j.data, "at": moved(j.data["at"])}) if "at" in j.data else j  # noqa: E731
        joints, drivers = [follow(j) for j in joints], [follow(d) for d in drivers]

    angles = {}
    for b, (ij, offset) in lines.items():
        spec = sk.bodies[b]
        if isinstance(spec, float) and (ij is None or all(np.array_equal(X[i], X0[i]) for i in ij)):
            angles[b] = spec  # the angle given, bit for bit
        else:
            angles[b] = offset + (_direction_of(X, *ij) if ij is not None else 0.0)
    for d in drivers:  # an angle input starts on the turn of its start value
        start = sk.starts.get(d.name)
        if start is not None and d.relative_angle:
            a, b = d.bodies
            if b != GROUND:
                angles[b] = start + angles[a] if a == GROUND else angles[b] + 2 * np.pi * round(
                    (start - angles[b] + angles[a]) / (2 * np.pi))
            else:
                angles[a] -= 2 * np.pi * round((start + angles[a]) / (2 * np.pi))
    mass, loads = dict(sk.mass), tuple(sk.loads)
    if sk.dimensions:  # centres of mass and load points move with their bodies' assembly
        o0, o1 = frame_origins(sk.joints, sk.points), frame_origins(joints, points)

        def carry(b, p):
            ij = lines[b][0]
            turn = _direction_of(X, *ij) - _direction_of(X0, *ij) if ij is not None else 0.0
            return o1[b] + rotate(turn, p - o0[b])
        mass = {b: (mb, carry(b, com), ib) for b, (mb, com, ib) in mass.items()}
        loads = tuple((b, carry(b, at), f, t, fixed) for b, at, f, t, fixed in loads)
    return Sketch(angles, points, tuple(joints), tuple(drivers), tuple(sk.dimensions), dict(sk.starts),
                  mass, loads, sk.gravity, sk.sides)


PLACES = ("at", "origin", "centre", "centre_a", "centre_b", "through")  # joint data that are world points


def site_key(p):
    """A world point as the key of its site in ``site`` (a tuple of two floats)."""
    return (float(p[0]), float(p[1]))


def sites(points, joints, L):
    """The distinct places of the sketch (X0 (S, 2)), ``site``: name or place (x, y) -> index,
    and the basis of each site's motion: free (I), along a slider's line on the ground (u) or
    held (none): the data of sliders on moving bodies, gears and rolling contacts stay as drawn,
    the first pivot on the ground too (the sketch's origin), and the next pivot apart stays on
    the line drawn from it (the frame's direction)."""
    X0, site, cells = [], {}, {}
    tol = 1e-12 * L or np.finfo(float).tiny

    def place(p):
        # the first site within tol of p: sites are kept by cells of side tol, so one within tol
        # lies in the 3 x 3 cells around p's (a search of every site made the sketch quadratic
        # in its points: 3,000 took 8.5 s)
        p = np.asarray(p, float)
        c = (math.floor(p[0] / tol), math.floor(p[1] / tol))
        near = [i for dx in (-1, 0, 1) for dy in (-1, 0, 1) for i in cells.get((c[0] + dx, c[1] + dy), ())
                if np.hypot(*(X0[i] - p)) <= tol]
        if near:
            return min(near)
        X0.append(p)
        cells.setdefault(c, []).append(len(X0) - 1)
        return len(X0) - 1

    for n, (_, p) in points.items():
        site[n] = site[site_key(p)] = place(p)
    bases = {}
    for j in joints:
        for key in PLACES:
            v = j.data.get(key)
            if v is None or j.pin:
                continue
            i = site[site_key(v)] = place(v)
            B = bases.get(i, np.eye(2))
            u = j.data["direction"][:, None] if key == "at" and j.slides and j.bodies[0] == GROUND else None
            along = u is not None and (B.shape[1] == 2 or (B.shape[1] == 1 and abs(B[:, 0] @ u[:, 0]) > 1 - 1e-12))
            bases[i] = u if along else np.zeros((2, 0))
    pivots = list(dict.fromkeys(site[j.name] for j in joints if GROUND in j.bodies and j.pin))
    for k, i in enumerate(pivots[:2]):
        if k == 0 or bases.get(i, np.eye(2)).shape[1] < 2:
            bases[i] = np.zeros((2, 0))
        else:
            d = X0[i] - X0[pivots[0]]
            bases[i] = (d / np.hypot(*d))[:, None]
    return np.array(X0).reshape(-1, 2), site, [bases.get(i, np.eye(2)) for i in range(len(X0))]


def _body_lines(sk, site, X0):
    """Each body's angle as (sites (i, j) of its line or None, offset): the angle is the
    offset plus the line's direction (the offset alone without a line)."""
    dist = _ground_distance(list(sk.bodies), sk.joints)
    lines = {GROUND: (None, 0.0)}
    for b, spec in list(sk.bodies.items())[1:]:
        if isinstance(spec, tuple):
            for n in spec:
                if n not in sk.points or b not in bodies_of(sk.joints, sk.points, n):
                    raise ModelError(f"the angle of body {b!r} is the line {spec[0]} -> {spec[1]}, but {n!r} is no "
                                     f"joint or point of {b!r}: name two of its joints or points")
            if site[spec[0]] == site[spec[1]]:
                raise ModelError(f"the angle of body {b!r} is the line {spec[0]} -> {spec[1]}, but both are at "
                                 f"one place: name two joints or points of {b!r} apart")
            lines[b] = ((site[spec[0]], site[spec[1]]), 0.0)
            continue
        rule = rule_line(sk, b, lambda p, q: site[p] != site[q], dist)
        if rule is None:
            lines[b] = (None, 0.0 if spec is None else spec)
        else:
            ij = (site[rule[0]], site[rule[1]])
            lines[b] = (ij, 0.0 if spec is None else spec - _direction_of(X0, *ij))
    return lines


def _driver_rows(sk, lines, site, X0, L):
    """The drivers as rows on the sites, held at their start (or drawn) values; without
    dimensions a start must be the value drawn."""
    rows = []
    for d in sk.drivers:
        label, start = f"the start of driver {d.name!r}", sk.starts.get(d.name)
        if d.relative_angle:
            a, b = d.bodies
            terms = tuple((s, *lines[x][0]) for s, x in ((1, b), (-1, a)) if lines[x][0] is not None)
            row = Row("angle", terms, 0.0, label, lines[b][1] - lines[a][1])
        elif "at" in d.data and (len(d.bodies) == 1 or d.bodies[0] == GROUND):
            u = d.data["direction"] if "direction" in d.data else d.data["axis"]
            row = Row("travel", ((site[site_key(d.data["at"])], d.data.get("origin", np.zeros(2)), u),), 0.0, label)
        else:
            continue  # a travel along a moving line: held by the sketch as drawn
        drawn = row.value(X0)
        rows.append(Row(row.kind, row.terms, drawn if start is None else start, label, row.offset))
        if start is not None and not sk.dimensions:
            if abs(rows[-1].residual(X0, start)) > 1e-9 * (1.0 if row.kind == "angle" else L):
                raise ModelError(f"driver {d.name!r} starts at {start:.12g} but the sketch has {drawn:.12g}: draw "
                                 f"the sketch at its start, or state the dimensions with distance() so that "
                                 f"compile assembles it there")
    return rows


def mode_triangles(sk, site):
    """The assembly mode drawn in ``sk``, as triangles (sites a, b, c, what) whose turn must stay: every
    triangle of three stated lengths, and every dyad's side (the rest follows the drawing, step
    by step)."""
    stated = {frozenset((d.a, d.b)) for d in sk.dimensions}
    names = sorted({n for d in sk.dimensions for n in (d.a, d.b)})
    triangles = [(site[a], site[b], site[c], f"the triangle {a}, {b}, {c}")
                 for a, b, c in itertools.combinations(names, 3)
                 if {frozenset((a, b)), frozenset((b, c)), frozenset((a, c))} <= stated]
    return triangles + [(site[a], site[b], site[n], f"{n}, {side} of the line {a} -> {b} (its dyad),")
                        for n, a, b, side in sk.sides]


def _direction_of(X, i, j):
    d = X[j] - X[i]
    return float(np.arctan2(d[1], d[0]))


def char_length(points, joints):
    """The extent of the sketch (or its largest radius): the scale of the scaled Jacobian,
    so it moves with the sketch, never with where the world origin happens to be."""
    P = np.array([p for _, p in points.values()] + [p for j in joints for _, p in j.touch_points()]).reshape(-1, 2)
    radii = [j.data[k] for j in joints for k in ("radius", "radius_a", "radius_b") if k in j.data]
    L = max(float(np.max(np.ptp(P, axis=0))) if len(P) else 0.0, max(radii, default=0.0))
    # an extent so small that 1/L or L**2 leave the float range is no length (all points coincide)
    return L if L > np.sqrt(np.finfo(float).tiny) else 1.0


def _check_connected(bodies, joints):
    import networkx as nx  # here, not at import: ``import planar`` stays light

    G = nx.Graph()
    G.add_nodes_from(bodies)
    for j in joints:
        for a in j.bodies:
            for b in j.bodies:
                if a != b:
                    G.add_edge(a, b)
    loose = sorted(set(bodies) - nx.node_connected_component(G, GROUND))
    if loose:
        raise ConnectivityError(f"bod{'ies' if len(loose) > 1 else 'y'} {loose} not connected to the ground: "
                                f"add a joint between {loose[0]!r} and the ground or a body connected to it")

