"""Every bad argument, file field and command line is refused up front by a PlanarError naming
it and the fix; the command line prints one line and exits 2 for a bad command line, 1 for a bad
file; sizes that cannot fit in memory or time are refused with the limit named."""

import importlib.util
import json
import math
import os
import re
import tracemalloc
import warnings

import numpy as np
import pytest

import planar
from planar import arguments, draw, io, synthesis
from planar.animate import animate
from planar.errors import FileFormatError, InputError, ModelError, SynthesisError
from planar.analysis import grashof, motion_range, stroke
from planar.mechanisms import four_bar, open_chain, planetary_gear_train, slider_crank, watt_six_bar
from tests.test_cli import run_or_exit

SWEEP_CALLS = [
    # (values, options, error, message)
    ([], {}, InputError, "the sweep has no values: give at least one"),
    (bytearray(b"12"), {}, InputError, "sweep values must be real numbers, got bytearray"),  # (its codes 49, 50)
    (np.zeros((0, 1)), {}, InputError, "the sweep has no values"),
    ([0.1], {"max_step": 0}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": -0.1}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": math.nan}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": math.inf}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": "big"}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": True}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": 1e-300}, InputError, "max_step must be at least 0.0001"),
    ([0.1], {"max_step": 1e-7}, InputError, "max_step must be at least 0.0001, got 1e-07: the walk shortens its own"),
    ([0.1], {"tol": -1}, InputError, "tol must be from 1e-15 to 0.001, got -1.0"),
    ([0.1], {"tol": 0}, InputError, "tol must be from 1e-15 to 0.001"),
    ([0.1], {"tol": 0.5}, InputError, "tol must be from 1e-15 to 0.001"),
    ([0.1], {"tol": math.nan}, InputError, "tol must be a finite number, got nan"),
    ([0.1], {"tol": math.inf}, InputError, "tol must be a finite number"),
    ([0.1], {"tol": "small"}, InputError, "tol must be a finite number, got 'small'"),
    ([0.1], {"tol": None}, InputError, "tol must be a finite number"),
    ([0.1], {"tolerance": 1e-9}, InputError, "unknown sweep option 'tolerance': the options are tol, max_step"),
    ([0.1], {"velocity_unit": "rpm"}, InputError, "unknown sweep option 'velocity_unit'"),
    ([0.1], {"rates": "no"}, InputError, "rates must be True or False"),
    ([0.1], {"branch": "left"}, InputError, "branch must be 'smooth' or 'other'"),
    ([0.1], {"engine": "fortran"}, InputError, "engine must be 'numpy' or 'numba'"),
    ([0.1], {"engine": np.zeros(3)}, InputError, "engine must be 'numpy' or 'numba'"),  # (a numpy ValueError)
    ([0.1], {"outputs": ["nope"]}, InputError, "unknown output 'nope'"),
    ([0.1], {"outputs": 3}, InputError, "outputs must be a name or a list of names of bodies, points or joints, got 3"),
    ([0.1], {"outputs": ["rocker", None]}, InputError, "outputs must be a name or a list of names"),
    ([[0.1, 0.2]], {}, InputError, "sweep values have shape (1, 2) but 1 input(s) ['crank'] need"),
    ([math.nan], {}, InputError, "sweep values must be finite"),
    (["a"], {}, InputError, "sweep values must be real numbers, got strings"),
    # (a list of these was read as numbers: "1.0" as 1.0, True as 1.0 and None as NaN, "must be finite")
    (["1.0", "2"], {}, InputError, "sweep values must be real numbers, got strings"),
    ([True, False], {}, InputError, "sweep values must be real numbers, got booleans"),
    ([0.1, None], {}, InputError, "sweep values must be numbers, got None among them"),
    (0.1, {}, InputError, "must be a sequence of input values, got a scalar"),
    ([0.0, 1e300], {}, InputError, "continuation steps of max_step = 0.05, more than the limit of 1e+08"),
    ([1e308, -1e308], {}, InputError, "more than the limit of 1e+08"),
    ([0.0, 1e7], {}, InputError, "more than the limit of 1e+08: sweep a shorter span"),
    ([10**400], {}, InputError, "sweep values must be finite; found an integer beyond any float"),
    ([0.1], {"tol": 10**400}, InputError, "tol must be a finite number"),
    ([0.1], {"max_step": 10**400}, InputError, "max_step must be a positive number"),
    ([0.1], {"branch": ["smooth"]}, InputError, "branch must be 'smooth' or 'other', got ['smooth']"),
    # (each was read as other numbers: days since 1970, 1.0, the real part, the values under the mask)
    (np.array(["2020-01-01"], dtype="datetime64[D]"), {}, InputError, "sweep values must be real numbers"),
    (np.array([True, False]), {}, InputError, "sweep values must be real numbers, got an array of bool"),
    (np.array([0.1 + 1j]), {}, InputError, "sweep values must be real numbers, got an array of complex128"),
    ([np.complex128(1 + 2j)], {}, InputError, "sweep values must be real numbers, got complex ones"),
    (np.ma.masked_array([0.1, 0.2], mask=[0, 1]), {}, InputError, "with masked values"),
    ([[1.0], 0.2], {}, InputError, "sweep values must be numbers, got list"),  # (a ValueError from the complex test)
]


@pytest.mark.parametrize("values, options, error, message", SWEEP_CALLS,
                         ids=[f"{v!r:.20}-{o}" for v, o, _, _ in SWEEP_CALLS])
def test_bad_sweep_arguments(values, options, error, message):
    for target in (four_bar(), four_bar().compile()):  # the builder and the model: one check
        with pytest.raises(error) as e:
            target.sweep(values, **options)
        assert message in str(e.value)
        assert isinstance(e.value, planar.PlanarError)


@pytest.mark.parametrize("kwargs, message", [
    ({"velocity": [1.0, 2.0, 3.0]}, "sweep velocity have shape (3,)"),
    ({"velocity": math.inf}, "sweep velocity must be finite"),
    ({"acceleration": "fast"}, "sweep acceleration must be real numbers, got strings"),
    ({"velocity": 1e160}, "sweep velocity reaches 1e+160 .* beyond 1e+100 the accelerations overflow"),
    ({"velocity": [1.0, -1e300]}, "sweep velocity reaches 1e+300"),
    ({"acceleration": 1e250}, "sweep acceleration reaches 1e+250"),
])
def test_bad_rates(kwargs, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("+", r"\+")):
        four_bar().sweep([0.0, 0.1], **kwargs)


@pytest.mark.parametrize("kwargs, message", [
    ({"tol": -1}, "tol must be from"),
    ({"tol": "small"}, "tol must be a finite number"),
    ({"max_step": 0}, "max_step must be a positive number"),
    ({"samples": 1}, "samples must be a whole number from 2 to 1e\\+06"),
    ({"samples": 10.5}, "samples must be a whole number"),
    ({"velocity": math.nan}, "velocity must be one finite number"),
    ({"velocity": 10**400}, "velocity must be one finite number"),
    ({"velocity": 1e200}, "velocity reaches 1e\\+200"),  # (the accelerations would be NaN, the values SOLVED)
    ({"max_step": 1e-9}, "max_step must be at least 0.0001"),  # (it hung)
    ({"max_step": 1e-3}, "give max_step of at least 0.0075"),  # (a circuit that does not close: 20-30 s)
    ({"samples": 10**6 + 1}, "samples must be a whole number from 2 to 1e\\+06, got 1000001"),  # (1e7: 26 s, 3.4 GB)
    ({"bogus": 1}, "unknown circuit option 'bogus': the options are tol, max_step"),  # (a TypeError)
    ({"samples": 10**400}, "the circuit of ~1e400 values needs about inf GiB"),  # (an OverflowError)
    ({"samples": -10**400}, "samples must be a whole number from 2 to 1e\\+06"),  # (an OverflowError)
    ({"velocity": np.complex128(1 + 0j)}, "velocity must be one finite number"),  # (its real part, with a warning)
])
def test_bad_circuit_arguments(kwargs, message):
    with pytest.raises(InputError, match=message):
        four_bar().circuit(**kwargs)


def _rocker_driving_a_train(gears):
    """A triple rocker whose rocker drives a train of ``gears`` gears on fixed axes."""
    m = four_bar(4, 3, 3, 3)
    x = 4.0
    for k in range(1, gears + 1):
        m.add_body(f"g{k}")
        x += 1.5
        m.add_revolute(f"G{k}", m.ground, f"g{k}", at=(x, 0.0))
        m.add_gear(f"mesh{k}", "rocker" if k == 1 else f"g{k - 1}", f"g{k}", 0.5 if k == 1 else 0.75, 1.0 if k == 1
                   else 0.75, carrier=m.ground)
    return m


def test_a_circuit_of_more_coordinates_than_it_traces_is_refused_up_front():
    # (a planetary train of 50 planets, 156 coordinates, traced its circuit of 91 samples in 63 s; an
    # input that turns fully is now swept, and the trace keeps to what has limits or events)
    with pytest.raises(InputError, match="would trace its 129 coordinates one pose at a time .*, more than 120 .* "
                                         "sweep it with Model.sweep"):
        _rocker_driving_a_train(40).circuit(91)


# (None, "1.0" and True were moves to NaN, 1.0 and 1.0)
# (a masked value was the number under the mask, a bytearray its characters' codes)
@pytest.mark.parametrize("value", ["a", None, object(), [[1.0], [2.0]], 10**400, np.complex128(1 + 2j), "1.0", True,
                                   np.bool_(False), [True], np.ma.masked, np.ma.masked_array(0.5, mask=True),
                                   bytearray(b"1"), memoryview(b"\x01")])
def test_a_tracker_move_to_no_number_is_an_input_error(value):
    with pytest.raises(InputError, match="move takes a number|sweep values"):
        four_bar().compile().track().move(value)


@pytest.mark.parametrize("torque, message", [
    (lambda u: np.full(len(u), np.nan), "a load's torque function gave NaN, infinity or a number beyond"),  # (NaN forces, SOLVED)
    (lambda u: np.full(len(u), 1e308), "torque function gave NaN, infinity or a number beyond \\+-1e\\+100"),  # (inf efforts)
    (lambda u: "abc", "a load's torque function gave str 'abc'; it must give real numbers"),  # (a ValueError)
])
def test_a_load_function_that_gives_no_finite_numbers_is_a_model_error(torque, message):
    m = four_bar()
    m.add_load("coupler", torque=torque)
    with pytest.raises(ModelError, match=message):
        m.sweep([0.1, 0.2]).forces()


def test_a_load_torque_beyond_the_numbers_a_sketch_holds_is_a_model_error():
    # (1e308: efforts inf and reactions NaN, SOLVED)
    with pytest.raises(ModelError, match=r"load torque on 'coupler' = 1e\+308 is beyond the numbers a sketch holds"):
        four_bar().add_load("coupler", torque=1e308)


def test_a_mechanism_with_nothing_to_drive_says_so():
    # (it said "add 0 with drive()")
    with pytest.raises(planar.MobilityError, match="has no driver and nothing to drive"):
        planar.Mechanism().sweep([0.0])


def test_a_design_parameter_the_builder_does_not_take_is_an_input_error():
    with pytest.raises(InputError, match=r"design 0 \{'nope': 1\}: four_bar refused its parameters .* name only"):
        planar.sweep_designs(four_bar, [{"nope": 1}], [0.1])


def _loaded():
    m = four_bar()
    m.set_mass("crank", 1.0, (0.5, 0.0), 0.1)
    return m


# (each a numpy ValueError: an array compared with a tuple of names, or a numpy warning)
@pytest.mark.parametrize("call, error, message", [
    (lambda: four_bar(coupler_point=(1, 0.5)).drive(point="C", axis=np.array(["x", "y"])), ModelError,
     "needs axis='x' or axis='y'"),
    (lambda: four_bar().add_load("crank", force=(1, 0), at=(0.5, 0.5), fixed=np.array(["world", "body"])), ModelError,
     "fixed must be 'world' or 'body'"),
    (lambda: planar.Dyad("A", 1.0, "B", 1.0, side=np.array(["left", "right"])), ModelError,
     "a dyad's side must be 'left' or 'right'"),
    (lambda: _loaded().sweep([0.1]).forces().driver_effort(np.array(["crank", "x"])), ModelError, "unknown driver"),
    (lambda: planar.analysis.outputs.output(four_bar().sweep([0.1]), "x:B", np.array([0, 1])), InputError,
     "derivative must be 0, 1 or 2"),
    (lambda: planar.analysis.outputs.output(four_bar().sweep([0.1]), "x:B", 1.0), InputError,  # (a TypeError)
     "derivative must be 0, 1 or 2, got 1.0"),
    (lambda: four_bar().compile().circuit(engine="numba"), InputError,  # (a TypeError, as Mechanism.circuit's was not)
     "unknown circuit option 'engine': the options are tol, max_step"),
    (lambda: four_bar().distance("O2", "A", np.longdouble("1e400")), ModelError, "distance O2-A must be finite"),
    (lambda: four_bar().sweep([0.1], velocity=np.longdouble("1e400")), InputError, "velocity must be finite"),
])
def test_arrays_for_names_and_choices_are_refused_by_name(call, error, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(error, match=message):
            call()


def test_a_load_function_of_complex_numbers_and_forces_beyond_float64_are_refused():
    m = _loaded()
    m.add_load("coupler", torque=lambda: 1.0)
    with pytest.raises(ModelError, match="a load's torque function must take the input values"):  # (a TypeError)
        m.sweep([0.1]).forces()
    m = _loaded()
    m.add_load("crank", force=lambda u: np.ones((len(u), 2)) * (1 + 5j), at=(0.5, 0.5))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (numpy dropped the imaginary parts, with a ComplexWarning)
        with pytest.raises(ModelError, match="a load's force function gave ndarray .* it must give real numbers"):
            m.sweep([0.1]).forces()
        m = four_bar()
        m.set_mass("crank", 1.0, (1e100, 1e100), 0.0)
        m.gravity = (0.0, -9.81)
        with pytest.raises(InputError, match="the forces of 'four_bar' overflow float64"):  # (a RuntimeWarning)
            m.sweep([0.1], velocity=1e100).forces()
        assert planar.Dyad("A", np.float32(2.5), "B", 1.5).length_a == 2.5  # (its bounds test warned)


def test_a_sweep_larger_than_memory_is_refused_with_the_limit(monkeypatch):
    monkeypatch.setattr(arguments, "_memory", lambda: 2**30)  # a machine with 1 GiB
    model = four_bar().compile()
    with pytest.raises(InputError, match=r"the sweep of 10000000 values needs about 3.35 GiB for its results, "
                                         r"more than the 1 GiB of memory this process may have: sweep fewer values"):
        arguments.size(model, 10_000_000)
    with pytest.raises(InputError, match="the circuit of 100000000 values needs about"):
        model.circuit(samples=100_000_000)
    model.sweep(np.linspace(0.0, 1.0, 1000))  # what fits still runs


def test_values_beyond_memory_are_refused_before_they_are_copied(monkeypatch):
    monkeypatch.setattr(arguments, "_memory", lambda: 2**30)
    model = four_bar().compile()
    values = np.zeros(10**7, np.int8)  # 10 MB; 80 MB as floats
    tracemalloc.start()
    try:
        with pytest.raises(InputError, match="the sweep of 10000000 values needs about"):
            model.sweep(values)
        with pytest.raises(InputError, match="move takes a number"):
            model.track().move(values)
        assert tracemalloc.get_traced_memory()[1] < 2e7
    finally:
        tracemalloc.stop()


def test_a_design_study_beyond_memory_is_refused_before_it_is_swept(monkeypatch):
    monkeypatch.setattr(arguments, "_memory", lambda: 2**20)  # 1 MiB: 1000 values of one four-bar fit
    # (1000 designs x 1e6 values grew to 23.5 GB, then a numpy MemoryError)
    with pytest.raises(InputError, match=r"a batch of 3 designs x 1000 values, a sweep of 3000 values needs about "
                                         r".* GiB .*: sweep fewer designs a batch \(batch=\), or fewer values"):
        planar.sweep_designs(four_bar, {"crank": [1.0, 1.1, 1.2]}, np.linspace(0, 1, 1000))
    with pytest.raises(InputError, match=r"the study of 3 designs x 1000 values, a sweep of 3000 values .* "
                                         r"on a cluster into a store"):
        planar.sweep_designs(four_bar, {"crank": [1.0, 1.1, 1.2]}, np.linspace(0, 1, 1000), batch=1)


@pytest.mark.parametrize("call, message", [
    (lambda: planar.sweep_designs(four_bar, {"crank": [[1.0], [1.0, 2.0]]}, [0.1]), "design column 'crank' must hold"),
    (lambda: planar.sweep_designs(four_bar, {"coupler_point": [(1, 0), (2,)]}, [0.1]),
     "design column 'coupler_point' must hold one value per design"),
    (lambda: planar.sweep_designs(four_bar, {"crank": np.ones((2, 2, 2))}, [0.1]),
     r"got an array of shape \(2, 2, 2\)"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0, 1.1]}, [[0.1], [0.2, 0.3]]), "sweep values must be numbers"),
    (lambda: planar.sweep_designs(lambda **k: open_chain() if k["crank"] > 1.2 else four_bar(),
                                  {"crank": [1.0, 1.5]}, [0.1]), r"design 1 .* and 3 inputs, design 0 .* and 1"),
    (lambda: planar.sweep_designs(lambda **k: slider_crank() if k["crank"] > 1.2 else four_bar(crank=k["crank"]),
                                  {"crank": [1.0, 1.5]}, [0.1]), r"design 1 .*'slider'\] .* design 0 .*'rocker'\]"),
    (lambda: planar.sweep_designs(lambda **k: slider_crank() if k["crank"] > 1.2 else four_bar(crank=k["crank"]),
                                  {"crank": [1.0, 1.5]}, [0.1], batch=1), "a study sweeps designs of one structure"),
    (lambda: planar.sweep_designs(lambda crank: four_bar(crank=crank) if crank < 1.2 else None,  # (NOT_ASSEMBLABLE,
                                  {"crank": [1.0, 1.5]}, [0.1]), "design 1: <lambda> returned NoneType"),  # no error)
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0]}, [0.1], rates=False),  # (it listed max_step too)
     r"takes the options tol, max_step, outputs, branch and engine, not \['rates'\]"),
    (lambda: planar.sweep_designs(lambda **k: planar.Mechanism(), {"crank": [1.0]}, [0.1]),
     "no design could be built: design 0 .* has no driver and nothing to drive"),
    (lambda: planar.Vary(four_bar()).check(None), "a design's numbers are a dict of numbers by name, got None"),
    (lambda: planar.Vary(four_bar()).check_all(None), "check_all takes a list of designs"),
    (lambda: planar.Vary(four_bar()).check_all(["x"]), "check_all takes a list of designs"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0]}, [0.1]).velocity(["B"]), "unknown point or joint"),
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), {"O2-A": [2.0**1023 * 1.9, 1.0]}, [0.1]),  # (a warning)
     r"O2-A = .* is beyond \+-1e\+100: give the design's numbers in another unit"),
    (lambda: planar.Vary(four_bar()).check_all([{"O2-A": 1.0}], first="x"), "check_all's first"),  # (a TypeError)
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), [{1: 1.5, "x": 2.0}], [0.1]),  # (a TypeError)
     r"design 0: \['x', 1\] are no numbers of mechanism 'four_bar'"),
    # (a Vary took the design's number; a builder's TypeError named it as a parameter it does not take)
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), {"O2-A": [1.0, 1.2]}, [0.1], fixed={"O2-A": 1.0}),
     r"\['O2-A'\] given both in fixed and in the designs: give each parameter once"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0, 1.2]}, [0.1], fixed={"crank": 1.0}),
     r"\['crank'\] given both in fixed and in the designs"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0]}, lambda d: 1 / 0),  # (the ZeroDivisionError itself)
     r"values\(\{'crank': 1.0\}\) raised ZeroDivisionError: division by zero: give a function of the design"),
])
def test_bad_design_study_arguments(call, message):
    # (each a ValueError, TypeError or AttributeError of numpy or Python)
    with pytest.raises(planar.PlanarError, match=message):
        call()


def test_a_vary_takes_a_float32_number_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (its size test cast 1e100 to float32: an overflow warning)
        m = planar.Vary(four_bar())(**{"O2-A": np.float32(1.5)})
    assert m.compile().sweep([0.1]).ok.all()


def test_a_design_drawn_at_an_angle_beyond_the_sketch_keeps_its_error_and_the_others_are_swept():
    # (its walk from 1e8 rad took 15 GB of stations on the compiled engine; from 1e300 it hung)
    for engine in ("numpy", "numba") if importlib.util.find_spec("numba") else ("numpy",):
        study = planar.sweep_designs(planar.Vary(four_bar()), {"O2-A": [1.0, 1.5], "crank": [0.0, 1e8]},
                                     np.linspace(0.0, 1.0, 5), engine=engine)
        assert study.errors[0] is None and "drawn at the angle 1e+08 rad, beyond" in study.errors[1]
        assert study.ok[0].all() and not study.posed[1].any()


def test_a_design_started_far_from_its_values_is_swept_alone():
    # (the batch walked every step from 1e6 rad: minutes; the sweep solves the values whole turns back)
    for engine in ("numpy", "numba") if importlib.util.find_spec("numba") else ("numpy",):
        study = planar.sweep_designs(four_bar, {"crank": [2.0, 1.5], "start": [1e6, 0.0]},
                                     np.linspace(0.0, 2 * np.pi, 12), engine=engine)
        assert study.batched.tolist() == [False, True] and study.ok.all()
        np.testing.assert_allclose(study.q[0], four_bar(crank=2.0, start=1e6).sweep(np.linspace(0.0, 2 * np.pi, 12)).q,
                                   rtol=0, atol=1e-9)


def test_a_process_limited_to_less_memory_than_the_machine_has_is_held_to_its_limit(monkeypatch):
    resource = pytest.importorskip("resource")
    monkeypatch.setattr(resource, "getrlimit", lambda which: (2**30, resource.RLIM_INFINITY))  # ulimit -v 1048576
    assert arguments._memory() == 2**30
    with pytest.raises(InputError, match=r"more than the 1 GiB of memory this process may have"):
        arguments.size(four_bar().compile(), 10_000_000)
    monkeypatch.setattr(resource, "getrlimit", lambda which: (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    assert arguments._memory() > 2**30  # no limit: the machine's memory


@pytest.mark.parametrize("call, message", [
    (lambda m: m.add_body("b", angle="x"), r"angle of body 'b' \(a number, or a line \(p, q\) of two point names\) must be numeric"),
    (lambda m: m.add_body(""), "body name must be a non-empty string"),
    (lambda m: m.add_body("b", angle=np.True_), r"angle of body 'b' .* must be a number, got (np.)?True"),  # (1 rad)
    # (com and inertia without mass were dropped: a driven body's effort 0)
    (lambda m: m.add_body("b", com=(1, 1), inertia=5.0), "body 'b': com and inertia come with its mass: give mass too"),
    (lambda m: m.add_body("b", angle=np.complex128(1j)), "angle of body 'b' .* must be a real number"),
    (lambda m: m.add_point("P", m.ground, at=(10**400, 0)), "'P' at must be finite, got an integer beyond"),  # (Overflow)
    (lambda m: m.add_point("P", m.ground, at=(0, [1.0])), "'P' at must be numeric"),  # (a ValueError: ragged)
    (lambda m: m.drive("O", name=["a"]), r"a driver's name must be a string, got \['a'\]"),  # (TypeError at compile)
    (lambda m: (m.add_body("b"), m.set_mass("b", 1e308, (0, 0))), r"mass 1e\+308 or inertia 0 is beyond"),  # (inf forces)
    (lambda m: planar.Mechanism(name=None), "a mechanism's name must be a string, got None"),
    (lambda m: setattr(m, "name", 3), "a mechanism's name must be a string, got 3"),
    (lambda m: four_bar(name=("four", "bar")), r"a mechanism's name must be a string, got \('four', 'bar'\)"),
    (lambda m: m.add_revolute("J", m.ground, "nobody", at=(0, 0)), "unknown body 'nobody'"),
    (lambda m: m.add_revolute("J", m.ground, m.ground, at=(0, 0)), "joins body 'ground' to itself"),
    (lambda m: m.add_point("P", m.ground, at=(0, math.nan)), "'P' at must be finite"),
    # (its square overflowed where compile assembles stated distances: an OverflowError)
    (lambda m: m.add_point("P", m.ground, at=(0, 1e308)), r"'P' at = \[0.0, 1e\+308\] is beyond the numbers a sketch holds"),
    (lambda m: m.add_slot("S", m.ground, m.ground, at=(0, 0), direction=(1, 0)), "to itself"),
    (lambda m: m.drive(), "drive needs exactly one of joint=, body= or point="),
    (lambda m: m.drive("nope"), "unknown joint 'nope'"),
    (lambda m: m.add_revolute("J", ["ground"], "b", at=(0, 0)), r"unknown body \['ground'\]"),
    # (an unhashable name was a TypeError, an array a numpy ValueError)
    (lambda m: m.distance(["O"], "P", 1.0), r"a joint or point is named by a string, got \['O'\]"),
    (lambda m: m.restate(np.zeros(2), 1.0), r"restate takes a stated distance 'a-b' or a driver's name"),
    (lambda m: m.drive(np.zeros(2)), r"drive joint= takes a joint's name, got array"),
    # (read by truthiness: "no" made an internal mesh)
    (lambda m: (m.add_body("b"), m.add_gear("G", m.ground, "b", 1.0, 2.0, internal="no")),
     "gear 'G' internal must be True or False, got 'no'"),
    # (a hand-built wheel in a track 1e-9 wider than itself: its sweep ran on for minutes)
    (lambda m: (m.add_body("b"), m.add_gear("G", m.ground, "b", 1.0 + 1e-9, 1.0, internal=True, centre_a=(0, 0),
                                            centre_b=(0, -1e-9), hold_distance=True)),
     "gear 'G': the internal radii 1 and 1.000000001 .* would circle 1e\\+09 times .* more than 100"),
    (lambda m: (m.add_body("b"), m.add_gear("G", m.ground, "b", 1.0, 1.0, internal=True, carrier=m.ground,
                                            centre_a=(0, 0), centre_b=(0, 0))),
     "gear 'G': an internal mesh needs different radii"),
])
def test_bad_builder_arguments(call, message):
    with pytest.raises(ModelError, match=message):
        call(planar.Mechanism())


def test_a_stated_distance_whose_name_is_another_numbers_is_refused():
    # (restate("A-B-C") and Vary's numbers took A-B to C for A to B-C, or the other way)
    m = planar.Mechanism()
    m.add_body("b")
    m.add_revolute("O", m.ground, "b", at=(0, 0))
    for name, at in (("A-B", (1, 0)), ("A", (0, 1)), ("B-C", (1, 1)), ("C", (2, 0))):
        m.add_point(name, "b", at=at)
    m.distance("A-B", "C", 2.0)
    with pytest.raises(ModelError, match="distance A-B-C: that name is another number's of the mechanism already"):
        m.distance("A", "B-C", 1.0)
    m.distance("O", "C", 2.0)
    with pytest.raises(ModelError, match="driver 'O-C': its start would have a stated distance's name"):
        m.drive("O", name="O-C", start=0.0)


def test_a_body_refused_for_its_mass_is_not_added():
    m = planar.Mechanism()
    with pytest.raises(ModelError, match="give com"):
        m.add_body("b", mass=1.0)
    m.add_body("b")  # (it was added before its mass was checked: the name was taken)



def test_a_stated_distance_whose_square_overflows_is_refused():
    # (a numpy LinAlgError from the assembly's least squares; then, followed by equal ratios, a
    # slider-crank's coupler of 1e308 assembled and the sketch's size overflowed)
    for m in (four_bar(), slider_crank()):
        with pytest.raises(ModelError, match="distance A-B = 1e\\+308 is beyond the lengths a sketch holds"):
            m.restate("A-B", 1e308)
    with pytest.raises(ModelError, match="distance O-P = 1e\\+101 is beyond the lengths"):
        planar.Mechanism().distance("O", "P", 1e101)


@pytest.mark.parametrize("call, message", [
    (lambda: four_bar(ground=10**400), "ground must be a positive length"),
    (lambda: four_bar(start=10**400), "start must be finite"),
    (lambda: planetary_gear_train(planets=10**40), "planets must be a whole number from 1 to 128"),  # (for ever)
    (lambda: open_chain([1.0] * 1000), "lengths must hold from 1 to 256 lengths, got 1000"),  # (compile: 20 s)
    (lambda: planar.mechanisms.gear_train([1.0] * 10**6), "radii must hold from 2 to 256 lengths"),
    (lambda: planar.mechanisms.gear_train("12"), "radii must be a sequence of lengths, got '12'"),  # (as [1, 2])
    (lambda: open_chain([1.0, 1.0], start=[0, np.complex128(1 + 0j)]), "start must hold 2 finite angles"),
    (lambda: four_bar(driver=np.array(["crank", "x"])), "driver must be one of"),  # (a numpy ValueError)
    (lambda: planar.Dyad("A", 10**400, "B", 1.0, side="left"), "a dyad's length_a must be a positive number"),
    (lambda: four_bar(ground=np.complex128(4 + 3j)), r"ground must be a number, got np.complex128\(4\+3j\)"),  # (ground 4)
    (lambda: four_bar(ground=np.complex64(4)), r"ground must be a number, got np.complex64"),  # (a ComplexWarning; 4)
    (lambda: four_bar(crossed="no"), "crossed must be True or False, got 'no'"),  # (it built the crossed one)
    (lambda: four_bar(crossed=2), "crossed must be True or False"),
    (lambda: slider_crank(crossed="False"), "crossed must be True or False"),
    (lambda: watt_six_bar(crossed_2="yes"), "crossed_2 must be True or False"),
    # (an OverflowError from the sketch's geometry)
    (lambda: slider_crank(crank=1e300), "crank = 1e\\+300 is beyond the lengths a sketch holds"),
    (lambda: slider_crank(offset=-1e300), "offset = -1e\\+300 is beyond the numbers a sketch holds"),
    (lambda: four_bar(ground=1e-300), "ground = 1e-300 is beyond the lengths a sketch holds"),
    (lambda: open_chain([1.0, 1.0], start="abc"), "start must hold 2 finite angles, one per link; got 'abc'"),
    # (its centre circling 1e9 times a turn of the wheel: a sweep of two values ran on for minutes)
    (lambda: planar.mechanisms.rolling_wheel(1.0, track_radius=1.0 + 1e-9),
     "the inner wheel's centre would circle 1e\\+09 times a turn of the wheel, more than 100"),
    (lambda: four_bar(crank=True), "crank must be a number, got True"),  # (a crank of 1)
    (lambda: four_bar().compile().sketch.position([1.0]), r"unknown joint or point \[1.0\]"),  # (a TypeError)
    (lambda: four_bar().set_angle("crank", 1e12), "the angle of body 'crank' is 1e\\+12 rad, beyond"),  # (8e-5 off)
    (lambda: planar.Mechanism().add_body("b", angle=-1e308), "the angle of body 'b' is -1e\\+308 rad, beyond"),
    (lambda: planar.analysis.grashof(True, 2.0, 3.0, 4.0), "ground must be a number, got True"),
    (lambda: planar.mechanisms.gear_train([1e4, 1e-4]),  # (5 values over a turn: 17 s, every one NEAR_SINGULAR)
     "gear 'mesh12': the radii 0.0001 and 10000 are 1e\\+08 times apart, more than 1e\\+06"),
    (lambda: planar.mechanisms.rolling_wheel(1.0, track_radius=1.001),  # (73 values over a turn: 20 s)
     "would circle 1e\\+03 times a turn of the wheel, more than 100; give radii more than 0.01 apart"),
])
def test_bad_catalogue_arguments(call, message):
    with pytest.raises(ModelError, match=message):
        call()


def test_integer_lengths_convert_without_wrapping_round():
    from planar.units import convert_length

    # (int64 products wrapped round: 1e13 m was -8.4e15 mm, 2**63 m 0 mm)
    assert convert_length(10**13, "m", "mm") == 1e16 and convert_length(np.uint64(2**63), "m", "mm") == 2.0**63 * 1e3
    assert convert_length(np.array([3, -10**13]), "m", "mm").tolist() == [3000.0, -1e16]
    assert convert_length(7, "mm", "m") == 0.007


@pytest.mark.parametrize("value, message", [
    (1e308, r"1e\+308 m is beyond float64 in mm"),  # (inf)
    ("1", "lengths to convert must be real numbers, got '1'"),  # (a numpy TypeError)
    (10**400, "lengths to convert must be real numbers, got 1000"),  # (an OverflowError)
])
def test_a_length_that_cannot_be_converted_is_an_input_error(value, message):
    from planar.units import convert_length

    with pytest.raises(InputError, match=message):
        convert_length(value, "m", "mm")
    with pytest.raises(InputError, match="cannot convert lengths from 'm' to \\['mm'\\]"):  # (a TypeError)
        convert_length(1.0, "m", ["mm"])


@pytest.mark.parametrize("kwargs, message", [
    (dict(bogus=1), "Units takes length, angle and rate, got 'bogus'"),  # (a TypeError)
    (dict(angle="grad"), "unknown angle unit 'grad': use one of rad, deg"),
    (dict(rate=60), "unknown rate unit 60"),
    (dict(length="m m"), "length unit must be a short label without spaces"),
    (dict(length="m\x00m"), "length unit must be a short label without spaces"),  # (drawn with a glyph warning)
    (dict(length=10**5000), "got an integer of 16610 bits"),  # (a ValueError from its repr)
])
def test_bad_units_are_input_errors(kwargs, message):
    from planar.units import Units

    with pytest.raises(InputError, match=message):
        Units(**kwargs)


@pytest.mark.parametrize("call, message", [
    (lambda u: u.angle_to_internal("1"), "angles to convert must be real numbers, got '1'"),  # (a UFuncTypeError)
    (lambda u: u.rate_to_internal(None), "rates to convert must be real numbers, got None"),  # (a TypeError)
    (lambda u: u.angle_to_internal(10**400), "angles to convert must be real numbers"),
    (lambda u: u.angle_from_internal(1e308), r"1e\+308 rad is beyond float64 in deg"),  # (inf, with a warning)
    (lambda u: u.input_to_internal(1.0, False, 3), "derivative must be 0 .*, 1 .* or 2 .*, got 3"),  # (an IndexError)
    (lambda u: u.input_from_internal(1.0, False, 1.5), "derivative must be .*, got 1.5"),  # (a TypeError)
])
def test_bad_unit_conversions_are_input_errors(call, message):
    from planar.units import Units

    with pytest.raises(InputError, match=message):
        call(Units())



@pytest.mark.parametrize("call, message", [
    (lambda: grashof(4, 2, 3, 4, rtol=-1), "rtol must be a number from 0 to 1"),  # (an IndexError)
    (lambda: grashof(4, 2, 3, 4, rtol=None), "rtol must be a number from 0 to 1"),  # (a TypeError)
    (lambda: stroke(four_bar(), "angle:rocker", samples=10.0), "stroke samples must be a whole number"),  # (TypeError)
    (lambda: stroke(four_bar(), "angle:rocker", samples=10**30), "stroke samples must be a whole number from 2"),
    (lambda: stroke(four_bar(), "angle:rocker", samples=10**5), "stroke samples must be a whole number from 2 to 10000"),
    (lambda: stroke(planar.mechanisms.slider_crank(), "x:O2"),  # (60 solves on rounding's signs: an AssemblyError)
     r"output 'x:O2' does not move over the turn \(0\): it has no stroke"),
    # (its sketch at an extreme, two samples bracket it alone: a stroke of 0 and a time ratio of inf)
    (lambda: stroke(planar.mechanisms.inverted_slider_crank(), "travel:slide", samples=2),
     "the 2 values over the turn bracket one extreme only .* give more samples"),
])
def test_bad_analysis_options(call, message):
    with pytest.raises(InputError, match=message):
        call()


@pytest.mark.parametrize("call, message", [
    (lambda p: io.save(four_bar(), None), "a mechanism file is named by a path, got None"),  # (a TypeError)
    (lambda p: io.to_dict(four_bar(), sweep="x"), "sweep must be a SweepSettings or a dict"),  # (AttributeError)
    (lambda p: io.loads(None), "a mechanism document is JSON text, got NoneType"),  # (a TypeError)
    (lambda p: io.load(io.save(four_bar(), p), length_unit=["mm"]), r"a length unit is a name .* got \['mm'\]"),
    (lambda p: io.convert_lengths(None, "mm"), "a mechanism document is a JSON object, got NoneType"),
    (lambda p: io.convert_lengths({"units": 3}, "mm"), r"units: must be a JSON object \{...\}, got 3"),  # (Attr.)
    # (a sweep's settings were read only where a file was written or swept: a TypeError, a
    # numpy ValueError, or NaN values)
    (lambda p: io.SweepSettings(start=(0.0,), stop=(90.0,), num=-5), "SweepSettings num: must be an integer of at least 2"),
    (lambda p: io.SweepSettings(start=("a",), stop=(1.0,)), r"SweepSettings start: must be a number or a list of numbers, got \('a',\)"),
    (lambda p: io.SweepSettings(start=0.0, stop=(math.nan,)), r"SweepSettings stop: must be .*, got \(nan,\)"),
    (lambda p: io.SweepSettings(start=0.0, stop=1.0, rocking="yes"), "SweepSettings rocking: must be true or false"),
    (lambda p: io.SweepSettings(start=[[1.0], [2.0, 3.0]], stop=1.0), "SweepSettings start: must be a number or a list"),
])
def test_bad_file_calls_are_file_format_errors(tmp_path, call, message):
    with pytest.raises(FileFormatError, match=message):
        call(tmp_path / "m.json")


@pytest.mark.parametrize("where", ["no folder/m", "."])
@pytest.mark.parametrize("write", [lambda p: io.save(four_bar(), p.with_suffix(".json")),
                                   lambda p: animate(four_bar().sweep([0.0, 0.1]), p.with_suffix(".gif"))],
                         ids=["save", "animate"])
def test_a_file_that_cannot_be_written_is_a_write_error_naming_it(tmp_path, where, write):
    # (a FileNotFoundError or IsADirectoryError; a WriteError is an OSError still)
    path = tmp_path / where
    if where == ".":
        (tmp_path / "m.json").mkdir()
        (tmp_path / "m.gif").mkdir()
        path = tmp_path / "m"
    with pytest.raises(planar.WriteError, match=re.escape(str(path.name))) as e:
        write(path)
    assert isinstance(e.value, OSError) and e.value.errno is not None


@pytest.mark.parametrize("call, message", [
    (lambda r, p: draw.draw(r, 12), r"pose index 12: a whole number from 0 to 11"),  # (an IndexError)
    (lambda r, p: draw.draw(r, 1.5), r"pose index 1.5"),
    (lambda r, p: draw.plot_outputs(r, ["nope"]), "unknown output 'nope'"),  # (a KeyError)
    (lambda r, p: draw.plot_outputs(r, []), "needs at least one output"),  # (a matplotlib ValueError)
    (lambda r, p: draw.figure(r, 0, points=[]), r"points to trace: name one or more of"),  # (an IndexError)
    (lambda r, p: animate(r, p, fps=0), "animate fps must be a number from 1 to 100, got 0"),  # (ZeroDivisionError)
    (lambda r, p: animate(r, p, dpi=0), "animate dpi must be a number from 20 to 1200"),  # (an IndexError)
    (lambda r, p: animate(r, p, size=None), r"animate size must be \(width, height\)"),  # (a TypeError)
    (lambda r, p: animate(r, p, progress="x"), "animate progress must be a function"),  # (a TypeError)
    (lambda r, p: animate(r, p, units="deg"), "units must be a planar.units.Units"),  # (each an AttributeError)
    (lambda r, p: io.save(four_bar(), p.with_suffix(".json"), "mm"), "units must be a planar.units.Units, .* got 'mm'"),
    (lambda r, p: animate(four_bar(), p), "animate needs a sweep result .* got Mechanism"),
    (lambda r, p: draw.draw(r, 0, ax="x"), "ax must be matplotlib axes"),
    (lambda r, p: draw.draw(r, 0, units="mm"), "units must be a planar.units.Units"),
    (lambda r, p: draw.draw_paths(r, ax=3), "ax must be matplotlib axes"),
    (lambda r, p: draw.draw_paths(four_bar().compile()), "draw_paths needs a sweep result .* got Model"),
    (lambda r, p: draw.draw_paths(None), "draw_paths needs a sweep result .* got NoneType"),
    (lambda r, p: draw.draw_event_poses(four_bar()), "draw_event_poses needs a sweep result"),
    (lambda r, p: draw.draw_instant_centres(r, 0, ax="x"), "ax must be matplotlib axes"),
    (lambda r, p: draw.plot_outputs(four_bar(), ["angle:rocker"]), "plot_outputs needs a sweep result"),
    (lambda r, p: draw.plot_outputs(r, ["angle:rocker"], ax=["x"]), "ax must be matplotlib axes"),
    (lambda r, p: draw.plot_forces(r), "plot_forces needs the forces of a sweep .* got Sweep"),
    (lambda r, p: draw.draw_forces(r), "draw_forces needs the forces of a sweep"),
    (lambda r, p: draw.draw_forces(r.forces(), scale=0), "draw_forces scale must be a positive number"),
    (lambda r, p: draw.draw_vectors(r, 0, scale=2.0), "draw_vectors scale must be \\(velocity scale, accel"),  # (TypeError)
    (lambda r, p: draw.draw_vectors(r, 0, scale=(1, -1)), "draw_vectors scale must be"),  # (arrows reversed)
    (lambda r, p: draw.draw_vectors(four_bar(), 0), "draw_vectors needs a sweep result"),
    (lambda r, p: draw.draw_vectors(r, 12), "pose index 12: a whole number from 0 to 11"),  # (an IndexError)
    (lambda r, p: draw.draw_vectors(r, None), "pose index None"),  # (an IndexError)
    (lambda r, p: draw.draw_instant_centres(r, 1.5), "pose index 1.5"),  # (an IndexError)
    (lambda r, p: draw.draw_instant_centres(four_bar()), "draw_instant_centres .* needs a sweep result"),  # (Attr.)
    (lambda r, p: draw.draw_instant_centres(None), "draw_instant_centres .* needs a sweep result"),
    (lambda r, p: draw.draw_paths(r, points=3), "points to trace: name one or more of"),  # (a TypeError)
    (lambda r, p: animate(r, p, points=3.5), "points to trace: name one or more of"),
    (lambda r, p: draw.plot_outputs(r, outputs=3), "unknown output 3"),  # (a TypeError)
])
def test_bad_drawing_arguments(tmp_path, call, message):
    res = four_bar().sweep(np.linspace(0.0, 1.0, 12))
    with pytest.raises(InputError, match=message):
        call(res, tmp_path / "a.gif")


def test_numbers_of_numpy_types_and_huge_integers_are_read_or_refused_as_numbers():
    # (motion_range's walk overflowed numpy's uint8 max_step; a move's velocity 10**400 was an
    # OverflowError)
    assert motion_range(four_bar(4, 3, 3, 3), max_step=np.uint8(3)) == motion_range(four_bar(4, 3, 3, 3), max_step=3.0)
    with pytest.raises(InputError, match="sweep velocity must be finite"):
        four_bar().track().move(0.1, velocity=10**400)


@pytest.mark.parametrize("call, message", [
    (lambda f: f.reaction(["B"]), r"unknown joint \['B'\]"),  # (a TypeError: unhashable)
    (lambda f: f.reaction("B", ["x"]), r"joint 'B' has no reaction component \['x'\]"),
    (lambda f: f.mechanical_advantage(["a"]), "output is a joint's or a moving body's name"),
    (lambda f: f.mechanical_advantage("ground"), "output is a joint's or a moving body's name"),  # (inf)
    (lambda f: f.shaking_moment("ab"), "shaking_moment about must be numeric"),  # (a numpy ValueError)
    (lambda f: f.shaking_moment((0, 0, 0)), r"shaking_moment about must have shape \(2,\)"),
])
def test_bad_force_arguments(call, message):
    m = four_bar()
    m.set_mass("coupler", 1.0, (1, 1), 0.1)
    with pytest.raises(planar.PlanarError, match=message):
        call(m.sweep([0.1, 0.2]).forces())


@pytest.mark.parametrize("call, message", [
    (lambda: planar.bar("x", (0, 0), (1, 0)), "mass must be numeric, got 'x'"),  # (a ValueError)
    (lambda: planar.disc(1, (0, 0), 1e200), "disc radius = 1e\\+200 is beyond the lengths a sketch holds"),  # (Overflow)
    (lambda: planar.plate(1, None, 1, 1), r"plate centre must have shape \(2,\), got None"),  # (a TypeError)
    (lambda: planar.bar(1.0, (0, 0), (1e90, 0)), r"the inertia 8.33333e\+178 is beyond"),
])
def test_bad_mass_helper_arguments(call, message):
    with pytest.raises(ModelError, match=message):
        call()


@pytest.mark.parametrize("call, message", [
    (lambda: synthesis.function_slider_crank(lambda x: x, (0, 1), (0, 1e8), (0, 1)),  # (a MemoryError: 9 GiB)
     "input_range spans 1e\\+08 rad, more than a turn"),
    (lambda: synthesis.function_four_bar(None, (0, 1), (0, 1), (0, 1)), "f must be a function of x, got None"),
    (lambda: synthesis.function_four_bar(lambda x: "a", (0, 1), (0, 1), (0, 1)), "f must give one number for each x"),
    (lambda: synthesis.function_four_bar(lambda x: np.array([x, x]), (0, 1), (0, 1), (0, 1)), "f must give one number"),
])
def test_bad_function_synthesis_arguments(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_angles_and_points_float64_rounds_coarser_than_the_tolerance_are_refused():
    # (a start of 1e15 was SOLVED with a residual of 2e-5, one of 3e15 walked for minutes; a
    # body drawn at 1e20 rad SOLVED with 4e-4)
    with pytest.raises(ModelError, match=r"body 'crank' is drawn at the angle 3e\+15 rad, beyond \+-8.38861e\+06"):
        four_bar(start=3e15).compile()
    with pytest.raises(ModelError, match=r"the angle of body 'slider' is 1e\+16 rad, beyond"):
        slider_crank(slide_angle=1e16).compile()
    # (so are points: a four-bar of size 4 drawn 1e15 from the origin was SOLVED with a residual
    # of 0.03, its crank 3 % off)
    with pytest.raises(ModelError, match=r"the sketch lies 1e\+15 from the world origin, 2.5e\+14 times its size 4"):
        four_bar(pivot=(1e15, 0.0)).compile()
    assert four_bar(pivot=(3e7, 0.0)).sweep([0.5]).status[0] == planar.Status.SOLVED
    m = four_bar(start=8e6)
    assert m.sweep([8e6 + 0.5]).status[0] == planar.Status.SOLVED
    with pytest.raises(InputError, match=r"sweep values of input 'crank' reach 8.5e\+06 rad, beyond"):
        m.sweep([8.5e6])
    with pytest.raises(InputError, match=r"reach 8.5e\+06 rad"):
        m.track().move(8.5e6)


def test_a_six_bar_takes_its_numbers_as_four_bar_does():
    # (its sketch read the raw arguments: a string length was a numpy UFuncTypeError)
    a, b = watt_six_bar(ground="4.5", start="1"), watt_six_bar(ground=4.5, start=1.0)
    assert np.allclose(a.compile().q0, b.compile().q0)


@pytest.mark.parametrize("call, message", [
    (lambda r: r.coordinate(["A"]), r"joint \['A'\] has no coordinate"),
    (lambda r: r.coordinate("A", "1"), "derivative must be 0, 1 or 2, got '1'"),
    (lambda r: r.coordinate("A", None), "derivative must be 0, 1 or 2"),
    (lambda r: r.coordinate("A", np.array([0, 1])), "derivative must be 0, 1 or 2"),  # (a numpy ValueError)
    (lambda r: r.coordinate("A", 1.0), "derivative must be 0, 1 or 2, got 1.0"),
    (lambda r: r.model.joint(np.array(["A", "B"])), "unknown joint"),  # (a numpy ValueError)
])
def test_bad_result_arguments(call, message):
    with pytest.raises(ModelError, match=message):
        call(four_bar().sweep([0.1, 0.2]))


@pytest.mark.parametrize("call, message", [
    (lambda a: a.instant_centres(four_bar()), "instant_centres needs a sweep result .* got Mechanism"),
    (lambda a: a.instant_centre(four_bar(), "ground", "coupler"), "instant_centre needs a sweep result"),
    (lambda a: a.transmission_angle(four_bar(), "coupler", "rocker"), "transmission_angle needs a sweep result"),
    (lambda a: a.swept_ranges(four_bar()), "swept_ranges needs a sweep result"),
    (lambda a: a.motion_range(four_bar().sweep([0.1])), "motion_range needs a Mechanism or a Model, got Sweep"),
    (lambda a: a.output(four_bar(), "angle:rocker"), "output needs a sweep result .* got Mechanism"),
    (lambda a: a.stroke(3, "angle:rocker"), "stroke needs a Mechanism, a Model or a sweep result, got int"),
    (lambda a: a.four_bar_links(four_bar()), r"four_bar_links needs a Model \(Mechanism.compile\(\)\), got Mechanism"),
])
def test_an_analysis_of_the_wrong_object_is_an_input_error(call, message):
    # (each was an AttributeError)
    with pytest.raises(InputError, match=message):
        call(planar.analysis)


@pytest.mark.parametrize("kwargs, message", [
    ({"samples": 1}, "samples must be a whole number from 2"),  # (a triple rocker came back a full turn)
    ({"samples": 10**9}, "samples must be a whole number from 2 to 10000"),
    ({"samples": 10**6}, "samples must be a whole number from 2 to 10000"),  # (over 40 s and 640 MB)
    ({"samples": 7.5}, "samples must be a whole number"),
    ({"max_step": -1}, "max_step must be a positive number"),
    ({"travel": "x"}, "travel is for a length input; 'crank' is an angle"),  # (was taken, and not used)
])
def test_bad_motion_range_arguments(kwargs, message):
    with pytest.raises(InputError, match=message):
        motion_range(four_bar(4, 3, 3, 3), **kwargs)


@pytest.mark.parametrize("travel", [-1.0, 0.0, math.inf, "far", [1.0]])
def test_a_bad_travel_is_an_input_error(travel):
    with pytest.raises(InputError, match="travel must be a positive length"):
        motion_range(slider_crank(driver="slider"), travel=travel)


def test_a_stretch_that_runs_past_the_travel_ends_there():
    # (it was a TypeError comparing None ends)
    u0 = slider_crank(driver="slider").compile().u0[0]
    assert np.allclose(motion_range(slider_crank(driver="slider"), travel=1.0), [(u0 - 1.0, u0 + 1.0)])


# ---- files ------------------------------------------------------------------------------------


def _doc():
    return io.to_dict(four_bar(), sweep={"start": 0, "stop": 90, "num": 5})


def _set(path, value):
    def edit(doc):
        *keys, last = path
        target = doc
        for k in keys:
            target = target[k]
        target[last] = value
        return doc
    return edit


FILES = [
    # (edit of a good document, or its text, message)
    (_set(["drivers"], []), "drivers: the mechanism has no driver to sweep: add 1 to drivers"),
    (_set(["sweep", "num"], 10**12), "sweep values: a run writes at most 1,000,000 rows"),
    (_set(["sweep", "num"], 1.5), "sweep.num: must be an integer of at least 2"),
    (_set(["sweep", "num"], 1), "sweep.num: must be an integer of at least 2"),
    (_set(["sweep", "stop"], 1e300), "more than the limit of 1e+08"),
    (_set(["sweep", "speed"], 1e308), "sweep velocity reaches 1e+308"),
    (_set(["sweep", "acceleration"], -1e308), "sweep acceleration reaches 1e+308"),
    (_set(["sweep", "start"], "zero"), "sweep.start: must be a number or a list of numbers"),
    (_set(["sweep", "start"], [0, 1]), "sweep.start: has 2 values but the mechanism has 1 input"),
    (_set(["sweep", "speed"], []), "sweep.speed: must be a number or a list of numbers"),
    (_set(["sweep", "rocking"], "yes"), "sweep.rocking: must be true or false"),
    (_set(["sweep", "steps"], 3), "sweep: unknown field 'steps'"),
    (_set(["units", "angle"], "grad"), "units: unknown angle unit 'grad'"),
    (_set(["units", "rate"], "rps"), "units: unknown rate unit 'rps'"),
    (_set(["bodies"], {"name": "crank"}), "bodies: must be a list"),
    (_set(["joints", 0, "at"], [0, "1"]), "joints[0].at: must be a list of two finite numbers"),
    (_set(["joints", 0, "type"], "weld"), "joints[0].type: must be one of revolute"),
    (_set(["drivers", 0], {"joint": "nope"}), "drivers[0]: unknown joint 'nope'"),
    (_set(["version"], 2), "version: this planar reads version 1 files"),
    (_set(["version"], True), "version: this planar reads version 1 files, got true"),  # (read as 1)
    ('{"name": "a", "bodies": [], "name": "b"}', "the field 'name' is given twice in one object"),  # (the last kept)
    (_set(["drivers"], [{"joint": "O2"}, {"body": "coupler"}]), "has 1 degree(s) of freedom but 2 driver(s)"),
    ('{"name": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply for a mechanism file"),
    ('{"name": ' + "[" * 20 + "]" * 20 + "}", "nested more than 16 levels deep"),
    ('{"bodies": [', "not valid JSON at line 1"),
    (b"\x89PNG\r\n\x1a\n\x00\xff", "not a text file"),
    (_set(["sweep", "start"], 10**400), "sweep.start: must be a number or a list of numbers"),
    ('{"name": 1' + "0" * 5000 + "}", "not a readable JSON number"),
    # (taken as the turns its line is counted from: a crank drawn 1e300 deg on read 0.56 rad off)
    (_set(["bodies", 0, "offset"], 1e300), "bodies[0].offset: the angle of"),
]


def _write(tmp_path, edit):
    path = tmp_path / "m.json"
    if isinstance(edit, bytes):
        path.write_bytes(edit)
    else:
        path.write_text(edit if isinstance(edit, str) else json.dumps(edit(_doc())))
    return path


@pytest.mark.parametrize("edit, message", FILES, ids=[m[:40] for _, m in FILES])
@pytest.mark.parametrize("command", ["run", "info"])
def test_bad_file_fields_exit_1_with_one_line(tmp_path, capsys, command, edit, message):
    path = _write(tmp_path, edit)
    extra = ["--no-plot", "--no-animation", "--out", tmp_path / "o"] if command == "run" else []
    code, out, err = run_or_exit(capsys, command, path, *extra)
    assert (code, err.count("\n")) == (1, 1), err
    assert err.startswith(f"planar: error: {path}: ") and message in err


@pytest.mark.parametrize("edit, message", [f for f in FILES if f[1].startswith((
    "sweep.num", "sweep.start: must", "sweep.speed", "sweep.rocking", "units", "joints", "bodies", "drivers[",
    "nested", "version"))])
def test_bad_file_fields_raise_file_format_errors(tmp_path, edit, message):
    with pytest.raises(FileFormatError) as e:
        io.load(_write(tmp_path, edit))
    assert message in str(e.value)


def test_a_path_that_is_no_regular_file_is_a_file_error(tmp_path, capsys):
    # (/dev/zero was read to a MemoryError, a pipe with no writer hung)
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    for path in (tmp_path, fifo, "/dev/zero"):
        with pytest.raises(FileFormatError, match="not a regular file"):
            io.load(path)
        code, out, err = run_or_exit(capsys, "info", path)
        assert (code, err.count("\n")) == (1, 1) and "not a regular file" in err, err
    with pytest.raises(FileFormatError, match="a mechanism file is named by a path, got None"):
        io.load(None)


def test_a_name_that_is_no_text_is_a_file_error(tmp_path, capsys):
    # (a lone surrogate loaded, then the command line failed printing it: a traceback)
    doc = _doc()
    doc["name"] = "\ud800"
    path = tmp_path / "m.json"
    path.write_text(json.dumps(doc))
    code, out, err = run_or_exit(capsys, "info", path)
    assert (code, err.count("\n")) == (1, 1) and "name: must be a string of text" in err, err


def test_a_length_unit_that_is_no_text_is_a_file_error(tmp_path, capsys):
    # (loaded; then planar run wrote its tables: a UnicodeEncodeError traceback)
    doc = _doc()
    doc["units"] = {"length": "\ud800"}
    path = tmp_path / "m.json"
    path.write_text(json.dumps(doc))
    code, out, err = run_or_exit(capsys, "run", path, "--no-plot", "--no-animation")
    assert (code, err.count("\n")) == (1, 1) and "length unit must be a short label" in err, err


def test_running_out_of_memory_is_one_line(tmp_path, capsys, monkeypatch):
    # (what fits is checked against the memory the process may have; running out anyway is one line)
    def fail(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(io, "load", fail)
    code, out, err = run_or_exit(capsys, "info", tmp_path / "m.json")
    assert (code, err.count("\n")) == (1, 1) and err.startswith("planar: error: out of memory"), err


@pytest.mark.parametrize("call, message", [
    (lambda: planar.sweep_designs(four_bar, None, [0.1]), "designs must be a dict of parameter columns"),
    (lambda: planar.sweep_designs(four_bar, 3, [0.1]), "designs must be a dict of parameter columns"),
    (lambda: planar.sweep_designs(lambda **k: 3, [{"crank": 1.0}], [0.1]),
     "design 0: <lambda> returned int: a builder of designs returns a planar.Mechanism"),
    # (an IndexError, and an OverflowError, from the designs' tables)
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), [{"O2-A": 1.0}, {"O2-A": math.nan}], [0.1]),
     "design 1: O2-A must be a finite number, got nan"),
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), [{"O2-A": 10**400}], [0.1]), "O2-A must be a finite"),
    (lambda: planar.sweep_designs(planar.Vary(four_bar()), [{"O2-A": 0}], [0.1]),  # (an IndexError)
     "no design could be built: design 0 {'O2-A': 0}: distance O2-A must be positive, got 0"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0, 2.0]}, [0.1], branch="x"), "branch must be 'smooth'"),
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0, 2.0]}, [0.1], fixed=True),  # (a TypeError)
     "fixed must be a dict of the builder's parameters by name, got True"),
    # (the first two rows were taken without a word)
    (lambda: planar.sweep_designs(four_bar, {"crank": [1.0, 2.0]}, np.zeros((3, 4, 1))),
     "values of shape \\(3, 4, 1\\) give 3 designs their values .* but there are 2 designs"),
])
def test_bad_design_arguments(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_a_builder_that_refuses_a_design_fails_that_design_only():
    def build(crank):
        if crank > 1.2:
            raise ValueError("too long a crank")
        return four_bar(crank=crank)

    study = planar.sweep_designs(build, {"crank": [1.0, 1.5]}, [0.1, 0.2])
    assert study.errors == (None, "design 1 {'crank': 1.5}: build raised ValueError: too long a crank")
    assert study[0].ok.all() and study[1] is None


PATH = [(0.0, 0.0), (1.0, 0.6), (2.0, 0.4), (2.6, -0.5), (2.0, -1.2)]
MOTION = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.3), (1.5, 0.5, 0.6)]


@pytest.mark.parametrize("call, message", [
    (lambda: synthesis.precision_points((1, 2), 10**9), "precision points must be a whole number from 1 to 10000"),
    # (a LinAlgError)
    (lambda: synthesis.freudenstein([math.nan, 1, 2], [1, 2, 3]), "th2 must be a list of finite numbers"),
    (lambda: synthesis.freudenstein("abc", [1, 2, 3]), "th2 must be a list of numbers"),
    (lambda: synthesis.freudenstein([1, 2, 3], [1, 2]), "th4 must be a list of finite numbers, one per"),
    (lambda: synthesis.freudenstein([1, 2], [1, 2]), "th2 holds 2 precision points: .* give at least three"),
    (lambda: synthesis.slider_crank_dimensions([], []), "th2 holds 0 precision points"),
    (lambda: synthesis.slider_crank_dimensions([0.1, 0.5, 0.9], [1, math.inf, 2]), "s must be a list of finite"),
    (lambda: synthesis.slider_crank_dimensions([0.1, 0.5, 0.9], [1, 2, 1e300]), "s must be slider travels within"),
    (lambda: synthesis.four_bar_lengths(None), "K must be Freudenstein's three constants"),
    (lambda: synthesis.four_bar_lengths((math.nan, 1, 1)), "Freudenstein's constants must be finite"),
    (lambda: synthesis.path_four_bar(PATH, seed=-1), "seed must be a whole number of at least 0"),
    (lambda: synthesis.path_four_bar(PATH, tol="x"), "tol must be a positive number"),
    (lambda: synthesis.path_four_bar(PATH, tol=math.inf), "tol must be a positive number"),  # (any design passed)
    (lambda: synthesis.path_four_bar(PATH, min_transmission=500), "min_transmission must be an angle from 0 to"),
    (lambda: synthesis.path_four_bar(PATH, designs=10**9), "designs must be a whole number from 1 to 1e\\+07"),
    (lambda: synthesis.path_four_bar(PATH, progress=3), "progress must be a function"),
    (lambda: synthesis.path_four_bar(PATH, timing="abcdef"), "timing must hold one finite crank angle per target"),
    (lambda: synthesis.path_four_bar(np.zeros((5000, 2))), "5000 target points, more than the limit of 50"),
    (lambda: synthesis.path_four_bar(np.c_[np.cos(np.arange(51)), np.sin(np.arange(51))]),  # (100: 26-131 s)
     "51 target points, more than the limit of 50"),
    (lambda: synthesis.path_four_bar([[1, 2], [3]]), "targets must be an \\(N, 2\\) array of finite points"),
    (lambda: synthesis.path_four_bar(-1), "targets must be an \\(N, 2\\) array of finite points"),  # (a TypeError)
    (lambda: synthesis.dyad(["x"], [0.1]), "positions must be an \\(N, 3\\) array"),  # (a numpy ValueError)
    (lambda: synthesis.path_four_bar(PATH, timing=[0.0] * len(PATH)), "crank angles 0 rad apart"),  # (a ValueError)
    (lambda: synthesis.path_four_bar(PATH, timing=[0.0, 2 * math.pi] + [1, 2, 3, 4][:len(PATH) - 2]),
     "crank angles 0 rad apart \\(modulo a turn\\)"),
    (lambda: synthesis.four_bar_lengths((1, 1, 1), ground="x"), "ground must be a positive length"),  # (ValueError)
    (lambda: synthesis.four_bar_lengths((1, 1, 1), ground=1e300), "ground must be a positive length up to"),
    (lambda: synthesis.dyad(MOTION, "ab"), "rotations must be 2 finite angles"),  # (a numpy ValueError)
    (lambda: synthesis.motion_four_bar(MOTION, beta="ab", gamma=[0.3, 0.7]), "rotations must be 2 finite angles"),
    (lambda: synthesis.path_check(None, [0, 1], PATH[:2]), "design must be a dict of four_bar's"),  # (TypeError)
    (lambda: synthesis.motion_four_bar(MOTION, beta=[0.5, 1.0], gamma=[0.3, 0.7]).save("m.json", "deg"),
     "units must be a planar.units.Units"),  # (an AttributeError)
    (lambda: synthesis.motion_four_bar(MOTION, beta=[0.5, 1.0], gamma=[0.3, 0.7]).draw(pose=3),
     "pose 3: a target's index, a whole number from 0 to 2"),  # (an IndexError)
])
def test_bad_synthesis_arguments(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_freudenstein_constants_whose_links_overflow_are_a_synthesis_error():
    with pytest.raises(SynthesisError, match="give links beyond float64"):  # (an OverflowError)
        synthesis.four_bar_lengths((1e-300, 1, 1), ground=1e10)


@pytest.mark.parametrize("tracer", [None, 3, "x"])
def test_a_six_bar_tracer_that_is_no_point_is_a_model_error(tracer):
    # (each a TypeError from unpacking it)
    with pytest.raises(ModelError, match="tracer must"):
        synthesis.stephenson_tracer(4, 2, 3, 4, coupler_point=(1, 1), link_5=3, link_6=3, pivot_6=(5, 3),
                                    tracer=tracer)


@pytest.mark.parametrize("option, message", [
    (["--seed", "-1"], "--seed -1: give a whole number of at least 0"),  # (each exited 1, after the file was read)
    (["--designs", "0"], "--designs 0: give a whole number from 1"),
    (["--tol", "nan"], "--tol nan: give a positive error"),
    (["--tol", "1e400"], "--tol inf: give a positive error"),  # (any design passed)
    (["--min-transmission", "500"], "--min-transmission 500.0: give an angle from 0 to 90 (deg)"),
    (["--points", "1000000000"], "--points 1000000000: give a whole number from 3 to 10000"),
    (["--points", "2"], "--points 2: give a whole number from 3 to 10000"),  # (exit 1, after the file was read)
    (["--beta", "1e6", "1e6"], "--beta 1000000.0 1000000.0: give rotations within a turn (+-360 deg)"),  # (it hung)
    (["--gamma", "-400", "1"], "--gamma -400.0 1.0: give rotations within a turn (+-360 deg)"),
])
def test_bad_synth_options_exit_2_with_one_line(tmp_path, capsys, option, message):
    path = tmp_path / "t.csv"
    path.write_text("x,y\n1,2\n3,4\n5,6\n")
    code, out, err = run_or_exit(capsys, "synth", "path", path, *option)
    assert (code, err.count("\n")) == (2, 1) and message in err, err


@pytest.mark.parametrize("text, message", [
    (b"x,y\n1,2,3\n1\n3,4\n", "line 2 has more values than the header has columns"),  # (an AttributeError)
    (b"x,y\n\xff\xfe,2\n", "not a CSV text file"),  # (a UnicodeDecodeError)
])
def test_a_bad_targets_file_is_one_line(tmp_path, capsys, text, message):
    path = tmp_path / "t.csv"
    path.write_bytes(text)
    code, out, err = run_or_exit(capsys, "synth", "path", path)
    assert (code, err.count("\n")) == (1, 1) and message in err, err


def test_a_targets_file_timing_one_crank_angle_twice_is_one_line(tmp_path, capsys):
    path = tmp_path / "t.csv"
    path.write_text("x,y,input\n0,0,10\n1,0,10\n1,1,20\n")
    code, out, err = run_or_exit(capsys, "synth", "path", path, "--timing")  # (a 31-line traceback)
    assert (code, err.count("\n")) == (1, 1) and "crank angles 0 rad apart" in err, err


@pytest.mark.parametrize("d", [True, 2, -3, "0", slice(0, 1), 1.0])
def test_a_design_is_picked_by_a_whole_index(d):
    study = planar.sweep_designs(four_bar, {"crank": [1.0, 1.5]}, [0.1, 0.2])
    with pytest.raises(InputError, match="a design is picked by its index, a whole number from 0 to 1"):
        study[d]
    with pytest.raises(InputError, match="a design is picked by its index"):
        study.models[d]
    assert study[-1].ok.all() and study[1].ok.all()


def test_a_file_sweep_too_large_for_memory_is_refused_before_it_is_made(monkeypatch):
    monkeypatch.setattr(arguments, "_memory", lambda: 1000)
    doc = io.from_dict(_doc())
    with pytest.raises(InputError, match=r"the sweep \(sweep.num\) of 5 values needs about"):
        doc.sweep.values(doc.mechanism.compile(), doc.units)


# ---- the command line -----------------------------------------------------------------------

COMMAND_LINES = [
    (["--dpi", "-1"], "argument --dpi: -1 is not from 20 to 1200"),
    (["--dpi", "5000"], "argument --dpi: 5000 is not from 20 to 1200"),
    (["--frames", "0"], "argument --frames: 0 is not from 2 to 2000"),
    (["--frames", "1000000"], "argument --frames: 1000000 is not from 2 to 2000"),
    (["--fps", "0"], "argument --fps: 0 is not from 1 to 100"),
    (["--num", "1"], "argument --num: 1 is not from 2 to 1000000"),
    (["--num", "1000000000"], "argument --num: 1000000000 is not from 2 to 1000000"),
    (["--circuit", "--num", "10000000"], "argument --num: 10000000 is not from 2 to 1000000"),  # (10 min, 15 GB)
    (["--num", "1e9"], "argument --num: '1e9' is not an integer"),
    (["--stop", "1e300"], "--stop: the walk through these sweep values is"),
    (["--start=-1e300", "--stop", "1e300"], "more than the limit of 1e+08"),
    (["--stop", "nan"], "argument --stop: 'nan' is not a finite number"),
    (["--start", "inf"], "argument --start: 'inf' is not a finite number"),
    (["--acceleration", "x"], "argument --acceleration: 'x' is not a number"),
    (["--start", "0", "1"], "--start: sweep.start: has 2 values but the mechanism has 1 input"),
    (["--speed", "fast"], "--speed: cannot read the speed 'fast'"),
    (["--speed", "1e999rpm"], "--speed: cannot read the speed"),
    (["--speed", "10mm/s"], "input 'crank' is an angle: give an angular rate"),
    (["--tables", "xml"], "--tables: unknown table format 'xml'"),
    (["--points", "Z"], "--points: no point or joint 'Z' in 'four_bar'"),
    (["--points", ","], "argument --points: ',' names no point: give names such as A,C"),
    (["--rate-unit", "rps"], "argument --rate-unit: invalid choice: 'rps'"),
    (["--length-unit", "km"], "argument --length-unit: invalid choice: 'km'"),
    (["--angle-unit", "grad"], "argument --angle-unit: invalid choice"),
    (["--engine", "gpu"], "argument --engine: invalid choice"),
    (["--circuit", "--start", "0"], "--circuit starts at the sketch and ends back there: drop --start and --stop"),
    (["--circuit", "--rocking"], "not allowed with argument"),
    (["--bogus"], "unrecognized arguments: --bogus"),
]


@pytest.mark.parametrize("argv, message", COMMAND_LINES, ids=[" ".join(a) for a, _ in COMMAND_LINES])
def test_bad_command_lines_exit_2_with_one_line(tmp_path, capsys, argv, message):
    path = _write(tmp_path, lambda doc: doc)
    code, out, err = run_or_exit(capsys, "run", path, "--no-animation", "--out", tmp_path / "o", *argv)
    assert (code, err.count("\n")) == (2, 1), err
    assert err.startswith("planar: error: ") and message in err
    assert not (tmp_path / "o").exists()  # refused before any work


@pytest.mark.parametrize("argv, message", [
    ([], "the following arguments are required: command"),
    (["frobnicate"], "invalid choice: 'frobnicate'"),
    (["run"], "the following arguments are required: file"),
    (["info"], "the following arguments are required: file"),
    (["example", "five_bar"], "no catalogue mechanism 'five_bar': the names are four_bar"),
    (["demo", "--num", "0"], "argument --num: 0 is not from 2"),
])
def test_bad_commands_exit_2_with_one_line(tmp_path, capsys, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_or_exit(capsys, *argv)
    assert (code, err.count("\n")) == (2, 1), err
    assert err.startswith("planar: error: ") and message in err


def test_a_file_that_is_fine_still_runs(tmp_path, capsys):
    path = _write(tmp_path, lambda doc: doc)
    code, out, err = run_or_exit(capsys, "run", path, "--no-plot", "--no-animation", "--out", tmp_path / "o")
    assert code == 0, err
    assert (tmp_path / "o" / "four_bar.csv").exists()


def test_a_length_unit_a_file_cannot_convert_is_a_file_error(tmp_path, capsys):
    path = tmp_path / "s.json"
    io.save(slider_crank(), path)  # units.length "": a label-free file
    code, out, err = run_or_exit(capsys, "info", path, "--length-unit", "mm")
    assert (code, err.count("\n")) == (1, 1), err
    assert "units.length: cannot convert lengths from 'no unit' to 'mm'" in err
