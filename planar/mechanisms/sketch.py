"""Geometric constructions that place a builder's sketch: one assembled pose, in world coordinates.

They draw the pose a builder starts from (and so pick its assembly mode); they are not
kinematic solutions. Positions, rates and sweeps always come from the solver.

>>> import numpy as np
>>> left, right = circle_circle((0, 0), 5, (8, 0), 5)   # left of the directed line first
>>> left.tolist(), right.tolist()
([4.0, 3.0], [4.0, -3.0])
>>> ahead, behind = circle_line((0, 0), 5, (0, 3), (1, 0))   # farther along the line first
>>> ahead.tolist(), behind.tolist()
([4.0, 3.0], [-4.0, 3.0])
"""

import numpy as np

from planar.dimensions import circle_circle  # noqa: F401  (the builders' constructions, in one place)
from planar.errors import AssemblyError


def polar(origin, length, angle):
    """The point ``length`` from ``origin`` at ``angle`` (radians, counter-clockwise from +x).

    >>> polar((1, 0), 2, np.pi / 2).round(12).tolist()
    [1.0, 2.0]
    """
    return np.asarray(origin, dtype=float) + length * np.array([np.cos(angle), np.sin(angle)])


def along(A, B, p, q=0.0):
    """The point ``p`` along the line A -> B from A and ``q`` to its left (a coupler point).

    >>> along((0, 0), (2, 0), 1, 0.5).tolist()
    [1.0, 0.5]
    """
    A, B = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    u = (B - A) / np.hypot(*(B - A))
    return A + p * u + q * np.array([-u[1], u[0]])


def angle_of(A, B):
    """Direction angle of the vector A -> B (radians, in (-pi, pi])."""
    d = np.asarray(B, dtype=float) - np.asarray(A, dtype=float)
    return float(np.arctan2(d[1], d[0]))


def left_of(A, B, P):
    """True when P lies left of the directed line A -> B (strictly)."""
    A, B, P = (np.asarray(v, dtype=float) for v in (A, B, P))
    d, e = B - A, P - A
    return bool(d[0] * e[1] - d[1] * e[0] > 0)


def circle_line(c, r, p, u, what="the circle and the line"):
    """Both intersections of circle(c, r) with the line through p along u: (ahead, behind), the
    one farther along u first. Raises :class:`planar.AssemblyError` when they do not meet."""
    c, p, u = (np.asarray(v, dtype=float) for v in (c, p, u))
    u = u / np.hypot(*u)
    t0 = float(np.dot(c - p, u))  # foot of the perpendicular from c
    # (the distance from the line itself, not |c - p|^2 - t0^2: with p far along the line those
    # squares cancel)
    dist = abs(float(u[0] * (c - p)[1] - u[1] * (c - p)[0]))
    h2 = (r - dist) * (r + dist)
    if h2 < 0:
        raise AssemblyError(f"{what} cannot be placed: the line passes {dist:.12g} from the "
                            f"circle's centre but the radius is {r:.12g}; choose a start inside the motion "
                            f"range or other dimensions")
    h = np.sqrt(h2)
    return p + (t0 + h) * u, p + (t0 - h) * u


def line_through(pivot, offset, point, longer=True, what="the line"):
    """Direction angle and travel of the line that runs ``offset`` to the right of ``pivot``
    (a fixed perpendicular distance, as a slide on a rocking link) and passes through
    ``point``: returns (theta, r) with point = pivot + (r - i offset) e^{i theta}, r >= 0 for
    ``longer`` else r <= 0.

    >>> th, r = line_through((0, 0), 0.0, (0, 2))
    >>> round(th, 12), round(r, 12)
    (1.570796326795, 2.0)
    """
    d = np.asarray(point, dtype=float) - np.asarray(pivot, dtype=float)
    D2 = float(np.dot(d, d))
    if D2 < offset**2 or D2 == 0:
        raise AssemblyError(f"{what} cannot be placed: the point is {np.sqrt(D2):.12g} from the pivot, "
                            f"less than the offset {abs(offset):.12g}; choose another start or dimensions")
    r = np.sqrt(D2 - offset**2) * (1.0 if longer else -1.0)
    theta = np.arctan2(d[1], d[0]) - np.arctan2(-offset, r)
    return float(theta), float(r)
