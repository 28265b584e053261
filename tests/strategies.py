"""Hypothesis strategies: random linkages built from dyads, and their rebuilding under a rigid
motion, a uniform scale or another naming.

A linkage is a crank pinned to the ground followed by dyads. Each dyad joins a point of one
existing body to a point of another through two new links: RRR (two links pinned together) or
RRP (a link and a slider block on a line of the second body). The sketch is assembled by
construction; a degenerate draw (collinear dyad, zero-length link) is allowed: planar must then
either refuse it with a PlanarError or solve it honestly.
"""

import numpy as np
from hypothesis import strategies as st

import planar

coord = st.floats(-3.0, 3.0, allow_nan=False)
point = st.tuples(coord, coord)


@st.composite
def linkages(draw, max_dyads=3):
    """A description: {"pivot", "crank_tip", "dyads": [(kind, body_x, p_x, joint, body_y, p_y, dir)]}.

    Bodies are numbered: 0 ground, 1 crank, then two per dyad."""
    desc = {"pivot": draw(point), "crank_tip": draw(point), "dyads": []}
    n_bodies = 2
    for _ in range(draw(st.integers(1, max_dyads))):
        x = draw(st.integers(0, n_bodies - 1))
        y = (x + draw(st.integers(1, n_bodies - 1))) % n_bodies
        kind = draw(st.sampled_from(["RRR", "RRP"]))
        direction = draw(st.floats(0, np.pi))
        desc["dyads"].append((kind, x, draw(point), draw(point), y, draw(point), direction))
        n_bodies += 2
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
    m.add_point("tip", name(1), at=P(desc["crank_tip"]))
    m.drive("p0")
    return m, pins
