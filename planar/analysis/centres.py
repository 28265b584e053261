"""Instant centres of relative rotation, from the solver's velocity solution.

The instant centre of bodies i and j is the point whose velocity is the same on both. With
V_k the velocity of body k's point at the world origin and w_k its angular velocity, a point P
of body k moves at V_k + w_k perp(P), so (w_i - w_j) perp(P) = V_j - V_i.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> res = four_bar(4, 2, 3, 4, start=np.radians(60)).sweep(np.radians([60.0]))
>>> instant_centre(res, "ground", "coupler").round(6).tolist()   # I13: lines O2A and O4B meet
[[2.839095, 4.917457]]
"""

import numpy as np

from planar.errors import ModelError
from planar.geometry import perp
from planar.results import as_sweep

TRANSLATION = 1e-12  # relative angular velocity, against the bodies' rates, below which the centre is at infinity


def _motion(res, body):
    """V (N, 2), the velocity of the body's point at the world origin, and w (N,)."""
    b = res.model.body_id(body)
    N = len(res)
    if b == 0:
        return np.zeros((N, 2)), np.zeros(N)
    r, rd, w = res.q[:, 3 * b - 3 : 3 * b - 1], res.qd[:, 3 * b - 3 : 3 * b - 1], res.qd[:, 3 * b - 1]
    return rd - perp(r) * w[:, None], w


def instant_centre(res, body_a, body_b):
    """(N, 2) locus of the instant centre of ``body_a`` and ``body_b`` over the sweep ``res``.

    NaN where the rates are not valid (see ``res.status``) and where the two bodies turn at the
    same rate: their relative motion is then a translation (the centre is at infinity, for
    example across a prismatic joint) or, at that instant, none at all. With ``body_a`` the ground, the locus is the fixed centrode of ``body_b``.
    """
    as_sweep(res, "instant_centre")
    if isinstance(body_a, str) and body_a == body_b:  # (NaN: a body has no motion relative to itself)
        raise ModelError(f"an instant centre is of two bodies, got {body_a!r} twice: name another body")
    Va, wa = _motion(res, body_a)
    Vb, wb = _motion(res, body_b)
    dw = wa - wb
    L = res.model.L
    scale = np.abs(wa) + np.abs(wb) + np.hypot(*(Vb - Va).T) / L
    with np.errstate(invalid="ignore", divide="ignore"):
        P = -perp(Vb - Va) / dw[:, None]
    return np.where((np.abs(dw) > TRANSLATION * scale)[:, None], P, np.nan)


def instant_centres(res):
    """Every instant centre of the mechanism: {(body_a, body_b): (N, 2) locus} for each pair of
    bodies (the ground included) in the model's body order.

    >>> import numpy as np
    >>> from planar.mechanisms import four_bar
    >>> ic = instant_centres(four_bar().sweep([0.5]))
    >>> len(ic), bool(np.allclose(ic["ground", "crank"], 0.0))   # I12 is the pivot O2
    (6, True)
    """
    names = as_sweep(res, "instant_centres").model.body_names
    return {(a, b): instant_centre(res, a, b) for i, a in enumerate(names) for b in names[i + 1 :]}
