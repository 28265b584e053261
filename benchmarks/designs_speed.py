"""Many designs of one structure: D random crank-rocker four-bars with coupler points, each over
N = 180 crank angles, swept by planar.sweep_designs (the designs folded into the solver's batch
axis), beside the closed form vectorised over all designs at once (positions, velocities and
accelerations of the coupler point) and planar's per-design loop (build, compile and sweep
each design alone). Prints the time per design and per value, the ratios to the closed form,
the largest error of the coupler point against the closed form, and the peak memory
(numpy allocations, tracemalloc) of the batch call.

    python3 benchmarks/designs_speed.py                        # D = 1e2, 1e3, 1e4
    python3 benchmarks/designs_speed.py --designs 100 1000     # a shorter run
    python3 benchmarks/designs_speed.py --designs 100000       # 1e5 (minutes)

The per-design loop is timed on at most --loop designs and scaled to D (it is linear in D).
"""

import argparse
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import planar  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402
from tests import oracles  # noqa: E402

N = 180
TH = np.linspace(0.0, 2 * np.pi, N, endpoint=False)


def designs(D, seed=0):
    """D crank-rockers: ground 4, crank shortest with s + l < 0.9 (p + q), coupler points."""
    rng = np.random.default_rng(seed)
    out = {k: [] for k in ("crank", "coupler", "rocker", "coupler_point")}
    while len(out["crank"]) < D:
        r2, r3, r4 = rng.uniform(0.5, 1.5), rng.uniform(2.5, 5.0), rng.uniform(2.5, 5.0)
        s, p, q, l = sorted([4.0, r2, r3, r4])
        if s == r2 and s + l < 0.9 * (p + q):
            for k, v in zip(out, (r2, r3, r4, tuple(rng.uniform(-1.0, 1.0, 2)))):
                out[k].append(v)
    return out


def closed_form(table):
    col = lambda k: np.array(table[k])[:, None]  # noqa: E731
    pq = np.array(table["coupler_point"])
    return oracles.four_bar(4.0, col("crank"), col("coupler"), col("rocker"), TH[None], w2=1.0,
                            p=pq[:, :1], q=pq[:, 1:])


def timed(f, repeat=1):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--designs", type=int, nargs="+", default=[100, 1000, 10000])
    ap.add_argument("--loop", type=int, default=200, help="designs the per-design loop is timed on")
    args = ap.parse_args(argv)
    print(f"four-bar designs x {N} crank angles; times in seconds (best of 3 for the closed form)")
    print(f"{'D':>7} {'D x N':>9} {'closed form':>12} {'batch':>9} {'x closed':>9} {'loop (scaled)':>14} "
          f"{'x closed':>9} {'batch us/value':>15} {'max |C err|':>12} {'peak MiB':>9}")
    for D in args.designs:
        table = designs(D)
        t_cf, cf = timed(lambda: closed_form(table), 3)
        t_b, study = timed(lambda: planar.sweep_designs(four_bar, table, TH, fixed=dict(ground=4.0)))
        k = min(D, args.loop)
        sub = {key: v[:k] for key, v in table.items()}
        t_l, _ = timed(lambda: [four_bar(ground=4.0, **{key: v[d] for key, v in sub.items()}).sweep(TH)
                                for d in range(k)])
        t_l *= D / k
        assert study.ok.all() and study.batched.all()
        err = max(np.abs(study.position("C") - cf["C"]).max(), np.abs(study.velocity("C") - cf["C_vel"]).max(),
                  np.abs(study.acceleration("C") - cf["C_acc"]).max())
        tracemalloc.start()
        planar.sweep_designs(four_bar, table, TH, fixed=dict(ground=4.0))
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        print(f"{D:>7} {D * N:>9} {t_cf:>12.4f} {t_b:>9.3f} {t_b / t_cf:>9.0f} {t_l:>14.2f} {t_l / t_cf:>9.0f} "
              f"{1e6 * t_b / (D * N):>15.2f} {err:>12.1e} {peak:>9.0f}")


if __name__ == "__main__":
    main()
