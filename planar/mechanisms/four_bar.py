"""The four-bar linkage: ground, crank, coupler and rocker joined by four revolutes.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> m = four_bar(4, 2, 3, 4, start=np.radians(60))
>>> res = m.sweep(np.radians([60.0]), velocity=10.0)
>>> np.degrees(res.angle("coupler")).round(6).tolist(), res.omega("rocker").round(6).tolist()
([46.080251], [1.43091])
"""

from collections.abc import Sequence

import numpy as np

from planar.errors import AssemblyError
from planar.mechanisms import checks
from planar.mechanisms.sketch import along, circle_circle, left_of, polar
from planar.model import Mechanism

DRIVERS = ("crank", "coupler", "rocker")


def loop_pose(O2, O4, crank, coupler, rocker, driver, start, crossed):
    """Sketch points A, B of the loop O2-A-B-O4 with the ``driver`` link ("crank": O2->A,
    "coupler": A->B, "rocker": O4->B) at absolute angle ``start``, B left of the directed line
    A -> O4 (right when ``crossed``). For the coupler and rocker drivers, when both poses at
    ``start`` have B on that side, the first circle intersection is taken."""
    O2, O4 = np.asarray(O2, dtype=float), np.asarray(O4, dtype=float)
    what = f"the four-bar at {driver} angle {start:.12g} rad"
    if driver == "crank":
        A = polar(O2, crank, start)
        B = circle_circle(A, coupler, O4, rocker, what)[1 if crossed else 0]
        return A, B
    if driver == "coupler":
        c = polar((0, 0), coupler, start)
        poses = [(A, A + c) for A in circle_circle(O2, crank, O4 - c, rocker, what)]
    else:
        B = polar(O4, rocker, start)
        poses = [(A, B) for A in circle_circle(O2, crank, B, coupler, what)]
    for A, B in poses:
        if left_of(A, O4, B) != crossed:
            return A, B
    side = "right" if crossed else "left"
    raise AssemblyError(f"{what} has no pose with B {side} of the directed line A -> O4: "
                        f"use crossed={not crossed} or another start")


def four_bar(ground: float = 4.0, crank: float = 2.0, coupler: float = 3.0, rocker: float = 4.0, *,
             frame_angle: float = 0.0, coupler_point: Sequence[float] | None = None, crossed: bool = False,
             driver: str = "crank", start: float = 0.0, pivot: Sequence[float] = (0.0, 0.0),
             name: str = "four_bar") -> Mechanism:
    """A four-bar sketched at input ``start`` and driven.

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Link lengths r1 (O2 to O4), r2 (O2 to A), r3 (A to B), r4 (O4 to B).
    frame_angle : float
        Angle th1 of O2 -> O4 (radians).
    coupler_point : (p, q), optional
        Adds point ``C`` on the coupler, p along A -> B and q to its left.
    crossed : bool
        The other assembly mode: B right of the directed line A -> O4 (default left).
    driver : {"crank", "coupler", "rocker"}
        The input: the absolute angle of O2 -> A, A -> B or O4 -> B.
    start : float
        Input value of the sketch (radians): sweeps continue from there.
    pivot : (x, y)
        Where O2 is (default the origin).

    Returns
    -------
    planar.Mechanism
        Bodies ``crank``, ``coupler``, ``rocker`` whose angles are th2, th3, th4; points
        ``O2``, ``A``, ``B``, ``O4`` (the revolutes) and ``C``; the four lengths (and C's
        distances from A and B) stated as dimensions.

    Examples
    --------
    >>> import numpy as np
    >>> res = four_bar(coupler_point=(2.0, 0.5)).sweep(np.linspace(0, 2 * np.pi, 5))
    >>> bool(res.ok.all()), res.position("C").shape
    (True, (5, 2))
    """
    r1, r2, r3, r4 = checks.lengths(ground=ground, crank=crank, coupler=coupler, rocker=rocker)
    th1 = checks.number(frame_angle, "frame_angle")
    start = checks.number(start, "start")
    checks.choice(driver, DRIVERS, "driver")
    pq = checks.point_pair(coupler_point, "coupler_point")

    O2 = np.asarray(checks.point_pair(pivot, "pivot", required=True), dtype=float)
    O4 = polar(O2, r1, th1)
    A, B = loop_pose(O2, O4, r2, r3, r4, driver, start, checks.flag(crossed, "crossed"))

    m = Mechanism(name)  # the bodies' angles are their lines O2 -> A, A -> B, O4 -> B
    for body in DRIVERS:
        m.add_body(body)
    m.add_revolute("O2", m.ground, "crank", at=O2)
    m.add_revolute("A", "crank", "coupler", at=A)
    m.add_revolute("B", "coupler", "rocker", at=B)
    m.add_revolute("O4", "rocker", m.ground, at=O4)
    # the link lengths stated, so that a file of it re-assembles when one is edited
    for a, b, r in (("O2", "O4", r1), ("O2", "A", r2), ("A", "B", r3), ("O4", "B", r4)):
        m.distance(a, b, r)
    if pq is not None:
        m.add_point("C", "coupler", at=along(A, B, *pq))
        if pq[1] != 0:  # C off the line A -> B: its distances from A and B hold it on the coupler
            m.distance("A", "C", float(np.hypot(*pq)))
            m.distance("B", "C", float(np.hypot(r3 - pq[0], pq[1])))
    m.drive(body=driver, start=start)  # the input starts at start, not wrapped to (-pi, pi]
    return m
