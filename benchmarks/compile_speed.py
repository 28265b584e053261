"""The compiled engine's fixed costs, and its speed on large sweeps against the closed form.

Prints, for ``engine="numba"``:

- the one-off compile (per installation): a new process with an empty numba cache (a temporary
  ``NUMBA_CACHE_DIR``) compiling the engine, wall and CPU seconds;
- loading in a new process (the cache filled): importing the engine (numba with it), checking
  the cache and the first sweep's extra time over the second (the machine code read from disk),
  beside numba's own floor: a one-line cached function's import and first call;
- a new mechanism structure in a warm process: the first sweep of a structure the process has
  not seen, over the second;
- the four-bar of ``peers.py`` swept over N values of a turn, full kinematics, against the
  vectorised closed form on the same inputs (best of interleaved rounds; wall time, and the
  process's CPU time over all threads, the fairer measure on a shared machine).

    nice python3 benchmarks/compile_speed.py --sizes 1e5 1e6 --rounds 3
    nice python3 benchmarks/compile_speed.py --threads 1   # on a shared machine: no waiting threads
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from peers import LENGTHS, closed_form  # noqa: E402

# run in a new process: seconds to import the engine, to make it ready (compile or check the
# cache), of the first and of the second sweep of 50 values of the four-bar
_PROCESS = """
import time, numpy as np
from planar.mechanisms import four_bar
model = four_bar().compile()
U = np.linspace(0, 1, 50)
t0 = time.perf_counter()
from planar.compiled import engine
t1 = time.perf_counter()
engine.ready()
t2 = time.perf_counter()
model.sweep(U, engine="numba")
t3 = time.perf_counter()
model.sweep(U, engine="numba")
t4 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3)
"""


def in_new_process(cache):
    """(seconds: import, ready, first sweep, second sweep; CPU seconds of the process)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", _PROCESS], env=dict(os.environ, NUMBA_CACHE_DIR=cache,
                         PYTHONPATH=str(ROOT)), capture_output=True, text=True, check=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return [float(v) for v in out.split()], cpu


# numba's own cost of loading machine code in a new process: a one-line function cached on
# disk, numpy imported first (as planar imports it): seconds to import numba and of its first call
_FLOOR = """
import time, numpy
t0 = time.perf_counter()
import numba
t1 = time.perf_counter()
import trivial
trivial.one(1.0)
print(t1 - t0, time.perf_counter() - t1)
"""


def numba_floor(rounds):
    """(import numba, first call) seconds of a trivial cached function in a new process, best of
    ``rounds`` (its cache filled by a first process)."""
    with tempfile.TemporaryDirectory() as home:
        Path(home, "trivial.py").write_text("import numba\n\n\n@numba.njit(cache=True)\ndef one(x):\n"
                                            "    return x + 1.0\n")
        env = dict(os.environ, NUMBA_CACHE_DIR=home, PYTHONPATH=home)
        runs = [subprocess.run([sys.executable, "-c", _FLOOR], env=env, capture_output=True, text=True,
                               check=True).stdout for _ in range(rounds + 1)]
    return np.min([[float(v) for v in out.split()] for out in runs[1:]], axis=0)


def new_structures(rounds):
    """Seconds of the first sweep of a new structure over its second, best over ``rounds``
    mechanisms of new structures (a chain of one more loop each time), in a warm process."""
    from planar.compiled import engine
    from planar.mechanisms import four_bar, slider_crank, watt_six_bar

    engine.ready()
    four_bar().compile().sweep([0.0, 0.1], engine="numba")
    builders = [watt_six_bar, lambda: slider_crank(2, 5, offset=1), lambda: slider_crank(2, 5, driver="slider"),
                lambda: four_bar(4, 2, 3.5, 3, coupler_point=(1.0, 0.8))]
    best = np.inf
    for build in builders[:max(rounds, 1)]:
        model = build().compile()
        U = model.u0[0] + np.linspace(0, 0.5, 50)
        t = time.perf_counter()
        model.sweep(U, engine="numba")
        first = time.perf_counter() - t
        t = time.perf_counter()
        model.sweep(U, engine="numba")
        best = min(best, first - (time.perf_counter() - t))
    return best


def sweeps(sizes, rounds):
    """{N: [planar seconds, closed form seconds, planar CPU seconds, closed form CPU seconds]},
    best of interleaved rounds (CPU: of the process, all threads)."""
    from planar.mechanisms import four_bar

    model = four_bar(*LENGTHS, coupler_point=(1.0, 0.8)).compile()
    model.sweep(np.linspace(0, 2 * np.pi, 3000), engine="numba")
    best = {n: [np.inf] * 4 for n in sizes}
    for _ in range(rounds):
        for n in sizes:
            U = np.linspace(0, 2 * np.pi, n)
            for k, run in enumerate((lambda: model.sweep(U, engine="numba"), lambda: closed_form(U))):
                t, c = time.perf_counter(), time.process_time()
                run()
                best[n][k] = min(best[n][k], time.perf_counter() - t)
                best[n][k + 2] = min(best[n][k + 2], time.process_time() - c)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="*", default=[1e5, 1e6], help="sweep sizes N against the closed form")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (the best is kept)")
    ap.add_argument("--threads", type=int, help="numba's threads for the sweeps (default: all cores)")
    args = ap.parse_args(argv)
    import numba

    if args.threads:
        numba.set_num_threads(args.threads)
    print(f"compiled engine (numba {numba.__version__}, {numba.get_num_threads()} threads)")
    with tempfile.TemporaryDirectory() as cache:
        (imp, ready, first, second), cpu = in_new_process(cache)
        print(f"one-off compile (empty cache, new process): {ready + first - second:.1f} s wall, {cpu:.1f} s CPU "
              f"for the whole process")
        loads = [in_new_process(cache)[0] for _ in range(args.rounds)]
        imp, ready, first, second = np.min(loads, axis=0)
        print(f"load in a new process (cache filled): {imp + ready + first - second:.3f} s (import of the engine "
              f"with numba {imp:.3f} s, cache check {ready:.3f} s, first sweep over the second "
              f"{first - second:.3f} s)")
    imp, call = numba_floor(args.rounds)
    print(f"numba's own floor, a one-line cached function in a new process: {imp + call:.3f} s (import of numba "
          f"{imp:.3f} s, its first call {call:.3f} s)")
    print(f"a new mechanism structure, warm process: {new_structures(args.rounds):.3f} s (first sweep over the second)")
    sizes = [int(n) for n in args.sizes]
    if sizes:
        print(f"four-bar {LENGTHS} + coupler point, full kinematics, best of {args.rounds} interleaved rounds")
        print("|         N | numba ms | closed form ms | numba / closed | numba CPU ms | closed CPU ms | CPU ratio |")
        print("|-----------|----------|----------------|----------------|--------------|---------------|-----------|")
        for n, (t, tc, c, cc) in sweeps(sizes, args.rounds).items():
            print(f"| {n:9.0e} | {t * 1e3:8.1f} | {tc * 1e3:14.1f} | {t / tc:14.2f} | {c * 1e3:12.1f} | "
                  f"{cc * 1e3:13.1f} | {c / cc:9.2f} |")


if __name__ == "__main__":
    main()
