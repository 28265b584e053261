"""The direct path (:func:`planar.tracking.direct`): poses near known poses, each in one walk
step of the sweep, equal the sweep from the sketch (statuses, events, poses to 1e-12, rates to
rounding) on every catalogue mechanism, near limits, change points and far from any known pose;
and it is taken where it applies (``tracker.direct``, and with the sweep made unavailable), for
one value and for many."""

import functools
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import planar.sweep
from planar import InputError, Status
from planar.mechanisms import CATALOGUE, four_bar, slider_crank
from planar.tracking import CAP

MECHANISMS = {name: build for name, build in CATALOGUE.items() if name != "open_chain"}  # (three inputs)
MECHANISMS.update({
    "triple rocker": lambda: four_bar(4, 3, 3, 2.5),  # limits at +-1.7913
    "crank-rocker by its rocker": lambda: four_bar(4, 2, 3, 3.5, driver="rocker", start=2.0),  # 1.6872..2.9096
    "parallelogram": lambda: four_bar(4, 2, 4, 2, start=0.5, crossed=True),  # change points at 0 and pi
    "slider-driven slider-crank": lambda: slider_crank(2, 5, offset=1, driver="slider", start=5.0),
})
# inputs where something happens: limits and change points (scaled by the input's unit below)
MARKS = {"triple rocker": (1.7913295877157296, -1.7913295877157296),
         "crank-rocker by its rocker": (1.6871538, 2.9096233), "parallelogram": (0.0, np.pi)}

_models, _references = {}, {}


def _model(name):
    if name not in _models:
        _models[name] = MECHANISMS[name]().compile()
    return _models[name]


def _reference(name, u, **options):
    """The sweep from the sketch of a model that knows no pose but its sketch."""
    key = (name, u, tuple(sorted(options.items())))
    if key not in _references:
        _references[key] = MECHANISMS[name]().compile().sweep([u], **options)
    return _references[key]


def _same(got, want):
    """Same statuses, events (kind, index, input), poses to 1e-12 (of the model's size L) and
    rates to rounding (of their conditioning)."""
    L = max(1.0, float(want.model.L))
    assert got.status.tolist() == want.status.tolist()
    assert [(e.kind, e.index) for e in got.events] == [(e.kind, e.index) for e in want.events]
    for a, b in zip(got.events, want.events):
        assert np.allclose(a.input, b.input, atol=1e-9, rtol=0)
    np.testing.assert_allclose(got.q, want.q, atol=1e-12 * L, rtol=0)
    np.testing.assert_allclose(got.singularity, want.singularity, atol=1e-12, rtol=0)
    np.testing.assert_array_equal(got.branch, want.branch)
    # rates next to a singular position amplify the poses' rounding by about 1 / singularity
    # (1e-6 from a triple rocker's limit: 8e-4, and 1.6e-10 of its rates): that much looser there
    sing = want.singularity[want.singularity > 0]  # (values with rates)
    c = max(1.0, 0.01 / float(np.min(sing, initial=1.0)))
    np.testing.assert_allclose(got.qd, want.qd, atol=1e-10 * c * L, rtol=1e-10 * c)
    np.testing.assert_allclose(got.qdd, want.qdd, atol=1e-9 * c**2 * L, rtol=1e-9 * c**2)
    for a in (got.q, got.qd, got.qdd, got.status):
        assert not a.flags.writeable


def _unit(model):
    return float(model.L) if model.input_lengths[0] else 1.0


@st.composite
def moves(draw):
    """A mechanism and moves: drags from the value before, values next to a known pose, near a
    limit or change point, and anywhere over two turns."""
    name = draw(st.sampled_from(sorted(MECHANISMS)))
    model = _model(name)
    u0, unit = float(model.u0[0]), _unit(model)
    marks = [u0 + unit * x for x in (0.3, 1.0, 2.5, -0.6)] + [unit * m for m in MARKS.get(name, ())]
    near = st.builds(lambda m, d: m + unit * d, st.sampled_from(marks),
                     st.sampled_from([0.0, 1e-9, -1e-6, 1e-3, -0.01, 0.05, -0.19, 0.3]))
    far = st.floats(u0 - 7 * unit, u0 + 14 * unit, allow_nan=False)
    drag = st.floats(-0.06, 0.06).map(lambda d: ("drag", d * unit))
    steps = draw(st.lists(st.one_of(near, far, drag), min_size=1, max_size=6))
    return name, steps


ENGINES = ["numpy", pytest.param("numba", marks=pytest.mark.numba)]


@pytest.mark.parametrize("engine", ENGINES)
@settings(max_examples=40, deadline=None)
@given(case=moves())
def test_moves_equal_the_sweep_from_the_sketch(engine, case):
    """Every move (by the direct path or by a sweep) gives the sweep from the sketch (of the
    same engine: next to a change point the engines may read a block's det, at rounding level,
    with other signs), and what a twin model that knows the same poses gives without the direct
    path."""
    name, steps = case
    model, twin = MECHANISMS[name]().compile(), MECHANISMS[name]().compile()
    for m in (model, twin):
        m.sweep(np.linspace(m.u0[0], m.u0[0] + 2 * np.pi * _unit(m), 40), engine=engine)
    tracker, twin_tracker = model.track(engine=engine), twin.track(engine=engine)
    u = float(model.u0[0])
    for s in steps:
        u = float(u + s[1]) if isinstance(s, tuple) else float(s)
        got = tracker.move(u)
        _same(got, _reference(name, u, engine=engine))
        with mock.patch("planar.tracking.Direct.__call__", return_value=None):
            _same(got, twin_tracker.move(u))


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_the_direct_path_is_taken_near_known_poses(name, engine, monkeypatch):
    """A warm model solves values near its known poses without a sweep: with run_sweep made to
    fail, tracker moves and one-value sweeps still give the sweep from the sketch (in either
    engine: the compiled one takes the direct path in one call of its loop)."""
    model = MECHANISMS[name]().compile()
    u0, unit = float(model.u0[0]), _unit(model)
    values = u0 + unit * np.array([0.02, 0.05, 0.051, 0.1, 0.13, 0.2, 0.25])
    references = {float(u): _reference(name, float(u), engine=engine) for u in values}
    model.sweep([u0 + 0.15 * unit], engine=engine)
    tracker = model.track(engine=engine)

    @functools.wraps(planar.sweep.run_sweep)  # (its options are read from its signature)
    def no_sweep(*args, **kwargs):
        raise AssertionError("the direct path fell back to a sweep")

    # many values at once, out of order and repeated, as a sweep of them from the sketch
    many = values[[3, 0, 6, 0, 2, 5, 1, 4]]
    reference = MECHANISMS[name]().compile().sweep(many, engine=engine)
    monkeypatch.setattr(planar.sweep, "run_sweep", no_sweep)
    for u in values:
        res = tracker.move(float(u))
        assert tracker.direct and tracker.pose is res
        _same(res, references[float(u)])
    _same(model.sweep([values[3]], engine=engine), references[float(values[3])])
    _same(model.sweep(many, engine=engine), reference)


@pytest.mark.parametrize("engine", ENGINES)
def test_a_sweep_over_a_stretch_the_model_has_swept_takes_the_direct_path(engine, monkeypatch):
    """100 values over a turn of a model that has swept that turn: one batch, no sweep, the
    sweep's results; with one value out of reach (past the known turn) all go to the sweep."""
    model = MECHANISMS["watt_six_bar"]().compile()
    u0 = float(model.u0[0])
    model.sweep(np.linspace(u0, u0 + 2 * np.pi, 200), engine=engine)
    values = np.linspace(u0, u0 + 2 * np.pi, 100)
    reference = MECHANISMS["watt_six_bar"]().compile().sweep(values, engine=engine)
    past = np.r_[values, u0 + 3 * np.pi]
    reference_past = MECHANISMS["watt_six_bar"]().compile().sweep(past, engine=engine)
    calls = []
    sweep = planar.sweep.run_sweep

    @functools.wraps(sweep)
    def counted(*args, **kwargs):
        calls.append(args[1].shape[0])
        return sweep(*args, **kwargs)

    monkeypatch.setattr(planar.sweep, "run_sweep", counted)
    _same(model.sweep(values, engine=engine), reference)
    assert not calls
    _same(model.sweep(past, engine=engine), reference_past)
    assert calls == [past.size]


@pytest.mark.numba
def test_the_engines_share_a_models_known_poses():
    """A model tracked by one engine, then the other: each takes the direct path from the
    poses the other learned, with the sweep's results (and the compiled loop keeps its one
    signature)."""
    from planar.compiled import engine

    model = MECHANISMS["watt_six_bar"]().compile()
    u0 = float(model.u0[0])
    for eng, u in (("numpy", u0 + 0.1), ("numba", u0 + 0.12), ("numpy", u0 + 0.14)):
        tracker = model.track(engine=eng)
        res = tracker.move(u)
        assert tracker.direct
        _same(res, _reference("watt_six_bar", u, engine=eng))
    assert len(engine._values.signatures) == 1


def test_values_it_cannot_certify_go_to_the_sweep():
    """Past a limit, through a change point and far from every known pose the tracker sweeps
    (``direct`` False), with the sweep's statuses and events."""
    name = "crank-rocker by its rocker"
    tracker = MECHANISMS[name]().compile().track()
    tracker.move(2.6)
    res = tracker.move(2.95)  # past the limit at 2.9096
    assert not tracker.direct and res.status[0] == Status.NOT_ASSEMBLABLE
    _same(res, _reference(name, 2.95))
    tracker.move(2.55)
    assert tracker.direct
    parallelogram = MECHANISMS["parallelogram"]().compile().track()
    parallelogram.move(0.3)
    parallelogram.move(0.2)
    parallelogram.move(0.12)
    assert parallelogram.direct
    _same(parallelogram.move(-0.05), _reference("parallelogram", -0.05))  # through the change point at 0
    assert not parallelogram.direct
    four = MECHANISMS["four_bar"]().compile().track()
    _same(four.move(3.0), _reference("four_bar", 3.0))
    assert not four.direct  # three radians from the sketch: walked by a sweep
    four.move(3.1)
    assert four.direct


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("options", [dict(velocity=2.5, acceleration=-4.0), dict(velocity=0.0, acceleration=3.0)])
def test_input_rates(options, engine):
    model = MECHANISMS["watt_six_bar"]().compile()
    tracker = model.track(engine=engine)
    for u in (0.05, 0.1, 0.12):
        res = tracker.move(u, **options)
        assert tracker.direct
        _same(res, MECHANISMS["watt_six_bar"]().compile().sweep([u], **options, engine=engine))


@pytest.mark.parametrize("options", [dict(rates=False), dict(tol=1e-10, max_step=0.02), dict(branch="other")])
def test_tracker_options(options):
    model = MECHANISMS["four_bar"]().compile()
    tracker = model.track(**options)
    for u in (0.03, 0.05, 0.06):
        res = tracker.move(u)
        assert tracker.direct
        _same(res, _reference("four_bar", u, **options))
    if options.get("rates") is False:
        assert np.isnan(res.qd).all() and np.isnan(res.qdd).all()


def test_many_moves_keep_the_known_poses_bounded():
    model = _model("four_bar")
    tracker = model.track()
    for u in np.linspace(0.0, 1.0, 3 * CAP):
        tracker.move(float(u))
    poses = model.known_poses[("smooth", 1e-12)]
    assert poses.u.size <= 2 * CAP and model.u0[0] in poses.u
    assert tracker.direct
    _same(tracker.move(0.5), _reference("four_bar", 0.5))


@pytest.mark.parametrize("options", [dict(branch="left"), dict(engine="fortran")])
def test_options_the_sweep_refuses_are_refused(options):
    model = _model("four_bar")
    with pytest.raises(InputError):
        model.track(**options).move(float(model.u0[0]) + 0.01)
    with pytest.raises(InputError):
        model.sweep([float(model.u0[0])], **options)
