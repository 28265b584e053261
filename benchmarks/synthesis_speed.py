"""Path generation: time to a defect-free four-bar (and six-bar) through N targets, planar against
pylinkage.

Four-bar: the targets are N points of the coupler curve of a known four-bar (the peers' four-bar
of ``peers.py``: O2 = (0, 0), O4 = (4, 0), crank 2, coupler 3.5, rocker 3, coupler point
(1.0, 0.8) along and left of A -> B), at crank angles spread over 270 deg. Six-bar: N points of
the tracer path of a known Stephenson six-bar (the one of tests/test_synthesis.py: O2 = (1, -2),
ground 4, crank 1.5, coupler 4, rocker 3.5, C at (2, 1.5) on the coupler, link 5 = 4 from C to D,
link 6 = 3 from D to O6 = (3, 4), tracer P at (1, 0.5) on link 5), at crank angles spread over
300 deg. Each method gets the same targets and runs once:

- planar: :func:`planar.synthesis.path_four_bar` / :func:`planar.synthesis.path_six_bar` (free
  timing, seeded search, least squares, the answer checked by planar's sweep: its errors and
  defects are its own);
- pylinkage's classical path synthesis, ``pylinkage.synthesis.path_generation`` (four-bar only:
  Burmester theory over the free coupler orientations; practical for 3-5 points);
- pylinkage's particle swarm, ``particle_swarm_optimization`` over the link lengths and the
  traced point (distance, angle), the ground pivots given (the known ones: a head start planar
  does not get); fitness: the largest distance from a target to the traced points of one
  96-frame turn.

planar's answer is measured by its own check (exact crank angles at the targets). The swarm's
best design is rebuilt in planar (``four_bar`` or ``stephenson_tracer``), swept over one crank
turn at 0.1 deg, its error the distance from each target to the nearest swept point (relative to
the targets' size), its defects planar's check on the crank interval that visits the targets in
order (``path_check``). The Burmester synthesis returns pylinkage linkages of its own, measured
by pylinkage's ``verify_path_generation``. Times are wall clock and CPU (the process's), as the
machine may be shared.

    python3 benchmarks/synthesis_speed.py                   # 4 and 11 targets, PSO 100 particles x 100 iterations
    python3 benchmarks/synthesis_speed.py --targets 6 --six-targets 9 --particles 50 --iterations 50
"""

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from planar.errors import PlanarError  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402
from planar.synthesis import (SynthesisError, path_check, path_four_bar, path_six_bar,  # noqa: E402
                              stephenson_tracer)
from tests import oracles  # noqa: E402

LENGTHS = (4.0, 2.0, 3.5, 3.0)  # r1 ground, r2 crank, r3 coupler, r4 rocker (peers.py)
PQ = (1.0, 0.8)
FRAMES = 96  # pylinkage's frames per turn in its fitness


def targets(n):
    th2 = np.radians(np.linspace(0.0, 270.0, n))
    return oracles.four_bar(*LENGTHS, th2, p=PQ[0], q=PQ[1])["C"]


SIX = dict(ground=4.0, crank=1.5, coupler=4.0, rocker=3.5, coupler_point=(2.0, 1.5), link_5=4.0, link_6=3.0,
           pivot_6=(3.0, 4.0), tracer=(1.0, 0.5), pivot=(1.0, -2.0))


def six_targets(n):
    return stephenson_tracer(**SIX).sweep(np.radians(np.linspace(0.0, 300.0, n))).position("P")


class Clock:
    """Wall-clock and CPU seconds of a ``with`` block."""

    def __enter__(self):
        self.t, self.c = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall, self.cpu = time.perf_counter() - self.t, time.process_time() - self.c


def measured(build, point, design, T):
    """Largest distance from a target to the design's traced path over one turn (relative to
    the targets' size), the crank angles of the nearest points and planar's defects there."""
    size = np.ptp(T, axis=0).max()
    u = np.radians(np.arange(0.0, 360.0, 0.1))
    res = build(**design, start=0.0).sweep(u)
    C = res.position(point)
    d = np.hypot(*(C[None, :, :] - T[:, None, :]).transpose(2, 0, 1))
    d = np.where(np.isnan(d), np.inf, d)
    k = np.argmin(d, axis=1)
    err = float(d[np.arange(len(T)), k].max() / size)
    try:
        s = path_check({**design, "start": float(u[k[0]])}, u[k], T)
        defects = "; ".join(s.defects) or "none"
    except PlanarError as e:
        defects = f"cannot be checked: {e}"
    return err, defects


def run_planar(synth, T, seed):
    with Clock() as c:
        try:
            s = synth(T, seed=seed)
        except SynthesisError as e:
            s = e
    if isinstance(s, SynthesisError):
        return c, math.nan, f"none found: {s}"
    return c, s.max_error / s.size, "; ".join(s.defects) or "none"


def run_pylinkage_synthesis(T):
    """pylinkage's answers are its own Linkage objects: measured by its own verify (the nearest
    of its simulated coupler points to each target), not rebuilt in planar."""
    from pylinkage.synthesis import path_generation, verify_path_generation

    with Clock() as c, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = path_generation([tuple(p) for p in T], max_solutions=1)
    if not result.solutions:
        return c, math.nan, "no solution returned"
    _, dist = verify_path_generation(result.solutions[0], [tuple(p) for p in T])
    return c, max(dist) / np.ptp(T, axis=0).max(), "not checked by planar (its own verify: error shown)"


def pso_four_bar():
    """pylinkage's four-bar with the known ground pivots, the index of its traced point, the
    swarm's bounds and the planar design of its dimensions."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    O2, O4 = Ground(0.0, 0.0, name="O2"), Ground(LENGTHS[0], 0.0, name="O4")
    crank = Crank(O2, radius=LENGTHS[1], angular_velocity=2 * math.pi / FRAMES, initial_angle=0.0, name="A")
    B = oracles.four_bar(*LENGTHS, 0.0)["B"]
    rocker = RRRDyad(crank.output, O4, distance1=LENGTHS[2], distance2=LENGTHS[3], x=B[0], y=B[1], name="B")
    coupler = FixedDyad(crank.output, rocker, distance=math.hypot(*PQ), angle=math.atan2(PQ[1], PQ[0]), name="C")

    def design(r2, r3, r4, dist, ang):
        return dict(ground=LENGTHS[0], crank=r2, coupler=r3, rocker=r4,
                    coupler_point=(dist * math.cos(ang), dist * math.sin(ang)))

    bounds = ([0.3, 0.3, 0.3, 0.0, -math.pi], [6.0, 8.0, 8.0, 6.0, math.pi])
    return Linkage([O2, O4, crank, rocker, coupler], name="four-bar"), 4, bounds, design


def pso_six_bar():
    """pylinkage's Stephenson six-bar with the known ground pivots, as :func:`pso_four_bar`."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    x0, y0 = SIX["pivot"]
    at = stephenson_tracer(**SIX).sweep([0.0])
    (Bx, By), (Dx, Dy) = at.position("B")[0], at.position("D")[0]
    O2, O4 = Ground(x0, y0, name="O2"), Ground(x0 + SIX["ground"], y0, name="O4")
    O6 = Ground(*SIX["pivot_6"], name="O6")
    crank = Crank(O2, radius=SIX["crank"], angular_velocity=2 * math.pi / FRAMES, initial_angle=0.0, name="A")
    rocker = RRRDyad(crank.output, O4, distance1=SIX["coupler"], distance2=SIX["rocker"], x=Bx, y=By, name="B")
    pq = SIX["coupler_point"]
    C = FixedDyad(crank.output, rocker, distance=math.hypot(*pq), angle=math.atan2(pq[1], pq[0]), name="C")
    D = RRRDyad(C, O6, distance1=SIX["link_5"], distance2=SIX["link_6"], x=Dx, y=Dy, name="D")
    pq = SIX["tracer"]
    P = FixedDyad(C, D, distance=math.hypot(*pq), angle=math.atan2(pq[1], pq[0]), name="P")

    def design(r2, r3, r4, dist, ang, r5, r6, dist5, ang5):
        return dict(SIX, crank=r2, coupler=r3, rocker=r4, coupler_point=(dist * math.cos(ang), dist * math.sin(ang)),
                    link_5=r5, link_6=r6, tracer=(dist5 * math.cos(ang5), dist5 * math.sin(ang5)))

    bounds = ([0.3, 0.3, 0.3, 0.0, -math.pi, 0.3, 0.3, 0.0, -math.pi],
              [6.0, 8.0, 8.0, 6.0, math.pi, 8.0, 8.0, 6.0, math.pi])
    return Linkage([O2, O4, O6, crank, rocker, C, D, P], name="six-bar"), 7, bounds, design


def run_pylinkage_pso(structure, build, point, T, particles, iterations, seed):
    from pylinkage.optimization.particle_swarm import particle_swarm_optimization
    from pylinkage.optimization.utils import kinematic_minimization

    linkage, iP, bounds, to_design = structure()

    @kinematic_minimization
    def fitness(loci, **_):
        P = np.array([frame[iP] for frame in loci], float)
        return float(np.hypot(*(P[None, :, :] - T[:, None, :]).transpose(2, 0, 1)).min(axis=1).max())

    np.random.seed(seed)
    with Clock() as c:
        best = particle_swarm_optimization(fitness, linkage, bounds=bounds, n_particles=particles,
                                           iterations=iterations, order_relation=min, verbose=False)
    design = to_design(*(float(v) for v in np.asarray(best.dimensions, float)[0]))
    try:
        err, defects = measured(build, point, design, T)
    except PlanarError as e:
        err, defects = math.nan, f"its best design does not assemble at crank 0 in planar: {e}"
    return c, err, defects


def table(title, rows):
    print(f"| {title} | time s | CPU s | max error / size | defects |")
    print("|---|---|---|---|---|")
    for name, c, err, defects in rows:
        print(f"| {name} | {c.wall:.3g} | {c.cpu:.3g} | {err:.3g} | {defects} |")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--targets", type=int, default=4, help="four-bar target points (default 4)")
    p.add_argument("--six-targets", type=int, default=11, help="six-bar target points (default 11; 0: no six-bar)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--particles", type=int, default=100, help="pylinkage PSO particles (default 100)")
    p.add_argument("--iterations", type=int, default=100, help="pylinkage PSO iterations (default 100)")
    args = p.parse_args(argv)
    try:
        import pylinkage  # noqa: F401
    except ImportError:
        pylinkage = None
        print("pylinkage is not installed (pip install -e \".[bench]\"): planar alone")
    pso = f"pylinkage PSO {args.particles}x{args.iterations}"
    T = targets(args.targets)
    rows = [("planar path_four_bar", *run_planar(path_four_bar, T, args.seed))]
    if pylinkage is not None:
        rows.append(("pylinkage path_generation", *run_pylinkage_synthesis(T)))
        rows.append((pso, *run_pylinkage_pso(pso_four_bar, four_bar, "C", T, args.particles, args.iterations,
                                             args.seed)))
    table(f"four-bar, {args.targets} targets", rows)
    if args.six_targets:
        T = six_targets(args.six_targets)
        rows = [("planar path_six_bar", *run_planar(path_six_bar, T, args.seed))]
        if pylinkage is not None:
            rows.append((pso, *run_pylinkage_pso(pso_six_bar, stephenson_tracer, "P", T, args.particles,
                                                 args.iterations, args.seed)))
        print()
        table(f"six-bar, {args.six_targets} targets", rows)


if __name__ == "__main__":
    main()
