"""The compile step: an assembled :class:`~planar.model.frozen.Sketch` to a
:class:`~planar.model.frozen.Model`: the constraint system, the rank of the joints and which
of them are redundant, the sketch assembled on the independent rows, the drivers checked."""

import numpy as np

from planar.blocks import plan as block_plan
from planar.errors import AssemblyError, MobilityError, ModelError, RedundancyError
from planar.joints.base import SketchFrames
from planar.mass import compile_mass
from planar.model.checks import MAX_ANGLE
from planar.model.frozen import Model
from planar.model.resolve import char_length, frame_origins
from planar.system import build_system

RANK_TOL = 1e-9  # a joint row is independent of the others where its pivot is above this of the largest
RANK_ROUNDING = 1e-12  # below this a row depends on the others but for rounding (a pin declared twice)


def compile_sketch(name, sk, plan=True):
    """The Model of an assembled :class:`Sketch` (body angles in radians); without ``plan``,
    not yet checked drivable (a study of designs plans one of each structure)."""
    joints = list(sk.joints)
    drivers = list(sk.drivers)
    bodies = list(sk.bodies)

    origins = frame_origins(joints, sk.points)
    sketch = SketchFrames(origins, dict(sk.bodies))

    constraints = joints + drivers
    params = [c.params(sketch) for c in constraints]
    body_index = {b: i for i, b in enumerate(bodies)}
    inputs = [-1] * len(joints) + list(range(len(drivers)))
    system, row_adr = build_system(constraints, params, body_index, len(bodies), inputs)
    n, m = system.n, system.m
    for b in bodies[1:]:
        if not abs(sk.bodies[b]) <= MAX_ANGLE:
            raise ModelError(f"body {b!r} is drawn at the angle {sk.bodies[b]:.6g} rad, beyond +-{MAX_ANGLE:.6g} rad "
                             f"(float64 rounds it by more than the rows' tolerance): give it within a turn")
    q0 = np.concatenate([np.r_[origins[b], sk.bodies[b]] for b in bodies[1:]]) if n else np.zeros(0)

    # the named points enter no row (a driven point enters as its driver's): they leave the scale alone
    L = char_length({}, constraints)
    far = max([float(np.max(np.abs(q0.reshape(-1, 3)[:, :2]), initial=0.0))]
              + [float(np.max(np.abs(p))) for c in joints for _, p in c.touch_points()])
    if far > MAX_ANGLE * L:  # (as for angles: float64's spacing there is 1.9e-9 of the size)
        raise ModelError(f"the sketch lies {far:.3g} from the world origin, {far / L:.3g} times its size {L:.3g}: "
                         f"float64 holds its points to {np.spacing(far) / L:.2g} of its size, beyond the rows' "
                         f"tolerance; move it within {MAX_ANGLE * L:.3g} of the origin")
    lengths = np.concatenate([np.array(c.length_rows, bool) for c in constraints]) if m else np.zeros(0, bool)
    row_scale = np.where(lengths, 1.0 / L, 1.0)
    col_scale = np.tile([L, L, 1.0], len(bodies) - 1)
    joint_rows = np.arange(row_adr[len(joints)] if drivers else m)
    driver_rows = np.arange(joint_rows.size, m)
    sketch_rows = np.array([row_adr[i] + r for i, c in enumerate(joints) for r in c.sketch_rows], int)
    geometric = np.setdiff1d(joint_rows, sketch_rows)

    # independent rows first (the rank does not depend on the constants), then assemble the
    # sketch on the independent geometric rows and take the rolling constants there
    rank, independent, unresolved = _joint_rank(system, q0, joint_rows, sketch_rows, row_scale, col_scale)
    redundant = np.setdiff1d(joint_rows, independent)
    names = lambda rows: sorted({_owner(int(i), row_adr, constraints).name for i in rows})  # noqa: E731
    q0 = _assemble(system, q0, np.intersect1d(geometric, independent), row_scale, col_scale, joints, row_adr)
    Phi, _ = system.evaluate(q0[None], np.zeros((1, len(drivers))), jacobian=False)
    for g in system.groups:
        for k, i in enumerate(g.members):
            for r in constraints[i].sketch_rows:
                g.P["c"][k, r] = Phi[0, row_adr[i] + r]
    u0 = Phi[0, driver_rows].copy()
    for d, u in zip(drivers, u0):
        if not d.length_rows[0] and not abs(u) <= MAX_ANGLE:
            raise ModelError(f"driver {d.name!r} starts at {u:.6g} rad, beyond +-{MAX_ANGLE:.6g} rad (float64 rounds "
                             f"it by more than the rows' tolerance): give its start within a turn")
    Phi, _ = system.evaluate(q0[None], u0[None], jacobian=False)
    r = np.abs(Phi[0, redundant] * row_scale[redundant])
    if redundant.size and r.max() > 1e-9:
        worst = _owner(int(redundant[np.argmax(r)]), row_adr, constraints)
        raise RedundancyError(f"{worst.describe()} contradicts the other joints (off by {r.max():.3g} x L) "
                              f"where it repeats what they already hold: make its dimensions agree with "
                              f"theirs, or remove it (redundant: {names(redundant)})")
    redundant_joints = tuple(sorted(names(redundant), key=[j.name for j in joints].index))

    dof = n - rank
    if drivers and len(drivers) < dof and unresolved > RANK_ROUNDING:
        raise MobilityError(f"the mobility of mechanism {name!r} cannot be told in double precision: its joints' "
                            f"rows are independent only to {unresolved:.2g} of its size, below {RANK_TOL:g}, as where "
                            f"links far apart in length meet: give lengths nearer in size")
    if drivers and len(drivers) != dof:
        raise MobilityError(f"mechanism {name!r} has {dof} degree(s) of freedom but {len(drivers)} "
                            f"driver(s) {[d.name for d in drivers]}: "
                            + (f"add {dof - len(drivers)} driver(s)" if len(drivers) < dof
                               else f"remove {len(drivers) - dof} driver(s), or a joint that locks the "
                                    f"mechanism (a pivot declared twice, an extra link)"))
    active = np.concatenate([independent, driver_rows])
    if drivers:
        _check_drivers(system, q0, u0, active, joint_rows.size - redundant.size, drivers, row_scale, col_scale)
    coord = [(j.name, j.coordinate()) for j in joints if j.coordinate() is not None]
    csys, _ = build_system([d for _, d in coord], [d.params(sketch) for _, d in coord], body_index,
                           len(bodies), [-1] * len(coord))
    model = Model(
        coordinates={name: (csys, k) for k, (name, _) in enumerate(coord)},
        name=name, body_names=tuple(bodies), body_angles0=np.array([sk.bodies[b] for b in bodies]),
        points={k: (body_index[b], sketch.local_point(b, p)) for k, (b, p) in sk.points.items()}, sketch=sk,
        joints=tuple(joints), drivers=tuple(drivers), system=system, row_adr=row_adr, q0=q0, u0=u0, L=L,
        row_scale=row_scale, col_scale=col_scale, active_rows=active,
        driver_rows_active=np.arange(len(independent), len(active)), redundant_rows=redundant,
        input_lengths=np.array([d.length_rows[0] for d in drivers], bool), rank=rank,
        grubler=n - joint_rows.size, redundant_joints=redundant_joints,
        **compile_mass(sk.mass or {}, sk.loads, sk.gravity, sketch, bodies))
    if drivers and plan:
        block_plan(model)  # a model the drivers cannot drive is refused here, not at sweep time
    return model



def _owner(row, row_adr, constraints):
    return constraints[int(np.searchsorted(row_adr, row, side="right") - 1)]


def _assemble(system, q, rows, rs, cs, joints, row_adr, iterations=50, held=0.0):
    """Minimum-norm Gauss-Newton on ``rows`` from q: the assembled pose nearest the sketch
    (``held``: (m,) the rows' values to hold, 0 where they are to vanish)."""
    q = q.copy()
    if rows.size == 0:
        return q
    held = np.broadcast_to(held, system.m)
    for _ in range(iterations):
        Phi, J = system.evaluate(q[None])
        r = (Phi[0, rows] - held[rows]) * rs[rows]
        if np.max(np.abs(r)) <= 1e-14:
            return q
        Js = J[0][rows] * rs[rows, None] * cs[None, :]
        dx = np.linalg.lstsq(Js, r, rcond=None)[0]
        dx *= min(1.0, 0.3 / max(np.max(np.abs(dx)), 1e-300))
        q -= dx * cs
    Phi, _ = system.evaluate(q[None], jacobian=False)
    r = np.abs((Phi[0, rows] - held[rows]) * rs[rows])
    if r.max() > 1e-9:
        worst = _owner(int(rows[np.argmax(r)]), row_adr, joints)
        raise AssemblyError(f"the sketch does not assemble: {worst.describe()} stays off by {r.max():.3g} x L; "
                            f"check its points and dimensions")
    return q


def _joint_rank(system, q0, rows, sketch_rows, rs, cs):
    """Rank of the joint rows, the independent ones, and the largest of the others' pivots
    over the largest (``unresolved``: 0 where every row is independent; the largest at the
    poses tried of that rank), at the sketch or, if the sketch is a singular pose, at a nearby
    assembled pose where the rank is higher."""
    best = None
    rng = np.random.default_rng(0)
    q = q0
    # a pose nearby holds the rows whose constants the sketch gives (a slider's angle, a mesh's
    # phase) at their values there: left free, a redundancy that holds only with them (a rack's
    # mesh beside the slider that carries it) reads as independent
    held = np.zeros(system.m)
    held[sketch_rows] = system.evaluate(q0[None], jacobian=False)[0][0, sketch_rows]
    for trial in range(3):
        _, J = system.evaluate(q[None])
        Js = J[0][rows] * rs[rows, None] * cs[None, :]
        if Js.size == 0:
            return 0, rows, 0.0
        import scipy.linalg  # here, not at import: ``import planar`` stays light

        _, R, piv = scipy.linalg.qr(Js.T, pivoting=True, mode="economic")
        diag = np.abs(np.diag(R))
        tol = RANK_TOL * max(diag[0], 1e-300) if diag.size else 0.0
        rank = int(np.sum(diag > tol))
        unresolved = float(diag[rank] / diag[0]) if rank < diag.size else 0.0
        if best is None or rank > best[0]:
            best = (rank, _first_independent(Js, rows, rank, tol, piv), unresolved)
        elif rank == best[0]:
            # (the nearest to independent the rows come at the poses tried: off a singular
            # sketch, rows that double precision cannot tell apart are told from rows that depend)
            best = (rank, best[1], max(best[2], unresolved))
        if rank == min(len(rows), system.n) or trial == 2:  # every row independent: no higher rank
            break
        # move along the free motion and reassemble, to leave a possibly singular sketch
        _, s, Vt = np.linalg.svd(Js)
        null = Vt[rank:]
        q = q + (null.T @ rng.normal(size=null.shape[0])) * 0.05 * cs
        try:
            q = _assemble(system, q, best[1], rs, cs, [], np.zeros(0), held=held)
        except (AssemblyError, IndexError):
            break
    return best


def _first_independent(Js, rows, rank, tol, piv):
    """The ``rank`` independent rows met first in the order the joints were added, so the
    joints called redundant are the later ones whatever the rounding (the pivoted order ``piv``
    where rounding leaves the greedy pick short)."""
    Qt = np.zeros((rank, Js.shape[1]))  # the kept rows' orthonormal basis, a row each
    keep = []
    for k, v in enumerate(Js):
        Q = Qt[: len(keep)]
        r = v - (Q @ v) @ Q
        r -= (Q @ r) @ Q  # twice is enough (Kahan)
        size = np.linalg.norm(r)
        if size > tol:
            Qt[len(keep)] = r / size
            keep.append(k)
            if len(keep) == rank:
                return rows[keep]
    return np.sort(rows[piv[:rank]])


def _check_drivers(system, q0, u0, active, n_joint_rows, drivers, rs, cs):
    _, J = system.evaluate(q0[None], u0[None])
    Js = J[0][active] * rs[active, None] * cs[None, :]
    # unpivoted QR of the rows in order: |R_ii| is row i's distance from the span of the rows
    # before it, so one factorisation says which driver depends on the rows before it
    import scipy.linalg  # here, not at import: ``import planar`` stays light

    R = scipy.linalg.qr(Js.T, mode="r")[0]
    reach = np.abs(np.diagonal(R))
    size = max(1.0, np.abs(Js).max())
    for k, d in enumerate(drivers):
        i = n_joint_rows + k
        if i < reach.size and RANK_ROUNDING * size < reach[i] <= RANK_TOL * size:
            raise MobilityError(f"driver {d.name!r} is independent of the joints and the drivers before it only to "
                                f"{reach[i] / size:.2g} of its size at the sketch, below {RANK_TOL:g}: double "
                                f"precision cannot tell whether it moves the mechanism, as where links far apart in "
                                f"length meet or the sketch lies that near a dead centre of the driver: give lengths "
                                f"nearer in size, or sketch the mechanism at another input value")
        if i >= reach.size or reach[i] <= RANK_TOL * size:
            raise MobilityError(f"driver {d.name!r} depends on the joints or on the drivers before it at the "
                                f"sketch: either it cannot move independently (for example both gears of one "
                                f"mesh driven: drive another coordinate, or remove it), or the sketch is a dead "
                                f"centre of this driver (sketch the mechanism at another input value)")
