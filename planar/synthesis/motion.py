"""Motion generation: a four-bar whose coupler passes prescribed positions (point and angle).

A position j is the coupler point P_j and the coupler's angle th_j; the displacements from
position 1 are delta_j = P_j - P_1 and alpha_j = th_j - th_1. A dyad is a link W from a ground
pivot to a moving pivot, then Z from the moving pivot to P on the coupler; its link turns by
beta_j. Closing the loop of the dyad between positions 1 and j gives the standard form
(Erdman and Sandor)::

    W (e^{i beta_j} - 1) + Z (e^{i alpha_j} - 1) = delta_j,   j = 2, 3

two complex equations, linear in W and Z: for three positions, the rotations beta_2, beta_3
are free choices and the dyad follows in closed form. The crank is one such dyad (rotations
``beta``), the rocker another (``gamma``); together they make the four-bar. With four
positions only beta_2 is free: beta_3 and beta_4 follow from Burmester's compatibility
equation (:func:`compatible`; over every beta_2 the dyads' pivots trace the centre-point and
circle-point curves, :func:`burmester_curves`); five positions leave up to four dyads, the
Burmester points (:func:`burmester_points`).

>>> import numpy as np
>>> positions = [(0.0, 0.0, 0.0), (1.0, 0.5, np.radians(20)), (2.0, 0.6, np.radians(45))]
>>> s = motion_four_bar(positions, beta=np.radians([30, 70]), gamma=np.radians([15, 40]))
>>> bool(s.errors.max() < 1e-9), s.ok
(True, True)
"""

import numpy as np

from planar.arguments import finite_number
from planar.errors import InputError, SynthesisError
from planar.mechanisms import four_bar
from planar.mechanisms.sketch import left_of
from planar.model.checks import MAX_ANGLE, SCALE
from planar.synthesis.result import check, floats

MAX_SAMPLES = 10**5  # values of beta_2 over a turn: ~0.1 ms each (burmester_points: ~0.3 ms), far finer than needed


def positions_array(positions, count=None):
    """The positions as an (N, 3) float array of x, y, angle (radians)."""
    P = floats(positions)
    if P is None:
        raise InputError(f"positions must be an (N, 3) array of finite x, y, angle (radians), got {positions!r}")
    if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)) or (count is not None and len(P) != count):
        need = f"{count}" if count is not None else "N"
        raise InputError(f"positions must be a ({need}, 3) array of finite x, y, angle (radians), got shape {P.shape}")
    far, turned = np.abs(P[:, :2]).max(initial=0.0), np.abs(P[:, 2]).max(initial=0.0)
    if far > SCALE or turned > MAX_ANGLE:  # (beyond, the displacements and their products overflow)
        raise InputError(f"positions reach x, y = {far:.3g}, angle {turned:.3g} rad: give x, y within +-{SCALE:g} "
                         f"(in another unit) and angles within +-{MAX_ANGLE:g} rad")
    return P


def _samples(samples, default):
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"samples must be a whole number from 2 to {MAX_SAMPLES} (values of beta_2 over a turn; "
                         f"the default is {default}), got {samples!r}")
    return int(samples)


def dyad(positions, rotations):
    """The dyad (W, Z), complex link vectors in position 1, whose link W turns by
    ``rotations`` (beta_2 ... beta_N) while the coupler moves through the N ``positions``
    (3 to 5). The first two equations fix W and Z; with four or five positions the rotations
    must be compatible (from :func:`compatible` or :func:`burmester_points`), which the other
    equations check.

    >>> beta, alpha = np.array([0, np.pi / 2, np.pi]), np.array([0, np.pi / 6, np.pi / 3])
    >>> P = 1.0 * np.exp(1j * beta) + 0.5j * np.exp(1j * alpha)   # made by W = 1, Z = 0.5i about O = 0
    >>> W, Z = dyad(np.column_stack((P.real, P.imag, alpha)), beta[1:])
    >>> complex(np.round(W, 12)), complex(np.round(Z, 12))
    ((1+0j), 0.5j)
    """
    P = positions_array(positions)
    if not 3 <= len(P) <= 5:
        raise InputError(f"motion generation takes 3, 4 or 5 positions, got {len(P)}")
    b = floats(rotations)
    if b is None or b.shape != (len(P) - 1,) or not np.all(np.isfinite(b)):
        raise InputError(f"rotations must be {len(P) - 1} finite angles (beta_2 ... beta_{len(P)}) in radians, "
                         f"got {rotations!r}")
    M, d = _standard_form(P, b)
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    if abs(det) < 1e-12:
        raise SynthesisError(f"the rotations {np.round(b, 9).tolist()} rad leave the dyad's equations singular "
                             "(a rotation of zero, or equal to the coupler's): choose other rotations")
    W = (d[0] * M[1, 1] - d[1] * M[0, 1]) / det
    Z = (M[0, 0] * d[1] - M[1, 0] * d[0]) / det
    miss = np.abs(M[2:] @ np.array([W, Z]) - d[2:])
    if np.any(miss > 1e-9 * (1 + np.abs(d).max())):
        raise SynthesisError(f"the rotations {np.round(b, 9).tolist()} rad do not fit positions 4 and on "
                             f"(missed by {miss.max():.3g}): take them from compatible() or burmester_points()")
    return W, Z


def _standard_form(P, b):
    """Rows (e^{i beta_j} - 1, e^{i alpha_j} - 1) and right-hand sides delta_j, j = 2 ... N."""
    z = P[:, 0] + 1j * P[:, 1]
    M = np.column_stack((np.exp(1j * b) - 1, np.exp(1j * (P[1:, 2] - P[0, 2])) - 1))
    return M, z[1:] - z[0]


def compatible(positions, beta2):
    """The rotation sets (beta_2, beta_3, beta_4) of a dyad through four positions with its
    link turning ``beta2`` to position 2: zero, one or two (Burmester's compatibility
    equation, sum_j D_j e^{i beta_j} = sum_j D_j, solved as a triangle for beta_3, beta_4).

    >>> P = [(0, 0, 0), (1, 0.2, 0.3), (1.8, 0.6, 0.7), (2.4, 1.3, 1.0)]
    >>> [np.round(b, 6).tolist() for b in compatible(P, 0.5)]
    [[0.5, 0.711206, 1.11171], [0.5, -1.078987, -1.299932]]
    """
    P = positions_array(positions, 4)
    if not finite_number(beta2):
        raise InputError(f"beta2 must be a finite angle in radians (the dyad's rotation from position 1 to 2), "
                         f"got {beta2!r}")
    a = np.exp(1j * (P[1:, 2] - P[0, 2])) - 1
    d = (P[1:, 0] + 1j * P[1:, 1]) - (P[0, 0] + 1j * P[0, 1])
    D = np.array([a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2], a[0] * d[1] - a[1] * d[0]])
    R = D.sum() - D[0] * np.exp(1j * beta2)
    r1, r2, L = abs(D[1]), abs(D[2]), abs(R)
    if L == 0 or r1 == 0 or r2 == 0:
        return []
    along = (r1**2 - r2**2 + L**2) / (2 * L)
    h2 = r1**2 - along**2
    if h2 < 0:
        return []
    out = []
    for h in sorted({np.sqrt(h2), -np.sqrt(h2)}, reverse=True):
        x = (along + 1j * h) * R / L
        out.append(np.array([beta2, np.angle(x / D[1]), np.angle((R - x) / D[2])]))
    return out


def burmester_curves(positions, samples=360):
    """The centre-point and circle-point curves of four positions: for ``samples`` values of
    beta_2 over a turn, the ground pivots (centre points) and moving pivots in position 1
    (circle points) of the compatible dyads, as complex arrays (samples, 2) (NaN where there
    is none). Returns (beta2, centre, circle)."""
    P = positions_array(positions, 4)
    beta2 = np.linspace(0, 2 * np.pi, _samples(samples, 360), endpoint=False)[1:]
    centre = np.full((len(beta2), 2), np.nan + 0j)
    circle = centre.copy()
    P1 = complex(P[0, 0], P[0, 1])
    for k, b in enumerate(beta2):
        for m, rot in enumerate(compatible(P, b)):
            try:
                W, Z = dyad(P, rot)
            except SynthesisError:
                continue
            centre[k, m], circle[k, m] = P1 - Z - W, P1 - Z
    return beta2, centre, circle


def burmester_points(positions, samples=720):
    """The rotation sets (beta_2 ... beta_5) of the dyads through five positions (Burmester
    points: where the curves of positions 1-4 and 1-2-3-5 meet): zero, two or four, found on
    a grid of ``samples`` values of beta_2 and refined with Brent's method."""
    from scipy.optimize import brentq

    P = positions_array(positions, 5)
    first, second = P[[0, 1, 2, 3]], P[[0, 1, 2, 4]]

    def gap(b, i, j):
        u, v = compatible(first, b), compatible(second, b)
        if len(u) <= i or len(v) <= j:
            return np.nan
        return float(np.angle(np.exp(1j * (u[i][1] - v[j][1]))))

    grid = np.linspace(0, 2 * np.pi, _samples(samples, 720) + 1)[1:-1]
    found = []
    for i in range(2):
        for j in range(2):
            g = np.array([gap(b, i, j) for b in grid])
            for k in np.flatnonzero((np.sign(g[:-1]) * np.sign(g[1:]) < 0) & (np.abs(g[:-1] - g[1:]) < 1.0)):
                b2 = brentq(gap, grid[k], grid[k + 1], args=(i, j), xtol=1e-15, rtol=1e-15)
                rot = np.r_[compatible(first, b2)[i], compatible(second, b2)[j][2]]
                try:
                    dyad(P, rot)
                except SynthesisError:
                    continue
                if not any(np.allclose(np.exp(1j * rot), np.exp(1j * f)) for f in found):
                    found.append(rot)
    return found


def motion_four_bar(positions, *, beta, gamma, name="motion_four_bar"):
    """A four-bar whose coupler point C passes the ``positions`` (x, y, angle of the coupler,
    radians; three, four or five) with the coupler at those angles; ``beta`` (beta_2 ...) are
    the crank's rotations from position 1 to the others, ``gamma`` the rocker's: with three
    positions the free choices, with four from :func:`compatible` (beta_2 free), with five
    from :func:`burmester_points`. Returns a :class:`planar.synthesis.Synthesis`: targets the
    positions, ``achieved`` what planar's sweep of the built four-bar reaches at the crank
    angles of the positions, ``errors`` (N, 2) the point's distance and the angle's error
    there."""
    P = positions_array(positions)
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

    return check(mech, four_bar, design, inputs, P, achieve, error, period=2 * np.pi, point="C", size=size,
                 exact=True)


def _xy(z):
    return np.array([z.real, z.imag])
