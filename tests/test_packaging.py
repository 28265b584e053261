"""What a newcomer meets first: the version, the licence, short reprs, readable statuses."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import planar
from planar.mechanisms import four_bar

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("module", ["planar", "planar.cli"])
def test_version_from_the_package_and_the_command(module):
    assert re.fullmatch(r"\d+(\.\d+)*\S*|0\+unknown", planar.__version__)
    done = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)
    assert done.returncode == 0
    assert done.stdout.strip() == f"planar {planar.__version__}"


def test_licence_and_distribution_name():
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    text = (ROOT / "pyproject.toml").read_text()
    assert 'name = "planar-kinematics"' in text


def test_install_hints_name_the_distribution():
    for path in [ROOT / "README.md", *ROOT.glob("docs/*.md"), *ROOT.glob("planar/**/*.py")]:
        hints = re.findall(r"pip install [\"']?planar\b(?!-kinematics)", path.read_text())
        assert not hints, f"{path.name}: install hint names the package index's 'planar', another project"


def test_status_prints_its_name():
    assert str(planar.Status.SOLVED) == "SOLVED"
    assert f"{planar.Status.NOT_CONVERGED}" == "NOT_CONVERGED"
    assert f"{planar.Status.NOT_CONVERGED:d}" == "5" and f"{planar.Status.LIMIT:>6}" == " LIMIT"
    assert planar.Status.SOLVED == 0 and planar.Status(7) is planar.Status.LIMIT


def test_short_reprs():
    m = four_bar()
    assert repr(m) == "<Mechanism 'four_bar': 3 moving bodies, 4 joints, 1 driver(s)>"
    model = m.compile()
    assert repr(model) == "<Model 'four_bar': 3 moving bodies, 4 joints, dof 1, inputs ['crank']>"
    assert str(model) == repr(model)
    res = model.sweep(np.radians([0.0, 90.0]))
    assert repr(res) == "Sweep('four_bar', N=2, inputs=['crank'], {'SOLVED': 2})"


def test_plot_outputs_returns_a_list_of_axes():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.axes import Axes

    from planar import draw

    axes = draw.plot_outputs(four_bar().sweep(np.radians(np.arange(0.0, 361.0, 30.0))))
    assert isinstance(axes, list) and axes and all(isinstance(a, Axes) for a in axes)
    import matplotlib.pyplot as plt

    plt.close(axes[0].figure)
