"""What branch certification costs: a sweep with it beside the same sweep without it.

Certification is the test ``planar.acceptance.certified(off, sing)`` on every accepted step (the
correction no more than CERT times the singularity measure, which the sweep computes anyway
for its statuses) and the gap bound of the tracer at crossings. Without it, every converged
step in the same assembly modes is accepted. Both run in interleaved rounds (best of each,
as ``sweep_speed.rounds``); the last column is the largest difference of the two results
(scaled coordinates), which is zero where no step was refused.

    python3 benchmarks/certification_cost.py            # N = 1e3 .. 1e5, numpy engine
    python3 benchmarks/certification_cost.py --quick    # N = 1e3, one round (a smoke run)
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from planar.sweep import branch  # noqa: E402  (Branch.accept reads its certified)
from planar.mechanisms import four_bar, slider_crank, watt_six_bar  # noqa: E402
from sweep_speed import rounds  # noqa: E402

CASES = {
    "four-bar": lambda: four_bar(4, 2, 3, 3.5, coupler_point=(1.0, 0.5)),
    "four-bar, avoided crossing 3e-5": lambda: four_bar(4, 2, 3, 3.00003, start=3.0),
    "slider-crank": lambda: slider_crank(2, 5, offset=1),
    "Watt six-bar": watt_six_bar,
}
REPEAT = 5


def uncertified(off, sing):
    """Every converged step accepted (the assembly-mode and jump tests still apply)."""
    return np.ones(np.shape(off), bool)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 1e3, one round (a smoke run)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000])
    args = ap.parse_args(argv)
    sizes, repeat = ([1000], 1) if args.quick else (args.sizes, REPEAT)
    kept = branch.certified
    print(f"{'mechanism':32s} {'N':>7s} {'certified us/val':>16s} {'without':>8s} {'cost':>6s}  results apart")
    for name, build in CASES.items():
        model = build().compile()
        for N in sizes:
            u = model.u0[0] + np.linspace(0.0, 2 * np.pi, N)

            def without():
                branch.certified = uncertified
                try:
                    return model.sweep(u)
                finally:
                    branch.certified = kept

            best = rounds({"certified": lambda: model.sweep(u), "without": without}, repeat)
            a, b = model.sweep(u), without()
            both = a.ok & b.ok
            scale = np.where(np.arange(model.n) % 3 == 2, 1.0, 1.0 / model.L)
            apart = float(np.max(np.abs(a.q[both] - b.q[both]) * scale, initial=0.0))
            c, w = best["certified"] * 1e6 / N, best["without"] * 1e6 / N
            print(f"{name:32s} {N:7d} {c:16.3f} {w:8.3f} {c / w - 1:+6.1%}  {apart:.1e}")


if __name__ == "__main__":
    main()
