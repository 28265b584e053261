"""Compile-time checks: each bad input raises the planned exception, naming what is at fault."""

import numpy as np
import pytest

import planar
from planar import (AssemblyError, ConnectivityError, InputError, MobilityError, ModelError,
                    PlanarError, RedundancyError)


def parallelogram(third_crank_at=None):
    """Parallelogram 0-(0,0), A(0,1), B(2,1), O4(2,0); optionally a third crank to the coupler."""
    m = planar.Mechanism("parallelogram")
    cr, co, ro = m.add_body("crank", np.pi / 2), m.add_body("coupler"), m.add_body("rocker", np.pi / 2)
    m.add_revolute("O2", m.ground, cr, at=(0, 0))
    m.add_revolute("A", cr, co, at=(0, 1))
    m.add_revolute("B", co, ro, at=(2, 1))
    m.add_revolute("O4", ro, m.ground, at=(2, 0))
    if third_crank_at is not None:
        c3 = m.add_body("crank3", np.pi / 2)
        m.add_revolute("O6", m.ground, c3, at=(1, 0))
        m.add_revolute("E", c3, co, at=third_crank_at)
    return m


def test_every_error_is_a_planar_error():
    for cls in (ModelError, ConnectivityError, MobilityError, RedundancyError, AssemblyError, InputError):
        assert issubclass(cls, PlanarError)


def test_unconnected_body_is_named():
    m = parallelogram()
    m.add_body("loose")
    with pytest.raises(ConnectivityError, match="'loose'"):
        m.compile()


def test_island_of_bodies_not_on_ground():
    m = parallelogram()
    a, b = m.add_body("a"), m.add_body("b")
    m.add_revolute("ab", a, b, at=(5, 5))
    with pytest.raises(ConnectivityError, match=r"\['a', 'b'\]"):
        m.compile()


def test_redundant_third_crank_is_found_and_kept_out():
    m = parallelogram(third_crank_at=(1, 1))
    m.drive("O2")
    model = m.compile()
    assert model.grubler == 0 and model.dof == 1
    assert len(model.redundant_joints) == 1
    res = m.sweep(np.linspace(np.pi / 2, 0.9 * np.pi, 7))
    assert res.ok.all()
    np.testing.assert_allclose(res.angle("crank3"), res.angle("crank"), atol=1e-12)


def test_pivot_declared_twice_locks_the_mechanism():
    m = parallelogram()
    # the same pivot declared twice, a millimetre apart on a 2 m mechanism: the rocker is welded
    m.add_revolute("O4bis", "rocker", m.ground, at=(2.001, 0))
    m.drive("O2")
    with pytest.raises(MobilityError, match="0 degree.*pivot declared twice"):
        m.compile()


def test_inconsistent_redundant_joint_is_an_error():
    """A wheel on the floor whose centre a slider also holds, at a height off by 4e-7 of its
    radius: the tangency row repeats the slider's and contradicts it."""
    m = planar.Mechanism("wheel on a guided axle")
    wheel, block = m.add_body("wheel"), m.add_body("block")
    m.add_prismatic("guide", m.ground, block, at=(0, 1 + 4e-7), direction=(1, 0))
    m.add_revolute("axle", block, wheel, at=(0, 1 + 4e-7))
    m.add_rolling("floor", wheel, m.ground, 1.0, centre=(0, 1 + 4e-7), through=(0, 0), direction=(1, 0))
    m.drive("guide")
    with pytest.raises(RedundancyError, match="'(floor|guide)'.*contradicts"):
        m.compile()


def test_consistent_redundant_contact_solves():
    m = planar.Mechanism("wheel on a guided axle")
    wheel, block = m.add_body("wheel"), m.add_body("block")
    m.add_prismatic("guide", m.ground, block, at=(0, 1), direction=(1, 0))
    m.add_revolute("axle", block, wheel, at=(0, 1))
    m.add_rolling("floor", wheel, m.ground, 1.0, centre=(0, 1), through=(0, 0), direction=(1, 0))
    m.drive("guide")
    model = m.compile()
    assert model.dof == 1 and model.redundant_joints
    res = m.sweep([0.0, 1.0, 2.0], velocity=3.0)
    assert res.ok.all()
    # rolling to the right turns the wheel clockwise: phi = -x / R
    np.testing.assert_allclose(res.angle("wheel"), [0.0, -1.0, -2.0], atol=1e-14)
    np.testing.assert_allclose(res.omega("wheel"), -3.0, atol=1e-14)


def test_too_many_and_too_few_drivers():
    m = parallelogram()
    m.drive("O2")
    m.drive("O4")
    with pytest.raises(MobilityError, match="1 degree"):
        m.compile()
    m = parallelogram()
    with pytest.raises(MobilityError, match="no driver"):
        m.sweep([0.1])


def test_both_gears_of_one_mesh_driven_is_dependent():
    m = planar.Mechanism("gear pair")
    g1, g2 = m.add_body("g1"), m.add_body("g2")
    m.add_revolute("p1", m.ground, g1, at=(0, 0))
    m.add_revolute("p2", m.ground, g2, at=(3, 0))
    m.add_gear("mesh", g1, g2, 1.0, 2.0, carrier=m.ground)
    m.add_body("arm")
    m.add_revolute("p3", m.ground, "arm", at=(0, 5))
    m.drive("p1")
    m.drive("p2")
    with pytest.raises(MobilityError, match="'p2' depends"):
        m.compile()


@pytest.mark.parametrize("call, match", [
    (lambda m: m.add_body("crank"), "already used"),
    (lambda m: m.add_body(""), "non-empty"),
    (lambda m: m.add_revolute("X", "crank", "crank", at=(0, 0)), "to itself"),
    (lambda m: m.add_revolute("X", "crank", "nowhere", at=(0, 0)), "unknown body 'nowhere'"),
    (lambda m: m.add_revolute("X", "crank", "ground", at=(np.nan, 0)), "finite"),
    (lambda m: m.add_revolute("X", "crank", "ground", at="here"), "unknown joint or point 'here'"),
    (lambda m: m.add_revolute("X", "crank", "ground", at=("here", 0)), "numeric"),
    (lambda m: m.add_gear("g", "crank", "rocker", -1.0, 1.0, carrier="ground"), "positive"),
    (lambda m: m.add_gear("g", "crank", "rocker", 1.0, 1.0, centre_a=(0, 0), centre_b=(5, 0)), "apart"),
    (lambda m: m.add_prismatic("s", "crank", "rocker", at=(0, 0), direction=(0, 0)), "non-zero"),
    (lambda m: m.add_rack_pinion("r", "crank", "ground", 1.0, centre=(0, 3), through=(0, 0),
                                 direction=(1, 0)), "left of the line"),
    (lambda m: m.drive("nothing"), "unknown joint"),
    (lambda m: m.drive(point="A", axis="z"), "unknown point|axis"),
    (lambda m: m.drive(), "exactly one"),
])
def test_bad_builder_calls(call, match):
    m = parallelogram()
    with pytest.raises(ModelError, match=match):
        call(m)


def test_sweep_values_of_the_wrong_shape():
    m = parallelogram()
    m.drive("O2")
    with pytest.raises(InputError, match="shape"):
        m.sweep(np.zeros((3, 2)))
    with pytest.raises(InputError, match="finite"):
        m.sweep([0.1, np.inf])
    with pytest.raises(InputError, match="shape"):
        m.sweep([0.1, 0.2], velocity=[1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="scalar"):
        m.sweep(0.3)


def test_unknown_names_in_results():
    m = parallelogram()
    m.drive("O2")
    res = m.sweep([1.0])
    with pytest.raises(ModelError, match="unknown point"):
        res.position("Z")
    with pytest.raises(ModelError, match="unknown body"):
        res.angle("Z")
    with pytest.raises(ModelError, match="no coordinate"):
        res.coordinate("Z")


def test_set_angle_restates_a_body_angle_and_names_what_is_at_fault():
    m = planar.Mechanism()
    wheel = m.add_body("wheel")
    m.add_revolute("O", m.ground, wheel, at=(0, 0))
    m.drive(body=wheel)
    assert m.compile().sketch.bodies["wheel"] == 0.0
    m.set_angle("wheel", 0.5)
    assert m.compile().sketch.bodies["wheel"] == 0.5  # the cached model is dropped
    with pytest.raises(ModelError, match="ground"):
        m.set_angle(m.ground, 0.5)
    with pytest.raises(ModelError, match="'axle'"):
        m.set_angle("axle", 0.5)
    with pytest.raises(ModelError, match="angle of body 'wheel'"):
        m.set_angle("wheel", float("nan"))


def test_restate_changes_a_stated_distance_or_a_start_and_refuses_others():
    m = planar.Mechanism()
    crank = m.add_body("crank")
    m.add_revolute("O", m.ground, crank, at=(0, 0))
    m.add_point("P", crank, at=(1, 0))
    m.distance("O", "P", 1.0)
    m.drive("O", start=0.0)
    assert m.compile().sketch.position("P").tolist() == [1.0, 0.0]
    m.restate("O-P", 2.0)
    assert np.allclose(m.compile().sketch.position("P"), [2.0, 0.0], atol=1e-12)  # the cached model is dropped
    with pytest.raises(ModelError, match="distance O-P must be positive"):
        m.restate("O-P", -1.0)
    with pytest.raises(ModelError, match="'Q' is no number"):
        m.restate("Q", 1.0)
