"""Many designs of one structure: D random crank-rocker four-bars with coupler points, each over
N = 180 crank angles (positions, velocities and accelerations), swept by planar.sweep_designs
planar.designs.BATCH designs at a time (the chunked path's unit of work: each chunk's results
are checked and let go, as a study on a cluster writes them to its store), the designs given two
ways: to the catalogue's builder (planar.mechanisms.four_bar, a Mechanism built per design,
"builder") and as the numbers of one dimensioned four-bar (planar.Vary: its stated lengths, no
Mechanism per design, "Vary"; also with the compiled engine, "Vary numba", where numba is
installed), beside

- the closed form vectorised over all designs at once (tests/oracles.py: four_bar),
- planar's per-design loop (build, compile and sweep each design alone; at D <= --loop-up-to,
  timed on at most --loop designs and scaled to D: it is linear in D),
- a Python loop of pylinkage (build and run each design's linkage with its velocities and
  accelerations, step_fast_with_kinematics with numba; timed on --loop designs, scaled), if
  pylinkage is installed.

Prints the times, their ratios to the closed form, the time per value, the largest error of the
coupler point's position, velocity and acceleration against the closed form over every design,
and the peak memory (numpy allocations, tracemalloc) of the chunked path, measured once on two
chunks: it does not depend on D.

    python3 benchmarks/designs_speed.py                        # D = 1e2, 1e3, 1e4
    python3 benchmarks/designs_speed.py --designs 100 1000     # a shorter run
    python3 benchmarks/designs_speed.py --designs 100000       # 1e5 (minutes)
"""

import argparse
import importlib.util
import math
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import planar  # noqa: E402
from planar.designs import BATCH  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402
from tests import oracles  # noqa: E402

N = 180
TH = np.linspace(0.0, 2 * np.pi, N, endpoint=False)
GROUND = 4.0


def designs(D, seed=0):
    """D crank-rockers: ground 4, crank shortest with s + l < 0.9 (p + q), coupler points (p, q)
    with q > 0 (left of A -> B, the side of the family's drawing)."""
    rng = np.random.default_rng(seed)
    out = {k: [] for k in ("crank", "coupler", "rocker", "coupler_point")}
    while len(out["crank"]) < D:
        r2, r3, r4 = rng.uniform(0.5, 1.5), rng.uniform(2.5, 5.0), rng.uniform(2.5, 5.0)
        s, p, q, l = sorted([GROUND, r2, r3, r4])
        if s == r2 and s + l < 0.9 * (p + q):
            for k, v in zip(out, (r2, r3, r4, (rng.uniform(-1.0, 1.0), rng.uniform(0.1, 1.0)))):
                out[k].append(v)
    return out


def closed_form(table):
    col = lambda k: np.array(table[k])[:, None]  # noqa: E731
    pq = np.array(table["coupler_point"])
    return oracles.four_bar(GROUND, col("crank"), col("coupler"), col("rocker"), TH[None], w2=1.0,
                            p=pq[:, :1], q=pq[:, 1:])


def chunk(table, lo, hi):
    return {k: v[lo:hi] for k, v in table.items()}


FAMILY = planar.Vary(four_bar(GROUND, 1.0, 3.5, 3.5, coupler_point=(0.5, 0.5)))


def numbers(table):
    """The designs as the family's numbers: the links' lengths and C's distances from A and B."""
    pq, r3 = np.array(table["coupler_point"]), np.array(table["coupler"])
    return {"O2-A": table["crank"], "A-B": table["coupler"], "O4-B": table["rocker"],
            "A-C": np.hypot(pq[:, 0], pq[:, 1]), "B-C": np.hypot(r3 - pq[:, 0], pq[:, 1])}


def chunked(table, D, vary, engine="numpy"):
    """planar.sweep_designs over the designs BATCH at a time, and the coupler point's position,
    velocity and acceleration (what the closed form gives): (seconds, the largest error of C
    against the closed form). Each chunk's results are checked and let go; the closed form and
    the check are outside the seconds."""
    err, seconds = 0.0, 0.0
    for lo in range(0, D, BATCH):
        part = chunk(table, lo, min(lo + BATCH, D))
        t = time.perf_counter()
        if vary:
            study = planar.sweep_designs(FAMILY, numbers(part), TH, engine=engine)
        else:
            study = planar.sweep_designs(four_bar, part, TH, fixed=dict(ground=GROUND), engine=engine)
        C = study.position("C"), study.velocity("C"), study.acceleration("C")
        seconds += time.perf_counter() - t
        assert study.ok.all() and study.batched.all()
        cf = closed_form(part)
        err = max(err, *(np.abs(c - cf[k]).max() for c, k in zip(C, ("C", "C_vel", "C_acc"))))
    return seconds, err


def planar_loop(table, k):
    for d in range(k):
        four_bar(ground=GROUND, **{key: v[d] for key, v in table.items()}).sweep(TH)


def pylinkage_design(r2, r3, r4, pq):
    """One design's linkage in pylinkage (as benchmarks/peers.py builds it) and its run: C's
    position, velocity and acceleration (N, 2) each."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    h = TH[1] - TH[0]  # step_fast turns the crank by h, then records: start one step early
    B = oracles.four_bar(GROUND, r2, r3, r4, np.array([TH[0] - h]))["B"][0]
    O2, O4 = Ground(0.0, 0.0, name="O2"), Ground(GROUND, 0.0, name="O4")
    crank = Crank(O2, radius=r2, angular_velocity=h, initial_angle=TH[0] - h, name="A")
    rocker = RRRDyad(crank.output, O4, distance1=r3, distance2=r4, x=B[0], y=B[1], name="B")
    coupler = FixedDyad(crank.output, rocker, distance=math.hypot(*pq), angle=math.atan2(pq[1], pq[0]), name="C")
    linkage = Linkage([O2, O4, crank, rocker, coupler], name="four-bar")
    linkage.set_input_velocity(crank, omega=1.0, alpha=0.0)
    linkage.compile()
    p, v, a = linkage.step_fast_with_kinematics(iterations=N)
    i = linkage.components.index(coupler)
    return p[:, i], v[:, i], a[:, i]


def pylinkage_loop(table, k):
    """The largest error of C against the closed form over the first k designs."""
    out = [pylinkage_design(table["crank"][d], table["coupler"][d], table["rocker"][d], table["coupler_point"][d])
           for d in range(k)]
    cf = closed_form(chunk(table, 0, k))
    return max(np.abs(np.array([o[j] for o in out]) - cf[key]).max() for j, key in enumerate(("C", "C_vel", "C_acc")))


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
    ap.add_argument("--loop", type=int, default=200, help="designs the per-design loops are timed on")
    ap.add_argument("--loop-up-to", type=int, default=1000, help="largest D at which planar's loop is timed")
    args = ap.parse_args(argv)
    peer = importlib.util.find_spec("pylinkage") is not None
    if peer:
        pylinkage_loop(designs(2), 2)  # numba compiles (or loads) its loops once, outside the timings
    compiled = importlib.util.find_spec("numba") is not None
    chunked(designs(2), 2, True)  # (the family's template compiled, once a process)
    if compiled:
        chunked(designs(2), 2, True, "numba")  # (the compiled engine compiled or loaded, outside the timings)
    print(f"four-bar designs x {N} crank angles; times in seconds (best of 3 for the closed form); "
          f"loops timed on at most {args.loop} designs and scaled to D")
    print(f"{'D':>7} {'D x N':>9} {'closed form':>12} {'builder':>9} {'x closed':>9} {'Vary':>9} {'x closed':>9} "
          f"{'us/value':>9} {'Vary numba':>11} {'x closed':>9} {'max |C err|':>12} {'planar loop':>12} {'x closed':>9} {'pylinkage loop':>15} "
          f"{'x closed':>9} {'pylinkage err':>14}")
    for D in args.designs:
        table = designs(D)
        t_cf, _ = timed(lambda: closed_form(table), 3)
        t_b, err_b = chunked(table, D, False)
        t_v, err = chunked(table, D, True)
        err = max(err, err_b)
        numba = f"{'(not installed)':>11} {'-':>9}"
        if compiled:
            t_n, err_n = chunked(table, D, True, "numba")
            numba, err = f"{t_n:>11.3f} {t_n / t_cf:>9.1f}", max(err, err_n)
        k = min(D, args.loop)
        loop = pyl = "-"
        if D <= args.loop_up_to:
            t_l, _ = timed(lambda: planar_loop(table, k))
            t_l *= D / k
            loop = f"{t_l:>12.2f} {t_l / t_cf:>9.0f}"
        else:
            loop = f"{'-':>12} {'-':>9}"
        if peer:
            t_p, e_p = timed(lambda: pylinkage_loop(table, k))
            t_p *= D / k
            pyl = f"{t_p:>15.2f} {t_p / t_cf:>9.0f} {e_p:>14.1e}"
        else:
            pyl = f"{'(not installed)':>15} {'-':>9} {'-':>14}"
        print(f"{D:>7} {D * N:>9} {t_cf:>12.4f} {t_b:>9.3f} {t_b / t_cf:>9.1f} {t_v:>9.3f} {t_v / t_cf:>9.1f} "
              f"{1e6 * t_v / (D * N):>9.2f} {numba} "
              f"{err:>12.1e} {loop} {pyl}", flush=True)
    table = designs(2 * BATCH, seed=1)
    tracemalloc.start()
    chunked(table, 2 * BATCH, True)
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    print(f"peak memory of the chunked path ({BATCH} designs x {N} values a chunk, two chunks): {peak:.0f} MiB")


if __name__ == "__main__":
    main()
