"""Progress: silent off a terminal and for quick work; a counter, or a tqdm bar, on one."""

import io
import sys

import numpy as np
import pytest

from planar.sweep import anchors
from planar.mechanisms import four_bar
from planar.progress import Progress


class Terminal(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture
def no_tqdm(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm raises ImportError


def test_nothing_is_written_off_a_terminal():
    out = io.StringIO()
    p = Progress("rows", out, delay=0.0)
    for k in range(1, 4):
        p(k, 3)
    assert out.getvalue() == ""


def test_the_counter_counts_on_a_terminal_and_ends_its_line(no_tqdm):
    out = Terminal()
    p = Progress("rows", out, delay=0.0)
    for k in range(1, 4):
        p(k, 3)
    assert out.getvalue() == "\rrows 1/3\rrows 2/3\rrows 3/3\n"


def test_quick_work_shows_nothing(no_tqdm):
    out = Terminal()
    p = Progress("frames", out, delay=3600.0)
    for k in range(1, 4):
        p(k, 3)
    assert out.getvalue() == ""


def test_a_tqdm_bar_when_tqdm_is_installed():
    pytest.importorskip("tqdm")
    out = Terminal()
    p = Progress("frames", out, delay=0.0)
    for k in range(1, 4):
        p(k, 3)
    assert p.bar and p.bar.n == 3 and "frames" in out.getvalue()


def test_a_sweep_reports_its_bulk(monkeypatch):
    seen = []

    class Record:
        def __init__(self, what):
            self.what = what

        def __call__(self, done, total):
            seen.append((self.what, done, total))

    monkeypatch.setattr(anchors, "Progress", Record)
    four_bar().sweep(np.linspace(0, 2 * np.pi, 100_000))
    assert len(seen) > 1 and seen[-1][0] == "sweep: values" and seen[-1][1] == seen[-1][2]
