"""Closed-form kinematics used only as test oracles (pure numpy; never imports `planar`).

Conventions (see the spec README): angles in radians, counter-clockwise from +x; a positive rate
is counter-clockwise; a link vector of length r at angle t is r e^{it}. Every oracle is vectorised
over its input angle (or travel) array; points come back as arrays of shape (..., 2) = (x, y).
Where a mechanism does not assemble the outputs are NaN.
"""
import json
import pathlib

import numpy as np

REFERENCE_PATH = pathlib.Path(__file__).parent / "data" / "textbook_reference.json"


def load_reference():
    """Reference cases of tests/data/textbook_reference.json as a dict id -> case."""
    with open(REFERENCE_PATH, encoding="utf-8") as fh:
        return {case["id"]: case for case in json.load(fh)["cases"]}


# ----------------------------------------------------------------------------- helpers

def _e(t):
    return np.exp(1j * np.asarray(t, dtype=float))


def _xy(z):
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag], axis=-1)


def _wrap(t):
    """Angle wrapped to (-pi, pi]."""
    return np.angle(_e(t))


def _cross(a, b):
    """z-component of a x b for complex numbers taken as plane vectors."""
    return (np.conj(a) * b).imag


def _solve2(P, Q, R):
    """Real x, y with x P + y Q = R (one complex equation = two real rows), by Cramer's rule;
    inf/NaN where P and Q are parallel (a singular position)."""
    with np.errstate(all="ignore"):
        return _cross(Q, R) / _cross(Q, P), _cross(P, R) / _cross(P, Q)


def _sqrt_or_nan(x):
    x = np.asarray(x, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.where(x >= 0, np.sqrt(np.maximum(x, 0.0)), np.nan)


def _acos_or_nan(c):
    c = np.asarray(c, dtype=float)
    return np.where(np.abs(c) <= 1, np.arccos(np.clip(c, -1, 1)), np.nan)


def _turn_intervals(intervals, shift=0.0):
    """Shift angle intervals by `shift`, start each in [-pi, pi), sort by start."""
    out = []
    for lo, hi in intervals:
        if hi - lo >= 2 * np.pi:
            return [(-np.pi, np.pi)]
        start = (lo + shift + np.pi) % (2 * np.pi) - np.pi
        out.append((start, start + (hi - lo)))
    return sorted(out)


def _sin_band(lo, hi, shift=0.0, snap=1e-12):
    """Intervals of x over one turn where lo <= sin(x - shift) <= hi (closed). A bound within
    `snap` of -1 or 1 is taken as reaching it: at a change point it does in exact arithmetic,
    and rounding must not cut a gap of ~1e-6 rad into a full turn."""
    lo = -1.0 if lo <= -1 + snap else lo
    hi = 1.0 if hi >= 1 - snap else hi
    if lo > hi or lo > 1 or hi < -1:
        return []
    if lo <= -1 and hi >= 1:
        return [(-np.pi, np.pi)]
    if hi >= 1:                                   # only sin >= lo bites
        a = np.arcsin(lo)
        return _turn_intervals([(a, np.pi - a)], shift)
    if lo <= -1:                                  # only sin <= hi bites
        b = np.arcsin(hi)
        return _turn_intervals([(np.pi - b, 2 * np.pi + b)], shift)
    a, b = np.arcsin(lo), np.arcsin(hi)           # both bite: one interval each side
    return _turn_intervals([(a, b), (np.pi - b, np.pi - a)], shift)


# ----------------------------------------------------------------------------- four-bar

def four_bar(r1, r2, r3, r4, th2, w2=1.0, a2=0.0, th1=0.0, sigma=1, p=None, q=None):
    """Crank-driven four-bar. O2 = 0, O4 = r1 e^{i th1}, A = r2 e^{i th2}, B = A + r3 e^{i th3}
    = O4 + r4 e^{i th4}. sigma = +1: B left of the directed line A -> O4, -1: right.
    Returns th3, th4 (wrapped to (-pi, pi]), w3, w4, a3, a4, A, B and, when p, q are given, the
    coupler point C = A + (p + i q) e^{i th3} with C_vel, C_acc."""
    th2 = np.asarray(th2, dtype=float)
    A = r2 * _e(th2)
    O4 = r1 * _e(th1)
    d = O4 - A
    L = np.abs(d)
    with np.errstate(all="ignore"):  # A on O4 (L = 0): no triangle, NaN
        alpha = _acos_or_nan((r3**2 + L**2 - r4**2) / (2 * r3 * L))  # angle at A in triangle A B O4
    th3 = _wrap(np.angle(d) + sigma * alpha)
    B = A + r3 * _e(th3)
    th4 = np.angle(B - O4)
    # The spec's verified closed forms (acceleration errata of seed 003 fixed); at a toggle
    # (sin(th4 - th3) = 0) the rates are infinite or NaN, which is the answer, not an accident.
    with np.errstate(all="ignore"):
        w3 = r2 * w2 * np.sin(th2 - th4) / (r3 * np.sin(th4 - th3))
        w4 = r2 * w2 * np.sin(th2 - th3) / (r4 * np.sin(th4 - th3))
        a3 = (-r2 * a2 * np.sin(th2 - th4) - r2 * w2**2 * np.cos(th2 - th4)
              - r3 * w3**2 * np.cos(th3 - th4) + r4 * w4**2) / (r3 * np.sin(th3 - th4))
        a4 = (r2 * a2 * np.sin(th2 - th3) + r2 * w2**2 * np.cos(th2 - th3)
              + r3 * w3**2 - r4 * w4**2 * np.cos(th4 - th3)) / (r4 * np.sin(th4 - th3))
    out = dict(th3=th3, th4=th4, w3=w3, w4=w4, a3=a3, a4=a4, A=_xy(A), B=_xy(B))
    if p is not None or q is not None:
        pq = (0.0 if p is None else p) + 1j * (0.0 if q is None else q)
        C = A + pq * _e(th3)
        out["C"] = _xy(C)
        with np.errstate(all="ignore"):  # infinite rates at a toggle, as above
            out["C_vel"] = _xy(1j * w2 * A + 1j * w3 * pq * _e(th3))
            out["C_acc"] = _xy((1j * a2 - w2**2) * A + (1j * a3 - w3**2) * pq * _e(th3))
    return out


def freudenstein(r1, r2, r3, r4, th2, p=0.0, q=0.0, sigma=1):
    """Crank-driven four-bar (O2 = 0, O4 = (r1, 0)) by Freudenstein's equation
    K1 cos th4 - K2 cos th2 + K3 = cos(th2 - th4), solved as a quadratic in tan(th4 / 2);
    vectorised over everything (lengths (D, 1) and th2 (N,) give (D, N) designs x angles).
    sigma = +1: B left of the directed line A -> O4 (the root taken per element by that
    side). Returns th3, th4 and the coupler point C = A + (p + i q) e^{i th3} (..., 2)."""
    r1, r2, r3, r4, th2 = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (r1, r2, r3, r4, th2)))
    K1, K2, K3 = r1 / r2, r1 / r4, (r2**2 - r3**2 + r4**2 + r1**2) / (2 * r2 * r4)
    c, s = np.cos(th2), np.sin(th2)
    A_, B_, C_ = c - K1 - K2 * c + K3, -2 * s, K1 - (K2 + 1) * c + K3
    with np.errstate(all="ignore"):
        root = np.sqrt(B_**2 - 4 * A_ * C_)
        A = r2 * _e(th2)
        best = None
        for sign in (1.0, -1.0):
            th4 = 2 * np.arctan2(-B_ + sign * root, 2 * A_)
            B = r1 + r4 * _e(th4)
            side = np.imag(np.conj(r1 - A) * (B - A)) * sigma > 0
            best = (th4, B) if best is None else (np.where(side, th4, best[0]), np.where(side, B, best[1]))
    th4, B = best
    th3 = np.angle(B - A)
    C = A + ((p + 1j * q) * np.ones_like(th2)) * _e(th3)
    return dict(th3=th3, th4=th4, C=_xy(C))


def four_bar_transmission_angle(r1, r2, r3, r4, th2, th1=0.0, sigma=1):
    """Angle between coupler and rocker, in [0, pi] (same for both assembly modes, so sigma is
    accepted only for a uniform call signature). NaN where the four-bar does not assemble."""
    L2 = np.abs(r1 * _e(th1) - r2 * _e(th2)) ** 2
    return _acos_or_nan((r3**2 + r4**2 - L2) / (2 * r3 * r4))


def grashof(r1, r2, r3, r4, rtol=1e-12):
    """Grashof class with r1 ground, r2 the input crank, r4 the output. s + l = p + q is taken
    as equal within rtol * l (change-point)."""
    links = [r1, r2, r3, r4]
    s, p, q, l = sorted(links)
    excess = (s + l) - (p + q)
    if abs(excess) <= rtol * l:
        return "change-point"
    if excess > 0:
        return "triple-rocker"
    # Grashof: the shortest link is unique here (a tie would force s + l >= p + q).
    return ("drag-link", "crank-rocker", "double-rocker", "rocker-crank")[int(np.argmin(links))]


def four_bar_input_limits(r1, r2, r3, r4):
    """Intervals (radians, start in [-pi, pi), sorted) of th2 over one turn where the four-bar
    assembles, th1 = 0: |A - O4| in [|r3 - r4|, r3 + r4], i.e.
    (r1^2 + r2^2 - (r3+r4)^2) / (2 r1 r2) <= cos th2 <= (r1^2 + r2^2 - (r3-r4)^2) / (2 r1 r2).
    A full turn is [(-pi, pi)]."""
    c_min = (r1**2 + r2**2 - (r3 + r4) ** 2) / (2 * r1 * r2)
    c_max = (r1**2 + r2**2 - (r3 - r4) ** 2) / (2 * r1 * r2)
    return _sin_band(c_min, c_max, shift=-np.pi / 2)  # cos x = sin(x + pi/2)


def four_bar_instant_centres(r1, r2, r3, r4, th2, th1=0.0, sigma=1):
    """Instant centres Ijk (1 ground, 2 crank, 3 coupler, 4 rocker) as (..., 2) points; I13 and
    I24 by Kennedy's theorem (inf/NaN when the two lines are parallel)."""
    fb = four_bar(r1, r2, r3, r4, th2, th1=th1, sigma=sigma)
    A, B = (fb[k][..., 0] + 1j * fb[k][..., 1] for k in ("A", "B"))
    O2 = np.zeros_like(A)
    O4 = r1 * _e(th1) + O2

    def meet(P1, d1, P2, d2):  # intersection of lines P1 + t d1 and P2 + s d2
        with np.errstate(all="ignore"):
            return P1 + _cross(P2 - P1, d2) / _cross(d1, d2) * d1

    return dict(I12=_xy(O2), I23=_xy(A), I34=_xy(B), I14=_xy(O4),
                I13=_xy(meet(O2, A - O2, O4, B - O4)),
                I24=_xy(meet(O2, O4 - O2, A, B - A)))


# ----------------------------------------------------------------------------- slider-crank
# Seed form: r2 e^{i th2} + r3 e^{i th3} = r1 e^{i th1} + offset e^{i(th1 + pi/2)}. The slider pin
# B sits at slide coordinates (r1, offset): r1 is the travel along th1 from the foot of the offset.

def slider_crank(r2, r3, th2, w2=1.0, a2=0.0, offset=0.0, th1=0.0, sigma=1):
    """Crank-driven slider-crank. sigma = +1: the root with B ahead (larger r1), -1: behind.
    Returns r1, th3, w3, a3, r1_v, r1_a, A, B."""
    u = _e(th1)
    A = r2 * _e(th2)
    a = A * np.conj(u)                            # crank pin in slide coordinates
    r1 = a.real + sigma * _sqrt_or_nan(r3**2 - (offset - a.imag) ** 2)
    B = (r1 + 1j * offset) * u
    th3 = np.angle(B - A)
    c = r3 * _e(th3)
    # i w2 A + i w3 c = r1' u, and its derivative.
    w3, r1_v = _solve2(1j * c, -u, -1j * w2 * A)
    a3, r1_a = _solve2(1j * c, -u, -(1j * a2 - w2**2) * A + w3**2 * c)
    return dict(r1=r1, th3=th3, w3=w3, a3=a3, r1_v=r1_v, r1_a=r1_a, A=_xy(A), B=_xy(B))


def slider_crank_coupler_driven(r2, r3, th3, w3=1.0, a3=0.0, offset=0.0, th1=0.0, sigma=1):
    """Coupler-driven slider-crank (seed driver 1). sigma = +1: the root with larger r1.
    Returns th2, r1, w2, r1_v, a2, r1_a, A, B."""
    u = _e(th1)
    c = r3 * _e(th3)
    V = offset * 1j * u - c                       # A = r1 u + V with |A| = r2
    b = (V * np.conj(u)).real
    r1 = -b + sigma * _sqrt_or_nan(b**2 - np.abs(V) ** 2 + r2**2)
    A = r1 * u + V
    th2 = np.angle(A)
    w2, r1_v = _solve2(1j * A, -u, -1j * w3 * c)
    a2, r1_a = _solve2(1j * A, -u, w2**2 * A - (1j * a3 - w3**2) * c)
    return dict(th2=th2, r1=r1, w2=w2, r1_v=r1_v, a2=a2, r1_a=r1_a, A=_xy(A), B=_xy(A + c))


def slider_crank_slider_driven(r2, r3, r1, v=1.0, a=0.0, offset=0.0, th1=0.0, sigma=1):
    """Slider-driven slider-crank (seed driver 2): travel r1 with rate v and acceleration a.
    sigma = +1: crank pin A left of the directed line O2 -> B (th2 = arg B + angle at O2),
    -1: right. Returns th2, th3, w2, w3, a2, a3, A, B."""
    u = _e(th1)
    B = (np.asarray(r1, dtype=float) + 1j * offset) * u
    Lb = np.abs(B)
    with np.errstate(all="ignore"):  # B on O2: no triangle, NaN
        gamma = _acos_or_nan((r2**2 + Lb**2 - r3**2) / (2 * r2 * Lb))
    th2 = _wrap(np.angle(B) + sigma * gamma)
    A = r2 * _e(th2)
    th3 = np.angle(B - A)
    c = r3 * _e(th3)
    # i w2 A + i w3 c = v u, and its derivative.
    w2, w3 = _solve2(1j * A, 1j * c, v * u)
    a2, a3 = _solve2(1j * A, 1j * c, a * u + w2**2 * A + w3**2 * c)
    return dict(th2=th2, th3=th3, w2=w2, w3=w3, a2=a2, a3=a3, A=_xy(A), B=_xy(B))


def slider_crank_stroke(r2, r3, e):
    """Stroke of the offset slider-crank (crank pivot at the origin, slider pin on y = e)."""
    return np.sqrt((r2 + r3) ** 2 - e**2) - np.sqrt((r3 - r2) ** 2 - e**2)


def slider_crank_time_ratio(r2, r3, e):
    """Time ratio (slow stroke / quick stroke crank angles; >= 1 for e >= 0)."""
    dth = np.pi + np.arcsin(e / (r3 - r2)) - np.arcsin(e / (r2 + r3))
    return dth / (2 * np.pi - dth)


def slider_crank_limits(r2, r3, offset, driver, th1=0.0):
    """Feasible intervals of the input. driver "crank": th2 with |r2 sin(th2 - th1) - offset|
    <= r3; "coupler": th3 with |r3 sin(th3 - th1) - offset| <= r2 (both over one turn, radians,
    start in [-pi, pi), sorted); "slider": travel r1 with (r2 - r3)^2 <= r1^2 + offset^2 <=
    (r2 + r3)^2 (sorted)."""
    if driver == "crank":
        return _sin_band((offset - r3) / r2, (offset + r3) / r2, th1)
    if driver == "coupler":
        return _sin_band((offset - r2) / r3, (offset + r2) / r3, th1)
    if driver == "slider":
        big = (r2 + r3) ** 2 - offset**2
        small = (r2 - r3) ** 2 - offset**2
        if big < 0:
            return []
        hi = np.sqrt(big)
        if small <= 0:
            return [(-hi, hi)]
        lo = np.sqrt(small)
        return [(-hi, -lo), (lo, hi)]
    raise ValueError(f"unknown driver {driver!r}")


# ---------------------------------------------------------------------- inverted slider-crank
# r2 e^{i th2} = r1 e^{i th1} + r3 e^{i th3} + r4 e^{i th4}, th4 = th3 - pi/2, so the last two
# terms are (r3 - i r4) e^{i th3}: r3 is the slider's (variable) position along link 3.

def inverted_slider_crank(r1, r2, r4, th2, w2=1.0, a2=0.0, th1=0.0, sigma=1):
    """Crank-driven inverted slider-crank. sigma = sign of r3: r3 = sigma sqrt(|A - O4|^2 - r4^2)
    (for r4 = 0, sigma = -1 is the same pose with link 3 turned by pi).
    Returns r3, th3, th4, w3, a3, r3_v, r3_a."""
    A = r2 * _e(th2)
    D = A - r1 * _e(th1)
    r3 = sigma * _sqrt_or_nan(np.abs(D) ** 2 - r4**2)
    th3 = _wrap(np.angle(D) - np.angle(r3 - 1j * r4))
    e3 = _e(th3)
    m = (r3 - 1j * r4) * e3                       # vector O4 -> A carried by link 3
    w3, r3_v = _solve2(1j * m, e3, 1j * w2 * A)
    # Coriolis term 2 i r3' w3 e^{i th3}.
    a3, r3_a = _solve2(1j * m, e3, (1j * a2 - w2**2) * A - 2j * r3_v * w3 * e3 + w3**2 * m)
    return dict(r3=r3, th3=th3, th4=th3 - np.pi / 2, w3=w3, a3=a3, r3_v=r3_v, r3_a=r3_a)


def inverted_slider_crank_link3_driven(r1, r2, r4, th3, w3=1.0, a3=0.0, th1=0.0, sigma=1):
    """Link-3-driven inverted slider-crank. sigma = +1: the root with larger r3 (the line of
    link 3 cuts the crank circle twice). Returns th2, r3, w2, a2, r3_v, r3_a."""
    e3 = _e(th3)
    P = r1 * _e(th1) - 1j * r4 * e3               # A = P + r3 e^{i th3} with |A| = r2
    b = (P * np.conj(e3)).real
    r3 = -b + sigma * _sqrt_or_nan(b**2 - np.abs(P) ** 2 + r2**2)
    A = P + r3 * e3
    m = (r3 - 1j * r4) * e3
    w2, r3_v = _solve2(1j * A, -e3, 1j * w3 * m)
    a2, r3_a = _solve2(1j * A, -e3, w2**2 * A + 2j * r3_v * w3 * e3 + (1j * a3 - w3**2) * m)
    return dict(th2=np.angle(A), r3=r3, w2=w2, a2=a2, r3_v=r3_v, r3_a=r3_a)


# ----------------------------------------------------------------------------- geared five-bar

def _bisect(f, a, b, xtol=1e-15):
    fa = f(a)
    while b - a > xtol:
        m = 0.5 * (a + b)
        if m <= a or m >= b:                      # no double between a and b
            break
        fm = f(m)
        if fm == 0:
            return m
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
    return 0.5 * (a + b)


def geared_five_bar(r1, R2, R4, r5, th2, w2=1.0, a2=0.0, max_step=np.radians(2.0)):
    """Geared five-bar of seed 000 (f5link). O2 = 0, O5 = (r1, 0); arm 3 (length R2 + R4) from O2
    to the gear-4 centre; link 4 (length R4) on gear 4 to C; link 5 from O5 to C:
    r3 e^{i th3} + r4 e^{i th4} = r1 + r5 e^{i th5}. External mesh on carrier 3:
    R2 (th2 - th3) + R4 (th4 - th3) = const, fixed at th2 = 0 with th3 = th4 = th30 (links 3, 4
    collinear, th50 from the cosine rule, upper assembly).
    The position is followed from th2 = 0 by continuation in steps <= max_step, solving
    f(th4) = |C - O5|^2 - r5^2 = 0 by bisection to 1e-15 near the extrapolated previous root;
    NaN past a limit position. th3, th4 stay continuous (unwrapped); th5 is in (-pi, pi];
    w2, a2 broadcast to the shape of th2. Returns th3, th4, th5, w3, w4, w5, a3, a4, a5, th30, th40, th50."""
    r3, r4, g = R2 + R4, R4, R4 / R2
    th50 = float(_acos_or_nan(((r3 + r4) ** 2 - r1**2 - r5**2) / (2 * r1 * r5)))
    th30 = float(np.angle(r1 + r5 * np.exp(1j * th50)))

    def th3_of(t2, t4):  # rolling row: (1 + g)(th3 - th30) = th2 + g (th4 - th30)
        return th30 + (t2 + g * (t4 - th30)) / (1 + g)

    def resid(t2, t4):
        C = r3 * np.exp(1j * th3_of(t2, t4)) + r4 * np.exp(1j * t4)
        return abs(C - r1) ** 2 - r5**2

    th2 = np.asarray(th2, dtype=float)
    flat = th2.ravel()
    th4 = np.full(flat.shape, np.nan)
    for targets in (np.flatnonzero(flat >= 0)[np.argsort(flat[flat >= 0])],
                    np.flatnonzero(flat < 0)[np.argsort(-flat[flat < 0])]):
        t, x, slope, lost = 0.0, th30, 0.0, False
        for k in targets:
            while not lost and t != flat[k]:
                gap = flat[k] - t                     # land exactly on the target
                t_new = flat[k] if abs(gap) <= max_step else t + np.copysign(max_step, gap)
                guess = x + slope * (t_new - t)
                delta, root = 1e-3, None
                while root is None and delta < 0.5:   # smallest bracket with a sign change
                    lo, hi = guess - delta, guess + delta
                    if resid(t_new, lo) * resid(t_new, hi) <= 0:
                        root = _bisect(lambda y: resid(t_new, y), lo, hi)
                    delta *= 2
                if root is None:
                    lost = True
                    break
                slope = (root - x) / (t_new - t)
                t, x = t_new, root
            if lost:
                break
            th4[k] = x
    th4 = th4.reshape(th2.shape)
    th3 = th3_of(th2, th4)
    C = r3 * _e(th3) + r4 * _e(th4)
    th5 = np.angle(C - r1)

    # Velocity and acceleration: two loop rows and the rolling row, one 3x3 solve per point.
    s3, c3, s4, c4, s5, c5 = (f(t) for t in (th3, th4, th5) for f in (np.sin, np.cos))
    zero = np.zeros_like(s3)
    M = np.stack([np.stack([-r3 * s3, -r4 * s4, r5 * s5], -1),
                  np.stack([r3 * c3, r4 * c4, -r5 * c5], -1),
                  np.stack([np.full_like(s3, 1 + g), np.full_like(s3, -g), zero], -1)], -2)
    w2 = np.broadcast_to(w2, s3.shape)
    a2 = np.broadcast_to(a2, s3.shape)
    w = np.linalg.solve(M, np.stack([zero, zero, w2], -1)[..., None])[..., 0]
    w3, w4, w5 = np.moveaxis(w, -1, 0)
    cen = w3**2 * r3 * _e(th3) + w4**2 * r4 * _e(th4) - w5**2 * r5 * _e(th5)
    acc = np.linalg.solve(M, np.stack([cen.real, cen.imag, a2], -1)[..., None])[..., 0]
    a3, a4, a5 = np.moveaxis(acc, -1, 0)
    return dict(th3=th3, th4=th4, th5=th5, w3=w3, w4=w4, w5=w5, a3=a3, a4=a4, a5=a5,
                th30=th30, th40=th30, th50=th50)


# ----------------------------------------------------------------------------- open chain

def open_chain(lengths, abs_angles, abs_rates, abs_accels=0.0):
    """Serial chain of vectors r_k e^{i th_k} (absolute angles; the chain runs along the last
    axis). Returns tip, tip_vel, tip_acc as (..., 2), and magnitudes and angles (..., 3) of
    [tip, tip_vel, tip_acc]."""
    z = np.asarray(lengths, dtype=float) * _e(abs_angles)
    w = np.asarray(abs_rates, dtype=float)
    a = np.asarray(abs_accels, dtype=float)
    tip = z.sum(-1)
    vel = (1j * w * z).sum(-1)
    acc = ((1j * a - w**2) * z).sum(-1)
    trio = np.stack([tip, vel, acc], -1)
    return dict(tip=_xy(tip), tip_vel=_xy(vel), tip_acc=_xy(acc),
                magnitudes=np.abs(trio), angles=np.angle(trio))
