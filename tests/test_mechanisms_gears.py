"""Rolling-contact builders against their closed forms (written here: pure rolling makes every
angle and travel linear in the input).

- rack and pinion: travel s = R (th - th0) along the rack;
- wheel on a line: centre (-R phi, R), rim point P = centre + R e^{i(phi - pi/2)} (a cycloid);
- wheel inside a circle of radius Rt: centre angle psi = -pi/2 - r phi / (Rt - r),
  P = centre + r e^{i(phi - pi/2)} (a hypocycloid);
- gear train: th_k = (-1)^(k-1) (R1 / Rk) th1;
- planetary set (Willis): Rs (th_s - th_c) = -(Rs + 2 Rp)(th_r - th_c) and
  Rp (th_p - th_c) = -Rs (th_s - th_c).
"""

import numpy as np
import pytest
from hypothesis import given, strategies as st

import planar
from planar.analysis import motion_range
from planar.results import POSED
from planar.mechanisms import gear_train, planetary_gear_train, rack_and_pinion, rolling_wheel
from tests.test_mechanisms_four_bar import FAST, SWEEPS, assert_close, rate

radius = st.floats(0.2, 5.0)
angle = st.floats(-np.pi, np.pi)


def motion(t, w, a):
    """Input values over a sweep: a turn and a half from ``t`` (rates w, a)."""
    return t + np.linspace(0, 3 * np.pi, 25), w, a


def xy(z):
    return np.stack([z.real, z.imag], -1)


@SWEEPS
@given(R=radius, th=angle, start=angle, driver=st.sampled_from(["pinion", "rack"]), w=rate, a=rate)
def test_rack_and_pinion(R, th, start, driver, w, a):
    m = rack_and_pinion(R, rack_angle=th, driver=driver, start=start)
    values = start + np.linspace(0, 3 * np.pi * (R if driver == "rack" else 1), 25)
    res = m.sweep(values, velocity=w, acceleration=a, **FAST)
    assert res.ok.all()
    if driver == "pinion":
        s, sd, sdd = R * (values - start), R * w, R * a
    else:
        s, sd, sdd = values, w, a
        assert_close(res.angle("pinion"), (values - start) / R, 1.0, 1e-9, "pinion angle")
    assert_close(res.coordinate("slide"), s, R, 1e-9, "travel")
    assert_close(res.coordinate("slide", 1), sd, abs(sd) + R * abs(w), 1e-8, "rack speed")
    assert_close(res.coordinate("slide", 2), sdd, abs(sdd) + R * abs(a), 1e-8, "rack acceleration")
    u = np.exp(1j * th)
    P = R * np.exp(1j * (th - np.pi / 2)) + s * u
    assert_close(res.position("P"), xy(P), R + np.abs(s).max(), 1e-9, "P")


@SWEEPS
@given(r=radius, ratio=st.floats(1.2, 6.0), inside=st.booleans(), start=angle, w=rate, a=rate,
       by_centre=st.booleans())
def test_rolling_wheel(r, ratio, inside, start, w, a, by_centre):
    Rt = ratio * r if inside else None
    driver = "centre" if by_centre and not inside else "wheel"
    m = rolling_wheel(r, track_radius=Rt, driver=driver, start=start)
    values, _, _ = motion(start, w, a)
    if driver == "centre":
        values = start + r * np.linspace(0, 3 * np.pi, 25)  # centre x; the wheel turns by -x / r
    res = m.sweep(values, velocity=w, acceleration=a, **FAST)
    assert res.ok.all()
    if driver == "centre":
        phi, phid, phidd = -values / r, -w / r, -a / r
    else:
        phi, phid, phidd = values, w, a
    rim = r * np.exp(1j * (phi - np.pi / 2))
    rim_d, rim_dd = 1j * phid * rim, (1j * phidd - phid**2) * rim
    if Rt is None:
        c, cd, cdd = -r * phi + 1j * r, -r * phid + 0j, -r * phidd + 0j
    else:
        k = r / (Rt - r)
        psi, psid, psidd = -np.pi / 2 - k * phi, -k * phid, -k * phidd
        c = (Rt - r) * np.exp(1j * psi)
        cd, cdd = 1j * psid * c, (1j * psidd - psid**2) * c
    L = r + (Rt or 0) + np.abs(c).max()
    V = abs(phid) * L
    assert_close(res.angle("wheel"), phi, 1.0, 1e-9, "wheel angle")
    assert_close(res.position("centre"), xy(c), L, 1e-9, "centre")
    assert_close(res.position("P"), xy(c + rim), L, 1e-9, "P")
    assert_close(res.velocity("centre"), xy(cd + 0 * c), V, 1e-8, "centre velocity")
    assert_close(res.velocity("P"), xy(cd + rim_d), V, 1e-8, "P velocity")
    assert_close(res.acceleration("P"), xy(cdd + rim_dd), abs(phidd) * L + phid**2 * L, 1e-8, "P acceleration")


@SWEEPS
@given(radii=st.lists(radius, min_size=2, max_size=5), start=angle, w=rate, a=rate)
def test_gear_train(radii, start, w, a):
    values, _, _ = motion(start, w, a)
    res = gear_train(radii, start=start).sweep(values, velocity=w, acceleration=a, **FAST)
    assert res.ok.all()
    for k, Rk in enumerate(radii, 1):
        ratio = (-1) ** (k - 1) * radii[0] / Rk
        scale = max(1.0, abs(ratio))
        assert_close(res.angle(f"gear{k}") - (start if k == 1 else 0.0), ratio * (values - start), scale * 10, 1e-9,
                     f"gear{k}")
        assert_close(res.omega(f"gear{k}"), ratio * w, scale * abs(w), 1e-8, f"w{k}")
        assert_close(res.alpha(f"gear{k}"), ratio * a, scale * abs(a), 1e-8, f"a{k}")


@SWEEPS
@given(Rs=radius, Rp=radius, planets=st.integers(1, 5), fixed=st.sampled_from(["sun", "carrier", "ring"]),
       pick=st.booleans(), start=angle, w=rate)
def test_planetary_gear_train(Rs, Rp, planets, fixed, pick, start, w):
    driver = [b for b in ("sun", "carrier", "ring") if b != fixed][int(pick)]
    m = planetary_gear_train(Rs, Rp, planets=planets, fixed=fixed, driver=driver, start=start)
    model = m.compile()
    assert model.dof == 1 and len(model.redundant_joints) == planets - 1
    values, _, _ = motion(start, w, 0.0)
    res = m.sweep(values, velocity=w, **FAST)
    assert res.ok.all()
    Rr = Rs + 2 * Rp
    th = {b: (res.angle(b) - (start if b == driver else 0.0) if b != fixed else 0.0) for b in ("sun", "carrier", "ring")}
    om = {b: (res.omega(b) if b != fixed else 0.0) for b in ("sun", "carrier", "ring")}
    scale = 1 + Rr / min(Rs, Rp)
    assert_close(Rs * (th["sun"] - th["carrier"]) + Rr * (th["ring"] - th["carrier"]), 0.0, scale * Rr * 10, 1e-9,
                 "Willis")
    assert_close(Rs * (om["sun"] - om["carrier"]) + Rr * (om["ring"] - om["carrier"]), 0.0, scale * Rr * abs(w),
                 1e-8, "Willis rates")
    for k in range(1, planets + 1):
        assert_close(Rp * (res.omega(f"planet{k}") - om["carrier"]) + Rs * (om["sun"] - om["carrier"]), 0.0,
                     scale * Rr * abs(w), 1e-8, f"planet{k}")


@pytest.mark.parametrize("build, kw, match", [
    (rolling_wheel, dict(radius=2, track_radius=1), "track_radius"),
    (rolling_wheel, dict(track_radius=3, driver="centre"), "driver='wheel'"),
    (gear_train, dict(radii=[1.0]), "radii"),
    (planetary_gear_train, dict(planets=0), "planets"),
    (planetary_gear_train, dict(fixed="sun", driver="sun"), "fixed member"),
    (rack_and_pinion, dict(driver="wheel"), "driver"),
])
def test_bad_arguments_are_refused_by_name(build, kw, match):
    with pytest.raises(planar.ModelError, match=match):
        build(**kw)


def test_redundant_rows_are_reported():
    assert rack_and_pinion().compile().redundant_joints == ("mesh",)  # its tangency row: the joint added last
    assert planetary_gear_train(planets=1).compile().redundant_joints == ()


def test_a_rack_on_a_slider_drives_a_linkage():
    """Rack-and-pinion steering: the pinion (radius 1, at the origin, driven) moves a rack that
    slides on the ground, s = R th, and a tie rod from the rack's end E turns a knuckle (arm
    1.5, pivot K): its arm's tip T meets the circle of the tie rod about E. The mesh's tangency
    row repeats what the slider holds: redundant, and the mechanism still has one degree of
    freedom (at a pose near the sketch, the slider's angle and the mesh's phase are held as
    drawn). The pinion turns more than a turn between the ends of its range, where the rod and
    the arm lie in line, and its pose does not repeat a turn on."""
    R, arm, K, E0 = 1.0, 1.5, np.array([4.5, 0.5]), np.array([2.0, -1.0])
    tip0 = K + arm * np.array([np.cos(2.5), np.sin(2.5)])
    m = planar.Mechanism("steering")
    for b in ("pinion", "rack", "rod", "knuckle"):
        m.add_body(b)
    m.add_revolute("O", m.ground, "pinion", at=(0, 0))
    m.add_prismatic("slide", m.ground, "rack", at=(0, -R), direction=(1, 0))
    m.add_rack_pinion("mesh", "pinion", "rack", R, centre=(0, 0), through=(0, -R), direction=(1, 0))
    m.add_revolute("E", "rack", "rod", at=E0)
    m.add_revolute("T", "rod", "knuckle", at=tip0)
    m.add_revolute("K", "knuckle", m.ground, at=K)
    m.drive("O")
    model = m.compile()
    assert model.dof == 1 and model.redundant_joints == ("mesh",)
    th = np.linspace(-0.3, 0.3, 13)
    res = model.sweep(th)
    assert res.ok.all()
    E = E0 + np.outer(R * th, [1.0, 0.0])
    assert_close(res.position("E"), E, np.abs(E).max(), 1e-12, "rack travel")
    rod = np.hypot(*(tip0 - E0))
    # the knuckle's tip: on the arm's circle about K and the rod's about E, on the sketch's side
    d = np.linalg.norm(E - K, axis=1)
    along = (arm**2 - rod**2 + d**2) / (2 * d)
    across = np.sqrt(arm**2 - along**2)
    ex = (E - K) / d[:, None]
    side = np.sign((E0 - K)[0] * (tip0 - K)[1] - (E0 - K)[1] * (tip0 - K)[0])
    tip = K + along[:, None] * ex + side * across[:, None] * np.stack([-ex[:, 1], ex[:, 0]], 1)
    assert_close(res.position("T"), tip, 10.0, 1e-10, "knuckle tip")
    dx, dy = K - E0
    ends = (dx + np.array([-1.0, 1.0]) * np.sqrt((arm + rod) ** 2 - dy**2)) / R
    np.testing.assert_allclose(motion_range(model), [ends], atol=1e-10)


def geared_inverted_slider():
    """A crank about O = (0, 0.5) drives a block that slides along it and is pinned to a rocker
    about the origin: the block sits at B = P + t d, P = O + R(u)(-O), d = (cos u, sin u), and
    |B| = 1 gives t = (-sin u + s sqrt(2) cos(u/2) sqrt(3 - cos u)) / 2 on the smooth branch s
    (+1 at the sketch): its two closures touch at u = pi, a change point every turn. The crank
    also meshes (radii sqrt(5)/4 both) with a gear on an arm about O, whose pin a link of
    length 2 ties to the ground at G = (0, 2): that loop's ends are limits, and its pose
    comes back a turn on only with the gear turned one back."""
    m = planar.Mechanism("geared inverted slider")
    for b in ("crank", "rocker", "block", "arm", "gear", "link"):
        m.add_body(b)
    m.add_revolute("O", m.ground, "crank", at=(0, 0.5))
    m.add_revolute("A", m.ground, "rocker", at=(0, 0))
    m.add_revolute("B", "rocker", "block", at=(1, 0))
    m.add_prismatic("S", "crank", "block", at=(1, 0), direction=(1, 0))
    m.add_revolute("ra", m.ground, "arm", at=(0, 0.5))
    m.add_revolute("rb", "arm", "gear", at=(1, 0))
    r = np.sqrt(5) / 4
    m.add_gear("mesh", "crank", "gear", r, r, carrier="arm")
    m.add_revolute("rc", "gear", "link", at=(0, 0))
    m.add_revolute("rd", "link", m.ground, at=(0, 2))
    m.drive("O")
    return m.compile()


def block_smooth(u, s):
    """The block's position on the smooth branch s (:func:`geared_inverted_slider`)."""
    P = np.stack((0.5 * np.sin(u), 0.5 - 0.5 * np.cos(u)), -1)
    t = (-np.sin(u) + s * np.sqrt(2) * np.cos(u / 2) * np.sqrt(3 - np.cos(u))) / 2
    return P + t[:, None] * np.stack((np.cos(u), np.sin(u)), -1)


def test_a_stretch_walked_back_through_a_change_point_on_a_value_keeps_the_smooth_branch():
    """Over a turn the crank meets the gear loop's limit near 0.73 and jumps to another stretch,
    walked back from further on through the change point at pi, a value of the sweep: the walk
    from that value on must keep the smooth branch, one s on the whole stretch."""
    model = geared_inverted_slider()
    u = np.linspace(0, 2 * np.pi, 721)
    res = model.sweep(u)
    assert POSED[res.status].all()
    jump = np.flatnonzero(res.status == planar.Status.JUMPED)
    assert jump.size == 1 and 0.7 < u[jump[0]] < 0.8
    B = res.position("B")
    for part in (slice(0, jump[0]), slice(jump[0], None)):
        err = [np.abs(B[part] - block_smooth(u[part], s)).max() for s in (1, -1)]
        assert min(err) <= 1e-12, err


def test_motion_range_of_a_geared_stretch_longer_than_a_turn():
    """The sketch's stretch runs from the gear loop's limit below, over a turn down, to the one
    near 0.73: the range the sweeps from the sketch meet, each end a double root in the arm's
    angle of the link's closure |Q - G|^2 = 4 (the gear turns 2 a - u with the arm's a)."""
    model = geared_inverted_slider()
    ((lo, hi),) = motion_range(model)
    span = hi - lo
    assert 2 * np.pi < span < 4 * np.pi
    hi = hi - 2 * np.pi * np.round(hi / (2 * np.pi))  # (the end near the sketch's input)
    lo = hi - span
    for end in (lo, hi):
        u = np.linspace(0, end + np.sign(end) * 0.05, 201)
        res = model.sweep(u)
        met = [float(np.ravel(e.input)[0]) for e in res.events if e.kind == "limit"]
        assert any(abs(v - end) <= 1e-9 for v in met), (end, met)
        assert POSED[res.status[np.abs(u) < abs(end)]].all()
        at = model.sweep([0, end])
        assert at.status[1] == planar.Status.LIMIT
        a = float(np.diff(at.angle("arm"))[0])  # (from the sketch's)
        C0, Q0, O, G = np.array([1, 0]), np.zeros(2), np.array([0, 0.5]), np.array([0, 2])

        def f(a):
            rot = lambda v, th: np.array([np.cos(th) * v[0] - np.sin(th) * v[1], np.sin(th) * v[0] + np.cos(th) * v[1]])  # noqa: E731
            Q = O + rot(C0 - O, a) + rot(Q0 - C0, 2 * a - end)
            return np.sum((Q - G) ** 2) - 4

        h = 1e-5
        assert abs(f(a)) <= 1e-10 and abs(f(a + h) - f(a - h)) / (2 * h) <= 1e-6
