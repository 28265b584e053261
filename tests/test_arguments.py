"""The sweep's argument checks at their limits: the bounds are the named constants, inclusive
where they say so, and lengths are counted in the mechanism's size. (Bad values through the
public API, one by one, are in test_bad_input.py.)"""

import numpy as np
import pytest

from planar import arguments
from planar.errors import InputError
from planar.mechanisms import four_bar, slider_crank
from planar.sweep import run_sweep


@pytest.fixture(scope="module")
def crank():
    return four_bar(4, 2, 3.5, 3).compile()


@pytest.fixture(scope="module")
def slider():
    """A slider crank driven by its slider's travel: a length input (L = its size)."""
    return slider_crank(2, 5, offset=1, driver="slider").compile()


def test_tolerance_bounds_are_inclusive():
    lo, hi = arguments.TOL_RANGE
    assert arguments.tolerance(lo) == lo and arguments.tolerance(hi) == hi
    for bad in (lo * (1 - 1e-9), hi * (1 + 1e-9), float("nan"), True, "1e-9"):
        with pytest.raises(InputError, match="tol must be"):
            arguments.tolerance(bad)


def test_options_are_the_run_s_keywords_and_max_step_is_filled_in():
    got = arguments.sweep_options({"tol": 1e-10}, run_sweep)
    assert got == {"tol": 1e-10, "max_step": 0.05}
    with pytest.raises(InputError, match="unknown sweep option 'tolerance': the options are tol, max_step, outputs"):
        arguments.sweep_options({"tolerance": 1e-10}, run_sweep)
    with pytest.raises(InputError, match="rates must be True or False"):
        arguments.sweep_options({"rates": 1}, run_sweep)
    # the sweep's private keywords (a sweep made by another) are no options
    with pytest.raises(InputError, match="'_nested': the options are tol, max_step, outputs, branch, rates, engine$"):
        arguments.sweep_options({"_nested": True}, run_sweep)
    assert arguments.sweep_options({"rates": np.bool_(False)}, run_sweep)["rates"] == np.False_


def test_the_walk_is_counted_from_the_sketch_in_steps_of_max_step(crank):
    """Steps are the input the walk covers through the values in the order the sweep solves
    them (one input's turning back: in the order of the input, from the end nearer the
    sketch's), over max_step: at MAX_STEPS the sweep is allowed, past it refused."""
    R = 1e6  # (angles within MAX_ANGLE)
    step = 2 * R / arguments.MAX_STEPS
    ok = crank.u0 + np.array([[R], [0.0]])  # out and back: MAX_STEPS
    arguments.values(crank, ok, step)
    with pytest.raises(InputError, match=r"is 2e\+08 continuation steps of max_step = 0.01, more than the limit"):
        arguments.values(crank, ok, step / 2)
    # jumping back and forth: solved as the values sorted, so counted once across
    jumping = crank.u0 + np.array([[2 * R], [0.0], [R], [-1.0]])
    arguments.values(crank, jumping, step * (2 * R + 2) / (2 * R))
    with pytest.raises(InputError, match="no values"):
        arguments.values(crank, np.zeros((0, 1)), step)


def test_length_inputs_count_in_the_mechanisms_size(slider):
    assert slider.input_lengths.all()
    far = slider.u0 + np.array([[arguments.MAX_STEPS * slider.L]])  # MAX_STEPS steps of L
    arguments.values(slider, far, 1.0)
    with pytest.raises(InputError, match="more than the limit"):
        arguments.values(slider, 1.01 * far, 1.0)
    arguments.rates(slider, np.array([[arguments.MAX_RATE * slider.L]]), np.zeros((1, 1)))
    with pytest.raises(InputError, match="sweep velocity reaches"):
        arguments.rates(slider, np.array([[2 * arguments.MAX_RATE * slider.L]]), np.zeros((1, 1)))
    with pytest.raises(InputError, match="sweep acceleration reaches .* squared"):
        arguments.rates(slider, np.zeros((1, 1)), np.array([[2 * arguments.MAX_ACCELERATION * slider.L]]))


def test_a_sweep_larger_than_memory_is_refused_before_any_work(crank, monkeypatch):
    need = 1000 * crank.n * arguments.BYTES_PER_COORDINATE
    monkeypatch.setattr(arguments, "_memory", lambda: need)
    arguments.size(crank, 1000)
    with pytest.raises(InputError, match="the sweep of 1001 values needs about .* GiB for its results"):
        arguments.size(crank, 1001)
    with pytest.raises(InputError, match="the circuit of 2000 values"):
        arguments.size(crank, 2000, "the circuit")
    with pytest.raises(InputError, match="the circuit of 251 values"):  # (its tracing keeps more a value)
        crank.circuit(samples=251)
    monkeypatch.setattr(arguments, "_memory", lambda: None)  # the system does not say: allowed
    arguments.size(crank, 10**15)
