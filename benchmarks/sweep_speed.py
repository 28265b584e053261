"""Sweep speed against error: planar's generic solver beside vectorised numpy closed forms and
peer libraries.

Prints, in one run, the time per position (of sweeps from the sketch, as a model's first
sweep) and the maximum error against the closed form for the four-bar with a coupler point,
the offset slider-crank, the Watt six-bar and the geared five-bar at N from 1e3 up, for several
solver tolerances; the scaling with the number of loops (a chain of k drag-link loops, k up to
100, with the time of its ``compile()``); the peak memory of one sweep at N = 1e6; and the
four-bar side by side with every peer library installed (the optional ``bench`` extra; see
``peers.py``), with the issue's speed targets.

    python3 benchmarks/sweep_speed.py              # N = 1e3 .. 1e6 (about 3-8 minutes)
    python3 benchmarks/sweep_speed.py --quick      # N = 1e3, slow peers at 200 (a smoke run, ~15 s)
    python3 benchmarks/sweep_speed.py --sizes 1000 100000 --no-peers
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peers  # noqa: E402
from peers import error  # noqa: E402

try:  # the compiled engine (the "fast" extra)
    import numba
except ImportError:
    numba = None
ENGINES = ("numpy", "numba") if numba else ("numpy",)


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


def cold(model, *args, **options):
    """``model.sweep`` as a model's first sweep: the walk from the sketch (a model remembers the
    poses it solved, and solves values on a turn it knows without the walk; those are timed in
    ``pose_speed.py``)."""
    model.known_poses.clear()
    return model.sweep(*args, **options)


def timed(f, repeat):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def rounds(runs, repeat):
    """The best seconds of each of ``runs`` (key -> function), timed in ``repeat`` rounds that
    each call every function once, so that the times compared run under the same conditions:
    this machine's speed drifts over minutes (the same sweep read up to 1.3x slower minutes
    later), and a ratio of two times taken minutes apart drifts with it. Each output is dropped
    at once, as in a loop that keeps no result: kept, the sweeps' ~300 MB at N = 1e6 made the
    closed form's next arrays fault in afresh (0.37 against 0.28 us per value)."""
    best = dict.fromkeys(runs, np.inf)
    for _ in range(repeat):
        for key, run in runs.items():
            t = time.perf_counter()
            run()
            best[key] = min(best[key], time.perf_counter() - t)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 1e3 only, best of one run, a short chain (a smoke run)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000, 1_000_000])
    ap.add_argument("--no-peers", action="store_true", help="skip the peer libraries")
    args = ap.parse_args(argv)
    sizes = [1000] if args.quick else args.sizes
    repeat = 1 if args.quick else peers.REPEAT
    print(f"planar sweep benchmark, numpy {np.__version__}" + (
        f", numba {numba.__version__} ({numba.get_num_threads()} threads)" if numba else ", numba not installed"))
    print(f"{'mechanism':26s} {'engine':6s} {'N':>8s} {'tol':>6s} {'planar us/pos':>13s} {'closed us/pos':>13s} "
          f"{'ratio':>6s}  max error (pos | vel | acc, relative)")
    four_bar_runs = {}  # (N, engine) -> (planar s, errors) at the default tolerance
    for name, build in CASES.items():
        m, closed, ours, L = build()
        model = m.compile()
        if numba:  # the compiled loop of this structure: built (or loaded from the disk cache) once
            t, _ = timed(lambda: cold(model, model.u0[0] + np.linspace(0, 0.1, 50), engine="numba"), 1)
            print(f"{name:26s} numba: compiling or loading the loop took {t:.1f} s (excluded below)")
        for N in sizes:
            th = model.u0[0] + np.linspace(0, 2 * np.pi, N, endpoint=False)
            if name == "geared five-bar":
                th = np.linspace(0, np.radians(200), N)  # inside the range of its sketched branch
            tols = [1e-12] if N > 1000 else [1e-8, 1e-10, 1e-12]
            runs = {(e, tol): (lambda e=e, tol=tol: cold(model, th, tol=tol, engine=e))
                    for e in ENGINES for tol in tols}
            if name == "geared five-bar":  # its closed form is a continuation (~100 us per value): once
                tc, ref = timed(lambda: closed(th), 1)
            else:
                runs["closed"] = lambda: closed(th)
            best = rounds(runs, repeat)
            if "closed" in runs:
                tc, ref = best["closed"], closed(th)
            for engine in ENGINES:
                for tol in tols:
                    tp, res = best[engine, tol], cold(model, th, tol=tol, engine=engine)  # (its outputs: untimed)
                    errs = error(ref, ours(res), L)
                    print(f"{name:26s} {engine:6s} {N:8d} {tol:6.0e} {tp / N * 1e6:13.3f} {tc / N * 1e6:13.3f} "
                          f"{tp / tc:6.3g}  " + _errs(errs.values()))
                    if case_four_bar is build and tol == 1e-12:
                        four_bar_runs[N, engine] = (tp, errs)
    # scaling with the number of loops: a chain of k drag-link loops, each driven by the one before
    ks, n_chain = ((1, 10), 100) if args.quick else ((1, 10, 30, 100), 2000)
    print(f"\nchain of k drag-link four-bar loops (every loop turns a full turn), N = {n_chain} positions, "
          f"best of {repeat}:")
    for k in ks:
        built = [chain(k) for _ in range(repeat)]  # (a mechanism compiles once: one each)
        tc, model = timed(lambda: built.pop().compile(), repeat)
        th = np.linspace(0, 2 * np.pi, n_chain)
        t, res = timed(lambda: cold(model, th), repeat)
        print(f"  k = {k:3d}: compile() {tc:6.3f} s, {t / n_chain * 1e6:9.1f} us per position, "
              f"{t / n_chain / k * 1e6:7.2f} us per loop, all solved: {bool(res.ok.all())}")
    if not args.quick and max(sizes) >= 1_000_000:
        model = four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8)).compile()
        th = np.linspace(0, 2 * np.pi, 1_000_000)
        tracemalloc.start()
        model.sweep(th)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        print(f"\npeak memory of a four-bar sweep at N = 1e6: {peak / 2**20:.0f} MiB (numpy allocations)")
    if not args.no_peers:
        side_by_side(sizes, args.quick, repeat, four_bar_runs)
    targets(sizes, repeat, not args.no_peers)


def side_by_side(sizes, quick, repeat, four_bar_runs):
    """The four-bar with a coupler point in planar, the closed form and each installed peer."""
    rows = peers.rows(sizes, quick)
    print("\nfour-bar + coupler point side by side (crank 0 .. 2 pi at unit rate; errors relative as above;"
          " full = positions, velocities, accelerations):")
    print(f"{'library':48s} {'outputs':9s} {'N':>8s} {'us/pos':>9s} {'/closed':>8s}  max error (pos | vel | acc)")
    m, closed, ours, L = case_four_bar()
    model = m.compile()
    by_n = {}
    for r in rows:
        by_n.setdefault(r["N"], []).append(r)
    line = "{:48s} {:9s} {:8d} {:9.3f} {:8.3g}  {}"
    for N in sorted(set(sizes) | set(by_n)):
        th = np.linspace(0, 2 * np.pi, N, endpoint=False)
        tc, ref = timed(lambda: closed(th), repeat)
        print(line.format("closed form (numpy, tests/oracles.py)", "full", N, tc / N * 1e6, 1.0, "reference"))
        runs = [(e, t) for e in ENGINES for t in (None, 1)[: 2 if e == "numba" else 1]]
        for engine, threads in runs:
            label = f"planar Model.sweep engine={engine}" + (" (1 thread)" if threads else "")
            with _threads(threads):
                if (N, engine) in four_bar_runs and not threads:
                    tp, errs = four_bar_runs[N, engine]  # (its ratio: to this table's closed form)
                else:  # a peer's own (smaller) N, or one thread: time planar here
                    tp, res = timed(lambda: cold(model, th, engine=engine), repeat)
                    errs = error(ref, ours(res), L)
                tq, res = timed(lambda: cold(model, th, rates=False, engine=engine), repeat)
            print(line.format(label, "full", N, tp / N * 1e6, tp / tc, _errs(errs.values())))
            print(line.format(label + " rates=False", "positions", N, tq / N * 1e6, tq / tc,
                              _errs(error({"C": ref["C"]}, {"C": res.position("C")}, L).values())))
        for r in by_n.get(N, []):
            what = "full" if len(r["errors"]) == 3 else "positions"
            print(line.format(r["label"], what, N, r["seconds"] / N * 1e6, r["seconds"] / tc, _errs(r["errors"].values()))
                  + (f"  [{r['note']}]" if r["note"] else ""))
    slow = sorted({f"{p.label} (N <= {p.quick_n if quick else p.max_n})" for p in peers.PEERS
                   if p.max_n is not None and peers.installed(p)})
    if slow:
        print("timed at smaller N only (a Python loop per position): " + "; ".join(slow))
    for line in peers.NOT_COMPARABLE:
        print("not comparable: " + line)
    missing = peers.not_installed()
    if missing:
        print("not installed (pip install -e '.[bench]'): " + ", ".join(missing))


class _threads:
    """Within: numba's loops on ``n`` threads (None: all)."""

    def __init__(self, n):
        self.n, self.was = n, None

    def __enter__(self):
        if numba and self.n:
            self.was = numba.get_num_threads()
            numba.set_num_threads(self.n)

    def __exit__(self, *exc):
        if self.was:
            numba.set_num_threads(self.was)


TARGET_PEERS = {"full": "pylinkage+numba step_fast_with_kinematics", "positions": "pylinkage+numba step_fast"}


def targets(sizes, repeat, with_peers=True):
    """The issue's speed targets for the four-bar at N >= 1e5, timed in rounds (:func:`rounds`)
    of the closed form, pylinkage's two numba loops (when installed) and planar's two sweeps on
    each engine."""
    big = [N for N in sizes if N >= 100_000]
    if not big:
        return
    m, closed, _, _ = case_four_bar()
    model = m.compile()
    found = [p for p in peers.PEERS if p.label in TARGET_PEERS.values() and peers.installed(p)] if with_peers else []
    configs = [(e, t) for e in ENGINES for t in (None, 1)[: 2 if e == "numba" else 1]]
    print(f"\ntargets (four-bar; full kinematics against the closed form and step_fast_with_kinematics, "
          f"positions only against step_fast; in rounds, best of {repeat}):")
    for N in big:
        th = peers.inputs(N)
        # (a pylinkage linkage is built once: a second run repeats the same work from where the
        # first left the crank)
        runs = {"closed": lambda: closed(th)} | {p.label: p.prepare(th, p.kinematics) for p in found}
        for engine, threads in configs:
            for what, rates in (("full", True), ("positions", False)):
                def run(e=engine, n=threads, r=rates):
                    with _threads(n):
                        cold(model, th, engine=e, rates=r)
                runs[engine, threads, what] = run
        best = rounds(runs, repeat)
        print(f"  N = {N:.0e}: closed form {best['closed'] / N * 1e6:.3f} us" + "".join(
            f", {TARGET_PEERS[w]} {best[TARGET_PEERS[w]] / N * 1e6:.3f} us" for w in TARGET_PEERS
            if TARGET_PEERS[w] in best))
        for engine, threads in configs:
            label = f"engine={engine}" + (" (1 thread)" if threads else "")
            full, pos = best[engine, threads, "full"], best[engine, threads, "positions"]
            print(f"  N = {N:.0e}, {label}: {full / N * 1e6:.3f} us full, {pos / N * 1e6:.3f} us positions; "
                  f"planar / closed form = {full / best['closed']:.2f} (target <= 2)", end="")
            for what, goal, ours in (("full", "< 1", full), ("positions", "<= 1", pos)):
                if TARGET_PEERS[what] in best:
                    print(f"; / {TARGET_PEERS[what]} = {ours / best[TARGET_PEERS[what]]:.2f} (target {goal})", end="")
            print()


def _errs(values):
    return " | ".join(f"{v:.1e}" for v in values)


def chain(k):
    """k drag-link four-bar loops in a row: loop j's output crank drives loop j+1.

    Each loop (ground 1, crank 2.5, coupler 3, output 2.8: the ground is the shortest link, so
    both cranks turn fully) turns its output once per input turn, so every loop of the chain
    moves, with rates within 2.5x of the input's. (A chain of crank-rockers would not do: each
    rocker swings less than the crank driving it, and past ~30 loops nothing moves.)
    """
    m = planar.Mechanism(f"chain{k}")
    pivot = np.zeros(2)
    crank = m.add_body("crank0", angle=np.pi / 3)
    m.add_revolute("O0", m.ground, crank, at=pivot)
    A = pivot + 2.5 * np.array([np.cos(np.pi / 3), np.sin(np.pi / 3)])
    for j in range(k):
        O4 = pivot + np.array([1.0, 0.0])
        B = circle(A, 3.0, O4, 2.8, left=True)
        co = m.add_body(f"coupler{j}")
        ro = m.add_body(f"rocker{j}")
        m.add_revolute(f"A{j}", crank if j == 0 else f"rocker{j - 1}", co, at=A)
        m.add_revolute(f"B{j}", co, ro, at=B)
        m.add_revolute(f"O4{j}", ro, m.ground, at=O4)
        # the next crank pin: the output's point 2.5 from O4 along O4 -> B
        A = O4 + 2.5 * (B - O4) / np.linalg.norm(B - O4)
        pivot = O4
    m.drive(body="crank0")
    return m


if __name__ == "__main__":
    main()
