"""Sweeps of random linkages: never garbage, never lost work, random inputs, invariances.

Every point a sweep returns either satisfies the constraints to tolerance or carries a status
that says why not (and is NaN); no numpy warning escapes; results are deterministic and move,
scale and rename with the sketch.
"""

import warnings

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import planar
from planar.results import POSED
from tests.strategies import build, linkages

offsets = st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=12)


def sweep(m, du, **kw):
    """Sweep the crank through u0 + du, turning numpy warnings into errors."""
    model = m.compile()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return m.sweep(model.u0[0] + np.asarray(du), **kw)
        except planar.AssemblyError as e:
            assert "singular position" in str(e)
            assume(False)  # a sketch drawn on a singular position is refused by name


def compiled(desc, **kw):
    try:
        m, pins = build(desc, **kw)
        m.compile()
    except planar.PlanarError:
        assume(False)  # a degenerate draw refused with a named error is the right answer
    return m, pins


@given(desc=linkages(), du=offsets)
@example(  # found by CI: a sketch on a singular pose got branch rates but kept status SINGULAR
    desc={"pivot": (2.5, 2.0830435124069506), "crank_tip": (0.0, 0.0),
          "dyads": [("RRP", 1, (0.0, 0.0), (1.0, 0.0), 0, (0.0, 0.0), 0.0),
                    ("RRP", 3, (0.0, 0.0), (0.0, -2.8984375), 0, (0.0, 0.0), 1.0945403947470475e-17)]},
    du=[0.0, 1.0])
@example(  # found by the long run: a RuntimeWarning from the batched walk at a singular sketch
    desc={"pivot": (2.215542766431805e-213, 0.0), "crank_tip": (0.0, 0.0),
          "dyads": [("RRP", 0, (0.0, 0.0), (0.0, 1.0), 1, (0.0, 0.0), 0.0)]},
    du=[0.0])
@example(  # found by a long run: a near-singular value (singularity 1.8e-8) swept warm 1.8e-6 apart
    desc={"pivot": (0.0, -1.7925068282315482), "crank_tip": (0.0, 0.0),
          "dyads": [("RRP", 0, (0.0, 0.0), (0.0, 3.0), 1, (0.0, 0.0), 1e-09)]},
    du=[4.74030107763473e-266])
@example(  # found by CI: Newton from afar counted an angle 2e8 turns on, holding its rows to 3e-8
    desc={"pivot": (1.6669682684370963e-19, 0.2654188828979489),
          "crank_tip": (-1.2039044416568588e-53, 1.2249852956909209),
          "dyads": [("RRR", 1, (-2.2871660248524564e-08, -0.6005463486207301), (-0.12891180130484958, 0.3462541477137231),
                     0, (1.467940444387958, -2.4329722094474606), 1.3),
                    ("RRP", 1, (-8.435452203261473e-12, -2.245192510818507), (-1.2559926735274952e-255, -1.3116837858684183),
                     2, (-1.3181370971067814, 1.4800863420125303), 0.07565548249853234)]},
    du=[1.601450410972273, -2.3200459043526163, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.6840582710449397])
def test_random_linkages_never_return_garbage(desc, du):
    never_garbage(desc, du)


@settings(max_examples=20)
@given(desc=linkages(max_dyads=2, rolling=True), du=offsets)
def test_random_rolling_linkages_never_return_garbage(desc, du):
    """The same of linkages with a loop closed by a gear or a rack (a geared linkage closes in
    the same modes at many poses, far apart)."""
    never_garbage(desc, du)


def never_garbage(desc, du):
    m, pins = compiled(desc)
    res = sweep(m, du, velocity=1.3, acceleration=-0.4)
    model = m.compile()
    st_ = res.status
    valid_pos = POSED[st_]  # SOLVED .. SINGULAR and LIMIT: positions valid
    q = res.q[valid_pos]
    if q.size:
        Phi, _ = model.system.evaluate(q, res.inputs[valid_pos])
        assert np.max(np.abs(Phi * model.row_scale)) < 1e-9
    assert np.all(np.isnan(res.q[~valid_pos]))
    assert np.all(np.isfinite(res.qd[res.ok])) and np.all(np.isfinite(res.qdd[res.ok]))
    assert np.all(np.isnan(res.qd[~res.ok]))
    # the velocity solution satisfies the velocity equations
    if res.ok.any():
        _, J = model.system.evaluate(res.q[res.ok], res.inputs[res.ok])
        rows = model.active_rows
        lhs = np.einsum("nij,nj->ni", J[:, rows], res.qd[res.ok])
        nu = np.zeros_like(lhs)
        nu[:, model.driver_rows_active] = 1.3
        assert np.max(np.abs((lhs - nu) * model.row_scale[rows])) < 1e-8 * (1 + np.abs(res.qd[res.ok]).max())
    # determinism: the same sweep of the same mechanism is the same to the bit; swept again by
    # the model that knows these poses now (it starts from the nearest), the same to rounding
    again = sweep(compiled(desc)[0], du, velocity=1.3, acceleration=-0.4)
    for a, b in ((res.q, again.q), (res.qd, again.qd), (res.status, again.status)):
        np.testing.assert_array_equal(a, b)
    warm = sweep(m, du, velocity=1.3, acceleration=-0.4)
    np.testing.assert_array_equal(warm.status, res.status)
    # (to the tolerance times the condition: a random linkage may be close to singular, where a
    # pose is known to about the tolerance over the singularity measure)
    cond = np.maximum(1.0, 1e-3 / np.where(res.singularity > 0, res.singularity, 1.0))
    err = np.where(np.isnan(warm.q) & np.isnan(res.q), 0.0, np.abs(warm.q - res.q))
    assert np.all(err <= 1e-9 * max(1.0, model.L) * cond[:, None]), (err.max(), res.singularity)


tracker_moves = st.lists(st.one_of(st.floats(-4.0, 4.0), st.tuples(st.just("drag"), st.floats(-0.08, 0.08)),
                                   st.tuples(st.just("step"), st.floats(-0.6, 0.6))), min_size=1, max_size=6)


@settings(max_examples=25)
@given(desc=linkages(), warm=st.sampled_from([None, 2 * np.pi, 3.0]), moves=tracker_moves)
def test_tracker_moves_equal_the_sweep_of_each_value_alone(desc, warm, moves):
    """On a model that knows no pose, or has swept a turn or values on both sides of its
    sketch, each move (a drag or step from the value before, or a jump from the sketch's)
    gives what a fresh model's sweep of that value gives: the same error, or the same
    statuses, poses and events but near_singular ones (a walk that needs the tracer, from a
    near-singular sketch, may report an avoided crossing where a move from a pose known
    nearer does not: docs/sweeps.md)."""
    moves_as_sweeps(desc, warm, moves)


@settings(max_examples=10)
@given(desc=linkages(max_dyads=2, rolling=True), warm=st.sampled_from([None, 2 * np.pi, 3.0]), moves=tracker_moves)
def test_tracker_moves_on_rolling_linkages_equal_the_sweep_of_each_value_alone(desc, warm, moves):
    moves_as_sweeps(desc, warm, moves)


def moves_as_sweeps(desc, warm, moves):
    m, _ = compiled(desc)
    model = m.compile()
    u0 = float(model.u0[0])
    try:
        if warm is not None:
            model.sweep(u0 + np.linspace(-warm / 2 if warm == 3.0 else 0.0, warm, 25))
    except planar.AssemblyError:
        assume(False)  # (a sketch on a singular position: refused by name, as above)
    tracker, u = model.track(), u0
    L = max(1.0, float(model.L))
    for s in moves:
        u = u + s[1] if isinstance(s, tuple) else u0 + s
        alone = compiled(desc)[0].compile()
        try:
            want = alone.sweep([u])
        except planar.PlanarError as e:
            with pytest.raises(type(e)):
                tracker.move(u)
            return
        got = tracker.move(u)
        assert got.status.tolist() == want.status.tolist()
        events = [[e.kind for e in r.events if e.kind != "near_singular"] for r in (got, want)]
        assert events[0] == events[1]
        cond = max(1.0, 1e-3 / want.singularity[0]) if want.singularity[0] > 0 else 1.0
        np.testing.assert_allclose(got.q, want.q, atol=1e-9 * L * cond, rtol=0)


def matched(desc, du, **kw):
    a, pins = compiled(desc)
    b, _ = compiled(desc, **kw)
    ra = sweep(a, du)
    assume(ra.ok.all() and np.all(ra.singularity > 1e-4))
    # the invariances are of regular branches: at a singular position met on the way (or drawn
    # in the sketch) which branch goes on is decided by rounding, and past a limit the sweep
    # re-enters the range by a search (least squares, then the way round through a limit)
    # whose outcome may differ with rounding (both found by the long run)
    assume(not ra.events)
    return ra, b, pins


@given(desc=linkages(), du=st.lists(st.floats(-0.5, 0.5), min_size=1, max_size=6),
       rotate=st.floats(-np.pi, np.pi), shift=st.tuples(st.floats(-50, 50), st.floats(-50, 50)))
@example(  # found by the long run: a RuntimeWarning from the modes of a diverged re-entry
    desc={"pivot": (-1.7906598513388094, 0.0), "crank_tip": (0.0, 0.0),
          "dyads": [("RRR", 0, (1e-14, 0.0), (1.0, 0.0), 1, (0.0, 0.0), 0.0),
                    ("RRR", 0, (0.0, 0.0), (0.0, 1.0), 1, (1.0, 0.0), 0.0),
                    ("RRR", 0, (0.0, 0.0), (0.0, 1.0), 1, (3.0, 0.0), 0.0)]},
    du=[4.951801075642734e-104], rotate=0.0, shift=(0.0, 0.0))
@example(  # a reference line drawn along -x: its angle is pi or -pi by rounding
    desc={"pivot": (0.0, 3.0), "crank_tip": (0.0, 0.0),
          "dyads": [("RRP", 0, (2.125, 1.0), (2.125, 0.0), 1, (0.0, 0.0), 3.125),
                    ("RRP", 2, (0.0, -1.625), (0.0, 0.0), 1, (0.0, 0.0), 2.6875)]},
    du=[0.5], rotate=0.0, shift=(0.0, 38.0))
def test_rigid_motion_of_the_sketch_moves_the_results(desc, du, rotate, shift):
    ra, b, pins = matched(desc, du, rotate=rotate, shift=shift)
    rb = sweep(b, du)
    assert rb.ok.all()
    R = np.array([[np.cos(rotate), -np.sin(rotate)], [np.sin(rotate), np.cos(rotate)]])
    for p in pins + ["tip"]:
        np.testing.assert_allclose(rb.position(p), ra.position(p) @ R.T + shift, atol=1e-9 * (1 + np.abs(shift).max()))
        np.testing.assert_allclose(rb.velocity(p), ra.velocity(p) @ R.T, atol=1e-8 * (1 + np.abs(ra.velocity(p)).max()))
    turn = (rb.angle("b1") - ra.angle("b1") - rotate + np.pi) % (2 * np.pi) - np.pi  # a line on +-pi may wrap
    np.testing.assert_allclose(turn, 0, atol=1e-12)


@given(desc=linkages(), du=st.lists(st.floats(-0.5, 0.5), min_size=1, max_size=6), exponent=st.floats(-3, 3))
@example(desc={"pivot": (0.0, 0.0), "crank_tip": (0.0, 0.0),
               "dyads": [("RRR", 0, (0.25, 0.875), (0.0, 0.953125), 1, (3.0, 0.0), 0.0),
                         ("RRR", 0, (0.0, 0.0), (0.25, 0.875), 2, (1.0, 0.0), 0.0)]},
         du=[0.0], exponent=1.0)
def test_uniform_scale_scales_positions_and_keeps_angles(desc, du, exponent):
    scale = 10.0**exponent
    ra, b, pins = matched(desc, du, scale=scale)
    rb = sweep(b, du)
    assert rb.ok.all()
    # rounding in accelerations is relative to the linkage's largest one, not each point's (a
    # point at rest beside one accelerating at 1e8 carries noise of 1e-8; found by the long run)
    acc = max(np.abs(ra.acceleration(p)).max() for p in pins + ["tip"])
    for p in pins + ["tip"]:
        np.testing.assert_allclose(rb.position(p) / scale, ra.position(p), atol=1e-10)
        np.testing.assert_allclose(rb.acceleration(p) / scale, ra.acceleration(p), atol=1e-8 * (1 + acc))
    for k in range(1, len(m_bodies(b))):
        np.testing.assert_allclose(rb.angle(f"b{k}"), ra.angle(f"b{k}"), atol=1e-10)


def m_bodies(m):
    return m.compile().body_names


@given(desc=linkages(), du=st.lists(st.floats(-0.5, 0.5), min_size=1, max_size=6), data=st.data())
def test_renaming_bodies_changes_nothing(desc, du, data):
    n = 2 + 2 * len(desc["dyads"])
    perm = data.draw(st.permutations(range(1, n)))
    names = {0: "ground", **{k: f"body_{perm[k - 1]}" for k in range(1, n)}}
    ra, b, pins = matched(desc, du, names=names)
    rb = sweep(b, du)
    np.testing.assert_array_equal(rb.status, ra.status)
    for p in pins + ["tip"]:
        np.testing.assert_allclose(rb.position(p), ra.position(p), atol=1e-12)
    for k in range(1, n):
        np.testing.assert_allclose(rb.omega(names[k]), ra.omega(f"b{k}"), atol=1e-9 * (1 + np.abs(ra.omega(f"b{k}")).max()))
