"""Kinetostatics: closed forms, virtual power on random mechanisms, and every joint type's
reaction against finite differences of its constraint rows."""

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import planar
from planar.joints import JOINT_TYPES
from planar.mechanisms import CATALOGUE, planetary_gear_train, rack_and_pinion, slider_crank
from planar.mechanisms import four_bar as four_bar_mechanism
from tests import oracles
from tests.strategies import build, linkages
from tests.test_joints import frames, group

G = 9.81


# ---- closed forms ----------------------------------------------------------------------------


def slide_x(r, l, e, th):
    """x of the slider pin of a slider-crank (slide y = e) and its first two th-derivatives."""
    s, s1, s2 = r * np.sin(th) - e, r * np.cos(th), -r * np.sin(th)
    c = np.sqrt(l**2 - s**2)
    x1 = -r * np.sin(th) - s * s1 / c
    x2 = -r * np.cos(th) - (s1**2 + s * s2) / c - s**2 * s1**2 / c**3
    return r * np.cos(th) + c, x1, x2


def test_slider_crank_input_torque_under_a_piston_force():
    r, l, e, P = 2.0, 5.0, 1.0, 300.0
    m = slider_crank(r, l, offset=e)
    m.add_load("slider", force=(-P, 0.0), at=m.sketch().points["B"][1])
    th = np.radians(np.arange(5.0, 360.0, 10.0))
    res = m.sweep(th, velocity=3.0)
    f = res.forces()
    x, x1, _ = slide_x(r, l, e, th)
    np.testing.assert_allclose(f.driver_effort("crank"), P * x1, rtol=1e-10, atol=1e-9 * P)
    # the massless coupler is a two-force member: the force on the slider along A -> B, x part P
    FB, AB = f.reaction("B"), res.position("B") - res.position("A")
    np.testing.assert_allclose(FB[:, 0], P, rtol=1e-10)
    np.testing.assert_allclose(FB[:, 0] * AB[:, 1] - FB[:, 1] * AB[:, 0], 0.0, atol=1e-9 * P * l)
    # the slide's normal force (on the slider, along +y) balances the coupler's y part, no moment
    np.testing.assert_allclose(f.reaction("slide", "normal"), -FB[:, 1], rtol=1e-10, atol=1e-9 * P)
    np.testing.assert_allclose(f.reaction("slide", "moment"), 0.0, atol=1e-9 * P * l)
    np.testing.assert_allclose(f.reaction("slide"), FB * [0, -1], atol=1e-9 * P)
    # ideal mechanical advantage: the piston force per unit crank torque
    np.testing.assert_allclose(f.mechanical_advantage("slide"), 1 / x1, rtol=1e-10)
    np.testing.assert_allclose(f.mechanical_advantage("slide") * f.driver_effort("crank"), P, rtol=1e-10)


def test_slider_crank_input_torque_with_link_inertia():
    """A heavy piston and a crank balanced about its pivot, driven with angular acceleration:
    T = I_O th'' + (P + m_s x'') x', x'' = x_thth th'^2 + x_th th''."""
    r, l, e, P, ms, IO = 2.0, 5.0, 1.0, 300.0, 4.0, 0.7
    m = slider_crank(r, l, offset=e)
    B = m.sketch().points["B"][1]
    m.set_mass("slider", ms, B, 0.3)
    m.set_mass("crank", 1.5, (0.0, 0.0), IO)
    m.add_load("slider", force=(-P, 0.0), at=B)
    th = np.radians(np.arange(5.0, 360.0, 10.0))
    w, a = 3.0, 2.0
    f = m.sweep(th, velocity=w, acceleration=a).forces()
    _, x1, x2 = slide_x(r, l, e, th)
    want = IO * a + (P + ms * (x2 * w**2 + x1 * a)) * x1
    np.testing.assert_allclose(f.driver_effort("crank"), want, rtol=1e-10, atol=1e-9 * P)
    np.testing.assert_allclose(f.inertia_force("slider")[:, 0], -ms * (x2 * w**2 + x1 * a), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f.inertia_torque("crank"), -IO * a)


def test_four_bar_at_rest_under_gravity_balances_its_weight():
    """Uniform bars at rest: the holding torque is minus the weights' virtual work per unit
    crank rotation (the oracle's rates at unit crank speed), and the pivots carry the weight."""
    r1, r2, r3, r4 = 4.0, 1.5, 4.0, 3.0
    m = four_bar_mechanism(r1, r2, r3, r4)
    pts = m.sketch().points
    O2, A, B, O4 = (pts[k][1] for k in ("O2", "A", "B", "O4"))
    masses = {"crank": 1.0, "coupler": 2.5, "rocker": 1.7}
    for body, (p, q) in (("crank", (O2, A)), ("coupler", (A, B)), ("rocker", (O4, B))):
        m.set_mass(body, **planar.bar(masses[body], p, q))
    m.gravity = (0.0, -G)
    th = np.radians(np.arange(0.0, 360.0, 15.0))
    f = m.sweep(th, velocity=0.0).forces()
    o = oracles.four_bar(r1, r2, r3, r4, th)
    th3, th4, w3, w4 = (o[k] for k in ("th3", "th4", "w3", "w4"))
    vA = 1j * r2 * np.exp(1j * th)
    v = {"crank": vA / 2, "coupler": vA + 1j * r3 * np.exp(1j * th3) * w3 / 2,
         "rocker": 1j * r4 * np.exp(1j * th4) * w4 / 2}
    want = sum(masses[b] * G * v[b].imag for b in masses)
    np.testing.assert_allclose(f.driver_effort("crank"), want, rtol=1e-10, atol=1e-10)
    support = f.reaction("O2") - f.reaction("O4")  # the ground's pushes on the crank and rocker
    np.testing.assert_allclose(support, np.broadcast_to([0.0, G * sum(masses.values())], support.shape), atol=1e-9)
    np.testing.assert_allclose(f.shaking_force(), 0.0, atol=0)


@pytest.mark.parametrize("carrier", [True, False], ids=["on a carrier", "free centres"])
def test_gear_pair_contact_force(carrier):
    """A torque tau on the output gear: the input holds tau R1 / R2; the tooth force is
    tau / R2 tangentially, along the pressure line tau / (R2 cos alpha), and each pin carries it."""
    R1, R2, tau, alpha = 1.0, 2.5, 10.0, np.radians(20.0)
    m = planar.Mechanism("pair")
    g1, g2 = m.add_body("g1"), m.add_body("g2")
    m.add_revolute("P1", m.ground, g1, at=(0, 0))
    m.add_revolute("P2", m.ground, g2, at=(R1 + R2, 0))
    if carrier:
        m.add_gear("mesh", g1, g2, R1, R2, carrier=m.ground, pressure_angle=alpha)
    else:
        m.add_gear("mesh", g1, g2, R1, R2, centre_a=(0, 0), centre_b=(R1 + R2, 0), pressure_angle=alpha)
    m.add_load(g2, torque=tau)
    m.drive("P1")
    f = m.sweep(np.linspace(0, 3, 7), velocity=2.0).forces()
    np.testing.assert_allclose(f.driver_effort("P1"), tau * R1 / R2, rtol=1e-12)
    Ft = tau / R2
    np.testing.assert_allclose(np.abs(f.reaction("mesh", "tangential")), Ft, rtol=1e-12)
    np.testing.assert_allclose(f.reaction("mesh", "contact"), Ft / np.cos(alpha), rtol=1e-12)
    np.testing.assert_allclose(f.reaction("mesh", "radial"), Ft * np.tan(alpha), rtol=1e-12)
    # gear 2 (a torque only on it): the tooth force and its pin's force cancel; the tooth force
    # pushes it away from gear 1 (+x) and turns it against tau (up at the pitch point x = R1)
    F = f.reaction("mesh")
    np.testing.assert_allclose(F, np.broadcast_to([Ft * np.tan(alpha), Ft], F.shape), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(f.reaction("P2"), -F, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(f.reaction("P1"), F, rtol=1e-12, atol=1e-12)  # ground on g1 = -(g2 on g1)


def test_internal_gear_tooth_force_pushes_the_pinion_towards_the_ring_centre():
    """A pinion (R2) inside a driven ring (R1), both on fixed pivots, a torque tau on the pinion:
    the ring holds -tau R1 / R2 (they turn the same way); at the contact (x = R1) the tooth
    force on the pinion is -tau / R2 in y, and its radial part pushes it towards -x."""
    R1, R2, tau, alpha = 3.0, 1.0, 6.0, np.radians(20.0)
    m = planar.Mechanism("ring")
    ring, pinion = m.add_body("ring"), m.add_body("pinion")
    m.add_revolute("P1", m.ground, ring, at=(0, 0))
    m.add_revolute("P2", m.ground, pinion, at=(R1 - R2, 0))
    m.add_gear("mesh", ring, pinion, R1, R2, internal=True, carrier=m.ground, pressure_angle=alpha)
    m.add_load(pinion, torque=tau)
    m.drive("P1")
    f = m.sweep(np.linspace(0, 3, 7)).forces()
    Ft = tau / R2
    np.testing.assert_allclose(f.driver_effort("P1"), -tau * R1 / R2, rtol=1e-12)
    F = f.reaction("mesh")
    np.testing.assert_allclose(F, np.broadcast_to([-Ft * np.tan(alpha), -Ft], F.shape), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(f.reaction("P2"), -F, rtol=1e-12, atol=1e-12)


def test_rack_and_pinion_force():
    """The rack's guide and the teeth both hold the rack across its line (indeterminate
    there); along it the tooth force and the torque are unique."""
    R, P = 0.8, 50.0
    m = rack_and_pinion(R)
    m.add_load("rack", force=(-P, 0.0), at=m.sketch().points["P"][1])
    with pytest.warns(planar.IndeterminateWarning, match="'slide'"):
        f = m.sweep(np.linspace(0, 2, 5)).forces()
    np.testing.assert_allclose(f.driver_effort("pinion"), P * R, rtol=1e-12)
    np.testing.assert_allclose(np.abs(f.reaction("mesh", "tangential")), P, rtol=1e-12)
    np.testing.assert_allclose(f.reaction("mesh", "contact"), P / np.cos(np.radians(20)), rtol=1e-12)


def test_rolling_wheel_friction_and_normal_force():
    """A wheel (m, r, I) accelerated on a floor: T = (I + m r^2) alpha; the floor pushes up m g
    and by friction m a_x = -m r alpha (rolling right turns clockwise)."""
    r, mass, I, alpha = 0.5, 3.0, 0.2, 4.0
    m = CATALOGUE["rolling_wheel"](r)
    m.set_mass("wheel", mass, m.sketch().points["centre"][1], I)
    m.gravity = (0.0, -G)
    f = m.sweep(np.linspace(0, 4, 5), velocity=2.0, acceleration=alpha).forces()
    np.testing.assert_allclose(f.driver_effort("wheel"), (I + mass * r**2) * alpha, rtol=1e-12)
    np.testing.assert_allclose(f.reaction("roll", "normal"), mass * G, rtol=1e-12)
    np.testing.assert_allclose(f.reaction("roll", "tangential"), -mass * r * alpha, rtol=1e-12)
    np.testing.assert_allclose(f.reaction("roll"), np.broadcast_to([-mass * r * alpha, mass * G], (5, 2)), rtol=1e-12)


def test_loads_fixed_in_the_body_and_per_input_value():
    """A force fixed in the crank stays square to it (torque F r everywhere); a force given per
    input value follows the function."""
    m = planar.Mechanism()
    crank = m.add_body("crank", angle=0.7)  # its angle is 0.7 at the sketch: the arm turns by th - 0.7
    m.add_revolute("O", m.ground, crank, at=(0, 0))
    m.add_load(crank, force=(0.0, 5.0), at=(2.0, 0.0), fixed="body")
    m.add_load(crank, force=lambda u: np.stack((0 * u[:, 0], u[:, 0]), axis=-1), at=(1.0, 0.0))
    m.add_load(crank, torque=lambda u: 3.0 + 0 * u[:, 0])
    m.drive("O")
    th = np.linspace(0, 6, 13)
    f = m.sweep(th).forces()
    np.testing.assert_allclose(f.driver_effort("O"), -(10.0 + th * np.cos(th - 0.7) + 3.0), rtol=1e-12, atol=1e-12)


# ---- virtual power ---------------------------------------------------------------------------


def add_mass_points(m, rng, names):
    """Random masses, centres, inertias and loads on the bodies ``names`` of ``m``, each centre
    and load point also a named point (its velocity and acceleration come from the sweep)."""
    pts = np.array([p for _, p in m.sketch().points.values()])
    lo, hi = pts.min(axis=0) - 0.5, pts.max(axis=0) + 0.5
    loads = []
    for b in names:
        com = rng.uniform(lo, hi)
        m.set_mass(b, rng.uniform(0.1, 5.0), com, rng.uniform(0.0, 2.0))
        m.add_point(f"com:{b}", b, at=com)
        at, F, T = rng.uniform(lo, hi), rng.uniform(-10, 10, 2), rng.uniform(-5, 5)
        m.add_load(b, force=F, at=at, torque=T)
        m.add_point(f"load:{b}", b, at=at)
        loads.append((b, F, T))
    m.gravity = tuple(rng.uniform(-10, 10, 2))
    return loads


def virtual_power(res, loads):
    """(driver power, dT/dt + dV/dt - load power) at every value, and a scale of the terms."""
    f = res.forces()
    model = res.model
    drive = sum(f.driver_effort(d) * res.input_rates[:, k] for k, d in enumerate(model.input_names))
    g = model.gravity
    dT, dV, P, scale = 0.0, 0.0, 0.0, np.abs(drive)
    for b, F, T in loads:
        i = model.body_id(b)
        mb, Ib = model.mass[i], model.inertia[i]
        v, a = res.velocity(f"com:{b}"), res.acceleration(f"com:{b}")
        terms = [mb * np.sum(v * a, axis=1), Ib * res.omega(b) * res.alpha(b), -mb * v @ g,
                 res.velocity(f"load:{b}") @ F, T * res.omega(b)]
        dT, dV, P = dT + terms[0] + terms[1], dV + terms[2], P + terms[3] + terms[4]
        scale = scale + sum(np.abs(t) for t in terms)
    return drive, dT + dV - P, scale


def assert_virtual_power(res, loads):
    """The driver's power is what the kinetic and potential energy and the loads take, at every
    sound value (the reactions of redundant joints are split, the driver's effort is not); NaN
    at the others."""
    sound = np.isin(res.status, (planar.Status.SOLVED, planar.Status.NEAR_SINGULAR))
    assume(sound.any())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", planar.IndeterminateWarning)
        drive, rest, scale = virtual_power(res, loads)
    # near a singular position the rates carry errors of about eps over the singularity measure
    # (the events' estimate): a link 1e-6 long gives rates of 1e13 there
    tol = 1e-10 * scale[sound].max() + 100 * np.finfo(float).eps / res.singularity[sound] * scale[sound]
    assert np.all(np.abs(drive - rest)[sound] <= tol), np.max(np.abs(drive - rest)[sound] / tol)
    assert np.isnan(drive[~sound]).all()


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(desc=st.one_of(linkages(max_dyads=2), linkages(max_dyads=2, rolling=True)), seed=st.integers(0, 2**32 - 1))
def test_virtual_power_on_random_linkages(desc, seed):
    """Linkages of pins and sliders, some with a loop closed by a gear or a rack."""
    rng = np.random.default_rng(seed)
    try:
        m, _ = build(desc)
        m.compile()
    except planar.PlanarError:
        assume(False)
    names = [b for b in m.sketch().bodies if b != "ground"]
    loads = add_mass_points(m, rng, names)
    th = np.linspace(0.0, 0.6, 7)
    try:
        res = m.sweep(th, velocity=rng.uniform(-3, 3), acceleration=rng.uniform(-3, 3))
    except planar.AssemblyError:
        assume(False)  # a sketch on a singular position is refused, named
    assert_virtual_power(res, loads)


def slotted_crank():
    """The crank's pin A in a slot of a rocker pivoted at O4."""
    m = planar.Mechanism("slotted crank")
    crank, rocker = m.add_body("crank"), m.add_body("rocker")
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("O4", m.ground, rocker, at=(0, -3))
    m.add_slot("A", rocker, crank, at=(1, 0), direction=(1, 3), origin=(0, -3))
    m.drive("O2")
    return m


def free_gears():
    """Two gears on the ends of a swinging arm and a pin: a mesh between moving centres."""
    m = planar.Mechanism("free gears")
    arm, g1, g2 = m.add_body("arm"), m.add_body("g1"), m.add_body("g2")
    m.add_revolute("O", m.ground, arm, at=(0, 0))
    m.add_revolute("P1", arm, g1, at=(0, 0))
    m.add_revolute("P2", arm, g2, at=(3, 0))
    m.add_gear("mesh", g1, g2, 1.0, 2.0, centre_a=(0, 0), centre_b=(3, 0))
    m.drive(body="arm")
    m.drive("P1")
    return m


def point_driven():
    m = planar.Mechanism("point driven")
    arm = m.add_body("arm")
    m.add_revolute("O", m.ground, arm, at=(0, 0))
    m.add_point("tip", arm, at=(0.5, 2.0))
    m.drive(point="tip", axis="x")
    return m


MORE = {
    "rolling inside a ring": lambda: CATALOGUE["rolling_wheel"](track_radius=3.0),
    "rack driven": lambda: rack_and_pinion(driver="rack"),
    "slotted crank": slotted_crank,
    "free gears": free_gears,
    "point driven": point_driven,
}


@pytest.mark.parametrize("name", sorted(CATALOGUE) + sorted(MORE))
def test_virtual_power_on_every_joint_and_driver_type(name):
    """The catalogue and a few more: every joint and driver type (gears on carriers and between
    moving bodies, racks, rolling on a line and inside a ring, sliders, slots; redundant
    planets; two inputs)."""
    rng = np.random.default_rng(sum(map(ord, name)))
    m = (CATALOGUE.get(name) or MORE.get(name) or MORE_FORCES[name])()
    names = [b for b in m.sketch().bodies if b != "ground"]
    loads = add_mass_points(m, rng, names)
    model = m.compile()
    u0 = model.u0
    values = u0 + np.linspace(0.0, 0.3, 5)[:, None] * np.where(model.input_lengths, model.L, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", planar.IndeterminateWarning)
        res = model.sweep(values, velocity=rng.uniform(0.5, 2, len(u0)), acceleration=rng.uniform(-2, 2, len(u0)))
        drive, rest, scale = virtual_power(res, loads)
    assert res.ok.all()
    np.testing.assert_allclose(drive, rest, rtol=0, atol=1e-10 * scale.max())


def test_point_driver_effort_is_the_force_along_its_axis():
    m = planar.Mechanism()
    arm = m.add_body("arm")
    m.add_revolute("O", m.ground, arm, at=(0, 0))
    m.add_point("tip", arm, at=(0.0, 2.0))
    m.add_load(arm, force=(7.0, 0.0), at=(0.0, 2.0))
    m.drive(point="tip", axis="x")
    f = m.sweep([0.0, 0.5, -0.5]).forces()
    np.testing.assert_allclose(f.driver_effort("tip.x"), -7.0, rtol=1e-12)


# ---- indeterminate, unsound values, shaking ---------------------------------------------------


def test_redundant_planets_share_the_load_evenly_with_a_warning():
    m = planetary_gear_train(planets=3)
    m.add_load("carrier", torque=-6.0)
    with pytest.warns(planar.IndeterminateWarning, match="planet2_ring"):
        f = m.sweep([0.0, 0.5]).forces()
    assert {"planet1_ring", "planet2_ring", "planet3_ring"} <= set(f.indeterminate)
    t = [f.reaction(f"planet{k}_ring", "tangential") for k in (1, 2, 3)]
    np.testing.assert_allclose(t[1], t[0], rtol=1e-9)
    np.testing.assert_allclose(t[2], t[0], rtol=1e-9)
    one = planetary_gear_train(planets=1)
    one.add_load("carrier", torque=-6.0)
    np.testing.assert_allclose(f.driver_effort("sun"), one.sweep([0.0, 0.5]).forces().driver_effort("sun"), rtol=1e-12)


def _swept(name, seed=0, n=5, start=0.0, loads=None):
    """A mechanism of the catalogue or of MORE with random masses and loads (appended to
    ``loads``), swept over a few values from ``start`` (input units, or L) past its sketch with
    random rates; and its model."""
    rng = np.random.default_rng(seed + sum(map(ord, name)))
    m = (CATALOGUE.get(name) or MORE.get(name) or MORE_FORCES[name])()
    added = add_mass_points(m, rng, [b for b in m.sketch().bodies if b != "ground"])
    if loads is not None:
        loads += added
    model = m.compile()
    values = model.u0 + (start + np.linspace(0.0, 0.3, n))[:, None] * np.where(model.input_lengths, model.L, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", planar.IndeterminateWarning)
        return model.sweep(values, velocity=rng.uniform(-2, 2, values.shape[1]),
                           acceleration=rng.uniform(-2, 2, values.shape[1])), model


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(sorted(CATALOGUE) + sorted(MORE)), seed=st.integers(0, 2**32 - 1),
       start=st.floats(-1.0, 1.0))
def test_virtual_power_with_random_masses_loads_and_rates_on_every_joint_type(name, seed, start):
    """Virtual power as on the random linkages, over the mechanisms with gears, racks, rolling,
    slots and sliders: random masses, loads, gravity, input rates and stretch of the input."""
    loads = []
    res, _ = _swept(name, seed, start=start, loads=loads)
    assert_virtual_power(res, loads)


@pytest.mark.parametrize("name", sorted(CATALOGUE) + sorted(MORE))
def test_the_transposed_block_solve_against_the_dense_jacobian(name):
    """``Factors.solve_transpose`` (the multipliers' solve, on the kinematic plan's blocks in
    reverse order) solves J^T y = c, J the plan's Jacobian, at poses off the sketch (the
    blocks' row swaps differ from pose to pose)."""
    from planar.blocks import plan

    res, model = _swept(name)
    p = plan(model)
    rng = np.random.default_rng(3)
    q = res.q + 0.05 * rng.normal(size=res.q.shape) * model.col_scale
    lu = p.factor(p.evaluate(q, res.inputs)[2], dets=False)
    J = model.system.evaluate(q, res.inputs)[1][:, p.rows]
    c = rng.normal(size=q.shape)
    y = lu.solve_transpose(c)
    np.testing.assert_allclose(np.einsum("nrc,nr->nc", J, y), c, rtol=0, atol=1e-12 * np.abs(y).max())


def held_pin_pair():
    """A gear pair on the ground with gear 2 on two pins at its centre: the pins share the
    tooth force's radial part."""
    m = planar.Mechanism("held pin pair")
    g1, g2 = m.add_body("g1"), m.add_body("g2")
    m.add_revolute("P1", m.ground, g1, at=(0, 0))
    m.add_revolute("P2", m.ground, g2, at=(3.5, 0))
    m.add_revolute("P2b", m.ground, g2, at=(3.5, 0))
    m.add_gear("mesh", g1, g2, 1.0, 2.5, carrier=m.ground)
    m.drive("P1")
    return m


MORE_FORCES = {"held pin pair": held_pin_pair}


@pytest.mark.parametrize("name", ["gear_train", "planetary_gear_train", "free gears", "four_bar", "rack_and_pinion",
                                  "held pin pair"])
def test_multipliers_solve_the_force_rows_with_the_least_norm(name):
    """W^T lam = Q with W the force rows (gears on a carrier: the rows of the contact, which
    the kinematic factors do not hold) and Q with the tooth forces' radial parts; the loads'
    split is the minimum-norm one (moments per length L: orthogonal to every self-balancing
    set of multipliers), the radial parts' the minimum-norm one that leaves the tooth forces
    as they are (two pins on one gear share them equally)."""
    from planar import kinetostatics as K

    res, model = _swept(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", planar.IndeterminateWarning)
        f = res.forces()
    q, lam = res.q, np.asarray(f.multipliers)
    pieces, blocks = K._force_rows(model, q, res.inputs)
    W = np.zeros((len(res), model.system.m, model.n + 1))
    for (g, _, _), B in zip(pieces, blocks):
        W[:, g.rows.T[:, None, :], g.cols.T[None, :, :]] = np.moveaxis(B, -1, 0)
    W = W[..., : model.n]
    Q = K._applied(model, q, res.qd, res.qdd, res.inputs)[0]
    extra, held = np.zeros((model.n + 1, len(res))), np.zeros(model.system.m, bool)
    for g, P, F in pieces:
        C = g.kind.contact_load(P, F, lam.T[g.rows.T])
        if C is not None:
            np.add.at(extra, g.cols.T, C)
            held[g.rows.ravel()] = True
    radial = extra[: model.n].T
    np.testing.assert_allclose(np.einsum("nrc,nr->nc", W, lam), Q + radial, rtol=0, atol=1e-10 * np.abs(Q).max())
    w = np.where(K._length_rows(model), 1.0, 1.0 / model.L)
    carried = np.zeros_like(lam)
    for k in range(len(res)):
        # the radial parts: what the rows not held carry, least norm (lstsq over those rows)
        A = (W[k] / w[:, None]).T
        carried[k, ~held] = np.linalg.lstsq(A[:, ~held], radial[k], rcond=None)[0] / w[~held]
        _, sv, Vt = np.linalg.svd(A)
        null = Vt[int(np.sum(sv > 1e-9 * sv[0])):]  # self-balancing, in the scaled multipliers
        assert null.shape[0] == model.redundant_rows.size
        loads = w * (lam[k] - carried[k])
        np.testing.assert_allclose(null @ loads, 0.0, atol=1e-10 * np.abs(loads).max())
    if name == "held pin pair":
        np.testing.assert_allclose(f.reaction("P2"), f.reaction("P2b"), rtol=1e-10)


def test_draw_forces_puts_each_reaction_at_its_joint():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.quiver import Quiver

    from planar.draw import draw_forces, plot_forces

    res, _ = _swept("slider_crank")
    f = res.forces()
    ax = draw_forces(f, 2, ["A", "B"], scale=0.01)
    arrows = next(c for c in ax.collections if isinstance(c, Quiver))
    np.testing.assert_allclose(arrows.get_offsets(), [res.position("A")[2], res.position("B")[2]])
    np.testing.assert_allclose(np.c_[arrows.U, arrows.V], 0.01 * np.array([f.reaction("A")[2], f.reaction("B")[2]]))
    effort = plot_forces(f)[0].get_lines()[0].get_ydata()
    np.testing.assert_allclose(effort, f.driver_effort("crank"))
    matplotlib.pyplot.close("all")


def test_unsound_values_give_nan():
    m = four_bar_mechanism(4, 3, 3, 3)  # a triple rocker: out of range past +-117 deg
    m.set_mass("coupler", 1.0, (1.0, 1.0), 0.1)
    m.gravity = (0.0, -G)
    res = m.sweep(np.radians([0.0, 60.0, 150.0]))
    f = res.forces()
    assert res.status[2] == planar.Status.NOT_ASSEMBLABLE
    assert np.isfinite(f.driver_effort("crank")[:2]).all() and np.isnan(f.driver_effort("crank")[2])
    assert np.isnan(f.reaction("A")[2]).all() and np.isnan(f.shaking_force()[2]).all()


def test_shaking_force_and_moment_are_what_the_ground_feels():
    """No gravity, no loads: the ground's pins and the driver's stator take the inertia forces."""
    m = four_bar_mechanism(4, 1.5, 4, 3)
    rng = np.random.default_rng(5)
    for b in ("crank", "coupler", "rocker"):
        m.set_mass(b, rng.uniform(1, 3), rng.uniform(0, 3, 2), rng.uniform(0.1, 1))
    res = m.sweep(np.linspace(0, 6, 25), velocity=10.0, acceleration=3.0)
    f = res.forces()
    on_ground = -f.reaction("O2") + f.reaction("O4")
    np.testing.assert_allclose(on_ground, f.shaking_force(), atol=1e-10 * np.abs(on_ground).max())
    O4 = res.position("O4")
    F4 = f.reaction("O4")
    moment = O4[:, 0] * F4[:, 1] - O4[:, 1] * F4[:, 0] - f.driver_effort("crank")  # about the origin (O2)
    np.testing.assert_allclose(moment, f.shaking_moment(), atol=1e-10 * np.abs(moment).max())


def test_reaction_names_and_errors():
    f = slider_crank().sweep([0.3]).forces()
    with pytest.raises(planar.ModelError, match="normal"):
        f.reaction("slide", "friction")
    with pytest.raises(planar.ModelError, match="unknown joint"):
        f.reaction("nope")
    with pytest.raises(planar.ModelError, match="unknown driver"):
        f.driver_effort("nope")
    assert f.reaction("O2").shape == (1, 2) and f.driver_effort("crank").shape == (1,)


# ---- each joint type against finite differences ------------------------------------------------

JOINTS = [cls for cls in JOINT_TYPES if not cls.is_driver]


def _perp(v):
    return np.stack((-v[1], v[0]))


def expected_force(cls, P, F, comps):
    """The force on slot 1 the class's named components describe, (2, K, N)."""
    name = cls.__name__
    if name == "Revolute":
        return None
    d = _d(P, F)
    if name in ("Slot", "Prismatic", "RackPinion"):
        u = F.vec(0, P["u"])
        n = _perp(u)
        if name == "RackPinion":
            return comps["normal"] * np.sign(P["sR"]) * n + comps["tangential"] * u
        return comps["normal"] * n
    dh = d / np.sqrt(d[0] ** 2 + d[1] ** 2)
    if name == "RollingContact":
        return comps["normal"] * np.sign(P["R"][1]) * dh + comps["friction"] * _perp(dh)
    return comps["tangential"] * _perp(dh)


def _d(P, F):
    """Centre a to centre b (or the line's origin to the point), (2, K, N)."""
    return F.r[:, 1] + F.vec(1, P["s"][:, 1]) - F.r[:, 0] - F.vec(0, P["s"][:, 0])


@pytest.mark.parametrize("cls", JOINTS, ids=lambda c: c.__name__)
def test_reaction_rows_against_finite_differences(cls):
    """The joint acts on its bodies with -force_rows^T lam: force_rows are the finite
    differences of the constraint rows (of the contact's rows for gears on a carrier), and the
    named components give the force on the second body."""
    rng = np.random.default_rng(17)
    P = group(cls, rng)
    nb = cls.n_bodies
    q = rng.uniform(-2, 2, (3, nb, 3, 5))
    # a carrier's mesh: the rows of the same mesh with free centres, on the two gears
    contact = planar.joints.Gear if cls.__name__ == "CarrierGear" else cls
    rows = lambda q: contact.Phi(P, frames(q[:, :2] if nb == 3 else q))  # noqa: E731
    P["c"] = np.zeros((contact.n_rows,) + P["c"].shape[1:])
    P["c"] = rows(q)
    W = cls.force_rows(P, frames(q))
    h = 1e-6
    for col in range(3 * min(nb, 2)):
        e = np.zeros((3, nb, 1, 1))
        e[col % 3, col // 3] = h
        fd = (rows(q + e) - rows(q - e)) / (2 * h)
        np.testing.assert_allclose(W[:, col], fd, atol=1e-7, rtol=1e-6)
    if nb == 3:
        assert not W[:, 6:].any()  # the carrier takes the tooth force through the pins only
    lam = rng.normal(size=(cls.n_rows, 3, 5))
    F = frames(q)
    force = -np.einsum("rcKN,rKN->cKN", W[:, 3:5], lam)
    comps = cls.reaction(P, F, lam)
    want = expected_force(cls, P, F, comps)
    if want is not None:
        np.testing.assert_allclose(want, force, rtol=1e-10, atol=1e-12)
    if cls.__name__ == "Prismatic":
        Sb = F.vec(1, P["s"][:, 1])
        moment = -np.einsum("rKN,rKN->KN", W[:, 5], lam)
        np.testing.assert_allclose(Sb[0] * force[1] - Sb[1] * force[0] + comps["moment"], moment, rtol=1e-10)
    C = cls.contact_load(P, F, lam)
    if C is not None:  # the radial tooth force: equal and opposite along the line of centres
        np.testing.assert_allclose(C[0:2] + C[3:5], 0.0, atol=1e-12)
        d = _d(P, F)
        np.testing.assert_allclose(C[3] * d[1] - C[4] * d[0], 0.0, atol=1e-10)
        np.testing.assert_allclose(np.hypot(C[3], C[4]), comps["radial"], rtol=1e-10)


# ---- files -----------------------------------------------------------------------------------


def test_mass_gravity_loads_and_pressure_angles_round_trip_through_files():
    from planar import io

    m = planar.Mechanism("geared arm")
    a = m.add_body("a", angle=0.3, **planar.bar(2.0, (0, 0), (1, 0)))
    b = m.add_body("b", **planar.disc(1.5, (3, 0), 2.0))
    m.add_revolute("O", m.ground, a, at=(0, 0))
    m.add_revolute("P", m.ground, b, at=(3, 0))
    m.add_gear("g", a, b, 1.0, 2.0, carrier=m.ground, pressure_angle=np.radians(25))
    m.gravity = (0.0, -9.81)
    m.add_load(b, force=(1.0, 2.0), at=(3.0, 1.0), torque=0.5, fixed="body")
    m.drive("O")
    text = io.dumps(m)
    back = io.loads(text).mechanism
    assert io.dumps(back) == text
    assert '"pressure_angle": 25.0' in text and '"gravity": [0.0, -9.81]' in text
    u = np.linspace(0, 2, 5)
    f, g = m.sweep(u, velocity=2.0).forces(), back.sweep(u, velocity=2.0).forces()
    np.testing.assert_array_equal(f.driver_effort("O"), g.driver_effort("O"))
    np.testing.assert_array_equal(f.reaction("g", "contact"), g.reaction("g", "contact"))
    wheel = CATALOGUE["rolling_wheel"]()  # a contact without teeth is written as rolling
    assert '"type": "rolling"' in io.dumps(wheel) and "pressure_angle" not in io.dumps(wheel)


@pytest.mark.parametrize("change, where", [
    (lambda d: d["bodies"][0].pop("com"), "bodies[0]: missing field 'com'"),
    (lambda d: d["loads"][0].update(fixed="ground"), "loads[0].fixed"),
    (lambda d: d.update(gravity=[0, "down"]), "file.gravity"),
    (lambda d: d["loads"][0].update(body="ground"), "loads[0]: a load on the ground"),
])
def test_file_errors_name_the_field(change, where):
    from planar import io

    m = slider_crank()
    m.set_mass("crank", 1.0, (0.5, 0.0), 0.1)
    m.add_load("slider", force=(-1.0, 0.0), at=m.sketch().points["B"][1])
    doc = io.to_dict(m)
    change(doc)
    with pytest.raises(planar.FileFormatError, match=where.replace("[", r"\[").replace("]", r"\]")):
        io.from_dict(doc, "f.json")


def test_a_load_given_by_a_function_has_no_file_form():
    from planar import io

    m = slider_crank()
    m.add_load("crank", torque=lambda u: u[:, 0])
    with pytest.raises(planar.FileFormatError, match="function"):
        io.dumps(m)


# ---- the command line --------------------------------------------------------------------------


def test_cli_run_forces_writes_efforts_reactions_and_their_pictures(tmp_path, capsys):
    import csv

    from planar import cli, io

    m = slider_crank(2, 5, offset=1)
    B = m.sketch().points["B"][1]
    m.set_mass("slider", 3.0, B, 0.01)
    m.add_load("slider", force=(-100.0, 0.0), at=B)
    path = io.save(m, tmp_path / "sc.json", units=planar.units.Units("m"))
    out = tmp_path / "out"
    code = cli.main(["run", str(path), "--forces", "--num", "13", "--no-animation", "--out", str(out)])
    text = capsys.readouterr().out
    assert code == 0
    assert "slider: mass 3 kg, inertia 0.01 kg m^2" in text and "effort of crank:" in text
    assert (out / "slider_crank_forces.png").exists() and (out / "slider_crank_efforts.png").exists()
    with open(out / "slider_crank.csv", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert {"effort:crank [N m]", "Fx:B [N]", "normal:slide [N]", "moment:slide [N m]", "shaking:Fx [N]"} <= set(rows[0])
    res = m.sweep(np.radians([float(r["input:crank [deg]"]) for r in rows]))
    want = res.forces().driver_effort("crank")
    np.testing.assert_allclose([float(r["effort:crank [N m]"]) for r in rows], want, rtol=1e-12)


def test_cli_notes_an_indeterminate_mechanism(tmp_path, capsys):
    from planar import cli, io

    path = io.save(planetary_gear_train(planets=3), tmp_path / "p.json")
    code = cli.main(["run", str(path), "--forces", "--num", "5", "--no-animation", "--no-plot",
                     "--out", str(tmp_path / "o")])
    assert code == 0
    assert "note: mechanism 'planetary_gear_train' is statically indeterminate" in capsys.readouterr().out


def test_the_docs_page_example_runs():
    import pathlib
    import re

    page = (pathlib.Path(__file__).parents[1] / "docs" / "forces.md").read_text(encoding="utf-8")
    for block in re.findall(r"```python\n(.*?)```", page, re.S):
        exec(compile(block, "docs/forces.md", "exec"), {})


def test_the_benchmarks_quick_path_runs_with_small_errors(capsys):
    import importlib.util
    import pathlib
    import re
    import sys

    path = pathlib.Path(__file__).parents[1] / "benchmarks" / "forces_speed.py"
    sys.path.insert(0, str(path.parent))
    try:
        spec = importlib.util.spec_from_file_location("forces_speed", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        module.main(["--quick"])
    finally:
        sys.path.remove(str(path.parent))
    out = capsys.readouterr().out
    for name in module.CASES:
        row = re.search(rf"^{re.escape(name)}\s+1000\s+([\d.]+)\s+([\d.]+)\s+[\d.]+\s+([\d.]+)\s+(\S+)$", out, re.M)
        assert row and min(float(row[k]) for k in (1, 2, 3)) > 0 and float(row[4]) < 1e-10, name
