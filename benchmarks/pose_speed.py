"""Poses on demand and small sweeps: planar's numpy engine beside the vectorised closed form.

The four-bar of ``peers.py`` (ground 4, crank 2, coupler 3.5, rocker 3, coupler point C), full
kinematics (positions, velocities, accelerations). Prints, in one run and in interleaved rounds
(planar and the closed form take turns; the best of the rounds is kept), the time of:

- one pose from a warm model (one that has swept a turn) near the last pose (a drag of 0.01
  rad), far from it (anywhere on the turn, on the known branch), and from the sketch of a model
  that knows no pose yet (a new model per pose: the cost of the walk from the sketch);
- 1, 10, 100 and 1000 values over a turn, swept by a warm model and from the sketch;

each beside the closed form on the same inputs, with the ratio planar / closed form.

    python3 benchmarks/pose_speed.py                # 5 rounds
    python3 benchmarks/pose_speed.py --rounds 2     # a quicker, noisier run
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from peers import LENGTHS, closed_form  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402


def build():
    return four_bar(*LENGTHS, coupler_point=(1.0, 0.8)).compile()


def _best(calls):
    """Seconds per call: the best of ``calls``."""
    best = np.inf
    for fn in calls:
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def _fresh(sweep, repeat):
    """``repeat`` calls of ``sweep`` on models that know no pose but their sketch (compiled
    outside the timing)."""
    return [lambda m=build(): sweep(m) for _ in range(repeat)]


def cases(rng):
    """(label, planar calls, closed-form call, calls per round) for each row: the planar calls
    made afresh each round."""
    warm = build()
    warm.sweep(np.linspace(0, 2 * np.pi, 100))
    tracker = warm.track()
    tracker.move(1.0)
    near = iter(1.0 + 0.01 * np.sin(np.arange(10**7)))
    far = iter(rng.uniform(0, 2 * np.pi, 10**6))

    def one(u):
        return lambda: closed_form(np.array([u]))

    out = [
        ("1 pose, warm, near the last", lambda r: [lambda: tracker.move(next(near))] * r, one(1.0), 20),
        ("1 pose, warm, far from the last", lambda r: [lambda: tracker.move(next(far))] * r, one(2.0), 20),
        ("1 pose at pi, from the sketch", lambda r: _fresh(lambda m: m.sweep([np.pi]), r), one(np.pi), 3),
    ]
    for n in (1, 10, 100, 1000):
        U = np.linspace(0, 2 * np.pi, n)
        out.append((f"{n} values over a turn, warm", lambda r, U=U: [lambda: warm.sweep(U)] * r,
                    lambda U=U: closed_form(U), 5))
        out.append((f"{n} values over a turn, from the sketch", lambda r, U=U: _fresh(lambda m: m.sweep(U), r),
                    lambda U=U: closed_form(U), 3))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds (the best is kept)")
    args = ap.parse_args(argv)
    rows = cases(np.random.default_rng(1))
    best = {label: [np.inf, np.inf] for label, *_ in rows}
    for _ in range(args.rounds):
        for label, fn, ref, repeat in rows:
            best[label][0] = min(best[label][0], _best(fn(repeat)))
            best[label][1] = min(best[label][1], _best([ref] * repeat))
    print(f"four-bar {LENGTHS} + coupler point, numpy engine, best of {args.rounds} interleaved rounds")
    print(f"| {'work':<40} | planar ms | closed form ms | planar / closed |")
    print(f"|{'-' * 42}|-----------|----------------|-----------------|")
    for label, (t, tc) in best.items():
        print(f"| {label:<40} | {t * 1e3:9.3f} | {tc * 1e3:14.4f} | {t / tc:15.0f} |")


if __name__ == "__main__":
    main()
