"""Mechanism files and units: exact round trips (every catalogue builder, and hypothesis over
random mechanisms of every joint type), validation that names the field, and fuzzed files that
only ever fail with FileFormatError."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import planar
from planar import io
from planar.errors import FileFormatError
from planar.mechanisms import CATALOGUE
from planar.units import Units

SETTINGS = settings(max_examples=200, deadline=None)


# ---- round trips -------------------------------------------------------------------------------

def same_mechanism(a, b):
    """Bodies, points, joints and drivers equal bit for bit (directions, which the builder
    normalises again on reading, to one unit in the last place)."""
    assert a.name == b.name
    assert drawn_angles(a) == pytest.approx(drawn_angles(b), rel=0, abs=1e-14)
    a, b = a.sketch(), b.sketch()
    assert [isinstance(v, tuple) and v for v in a.bodies.values()] == [isinstance(v, tuple) and v for v in b.bodies.values()]
    assert a.dimensions == b.dimensions
    if a.dimensions:  # without dimensions the sketch shows the starts, and files leave them out
        assert a.starts == pytest.approx(b.starts, rel=1e-14, abs=1e-300)
    assert sorted(a.points) == sorted(b.points)  # joint points come with their joints
    for k in a.points:
        assert a.points[k][0] == b.points[k][0] and np.array_equal(a.points[k][1], b.points[k][1])
    for ja, jb in zip(a.joints + a.drivers, b.joints + b.drivers, strict=True):
        assert type(ja) is type(jb) and ja.name == jb.name and ja.bodies == jb.bodies
        assert ja.data.keys() == jb.data.keys()
        for key in ja.data:
            if key == "direction":
                np.testing.assert_allclose(ja.data[key], jb.data[key], rtol=0, atol=4e-16)
            else:
                assert np.array_equal(ja.data[key], jb.data[key]), (ja.name, key)


def drawn_angles(m):
    """Each body's angle in the sketch as drawn: a number given, else its line's direction (its
    named line, or the default one), else 0."""
    out, sk = [], m.sketch()
    for b, spec in sk.bodies.items():
        line = spec if isinstance(spec, tuple) else m.reference_line(b) if b != "ground" and spec is None else None
        if line is None or not set(line) <= set(sk.points):
            out.append(0.0 if spec is None or isinstance(spec, tuple) else spec)
        else:
            d = sk.points[line[1]][1] - sk.points[line[0]][1]
            out.append(math.atan2(d[1], d[0]))
    return out


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_every_catalogue_builder_round_trips(name, tmp_path):
    mech = CATALOGUE[name]()
    path = io.save(mech, tmp_path / f"{name}.json", Units(length="mm"))
    doc = io.load(path)
    same_mechanism(mech, doc.mechanism)
    assert io.dumps(doc) == path.read_text()  # a written file reads and writes back the same
    m1, m2 = mech.compile(), doc.mechanism.compile()
    u = m1.u0 + np.linspace(0, 0.3, 4)[:, None]
    r1, r2 = m1.sweep(u), m2.sweep(u)
    np.testing.assert_array_equal(r1.status, r2.status)
    np.testing.assert_allclose(r1.q, r2.q, rtol=0, atol=1e-12 * m1.L)


# hypothesis: random mechanisms built from every joint type (the builder's checks must pass,
# the mechanism need not move: files describe any mechanism)
coord = st.floats(-50, 50, allow_nan=False).map(lambda v: round(v, 6) if abs(v) > 1e-3 else v)
point = st.tuples(coord, coord)
radius = st.floats(0.01, 20)
angle = st.floats(-10, 10)


@st.composite
def mechanisms(draw):
    n = draw(st.integers(1, 5))
    m = planar.Mechanism(draw(st.text(min_size=1, max_size=12)))
    bodies = [m.add_body(f"b{k}", angle=draw(angle)).name for k in range(n)]
    allb = ["ground"] + bodies
    for k in range(draw(st.integers(1, 7))):
        a, b = draw(st.lists(st.sampled_from(allb), min_size=2, max_size=2, unique=True))
        kind = draw(st.sampled_from(["revolute", "prismatic", "slot", "gear", "carrier_gear", "rack_pinion",
                                     "rolling"]))
        name = f"j{k}"
        at = np.array(draw(point))
        u = np.array([math.cos(t := draw(angle)), math.sin(t)])
        if kind == "revolute":
            m.add_revolute(name, a, b, at=at)
        elif kind in ("prismatic", "slot"):
            origin = at + draw(st.floats(-5, 5)) * u if draw(st.booleans()) else None
            getattr(m, f"add_{kind}")(name, a, b, at=at, direction=u * draw(st.floats(0.1, 10)), origin=origin)
        elif kind in ("gear", "carrier_gear"):
            ra, rb, internal = draw(radius), draw(radius), draw(st.booleans())
            if internal and ra == rb:
                rb = ra * 1.5
            cb = at + abs(ra + (-rb if internal else rb)) * u
            if kind == "gear":
                m.add_gear(name, a, b, ra, rb, internal=internal, centre_a=at, centre_b=cb,
                           hold_distance=draw(st.booleans()))
            else:
                c = draw(st.sampled_from([x for x in allb if x not in (a, b)] or [None]))
                if c is None:
                    continue
                m.add_gear(name, a, b, ra, rb, internal=internal, carrier=c, centre_a=at, centre_b=cb)
        else:
            r, side = draw(radius), draw(st.sampled_from(["left", "right"]))
            sign = 1 if side == "left" else -1
            centre = at + sign * r * np.array([-u[1], u[0]])
            getattr(m, f"add_{kind}")(name, a, b, r, centre=centre, through=at, direction=u, side=side)
    for k in range(draw(st.integers(0, 3))):
        p = f"p{k}"
        m.add_point(p, draw(st.sampled_from(allb)), at=draw(point))
    named = sorted(m.sketch().points)
    for k in range(draw(st.integers(0, 3)) if len(named) > 1 else 0):
        a, b = draw(st.lists(st.sampled_from(named), min_size=2, max_size=2, unique=True))
        try:
            m.distance(a, b, draw(radius))
        except planar.ModelError:
            pass  # not on one body, or stated already
    joints = [j.name for j in m.sketch().joints if j.coordinate() is not None]
    for k in range(draw(st.integers(0, 3))):
        how = draw(st.sampled_from(["joint", "body", "point"]))
        start = draw(st.none() | st.floats(-5, 5))
        try:
            if how == "joint" and joints:
                m.drive(draw(st.sampled_from(joints)), name=draw(st.sampled_from([None, f"d{k}"])), start=start)
            elif how == "body":
                m.drive(body=draw(st.sampled_from(bodies)), start=start)
            elif m.sketch().points:
                m.drive(point=draw(st.sampled_from(sorted(m.sketch().points))), axis=draw(st.sampled_from("xy")),
                        start=start)
        except planar.ModelError:
            pass  # the same driver twice: skip it
    return m


@SETTINGS
@given(mechanisms(), st.sampled_from(["deg", "rad"]))
def test_random_mechanisms_round_trip_exactly(mech, angle_unit):
    units = Units(length="mm", angle=angle_unit, rate="rpm")
    sweep = io.SweepSettings(start=(0.0,), stop=(90.0,), num=7, speed=(30.0,), rocking=True)
    text = io.dumps(mech, units, sweep)
    doc = io.loads(text)
    same_mechanism(mech, doc.mechanism)
    assert io.dumps(doc) == text
    assert doc.units == units and doc.sweep == sweep


# ---- validation names the field ------------------------------------------------------------------

def four_bar_doc():
    return io.to_dict(CATALOGUE["four_bar"](coupler_point=(1.0, 0.5)), Units(), io.SweepSettings(start=(0.0,), stop=(360.0,)))


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d["joints"][1].pop("at"), r"joints\[1\]: missing field 'at'"),
    (lambda d: d["joints"][0].update(at=[0, "x"]), r"joints\[0\]\.at: must be a list of two finite numbers"),
    (lambda d: d["joints"][2].update(type="hinge"), r"joints\[2\]\.type: must be one of revolute"),
    (lambda d: d["joints"][0].update(dirction=[1, 0]), r"joints\[0\]: unknown field 'dirction'"),
    (lambda d: d["joints"][3].update(bodies=["rocker", "nowhere"]), r"joints\[3\] \(revolute 'O4'\): unknown body 'nowhere'"),
    (lambda d: d["joints"][3].update(bodies=["rocker"]), r"joints\[3\]\.bodies: must be a list of two body names"),
    (lambda d: d["bodies"][0].update(angle="ninety"), r"bodies\[0\]\.angle: must be a finite number"),
    (lambda d: d["bodies"].append({"name": "crank"}), r"bodies\[3\]: the name 'crank' is already used"),
    (lambda d: d["points"][0].update(body=""), r"points\[0\]\.body: must be a non-empty string"),
    (lambda d: d["drivers"][0].update(axis="z"), r"drivers\[0\]\.axis: must be \"x\" or \"y\""),
    (lambda d: d["drivers"].append({"joint": "Q"}), r"drivers\[1\]: unknown joint 'Q'"),
    (lambda d: d["units"].update(angle="grad"), r"units: unknown angle unit 'grad'"),
    (lambda d: d.update(version=2), r"version: this planar reads version 1 files"),
    (lambda d: d.update(colour="red"), r"file: unknown field 'colour'"),
    (lambda d: d["sweep"].update(num=1), r"sweep\.num: must be an integer of at least 2"),
    (lambda d: d["sweep"].pop("stop"), r"sweep: missing field 'stop'"),
    (lambda d: d.update(joints={}), r"joints: must be a list"),
])
def test_validation_names_the_field(mutate, message):
    d = four_bar_doc()
    mutate(d)
    with pytest.raises(FileFormatError, match=message):
        io.from_dict(d, "four_bar.json")


def test_gear_and_rack_geometry_errors_name_the_joint():
    d = io.to_dict(CATALOGUE["gear_train"]())
    gear = next(k for k, j in enumerate(d["joints"]) if j["type"] == "gear")
    d["joints"][gear]["radius_b"] *= 2
    with pytest.raises(FileFormatError, match=rf"joints\[{gear}\] \(gear .*centres are .* apart"):
        io.from_dict(d)
    d = io.to_dict(CATALOGUE["rack_and_pinion"]())
    rack = next(k for k, j in enumerate(d["joints"]) if j["type"] == "rack_pinion")
    d["joints"][rack]["radius"] = -1
    with pytest.raises(FileFormatError, match=rf"joints\[{rack}\]\.radius: must be a positive number"):
        io.from_dict(d)


@pytest.mark.parametrize("text, message", [
    ('{"joints": [', "not valid JSON at line 1"),
    ("", "not valid JSON"),
    ("[1, 2]", "file: must be a JSON object"),
    ('{"bodies": [{"name": "a", "angle": NaN}]}', r"bodies\[0\]\.angle: must be a finite number"),
])
def test_malformed_and_truncated_text(text, message):
    with pytest.raises(FileFormatError, match=message):
        io.loads(text)


def test_missing_and_binary_files(tmp_path):
    with pytest.raises(FileFormatError, match="cannot read the file"):
        io.load(tmp_path / "nothing.json")
    (tmp_path / "bin.json").write_bytes(b"\xff\xfe\x00")
    with pytest.raises(FileFormatError, match="not a text file"):
        io.load(tmp_path / "bin.json")


def test_truncated_files_fail_cleanly():
    text = io.dumps(CATALOGUE["slider_crank"](), Units())
    for cut in range(0, len(text) - 3, 7):
        with pytest.raises(FileFormatError):
            io.loads(text[:cut])


junk = st.one_of(st.none(), st.booleans(), st.integers(-3, 3), st.floats(allow_nan=True), st.text(max_size=4),
                 st.lists(st.floats(-5, 5), max_size=3), st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))


@SETTINGS
@given(st.data())
def test_mutated_files_load_or_raise_file_format_error(data):
    doc = four_bar_doc()
    # pick a random place in the document and put junk there, or delete it
    node, path = doc, []
    while isinstance(node, (dict, list)) and node and data.draw(st.booleans()):
        key = data.draw(st.sampled_from(sorted(node) if isinstance(node, dict) else range(len(node))))
        path.append(key)
        node = node[key]
    if not path:
        return
    parent = doc
    for key in path[:-1]:
        parent = parent[key]
    if data.draw(st.booleans()) and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = data.draw(junk)
    try:
        text = json.dumps(doc)
    except ValueError:
        return
    try:
        io.loads(text)
    except FileFormatError:
        pass


# ---- sweep settings --------------------------------------------------------------------------------

def test_sweep_settings_in_file_units():
    model = CATALOGUE["four_bar"]().compile()
    s = io.SweepSettings(start=(0.0,), stop=(180.0,), num=3, speed=(60.0,), acceleration=(0.0,), rocking=True)
    U, Ud, Udd = s.values(model, Units(angle="deg", rate="rpm"))
    np.testing.assert_allclose(U[:, 0], np.radians([0, 90, 180, 90, 0]), rtol=1e-15)
    np.testing.assert_allclose(Ud[:, 0], 2 * np.pi * np.array([1, 1, 1, -1, -1]), rtol=1e-15)
    assert np.all(Udd == 0)
    back = io.SweepSettings(start=(90.0,), stop=(0.0,), num=2, speed=(-10.0,))
    assert np.all(back.values(model, Units(rate="deg/s"))[1] < 0)  # speed is a size; the sweep sets the sign
    with pytest.raises(FileFormatError, match="sweep.start: has 2 values but the mechanism has 1 input"):
        io.SweepSettings(start=(0.0, 1.0), stop=(1.0,)).values(model, Units())
    # a number for one input, numpy's numbers: as a file holds them
    given = io.SweepSettings(start=0, stop=np.array([90.0]), num=np.int64(3), rocking=np.bool_(False))
    assert given == io.SweepSettings(start=(0.0,), stop=(90.0,), num=3)
    assert type(given.num) is int and type(given.rocking) is bool


def _bodies(angle):
    return {"version": 1, "name": "x", "bodies": [{"name": "a", "angle": angle}], "joints": [], "drivers": []}


def _without_types():
    d = four_bar_doc()
    for j in d["joints"]:
        del j["type"]
    return d


@pytest.mark.parametrize("call, error, message", [
    # (each a TypeError from the JSON encoder, a KeyError, a TypeError or a ValueError)
    (lambda p: io.from_dict(_bodies(1 + 1j)), FileFormatError,
     r"<mechanism file>: bodies\[0\]\.angle: must be JSON \(numbers, .*\), got \(1\+1j\): give plain Python numbers"),
    (lambda p: io.from_dict(_bodies(object())), FileFormatError, r"bodies\[0\]\.angle: must be JSON .* got <object object"),
    (lambda p: io.from_dict(_bodies(np.zeros(2))), FileFormatError, r"bodies\[0\]\.angle: must be JSON .* got array\("),
    (lambda p: io.from_dict(_bodies(10**5000)), FileFormatError, r"bodies\[0\]\.angle: .* got an integer of 16610 bits"),
    (lambda p: io.from_dict({"version": np.array([1, 2])}), FileFormatError, r"version: must be JSON .* got array"),
    (lambda p: io.from_dict({"version": 1, 2: 3, "colour": 4}), FileFormatError, r"file: unknown field 2: the fields here"),
    (lambda p: io.from_dict({"version": 1, (2, 3): 4}), FileFormatError, r"file: must be JSON .* got the field name \(2, 3\)"),
    (lambda p: io.from_dict({"units": {"length": np.array(["m", "mm"])}}), FileFormatError, r"units\.length: must be JSON"),
    (lambda p: io.convert_lengths(_without_types(), "mm"), FileFormatError, r"joints\[0\]\.type: must be one of revolute"),
    (lambda p: io.convert_lengths({"points": [1.0]}, ""), FileFormatError, r"points\[0\]: must be a JSON object"),
    (lambda p: io.convert_lengths({"units": {"length": "m"}, "dimensions": [1.0]}, "mm"), FileFormatError,
     r"dimensions\[0\]: must be a JSON object"),
    (lambda p: io.convert_lengths({**four_bar_doc(), "units": {"length": "m"}}, ""), FileFormatError,
     r"units\.length: cannot convert lengths from 'm' to 'no unit'"),
    (lambda p: io.load(p.with_name("m\x00.json")), FileFormatError,
     r"'.*m\\x00\.json': a file name cannot hold a NUL byte \('\\x00'\); name the file without it"),
    (lambda p: io.save(CATALOGUE["four_bar"](), "\x00"), planar.WriteError,
     r"a file name cannot hold a NUL byte \('\\x00'\); name the file without it: '\\x00'"),
])
def test_bad_documents_and_paths_name_the_field_or_the_file(tmp_path, call, error, message):
    with pytest.raises(error, match=message):
        call(tmp_path / "m.json")


def test_save_refuses_what_is_not_a_mechanism(tmp_path):
    with pytest.raises(FileFormatError, match="can only save"):
        io.save({"bodies": []}, tmp_path / "x.json")


def test_every_joint_class_has_a_file_form():
    from planar.joints import FILE_TYPES, JOINT_TYPES

    joints = [cls for cls in JOINT_TYPES if not cls.is_driver]
    kinds = {"Revolute": "revolute", "Prismatic": "prismatic", "Slot": "slot", "CarrierGear": "gear",
             "Gear": "gear", "RollingContact": "gear", "RackPinion": "rack_pinion"}
    assert sorted(c.__name__ for c in joints) == sorted(kinds)
    assert set(kinds.values()) | {"rolling"} == set(FILE_TYPES)
