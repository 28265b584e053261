"""Mass properties of simple shapes against their integrals, loads, and the compiled fields.

The shapes' moments of inertia are checked against a fine sum of point masses (midpoint
rule), the loads against a rotation by hand, and the compiled mass fields against the
sketch they were given in (centres of mass in the body frames, read-only arrays).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planar.errors import ModelError
from planar.mass import Load, bar, disc, plate
from planar.mechanisms import four_bar

M = 1000  # points per side of the midpoint sums
coords = st.floats(-10, 10)


def moment(points, weights, centre):
    return float(np.sum(weights * np.sum((points - centre) ** 2, axis=1)))


@settings(max_examples=25, deadline=None)
@given(st.floats(0.1, 10), st.tuples(coords, coords), st.tuples(coords, coords))
def test_bar_is_the_sum_of_its_points(mass, a, b):
    t = (np.arange(M) + 0.5) / M
    pts = np.asarray(a) + t[:, None] * (np.asarray(b) - np.asarray(a))
    got = bar(mass, a, b)
    assert got["mass"] == mass
    np.testing.assert_allclose(got["com"], pts.mean(axis=0), atol=1e-9)
    assert got["inertia"] == pytest.approx(moment(pts, mass / M, got["com"]), rel=1e-5, abs=1e-12)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.1, 10), st.tuples(coords, coords), st.floats(0.1, 5), st.floats(0.1, 5))
def test_plate_is_the_sum_of_its_points(mass, centre, w, h):
    g = (np.arange(200) + 0.5) / 200 - 0.5
    X, Y = np.meshgrid(g * w, g * h)
    pts = np.stack((X.ravel(), Y.ravel()), axis=1) + centre
    got = plate(mass, centre, w, h)
    assert got["com"] == tuple(map(float, centre))
    assert got["inertia"] == pytest.approx(moment(pts, mass / pts.shape[0], centre), rel=1e-4)


def test_disc_is_the_sum_of_its_rings():
    mass, r = 3.0, 0.7
    rho = (np.arange(M) + 0.5) / M * r  # rings of area 2 pi rho d rho
    dm = mass * 2 * rho * (r / M) / r**2
    assert disc(mass, (1.0, 2.0), r) == {"mass": 3.0, "com": (1.0, 2.0),
                                         "inertia": pytest.approx(float(np.sum(dm * rho**2)), rel=1e-6)}


def test_a_body_fixed_load_turns_with_its_body_and_a_world_load_does_not():
    inputs = np.zeros((4, 1))
    phi = np.array([0.3, 1.0, 2.0, -1.5])
    world = Load(1, np.zeros(2), np.array([1.0, 2.0]), 0.5, "world", 0.3)
    f, tau = world.at(inputs, phi)
    np.testing.assert_array_equal(f, np.tile([1.0, 2.0], (4, 1)))
    np.testing.assert_array_equal(tau, np.full(4, 0.5))
    body = Load(1, np.zeros(2), np.array([1.0, 2.0]), 0.0, "body", 0.3)
    f, _ = body.at(inputs, phi)
    turn = phi - 0.3
    want = np.stack((np.cos(turn) - 2 * np.sin(turn), np.sin(turn) + 2 * np.cos(turn)), axis=1)
    np.testing.assert_allclose(f, want, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(f, axis=1), np.sqrt(5.0), rtol=1e-15)


def test_load_functions_of_the_inputs_and_their_shapes():
    inputs = np.linspace(0, 1, 5)[:, None]
    load = Load(1, np.zeros(2), lambda u: np.hstack((u, 2 * u)), lambda u: 3 * u[:, 0], "world", 0.0)
    f, tau = load.at(inputs, np.zeros(5))
    np.testing.assert_array_equal(f, np.hstack((inputs, 2 * inputs)))
    np.testing.assert_array_equal(tau, 3 * inputs[:, 0])
    bad = Load(1, np.zeros(2), lambda u: u, 0.0, "world", 0.0)
    with pytest.raises(ModelError, match=r"force function gave shape \(5, 1\) for 5 input values; it must give"):
        bad.at(inputs, np.zeros(5))


def test_compiled_centres_of_mass_are_the_sketch_points_in_the_body_frames():
    mech = four_bar(4, 2, 3.5, 3)
    sk = mech.sketch()
    A, B = sk.points["A"][1], sk.points["B"][1]
    mech.set_mass("coupler", **bar(2.0, A, B))
    mech.set_mass("crank", 1.0, (0.5, 0.25), 0.1)
    mech.add_load("coupler", force=(0.0, -3.0), at=B, fixed="body")
    model = mech.compile()
    for body, want in (("coupler", 0.5 * (np.asarray(A) + B)), ("crank", (0.5, 0.25))):
        b = model.body_id(body)
        x, y, phi = model.q0[3 * b - 3 : 3 * b]
        c, s = np.cos(phi), np.sin(phi)
        world = np.array([x, y]) + np.array([[c, -s], [s, c]]) @ model.com[b]
        np.testing.assert_allclose(world, want, atol=1e-12, err_msg=body)
    np.testing.assert_array_equal(model.mass, [0.0, 1.0, 2.0, 0.0])
    assert model.inertia[2] == pytest.approx(2.0 * 3.5**2 / 12)
    (load,) = model.loads
    assert load.body == model.body_id("coupler") and load.fixed == "body"
    for a in (model.mass, model.com, model.inertia, model.gravity, load.s, load.force):
        assert not a.flags.writeable
