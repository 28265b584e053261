"""``planar app`` end to end in a real browser: headless Debian chromium driven by Playwright's
Python API loads the page, edits lengths and sees the library's messages, plays, drags the
input, reads the plotted values back from the page and checks them against the library.

Skipped where Bokeh, Playwright or /usr/bin/chromium is missing (``.ci/run`` installs them).
"""

import contextlib
import math
import os
import re
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("bokeh")
sync_api = pytest.importorskip("playwright.sync_api")

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]
ROOT = Path(__file__).resolve().parents[1]

if not os.path.exists(CHROMIUM):
    pytest.skip(f"no browser at {CHROMIUM} (apt-get install chromium)", allow_module_level=True)


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def running_app(*args):
    """``planar app`` in a subprocess on a free 127.0.0.1 port: yields its address; stopped on exit."""
    port = _free_port()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen([sys.executable, "-m", "planar.cli", "app", *args, "--port", str(port), "--no-browser"],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(f"planar app did not start: {proc.stdout.read() if proc.poll() is not None else ''}")
                time.sleep(0.2)
        yield f"http://127.0.0.1:{port}/"
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@pytest.fixture(scope="module")
def server():
    with running_app() as url:
        yield url


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


@pytest.fixture
def page(server, browser):
    context = browser.new_context(viewport={"width": 1600, "height": 1000}, accept_downloads=True)
    pg = context.new_page()
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.goto(server)
    pg.locator("span.planar-input").wait_for(timeout=30000)
    yield pg
    context.close()
    assert errors == [], errors


def _message(pg):
    return " ".join(pg.locator(".planar-message").all_inner_texts())


def _wait_message(pg, fragment, timeout=20):
    deadline = time.monotonic() + timeout
    while fragment not in _message(pg):
        if time.monotonic() > deadline:
            raise AssertionError(f"{fragment!r} not in the page's messages: {_message(pg)!r}")
        time.sleep(0.05)


def _readout(pg):
    """(input, output name, output, status) as the page prints them for the pose shown."""
    return (float(pg.locator("span.planar-input").inner_text()), pg.locator("span.planar-output-name").inner_text(),
            float(pg.locator("span.planar-output").inner_text()), pg.locator("span.planar-status").inner_text())


def _type(pg, field, text):
    box = pg.locator(f".planar-field-{field} input")
    box.fill(text)


def test_edit_see_the_library_messages_play_and_read_a_value_back(page):
    from planar.mechanisms import four_bar

    pg = page
    _wait_message(pg, "Grashof class: crank-rocker")
    _type(pg, "rocker", "10")
    _wait_message(pg, "circles of radii 3 and 10 with centres 2 apart do not meet")  # the AssemblyError
    _wait_message(pg, "Grashof class: triple-rocker")
    _type(pg, "rocker", "abc")
    _wait_message(pg, "rocker: 'abc' is not a number")
    _type(pg, "rocker", "-4")
    _wait_message(pg, "rocker: -4 cm is refused: a length must be positive")
    _type(pg, "rocker", "3.5")
    _wait_message(pg, "assembles: 721 poses")
    before = _readout(pg)

    pg.locator(".planar-play button").click()
    time.sleep(1.0)
    pg.locator(".planar-play button").click()
    time.sleep(0.3)
    x, name, y, status = _readout(pg)
    assert x != before[0] and status == "SOLVED"
    assert name == "angle of rocker [deg]"
    res = four_bar(4, 2, 3, 3.5, coupler_point=(1.732, 1.0)).sweep([math.radians(x)])
    assert y == pytest.approx(math.degrees(res.angle("rocker")[0]), abs=1e-8)

    # one value exactly, as the library solves it
    pg.locator(".planar-query input").fill("60")
    pg.locator(".planar-query input").press("Enter")
    pg.locator("pre.planar-pose").wait_for(timeout=20000)
    text = pg.locator("pre.planar-pose").inner_text()
    res = four_bar(4, 2, 3, 3.5, coupler_point=(1.732, 1.0)).sweep([math.radians(60)], velocity=10.0)
    assert f"rocker: angle {math.degrees(res.angle('rocker')[0]):.9g} deg, rate {res.omega('rocker')[0]:.9g} rad/s" in text

    with pg.expect_download() as download:
        pg.locator(".planar-export-csv button").click()
    rows = Path(download.value.path()).read_text().splitlines()
    assert rows[0].startswith("input:crank [deg],status") and len(rows) == 722


def test_a_six_bar_follows_the_dragged_input(page):
    from planar.mechanisms import watt_six_bar

    pg = page
    pg.locator(".planar-choice select").select_option("watt_six_bar")
    _wait_message(pg, "watt_six_bar assembles: 721 poses")
    handle = pg.locator(".planar-scrub .noUi-handle")
    box = pg.locator(".planar-scrub .noUi-base").bounding_box()
    h = handle.bounding_box()
    pg.mouse.move(h["x"] + h["width"] / 2, h["y"] + h["height"] / 2)
    pg.mouse.down()
    for k in range(1, 21):
        pg.mouse.move(box["x"] + box["width"] * 0.3 * k / 20, h["y"] + h["height"] / 2)
    pg.mouse.up()
    time.sleep(0.3)
    x, name, y, status = _readout(pg)
    assert 60 < x < 150 and status == "SOLVED"
    spec = re.fullmatch(r"angle of (\w+) \[deg\]", name)
    assert spec, name
    res = watt_six_bar().sweep([math.radians(x)])
    assert y == pytest.approx(math.degrees(res.angle(spec.group(1))[0]), abs=1e-8)


def test_open_a_mechanism_file_edit_its_stated_length_and_export_it(page, tmp_path):
    from planar import io
    from planar.mechanisms import four_bar
    from planar.units import Units

    pg = page
    path = io.save(four_bar(4, 3, 3, 3), tmp_path / "triple.json", Units("mm"))
    pg.locator(".planar-open input[type=file]").set_input_files(str(path))
    _wait_message(pg, "limit position at crank = 117.2796 deg")  # the circuit's limits, from the file
    _wait_message(pg, "Grashof class: triple-rocker")
    # (the page's choice follows its messages: under load, a moment later)
    sync_api.expect(pg.locator(".planar-choice select")).to_have_value("mechanism file", timeout=20000)
    _type(pg, "O4-B", "3.5")
    _wait_message(pg, "Grashof class: triple-rocker (s + l - p - q = 0.5)")
    with pg.expect_download() as download:
        pg.locator(".planar-export-json button").click()
    back = io.load(download.value.path())
    assert back.units.length == "mm" and back.data["dimensions"][3]["length"] == 3.5
