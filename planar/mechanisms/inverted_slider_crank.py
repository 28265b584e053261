"""The inverted slider-crank of the seed (sldinv): the slider rides on the rocking link 3.

Loop r2 e^{i th2} = r1 e^{i th1} + r3 e^{i th3} + r4 e^{i th4}, th4 = th3 - 90 deg: link 3
turns about O4; the slider, pinned to the crank at A, slides on the line of link 3 that runs
r4 to its right; r3 is the slider's travel along that line.

>>> import numpy as np
>>> from planar.mechanisms import inverted_slider_crank
>>> m = inverted_slider_crank(20, 8.5, start=np.radians(60))
>>> res = m.sweep(np.radians([60.0]), velocity=2.5)
>>> res.coordinate("slide").round(6).tolist(), np.degrees(res.angle("link3")).round(4).tolist()
([17.385339], [154.9496])
"""

import numpy as np

from planar.mechanisms import checks
from planar.mechanisms.sketch import circle_circle, circle_line, line_through, polar
from planar.model import Mechanism

DRIVERS = ("crank", "link3", "slide")


def inverted_slider_crank(ground: float = 20.0, crank: float = 8.5, *, offset: float = 0.0,
                          frame_angle: float = 0.0, crossed: bool = False, driver: str = "crank",
                          start: float | None = None, name: str = "inverted_slider_crank") -> Mechanism:
    """An inverted slider-crank sketched at input ``start`` and driven.

    Parameters
    ----------
    ground, crank : float
        Lengths r1 (O2 to O4) and r2 (O2 to A).
    offset : float
        r4, the signed distance of the slide line to the right of link 3's axis through O4.
    frame_angle : float
        Angle th1 of O2 -> O4 (radians); O2 is at the origin.
    crossed : bool
        The other assembly mode. Crank driven: travel r3 < 0 (default r3 > 0). Link-3 driven:
        the smaller of the two travels (default the larger). Slide driven: A right of the
        directed line O2 -> O4 (default left).
    driver : {"crank", "link3", "slide"}
        The input: the absolute angle of O2 -> A, the absolute angle th3 of link 3, or the
        travel r3 (joint ``slide``).
    start : float, optional
        Input value of the sketch. Default 0 for the angle drivers; for the slide, the travel
        of the (default-mode) pose with the crank at right angles to O2 -> O4.

    Returns
    -------
    planar.Mechanism
        Bodies ``crank`` (th2), ``link3`` (th3) and ``slider`` (th4 = th3 - 90 deg); points
        ``O2``, ``O4``, ``A`` (revolutes) and ``slide`` (the prismatic joint, at A).

    Examples
    --------
    >>> import numpy as np
    >>> res = inverted_slider_crank().sweep(np.linspace(0, 2 * np.pi, 9))
    >>> bool(res.ok.all()), float(res.coordinate("slide")[0])
    (True, 11.5)
    """
    r1, r2 = checks.lengths(ground=ground, crank=crank)
    r4 = checks.number(offset, "offset")
    th1 = checks.number(frame_angle, "frame_angle")
    checks.choice(driver, DRIVERS, "driver")
    crossed = checks.flag(crossed, "crossed")

    O2 = np.zeros(2)
    O4 = polar(O2, r1, th1)
    if start is None and driver == "slide":
        # the crank across the ground line: away from the dead centres of the slide drive
        start = line_through(O4, r4, polar(O2, r2, th1 + np.pi / 2), True,
                             "the inverted slider-crank with the crank across the ground line")[1]
    start = checks.number(0.0 if start is None else start, "start")
    what = f"the inverted slider-crank at {driver} input {start:.12g}"
    if driver == "crank":
        A = polar(O2, r2, start)
        th3, _ = line_through(O4, r4, A, not crossed, what)
    elif driver == "link3":
        th3 = start
        A = circle_line(O2, r2, polar(O4, r4, th3 - np.pi / 2), polar((0, 0), 1.0, th3), what)[int(crossed)]
    else:
        A = circle_circle(O2, r2, O4, np.hypot(start, r4), what)[int(crossed)]
        th3, _ = line_through(O4, r4, A, start >= 0, what)
    angles = {"link3": start if driver == "link3" else th3}
    foot = polar(O4, r4, angles["link3"] - np.pi / 2)

    m = Mechanism(name)
    m.add_body("crank")  # its angle is its line O2 -> A
    m.add_body("link3", angle=angles["link3"])
    m.add_body("slider", angle=angles["link3"] - np.pi / 2)
    m.add_revolute("O2", m.ground, "crank", at=O2)
    m.add_revolute("O4", m.ground, "link3", at=O4)
    m.add_revolute("A", "crank", "slider", at=A)
    m.add_prismatic("slide", "link3", "slider", at=A, direction=polar((0, 0), 1.0, angles["link3"]), origin=foot)
    if driver == "slide":
        m.drive("slide", start=start)
    else:
        m.drive(body=driver, start=start)
    return m
