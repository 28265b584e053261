"""Kinetostatics speed: ``Sweep.forces()`` beside the sweep it reads, and its error.

For each mechanism (random masses, centres, inertias and loads, gravity; seeded) and N, the
time per value of the sweep (positions, velocities, accelerations) and of ``res.forces()`` on
it, best of rounds that call both (as ``sweep_speed.rounds``), their ratio; the time per value
of the kinematic block factors at the solved poses, chunk by chunk (the Jacobian's evaluation
and the blocks' LU, which ``forces()`` forms again rather than keep the sweep's: what keeping
them would save);
and the largest virtual power residual (driver power against d/dt (kinetic + potential
energy) - load power), relative to the largest term.

    python3 benchmarks/forces_speed.py             # N = 1e3 .. 1e5
    python3 benchmarks/forces_speed.py --quick     # N = 1e3, one round (a smoke run)
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from planar.blocks import plan  # noqa: E402
from planar.mechanisms import four_bar, gear_train, slider_crank, watt_six_bar  # noqa: E402
from planar.system import chunks  # noqa: E402
from sweep_speed import rounds  # noqa: E402
from tests.test_forces import add_mass_points, virtual_power  # noqa: E402

CASES = {"four-bar": four_bar, "slider-crank": slider_crank, "Watt six-bar": watt_six_bar, "gear train": gear_train}
REPEAT = 5


def case(build):
    """The model with masses and loads, and the loads for the virtual power check."""
    m = build()
    loads = add_mass_points(m, np.random.default_rng(1), [b for b in m.sketch().bodies if b != "ground"])
    return m.compile(), loads


def factors(p, res):
    """The kinematic block factors at the solved poses of ``res``, chunk by chunk as
    ``forces()`` forms them."""
    for sl in chunks(len(res)):
        p.factor(p.evaluate(res.q[sl], res.inputs[sl])[2], dets=False)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 1e3, one round (a smoke run)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000])
    args = ap.parse_args(argv)
    sizes, repeat = ([1000], 1) if args.quick else (args.sizes, REPEAT)
    print(f"{'mechanism':14s} {'N':>8s} {'sweep us/val':>12s} {'forces us/val':>13s} {'ratio':>6s} "
          f"{'factors us/val':>14s}  virtual power error")
    for name, build in CASES.items():
        model, loads = case(build)
        p = plan(model)
        for N in sizes:
            u = model.u0[0] + np.linspace(0.0, 2 * np.pi, N)
            res = model.sweep(u, velocity=10.0, acceleration=3.0)
            best = rounds({"sweep": lambda: model.sweep(u, velocity=10.0, acceleration=3.0),
                           "forces": lambda: res.forces(),
                           "factors": lambda: factors(p, res)}, repeat)
            drive, rest, scale = virtual_power(res, loads)
            err = np.nanmax(np.abs(drive - rest)) / np.nanmax(scale)
            s, f, k = (best[key] * 1e6 / N for key in ("sweep", "forces", "factors"))
            print(f"{name:14s} {N:8d} {s:12.3f} {f:13.3f} {f / s:6.2f} {k:14.3f}  {err:.1e}")


if __name__ == "__main__":
    main()
