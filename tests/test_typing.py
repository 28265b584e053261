"""The package type-checks: mypy over planar/ with the settings in pyproject.toml."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_mypy_finds_no_errors():
    pytest.importorskip("mypy")
    done = subprocess.run([sys.executable, "-m", "mypy", "planar", "--no-incremental"], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr


def test_typed_marker_ships():
    assert (ROOT / "planar" / "py.typed").is_file()
