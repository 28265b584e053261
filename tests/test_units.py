"""Units at the edges: lengths in m, cm, mm, in; angles in deg, rad; rates in rad/s, deg/s, rpm;
files restated in another length unit; the command line's --length-unit, --rate-unit and
--speed with and without units."""

import csv
import json
import math

import numpy as np
import pytest

from planar import cli, io
from planar.errors import FileFormatError, InputError
from planar.mechanisms import gear_train, slider_crank
from planar.units import LENGTH_UNITS, Units, convert_length, parse_rate

METRES = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}


@pytest.mark.parametrize("source", LENGTH_UNITS)
@pytest.mark.parametrize("target", LENGTH_UNITS)
def test_every_length_unit_converts_to_every_other(source, target):
    got = convert_length(np.array([1.0, 2.5, -40.0]), source, target)
    np.testing.assert_allclose(got, np.array([1.0, 2.5, -40.0]) * METRES[source] / METRES[target], rtol=1e-15)
    np.testing.assert_allclose(convert_length(got, target, source), [1.0, 2.5, -40.0], rtol=1e-15)


@pytest.mark.parametrize("value, source, target, want", [
    (25.4, "mm", "in", 1.0), (1.0, "in", "cm", 2.54), (1.0, "m", "mm", 1000.0), (12.0, "in", "m", 0.3048),
    (7.0, "cm", "cm", 7.0), (3.0, "furlong", "furlong", 3.0)])
def test_lengths_convert_exactly_where_the_result_is_exact(value, source, target, want):
    assert float(convert_length(value, source, target)) == want


@pytest.mark.parametrize("source, target", [("", "mm"), ("mm", ""), ("furlong", "m"), ("m", "km")])
def test_a_length_without_a_convertible_unit_is_refused_by_name(source, target):
    with pytest.raises(InputError, match="lengths convert between m, cm, mm, in"):
        convert_length(1.0, source, target)


@pytest.mark.parametrize("unit, one_in_internal", [("rad", 1.0), ("deg", math.pi / 180)])
def test_angles(unit, one_in_internal):
    u = Units(angle=unit)
    assert float(u.angle_to_internal(90.0)) == pytest.approx(90.0 * one_in_internal, rel=1e-15)
    assert float(u.angle_from_internal(u.angle_to_internal(90.0))) == pytest.approx(90.0, rel=1e-15)


@pytest.mark.parametrize("unit, one_in_rad_s", [("rad/s", 1.0), ("deg/s", math.pi / 180), ("rpm", math.pi / 30)])
def test_rates(unit, one_in_rad_s):
    u = Units(rate=unit)
    assert float(u.rate_to_internal(60.0)) == pytest.approx(60.0 * one_in_rad_s, rel=1e-15)
    assert float(u.rate_from_internal(u.rate_to_internal(60.0))) == pytest.approx(60.0, rel=1e-15)


def test_speeds_with_length_units_parse():
    assert parse_rate("40mm/s") == (40.0, "mm/s")
    assert parse_rate("1.5 in/s") == (1.5, "in/s")
    for bad in ("40mm", "1e400rpm", "nan", "10 km/s"):
        with pytest.raises(InputError, match="cannot read the speed"):
            parse_rate(bad)


def _file(mech, length, tmp_path, name="m.json", **sweep):
    data = io.to_dict(mech, Units(length=length), sweep or None)
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


def test_a_file_restated_in_another_length_unit_scales_every_length(tmp_path):
    # a slider input (a length) and gears (radii): every length scales, angles do not
    mech = slider_crank(2.0, 5.0, offset=1.0, driver="slider", coupler_point=(1.0, 0.5))
    path = _file(mech, "in", tmp_path, start=6.8, stop=3.2, num=5, speed=2.0, acceleration=0.5)
    inches, mm = io.load(path), io.load(path, length_unit="mm")
    assert mm.units.length == "mm" and mm.data["units"]["length"] == "mm"
    assert mm.sweep.start == (6.8 * 25.4,) and mm.sweep.speed == (2.0 * 25.4,) and mm.sweep.acceleration == (0.5 * 25.4,)
    a = inches.mechanism.sweep(np.linspace(6.8, 3.2, 5))
    b = mm.mechanism.sweep(np.linspace(6.8, 3.2, 5) * 25.4)
    np.testing.assert_allclose(b.position("C"), a.position("C") * 25.4, rtol=1e-12)
    np.testing.assert_allclose(b.angle("coupler"), a.angle("coupler"), rtol=1e-12)
    gears = io.load(_file(gear_train((1.0, 2.0)), "cm", tmp_path, "g.json"), length_unit="m")
    assert [j["radius_a"] for j in gears.data["joints"] if j["type"] == "gear"] == [0.01]


def test_a_file_without_a_convertible_length_unit_is_refused(tmp_path):
    path = _file(slider_crank(), "", tmp_path)
    with pytest.raises(FileFormatError, match="units.length: cannot convert lengths from 'no unit' to 'mm'"):
        io.load(path, length_unit="mm")


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _table(path):
    rows = list(csv.reader(open(path)))
    return [dict(zip(rows[0], r)) for r in rows[1:]]


def test_rate_unit_applies_when_the_speed_names_its_own_unit(tmp_path, capsys):
    path = _file(slider_crank(), "mm", tmp_path, start=0, stop=90, num=3)
    code, _, err = run(capsys, "run", path, "--speed", "10rad/s", "--rate-unit", "deg/s", "--no-plot",
                       "--no-animation", "--out", tmp_path / "o")
    assert code == 0, err
    row = _table(tmp_path / "o" / "slider_crank.csv")[0]
    assert float(row["omega:crank [deg/s]"]) == pytest.approx(10.0 * 180 / math.pi, rel=1e-14)
    code, _, err = run(capsys, "run", path, "--speed", "60rpm", "--no-plot", "--no-animation", "--out", tmp_path / "p")
    assert float(_table(tmp_path / "p" / "slider_crank.csv")[0]["omega:crank [rpm]"]) == pytest.approx(60.0)
    code, _, err = run(capsys, "run", path, "--speed", "3", "--rate-unit", "rpm", "--no-plot", "--no-animation",
                       "--out", tmp_path / "q")
    assert float(_table(tmp_path / "q" / "slider_crank.csv")[0]["omega:crank [rpm]"]) == pytest.approx(3.0)


def test_rate_unit_restates_the_files_speed_and_acceleration(tmp_path, capsys):
    path = _file(slider_crank(), "mm", tmp_path, start=0, stop=90, num=3, speed=1.0, acceleration=2.0)
    code, _, err = run(capsys, "run", path, "--rate-unit", "deg/s", "--no-plot", "--no-animation", "--out", tmp_path / "o")
    assert code == 0, err
    row = _table(tmp_path / "o" / "slider_crank.csv")[0]
    assert float(row["omega:crank [deg/s]"]) == pytest.approx(180 / math.pi, rel=1e-14)
    assert float(row["alpha:crank [deg/s^2]"]) == pytest.approx(2.0 * 180 / math.pi, rel=1e-14)


def test_length_unit_on_the_command_line(tmp_path, capsys):
    path = _file(slider_crank(2.0, 5.0, offset=1.0, driver="slider"), "cm", tmp_path, start=6.8, stop=3.2, num=3)
    code, out, err = run(capsys, "run", path, "--length-unit", "mm", "--speed", "2cm/s", "--no-plot",
                         "--no-animation", "--out", tmp_path / "o")
    assert code == 0, err
    rows = _table(tmp_path / "o" / "slider_crank.csv")
    assert [float(r["input:slide [mm]"]) for r in rows] == pytest.approx([68.0, 50.0, 32.0], rel=1e-14)
    assert float(rows[0]["travel_rate:slide [mm/s]"]) == pytest.approx(-20.0, rel=1e-14)
    code, out, err = run(capsys, "info", path, "--length-unit", "in")
    assert code == 0, err
    assert "slide: travel 1.25984 in to 2.67717 in" in out
    code, out, err = run(capsys, "run", path, "--speed", "10rpm", "--no-plot", "--no-animation", "--out", tmp_path / "p")
    assert code != 0 and "input 'slide' is a length: give a length per second" in err


def test_units_convert_at_the_edges():
    u = Units(length="mm", angle="deg", rate="rpm")
    assert u.angle_to_internal(180.0) == pytest.approx(math.pi, rel=1e-15)
    assert u.rate_to_internal(60.0) == pytest.approx(2 * math.pi, rel=1e-15)
    assert u.rate_from_internal(2 * math.pi) == pytest.approx(60.0, rel=1e-15)
    assert u.acceleration == "rad/s^2" and Units(rate="deg/s").acceleration == "deg/s^2"
    assert Units(rate="deg/s").acceleration_to_internal(180.0) == pytest.approx(math.pi)
    # radians pass through bit for bit
    assert Units(angle="rad").angle_to_internal(0.1) == 0.1
    # lengths are labels, never converted
    assert u.input_to_internal(3.0, is_length=True, derivative=1) == 3.0
    assert u.label("speed") == "mm/s" and u.input_label(False, 1) == "rpm"


@pytest.mark.parametrize("kwargs, field", [({"angle": "grad"}, "angle"), ({"rate": "rps"}, "rate"),
                                           ({"length": "m m"}, "length")])
def test_units_reject_unknown_units(kwargs, field):
    with pytest.raises(InputError, match=field):
        Units(**kwargs)


def test_parse_rate():
    assert parse_rate("120rpm") == (120.0, "rpm")
    assert parse_rate(" -2.5 rad/s ") == (-2.5, "rad/s")
    assert parse_rate("1e1deg/s") == (10.0, "deg/s")
    assert parse_rate("3") == (3.0, None)
    with pytest.raises(InputError, match="120rpm"):
        parse_rate("fast")
