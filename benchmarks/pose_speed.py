"""Poses on demand and small sweeps: planar's engines beside the vectorised closed form.

The four-bar of ``peers.py`` (ground 4, crank 2, coupler 3.5, rocker 3, coupler point C), full
kinematics (positions, velocities, accelerations). Prints, in one run and in interleaved rounds
(planar, the closed form and pylinkage take turns; the best of the rounds is kept), the time of:

- one pose from a warm model (one that has swept a turn) near the last pose (a drag of 0.01
  rad), far from it (anywhere on the turn, on the known branch), and from the sketch of a model
  that knows no pose yet (a new model per pose: the cost of the walk from the sketch);
- 1, 10, 100 and 1000 values over a turn, swept by a warm model and from the sketch; and 100
  values over the turn a warm model knows, new to it at each call (its 100 values moved by a
  random fraction of their spacing: none at an input it has solved);

each beside the closed form on the same inputs, with the ratio planar / closed form, and beside
pylinkage's ``step()`` on the same linkage (``peers.py``; when pylinkage is installed) moving its
crank to the same inputs: one step per pose (from the last pose; one step from the sketch's
angle for "from the sketch"), one step per value for the values over a turn; and beside
pylinkage's ``step_fast`` (its numba loop, compiled before the timing) over the values over a
turn (two or more: its crank turns by one fixed step). ``step()`` and ``step_fast`` give
positions only (planar gives velocities and accelerations too).

The rows come for each engine (numpy, and numba where it is installed: its one-off compile is
done before the timing).

    python3 benchmarks/pose_speed.py                # 5 rounds
    python3 benchmarks/pose_speed.py --rounds 2     # a quicker, noisier run
"""

import argparse
import importlib.util
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from peers import LENGTHS, closed_form, pylinkage_linkage, pylinkage_prepare  # noqa: E402
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


class Stepper:
    """pylinkage's four-bar moved by ``step()``: its crank turned from its last angle."""

    def __init__(self, th0=0.0):
        self.linkage, self.crank, _ = pylinkage_linkage(th0, 0.0)
        self.th = th0

    def move(self, u):
        """The positions at crank angle u, one step from the last."""
        self.crank.angular_velocity, self.th = u - self.th, u
        for pos in self.linkage.step(iterations=1):
            return pos

    def sweep(self, U):
        """The positions at the evenly spaced crank angles U: a step to the first, one per value."""
        out = [self.move(U[0])]
        if len(U) > 1:
            self.crank.angular_velocity, self.th = U[1] - U[0], U[-1]
            out += list(self.linkage.step(iterations=len(U) - 1))
        return out


def cases(rng, engine):
    """(label, planar calls, closed-form call, pylinkage step() calls or None, pylinkage
    step_fast call or None, calls per round) for each row of ``engine``: the planar and
    pylinkage calls made afresh each round."""
    warm = build()
    warm.sweep(np.linspace(0, 2 * np.pi, 100), engine=engine)
    tracker = warm.track(engine=engine)
    tracker.move(1.0)
    near = iter(1.0 + 0.01 * np.sin(np.arange(10**7)))
    far = iter(rng.uniform(0, 2 * np.pi, 10**6))
    peer = importlib.util.find_spec("pylinkage") is not None
    stepper = Stepper(1.0) if peer else None
    near_p, far_p = iter(1.0 + 0.01 * np.sin(np.arange(10**7))), iter(rng.uniform(0, 2 * np.pi, 10**6))

    def one(u):
        return lambda: closed_form(np.array([u]))

    def stepped(call):
        return (lambda r: [call] * r) if peer else None

    out = [
        ("1 pose, warm, near the last", lambda r: [lambda: tracker.move(next(near))] * r, one(1.0),
         stepped(lambda: stepper.move(next(near_p))), None, 20),
        ("1 pose, warm, far from the last", lambda r: [lambda: tracker.move(next(far))] * r, one(2.0),
         stepped(lambda: stepper.move(next(far_p))), None, 20),
        ("1 pose at pi, from the sketch", lambda r: _fresh(lambda m: m.sweep([np.pi], engine=engine), r), one(np.pi),
         peer and (lambda r: [lambda s=Stepper(): s.move(np.pi) for _ in range(r)]), None, 3),
    ]
    V = np.linspace(0, 2 * np.pi, 100)
    shift = iter(rng.uniform(0, V[1], 10**6))
    known = build()  # (a warm model of its own: the new values it learns leave the other's as they are)
    known.sweep(V, engine=engine)
    out.append(("100 new values over a known turn", lambda r: [lambda: known.sweep(V + next(shift), engine=engine)] * r,
                lambda: closed_form(V), stepped(lambda: stepper.sweep(V)), pylinkage_prepare(V, False) if peer else None,
                5))
    for n in (1, 10, 100, 1000):
        U = np.linspace(0, 2 * np.pi, n)
        sweep = stepped(lambda U=U: stepper.sweep(U))
        # (step_fast turns its crank by one fixed step: evenly spaced values, two or more)
        fast = pylinkage_prepare(U, False) if peer and n > 1 else None
        out.append((f"{n} values over a turn, warm", lambda r, U=U: [lambda: warm.sweep(U, engine=engine)] * r,
                    lambda U=U: closed_form(U), sweep, fast, 5))
        out.append((f"{n} values over a turn, from the sketch",
                    lambda r, U=U: _fresh(lambda m: m.sweep(U, engine=engine), r), lambda U=U: closed_form(U), sweep,
                    fast, 3))
    return [(f"{engine}: {label}", *rest) for label, *rest in out]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds (the best is kept)")
    args = ap.parse_args(argv)
    engines = ["numpy"] + (["numba"] if importlib.util.find_spec("numba") else [])
    rows = [row for e in engines for row in cases(np.random.default_rng(1), e)]
    best = {label: [np.inf] * 4 for label, *_ in rows}
    for _ in range(args.rounds):
        for label, fn, ref, peer, fast, repeat in rows:
            best[label][0] = min(best[label][0], _best(fn(repeat)))
            best[label][1] = min(best[label][1], _best([ref] * repeat))
            if peer:
                best[label][2] = min(best[label][2], _best(peer(repeat)))
            if fast:
                best[label][3] = min(best[label][3], _best([fast] * repeat))
    print(f"four-bar {LENGTHS} + coupler point, best of {args.rounds} interleaved rounds")
    print(f"| {'engine: work':<47} | planar ms | closed form ms | planar / closed | pylinkage step() ms | planar / step() "
          "| step_fast ms | planar / step_fast |")
    print(f"|{'-' * 49}|-----------|----------------|-----------------|---------------------|-----------------|"
          "--------------|--------------------|")
    for label, (t, tc, tp, tf) in best.items():
        peer = f"{tp * 1e3:19.4f} | {t / tp:15.1f}" if np.isfinite(tp) else f"{'-':>19} | {'-':>15}"
        fast = f"{tf * 1e3:12.4f} | {t / tf:18.1f}" if np.isfinite(tf) else f"{'-':>12} | {'-':>18}"
        print(f"| {label:<47} | {t * 1e3:9.3f} | {tc * 1e3:14.4f} | {t / tc:15.0f} | {peer} | {fast} |")


if __name__ == "__main__":
    main()
