"""Motion generation: a four-bar whose coupler passes prescribed positions (point and angle).

A position j is the coupler point P_j and the coupler's angle th_j; the displacements from
position 1 are delta_j = P_j - P_1 and alpha_j = th_j - th_1. A dyad is a link W from a ground
pivot to a moving pivot, then Z from the moving pivot to P on the coupler; its link turns by
beta_j. Closing the loop of the dyad between positions 1 and j gives the standard form
(Erdman and Sandor)::

    W (e^{i beta_j} - 1) + Z (e^{i alpha_j} - 1) = delta_j,   j = 2, 3

two complex equations, linear in W and Z: for three positions, the rotations beta_2, beta_3
are free choices and the dyad follows in closed form. The crank is one such dyad (rotations
``beta``), the rocker another (``gamma``); together they make the four-bar.

>>> import numpy as np
>>> positions = [(0.0, 0.0, 0.0), (1.0, 0.5, np.radians(20)), (2.0, 0.6, np.radians(45))]
>>> s = motion_four_bar(positions, beta=np.radians([30, 70]), gamma=np.radians([15, 40]))
>>> bool(s.errors.max() < 1e-9), s.ok
(True, True)
"""

import numpy as np

from planar.errors import InputError, SynthesisError
from planar.mechanisms import four_bar
from planar.mechanisms.sketch import left_of
from planar.synthesis.result import check


def positions_array(positions, count=None):
    """The positions as an (N, 3) float array of x, y, angle (radians)."""
    P = np.asarray(positions, float)
    if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)) or (count is not None and len(P) != count):
        need = f"{count}" if count is not None else "N"
        raise InputError(f"positions must be a ({need}, 3) array of finite x, y, angle (radians), got shape {P.shape}")
    return P


def dyad(positions, rotations):
    """The dyad (W, Z), complex link vectors in position 1, whose link W turns by
    ``rotations`` (beta_2, beta_3) while the coupler moves through the three ``positions``.

    >>> beta, alpha = np.array([0, np.pi / 2, np.pi]), np.array([0, np.pi / 6, np.pi / 3])
    >>> P = 1.0 * np.exp(1j * beta) + 0.5j * np.exp(1j * alpha)   # made by W = 1, Z = 0.5i about O = 0
    >>> W, Z = dyad(np.column_stack((P.real, P.imag, alpha)), beta[1:])
    >>> complex(np.round(W, 12)), complex(np.round(Z, 12))
    ((1+0j), 0.5j)
    """
    P = positions_array(positions, 3)
    b = np.asarray(rotations, float)
    if b.shape != (2,) or not np.all(np.isfinite(b)):
        raise InputError(f"rotations must be two finite angles (beta_2, beta_3) in radians, got {rotations!r}")
    z = P[:, 0] + 1j * P[:, 1]
    M = np.array([[np.exp(1j * b[0]) - 1, np.exp(1j * (P[1, 2] - P[0, 2])) - 1],
                  [np.exp(1j * b[1]) - 1, np.exp(1j * (P[2, 2] - P[0, 2])) - 1]])
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    if abs(det) < 1e-12:
        raise SynthesisError(f"the rotations {np.round(b, 9).tolist()} rad leave the dyad's equations singular "
                             "(a rotation of zero, or equal to the coupler's): choose other rotations")
    d = z[1:] - z[0]
    return (d[0] * M[1, 1] - d[1] * M[0, 1]) / det, (M[0, 0] * d[1] - M[1, 0] * d[0]) / det


def motion_four_bar(positions, *, beta, gamma, name="motion_four_bar"):
    """A four-bar whose coupler point C passes the three ``positions`` (x, y, angle of the
    coupler, radians) with the coupler at those angles; ``beta`` (beta_2, beta_3) are the
    crank's rotations from position 1 to positions 2 and 3, ``gamma`` the rocker's (the free
    choices). Returns a :class:`planar.synthesis.Synthesis`: targets the positions,
    ``achieved`` what planar's sweep of the built four-bar reaches at the crank angles of the
    positions, ``errors`` (3, 2) the point's distance and the angle's error there."""
    P = positions_array(positions, 3)
    W, Z = dyad(P, beta)
    U, S = dyad(P, gamma)
    P1 = complex(P[0, 0], P[0, 1])
    O2, A, B, O4 = P1 - Z - W, P1 - Z, P1 - S, P1 - S - U
    AB = B - A
    for what, v in (("crank", W), ("rocker", U), ("coupler", AB), ("ground", O4 - O2)):
        if abs(v) < 1e-12 * (1 + abs(P1)):
            raise SynthesisError(f"the free choices beta = {np.round(beta, 9).tolist()}, gamma = "
                                 f"{np.round(gamma, 9).tolist()} give a {what} of zero length: choose others")
    C = (P1 - A) * np.conj(AB) / abs(AB)  # C in the coupler's frame: along A -> B and to its left
    design = dict(ground=abs(O4 - O2), crank=abs(W), coupler=abs(AB), rocker=abs(U),
                  frame_angle=float(np.angle(O4 - O2)), coupler_point=(float(C.real), float(C.imag)),
                  crossed=not left_of(_xy(A), _xy(O4), _xy(B)), start=float(np.angle(W)),
                  pivot=(float(O2.real), float(O2.imag)), name=name)
    design = {k: (float(v) if isinstance(v, np.floating) else v) for k, v in design.items()}
    mech = four_bar(**design)
    inputs = np.angle(W) + np.r_[0.0, np.asarray(beta, float)]
    size = float(np.ptp(P[:, :2], axis=0).max()) or 1.0

    def achieve(res, i):
        th = P[0, 2] + res.angle("coupler")[i] - res.angle("coupler")[i[0]]
        return np.column_stack((res.position("C")[i], th))

    def error(got, want):
        return np.column_stack((np.hypot(*(got[:, :2] - want[:, :2]).T),
                                np.abs(np.angle(np.exp(1j * (got[:, 2] - want[:, 2]))))))

    return check(mech, four_bar, design, inputs, P, achieve, error, period=2 * np.pi, point="C", size=size)


def _xy(z):
    return np.array([z.real, z.imag])
