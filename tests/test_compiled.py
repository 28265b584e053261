"""The compiled path (engine="numba") against the numpy path, on mechanisms that use every joint
type between them: the same poses, rates and statuses (to rounding: numba's tan and numpy's
differ in the last bit), the same events. The scalar kernels are checked against the numpy
kernels joint by joint in tests/test_joints.py.
"""

import sys

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import planar
from planar import compiled
from planar.blocks import plan
from planar.errors import InputError
from planar.mechanisms import four_bar, geared_five_bar, rolling_wheel, slider_crank
from planar.sweep.anchors import quintic
from tests.strategies import build, point
from tests.test_sweep_closed_forms import geared_five_bar as general_geared_five_bar

N = 2000  # enough values that the bulk of them goes through the batch step


def scotch_yoke():
    """A crank pin in a vertical slot of a yoke that slides along x: x_yoke = r cos(theta)."""
    m = planar.Mechanism("scotch yoke")
    crank, yoke = m.add_body("crank"), m.add_body("yoke")
    m.add_revolute("O", m.ground, crank, at=(0, 0))
    m.add_prismatic("guide", m.ground, yoke, at=(1.5, -2.0), direction=(1, 0))
    m.add_slot("pin", yoke, crank, at=(1.5, 0.0), direction=(0, 1))
    m.drive("O")
    return m


CASES = {
    # name: (builder, input values) -- the joint types each one adds
    "four-bar triple rocker (limits)": (lambda: four_bar(4.0, 3.0, 3.0, 2.5), np.linspace(0, 2 * np.pi, N)),
    "slider-driven slider-crank (Prismatic, TravelDriver)":
        (lambda: slider_crank(2, 5, offset=1, driver="slider"), np.linspace(4.9, 3.2, N)),
    "scotch yoke (Slot)": (scotch_yoke, np.linspace(0, 4 * np.pi, N)),
    "geared five-bar (CarrierGear)": (geared_five_bar, np.radians(np.linspace(0, 200, N))),
    "geared five-bar, general gear (Gear)":
        (lambda: general_geared_five_bar(8, 3, 3.5, 6, general=True), np.radians(np.linspace(0, 200, N))),
    "wheel inside a ring (RollingContact)": (lambda: rolling_wheel(1.0, track_radius=4.0), np.linspace(0, 9, N)),
    "wheel driven by its centre (RackPinion, CoordinateDriver)":
        (lambda: rolling_wheel(1.0, driver="centre"), np.linspace(0, 5, N)),
}


def assert_same_sweeps(model, values):
    """The numpy and numba engines give the same statuses, events, poses and rates: to 1e-12
    where the Jacobian is well conditioned; near a singular position (singularity s below 0.1)
    rounding grows like 1 / s in the poses, 1 / s^2 in the velocities and 1 / s^3 in the
    accelerations, and so does the tolerance."""
    a = model.sweep(values, velocity=1.3, acceleration=-0.4, engine="numpy")
    b = model.sweep(values, velocity=1.3, acceleration=-0.4, engine="numba")
    assert np.array_equal(a.status, b.status)
    assert [(e.kind, e.index) for e in a.events] == [(e.kind, e.index) for e in b.events]
    ok = a.ok
    scale = np.tile([model.L, model.L, 1.0], model.n // 3)
    growth = 0.1 / np.clip(a.singularity[ok], 1e-6, 0.1)
    for power, (x, y) in enumerate(((a.q, b.q), (a.qd, b.qd), (a.qdd, b.qdd)), 1):
        assert np.array_equal(np.isnan(x), np.isnan(y))
        big = 1.0 + np.nanmax(np.abs(x[ok]) / scale, initial=0.0)
        assert np.all(np.abs(x[ok] - y[ok]) / scale <= 1e-12 * big * growth[:, None] ** power)
    return a


@pytest.mark.numba
@pytest.mark.parametrize("name", CASES)
def test_compiled_sweep_equals_the_numpy_sweep(name):
    build_case, values = CASES[name]
    a = assert_same_sweeps(build_case().compile(), values)
    assert a.ok.sum() > N // 2


@st.composite
def dyad_linkages(draw, kind):
    """A crank and one dyad from the ground to it (a four-bar for RRR, a slider-crank for RRP),
    its points drawn apart: one plan structure, so one compiled loop, for every draw."""
    pts = [draw(point) for _ in range(5)]
    assume(min(np.hypot(p[0] - r[0], p[1] - r[1]) for k, p in enumerate(pts) for r in pts[k + 1:]) > 0.05)
    pivot, tip, x, j, y = pts
    return {"pivot": pivot, "crank_tip": tip, "dyads": [(kind, 0, x, j, 1, y, draw(st.floats(0.1, 3.0)))]}


@pytest.mark.numba
@settings(max_examples=40)
@given(desc=st.sampled_from(["RRR", "RRP"]).flatmap(dyad_linkages))
@example(  # found by this test: a triple rocker, rates next to its limits (s ~ 0.006) agreed to 3e-12
    desc={"pivot": (0.0, 0.0), "crank_tip": (0.0, 1.0), "dyads": [("RRR", 0, (0.0, 0.25), (1.0, -1.0), 1, (-2.0, 1.0), 1.0)]})
@example(  # found by this test: the last value 1.6e-5 from a singular position, velocities of 2.6e4 agreeing
    # to 5e-8 of themselves (220 times the rounding where the Jacobian is well conditioned)
    desc={"pivot": (0.0, 1.0), "crank_tip": (0.0, 2.0), "dyads": [("RRR", 0, (2.0, 0.0001), (0.0, 0.0), 1, (1.0, 0.0), 1.0)]})
def test_compiled_sweeps_of_random_dimensions_equal_the_numpy_sweeps(desc):
    m, _ = build(desc)
    try:
        model = m.compile()
    except planar.PlanarError:
        assume(False)  # a degenerate draw, refused with a named error
    assert_same_sweeps(model, model.u0[0] + np.linspace(0, 2 * np.pi, 600))


@pytest.mark.numba
def test_every_structure_runs_on_one_compiled_loop():
    # every call of the loop (final steps, anchors' Newton, the bulk pass, with and without
    # rates) of any mechanism passes the same types: one machine-code specialisation, compiled
    # once, not one per structure or use
    from planar.compiled import engine

    for model in (four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8)).compile(), geared_five_bar().compile(),
                  slider_crank(2, 5, offset=1, driver="slider").compile()):
        for n in (100, 3000):
            model.sweep(np.linspace(0, 1, n) + model.u0[0], engine="numba")
            model.sweep(np.linspace(0, 1, n) + model.u0[0], engine="numba", rates=False)
    assert len(engine._values.signatures) == 1 and len(engine._buffers.signatures) == 1
    assert not engine._missing(engine._stamp())  # on disk, for the kernels as they are
    assert engine._missing("kernels changed")  # a change to them: compiled afresh


@pytest.mark.numba
def test_every_function_the_engine_caches_is_dropped_with_it():
    # the loop's stages are cached apart: one left out of the engine's entries would be loaded
    # from numba's cache, compiled with the kernels as they were, after a change to them
    import numba
    from numba.core.caching import NullCache

    from planar.compiled import engine

    cached = {name for name, fn in vars(engine).items()
              if isinstance(fn, numba.core.registry.CPUDispatcher) and not isinstance(fn._cache, NullCache)}
    assert cached == {fn.__name__ for fn in engine._ENTRIES}


@pytest.mark.numba
def test_the_bulk_pass_leaves_a_solved_anchor_it_cannot_take_as_it_was():
    # the compiled pass takes the solved anchors with the other values (their final step); an
    # anchor whose step fails there (here: a table whose second interval guesses 0.3 off)
    # keeps the pose and modes it had, for the general path, and the interval's other values
    # are left unposed; the first anchor is taken from the start of the first interval
    model = four_bar(4, 2, 3.5, 3).compile()
    p = plan(model)
    N, G = 9, np.array([0, 4, 8])
    U = np.linspace(0.0, 0.4, N)[:, None]
    ones = np.ones((G.size, 1))
    f = compiled.final(model, p, model.sweep(U[G, 0]).q, U[G], ones, 0 * ones)
    P = quintic(f["q"], f["qd"], f["qdd"], np.diff(U[G, 0]))
    P[1, 0] += 0.3
    q = np.full((N, model.n), 7.0)
    q[G] = f["q"]
    signs = np.zeros((N, len(p.blocks)), np.int8)
    signs[G] = f["signs"]
    solved = np.isin(np.arange(N), G)
    arrays = dict(q=q, U=U, Ud=np.ones((N, 1)), Udd=np.zeros((N, 1)), qd=np.empty((N, model.n)),
                  qdd=np.empty((N, model.n)), res=np.empty(N), signs=signs, sing=np.empty(N), branch=np.empty(N),
                  status=np.zeros(N, np.int8), iters=np.zeros(N, np.int64), solved=solved.copy(), done=np.zeros(N, bool))
    ok = compiled.fill(model, p, np.arange(N), np.ones(G.size, bool), G, P, f["signs"], 1e-12, True, arrays)
    assert ok.tolist() == [True] * 5 + [False] * 4
    assert np.array_equal(q[8], f["q"][2]) and np.array_equal(signs[8], f["signs"][2])  # as it was
    assert np.all(np.isnan(q[5:8])) and arrays["solved"].tolist() == [True] * 5 + [False] * 3 + [True]
    assert arrays["done"].tolist() == [True] * 5 + [False] * 4
    assert np.allclose(q[:5], model.sweep(U[:5, 0]).q, atol=1e-14)


def test_unknown_engine_is_refused():
    with pytest.raises(InputError, match="engine"):
        four_bar().sweep([0.0, 0.1], engine="fortran")


def test_compiled_engine_without_numba_is_a_named_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", None)  # as if numba were not installed
    with pytest.raises(InputError, match="engine='numba' needs numba"):
        four_bar().sweep([0.0, 0.1], engine="numba")


@pytest.mark.numba
def test_the_one_off_compile_says_so(monkeypatch, capsys):
    # no machine code on disk: the first sweep compiles the engine, and says so
    from planar.compiled import engine

    done = []
    monkeypatch.setattr(engine, "_ready", False)
    monkeypatch.setattr(engine, "_missing", lambda stamp: True)
    monkeypatch.setattr(engine, "_compile", lambda stamp: done.append(stamp))
    engine.ready()
    err = capsys.readouterr().err
    assert done == [engine._stamp()]
    assert "compiling the numba engine, once per installation" in err and "compiled the numba engine in" in err
    engine.ready()  # once per process
    assert capsys.readouterr().err == "" and len(done) == 1
