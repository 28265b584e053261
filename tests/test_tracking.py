"""Poses on demand: sweeps from the nearest known pose and the tracker give what the sweep from
the sketch gives (statuses, events, poses to 1e-12), on the branch, past limits and through
bifurcations, for any order of moves."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planar import Status
from planar.mechanisms import four_bar, gear_train, slider_crank
from planar.tracking import CAP

MECHANISMS = {
    "four-bar": lambda: four_bar(coupler_point=(1.0, 0.5)),
    "slider-crank": lambda: slider_crank(2, 5, offset=1),
    "gear train": lambda: gear_train((1.0, 2.0, 1.5)),  # gear 2 turns half as fast: u + 2 pi is another pose
    # 96.67..166.71 deg on the branch drawn (and 193.29..263.33 in the other mode)
    "crank-rocker by its rocker": lambda: four_bar(4, 2, 3, 3.5, driver="rocker", start=2.0),
    "triple rocker": lambda: four_bar(4, 3, 3, 2.5),  # limit at 1.7913
    "rocking slider-crank": lambda: slider_crank(3, 2.5, offset=0.2, start=0.3),  # -0.8736..1.1198
    "parallelogram": lambda: four_bar(4, 2, 4, 2, start=0.5, crossed=True),  # change points at 0 and pi
    # (a fuzz of tracker moves) two intervals a turn, [-2.0256, -0.0608] and [1.3047, 3.2695]
    "two intervals a turn": lambda: four_bar(3.3945447384494383, 5.750519882703604, 5.925034614526665,
                                             2.7283713165286407, frame_angle=-2.519667741128898, crossed=True,
                                             start=-1.333203408382447),
}


def _same(got, want):
    """Same statuses, events (kind, index, input) and poses to 1e-12 (rates to 1e-9)."""
    assert got.status.tolist() == want.status.tolist()
    assert [(e.kind, e.index) for e in got.events] == [(e.kind, e.index) for e in want.events]
    for a, b in zip(got.events, want.events):
        assert np.allclose(a.input, b.input, atol=1e-9, rtol=0)
    np.testing.assert_allclose(got.q, want.q, atol=1e-12, rtol=0)
    np.testing.assert_allclose(got.qd, want.qd, atol=1e-9, rtol=1e-9)
    np.testing.assert_allclose(got.qdd, want.qdd, atol=1e-8, rtol=1e-8)


def _from_sketch(name, values, **options):
    """The sweep of a model that knows no pose but its sketch."""
    return MECHANISMS[name]().compile().sweep(values, **options)


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_tracker_moves_equal_sweeps_from_the_sketch(name):
    model = MECHANISMS[name]().compile()
    tracker = model.track()
    assert tracker.pose is None
    moves = [1.0, 1.05, 2.5, 1.6, 1.9, 2.2, 3.0, -0.7, 7.0, 6.9, 13.0, 2.4, 1.7, 1.8]
    for u in moves:
        res = tracker.move(u)
        assert res.q.shape[0] == 1 and tracker.pose is res
        _same(res, _from_sketch(name, [u]))


@pytest.mark.parametrize("name", sorted(MECHANISMS))
@pytest.mark.filterwarnings("error")  # (a value on the parallelogram's change point: no RuntimeWarning)
def test_warm_sweeps_equal_sweeps_from_the_sketch(name):
    model = MECHANISMS[name]().compile()
    model.sweep([2.0, 5.0])
    tracker = model.track()
    tracker.move(4.0)
    for U in (np.linspace(0, 2 * np.pi, 10), np.linspace(3.0, 3.0 + 2 * np.pi, 100), np.linspace(8.0, -1.0, 37)):
        _same(model.sweep(U), _from_sketch(name, U))


def test_a_sweep_past_the_known_poses_of_a_branch_with_limits_is_made_once(monkeypatch):
    # a warm sweep that meets a limit is made again from the sketch (past a limit the way on
    # depends on the whole walk); once a sweep of the branch has met one, sweeps past the known
    # poses start from the sketch: each of them was made twice, for 1.5-2x the cost
    import functools

    import planar.sweep

    model = MECHANISMS["triple rocker"]().compile()
    model.sweep(np.linspace(0.0, 2.5, 30))  # (past the limit at 1.7913)
    runs = []
    real = planar.sweep.run_sweep

    @functools.wraps(real)  # (its signature names the sweep's options)
    def counted(*args, **kw):
        runs.append(1)
        return real(*args, **kw)

    monkeypatch.setattr(planar.sweep, "run_sweep", counted)
    # (the first value's nearest known pose is not the sketch's)
    for U in (np.linspace(1.6, 2.4, 41), np.r_[1.5, np.random.default_rng(0).permutation(np.linspace(-3.0, 3.0, 61))]):
        runs.clear()
        res = model.sweep(U)
        assert len(runs) == 1
        _same(res, _from_sketch("triple rocker", U))


def test_beyond_a_limit_stays_unassemblable_and_moving_back_works():
    model = MECHANISMS["crank-rocker by its rocker"]().compile()
    tracker = model.track()
    lo, hi = np.radians([96.6654, 166.7088])
    inside = tracker.move(np.radians(120.0))
    assert inside.status[0] == Status.SOLVED
    for u in (hi + 0.05, hi + 0.3, lo - 0.3, hi + 0.01):
        res = tracker.move(u)
        assert res.status[0] == Status.NOT_ASSEMBLABLE and not res.ok[0]
        assert [e.kind for e in res.events] == ["limit"]
    back = tracker.move(np.radians(150.0))
    assert back.status[0] == Status.SOLVED
    _same(back, _from_sketch("crank-rocker by its rocker", [np.radians(150.0)]))


@pytest.mark.parametrize("name, out, back, beyond", [
    ("triple rocker", (1.85, 2.2, 3.0), [2.5, 1.8, 3.0, 2.0], 3.2),
    ("rocking slider-crank", (1.2, 2.0), [1.5, 1.8, 1.13], 2.01),  # (a slider: not geared)
    # past the second limit a walk from the sketch meets (3.2695, after the gap from -0.0608)
    ("two intervals a turn", (3.6, 4.2), [3.5, 3.9, 3.3, 4.1], 4.25),
])
def test_moves_back_into_a_stretch_past_a_limit_that_holds_nothing_run_no_sweep(monkeypatch, name, out, back, beyond):
    # a rocker dragged past its limit (the triple rocker's at 1.7913): each move out is a sweep
    # from the sketch, whose search past the limit finds nothing up to the value, in any modes;
    # a move back into that stretch is that sweep's result with its own gap (least squares from
    # the limit's pose), not a sweep again (~100 ms each; past a second limit ~300 ms, and the
    # limits equal to rounding)
    import functools

    import planar.sweep

    model = MECHANISMS[name]().compile()
    tracker = model.track()
    for u in out:
        tracker.move(u)
    runs = []
    real = planar.sweep.run_sweep

    @functools.wraps(real)
    def counted(*args, **kw):
        runs.append(1)
        return real(*args, **kw)

    monkeypatch.setattr(planar.sweep, "run_sweep", counted)
    moves = [tracker.move(u) for u in back]
    assert not runs and not tracker.direct
    monkeypatch.undo()
    for u, res in zip(back, moves):
        want = _from_sketch(name, [u])
        assert res.status[0] == Status.NOT_ASSEMBLABLE
        _same(res, want)
        np.testing.assert_allclose(res.gap, want.gap, rtol=1e-4)
        np.testing.assert_allclose(res.nearest_limit, want.nearest_limit, atol=1e-9, rtol=0)
    # (past the stretch searched: a sweep)
    _same(tracker.move(beyond), _from_sketch(name, [beyond]))


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_a_geared_linkage_remembers_no_stretch_past_a_limit_as_holding_nothing(engine):
    # (found by a fuzz of tracker moves) a geared five-bar closes in its modes on many
    # stretches, far apart: the sweep of -2.151 found nothing past the limit at -1.9975 at its
    # search's steps, but -2.137 swept alone enters a stretch (least squares from the sketch's
    # pose lands there). Least squares cannot tell that no stretch reaches a value: each move
    # there is its own sweep.
    from planar.mechanisms import geared_five_bar

    def build():
        return geared_five_bar(13.6016, 8.6520, 7.3942, 12.8716, start=-1.5954)

    model = build().compile()
    tracker = model.track(engine=engine)
    assert tracker.move(-2.151).status[0] == Status.NOT_ASSEMBLABLE
    assert not model.known_poses[("smooth", 1e-12)].bare
    want = build().compile().sweep([-2.137], engine=engine)
    assert want.status[0] == Status.SOLVED
    _same(tracker.move(-2.137), want)


@pytest.mark.parametrize("engine", ["numpy", pytest.param("numba", marks=pytest.mark.numba)])
def test_values_past_a_close_approach_are_not_reached_from_poses_learned_past_it(engine):
    # (found by a fuzz of tracker moves) a geared five-bar with a limit pair 1.4e-6 apart at
    # -3.8766: the sweep of a turn steps over it (a near_singular event), the sweep of one
    # value at -5.96 from the sketch meets the limits. The poses past the close approach are
    # not learned, so the move is the sweep from the sketch, not a step from the turn's pose.
    def build():
        from planar.mechanisms import geared_five_bar

        return geared_five_bar(ground=19.128453614447388, gear_radius_2=8.429099894103178,
                               gear_radius_4=9.280480566143305, link_5=16.996051107697404, crossed=True,
                               start=-1.6216414602953408)

    model = build().compile()
    turn = model.sweep(model.u0[0] - np.linspace(0, 2 * np.pi, 60), engine=engine)
    assert [e.kind for e in turn.events] == ["near_singular"]
    u = -5.959109614199423
    want = build().compile().sweep([u], engine=engine)
    assert [e.kind for e in want.events] == ["limit", "near_singular"]
    tracker = model.track(engine=engine)
    _same(tracker.move(u), want)
    assert not tracker.direct


def test_a_pose_a_turn_on_is_another_pose():
    model = MECHANISMS["gear train"]().compile()
    tracker = model.track()
    a, b = tracker.move(1.0), tracker.move(1.0 + 2 * np.pi)
    assert abs(b.angle("gear2")[0] - a.angle("gear2")[0] + np.pi) < 1e-12  # half a turn the other way
    assert abs(tracker.move(1.0).angle("gear2")[0] - a.angle("gear2")[0]) < 1e-12


def test_values_a_rocking_input_reaches_by_whole_periods_are_not_remembered():
    """A crank that rocks (its rocker is the shortest link) reaches values whole turns on from
    the sketch only by a jump: a model that has swept them, in any order, remembers none of
    them, and its later sweeps stay those from the sketch."""
    rocking = lambda: four_bar(0.6258855, 3.0296554, 3.04322927, 0.5518215, start=2.54985073)  # noqa: E731
    model, u0 = rocking().compile(), 2.54985073
    far = u0 + 0.01 + 6 * np.pi
    for values in ([far, u0, u0 + 0.005], [u0, far, u0 + 0.005], [u0, far, far + 0.01], [far + 0.02]):
        _same(model.sweep(values), rocking().compile().sweep(values))
        assert np.all(np.abs(model.known_poses[("smooth", 1e-12)].u - u0) < 1)


@pytest.mark.parametrize("branch", ["smooth", "other"])
def test_each_branch_option_knows_its_own_poses(branch):
    model = MECHANISMS["parallelogram"]().compile()
    model.sweep(np.linspace(0.5, 7.0, 50), branch="smooth")
    model.sweep(np.linspace(0.5, 7.0, 50), branch="other")
    tracker = model.track(branch=branch)
    for u in (3.5, 4.0, 6.0, 0.2):
        _same(tracker.move(u), _from_sketch("parallelogram", [u], branch=branch))


def test_the_known_poses_stay_bounded():
    model = MECHANISMS["four-bar"]().compile()
    for k in range(5):
        model.sweep(k + np.linspace(0, 1, 1000))
    poses = model.known_poses[("smooth", 1e-12)]
    assert poses.u.size <= CAP + CAP // 2 + 1
    assert np.all(np.diff(poses.u) > 0) and model.u0[0] in poses.u
    tracker = model.track()
    _same(tracker.move(4.5), _from_sketch("four-bar", [4.5]))


def test_outputs_and_multi_input_models_sweep_as_from_the_sketch():
    model = MECHANISMS["four-bar"]().compile()
    model.sweep([3.0])
    _same(model.sweep([3.2], outputs=["rocker"]), _from_sketch("four-bar", [3.2], outputs=["rocker"]))
    from planar.mechanisms import open_chain

    chain = open_chain((5.0, 8.0), start=(0.3, 0.5)).compile()
    tracker = chain.track()
    for u in ([0.3, 0.2], [1.0, -0.5]):
        _same(tracker.move(u), open_chain((5.0, 8.0), start=(0.3, 0.5)).sweep(np.array([u])))


@settings(max_examples=12, deadline=None)
@given(name=st.sampled_from(["four-bar", "crank-rocker by its rocker", "triple rocker", "gear train"]),
       moves=st.lists(st.one_of(st.floats(-7.0, 14.0), st.floats(-0.08, 0.08)), min_size=1, max_size=6))
def test_random_moves_equal_sweeps_from_the_sketch(name, moves):
    """Moves of any size (small ones relative to the last value) give the sweep from the sketch."""
    model = MECHANISMS[name]().compile()
    tracker = model.track()
    u = 0.5
    for d in moves:
        u = u + d if abs(d) <= 0.08 else d
        _same(tracker.move(u), _from_sketch(name, [u]))


@settings(max_examples=25, deadline=None)
@given(name=st.sampled_from(sorted(MECHANISMS)),
       values=st.lists(st.one_of(st.floats(-1.0, 7.5), st.sampled_from([0.0, np.pi, 1.7913295877157296, 2.9096233]).map(
           lambda x: x + 1e-7)), min_size=1, max_size=40))
def test_random_values_of_a_swept_stretch_equal_sweeps_from_the_sketch(name, values):
    """Values in any order, repeated, on a stretch the model has swept (solved in one batch by
    the direct path where each is near a known pose), past its limits and next to its change
    points give the sweep from the sketch."""
    model = MECHANISMS[name]().compile()
    model.sweep(np.linspace(-1.0, 7.5, 200))
    U = np.array(values)
    _same(model.sweep(U), _from_sketch(name, U))
