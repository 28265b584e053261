"""Kinetostatics: driving efforts and joint reactions from the transposed Jacobian.

At each solved value the bodies move as the sweep says; their d'Alembert inertia forces, the
weights and the external loads are balanced by the joints and drivers:

    Phi_q^T lambda = Q,   Q = Q_loads + Q_gravity - (M qdd + the velocity terms)

with Q the generalised forces on every body's (x, y, phi) and lambda one Lagrange multiplier
per constraint row. A joint acts on its bodies with ``-force_rows^T lambda`` (its Jacobian,
see :meth:`planar.joints.base.Joint.force_rows`); a driver's effort (the torque or force the
input has to apply, positive along its coordinate, so that its power is effort x input rate)
is minus its multiplier. Each joint class names its reaction components (a normal force, a
moment, a tooth force): the code here never asks what type a joint is.

Redundant joints make the reactions statically indeterminate: the multipliers then are the
minimum-norm split (forces, and moments counted per characteristic length L), and an
:class:`planar.errors.IndeterminateWarning` names the joints whose share is not unique.
Values not SOLVED or NEAR_SINGULAR give NaN.

>>> import numpy as np, planar
>>> m = planar.Mechanism()
>>> arm = m.add_body("arm", **planar.bar(2.0, (0, 0), (1, 0)))   # 2 kg, 1 m, horizontal
>>> m.add_revolute("O", m.ground, arm, at=(0, 0))
>>> m.gravity = (0.0, -9.81)
>>> m.drive("O")
>>> f = m.sweep([0.0, np.pi / 2], velocity=0.0).forces()
>>> f.driver_effort("O").round(6).tolist()     # holding torque m g L / 2, then none
[9.81, 0.0]
>>> (f.reaction("O") + 0.0).round(6).tolist()    # the pin carries the weight
[[0.0, 19.62], [0.0, 19.62]]
"""

import warnings
from dataclasses import dataclass

import numpy as np

from planar.blocks import plan as block_plan
from planar.errors import IndeterminateWarning, InputError, ModelError
from planar.geometry import cross, perp, rotate
from planar.model import checks
from planar.results import Status
from planar.system import chunks

# values whose accelerations are sound: a BRANCH_EVENT sits where the multipliers are not unique
_SOUND = (Status.SOLVED, Status.NEAR_SINGULAR)


@dataclass(frozen=True, eq=False)
class Forces:
    """Kinetostatics of a :class:`planar.Sweep`, one row per input value, arrays read-only.

    ``multipliers`` (N, m) holds the Lagrange multipliers of every row; ``indeterminate``
    the joints whose reactions are a minimum-norm split (empty when all are determinate).
    Forces are in the units of mass x length / time^2 of the model (N with kg, m, s).
    """

    sweep: object
    multipliers: np.ndarray
    inertia_forces: np.ndarray  # (N, n_bodies, 2) -m a_c (the ground's zero)
    inertia_torques: np.ndarray  # (N, n_bodies) -I alpha about each centre of mass
    centres: np.ndarray  # (N, n_bodies, 2) world centres of mass
    reactions: dict  # joint name -> component name -> (N,) or (N, 2)
    indeterminate: tuple = ()

    def __post_init__(self):
        arrays = [self.multipliers, self.inertia_forces, self.inertia_torques, self.centres]
        arrays += [a for comps in self.reactions.values() for a in comps.values()]
        for a in arrays:
            a.flags.writeable = False

    def __len__(self):
        return self.multipliers.shape[0]

    def driver_effort(self, name):
        """(N,) the torque or force driver ``name`` applies along its coordinate (its power is
        this times the input rate): a joint's driver acts on the joint's second body."""
        model = self.sweep.model
        if not isinstance(name, str) or name not in model.input_names:
            raise ModelError(f"unknown driver {name!r}: the drivers are {list(model.input_names)}")
        return -self.multipliers[:, model.row_adr[len(model.joints) + model.input_names.index(name)]]

    def reaction(self, joint, component="force"):
        """The reaction on ``joint``'s second body from its first: ``"force"`` (N, 2) in world
        axes, or a component (N,) the joint carries: ``"normal"`` (slot, prismatic, rack,
        rolling), ``"moment"`` (prismatic), ``"tangential"``, ``"radial"`` and ``"contact"``
        (gears, racks: the tooth force along the pressure line), ``"friction"`` (rolling)."""
        comps = self.reactions.get(joint) if isinstance(joint, str) else None
        if comps is None:
            raise ModelError(f"unknown joint {joint!r}: the joints are {list(self.reactions)}")
        if not isinstance(component, str) or component not in comps:
            raise ModelError(f"joint {joint!r} has no reaction component {component!r}: it has {list(comps)}")
        return comps[component]

    def inertia_force(self, body):
        """(N, 2) the d'Alembert force -m a of ``body``, at its centre of mass."""
        return self.inertia_forces[:, self.sweep.model.body_id(body)]

    def inertia_torque(self, body):
        """(N,) the d'Alembert torque -I alpha of ``body`` about its centre of mass."""
        return self.inertia_torques[:, self.sweep.model.body_id(body)]

    def shaking_force(self):
        """(N, 2) the resultant of the inertia forces: the force the moving mechanism puts on
        its frame, weights and external loads left out."""
        return self.inertia_forces.sum(axis=1)

    def shaking_moment(self, about=(0.0, 0.0)):
        """(N,) the moment of the inertia forces and torques about the world point ``about``
        (the frame's moment, weights and external loads left out)."""
        try:
            about = checks.point(about, "shaking_moment about")
        except ModelError as e:
            raise InputError(str(e)) from None
        arm = self.centres - about
        return (cross(arm, self.inertia_forces) + self.inertia_torques).sum(axis=1)

    def mechanical_advantage(self, output):
        """(N,) the ideal mechanical advantage of a one-input mechanism: the generalised force
        at ``output`` (a joint's coordinate, or a body's angle) per unit input effort when
        power passes without loss, i.e. the input's rate over the output's."""
        res, model = self.sweep, self.sweep.model
        if len(model.drivers) != 1:
            raise ModelError(f"mechanical advantage needs one input; the model has {list(model.input_names)}")
        if not isinstance(output, str) or output == model.body_names[0]:  # (the ground's: inf everywhere)
            raise ModelError(f"mechanical advantage: output is a joint's or a moving body's name, got {output!r}")
        rate = res.coordinate(output, 1) if output in model.coordinates else res.omega(output)
        with np.errstate(divide="ignore", invalid="ignore"):
            return res.input_rates[:, 0] / rate


def as_forces(forces, who):
    """``forces`` where it is a :class:`Forces`, else an InputError saying ``who`` needs one."""
    if not isinstance(forces, Forces):
        raise InputError(f"{who} needs the forces of a sweep (Sweep.forces()), got {type(forces).__name__}")
    return forces


def forces(res):
    """The :class:`Forces` of sweep ``res`` (see the module docstring); prefer
    :meth:`planar.Sweep.forces`."""
    model = res.model
    sound = np.isin(res.status, _SOUND) & np.all(np.isfinite(res.qdd), axis=1) & np.all(np.isfinite(res.q), axis=1)
    # unsound values are evaluated at the sketch at rest (a regular pose), then set to NaN
    q = np.where(sound[:, None], res.q, model.q0)
    qd, qdd = (np.where(sound[:, None], a, 0.0) for a in (res.qd, res.qdd))
    u = np.where(sound[:, None], res.inputs, model.u0)
    out, stand_in = None, _stand_ins(model)
    for sl in chunks(len(res)):
        try:
            with np.errstate(over="raise"):
                part = _values(model, q[sl], qd[sl], qdd[sl], u[sl], stand_in)
        except FloatingPointError:
            raise InputError(f"the forces of {model.name!r} overflow float64 (masses, lengths and input rates this "
                             f"large): give them in other units") from None
        if out is None:  # the whole arrays, shaped as the first chunk's
            out = [np.empty((len(res),) + a.shape[1:]) for a in part[:4]]
            reactions = {j: {c: np.empty((len(res),) + v.shape[1:]) for c, v in comps.items()}
                         for j, comps in part[4].items()}
        for a, p in zip(out, part[:4]):
            a[sl] = p
        for j, comps in part[4].items():
            for c, v in comps.items():
                reactions[j][c][sl] = v
    lam, F_in, T_in, centres = out
    for a in [lam, F_in, T_in, centres] + [v for comps in reactions.values() for v in comps.values()]:
        a[~sound] = np.nan
    involved = _indeterminate(model)
    if involved:
        warnings.warn(f"mechanism {model.name!r} is statically indeterminate: the reactions of {list(involved)} "
                      f"are not unique (redundant: {list(model.redundant_joints)}); they are the minimum-norm "
                      f"split. Remove the redundant joints, or make them compliant, for a unique answer",
                      IndeterminateWarning, stacklevel=3)
    return Forces(res, lam, F_in, T_in, centres, reactions, involved)


def _values(model, q, qd, qdd, u, stand_in):
    """Multipliers (N, m), inertia forces, torques and centres (see :func:`_applied`) and the
    reactions {joint: {component: (N,) or (N, 2)}} at the configurations q (N, n);
    ``stand_in``: see :func:`_stand_ins`."""
    n, N = model.n, q.shape[0]
    Q, F_in, T_in, centres = _applied(model, q, qd, qdd, u)
    pieces, blocks = _force_rows(model, q, u)
    solve, carry = _solver(model, q, u, pieces, blocks, stand_in)
    lam = solve(Q)
    # forces a joint adds as its multipliers say (a tooth force's radial part): a second
    # right-hand side, the same factors, that leaves those multipliers as they are
    extra, contact, held = np.zeros((n + 1, N)), [], []
    for g, P, F in pieces:
        contact.append(g.kind.contact_load(P, F, lam.T[g.rows.T]))
        if contact[-1] is not None:
            _add_columns(extra, g.cols, contact[-1])
            held.append(g.rows.ravel())
    if held:
        lam = lam + carry(extra[:n].T, np.concatenate(held))

    reactions = {}
    for (g, P, F), B, C in zip(pieces, blocks, contact):
        if g.members[0] >= len(model.joints):
            continue  # drivers: their efforts are the multipliers themselves
        lg = lam.T[g.rows.T]
        force = -np.einsum("rcKN,rKN->KNc", B[:, 3:5], lg)
        if C is not None:
            force += np.moveaxis(C[3:5], 0, -1)
        comps = g.kind.reaction(P, F, lg)
        for k, i in enumerate(g.members):
            reactions[model.joints[i].name] = {"force": force[k],
                                               **{c: np.array(np.broadcast_to(v[k], (N,))) for c, v in comps.items()}}
    return lam, F_in, T_in, centres, reactions


def _solver(model, q, u, pieces, blocks, stand_in):
    """Two functions of Q (N, n) giving lam (N, m) with ``W^T lam = Q`` (W: the force rows) at
    the configurations q: the minimum-norm one, and one whose multipliers of the rows ``held``
    (its second argument) are 0, the minimum norm among those (a tooth force's radial part:
    what holds the centre distances carries it, the tooth forces' split stays as the loads
    made it, and every body stays in balance). Both go through the kinematic plan's block
    factors at q: one transposed block solve (:meth:`planar.blocks.Factors.solve_transpose`).
    Where a joint's force rows stand in for its Jacobian rows (a gear on a carrier:
    ``stand_in``), one correction with the same factors makes the answer exact (the
    difference lies in the rows of the pins holding the gears, so their multipliers take it up
    at once). Redundant rows (outside the plan) get the minimum-norm split: moments counted
    per length L, the self-balancing multipliers projected out."""
    m, N = model.system.m, q.shape[0]
    p = block_plan(model)
    lu = p.factor(p.evaluate(q, u)[2], dets=False)

    def particular(c):
        lam = np.zeros((N, m))
        lam[:, p.rows] = lu.solve_transpose(c)
        if stand_in:
            lam[:, p.rows] += lu.solve_transpose(c - _transposed(model, pieces, blocks, lam))
        return lam

    free = np.setdiff1d(np.arange(m), p.rows)
    if not free.size:
        return particular, lambda c, held: particular(c)
    # a basis of the self-balancing multipliers: one per redundant row, the rest balancing it
    V = np.empty((N, m, free.size))
    for k, r in enumerate(free):
        e = np.zeros((N, m))
        e[:, r] = 1.0
        V[..., k] = e - particular(_transposed(model, pieces, blocks, e))
    w2 = np.where(_length_rows(model), 1.0, model.L**-2)
    M = np.einsum("nik,i,nil->nkl", V, w2, V)

    def least_norm(c):
        lam = particular(c)
        z = np.linalg.solve(M, -np.einsum("nik,i,ni->nk", V, w2, lam)[..., None])[..., 0]
        return lam + np.einsum("nik,nk->ni", V, z)

    def held_least_norm(c, held):
        # the least norm with lam[held] = 0: its KKT system (a rank-deficient VH when
        # redundant rows are held themselves, so a pseudo-inverse)
        lam, k, VH = particular(c), free.size, V[:, held]
        A = np.zeros((N, k + held.size, k + held.size))
        A[:, :k, :k], A[:, :k, k:], A[:, k:, :k] = M, VH.transpose(0, 2, 1), VH
        b = np.concatenate((-np.einsum("nik,i,ni->nk", V, w2, lam), -lam[:, held]), axis=1)
        z = np.einsum("nij,nj->ni", np.linalg.pinv(A, rcond=1e-12), b)[:, :k]
        return lam + np.einsum("nik,nk->ni", V, z)

    return least_norm, held_least_norm


def _force_rows(model, q, u):
    """Each group's (group, parameters, frames) and its force rows (n_rows, 3 n_bodies, K, N)."""
    system = model.system
    full = system.full(q)
    pieces = [(g, g.params(u), g.frames(full)) for g in system.groups]
    return pieces, [g.kind.force_rows(P, F) for g, P, F in pieces]


def _transposed(model, pieces, blocks, lam):
    """W^T lam (N, n): the generalised forces of multipliers ``lam`` (N, m) through the force
    rows."""
    out = np.zeros((model.n + 1, lam.shape[0]))
    for (g, _, _), B in zip(pieces, blocks):
        _add_columns(out, g.cols, np.einsum("rcKN,rKN->cKN", B, lam.T[g.rows.T]))
    return out[: model.n].T


def _add_columns(out, cols, values):
    """``out[cols.T] += values`` (values (3 n_bodies, K, N)) with the members' shares summed
    where they meet on a body: member by member (a joint's bodies differ, so its own columns
    repeat only in the ground's dump column, which is dropped)."""
    for k in range(cols.shape[0]):
        out[cols[k]] += values[:, k]


def _sketch_rows(model):
    """The force rows W (m, n) at the sketch, dense."""
    pieces, blocks = _force_rows(model, model.q0[None], model.u0[None])
    W = np.zeros((model.system.m, model.n + 1))
    for (g, _, _), B in zip(pieces, blocks):
        W[g.rows.T[:, None, :], g.cols.T[None, :, :]] = B[..., 0]
    return W[:, : model.n]


def _stand_ins(model):
    """Whether some joint's force rows are not its Jacobian rows (read at the sketch)."""
    W = _sketch_rows(model)
    J = model.system.evaluate(model.q0[None], model.u0[None])[1][0]
    return bool(np.any(np.abs(W - J) > 1e-9 * np.abs(J).max()))


def _length_rows(model):
    return np.concatenate([np.array(c.length_rows, bool) for c in model.joints + model.drivers])


def _applied(model, q, qd, qdd, u):
    """Q (N, n): the generalised forces of gravity, loads and d'Alembert inertia on every
    body's (x, y, phi); and the inertia forces (N, nb, 2), torques (N, nb) and the world
    centres of mass (N, nb, 2) (the ground's: zero)."""
    N, nb = q.shape[0], len(model.body_names)
    x, xd, xdd = (a.reshape(N, nb - 1, 3) for a in (q, qd, qdd))
    phi, w, al = x[..., 2], xd[..., 2], xdd[..., 2]
    m, I = model.mass[1:], model.inertia[1:]
    S = rotate(phi, model.com[1:])
    a_c = xdd[..., :2] + perp(S) * al[..., None] - S * (w**2)[..., None]
    F_in, T_in = np.zeros((N, nb, 2)), np.zeros((N, nb))
    F_in[:, 1:] = -m[:, None] * a_c
    T_in[:, 1:] = -I * al
    centres = np.zeros((N, nb, 2))
    centres[:, 1:] = x[..., :2] + S
    Fb = F_in[:, 1:] + m[:, None] * model.gravity
    Q = np.concatenate((Fb, (cross(S, Fb) + T_in[:, 1:])[..., None]), axis=-1)
    for load in model.loads:
        b = load.body - 1
        f, t = load.at(u, phi[:, b])
        Q[:, b, :2] += f
        Q[:, b, 2] += cross(rotate(phi[:, b], load.s), f) + t
    return Q.reshape(N, -1), F_in, T_in, centres


def _indeterminate(model):
    """The joints whose rows take part in a self-balancing set of multipliers at the sketch."""
    if not model.redundant_joints:
        return ()
    W = _sketch_rows(model) * model.row_scale[:, None] * model.col_scale[None, :]
    U, sv, _ = np.linalg.svd(W)
    rank = int(np.sum(sv > 1e-9 * max(sv[0], 1e-300)))
    null = U[:, rank:]  # multipliers that balance themselves
    rows = np.flatnonzero(np.abs(null).max(axis=1) > 1e-9)
    owners = {int(np.searchsorted(model.row_adr, r, side="right") - 1) for r in rows}
    return tuple(model.joints[i].name for i in sorted(owners) if i < len(model.joints))


__all__ = ["Forces", "forces"]
