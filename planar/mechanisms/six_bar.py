"""Six-bar linkages: a crank-driven four-bar O2-A-B-O4 with a second loop closed by a dyad.

- :func:`watt_six_bar`: Watt chain, binary ground: the dyad C-E-D joins a point C of the
  coupler to a point D of the rocker (the two ternary links, adjacent at B).
- :func:`stephenson_six_bar`: Stephenson chain, ternary ground: the dyad C-D-O6 joins a
  coupler point C to a third ground pivot O6.
- :func:`two_loop_six_bar`: the student report's six-bar, two four-bars in series
  (R1 - R2 - R3 + R4 = 0, R5 - R6 - R7 + R8 = 0): the rocker, extended to D, is the crank
  of the second four-bar O4-D-E-O6 (the Watt chain with a ternary ground).

Every one is driven by the crank's absolute angle and sketched at ``start``; ``crossed``
picks the first loop's assembly mode (B right of the directed line A -> O4) and ``crossed_2``
the second's (the dyad's middle joint right of the line through its two end joints).

>>> import numpy as np
>>> from planar.mechanisms import stephenson_six_bar
>>> res = stephenson_six_bar().sweep(np.linspace(0, 2 * np.pi, 13))
>>> bool(res.ok.all())
True
"""

from collections.abc import Sequence

import numpy as np

from planar.mechanisms import checks
from planar.mechanisms.four_bar import four_bar, loop_pose
from planar.mechanisms.sketch import along, angle_of, circle_circle, polar
from planar.model import Mechanism


def _first_loop(name, ground, crank, coupler, rocker, frame_angle, crossed, start):
    """The driven four-bar and its sketch points O4, A, B."""
    m = four_bar(ground, crank, coupler, rocker, frame_angle=frame_angle, crossed=crossed, start=start, name=name)
    # (four_bar has checked them: as numbers now)
    ground, crank, coupler, rocker = checks.lengths(ground=ground, crank=crank, coupler=coupler, rocker=rocker)
    frame_angle, start = checks.number(frame_angle, "frame_angle"), checks.number(start, "start")
    O4 = polar((0, 0), ground, frame_angle)
    A, B = loop_pose((0, 0), O4, crank, coupler, rocker, "crank", start, bool(crossed))
    return m, O4, A, B


def dyad(m, names, bodies, P, Q, r_p, r_q, crossed, what):
    """Close a loop with two links: ``bodies[0]`` from P (on ``bodies[2]``) and ``bodies[1]``
    from Q (on ``bodies[3]``), pinned together at the intersection left of P -> Q (right if
    ``crossed``). ``names`` are the three revolutes at P, the middle joint and Q."""
    M = circle_circle(P, r_p, Q, r_q, what)[int(checks.flag(crossed, "crossed_2"))]
    m.add_body(bodies[0], angle=(names[0], names[1]))
    m.add_body(bodies[1], angle=(names[2], names[1]))
    m.add_revolute(names[0], bodies[2], bodies[0], at=P)
    m.add_revolute(names[1], bodies[0], bodies[1], at=M)
    m.add_revolute(names[2], bodies[1], bodies[3], at=Q)
    m.distance(names[0], names[1], r_p)
    m.distance(names[2], names[1], r_q)
    return m


def _held(m, name, a, b):
    """State the distances from joints a and b of one body to its joint ``name`` (only from a
    when the three are in line, where both would over-state it), so that the joint stays on the
    body when a length of a file is edited."""
    P = {n: m.sketch().position(n) for n in (name, a, b)}
    d, e = P[b] - P[a], P[name] - P[a]
    refs = (a, b) if abs(d[0] * e[1] - d[1] * e[0]) > 1e-12 * (d @ d) else (a,)
    for ref in refs:
        r = float(np.hypot(*(P[name] - P[ref])))
        if r > 1e-12 * np.sqrt(d @ d):  # a joint on a joint is held by it already
            m.distance(ref, name, r)


def watt_six_bar(ground: float = 4.0, crank: float = 1.5, coupler: float = 4.0, rocker: float = 3.5, *,
                 coupler_point: Sequence[float] = (2.0, 1.5), rocker_point: Sequence[float] = (1.5, -1.5),
                 link_5: float = 3.0, link_6: float = 3.0, frame_angle: float = 0.0, crossed: bool = False,
                 crossed_2: bool = False, start: float = 0.0, name: str = "watt_six_bar") -> Mechanism:
    """Watt six-bar with a binary ground: a four-bar whose coupler point C and rocker point D
    are joined by link 5 (C to E) and link 6 (E to D).

    Parameters
    ----------
    ground, crank, coupler, rocker, frame_angle, crossed, start
        The four-bar, as in :func:`planar.mechanisms.four_bar` (crank driven).
    coupler_point : (p, q)
        C on the coupler, p along A -> B and q to its left.
    rocker_point : (p, q)
        D on the rocker, p along O4 -> B and q to its left.
    link_5, link_6 : float
        Lengths C to E and D to E.
    crossed_2 : bool
        E right of the directed line C -> D (default left).

    Returns
    -------
    planar.Mechanism
        Bodies ``crank``, ``coupler``, ``rocker``, ``link5`` (C -> E), ``link6`` (D -> E);
        points ``O2``, ``A``, ``B``, ``O4``, ``C``, ``E``, ``D``.

    Examples
    --------
    >>> import numpy as np
    >>> bool(watt_six_bar().sweep(np.linspace(0, 2 * np.pi, 13)).ok.all())
    True
    """
    r5, r6 = checks.lengths(link_5=link_5, link_6=link_6)
    pq_c = checks.point_pair(coupler_point, "coupler_point", required=True)
    pq_d = checks.point_pair(rocker_point, "rocker_point", required=True)
    m, O4, A, B = _first_loop(name, ground, crank, coupler, rocker, frame_angle, crossed, start)
    m = dyad(m, ("C", "E", "D"), ("link5", "link6", "coupler", "rocker"), along(A, B, *pq_c),
              along(O4, B, *pq_d), r5, r6, crossed_2, "the Watt six-bar's dyad C-E-D")
    _held(m, "C", "A", "B")
    _held(m, "D", "O4", "B")
    return m


def stephenson_six_bar(ground: float = 4.0, crank: float = 1.5, coupler: float = 4.0, rocker: float = 3.5, *,
                       coupler_point: Sequence[float] = (2.0, 1.5), link_5: float = 4.0, link_6: float = 3.0,
                       pivot_6: Sequence[float] = (2.0, 6.0), frame_angle: float = 0.0, crossed: bool = False,
                       crossed_2: bool = False, start: float = 0.0,
                       name: str = "stephenson_six_bar") -> Mechanism:
    """Stephenson six-bar with a ternary ground: a four-bar whose coupler point C drives link 6
    (pivoted on the ground at O6) through link 5 (C to D).

    Parameters
    ----------
    ground, crank, coupler, rocker, frame_angle, crossed, start
        The four-bar, as in :func:`planar.mechanisms.four_bar` (crank driven).
    coupler_point : (p, q)
        C on the coupler, p along A -> B and q to its left.
    link_5, link_6 : float
        Lengths C to D and O6 to D.
    pivot_6 : (x, y)
        The ground pivot O6 of link 6.
    crossed_2 : bool
        D right of the directed line C -> O6 (default left).

    Returns
    -------
    planar.Mechanism
        Bodies ``crank``, ``coupler``, ``rocker``, ``link5`` (C -> D), ``link6`` (O6 -> D);
        points ``O2``, ``A``, ``B``, ``O4``, ``C``, ``D``, ``O6``.
    """
    r5, r6 = checks.lengths(link_5=link_5, link_6=link_6)
    pq = checks.point_pair(coupler_point, "coupler_point", required=True)
    O6 = np.array(checks.point_pair(pivot_6, "pivot_6", required=True))
    m, O4, A, B = _first_loop(name, ground, crank, coupler, rocker, frame_angle, crossed, start)
    m = dyad(m, ("C", "D", "O6"), ("link5", "link6", "coupler", m.ground), along(A, B, *pq), O6, r5, r6,
              crossed_2, "the Stephenson six-bar's dyad C-D-O6")
    _held(m, "C", "A", "B")
    _held(m, "O6", "O2", "O4")
    return m


def two_loop_six_bar(lengths: Sequence[float] = (4.0, 1.5, 4.0, 3.5, 5.0, 2.0, 5.0, 3.5), *,
                     frame_angle: float = 0.0, frame_angle_2: float = 0.0, phase: float = np.pi,
                     crossed: bool = False, crossed_2: bool = False, start: float = 0.0,
                     name: str = "two_loop_six_bar") -> Mechanism:
    """The student report's six-bar: two four-bars in series sharing the pivot O4.

    Loop 1: R2 + R3 = R1 + R4 (O2-A-B-O4, as :func:`planar.mechanisms.four_bar`). Loop 2:
    R6 + R7 = R5 + R8 with R5 = O4 -> O6 on the ground, R6 = O4 -> D on the rocker (at angle
    ``phase`` from O4 -> B), R7 = D -> E, R8 = O6 -> E.

    Parameters
    ----------
    lengths : 8 floats
        r1 ... r8 as above.
    frame_angle, frame_angle_2 : float
        Angles of O2 -> O4 and of O4 -> O6 (radians).
    phase : float
        Angle of O4 -> D from O4 -> B, fixed in the rocker (default pi: a straight lever
        through O4).
    crossed, crossed_2 : bool
        B right of A -> O4; E right of D -> O6 (defaults left).
    start : float
        The crank's absolute angle in the sketch.

    Returns
    -------
    planar.Mechanism
        Bodies ``crank``, ``coupler``, ``rocker`` (angle of O4 -> B), ``coupler2`` (D -> E),
        ``rocker2`` (O6 -> E); points ``O2``, ``A``, ``B``, ``O4``, ``D``, ``E``, ``O6``.
    """
    r = checks.length_list(lengths, "lengths", count=8)
    th5 = checks.number(frame_angle_2, "frame_angle_2")
    phase = checks.number(phase, "phase")
    m, O4, A, B = _first_loop(name, r[0], r[1], r[2], r[3], frame_angle, crossed, start)
    D = polar(O4, r[5], angle_of(O4, B) + phase)
    m = dyad(m, ("D", "E", "O6"), ("coupler2", "rocker2", "rocker", m.ground), D, polar(O4, r[4], th5),
              r[6], r[7], crossed_2, "the second loop D-E-O6")
    _held(m, "D", "O4", "B")
    _held(m, "O6", "O2", "O4")
    return m
