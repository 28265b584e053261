"""Every script in examples/ runs and prints exactly the output recorded beside it
(examples/NAME.out), and writes the figure it names."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).parents[1] / "examples"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))


def test_every_example_has_its_output():
    assert {p.stem for p in SCRIPTS} == {p.stem for p in EXAMPLES.glob("*.out")}
    assert len(SCRIPTS) >= 6


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_example_runs_and_prints_its_recorded_output(script, tmp_path):
    run = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True,
                         cwd=tmp_path, timeout=300,
                         env=dict(os.environ, PYTHONPATH=str(EXAMPLES.parent), MPLBACKEND="Agg"))
    assert run.returncode == 0, run.stderr
    assert run.stdout == script.with_suffix(".out").read_text()
    for line in run.stdout.splitlines():
        if line.startswith("wrote "):
            assert (tmp_path / line.split()[1]).stat().st_size > 0
