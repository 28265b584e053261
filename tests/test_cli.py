"""The command line end to end in a temporary folder, its outputs, and its error paths with
their exit codes."""

import csv
import importlib.util
import json
import subprocess
import sys

import numpy as np
import pytest

from planar import cli, io
from planar.mechanisms import CATALOGUE
from planar.units import Units


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_demo_writes_plot_animation_csv_and_file(here, capsys):
    code, out, err = run(capsys, "demo", "--num", "25", "--frames", "8", "--dpi", "40")
    assert code == 0, err
    files = sorted(p.name for p in (here / "planar-demo").iterdir())
    assert files == ["four_bar.csv", "four_bar.gif", "four_bar.json", "four_bar.png", "four_bar_outputs.png"]
    assert "1 degree(s) of freedom" in out and "25 solved" in out and "coupler: angle" in out
    rows = list(csv.reader(open(here / "planar-demo" / "four_bar.csv")))
    assert len(rows) == 26 and rows[0][:3] == ["input:crank [deg]", "status", "angle:crank [deg]"]
    head = rows[0]
    # the seed's case: crank at 60 deg, 10 rad/s (row 5 of 25 over one turn: 60 deg)
    row = dict(zip(head, rows[5]))
    assert float(row["input:crank [deg]"]) == pytest.approx(60.0)
    assert float(row["omega:rocker [rad/s]"]) == pytest.approx(1.4309095175803546, rel=1e-9)
    assert float(row["vx:C [cm/s]"]) == pytest.approx(-6.764952520133216, rel=1e-9)
    assert "progress" not in out and "\r" not in out  # no progress indicator off a terminal


def test_example_then_run_with_rpm_and_json(here, capsys):
    code, out, _ = run(capsys, "example")
    assert code == 0 and all(name in out for name in CATALOGUE)
    code, out, _ = run(capsys, "example", "slider_crank", "-o", "sc.json")
    assert code == 0 and (here / "sc.json").exists()
    code, out, err = run(capsys, "run", "sc.json", "--num", "13", "--speed", "60rpm", "--tables", "csv,json",
                         "--no-animation", "--no-plot", "--out", "o")
    assert code == 0, err
    rows = list(csv.reader(open(here / "o" / "slider_crank.csv")))
    head = rows[0]
    assert len(rows) == 14 and "omega:crank [rpm]" in head and "travel:slide" in head
    assert float(dict(zip(head, rows[3]))["omega:crank [rpm]"]) == pytest.approx(60.0)
    table = json.loads((here / "o" / "slider_crank.json").read_text())
    assert len(table["columns"]["status"]) == 13 and table["units"]["omega:crank"] == "rpm"
    assert "stroke" in out


def test_run_defaults_to_a_folder_named_after_the_file(here, capsys):
    io.save(CATALOGUE["four_bar"](), here / "fb.json")
    code, out, err = run(capsys, "run", "fb.json", "--no-animation", "--num", "5", "--start", "0", "--stop", "40",
                         "--angle-unit", "deg", "--rate-unit", "deg/s")
    assert code == 0, err
    assert (here / "fb-out" / "four_bar.png").exists() and (here / "fb-out" / "four_bar_outputs.png").exists()
    rows = list(csv.reader(open(here / "fb-out" / "four_bar.csv")))
    assert [float(r[0]) for r in rows[1:]] == pytest.approx([0.0, 10.0, 20.0, 30.0, 40.0], rel=1e-15)
    assert "omega:crank [deg/s]" in rows[0]


@pytest.mark.numba
def test_run_on_the_compiled_engine_writes_the_same_table(here, capsys):
    io.save(CATALOGUE["four_bar"](), here / "fb.json")
    tables = []
    for engine in ("numpy", "numba"):
        code, out, err = run(capsys, "run", "fb.json", "--num", "2000", "--engine", engine, "--no-plot",
                             "--no-animation", "--out", engine)
        assert code == 0, err
        tables.append(list(csv.reader(open(here / engine / "four_bar.csv"))))
    head = tables[0][0]
    assert tables[1][0] == head and len(tables[0]) == 2001
    status = head.index("status")
    assert [r[status] for r in tables[0]] == [r[status] for r in tables[1]]
    a, b = (np.array([[float(v) for k, v in enumerate(r) if k != status] for r in t[1:]]) for t in tables)
    np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9)


def test_rocking_run_goes_there_and_back(here, capsys):
    io.save(CATALOGUE["four_bar"](4, 3, 3, 3), here / "rocker.json")  # a triple rocker
    # (--dpi at its lowest: the animation's, 3/4 of it, was refused)
    code, out, err = run(capsys, "run", "rocker.json", "--start", "-150", "--stop", "150", "--num", "21",
                         "--rocking", "--frames", "6", "--dpi", "20", "--no-plot")
    assert code == 0, err
    assert "there and back" in out and "limit position at crank = 117.28 deg" in out
    assert "assembles over -117.28 to 117.28; 117.28 to -117.28 (input crank [deg])" in out
    assert (here / "rocker-out" / "four_bar.gif").exists()
    rows = list(csv.reader(open(here / "rocker-out" / "four_bar.csv")))
    assert len(rows) == 1 + 41


def test_circuit_run_traces_the_whole_circuit_from_the_sketch(here, capsys):
    io.save(CATALOGUE["four_bar"](4, 3, 3, 3), here / "rocker.json")  # a triple rocker, sketched at 0
    code, out, err = run(capsys, "run", "rocker.json", "--circuit", "--num", "41", "--speed", "2",
                         "--frames", "6", "--dpi", "30", "--no-plot")
    assert code == 0, err
    assert "circuit: input crank [deg] from 0 to 0 turning back at 2 limit(s), 41 values: 39 solved, 2 limit" in out
    assert "limit position at crank = 117.28 deg" in out and "limit position at crank = -117.28 deg" in out
    assert (here / "rocker-out" / "four_bar.gif").exists()
    rows = list(csv.reader(open(here / "rocker-out" / "four_bar.csv")))
    rows = [dict(zip(rows[0], r)) for r in rows[1:]]
    crank = [float(r["input:crank [deg]"]) for r in rows]
    # up to one limit, down to the other, back to the sketch; the rate follows the motion
    assert len(rows) == 41 and crank[0] == crank[-1] == 0.0
    assert max(crank) == pytest.approx(117.27961273597809, abs=1e-9) and min(crank) == pytest.approx(-max(crank))
    assert [r["status"] for r in rows].count("LIMIT") == 2
    assert {r["omega:crank [rad/s]"] for r in rows if r["status"] == "SOLVED"} == {"2.0", "-2.0"}
    # the circuit starts at the sketch: start and stop do not apply, nor does rocking
    code, _, err = run(capsys, "run", "rocker.json", "--circuit", "--start", "10")
    assert code == 2 and "drop --start and --stop" in err
    with pytest.raises(SystemExit) as e:
        cli.main(["run", "rocker.json", "--circuit", "--rocking"])
    assert e.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


def test_info_of_a_four_bar_names_its_grashof_class_and_strokes(here, capsys):
    io.save(CATALOGUE["four_bar"](4, 2, 3, 4), here / "fb.json")
    code, out, err = run(capsys, "info", "fb.json")
    assert code == 0, err
    assert "Grashof class: crank-rocker (links 4, 2, 3, 4: s + l - p - q = -1); the input turns fully" in out
    assert "rocker: stroke 63.0029 deg, time ratio 1.424266" in out
    assert "motion range of crank: a full turn" in out
    io.save(CATALOGUE["four_bar"](4, 3, 3, 3), here / "rocker.json")
    code, out, err = run(capsys, "info", "rocker.json")
    assert "Grashof class: triple-rocker" in out and "the input cannot turn fully" in out
    assert "motion range of crank: -117.28 to 117.28 deg" in out


def test_info(here, capsys):
    io.save(CATALOGUE["geared_five_bar"](), here / "g5.json")
    code, out, err = run(capsys, "info", "g5.json")
    assert code == 0, err
    assert "mobility: 12 coordinates, 11 joint rows: Grubler 1, rank 11, 1 degree(s) of freedom" in out
    assert "redundant joints: none" in out
    assert "Grashof class:" in out and "sweep:" in out and "events:" in out


@pytest.mark.parametrize("argv, code, message", [
    (["run", "missing.json"], 1, "cannot read the file"),
    (["info", "bad.json"], 1, "not valid JSON at line 1"),
    (["run", "field.json"], 1, r"joints[0].at: must be a list of two finite numbers"),
    (["run", "ok.json", "--speed", "fast"], 2, "cannot read the speed 'fast'"),
    (["run", "ok.json", "--num", "1"], 2, "--num: 1 is not from 2 to"),
    (["run", "ok.json", "--tables", "xls", "--no-plot", "--no-animation"], 2, "unknown table format 'xls'"),
    (["run", "ok.json", "--tables", ",", "--no-plot", "--no-animation"], 2, "--tables ',' names no table format"),
    (["run", "ok.json", "--start", "0", "1"], 2, "sweep.start: has 2 values but the mechanism has 1 input"),
    (["example", "five_bar"], 2, "no catalogue mechanism 'five_bar'"),
    (["run"], 2, "the following arguments are required: file"),
    (["frobnicate"], 2, "invalid choice"),
    (["run", "ok.json", "--out", "blocker/x", "--no-animation"], 3, "cannot write"),
])
def test_error_paths(here, capsys, argv, code, message):
    (here / "bad.json").write_text('{"bodies": [')
    doc = io.to_dict(CATALOGUE["four_bar"]())
    io.save(CATALOGUE["four_bar"](), here / "ok.json")
    doc["joints"][0]["at"] = [0]
    (here / "field.json").write_text(json.dumps(doc))
    (here / "blocker").write_text("a file where a folder should be")
    got, out, err = run_or_exit(capsys, *argv)
    assert got == code
    assert message in err and err.startswith("planar: error:") and err.count("\n") == 1


def run_or_exit(capsys, *argv):
    """Exit code, stdout and stderr of the command line, whether it returns or exits (argparse)."""
    try:
        code = cli.main([str(a) for a in argv])
    except SystemExit as e:
        code = e.code
    out, err = capsys.readouterr()
    return code, out, err


def test_console_entry_point_and_exit_code(here):
    """The installed command (or python -m planar.cli) returns the exit codes."""
    ok = subprocess.run([sys.executable, "-m", "planar.cli", "example", "four_bar", "-o", "f.json"],
                        capture_output=True, text=True, cwd=here)
    assert ok.returncode == 0 and (here / "f.json").exists()
    bad = subprocess.run([sys.executable, "-m", "planar.cli", "info", "nothing.json"], capture_output=True,
                         text=True, cwd=here)
    assert bad.returncode == 1 and "planar: error:" in bad.stderr


def test_progress_only_on_a_terminal():
    class Tty:
        def __init__(self, tty):
            self.tty, self.text = tty, ""

        def isatty(self):
            return self.tty

        def write(self, s):
            self.text += s

        def flush(self):
            pass

    import planar.progress

    for tqdm in (None, "installed"):  # the counter without tqdm, tqdm's bar with it
        with pytest.MonkeyPatch.context() as mp:
            if tqdm is None:
                mp.setitem(sys.modules, "tqdm", None)
            elif importlib.util.find_spec("tqdm") is None:
                continue
            for tty, delay in ((True, 0.0), (False, 0.0), (True, 60.0)):
                stream = Tty(tty)
                p = planar.progress.Progress("frame", stream, delay=delay)
                p(1, 2)
                p(2, 2)
                if tty and delay == 0.0:
                    assert "frame" in stream.text  # tqdm clears its bar when done
                    assert tqdm or stream.text == "\rframe 1/2\rframe 2/2\n"
                else:  # off a terminal, or work done before the delay: nothing
                    assert stream.text == ""


def test_default_sweep_is_a_turn_or_a_travel():
    units = Units()
    s = cli.default_sweep(CATALOGUE["four_bar"]().compile(), units)
    assert s.stop[0] - s.start[0] == pytest.approx(360.0) and s.num == 73
    m = CATALOGUE["slider_crank"](driver="slider").compile()
    s = cli.default_sweep(m, units)
    assert s.stop[0] - s.start[0] == pytest.approx(0.5 * m.L)
    assert np.isclose(0.5 * (s.start[0] + s.stop[0]), m.u0[0])


def test_the_csv_table_in_pieces_reads_back_every_number_and_quotes_its_header(monkeypatch):
    from io import StringIO

    from planar.cli import tables

    monkeypatch.setattr(tables, "ROWS", 3)  # three pieces and a short one
    x = np.array([0.1, 1 / 3, np.nan, 2.0, 1e-300, -np.inf, 7.0])
    status = np.array(["SOLVED", "SOLVED", "NOT_ASSEMBLABLE", "LIMIT", "SOLVED", "NOT_ASSEMBLABLE", "SOLVED"])
    cols = [("input:crank", "deg", x), ("status", "", status), ('n, "q"', "", np.arange(7))]
    pieces = list(tables.csv_chunks(cols))
    assert [done for _, done in pieces] == [0, 3, 6, 7]
    rows = list(csv.reader(StringIO("".join(text for text, _ in pieces))))
    assert rows[0] == ["input:crank [deg]", "status", 'n, "q"']
    assert [r[0] for r in rows[1:]] == ["0.1", repr(1 / 3), "", "2.0", "1e-300", "", "7.0"]
    assert [float(r[0]) for r in rows[1:] if r[0]] == [v for v in x if np.isfinite(v)]
    assert [r[1] for r in rows[1:]] == status.tolist() and [r[2] for r in rows[1:]] == [repr(float(k)) for k in range(7)]
