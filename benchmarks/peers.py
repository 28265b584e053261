"""Peer libraries on the benchmark's four-bar: the same linkage, the same inputs, the same error.

The four-bar of ``case_four_bar`` in ``sweep_speed.py``: ground O2 = (0, 0) -> O4 = (4, 0), crank
2, coupler 3.5, rocker 3, B left of the directed line A -> O4, coupler point C = A + (1.0 + 0.8 i)
e^{i th3}; the crank turns at unit rate (omega = 1 rad/s, alpha = 0), so velocities and
accelerations are the closed form's ``C_vel`` and ``C_acc``. Each adapter builds the linkage in
its library's own terms (outside the timing: like ``Model.compile`` for planar) and returns a
function that runs the sweep and gives ``{"C": (N, 2)[, "C_vel", "C_acc"]}``.

Only peers that are installed are run (``pip install -e ".[bench]"``). pylinkage without numba
runs in a child process in which ``import numba`` fails, which is how pylinkage runs when numba
is not installed (its ``njit`` becomes a no-op).

    python3 benchmarks/peers.py --sizes 1000 10000     # the peers alone, as JSON lines
"""

import argparse
import contextlib
import importlib.util
import io
import json
import math
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests import oracles  # noqa: E402

LENGTHS = (4.0, 2.0, 3.5, 3.0)  # r1 ground, r2 crank, r3 coupler, r4 rocker
PQ = (1.0, 0.8)  # coupler point: along A -> B, to its left
SCALE = 4.0  # positions are compared relative to the largest link, as in sweep_speed.error
REPEAT = 5  # runs per timing, the best taken (sweep_speed.py's too): first runs read up to 3x slower here


def closed_form(th):
    """The reference outputs of the four-bar at crank angles ``th`` (unit rate)."""
    o = oracles.four_bar(*LENGTHS, th, p=PQ[0], q=PQ[1])
    return {"C": o["C"], "C_vel": o["C_vel"], "C_acc": o["C_acc"]}


def _pose(th0):
    """A, B, th3, th4 at one crank angle: the assembly hint every library is given (a sketch)."""
    o = oracles.four_bar(*LENGTHS, np.array([th0]), p=PQ[0], q=PQ[1])
    return o["A"][0], o["B"][0], float(o["th3"][0]), float(o["th4"][0])


def _uniform_step(th):
    """The step of evenly spaced inputs (pylinkage's cranks can only turn by a fixed step)."""
    h = th[1] - th[0]
    if not np.allclose(np.diff(th), h, rtol=1e-9, atol=1e-15):
        raise ValueError("pylinkage sweeps evenly spaced crank angles only")
    return h


# ---- adapters: prepare(th) builds the linkage and returns run() -> outputs --------------------


def pylinkage_linkage(th0, h):
    """(linkage, crank, index of C) of pylinkage's four-bar, its crank at ``th0`` turning by
    ``h`` per step."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    A, B, _, _ = _pose(th0)
    O2, O4 = Ground(0.0, 0.0, name="O2"), Ground(LENGTHS[0], 0.0, name="O4")
    crank = Crank(O2, radius=LENGTHS[1], angular_velocity=h, initial_angle=th0, name="A")
    # B: circle-circle intersection, the root nearest the previous B (the hint picks the mode)
    rocker = RRRDyad(crank.output, O4, distance1=LENGTHS[2], distance2=LENGTHS[3], x=B[0], y=B[1], name="B")
    # C: polar from A, at a fixed angle from the direction A -> B
    coupler = FixedDyad(crank.output, rocker, distance=math.hypot(*PQ), angle=math.atan2(PQ[1], PQ[0]), name="C")
    linkage = Linkage([O2, O4, crank, rocker, coupler], name="four-bar")
    linkage.set_input_velocity(crank, omega=1.0, alpha=0.0)
    return linkage, crank, linkage.components.index(coupler)


def pylinkage_prepare(th, kinematics):
    h = _uniform_step(th)
    # step_fast turns the crank by h, then solves and records: start one step early so
    # record i is crank angle th[0] + i h
    linkage, _, iC = pylinkage_linkage(th[0] - h, h)
    linkage.compile()
    N = len(th)

    if kinematics:
        def run():
            p, v, a = linkage.step_fast_with_kinematics(iterations=N)
            return {"C": p[:, iC], "C_vel": v[:, iC], "C_acc": a[:, iC]}
    else:
        def run():
            return {"C": linkage.step_fast(iterations=N)[:, iC]}
    return run


def kinepy_prepare(th, kinematics):
    from kinepy.interface.system import System

    with contextlib.redirect_stdout(io.StringIO()):  # kinepy prints its compilation steps
        s = System()
        crank, coupler, rocker = s.add_solid("crank"), s.add_solid("coupler"), s.add_solid("rocker")
        # each solid's frame: origin at its first pin, x along the link
        O2 = s.add_revolute(s.ground, crank, (0.0, 0.0), (0.0, 0.0))
        s.add_revolute(crank, coupler, (LENGTHS[1], 0.0), (0.0, 0.0))
        s.add_revolute(coupler, rocker, (LENGTHS[2], 0.0), (LENGTHS[3], 0.0))
        s.add_revolute(rocker, s.ground, (0.0, 0.0), (LENGTHS[0], 0.0))
        s.pilot(O2)  # input: the relative angle ground -> crank = th2
        s.compile()
        s.change_signs([-1])  # the RRR group's sign for B left of A -> O4 (checked by the error)

    def run():
        s.solve_kinematics(th[None, :].copy())  # kinepy scales its input array in place
        return {"C": np.asarray(coupler.get_point(PQ)).T}
    return run


def kimech_prepare(th, kinematics):
    import kimech

    A, B, th3, th4 = _pose(th[0])
    mech = kimech.Mechanism("four-bar")
    g = mech.ground
    crank, coupler, rocker = mech.add_link("crank"), mech.add_link("coupler"), mech.add_link("rocker")
    C = coupler.add_point("C", PQ)
    driver = mech.revolute(g.add_point("O2", (0.0, 0.0)), crank.add_point("O2", (0.0, 0.0)))
    mech.revolute(crank.add_point("A", (LENGTHS[1], 0.0)), coupler.add_point("A", (0.0, 0.0)))
    mech.revolute(coupler.add_point("B", (LENGTHS[2], 0.0)), rocker.add_point("B", (LENGTHS[3], 0.0)))
    mech.revolute(rocker.add_point("O4", (0.0, 0.0)), g.add_point("O4", (LENGTHS[0], 0.0)))
    guess = {crank: (0.0, 0.0, th[0]), coupler: (A[0], A[1], th3), rocker: (LENGTHS[0], 0.0, th4)}
    N = len(th)

    def run():
        rates = dict(velocity=np.ones(N), acceleration=np.zeros(N)) if kinematics else {}
        sol = kimech.solve(mech, drivers=kimech.KinematicDriver(driver, position=th, **rates), initial_guess=guess)
        out = {"C": sol.point_positions(C)}
        if kinematics:
            out.update(C_vel=sol.point_velocities(C), C_acc=sol.point_accelerations(C))
        return out
    return run


def mechanism_prepare(th, kinematics):
    from mechanism import Mechanism, Vector, get_joints

    O, A, B, O4, C = get_joints("O A B O4 C")
    a, b = Vector((O, A), r=LENGTHS[1]), Vector((A, B), r=LENGTHS[2])
    ground = Vector((O, O4), r=LENGTHS[0], theta=0.0, style="ground")
    d = Vector((O4, B), r=LENGTHS[3])
    # the coupler point: a rigid triangle A -> C -> B closing on the coupler vector A -> B
    e, f = Vector((A, C), r=math.hypot(*PQ)), Vector((C, B), r=math.hypot(LENGTHS[2] - PQ[0], PQ[1]))

    def loops(x, i):
        t = np.zeros((2, 2))
        t[0] = a(i) + b(x[0]) - d(x[1]) - ground()
        t[1] = e(x[2]) + f(x[3]) - b(x[0])
        return t.flatten()

    _, _, th3, th4 = _pose(th[0])
    guess = np.array([th3, th4, th3 + math.atan2(PQ[1], PQ[0]), th3 - math.atan2(PQ[1], LENGTHS[2] - PQ[0])])
    N = len(th)

    def run():
        rates = dict(vel=np.ones(N), acc=np.zeros(N)) if kinematics else {}
        mech = Mechanism(vectors=(a, b, ground, d, e, f), origin=O, loops=loops, pos=th,
                         guess=(guess, np.zeros(4), np.zeros(4)), **rates)
        mech.iterate()
        out = {"C": np.stack((C.x_positions, C.y_positions), -1)}
        if kinematics:
            out.update(C_vel=np.stack((C.x_velocities, C.y_velocities), -1),
                       C_acc=np.stack((C.x_accelerations, C.y_accelerations), -1))
        return out
    return run


def solvespace_prepare(th, kinematics):
    from python_solvespace import ResultFlag, SolverSystem

    A0, B0, _, _ = _pose(th[0])
    C0 = closed_form(th[:1])["C"][0]
    s = SolverSystem()
    s.set_group(1)  # group 1 is held fixed by the solve of group 2: the frame and the crank pin
    wp = s.create_2d_base()
    O4 = s.add_point_2d(LENGTHS[0], 0.0, wp)
    A = s.add_point_2d(A0[0], A0[1], wp)
    s.set_group(2)
    B, C = s.add_point_2d(B0[0], B0[1], wp), s.add_point_2d(C0[0], C0[1], wp)
    s.distance(A, B, LENGTHS[2], wp)
    s.distance(O4, B, LENGTHS[3], wp)
    s.distance(A, C, math.hypot(*PQ), wp)
    s.distance(B, C, math.hypot(LENGTHS[2] - PQ[0], PQ[1]), wp)
    x, y = LENGTHS[1] * np.cos(th), LENGTHS[1] * np.sin(th)

    def run():
        out = np.empty((len(th), 2))
        for i in range(len(th)):  # one solve per pose, each starting from the last one
            s.set_params(A.params, (x[i], y[i]))
            if s.solve() != ResultFlag.OKAY:
                out[i] = np.nan
            else:
                out[i] = s.params(C.params)
        return {"C": out}
    return run


@dataclass(frozen=True)
class Peer:
    """One library's way of sweeping the four-bar.

    ``label`` names the row; ``modules`` must all be installed for the row to run;
    ``kinematics`` whether velocities and accelerations come out; ``max_n`` is the largest N
    timed (None: every N; a Python loop per position is slow) and ``quick_n`` the one N timed
    by ``--quick`` for those; ``child`` runs it in a child process without numba.
    """

    label: str
    modules: tuple
    prepare: object
    kinematics: bool
    max_n: int = None
    quick_n: int = None
    child: bool = False
    note: str = ""


PEERS = (
    Peer("pylinkage+numba step_fast", ("pylinkage", "numba"), pylinkage_prepare, False,
         note="numba JIT warm-up excluded"),
    Peer("pylinkage+numba step_fast_with_kinematics", ("pylinkage", "numba"), pylinkage_prepare, True,
         note="numba JIT warm-up excluded"),
    Peer("pylinkage step_fast (no numba)", ("pylinkage",), pylinkage_prepare, False, 10_000, 1000, True),
    Peer("pylinkage step_fast_with_kinematics (no numba)", ("pylinkage",), pylinkage_prepare, True, 10_000, 1000, True),
    Peer("kinepy solve_kinematics", ("kinepy",), kinepy_prepare, False,
         note="positions only: kinepy gives rates only by finite differences of the samples"),
    Peer("python-solvespace", ("python_solvespace",), solvespace_prepare, False, 100_000, 1000,
         note="positions only: a geometric constraint solver, one solve() per pose"),
    Peer("mechanism (positions)", ("mechanism",), mechanism_prepare, False, 1000, 200,
         note="scipy fsolve per pose"),
    Peer("mechanism iterate", ("mechanism",), mechanism_prepare, True, 1000, 200,
         note="scipy fsolve per pose, also for the rates"),
    Peer("kimech solve", ("kimech",), kimech_prepare, True, 1000, 200, note="scipy optimize.root (MINPACK hybr) per pose"),
)


NOT_COMPARABLE = (
    "kinepy velocities and accelerations: it has no rate solver, only finite differences of the samples",
    "python-solvespace velocities and accelerations: a geometric constraint solver, positions only",
)


def installed(peer):
    return all(importlib.util.find_spec(m) is not None for m in peer.modules)


def sizes_for(peer, sizes, quick):
    """The N at which ``peer`` is timed: all of ``sizes`` up to its ``max_n``, else its own N."""
    if peer.max_n is None:
        return list(sizes)
    if quick:
        return [min(peer.quick_n, *sizes)]
    return [n for n in sizes if n <= peer.max_n] or [peer.max_n]


def _ang(a, b):
    return np.abs(np.angle(np.exp(1j * (a - b))))


def error(ref, got, L=SCALE):
    """Largest error of each output in ``got``: angles (keys ``th*``) modulo 2 pi, relative to
    ``L`` for positions and angles, to 1 + the largest reference value for rates (keys ``w*``,
    ``a*``, ``*vel``, ``*acc``). Points where the reference is undefined (NaN) are left out; a
    NaN where the reference is defined makes the error NaN (a failed point shows)."""
    errs = {}
    for k, v in got.items():
        a, b = np.asarray(ref[k], dtype=float), np.asarray(v, dtype=float)
        d = _ang(a, b) if k.startswith("th") else np.abs(a - b)
        d = d[~np.isnan(a)]
        rate = k[:1] in "wa" or k.endswith(("vel", "acc"))
        scale = 1 + np.nanmax(np.abs(a)) if rate else L
        errs[k] = float(np.max(d)) / scale if d.size else float("nan")
    return errs


def inputs(N):
    """The crank angles of the four-bar rows: one turn from the sketch (th2 = 0)."""
    return np.linspace(0, 2 * np.pi, N, endpoint=False)


def measure(peer, N, repeat):
    """Best time (the building outside the timing) and the errors: up to ``repeat`` runs, no
    more once one second has been spent."""
    th = inputs(N)
    best, out, spent = np.inf, None, 0.0
    for _ in range(repeat):
        run = peer.prepare(th, peer.kinematics)
        t = time.perf_counter()
        out = run()
        t = time.perf_counter() - t
        best, spent = min(best, t), spent + t
        if spent > 1.0:
            break
    return best, error(closed_form(th), out)


def warm_up():
    """Compile (or load from numba's cache) pylinkage's jitted loops; the seconds it took."""
    t = time.perf_counter()
    for kin in (False, True):
        pylinkage_prepare(inputs(16), kin)()
    return time.perf_counter() - t


def rows(sizes, quick=False, child=False):
    """Timed rows ``dict(label, N, seconds, errors, note)`` of every installed peer.

    ``child`` selects the peers run without numba (in this process, which must have numba
    blocked); otherwise those are run through a child process.
    """
    out, warm, warmed = [], 0.0, False
    if not child and any(p.child and installed(p) for p in PEERS):
        out += _child_rows(sizes, quick)
    for peer in PEERS:
        if peer.child != child or not installed(peer):
            continue
        if "numba" in peer.modules and not warmed:
            warm = warm_up()
            warmed = True
        for N in sizes_for(peer, sizes, quick):
            t, errs = measure(peer, N, REPEAT)
            note = peer.note + (f" ({warm:.1f} s)" if "warm-up" in peer.note else "")
            out.append(dict(label=peer.label, N=N, seconds=t, errors=errs, note=note))
    return out


def _child_rows(sizes, quick):
    """The no-numba rows, from a child process in which ``import numba`` fails."""
    code = ("import sys; sys.modules['numba'] = None; sys.path.insert(0, sys.argv[1]); "
            "import peers; peers.main(sys.argv[2:])")
    args = [sys.executable, "-c", code, str(Path(__file__).parent), "--child", "--sizes", *map(str, sizes)]
    if quick:
        args.append("--quick")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = subprocess.run(args, capture_output=True, text=True, env=env, check=True)
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]


def not_installed():
    """Modules of the peers that are not installed, for the table's footnote."""
    return sorted({m for p in PEERS for m in p.modules if importlib.util.find_spec(m) is None})


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    for row in rows(args.sizes, args.quick, args.child):
        print(json.dumps(row))


if __name__ == "__main__":
    main()
