"""Sweep speed against error: planar's generic solver beside vectorised numpy closed forms.

Prints, in one run, the time per position and the maximum error against the closed form for
the four-bar with a coupler point, the offset slider-crank, the Watt six-bar and the geared
five-bar at N from 1e3 up, for several solver tolerances; the scaling with the number of loops
(a chain of k four-bar loops); and the peak memory of one sweep. Peer libraries are timed when
installed (the optional ``bench`` extra).

    python3 benchmarks/sweep_speed.py              # N = 1e3 .. 1e6 (a few minutes)
    python3 benchmarks/sweep_speed.py --quick      # N = 1e3 only (a smoke run)
    python3 benchmarks/sweep_speed.py --sizes 1000 100000
"""

import argparse
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import planar  # noqa: E402
from planar.mechanisms import four_bar, geared_five_bar, slider_crank, watt_six_bar  # noqa: E402
from tests import oracles  # noqa: E402


def _ang(a, b):
    return np.abs(np.angle(np.exp(1j * (a - b))))


def circle(c1, r1, c2, r2, left=True):
    """Vectorised circle-circle intersection (the point left of c1 -> c2 when ``left``)."""
    d = c2 - c1
    L = np.hypot(d[..., 0], d[..., 1])
    a = (r1**2 - r2**2 + L**2) / (2 * L)
    h = np.sqrt(np.maximum(r1**2 - a**2, 0.0))
    u = d / L[..., None]
    n = np.stack((-u[..., 1], u[..., 0]), -1)
    return c1 + a[..., None] * u + (1 if left else -1) * h[..., None] * n


# ---- cases: (builder, closed form returning the reference outputs, outputs compared) --------


def case_four_bar():
    m = four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8))

    def closed(th):
        o = oracles.four_bar(4, 2, 3.5, 3, th, p=1.0, q=0.8)
        return {"C": o["C"], "C_vel": o["C_vel"], "C_acc": o["C_acc"]}

    def ours(res):
        return {"C": res.position("C"), "C_vel": res.velocity("C"), "C_acc": res.acceleration("C")}

    return m, closed, ours, 4.0


def case_slider_crank():
    m = slider_crank(2, 5, offset=1)

    def closed(th):
        o = oracles.slider_crank(2, 5, th, offset=1.0)
        return {"B": o["B"], "B_vel": np.stack((o["r1_v"], 0 * o["r1_v"]), -1),
                "B_acc": np.stack((o["r1_a"], 0 * o["r1_a"]), -1)}

    def ours(res):
        return {"B": res.position("B"), "B_vel": res.velocity("B"), "B_acc": res.acceleration("B")}

    return m, closed, ours, 5.0


def case_watt():
    m = watt_six_bar()
    model = m.compile()
    # the dyad C-E-D of the builder's defaults: link_5 = link_6 = 3, E left of C -> D
    def closed(th):
        o = oracles.four_bar(4, 1.5, 4, 3.5, th, p=2.0, q=1.5)
        th4 = o["th4"]
        O4 = np.array([4.0, 0.0])
        D = O4 + 1.5 * np.stack((np.cos(th4), np.sin(th4)), -1) + 1.5 * np.stack((np.sin(th4), -np.cos(th4)), -1)
        return {"E": circle(o["C"], 3.0, D, 3.0, left=True)}

    def ours(res):
        return {"E": res.position("E")}

    return m, closed, ours, model.L


def case_geared():
    m = geared_five_bar()

    def closed(th):
        o = oracles.geared_five_bar(8, 3, 3.5, 6, th)
        return {"th5": o["th5"], "w5": o["w5"], "a5": o["a5"]}

    def ours(res):
        return {"th5": res.angle("link5"), "w5": res.omega("link5"), "a5": res.alpha("link5")}

    return m, closed, ours, 8.0


CASES = {"four-bar + coupler point": case_four_bar, "offset slider-crank": case_slider_crank,
         "Watt six-bar": case_watt, "geared five-bar": case_geared}


def timed(f, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def error(ref, got, L):
    errs = {}
    for k in ref:
        a, b = np.asarray(ref[k]), np.asarray(got[k])
        d = _ang(a, b) if k.startswith("th") else np.abs(a - b)
        scale = L if not k[:1] in "wa" and not k.endswith(("vel", "acc")) else 1 + np.nanmax(np.abs(a))
        errs[k] = float(np.nanmax(d)) / scale
    return errs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 1e3 only")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000, 1_000_000])
    args = ap.parse_args(argv)
    sizes = [1000] if args.quick else args.sizes
    print(f"planar sweep benchmark, numpy {np.__version__}")
    print(f"{'mechanism':26s} {'N':>8s} {'tol':>6s} {'planar us/pos':>13s} {'closed us/pos':>13s} "
          f"{'ratio':>6s}  max error (pos | vel | acc, relative)")
    for name, build in CASES.items():
        m, closed, ours, L = build()
        model = m.compile()
        for N in sizes:
            th = model.u0[0] + np.linspace(0, 2 * np.pi, N, endpoint=False)
            if name == "geared five-bar":
                th = np.linspace(0, np.radians(200), N)  # inside the range of its sketched branch
            tc, ref = timed(lambda: closed(th), 1 if name == "geared five-bar" else 3)
            for tol in ([1e-12] if N > 1000 else [1e-8, 1e-10, 1e-12]):
                tp, res = timed(lambda: model.sweep(th, tol=tol), 1 if N >= 100_000 else 3)
                errs = error(ref, ours(res), L)
                print(f"{name:26s} {N:8d} {tol:6.0e} {tp / N * 1e6:13.3f} {tc / N * 1e6:13.3f} "
                      f"{tp / tc:6.1f}  " + " | ".join(f"{v:.1e}" for v in errs.values()))
    # scaling with the number of loops: a chain of k four-bars, each driven by the one before
    print("\nchain of k four-bar loops, N = 2000 positions:")
    for k in (1, 10, 30, 100):
        m = chain(k)
        model = m.compile()
        th = np.linspace(0, 2 * np.pi, 2000)
        t, res = timed(lambda: model.sweep(th), 1)
        print(f"  k = {k:3d}: {t / 2000 * 1e6:9.1f} us per position, {t / 2000 / k * 1e6:7.2f} us per loop,"
              f" all solved: {bool(res.ok.all())}")
    if not args.quick and max(sizes) >= 1_000_000:
        model = four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8)).compile()
        th = np.linspace(0, 2 * np.pi, 1_000_000)
        tracemalloc.start()
        model.sweep(th)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        print(f"\npeak memory of a four-bar sweep at N = 1e6: {peak / 2**20:.0f} MiB (numpy allocations)")
    peers()


def chain(k):
    """k parallelogram-free four-bar loops in a row: loop j's rocker drives loop j+1 as crank."""
    m = planar.Mechanism(f"chain{k}")
    prev, pivot = m.ground, np.zeros(2)
    crank = m.add_body("crank0", angle=np.pi / 3)
    m.add_revolute("O0", m.ground, crank, at=pivot)
    A = pivot + 2 * np.array([np.cos(np.pi / 3), np.sin(np.pi / 3)])
    for j in range(k):
        O4 = pivot + np.array([4.0, 0.0])
        B = circle(A, 3.5, O4, 3.0, left=True)
        co = m.add_body(f"coupler{j}")
        ro = m.add_body(f"rocker{j}")
        m.add_revolute(f"A{j}", crank if j == 0 else f"rocker{j - 1}", co, at=A)
        m.add_revolute(f"B{j}", co, ro, at=B)
        m.add_revolute(f"O4{j}", ro, m.ground, at=O4)
        # the next crank pin: the rocker's point 2 long from O4 along O4 -> B
        A = O4 + 2 * (B - O4) / np.linalg.norm(B - O4)
        pivot = O4
    m.drive(body="crank0")
    return m


def peers():
    found = []
    for mod in ("pylinkage", "numba", "kinepy", "kimech", "mechanism", "python_solvespace"):
        try:
            __import__(mod)
            found.append(mod)
        except ImportError:
            pass
    print("\npeer libraries installed:", ", ".join(found) if found else "none (pip install -e '.[bench]')")


if __name__ == "__main__":
    main()
