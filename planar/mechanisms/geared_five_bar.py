"""The geared five-bar of the seed (f5link): a five-bar loop closed by a pair of gears.

Gear 2 (pitch radius R2) turns about O2 at the origin; arm 3 (length R2 + R4) turns about O2
too and carries the centre B of gear 4 (radius R4), which meshes with gear 2; link 4 (length
R4) is fixed to gear 4 and pinned at C to link 5 (length r5), pinned to the ground at
O5 = (r1, 0). Reference configuration: gear 2 at angle 0 with links 3 and 4 collinear; there the
gears are meshed, which fixes the rolling row (1 + g)(th3 - th30) = th2 + g (th4 - th40),
g = R4 / R2. The input is gear 2's angle.

>>> import numpy as np
>>> from planar.mechanisms import geared_five_bar
>>> res = geared_five_bar(8, 3, 3.5, 6).sweep(np.radians([60.0]), velocity=10.0)
>>> np.degrees(res.angle("arm")).round(6).tolist(), res.omega("link5").round(6).tolist()
([52.150565], [1.844273])
"""

import numpy as np

from planar.errors import AssemblyError
from planar.mechanisms import checks
from planar.mechanisms.sketch import angle_of, circle_circle, polar
from planar.model import Mechanism

BODIES = ("gear2", "arm", "gear4", "link5")


def geared_five_bar(ground: float = 8.0, gear_radius_2: float = 3.0, gear_radius_4: float = 3.5,
                    link_5: float = 6.0, *, crossed: bool = False, start: float = 0.0,
                    name: str = "geared_five_bar") -> Mechanism:
    """The seed's geared five-bar, driven by gear 2's angle and sketched at input ``start``.

    Parameters
    ----------
    ground, gear_radius_2, gear_radius_4, link_5 : float
        r1 (O2 to O5), the pitch radii R2 and R4, and r5 (O5 to C).
    crossed : bool
        The other reference configuration: C below the line O2 -> O5 (default above).
    start : float
        Gear 2's angle in the sketch (radians). The reference configuration is at 0; another
        start is reached from it along its branch by the solver, so the gears stay meshed as
        in the reference.

    Returns
    -------
    planar.Mechanism
        Bodies ``gear2`` (th2), ``arm`` (th3, O2 -> B), ``gear4`` (th4, B -> C, link 4) and
        ``link5`` (th5, O5 -> C); points ``O2`` (gear 2's pivot), ``A`` (the arm's pivot, also
        at O2), ``B``, ``C``, ``O5`` and the gear mesh ``mesh`` (at B).

    Examples
    --------
    >>> import numpy as np
    >>> m = geared_five_bar(start=np.radians(30))
    >>> float(np.degrees(m.compile().u0[0]).round(12))
    30.0
    """
    r1, R2, R4, r5 = checks.lengths(ground=ground, gear_radius_2=gear_radius_2, gear_radius_4=gear_radius_4,
                                     link_5=link_5)
    start = checks.number(start, "start")
    O2, O5 = np.zeros(2), np.array([r1, 0.0])
    # reference configuration: links 3 and 4 in line, so O2, B, C are collinear
    crossed = checks.flag(crossed, "crossed")
    C = circle_circle(O2, R2 + 2 * R4, O5, r5, "the geared five-bar's reference configuration")[int(crossed)]
    th30 = angle_of(O2, C)
    pose = {"B": polar(O2, R2 + R4, th30), "C": C}
    m = _build(name, O2, O5, pose, 0.0, R2, R4)
    if start == 0.0:
        return m
    res = m.sweep([start])
    if not res.ok[0]:
        raise AssemblyError(f"the geared five-bar cannot reach gear angle {start:.12g} rad from its reference "
                            f"configuration ({res.model.name!r}: status {res.status[0]}); choose a start inside "
                            f"its motion range")
    pose = {p: res.position(p)[0] for p in pose}
    return _build(name, O2, O5, pose, float(res.angle("gear2")[0]), R2, R4)


def _build(name, O2, O5, pose, gear_angle, R2, R4):
    m = Mechanism(name)  # the arm's, gear 4's and link 5's angles are their lines O2 -> B, B -> C, O5 -> C
    for b in BODIES:
        m.add_body(b, angle=gear_angle if b == "gear2" else None)
    m.add_revolute("O2", m.ground, "gear2", at=O2)
    m.add_revolute("A", m.ground, "arm", at=O2)
    m.add_revolute("B", "arm", "gear4", at=pose["B"])
    m.add_revolute("C", "gear4", "link5", at=pose["C"])
    m.add_revolute("O5", "link5", m.ground, at=O5)
    m.add_gear("mesh", "gear2", "gear4", R2, R4, carrier="arm", centre_a=O2)
    m.drive(body="gear2")
    return m
