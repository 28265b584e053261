"""Parameter studies: one sweep over many designs, stacked with a leading design axis."""

import numpy as np
import pytest

import planar
from planar.designs import DesignSweep, sweep_designs
from planar.mechanisms import four_bar, slider_crank
from tests import oracles

TH = np.radians(np.arange(0.0, 360.0, 10.0))


def test_a_four_bar_family_matches_the_closed_form_design_by_design():
    cranks = np.linspace(0.8, 2.2, 8)
    study = sweep_designs(four_bar, {"crank": cranks, "coupler_point": [(1.0, 0.8)] * 8}, TH, 1.5, -0.3,
                          fixed=dict(ground=4.0, coupler=3.5, rocker=3.0))
    assert isinstance(study, DesignSweep) and len(study) == 8 and study.N == TH.size
    assert study.ok.all() and study.status.shape == (8, TH.size)
    C, V, A = study.position("C"), study.velocity("C"), study.acceleration("C")
    assert C.shape == V.shape == A.shape == (8, TH.size, 2)
    for d, r2 in enumerate(cranks):
        o = oracles.four_bar(4.0, r2, 3.5, 3.0, TH, w2=1.5, a2=-0.3, p=1.0, q=0.8)
        np.testing.assert_allclose(C[d], o["C"], atol=1e-12)
        np.testing.assert_allclose(V[d], o["C_vel"], atol=1e-10)
        np.testing.assert_allclose(A[d], o["C_acc"], atol=1e-10)
        np.testing.assert_allclose(np.unwrap(study.angle("rocker")[d]), np.unwrap(o["th4"]), atol=1e-12)


def test_each_design_row_is_that_design_swept_alone():
    study = sweep_designs(slider_crank, [dict(crank=1.0, offset=0.0), dict(crank=2.0, offset=0.5)], TH,
                          fixed=dict(coupler=5.0))
    for d, design in enumerate(study.designs):
        alone = slider_crank(coupler=5.0, **design).sweep(TH)
        np.testing.assert_allclose(study.position("B")[d], alone.position("B"), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(study.status[d], alone.status)
        assert study[d].model.name == alone.model.name


def test_a_design_that_cannot_be_built_is_kept_with_nan_and_its_reason():
    # a coupler of 0.5 cannot close a 4 / 2 / 3 loop: the sketch does not assemble
    study = sweep_designs(four_bar, {"coupler": [3.5, 0.5, 3.5]}, TH, fixed=dict(ground=4.0, crank=2.0, rocker=3.0))
    assert study.errors[0] is None and study.errors[2] is None
    assert "design 1" in study.errors[1] and "coupler" in study.errors[1]
    assert study.sweeps[1] is None and study.events[1] == ()
    assert np.all(np.isnan(study.position("B")[1])) and np.all(study.status[1] == planar.Status.NOT_ASSEMBLABLE)
    assert study.ok[0].all() and study.ok[2].all() and not study.ok[1].any()


def test_values_may_depend_on_the_design_and_limits_are_per_design():
    # triple rockers of growing crank: each swept up to just past its own limit
    cranks = [2.6, 2.8, 3.0]
    limits = [oracles.four_bar_input_limits(4.0, r2, 3.0, 3.0)[0][1] for r2 in cranks]
    study = sweep_designs(four_bar, {"crank": cranks}, lambda d: np.linspace(0.0, 3.0, 31),
                          fixed=dict(ground=4.0, coupler=3.0, rocker=3.0))
    for d, lim in enumerate(limits):
        got = [e.input for e in study.events[d] if e.kind == "limit"]
        assert got and abs(got[0] - lim) < 1e-9
        u = study.inputs[d, :, 0]
        assert np.all(study.ok[d][u < lim - 1e-6]) and not study.ok[d][u > lim + 1e-6].any()


def test_wrong_calls_are_named():
    with pytest.raises(planar.InputError, match="equal, non-zero lengths"):
        sweep_designs(four_bar, {"crank": [1.0, 2.0], "rocker": [3.0, 3.5, 4.0]}, TH)
    with pytest.raises(planar.InputError, match="no design could be built"):
        sweep_designs(four_bar, {"coupler": [0.1, 0.2]}, TH, fixed=dict(ground=4.0, crank=2.0, rocker=3.0))
    with pytest.raises(planar.InputError, match="designs"):
        sweep_designs(four_bar, [], TH)
