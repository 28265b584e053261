"""Parameter studies: one sweep over many designs, stacked with a leading design axis."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import planar
from planar.designs import batch as design_batch
from planar.designs import tables as design_tables
from planar.designs import DesignSweep, Vary, sweep_designs
from planar.results import POSED
from planar.mechanisms import (four_bar, gear_train, geared_five_bar, inverted_slider_crank, open_chain,
                               planetary_gear_train, rack_and_pinion, rolling_wheel, slider_crank, watt_six_bar)
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


# ---- the batch: designs folded into the solver's batch axis -----------------------------------

def _crank_rockers(rng, D):
    """D Grashof crank-rockers (crank shortest, s + l < p + q by a margin) with coupler points
    and starts."""
    out = []
    while len(out) < D:
        r1, r3, r4 = rng.uniform(2.5, 5.0, 3)
        r2 = rng.uniform(0.3, 1.5)
        s, p_, q_, l = sorted([r1, r2, r3, r4])
        if r2 == s and s + l < 0.9 * (p_ + q_):
            out.append(dict(ground=r1, crank=r2, coupler=r3, rocker=r4,
                            coupler_point=tuple(rng.uniform(-1.5, 1.5, 2)), start=rng.uniform(-np.pi, np.pi)))
    return out


def _alone(build, design, values, *rates):
    return build(**design).compile().sweep(values, *rates)


ENGINES = ["numpy", pytest.param("numba", marks=pytest.mark.numba)]


@pytest.mark.parametrize("engine", ENGINES)
def test_a_batch_of_designs_is_each_design_swept_alone_and_freudensteins_closed_form(engine):
    rng = np.random.default_rng(5)
    designs = _crank_rockers(rng, 16)
    study = sweep_designs(four_bar, designs, lambda d: d["start"] + TH, 1.3, 0.4, engine=engine)
    assert study.batched.all() and study.ok.all() and all(e is None for e in study.errors)
    col = lambda k: np.array([d[k] for d in designs])[:, None]  # noqa: E731
    pq = np.array([d["coupler_point"] for d in designs])
    cf = oracles.freudenstein(col("ground"), col("crank"), col("coupler"), col("rocker"), col("start") + TH,
                              pq[:, :1], pq[:, 1:])
    np.testing.assert_allclose(study.position("C"), cf["C"], rtol=0, atol=1e-12)
    dth = study.angle("rocker") - cf["th4"]
    np.testing.assert_allclose(np.angle(np.exp(1j * dth)), 0.0, atol=1e-12)
    for d, design in enumerate(designs):
        alone = _alone(four_bar, design, design["start"] + TH, 1.3, 0.4)
        np.testing.assert_array_equal(study.status[d], alone.status)
        np.testing.assert_allclose(study.q[d], alone.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(study.qd[d], alone.qd, rtol=0, atol=1e-10)
        np.testing.assert_allclose(study.qdd[d], alone.qdd, rtol=0, atol=1e-9)
        np.testing.assert_allclose(study.velocity("C")[d], alone.velocity("C"), rtol=0, atol=1e-10)
        np.testing.assert_allclose(study[d].acceleration("C"), alone.acceleration("C"), rtol=0, atol=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
def test_a_batch_walks_values_in_any_order_and_spacing_as_each_design_alone(engine):
    """Values back and forth, repeated, dense and a turn apart: each design's walk (on the
    compiled engine, a design a lane through stations between values further apart than
    max_step) gives what the design swept alone does."""
    designs = _crank_rockers(np.random.default_rng(11), 5)
    U = np.r_[np.linspace(1.0, 0.2, 9), 0.2, 0.2 + 2 * np.pi, np.linspace(6.0, 6.01, 4), -3.0]
    study = sweep_designs(four_bar, designs, U, 1.3, 0.4, engine=engine)
    assert study.batched.all() and study.ok.all()
    for d, design in enumerate(designs):
        alone = _alone(four_bar, design, U, 1.3, 0.4)
        np.testing.assert_array_equal(study.status[d], alone.status)
        np.testing.assert_allclose(study.q[d], alone.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(study.qdd[d], alone.qdd, rtol=0, atol=1e-9)


@pytest.mark.numba
def test_the_compiled_walk_over_slices_of_designs_is_the_walk_over_all(monkeypatch):
    """Walks too long for one call (stations beyond WALK_BYTES) go a few designs a call; a
    design that meets a limit on the way is left to its sweep alone, whatever its slice."""
    designs = _crank_rockers(np.random.default_rng(3), 4)
    designs.insert(2, dict(designs[0], crank=3.0))  # crank no longer the shortest: limits within the turn
    whole = sweep_designs(four_bar, designs, TH, 1.3, 0.4, engine="numba")
    monkeypatch.setattr(design_batch, "WALK_BYTES", 1)  # a design a call
    sliced = sweep_designs(four_bar, designs, TH, 1.3, 0.4, engine="numba")
    assert whole.batched.tolist() == sliced.batched.tolist() == [True, True, False, True, True]
    for k in ("q", "qd", "qdd", "status", "residual", "singularity", "iterations"):
        np.testing.assert_array_equal(getattr(sliced, k), getattr(whole, k))


def test_failing_designs_keep_their_statuses_and_reasons_and_the_others_are_batched():
    fixed = dict(ground=4.0, rocker=3.0, coupler_point=(1.0, 0.5))
    designs = [dict(crank=1.0, coupler=3.5),  # crank-rocker: regular all round
               dict(crank=3.0, coupler=3.0),  # triple rocker: limits, values out of range
               dict(crank=2.0, coupler=0.5),  # does not assemble
               dict(crank=1.2, coupler=3.2)]
    study = sweep_designs(four_bar, designs, TH, fixed=fixed)
    assert study.batched.tolist() == [True, False, False, True]
    assert study.errors[2] is not None and "design 2" in study.errors[2] and study[2] is None
    assert np.all(study.status[2] == planar.Status.NOT_ASSEMBLABLE) and np.isnan(study.q[2]).all()
    alone = _alone(four_bar, dict(fixed, **designs[1]), TH)
    np.testing.assert_array_equal(study.status[1], alone.status)
    assert {e.kind for e in study.events[1]} == {"limit"} and not study.ok[1].all() and study.ok[1].any()
    np.testing.assert_array_equal(study.position("C")[1], alone.position("C"))
    np.testing.assert_array_equal(study.gap[1], alone.gap)
    assert study.ok[[0, 3]].all() and study.events[0] == study.events[3] == ()


def test_a_design_whose_walk_is_too_long_for_the_batch_keeps_its_points():
    # a start 1e6 rad away is swept alone (its sweep solves the values whole periods back): its
    # points' positions were NaN under SOLVED, and a study of it alone raised a KeyError
    study = sweep_designs(four_bar, {"start": [1e6, 0.5]}, [0.1, 0.2])
    assert study.batched.tolist() == [False, True] and study.ok.all()
    for name in ("A", "B"):
        np.testing.assert_array_equal(study.position(name)[0], _alone(four_bar, dict(start=1e6), [0.1, 0.2]).position(name))
    alone = sweep_designs(four_bar, {"start": [1e6]}, [0.1, 0.2])
    np.testing.assert_array_equal(alone.velocity("B")[0], study.velocity("B")[0])


def _dimensioned_four_bar(crank, coupler, rocker):
    """A four-bar drawn roughly once, its lengths stated with Mechanism.distance."""
    m = planar.Mechanism("dimensioned")
    for b in ("crank", "coupler", "rocker"):
        m.add_body(b)
    m.add_revolute("O2", m.ground, "crank", at=(0.0, 0.0))
    m.add_revolute("A", "crank", "coupler", at=(1.0, 0.3))
    m.add_revolute("B", "coupler", "rocker", at=(3.5, 2.5))
    m.add_revolute("O4", "rocker", m.ground, at=(4.0, 0.0))
    for a, b, r in (("O2", "O4", 4.0), ("O2", "A", crank), ("A", "B", coupler), ("O4", "B", rocker)):
        m.distance(a, b, r)
    m.drive(body="crank", start=0.0)
    return m


def test_designs_vary_by_the_numbers_of_stated_distances():
    cranks, couplers = np.array([0.8, 1.0, 1.3]), np.array([3.6, 3.4, 3.9])
    study = sweep_designs(_dimensioned_four_bar, {"crank": cranks, "coupler": couplers, "rocker": 3.0}, TH)
    assert study.batched.all() and study.ok.all()
    cf = oracles.freudenstein(4.0, cranks[:, None], couplers[:, None], 3.0, TH)
    B = cf["C"] + np.stack([couplers[:, None] * np.cos(cf["th3"]), couplers[:, None] * np.sin(cf["th3"])], -1)
    np.testing.assert_allclose(study.position("B"), B, rtol=0, atol=1e-12)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(0.3, 5.0), st.floats(0.3, 5.0), st.floats(0.3, 5.0), st.floats(-np.pi, np.pi)),
                min_size=1, max_size=6))
def test_any_batch_of_four_bars_is_each_design_swept_alone(rows):
    """Random designs, regular or not: the batch reports what each design swept alone does."""
    designs = [dict(crank=a, coupler=b, rocker=c, start=s) for a, b, c, s in rows]
    U = np.linspace(-1.0, 1.0, 25)
    try:
        study = sweep_designs(four_bar, designs, lambda d: d["start"] + U, fixed=dict(ground=4.0))
    except planar.InputError as e:  # no design assembles
        assert "no design could be built" in str(e)
        return
    for d, design in enumerate(designs):
        try:
            alone = _alone(four_bar, dict(design, ground=4.0), design["start"] + U)
        except planar.PlanarError:
            assert study[d] is None and study.errors[d] is not None
            continue
        np.testing.assert_array_equal(study.status[d], alone.status)
        ok = alone.ok
        np.testing.assert_allclose(study.q[d][ok], alone.q[ok], rtol=0, atol=1e-11)
        np.testing.assert_allclose(study.qd[d][ok], alone.qd[ok], rtol=0, atol=1e-8)


CATALOGUE = {
    # sliders along x and at an angle: the first plan has structural zeros the others fill
    "slider_crank": (slider_crank, [dict(crank=1.0, offset=0.0, slide_angle=0.0), dict(crank=1.5, offset=0.5,
                     slide_angle=0.3), dict(crank=2.0, offset=1.0, slide_angle=0.6)], TH),
    "gear_train": (gear_train, [dict(radii=(1, 2, 1.5)), dict(radii=(1, 3, 2)), dict(radii=(2, 1, 1.5))], TH),
    "geared_five_bar": (geared_five_bar, [dict(), dict(gear_radius_2=3.2)], np.linspace(0.0, 1.0, 11)),
    "rack_and_pinion": (rack_and_pinion, [dict(radius=1.0), dict(radius=2.0, rack_angle=0.3)], TH),
    "open_chain": (open_chain, [dict(lengths=(5, 8, 9)), dict(lengths=(4, 7, 9))], np.stack([TH, TH / 2, TH / 3], 1)),
    "watt_six_bar": (watt_six_bar, [dict(crank=1.5), dict(crank=1.4), dict(crank=1.6, link_5=3.2)], TH),
    "inverted_slider_crank": (inverted_slider_crank, [dict(), dict(crank=7.0)], TH),
    "planetary_gear_train": (planetary_gear_train, [dict(), dict(sun=1.2)], TH),
    "rolling_wheel": (rolling_wheel, [dict(), dict(radius=1.5)], np.linspace(0.0, 3.0, 21)),
}


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_designs_of_every_joint_type_are_batched_and_each_is_its_sweep_alone(name, engine):
    build, designs, U = CATALOGUE[name]
    study = sweep_designs(build, designs, U, 1.3, 0.2, engine=engine)
    assert study.batched.all()
    for d, design in enumerate(designs):
        alone = _alone(build, design, U, 1.3, 0.2)
        np.testing.assert_array_equal(study.status[d], alone.status)
        np.testing.assert_allclose(study.q[d], alone.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(study.qdd[d], alone.qdd, rtol=0, atol=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
def test_outputs_restrict_the_batch_to_the_blocks_they_need(engine):
    study = sweep_designs(watt_six_bar, {"crank": [1.4, 1.5]}, TH, outputs=("rocker",), engine=engine)
    alone = watt_six_bar(crank=1.4).sweep(TH, outputs=("rocker",))
    assert study.batched.all() and np.isnan(alone.q).any()
    np.testing.assert_array_equal(np.isnan(study.q[0]), np.isnan(alone.q))
    np.testing.assert_allclose(study.q[0], alone.q, rtol=0, atol=1e-12)


@pytest.mark.parametrize("engine", ENGINES)
def test_values_may_be_one_row_per_design(engine):
    starts = np.array([0.3, -1.0, 2.0])
    U = starts[:, None] + TH[None] * np.array([1.0, -0.5, 2.0])[:, None]  # (D, N): each design its own values
    fixed = dict(ground=4.0, crank=1.0, coupler=3.5, rocker=3.0, coupler_point=(1.0, 0.5))
    study = sweep_designs(four_bar, {"start": starts}, U, fixed=fixed, engine=engine)
    assert study.batched.all() and study.inputs.shape == (3, TH.size, 1)
    cf = oracles.freudenstein(4.0, 1.0, 3.5, 3.0, U, 1.0, 0.5)
    np.testing.assert_allclose(study.position("C"), cf["C"], rtol=0, atol=1e-12)
    same = sweep_designs(four_bar, {"start": starts}, U[:, :, None], fixed=fixed, engine=engine)  # (D, N, f)
    np.testing.assert_array_equal(same.q, study.q)
    with pytest.raises(planar.InputError, match="one row per design"):
        sweep_designs(four_bar, {"start": starts}, U[:2], fixed=fixed)


# ---- the tables built at once, and designs as a mechanism's numbers ---------------------------

def _tables_against_alone(t, mechs):
    for k, d in enumerate(t.index):
        m = mechs[d].compile()
        np.testing.assert_allclose(t.q0[k], m.q0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(t.u0[k], m.u0, rtol=0, atol=1e-12)
        assert abs(t.L[k] - m.L) <= 1e-12 * m.L
        for g, h in zip(t.system.groups, m.system.groups):
            assert g.kind is h.kind and g.P.keys() == h.P.keys()
            for key in g.P:
                np.testing.assert_allclose(g.P[key][k], h.P[key], rtol=0, atol=1e-12)
        for name, (b, S) in t.points.items():
            assert m.points[name][0] == b
            np.testing.assert_allclose(S[k], m.points[name][1], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_the_tables_built_at_once_are_each_design_compiled_alone(name):
    build, designs, _ = CATALOGUE[name]
    mechs = [build(**d) for d in designs]
    t, alone = design_tables.tables(mechs[0], mechs[0].compile(), mechs)
    assert alone == [] and t.index.tolist() == list(range(len(designs)))
    _tables_against_alone(t, mechs)


def test_sketches_drawn_roughly_are_assembled_at_once_and_a_design_that_cannot_be_is_left_alone():
    mechs = [_dimensioned_four_bar(c, cp, 3.0) for c, cp in [(0.8, 3.6), (1.0, 3.4), (1.3, 3.9), (0.3, 0.2)]]
    t, alone = design_tables.tables(mechs[0], mechs[0].compile(), mechs)
    assert t.index.tolist() == [0, 1, 2] and alone == [3]
    _tables_against_alone(t, mechs)
    with pytest.raises(planar.AssemblyError):
        mechs[3].compile()


def _rigid_coupler_four_bar():
    """A four-bar whose coupler's four points have all six distances stated: one redundant
    (J J^T singular at every assembly step: the pseudo-inverse's path)."""
    P = dict(O2=(0.0, 0.0), A=(1.0, 0.3), B=(3.5, 2.5), O4=(4.0, 0.0), C=(2.0, 2.0), E=(2.5, 0.5))
    m = planar.Mechanism("rigid coupler")
    for b in ("crank", "coupler", "rocker"):
        m.add_body(b)
    for name, a, b in (("O2", m.ground, "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
                       ("O4", "rocker", m.ground)):
        m.add_revolute(name, a, b, at=P[name])
    for name in "CE":
        m.add_point(name, "coupler", P[name])
    for a, b in (("O2", "O4"), ("O2", "A"), ("A", "B"), ("O4", "B"), ("A", "C"), ("B", "C"), ("A", "E"), ("B", "E"),
                 ("C", "E")):
        m.distance(a, b, float(np.hypot(*np.subtract(P[a], P[b]))))
    m.drive(body="crank", start=0.0)
    return m


@pytest.mark.numba
@pytest.mark.parametrize("mech, lengths", [(four_bar(coupler_point=(1.0, 0.5)), ("O2-A", "A-B", "O4-B")),
                                           (slider_crank(driver="slider"), ("O2-A", "A-B")),
                                           (watt_six_bar(), ("O2-A", "A-B", "O4-B")),
                                           (_rigid_coupler_four_bar(), ("O2-A", "O4-B"))], ids=["four_bar", "slider",
                                                                                           "watt", "redundant"])
def test_the_compiled_engine_assembles_the_designs_sketches_as_the_numpy_engine(mech, lengths):
    """Lengths, angle and travel starts, redundant lengths; some designs cannot be assembled."""
    family, rng = Vary(mech), np.random.default_rng(5)
    starts = mech.sketch().starts
    numbers = [{k: v + rng.uniform(-0.5, 0.5) if k in starts else v * rng.uniform(0.6, 1.4)
                for k, v in family.numbers.items() if k in starts or k in lengths} for _ in range(40)]
    a, left = design_tables.varied(family.mechanism, family.model, numbers)
    b, also = design_tables.varied(family.mechanism, family.model, numbers, "numba")
    assert left == also and a.index.tolist() == b.index.tolist() and a.index.size >= 10
    np.testing.assert_allclose(b.q0, a.q0, rtol=0, atol=1e-12)
    for name, (body, S) in a.points.items():
        np.testing.assert_allclose(b.points[name][1], S, rtol=0, atol=1e-12)
    _tables_against_alone(b, [family(**x) for x in numbers])


def test_a_mechanisms_numbers_vary_without_a_mechanism_per_design_and_match_freudenstein():
    rng = np.random.default_rng(7)
    designs = _crank_rockers(rng, 12)
    family = Vary(_dimensioned_four_bar(1.0, 3.5, 3.5))
    numbers = [{"O2-O4": d["ground"], "O2-A": d["crank"], "A-B": d["coupler"], "O4-B": d["rocker"], "crank": d["start"]}
               for d in designs]
    study = sweep_designs(family, numbers, lambda x: x["crank"] + TH, 1.3, 0.4)
    assert study.batched.all() and study.ok.all() and family.model is study.template
    col = lambda k: np.array([d[k] for d in designs])[:, None]  # noqa: E731
    cf = oracles.freudenstein(col("ground"), col("crank"), col("coupler"), col("rocker"), col("start") + TH)
    B = cf["C"] + np.stack([col("coupler") * np.cos(cf["th3"]), col("coupler") * np.sin(cf["th3"])], -1)
    np.testing.assert_allclose(study.position("B"), B, rtol=0, atol=1e-12)
    for d in (0, 5, 11):
        alone = family(**numbers[d]).compile().sweep(numbers[d]["crank"] + TH, 1.3, 0.4)
        np.testing.assert_allclose(study.q[d], alone.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(study.qdd[d], alone.qdd, rtol=0, atol=1e-9)
    with pytest.raises(planar.InputError, match="no numbers of mechanism"):
        sweep_designs(family, {"O2-B": [1.0]}, TH)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(0.3, 5.0), st.floats(0.3, 5.0), st.floats(0.3, 5.0), st.floats(-np.pi, np.pi),
                          st.floats(-1.5, 1.5), st.floats(-1.5, 1.5), st.booleans()), min_size=1, max_size=6),
       st.booleans())
@pytest.mark.parametrize("engine", ENGINES)
def test_any_batch_of_designs_with_coupler_points_is_each_design_swept_alone(engine, rows, numbers):
    """Random four-bars with coupler points, either assembly mode, regular or not (some cannot
    be assembled, some meet limits or branch events), from the builder or as a dimensioned
    mechanism's numbers, on either engine: the batch reports what each design swept alone
    does."""
    U = np.linspace(-1.0, 1.0, 21)
    if numbers:
        build = Vary(_dimensioned_four_bar(1.0, 3.5, 3.5))
        designs = [{"O2-A": a, "A-B": b, "O4-B": c, "crank": s} for a, b, c, s, *_ in rows]
        start = "crank"
    else:
        build = four_bar
        designs = [dict(crank=a, coupler=b, rocker=c, start=s, coupler_point=(p, q), crossed=x)
                   for a, b, c, s, p, q, x in rows]
        start = "start"
    try:
        study = sweep_designs(build, designs, lambda d: d[start] + U, engine=engine)
    except planar.InputError as e:  # no design assembles
        assert "no design could be built" in str(e)
        return
    for d, design in enumerate(designs):
        try:
            alone = build(**design).compile().sweep(design[start] + U)
        except planar.PlanarError:
            assert study[d] is None and study.errors[d] is not None
            assert (study.status[d] == planar.Status.NOT_ASSEMBLABLE).all()
            continue
        np.testing.assert_array_equal(study.status[d], alone.status)
        assert len(study.events[d]) == len(alone.events)
        ok = POSED[alone.status]
        np.testing.assert_allclose(study.q[d][ok], alone.q[ok], rtol=0, atol=1e-11)
        if not numbers:
            np.testing.assert_allclose(study.position("C")[d][ok], alone.position("C")[ok], rtol=0, atol=1e-11)


def test_designs_of_other_structures_and_points_some_designs_lack():
    ds = [dict(crank=1.0), dict(crank=1.2, coupler_point=(1.0, 0.5)), dict(crank=1.1),
          dict(crank=1.3, coupler_point=(1.0, 0.0)), dict(crank=0.3, rocker=0.2)]
    study = sweep_designs(four_bar, ds, TH, fixed=dict(ground=4.0, coupler=3.5))
    assert study.batched.tolist() == [True, True, True, True, False] and study.errors[4] is not None
    C = study.position("C")
    assert np.isnan(C[[0, 2, 4]]).all()
    for d in (0, 1, 2, 3):
        alone = four_bar(ground=4.0, coupler=3.5, **ds[d]).sweep(TH)
        np.testing.assert_allclose(study.q[d], alone.q, rtol=0, atol=1e-12)
        if d in (1, 3):
            np.testing.assert_allclose(C[d], alone.position("C"), rtol=0, atol=1e-12)
