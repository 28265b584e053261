"""An open serial chain of links (the seed's acc2 / dyad): one input per link.

>>> import numpy as np
>>> from planar.mechanisms import open_chain
>>> m = open_chain([5.0], start=[np.radians(10)])
>>> res = m.sweep([[np.radians(10)]], velocity=[20.0])
>>> res.position("tip").round(6).tolist(), res.velocity("tip").round(6).tolist()
([[4.924039, 0.868241]], [[-17.364818, 98.480775]])
"""

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from planar.errors import ModelError
from planar.mechanisms import checks
from planar.mechanisms.sketch import polar
from planar.model import Mechanism
from planar.model.checks import is_complex


def open_chain(lengths: Sequence[float] = (5.0, 8.0, 9.0), *, start: ArrayLike | None = None,
               driver: str = "absolute", name: str = "open_chain") -> Mechanism:
    """A serial chain from a ground pivot at the origin, every link driven.

    Parameters
    ----------
    lengths : sequence of float
        Link lengths r1 ... rN (1 to 256).
    start : sequence of float, optional
        Input values of the sketch (radians; default all 0, the chain along +x).
    driver : {"absolute", "relative"}
        Inputs are the links' absolute angles (the seed's convention), or the joints'
        relative angles (link k against link k-1; the ground for link 1).

    Returns
    -------
    planar.Mechanism
        Bodies ``link1`` ... ``linkN`` (angle of each link's direction); revolutes ``J1`` (on the
        ground, at the origin) ... ``JN``; point ``tip`` at the end of the last link. Inputs in
        link order.

    Examples
    --------
    >>> import numpy as np
    >>> res = open_chain([1.0, 1.0], driver="relative").sweep([[0.0, np.pi / 2]])
    >>> res.position("tip").round(12).tolist()
    [[1.0, 1.0]]
    """
    r = checks.length_list(lengths, "lengths")
    checks.choice(driver, ("absolute", "relative"), "driver")
    try:
        if start is not None and is_complex(start):  # (numpy would take its real part)
            raise TypeError(start)
        th0 = np.zeros(len(r)) if start is None else np.asarray(start, dtype=float)
    except (TypeError, ValueError, OverflowError):
        th0 = None
    if th0 is None or th0.shape != (len(r),) or not np.all(np.isfinite(th0)):
        raise ModelError(f"start must hold {len(r)} finite angles, one per link; got {start!r}")
    angles = th0 if driver == "absolute" else np.cumsum(th0)

    m = Mechanism(name)
    P, prev = np.zeros(2), m.ground
    for k, (rk, th) in enumerate(zip(r, angles), 1):
        link = m.add_body(f"link{k}")  # its angle is its line J_k -> J_k+1 (or -> tip)
        m.add_revolute(f"J{k}", prev, link, at=P)
        P, prev = polar(P, rk, th), link
    m.add_point("tip", prev, at=P)
    for k in range(1, len(r) + 1):
        if driver == "absolute":
            m.drive(body=f"link{k}", start=float(th0[k - 1]))
        else:
            m.drive(f"J{k}", start=float(th0[k - 1]))
    return m
