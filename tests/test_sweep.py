"""Sweeps at scale: batched against sequential, outputs that solve only what they need."""

import numpy as np
import pytest

from planar import InputError, Status
from planar.mechanisms import four_bar, geared_five_bar, slider_crank, watt_six_bar


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


def test_an_unknown_branch_option_is_refused():
    with pytest.raises(InputError, match="branch must be"):
        four_bar(4, 2, 3, 4).sweep([0.0, 0.1], branch="left")


def test_events_and_nearest_limit_on_the_result():
    m = four_bar(4, 3, 3, 2.5)
    res = m.sweep(np.linspace(0, 3, 31))
    lim = res.events[0].input
    out = res.status == Status.NOT_ASSEMBLABLE
    assert out.any() and np.all(res.nearest_limit[out] == lim) and np.all(np.isnan(res.nearest_limit[~out]))
