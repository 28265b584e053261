"""Path generation: time to a defect-free four-bar through N targets, planar against pylinkage.

The targets are N points of the coupler curve of a known four-bar (the peers' four-bar of
``peers.py``: O2 = (0, 0), O4 = (4, 0), crank 2, coupler 3.5, rocker 3, coupler point
(1.0, 0.8) along and left of A -> B), at crank angles spread over 270 deg. Each method gets the
same targets and runs once:

- planar: :func:`planar.synthesis.path_four_bar` (free timing, seeded search, least squares,
  the answer checked by planar's sweep: its errors and defects are its own);
- pylinkage's classical path synthesis, ``pylinkage.synthesis.path_generation`` (Burmester
  theory over the free coupler orientations; practical for 3-5 points);
- pylinkage's particle swarm, ``particle_swarm_optimization`` over the crank, coupler, rocker
  lengths and the coupler point (distance, angle), the ground pivots given (the known ones: a
  head start the others do not get); fitness: the largest distance from a target to the
  coupler points of one 96-frame turn.

planar's answer is measured by its own check (exact crank angles at the targets). The swarm's
best design is rebuilt as a planar ``four_bar``, swept over one crank turn at 0.1 deg, its
error the distance from each target to the nearest swept coupler point (relative to the
targets' size), its defects planar's check on the crank interval that visits the targets in
order (``path_check``). The Burmester synthesis returns pylinkage linkages of its own, measured
by pylinkage's ``verify_path_generation``.

    python3 benchmarks/synthesis_speed.py                   # 4 targets, PSO 100 particles x 100 iterations
    python3 benchmarks/synthesis_speed.py --targets 6 --particles 50 --iterations 50
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
from planar.synthesis import SynthesisError, path_check, path_four_bar  # noqa: E402
from tests import oracles  # noqa: E402

LENGTHS = (4.0, 2.0, 3.5, 3.0)  # r1 ground, r2 crank, r3 coupler, r4 rocker (peers.py)
PQ = (1.0, 0.8)
FRAMES = 96  # pylinkage's frames per turn in its fitness


def targets(n):
    th2 = np.radians(np.linspace(0.0, 270.0, n))
    return oracles.four_bar(*LENGTHS, th2, p=PQ[0], q=PQ[1])["C"]


def measured(design, T):
    """Largest distance from a target to the design's coupler curve over one turn (relative to
    the targets' size), the crank angles of the nearest points and planar's defects there."""
    size = np.ptp(T, axis=0).max()
    u = np.radians(np.arange(0.0, 360.0, 0.1))
    res = four_bar(**design, start=0.0).sweep(u)
    C = res.position("C")
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


def run_planar(T, seed):
    t = time.perf_counter()
    try:
        s = path_four_bar(T, seed=seed)
    except SynthesisError as e:
        return time.perf_counter() - t, math.nan, f"none found: {e}"
    dt = time.perf_counter() - t
    return dt, s.max_error / s.size, "; ".join(s.defects) or "none"


def run_pylinkage_synthesis(T):
    """pylinkage's answers are its own Linkage objects: measured by its own verify (the nearest
    of its simulated coupler points to each target), not rebuilt in planar."""
    from pylinkage.synthesis import path_generation, verify_path_generation

    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = path_generation([tuple(p) for p in T], max_solutions=1)
    dt = time.perf_counter() - t
    if not result.solutions:
        return dt, math.nan, "no solution returned"
    _, dist = verify_path_generation(result.solutions[0], [tuple(p) for p in T])
    return dt, max(dist) / np.ptp(T, axis=0).max(), "not checked by planar (its own verify: error shown)"


def pso_linkage():
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    O2, O4 = Ground(0.0, 0.0, name="O2"), Ground(LENGTHS[0], 0.0, name="O4")
    crank = Crank(O2, radius=LENGTHS[1], angular_velocity=2 * math.pi / FRAMES, initial_angle=0.0, name="A")
    B = oracles.four_bar(*LENGTHS, 0.0)["B"]
    rocker = RRRDyad(crank.output, O4, distance1=LENGTHS[2], distance2=LENGTHS[3], x=B[0], y=B[1], name="B")
    coupler = FixedDyad(crank.output, rocker, distance=math.hypot(*PQ), angle=math.atan2(PQ[1], PQ[0]), name="C")
    return Linkage([O2, O4, crank, rocker, coupler], name="four-bar"), 4


def run_pylinkage_pso(T, particles, iterations, seed):
    from pylinkage.optimization.particle_swarm import particle_swarm_optimization
    from pylinkage.optimization.utils import kinematic_minimization

    linkage, iC = pso_linkage()

    @kinematic_minimization
    def fitness(loci, **_):
        C = np.array([frame[iC] for frame in loci], float)
        return float(np.hypot(*(C[None, :, :] - T[:, None, :]).transpose(2, 0, 1)).min(axis=1).max())

    bounds = ([0.3, 0.3, 0.3, 0.0, -math.pi], [6.0, 8.0, 8.0, 6.0, math.pi])
    np.random.seed(seed)
    t = time.perf_counter()
    best = particle_swarm_optimization(fitness, linkage, bounds=bounds, n_particles=particles,
                                       iterations=iterations, order_relation=min, verbose=False)
    dt = time.perf_counter() - t
    r2, r3, r4, dist, ang = np.asarray(best.dimensions, float)[0]
    design = dict(ground=LENGTHS[0], crank=float(r2), coupler=float(r3), rocker=float(r4),
                  coupler_point=(float(dist * math.cos(ang)), float(dist * math.sin(ang))))
    try:
        err, defects = measured(design, T)
    except PlanarError as e:
        err, defects = math.nan, f"its best design does not assemble at crank 0 in planar: {e}"
    return dt, err, defects


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--targets", type=int, default=4, help="target points (default 4)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--particles", type=int, default=100, help="pylinkage PSO particles (default 100)")
    p.add_argument("--iterations", type=int, default=100, help="pylinkage PSO iterations (default 100)")
    args = p.parse_args(argv)
    T = targets(args.targets)
    rows = [("planar path_four_bar", *run_planar(T, args.seed))]
    try:
        import pylinkage  # noqa: F401
    except ImportError:
        print("pylinkage is not installed (pip install -e \".[bench]\"): planar alone")
    else:
        rows.append(("pylinkage path_generation", *run_pylinkage_synthesis(T)))
        rows.append((f"pylinkage PSO {args.particles}x{args.iterations}",
                     *run_pylinkage_pso(T, args.particles, args.iterations, args.seed)))
    print(f"| method ({args.targets} targets) | time s | max error / size | defects |")
    print("|---|---|---|---|")
    for name, dt, err, defects in rows:
        print(f"| {name} | {dt:.3g} | {err:.3g} | {defects} |")


if __name__ == "__main__":
    main()
