"""Sweeps at scale: batched against sequential, outputs that solve only what they need."""

import platform

import numpy as np
import pytest

from planar import InputError, Status
from planar.mechanisms import four_bar, geared_five_bar, open_chain, slider_crank, watt_six_bar
from planar.sweep.anchors import walk_anchors


@pytest.mark.parametrize("build", [lambda: four_bar(4, 2, 3, 4, coupler_point=(1.0, 0.8)),
                                   lambda: slider_crank(2, 5, offset=1),
                                   watt_six_bar, geared_five_bar])
def test_batched_and_sequential_sweeps_agree(build):
    m = build()
    values = np.linspace(0, 2 * np.pi, 150) + m.compile().u0[0]
    batched = m.sweep(values, velocity=3.0, acceleration=-2.0)
    # a max_step below the spacing makes every value an anchor of the sequential walk
    sequential = m.sweep(values, velocity=3.0, acceleration=-2.0, max_step=0.03)
    np.testing.assert_array_equal(batched.status, sequential.status)
    ok = batched.ok
    L = m.compile().L
    scale = np.tile([L, L, 1.0], m.compile().n // 3)
    assert np.nanmax(np.abs(batched.q - sequential.q)[ok] / scale) <= 1e-13
    assert np.nanmax(np.abs(batched.qd - sequential.qd)[ok] / scale) <= 1e-11 * (1 + np.nanmax(np.abs(batched.qd)))
    assert np.nanmax(np.abs(batched.qdd - sequential.qdd)[ok] / scale) <= 1e-10 * (1 + np.nanmax(np.abs(batched.qdd)))


def test_outputs_solve_only_the_blocks_they_need():
    m = watt_six_bar()
    values = np.linspace(0, 2 * np.pi, 50)
    full = m.sweep(values)
    first = m.sweep(values, outputs=["rocker"])
    np.testing.assert_allclose(first.angle("rocker"), full.angle("rocker"), atol=1e-13)
    np.testing.assert_allclose(first.omega("rocker"), full.omega("rocker"), atol=1e-12)
    assert np.all(np.isnan(first.angle("link5"))) and np.all(np.isnan(first.position("E")))
    assert np.all(first.status == Status.SOLVED)
    point = m.sweep(values, outputs="E")  # a point of the second loop needs both loops
    np.testing.assert_allclose(point.position("E"), full.position("E"), atol=1e-12)
    with pytest.raises(InputError, match="unknown output 'nothing'"):
        m.sweep(values, outputs=["nothing"])
    m.add_point("G", m.ground, at=(1.0, 1.0))  # fixed to the ground: needs no coordinate
    ground = m.sweep(values, outputs=["G"])
    assert np.all(ground.status == Status.SOLVED)
    np.testing.assert_allclose(ground.position("G"), 1.0, atol=0)


def test_positions_only_gives_the_same_poses_and_statuses_without_rates():
    m = four_bar(4, 3, 3, 2.5, coupler_point=(1.0, 0.8))  # a triple rocker: limits, out of range
    values = np.linspace(0, 2 * np.pi, 2001)
    full, only = m.sweep(values), m.sweep(values, rates=False)
    np.testing.assert_array_equal(only.status, full.status)
    np.testing.assert_array_equal(only.position("C"), full.position("C"))
    assert only.ok.any() and np.all(np.isnan(only.qd)) and np.all(np.isnan(only.acceleration("C")))
    assert [e.kind for e in only.events] == [e.kind for e in full.events]


@pytest.mark.parametrize("kind", ["uniform", "uneven", "decreasing", "sparse", "one value"])
def test_walk_anchors_are_within_max_step_where_the_values_allow(kind):
    rng = np.random.default_rng(3)
    v = {"uniform": np.linspace(0, 7, 100_001), "uneven": np.cumsum(rng.uniform(0, 1e-3, 50_000)),
         "decreasing": np.linspace(2, -3, 20_000), "sparse": np.cumsum(rng.uniform(0.01, 0.2, 300)),
         "one value": np.array([0.5])}[kind]
    scale, max_step = np.array([0.5]), 0.05  # an input in lengths: steps of 0.1 in its own unit
    idx, monotone = walk_anchors(v[:, None], scale, max_step)
    assert monotone and idx[0] == 0 and np.all(np.diff(idx) > 0) and idx[-1] < v.size
    stops = np.unique(np.r_[idx, v.size - 1])  # the walk ends at the last value
    gaps = np.abs(np.diff(v[stops]))
    room = max_step / scale[0]
    # each pick is within reach of the one before, or the next value when none is
    next_ok = np.abs(np.diff(v))[stops[:-1]]
    assert np.all((gaps <= room * (1 + 1e-12)) | (gaps <= next_ok * (1 + 1e-12)))
    if kind != "sparse":  # densely sampled: at most about one pick per max_step, not more
        assert idx.size <= np.ptp(v) / room * 2.2 + 1


def test_the_sweep_keeps_its_own_copy_of_the_inputs():
    m = four_bar(4, 2, 3, 4)
    values = np.linspace(0, 1, 11)
    res = m.sweep(values, velocity=np.full(11, 2.0))
    values[:] = 5.0
    np.testing.assert_array_equal(res.inputs[:, 0], np.linspace(0, 1, 11))
    assert not res.inputs.flags.writeable and not res.qd.flags.writeable
    np.testing.assert_array_equal(res.input_rates, 2.0)
    arm = open_chain([1.0, 0.5]).compile()  # two inputs: values in Fortran order come back in C order
    values = np.asfortranarray(arm.u0 + np.linspace(0, 0.2, 5)[:, None])
    assert not values.flags.c_contiguous and arm.sweep(values).inputs.flags.c_contiguous


def test_an_unknown_branch_option_is_refused():
    with pytest.raises(InputError, match="branch must be"):
        four_bar(4, 2, 3, 4).sweep([0.0, 0.1], branch="left")


def test_events_and_nearest_limit_on_the_result():
    m = four_bar(4, 3, 3, 2.5)
    res = m.sweep(np.linspace(0, 3, 31))
    lim = res.events[0].input
    out = res.status == Status.NOT_ASSEMBLABLE
    assert out.any() and np.all(res.nearest_limit[out] == lim) and np.all(np.isnan(res.nearest_limit[~out]))


@pytest.mark.parametrize("build", [lambda: four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8)),
                                   lambda: slider_crank(2, 5, offset=1)])
def test_the_bulk_of_a_sweep_is_one_newton_step_per_value(build):
    # the Hermite guesses from the anchors' poses and kinematic coefficients (kept from the
    # waves that solved them, or computed once) sit at rounding level: one evaluation and one
    # factorisation certify each value and give its rates
    m = build().compile()
    res = m.sweep(m.u0[0] + np.linspace(0, 2 * np.pi, 20000, endpoint=False))
    assert res.ok.all()
    assert np.mean(res.iterations == 1) >= 0.99


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the heap policy of glibc's malloc")
def test_repeated_sweeps_reuse_their_memory():
    """A sweep's freed memory is malloc's to reuse at the next call, not faulted in afresh
    (planar.sweep.run._keep_freed_memory): with the heap trimmed after each call this sweep
    faulted ~8000 pages in at every call (~20 % of its time here)."""
    import resource  # (POSIX only: glibc implies it)

    model = slider_crank(2, 5, offset=1).compile()
    th = np.linspace(0, 2 * np.pi, 100_000)
    faults = []
    for _ in range(3):
        before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        model.sweep(th)
        faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
    assert min(faults[1:]) < 1000, faults
