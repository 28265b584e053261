"""Hypothesis strategies: random linkages built from dyads, and their rebuilding under a rigid
motion, a uniform scale or another naming.

A linkage is a crank pinned to the ground followed by dyads. Each dyad joins a point of one
existing body to a point of another through two new links: RRR (two links pinned together) or
RRP (a link and a slider block on a line of the second body). A rolling linkage ends with one
loop closed by a rolling contact on a body G pinned to a body X (the crank, or a dyad's first
link): a gear on an arm pivoting with G on X, meshing with G (external or internal) and
pinned by a link to a body Y, as in the geared five-bar; or a rack sliding on X, meshing with
G, joined to Y by an RRR dyad. The sketch is assembled by construction (a gear or rack meshes
as drawn); a degenerate draw (collinear dyad, zero-length link) is allowed: planar must then
either refuse it with a PlanarError or solve it honestly.
"""

import numpy as np
from hypothesis import strategies as st

import planar

coord = st.floats(-3.0, 3.0, allow_nan=False)
point = st.tuples(coord, coord)


@st.composite
def linkages(draw, max_dyads=3, rolling=False):
    """A description: {"pivot", "crank_tip", "dyads": [(kind, body_x, p_x, joint, body_y, p_y, dir)]},
    and with ``rolling`` "rolling": (kind, g, p_a, p_b, body_y, p_y, split, internal, dir, side).

    Bodies are numbered: 0 ground, 1 crank, then two per dyad, then the rolling loop's three.
    The rolling loop's G is the crank (g = 0) or dyad g - 1's first link; p_a and p_b are its
    arm's pin and the gear's link pin, or the rack's dyad's pins; ``split`` sets the radii."""
    desc = {"pivot": draw(point), "crank_tip": draw(point), "dyads": []}
    n_bodies = 2
    for _ in range(draw(st.integers(1, max_dyads))):
        x = draw(st.integers(0, n_bodies - 1))
        y = (x + draw(st.integers(1, n_bodies - 1))) % n_bodies
        kind = draw(st.sampled_from(["RRR", "RRP"]))
        direction = draw(st.floats(0, np.pi))
        desc["dyads"].append((kind, x, draw(point), draw(point), y, draw(point), direction))
        n_bodies += 2
    if rolling:
        desc["rolling"] = (draw(st.sampled_from(["gear", "rack"])), draw(st.integers(0, len(desc["dyads"]))),
                           draw(point), draw(point), draw(st.integers(0, n_bodies - 1)), draw(point),
                           draw(st.floats(0.05, 0.95)), draw(st.booleans()), draw(st.floats(0, np.pi)),
                           draw(st.sampled_from(["left", "right"])))
    return desc


def build(desc, *, rotate=0.0, shift=(0.0, 0.0), scale=1.0, names=None):
    """The mechanism of ``desc`` with every sketch point mapped by p -> scale R(rotate) p + shift.

    ``names`` maps body numbers to names (default b0.. with b0 the ground). Returns the
    mechanism and the names of its pin points (p0, p1, ...), in order."""
    c, s = np.cos(rotate), np.sin(rotate)

    def P(p):
        return (scale * (c * p[0] - s * p[1]) + shift[0], scale * (s * p[0] + c * p[1]) + shift[1])

    name = (lambda b: "ground" if b == 0 else f"b{b}") if names is None else names.__getitem__
    m = planar.Mechanism("random linkage")
    body = lambda b: m.ground if b == 0 else name(b)  # noqa: E731
    m.add_body(name(1), rotate)
    m.add_revolute("p0", m.ground, name(1), at=P(desc["pivot"]))
    pins = ["p0"]
    n = 2
    for k, (kind, x, px, j, y, py, direction) in enumerate(desc["dyads"]):
        d1, d2 = n, n + 1
        m.add_body(name(d1), rotate)
        m.add_body(name(d2), rotate)
        m.add_revolute(f"x{k}", body(x), name(d1), at=P(px))
        m.add_revolute(f"j{k}", name(d1), name(d2), at=P(j))
        pins += [f"x{k}", f"j{k}"]
        if kind == "RRR":
            m.add_revolute(f"y{k}", name(d2), body(y), at=P(py))
            pins.append(f"y{k}")
        else:
            u = (np.cos(direction + rotate), np.sin(direction + rotate))
            m.add_prismatic(f"y{k}", body(y), name(d2), at=P(j), direction=u)
        n += 2
    if "rolling" in desc:
        pins += _rolling(m, desc, P, name, body, n, rotate, scale)
    m.add_point("tip", name(1), at=P(desc["crank_tip"]))
    m.drive("p0")
    return m, pins


def _rolling(m, desc, P, name, body, n, rotate, scale):
    """The rolling loop of ``desc`` on bodies n, n + 1, n + 2; the names of its pins."""
    kind, g, pa, pb, y, py, split, internal, direction, side = desc["rolling"]
    G, X, c = (1, 0, desc["pivot"]) if g == 0 else (2 + 2 * (g - 1), *desc["dyads"][g - 1][1:3])
    a, b, d = name(n), name(n + 1), name(n + 2)
    for k in (a, b, d):
        m.add_body(k, rotate)
    if kind == "gear":  # a: the arm, b: the gear meshing with G, d: the link from b to y
        m.add_revolute("ra", body(X), a, at=P(c))
        m.add_revolute("rb", a, b, at=P(pa))
        dist = scale * float(np.hypot(pa[0] - c[0], pa[1] - c[1]))
        radii = (dist * (1 + split), dist * split) if internal else (dist * split, dist * (1 - split))
        m.add_gear("mesh", body(G), b, *radii, internal=internal, carrier=a)
    else:  # a: the rack, sliding on X with its pitch line a radius from G's centre
        u = np.array([np.cos(direction), np.sin(direction)])
        through = np.asarray(c) + (0.1 + 2 * split) * np.array([u[1], -u[0]]) * (1 if side == "left" else -1)
        along = (np.cos(direction + rotate), np.sin(direction + rotate))
        m.add_prismatic("ra", body(X), a, at=P(through), direction=along)
        m.add_rack_pinion("mesh", body(G), a, scale * (0.1 + 2 * split), centre=P(c), through=P(through),
                          direction=along, side=side)
        m.add_revolute("rb", a, b, at=P(pa))
    m.add_revolute("rc", b, d, at=P(pb))
    m.add_revolute("rd", d, body(y), at=P(py))
    return ["ra", "rb", "rc", "rd"] if kind == "gear" else ["rb", "rc", "rd"]
