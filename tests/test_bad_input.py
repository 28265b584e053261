"""Every bad argument, file field and command line is refused up front by a PlanarError naming
it and the fix; the command line prints one line and exits 2 for a bad command line, 1 for a bad
file; sizes that cannot fit in memory or time are refused with the limit named."""

import json
import math

import numpy as np
import pytest

import planar
from planar import arguments, io
from planar.errors import FileFormatError, InputError, ModelError
from planar.mechanisms import four_bar, slider_crank
from tests.test_cli import run_or_exit

SWEEP_CALLS = [
    # (values, options, error, message)
    ([], {}, InputError, "the sweep has no values: give at least one"),
    (np.zeros((0, 1)), {}, InputError, "the sweep has no values"),
    ([0.1], {"max_step": 0}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": -0.1}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": math.nan}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": math.inf}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": "big"}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": True}, InputError, "max_step must be a positive number"),
    ([0.1], {"max_step": 1e-300}, InputError, "more than the limit of 1e+08"),
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
    ([0.1], {"outputs": ["nope"]}, InputError, "unknown output 'nope'"),
    ([0.1], {"outputs": 3}, InputError, "outputs must be a name or a list of names of bodies, points or joints, got 3"),
    ([0.1], {"outputs": ["rocker", None]}, InputError, "outputs must be a name or a list of names"),
    ([[0.1, 0.2]], {}, InputError, "sweep values have shape (1, 2) but 1 input(s) ['crank'] need"),
    ([math.nan], {}, InputError, "sweep values must be finite"),
    (["a"], {}, InputError, "sweep values must be numbers"),
    (0.1, {}, InputError, "must be a sequence of input values, got a scalar"),
    ([0.0, 1e300], {}, InputError, "continuation steps of max_step = 0.05, more than the limit of 1e+08"),
    ([1e308, -1e308], {}, InputError, "more than the limit of 1e+08"),
    ([0.0, 1e7], {}, InputError, "more than the limit of 1e+08: sweep a shorter span"),
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
    ({"acceleration": "fast"}, "sweep acceleration must be numbers"),
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
    ({"samples": 1}, "samples must be a whole number of at least 2"),
    ({"samples": 10.5}, "samples must be a whole number"),
    ({"velocity": math.nan}, "velocity must be one finite number"),
])
def test_bad_circuit_arguments(kwargs, message):
    with pytest.raises(InputError, match=message):
        four_bar().circuit(**kwargs)


@pytest.mark.parametrize("value", ["a", None, object(), [[1.0], [2.0]]])
def test_a_tracker_move_to_no_number_is_an_input_error(value):
    with pytest.raises(InputError, match="move takes a number|sweep values"):
        four_bar().compile().track().move(value)


def test_a_design_parameter_the_builder_does_not_take_is_an_input_error():
    with pytest.raises(InputError, match=r"design 0 \{'nope': 1\}: four_bar refused its parameters .* name only"):
        planar.sweep_designs(four_bar, [{"nope": 1}], [0.1])


def test_a_sweep_larger_than_memory_is_refused_with_the_limit(monkeypatch):
    monkeypatch.setattr(arguments, "_memory", lambda: 2**30)  # a machine with 1 GiB
    model = four_bar().compile()
    with pytest.raises(InputError, match=r"the sweep of 10000000 values needs about 3.35 GiB for its results, "
                                         r"more than this machine's 1 GiB of memory: sweep fewer values"):
        arguments.size(model, 10_000_000)
    with pytest.raises(InputError, match="the circuit of 100000000 values needs about"):
        model.circuit(samples=100_000_000)
    model.sweep(np.linspace(0.0, 1.0, 1000))  # what fits still runs


@pytest.mark.parametrize("call, message", [
    (lambda m: m.add_body("b", angle="x"), r"angle of body 'b' \(a number, or a line \(p, q\) of two point names\) must be numeric"),
    (lambda m: m.add_body(""), "body name must be a non-empty string"),
    (lambda m: m.add_revolute("J", m.ground, "nobody", at=(0, 0)), "unknown body 'nobody'"),
    (lambda m: m.add_revolute("J", m.ground, m.ground, at=(0, 0)), "joins body 'ground' to itself"),
    (lambda m: m.add_point("P", m.ground, at=(0, math.nan)), "'P' at must be finite"),
    (lambda m: m.add_slot("S", m.ground, m.ground, at=(0, 0), direction=(1, 0)), "to itself"),
    (lambda m: m.drive(), "drive needs exactly one of joint=, body= or point="),
    (lambda m: m.drive("nope"), "unknown joint 'nope'"),
])
def test_bad_builder_arguments(call, message):
    with pytest.raises(ModelError, match=message):
        call(planar.Mechanism())


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
    (_set(["sweep", "num"], 10**12), "sweep values: a run writes at most 10,000,000 rows"),
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
    (_set(["drivers"], [{"joint": "O2"}, {"body": "coupler"}]), "has 1 degree(s) of freedom but 2 driver(s)"),
    ('{"name": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply for a mechanism file"),
    ('{"name": ' + "[" * 20 + "]" * 20 + "}", "nested more than 16 levels deep"),
    ('{"bodies": [', "not valid JSON at line 1"),
    (b"\x89PNG\r\n\x1a\n\x00\xff", "not a text file"),
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
    (["--num", "1"], "argument --num: 1 is not from 2 to 10000000"),
    (["--num", "1000000000"], "argument --num: 1000000000 is not from 2 to 10000000"),
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
