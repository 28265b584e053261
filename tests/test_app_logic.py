"""The app's logic without a browser: typed fields and their refusals, units, the circuit laid
out for drawing, the single-value query, the exports, and the page's document driven from Python
(Bokeh needed for the last ones only)."""

import math
import warnings

import numpy as np
import pytest

from planar import io
from planar.analysis import instant_centre
from planar.app.forms import FORMS, Design, FileDesign, grashof_line, slider_line
from planar.app.frames import csv_text, outputs, pose_lines, solve
from planar.errors import AssemblyError, InputError
from planar.mechanisms import four_bar, slider_crank, watt_six_bar
from planar.units import Units


@pytest.mark.parametrize("text, fragment", [
    ("abc", "crank: 'abc' is not a number"),
    ("", "crank: '' is not a number"),
    ("inf", "is not a finite number"),
    ("-4", "crank: -4 cm is refused: a length must be positive"),
    ("0", "a length must be positive"),
])
def test_a_length_that_is_not_a_positive_number_is_refused_by_name(text, fragment):
    with pytest.raises(InputError, match="^crank: ") as e:
        FORMS["four_bar"].read({"crank": text}, "cm")
    assert fragment in str(e.value)


def test_signed_fields_take_negative_numbers_and_defaults_fill_the_rest():
    v = FORMS["slider_crank"].read({"offset": "-1.5", "coupler point q (left)": " -0.25 "})
    assert v["offset"] == -1.5 and v["coupler point q (left)"] == -0.25 and v["crank"] == 2.0


def test_grashof_and_slider_lines():
    assert grashof_line((4, 2, 3, 4)) == "Grashof class: crank-rocker (s + l - p - q = -1): the crank turns fully"
    assert "triple-rocker" in grashof_line((4, 3, 3, 3)) and "cannot turn fully" in grashof_line((4, 3, 3, 3))
    assert slider_line(2, 5, 1).startswith("the crank turns fully")
    assert slider_line(2, 3, 2).startswith("the crank cannot turn fully")
    assert slider_line(2, 3, 6).startswith("cannot be assembled")


def test_design_converts_the_start_angle_and_builds_the_catalogue_mechanism():
    form = FORMS["four_bar"]
    d = Design(form, form.read({"start": "60"}), Units("cm", "deg"))
    assert d.kwargs()["start"] == pytest.approx(math.pi / 3)
    assert d.kwargs()["coupler_point"] == (1.732, 1.0)
    ref = four_bar(4, 2, 3, 4, coupler_point=(1.732, 1.0), start=math.pi / 3).compile()
    assert np.allclose(d.build().compile().q0, ref.q0, atol=1e-12)
    assert d.checks() == [grashof_line((4, 2, 3, 4))]


def test_restating_lengths_in_another_unit_scales_the_numbers_not_the_mechanism():
    form = FORMS["watt_six_bar"]
    d = Design(form, form.read({}), Units("cm"))
    mm = d.restated("mm")
    assert mm.units.length == "mm" and mm.values["crank"] == pytest.approx(15.0)
    assert mm.values["start"] == d.values["start"]  # an angle
    a, b = d.build().compile(), mm.build().compile()
    assert np.allclose(b.sketch.position("E"), 10 * a.sketch.position("E"))
    inch = Design(form, form.read({}), Units("in")).restated("cm")
    assert inch.values["ground"] == pytest.approx(4 * 2.54)


def test_an_unassemblable_set_raises_the_library_error():
    form = FORMS["four_bar"]
    d = Design(form, form.read({"rocker": "10"}), Units("cm"))
    assert "triple-rocker" in d.checks()[0]
    with pytest.raises(AssemblyError, match="circles of radii 3 and 10"):
        d.build()


def test_a_file_design_edits_the_files_stated_lengths():
    data = io.to_dict(four_bar(), Units("mm"))
    f = FileDesign(data, "fb.json")
    assert [x.name for x in f.fields] == ["O2-O4", "O2-A", "A-B", "O4-B"]
    assert f.units.length == "mm"
    g = f.with_values(f.read({"O4-B": "3.5"}))
    assert g.data["dimensions"][3]["length"] == 3.5 and f.data["dimensions"][3]["length"] == 4.0
    B = g.build().compile().sketch.position("B")
    assert np.hypot(*(B - g.build().compile().sketch.position("O4"))) == pytest.approx(3.5)
    with pytest.raises(InputError, match="O2-A: 'x' is not a number"):
        f.read({"O2-A": "x"})
    with pytest.raises(AssemblyError, match="distance O4-B = 40 cannot hold"):
        f.with_values(f.read({"O4-B": "40"})).build().compile()
    cm = f.restated("cm")
    assert cm.fields[0].default == pytest.approx(0.4) and cm.units.length == "cm"


def test_the_circuit_layout_holds_every_pose_and_arrow():
    model = four_bar(coupler_point=(1.732, 1.0)).compile()
    c = solve(model, Units("cm", "deg", "rpm"), rate=60.0, samples=97)
    res = c.res
    drawn = [k for k in range(c.X.shape[1]) if k not in {i for _, i in c.centres}]
    assert c.X.shape[0] == 97 and np.all(np.isfinite(c.X[:, drawn]))
    # instant centres numbered as textbooks number bodies: I13 is where O2A and O4B meet
    i13 = dict(c.centres)["I13"]
    assert np.allclose(np.c_[c.X[:, i13], c.Y[:, i13]], instant_centre(res, "ground", "coupler"), equal_nan=True)
    assert len(c.centres) == 6
    # the pins are where the sweep puts the joints
    for name in ("A", "B"):
        assert any(np.allclose(np.c_[c.X[:, i], c.Y[:, i]], res.position(name)) for i in c.pins)
    # one crank turn at 60 rpm takes one second; the input runs 0 .. 360 deg
    assert c.time[-1] == pytest.approx(1.0) and np.all(np.diff(c.time) > 0)
    assert c.x[0] == pytest.approx(0.0) and c.x[-1] == pytest.approx(360.0)
    name, base, vel, acc = next(a for a in c.arrows if a[0] == "C")
    V = np.c_[c.X[:, vel] - c.X[:, base], c.Y[:, vel] - c.Y[:, base]]
    assert np.allclose(V, c.scales[0] * res.velocity("C"))
    assert np.allclose(res.omega("crank"), 2 * np.pi)  # 60 rpm in rad/s
    assert list(c.paths) == ["C"] and c.event_lines() == []
    assert "angle:rocker" in outputs(model) and "speed:C" in outputs(model)


def test_a_triple_rockers_circuit_marks_its_limit_positions():
    c = solve(four_bar(4, 3, 3, 3).compile(), Units("cm"), rate=1.0, samples=73)
    lines = c.event_lines()
    assert len(lines) == 2 and lines[0].startswith("limit position at crank = 117.2796 deg")
    marks = c.event_marks()
    assert [m[0] for m in marks] == ["limit", "limit"]
    for kind, i, u, pts in marks:
        assert c.x[i] == pytest.approx(u, abs=1e-6)


def test_a_slider_cranks_layout_has_its_guide_and_block():
    c = solve(slider_crank().compile(), Units("mm"), rate=10.0, samples=37)
    assert len(c.guides) == 1 and len(c.blocks) == 1
    assert np.allclose(np.c_[c.X[:, c.blocks[0]], c.Y[:, c.blocks[0]]], c.res.position("B"))


def test_the_query_solves_one_value_as_the_library_does():
    model = watt_six_bar().compile()
    lines = pose_lines(model, Units("cm", "deg", "deg/s"), 75.0, 90.0)
    res = model.sweep([math.radians(75.0)], velocity=math.radians(90.0))
    assert lines[0] == "crank = 75 deg: SOLVED"
    line = next(s for s in lines if s.startswith("link6:"))
    assert f"angle {math.degrees(res.angle('link6')[0]):.9g} deg" in line
    assert f"rate {math.degrees(res.omega('link6')[0]):.9g} deg/s" in line


def test_the_csv_export_is_the_run_table():
    c = solve(four_bar().compile(), Units("cm"), rate=1.0, samples=19)
    text = csv_text(c.res, c.units).splitlines()
    assert text[0].startswith("input:crank [deg],status,angle:crank [deg]")
    assert len(text) == 20 and text[1].split(",")[1] == "SOLVED"


# ---- the page's document, driven from Python (no browser) --------------------------------


@pytest.fixture
def page():
    pytest.importorskip("bokeh")
    from bokeh.document import Document

    from planar.app.page import Page

    return Page(Document())


def _field(page, name):
    return next(w for w in page.field_widgets if w.name == name)


def test_the_page_shows_the_library_messages_as_fields_change(page):
    assert "assembles: 721 poses" in page.message.text and "crank-rocker" in page.checks.text
    _field(page, "rocker").value_input = "10"
    assert "circles of radii 3 and 10 with centres 2 apart do not meet" in page.message.text
    assert "triple-rocker" in page.checks.text
    _field(page, "rocker").value_input = "-1"
    assert "rocker: -1 cm is refused: a length must be positive" in page.message.text
    page.rate.value_input = "0"
    _field(page, "rocker").value_input = "4"
    assert "input rate: 0 rad/s does not move the mechanism" in page.message.text
    page.rate.value_input = "10"
    assert "assembles" in page.message.text


def test_the_page_restates_units_and_sends_one_circuit(page):
    page.length.value = "mm"
    assert _field(page, "crank").value_input == "20"
    assert "assembles" in page.message.text
    N, P = len(page.track.data["x"]), page.track.data["P"][0]
    assert len(page.frames.data["x"]) == N * P == 721 * P
    page.rate_unit.value = "rpm"
    assert float(page.rate.value_input) == pytest.approx(10 * 60 / (2 * math.pi))
    page.angle.value = "rad"
    assert _field(page, "start").title == "start [rad]" and page.rate.title == "input rate [rpm]"
    assert page.track.data["x"][-1] == pytest.approx(2 * math.pi)
    page.choice.value = "slider_crank"
    assert [w.name for w in page.field_widgets][:3] == ["crank", "coupler", "offset"]
    assert "the crank turns fully" in page.checks.text and "slider_crank assembles" in page.message.text


def test_the_page_answers_a_query_and_exports(page):
    page.query.value = "60"
    assert "coupler: angle 46.0802514 deg, rate -5.43745617 rad/s" in page.answer.text
    page.query.value = "sixty"
    assert "'sixty' is not a number" in page.answer.text
    page.export("csv")
    assert page.download.data["name"] == ["four_bar.csv"]
    page.export("json")
    import base64

    doc = io.loads(base64.b64decode(page.download.data["content"][0]).decode())
    assert doc.units.length == "cm" and [d["length"] for d in doc.data["dimensions"]][:4] == [4.0, 2.0, 3.0, 4.0]


def test_the_page_opens_a_file_in_its_units_and_refuses_a_bad_one(page):
    page.open_text(io.dumps(four_bar(4, 3, 3, 3), Units("mm")), "triple.json")
    assert page.choice.value == "mechanism file" and page.length.value == "mm"
    assert [w.name for w in page.field_widgets] == ["O2-O4", "O2-A", "A-B", "O4-B"]
    assert "limit position at crank = 117.2796 deg" in page.message.text and "triple-rocker" in page.checks.text
    _field(page, "O4-B").value_input = "30"
    assert "distance O4-B = 30 cannot hold" in page.message.text
    page.open_text('{"version": 1, "bodies": 3}', "bad.json")
    assert "bad.json" in page.message.text and "planar-error" in page.message.text


@pytest.mark.parametrize("change, message", [
    # (each a traceback on the server's stderr and no message on the page)
    (lambda p: setattr(p.choice, "value", "bogus"), "unknown mechanism 'bogus': choose one of four_bar"),  # (KeyError)
    (lambda p: setattr(p.choice, "value", "mechanism file"), "no mechanism file is open"),  # (AttributeError)
    (lambda p: setattr(p.output, "value", "bogus"), "unknown output 'bogus'"),  # (KeyError)
    (lambda p: setattr(p.output, "value", "angle:nobody"), "unknown output 'angle:nobody'"),  # (the InputError, raised)
    (lambda p: setattr(p.angle, "value", "grad"), "unknown angle unit 'grad'"),  # (the InputError, raised)
    (lambda p: setattr(p.rate_unit, "value", "hz"), "unknown rate unit 'hz'"),
    # (a binascii.Error; with no file name, bokeh's UnsetValueError)
    (lambda p: p.opener.set_from_json("value", "!!!not base64") or p._shown(p.open_file), "not a text file"),
    (lambda p: p.open_text('{"version": 1}', "x.json"), "has no driver and nothing to drive"),  # (an IndexError)
    (lambda p: setattr(p.rate, "value_input", "1e-308"), "input rate: 1e-308 rad/s is beyond what the page times"),
])
def test_values_a_client_sends_that_the_page_did_not_offer_are_messages(page, change, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (a tiny rate overflowed the circuit's time axis)
        change(page)
    assert message in page.message.text and "planar-error" in page.message.text


def test_a_start_that_overflows_in_another_angle_unit_stays_as_typed(page):
    page.angle.value = "rad"
    _field(page, "start").value_input = "1e308"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (1e308 rad in degrees overflowed, with numpy's warning)
        page.angle.value = "deg"
    assert _field(page, "start").value_input == "1e308" and "planar-error" in page.message.text


def test_forces_are_offered_for_a_mechanism_with_masses_and_match_the_library():
    m = slider_crank(2.0, 5.0, offset=1.0)
    m.set_mass("slider", 3.0, com=m.sketch().points["B"][1])
    m.gravity = (0.0, -9.81)
    model = m.compile()
    assert "effort:crank" in outputs(model) and "reaction:B" in outputs(model)
    assert "effort:crank" not in outputs(slider_crank().compile())
    c = solve(model, Units("m"), rate=4 * np.pi, samples=37)
    f = c.res.forces()
    assert np.allclose(c.series("effort:crank"), f.driver_effort("crank"), equal_nan=True)
    assert np.allclose(c.series("reaction:B"), np.hypot(*f.reaction("B").T), equal_nan=True)
    from planar.app.frames import output_label

    assert output_label("effort:crank", c.units, model) == "driving effort of crank [N m]"
    assert output_label("reaction:B", Units("mm"), model) == "reaction force of B [kg mm/s^2]"


def test_the_page_exports_a_gif(page):
    import base64

    page.export("gif")
    assert page.download.data["name"] == ["four_bar.gif"] and page.download.data["mime"] == ["image/gif"]
    assert base64.b64decode(page.download.data["content"][0]).startswith(b"GIF89a")


# ---- the command -------------------------------------------------------------------------


def test_planar_app_refuses_a_bad_file_before_serving(tmp_path, capsys):
    from planar.cli import main

    pytest.importorskip("bokeh")
    bad = tmp_path / "bad.json"
    bad.write_text(io.dumps(four_bar(), Units("cm")).replace('"length": 3.0', '"length": 30.0'))
    assert main(["app", str(bad), "--no-browser"]) == 1
    assert "cannot hold with the others" in capsys.readouterr().err
    assert main(["app", str(tmp_path / "none.json"), "--no-browser"]) == 1


def test_planar_app_stops_on_ctrl_c_and_refuses_a_busy_port():
    import signal
    import socket
    import subprocess
    import sys
    import time
    from pathlib import Path

    pytest.importorskip("bokeh")
    root = Path(__file__).resolve().parents[1]
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        busy = s.getsockname()[1]
        done = subprocess.run([sys.executable, "-m", "planar.cli", "app", "--port", str(busy), "--no-browser"],
                              cwd=root, capture_output=True, text=True, timeout=120)
        assert done.returncode == 2 and f"--port {busy}: cannot serve on 127.0.0.1:{busy}" in done.stderr
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen([sys.executable, "-m", "planar.cli", "app", "--port", str(port), "--no-browser"],
                            cwd=root, stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().startswith(f"planar app: http://127.0.0.1:{port}/")
        time.sleep(0.5)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
