"""Transmission angle: the angle between two directions of a mechanism over a sweep.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> res = four_bar(4, 2, 3, 4).sweep([0.0, np.pi])
>>> np.degrees(transmission_angle(res, ("B", "A"), ("B", "O4"))).round(6).tolist()
[28.955024, 117.279613]
"""

import numpy as np

from planar.errors import ModelError
from planar.results import as_sweep


def _direction(res, d):
    if isinstance(d, str):
        if d not in res.model.body_names:
            raise ModelError(f"unknown body {d!r}: give a body {list(res.model.body_names)} or a pair of points")
        th = res.angle(d)
        return np.stack((np.cos(th), np.sin(th)), axis=-1)
    try:
        p, q = d
    except (TypeError, ValueError):
        raise ModelError(f"a direction is a body name or a pair of point names (from, to); got {d!r}") from None
    if isinstance(p, str) and p == q:
        raise ModelError(f"a direction runs between two points, got {p!r} twice: name another point")
    return res.position(q) - res.position(p)


def transmission_angle(res, first, second):
    """(N,) angle in [0, pi] between two directions over the sweep ``res``.

    Each direction is a body (its absolute angle's direction) or a pair of point names
    (from the first to the second). For a four-bar the transmission angle is the angle at B
    between the coupler and the rocker: ``transmission_angle(res, ("B", "A"), ("B", "O4"))``
    (or the bodies "coupler" and "rocker", the same angle); it is best near 90 deg and the
    mechanism locks where it reaches 0 or 180 deg. NaN where a pair of points meets (within
    rounding of the model's length scale): a direction of no length has no angle.
    """
    as_sweep(res, "transmission_angle")
    a, b = _direction(res, first), _direction(res, second)
    angle = np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    short = np.minimum(np.hypot(*a.T), np.hypot(*b.T)) <= 1e-12 * res.model.L
    return np.where(short, np.nan, angle)
