"""The slider-crank: crank, coupler and a slider on a straight line of the ground.

>>> import numpy as np
>>> from planar.mechanisms import slider_crank
>>> res = slider_crank(2, 3, offset=4, start=np.radians(60)).sweep(np.radians([60.0]), velocity=10.0)
>>> res.coordinate("slide").round(6).tolist(), res.coordinate("slide", 1).round(6).tolist()
([2.963774], [-5.771574])
"""

from collections.abc import Sequence

import numpy as np

from planar.mechanisms import checks
from planar.mechanisms.sketch import along, circle_circle, circle_line, polar
from planar.model import Mechanism

DRIVERS = ("crank", "coupler", "slider")


def slider_crank(crank: float = 2.0, coupler: float = 5.0, *, offset: float = 1.0, slide_angle: float = 0.0,
                 coupler_point: Sequence[float] | None = None, crossed: bool = False, driver: str = "crank",
                 start: float | None = None, name: str = "slider_crank") -> Mechanism:
    """A slider-crank sketched at input ``start`` and driven.

    The crank pivot O2 is at the origin. The slide line runs at ``slide_angle`` through the
    point at signed distance ``offset`` to the left of O2 (with slide_angle 0, the line
    y = offset); the slider's pin B rides on it.

    Parameters
    ----------
    crank, coupler : float
        Lengths r2 (O2 to A) and r3 (A to B).
    offset, slide_angle : float
        The slide line, as above (slide_angle in radians).
    coupler_point : (p, q), optional
        Adds point ``C`` on the coupler, p along A -> B and q to its left.
    crossed : bool
        The other assembly mode. Crank or coupler driven: B behind its partner pose along the
        slide direction (default ahead: the larger travel). Slider driven: A right of the
        directed line O2 -> B (default left).
    driver : {"crank", "coupler", "slider"}
        The input: the absolute angle of O2 -> A or of A -> B, or the travel of B along the line
        (joint ``slide``, measured from the foot of the offset).
    start : float, optional
        Input value of the sketch. Default 0 for the angle drivers; for the slider, the travel
        of the (default-mode) pose with the crank at right angles to the slide.

    Returns
    -------
    planar.Mechanism
        Bodies ``crank``, ``coupler`` (angles th2, th3) and ``slider`` (angle slide_angle);
        points ``O2``, ``A``, ``B`` (revolutes), ``slide`` (the prismatic joint, at B) and ``C``.

    Examples
    --------
    >>> import numpy as np
    >>> res = slider_crank().sweep(np.linspace(0, 2 * np.pi, 9))
    >>> bool(res.ok.all()), float(res.position("B")[0, 0].round(6))
    (True, 6.898979)
    """
    r2, r3 = checks.lengths(crank=crank, coupler=coupler)
    e = checks.number(offset, "offset")
    th1 = checks.number(slide_angle, "slide_angle")
    checks.choice(driver, DRIVERS, "driver")
    pq = checks.point_pair(coupler_point, "coupler_point")
    crossed = checks.flag(crossed, "crossed")

    O2 = np.zeros(2)
    u = polar((0, 0), 1.0, th1)
    foot = polar(O2, e, th1 + np.pi / 2)
    if start is None and driver == "slider":
        # the crank at right angles to the slide: away from the slider's dead centres
        A = polar(O2, r2, th1 + np.pi / 2)
        start = float(np.dot(circle_line(A, r3, foot, u, "the slider-crank with the crank across the slide")[0]
                             - foot, u))
    start = checks.number(0.0 if start is None else start, "start")
    what = f"the slider-crank at {driver} input {start:.12g}"
    if driver == "crank":
        A = polar(O2, r2, start)
        B = circle_line(A, r3, foot, u, what)[int(crossed)]
    elif driver == "coupler":
        c = polar((0, 0), r3, start)
        A = circle_line(O2, r2, foot - c, u, what)[int(crossed)]
        B = A + c
    else:
        B = foot + start * u
        A = circle_circle(O2, r2, B, r3, what)[int(crossed)]
    m = Mechanism(name)  # the crank's and coupler's angles are their lines O2 -> A and A -> B
    m.add_body("crank")
    m.add_body("coupler")
    m.add_body("slider", angle=th1)
    m.add_revolute("O2", m.ground, "crank", at=O2)
    m.add_revolute("A", "crank", "coupler", at=A)
    m.add_revolute("B", "coupler", "slider", at=B)
    m.add_prismatic("slide", m.ground, "slider", at=B, direction=u, origin=foot)
    m.distance("O2", "A", r2)  # stated, so that a file of it re-assembles when one is edited
    m.distance("A", "B", r3)
    if pq is not None:
        m.add_point("C", "coupler", at=along(A, B, *pq))
        if pq[1] != 0:  # C off the line A -> B: its distances from A and B hold it on the coupler
            m.distance("A", "C", float(np.hypot(*pq)))
            m.distance("B", "C", float(np.hypot(r3 - pq[0], pq[1])))
    if driver == "slider":
        m.drive("slide", start=start)
    else:
        m.drive(body=driver, start=start)
    return m
