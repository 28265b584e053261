"""The six-bars against closed forms over full sweeps, both assembly modes of both loops: the
four-bar oracle of tests/oracles.py for the first loop, and below the closed form of the dyad
that closes the second (two links between two moving end points)."""

import numpy as np
from hypothesis import assume, given, strategies as st

from planar.mechanisms import stephenson_six_bar, two_loop_six_bar, watt_six_bar
from tests.oracles import four_bar as fb_oracle
from tests.test_mechanisms_four_bar import FAST, SWEEPS, assert_angles, assert_close, compare_four_bar, crank_range, rate


def cplx(xy):
    return xy[..., 0] + 1j * xy[..., 1]


def dyad(P, Pv, Pa, Q, Qv, Qa, r_p, r_q, sigma):
    """Closed form of the dyad P-M-Q: M = P + r_p e^{i t_p} = Q + r_q e^{i t_q}, M left of the
    directed line P -> Q for sigma = +1 (right for -1). P, Q and their rates are complex.
    Returns t_p, t_q, their rates w_p, w_q and accelerations a_p, a_q, and M."""
    d = Q - P
    L = np.abs(d)
    alpha = np.arccos(np.clip((r_p**2 + L**2 - r_q**2) / (2 * r_p * L), -1, 1))
    t_p = np.angle(d) + sigma * alpha
    M = P + r_p * np.exp(1j * t_p)
    t_q = np.angle(M - Q)
    ep, eq = r_p * np.exp(1j * t_p), r_q * np.exp(1j * t_q)
    cross = lambda a, b: (np.conj(a) * b).imag  # noqa: E731

    def solve(rhs):  # i w_p ep - i w_q eq = rhs, two real rows
        a, b = 1j * ep, -1j * eq
        return cross(rhs, b) / cross(a, b), cross(a, rhs) / cross(a, b)

    w_p, w_q = solve(Qv - Pv)
    a_p, a_q = solve(Qa - Pa + w_p**2 * ep - w_q**2 * eq)
    return dict(t_p=t_p, t_q=t_q, w_p=w_p, w_q=w_q, a_p=a_p, a_q=a_q, M=np.stack([M.real, M.imag], -1))


def body_point(O, th, w, a, p, q):
    """A point (p along, q left) of a link at angle th through O (fixed), with its rates."""
    z = (p + 1j * q) * np.exp(1j * th)
    return O + z, 1j * w * z, (1j * a - w**2) * z


def second_loop(family, w2, a2, o, r, dims):
    """The dyad of each six-bar from the four-bar oracle ``o``: its end points P, Q (each
    (position, velocity, acceleration), complex), its links' names and its middle joint."""
    A = cplx(o["A"])
    O4 = r[0] * np.exp(1j * dims["frame_angle"])
    zero = np.zeros_like(A)
    if family == "two_loop":
        D = body_point(O4, o["th4"] + dims["phase"], o["w4"], o["a4"], dims["lengths"][5], 0.0)
        O6 = O4 + dims["lengths"][4] * np.exp(1j * dims["frame_angle_2"])
        return D, (O6 + zero, zero, zero), ("coupler2", "rocker2"), "E"
    # C on the coupler, which moves with A: add A's velocity and acceleration
    C = body_point(A, o["th3"], o["w3"], o["a3"], *dims["coupler_point"])
    C = (C[0], C[1] + 1j * w2 * A, C[2] + (1j * a2 - w2**2) * A)
    if family == "watt":
        return C, body_point(O4, o["th4"], o["w4"], o["a4"], *dims["rocker_point"]), ("link5", "link6"), "E"
    return C, (complex(*dims["pivot_6"]) + zero, zero, zero), ("link5", "link6"), "D"


length = st.floats(0.5, 5.0)
coord = st.floats(-3.0, 3.0)
BUILD = {"watt": watt_six_bar, "stephenson": stephenson_six_bar, "two_loop": two_loop_six_bar}


@SWEEPS
@given(family=st.sampled_from(sorted(BUILD)), r=st.tuples(length, length, length, length),
       frame=st.tuples(st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi)),
       modes=st.tuples(st.booleans(), st.booleans()), points=st.tuples(coord, coord, coord, coord),
       extra=st.tuples(length, length), band=st.tuples(st.floats(0, 1), st.floats(0.05, 0.95)),
       w2=rate, a2=rate, at=st.floats(0, 1))
def test_six_bars_match_the_four_bar_and_dyad_closed_forms(family, r, frame, modes, points, extra, band, w2, a2, at):
    sigma, sigma2 = (-1 if modes[0] else 1), (-1 if modes[1] else 1)
    dims = {"frame_angle": frame[0], "crossed": modes[0], "crossed_2": modes[1]}
    if family == "watt":
        dims.update(coupler_point=points[:2], rocker_point=points[2:])
    elif family == "stephenson":
        dims.update(coupler_point=points[:2], pivot_6=(2 * points[2], 2 * points[3]))
    else:
        dims.update(lengths=r + (extra[0], extra[1], 1.0, 1.0), frame_angle_2=frame[1], phase=frame[2])
    values = crank_range(r, dims["frame_angle"], sigma)
    assume(values is not None)
    # the dyad's two links, chosen so that the angle between them at their middle joint stays
    # within 20 .. 160 deg over the whole sweep: clear of its limit positions, where they line up
    o = fb_oracle(*r, values, w2, a2, th1=dims["frame_angle"], sigma=sigma)
    P, Q = second_loop(family, w2, a2, o, r, dims)[:2]
    d = np.abs(Q[0] - P[0])
    rho = 0.5 + 1.5 * band[0]  # r_q / r_p
    c = 2 * rho * np.cos(np.radians(20))
    lo, hi = d.max() ** 2 / (1 + rho**2 + c), d.min() ** 2 / (1 + rho**2 - c)  # bounds on r_p^2
    assume(d.min() > 0.05 and lo < hi)
    rp = np.sqrt(lo + band[1] * (hi - lo))
    rq = rho * rp
    if family == "two_loop":
        dims["lengths"] = dims["lengths"][:6] + (rp, rq)
    else:
        dims.update(link_5=rp, link_6=rq)
    start = values[int(at * (len(values) - 1))]
    kw = {k: v for k, v in dims.items() if k != "lengths"}
    m = BUILD[family](*((dims["lengths"],) if family == "two_loop" else r), **kw, start=start)
    res = m.sweep(values, velocity=w2, acceleration=a2, **FAST)
    assert res.ok.all()
    compare_four_bar(res, r, dims["frame_angle"], sigma, w2, a2)
    P, Q, (link_p, link_q), middle = second_loop(family, w2, a2, o, r, dims)
    e = dyad(*P, *Q, rp, rq, sigma2)
    assert_angles(res.angle(link_p), e["t_p"], link_p)
    assert_angles(res.angle(link_q), e["t_q"], link_q)
    w = max(np.abs(e["w_p"]).max(), np.abs(e["w_q"]).max(), np.abs(o["w3"]).max(), abs(w2))
    a = max(np.abs(e["a_p"]).max(), np.abs(e["a_q"]).max(), w**2)
    assert_close(res.omega(link_p), e["w_p"], w, 1e-8, "w_p")
    assert_close(res.omega(link_q), e["w_q"], w, 1e-8, "w_q")
    assert_close(res.alpha(link_p), e["a_p"], a, 1e-8, "a_p")
    assert_close(res.alpha(link_q), e["a_q"], a, 1e-8, "a_q")
    assert_close(res.position(middle), e["M"], max(r) + rp + rq, 1e-9, middle)


def test_defaults_turn_fully_in_every_mode():
    th = np.linspace(0, 2 * np.pi, 37)
    for build in BUILD.values():
        for crossed_2 in (False, True):
            m = build(crossed_2=crossed_2)
            assert m.compile().dof == 1 and m.compile().grubler == 1
            assert m.sweep(th, **FAST).ok.all(), build.__name__
