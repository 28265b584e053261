"""The compiled constraint system: Phi, Phi_q and gamma over a batch of configurations.

Constraints (joints and drivers) are grouped by class at compile time; each group keeps index
arrays (MuJoCo style ``*_adr``): the body slots it reads, the rows it writes and the columns
of its Jacobian blocks. Evaluation loops over groups, never over configurations, and never
asks what a group's class is.

Coordinates: ``q`` is (N, n) with (x, y, phi) per moving body; the ground (body 0) is fixed
at zero and its Jacobian columns go to a dump column that is dropped.
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from planar.errors import ModelError
from planar.geometry import Frames, cos_sin
from planar.joints.base import kernel_params


@dataclass(frozen=True, eq=False)
class Group:
    kind: type  # the joint class: supplies Phi, Phi_q, gamma
    members: np.ndarray  # (K,) constraint indices
    bodies: np.ndarray  # (K, nb) body ids (0 = ground)
    P: dict  # stacked parameters, (K, ...) arrays, one joint per row
    rows: np.ndarray  # (K, n_rows) global row ids
    cols: np.ndarray  # (K, 3 nb) global column ids, ground columns -> n (dumped)
    inputs: np.ndarray  # (K,) input column of each driver, -1 for joints
    # P holds (D, K, ...) tables, one per design: each configuration reads the parameters of
    # the design in the last column of its inputs u (see :meth:`System.over_designs`)
    per_design: bool = False

    @cached_property
    def kernel_P(self):
        """``P`` as the kernels take it (views: the model's sketch constants reach them); per
        design (D, K, a, b) -> (b, a, K, D), the design axis where the configurations go, a
        contiguous copy (so a gather of designs reads whole rows; a group per design is made
        with its final tables)."""
        if self.per_design:
            return {key: np.ascontiguousarray(v.T) for key, v in self.P.items()}
        return kernel_params(self.P)

    @cached_property
    def slots(self):
        """(nb, K) body ids, slot first: the gather of the group's frames."""
        return np.ascontiguousarray(self.bodies.T)

    def params(self, u, sl=slice(None)):
        """Kernel parameters at the configurations ``sl`` of the inputs ``u`` (N, f)."""
        P = self.kernel_P
        if self.per_design:
            d = u[sl, -1].astype(np.intp)
            D = self.members.size and next(iter(self.P.values())).shape[0]
            if d.size != D or np.any(d != np.arange(D)):  # (every design once, in order: no gather)
                P = {key: v[..., d] for key, v in P.items()}
        if self.inputs[0] < 0 or u is None:
            return P
        # a driver row is g(q) - u: the input values (1, K, N) stand in the constant c
        return dict(P, c=u[sl, self.inputs].T[None])

    def frames(self, full):
        """The group's :class:`Frames` from the bodies' (x, y, phi, cos, sin[, rates]) rows."""
        return Frames.gather(full, self.slots)


# a body's rows in the full array: x, y, phi, cos phi, sin phi, and the rates xd, yd, phid
_GROUND = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])[:, None]


@dataclass(frozen=True, eq=False)
class System:
    n_bodies: int  # including the ground
    m: int  # rows
    groups: tuple

    @property
    def n(self):
        return 3 * (self.n_bodies - 1)

    def full(self, q, qd=None):
        """(5, n_bodies, N) rows x, y, phi, cos, sin of every body, configurations last (8
        with the rates xd, yd, phid): one transposing copy of q, so the groups' gathers and
        all kernel operations run over contiguous rows of configurations."""
        N = q.shape[0]
        full = np.empty((5 if qd is None else 8, self.n_bodies, N))
        full[:, 0] = _GROUND[: len(full)]
        full[:3, 1:] = q.reshape(N, self.n_bodies - 1, 3).T
        cos_sin(full[2, 1:], full[3, 1:], full[4, 1:])
        if qd is not None:
            full[5:, 1:] = qd.reshape(N, self.n_bodies - 1, 3).T
        return full

    @cached_property
    def _complete(self):
        """True when the groups write every row (a restricted system leaves some at zero)."""
        return sum(g.rows.size for g in self.groups) == self.m

    def _rows(self, N):
        return np.empty((self.m, N)) if self._complete else np.zeros((self.m, N))

    def evaluate(self, q, u=None, jacobian=True, groups=None):
        """Phi (N, m) and, if asked, Phi_q (N, m, n) at configurations q (N, n)."""
        N = q.shape[0]
        full = self.full(q)
        Phi = np.zeros((self.m, N))
        J = np.zeros((N, self.m, self.n + 1)) if jacobian else None
        for g in self.groups if groups is None else groups:
            F, P = g.frames(full), g.params(u)
            Phi[g.rows.T] = g.kind.Phi(P, F)
            if jacobian:
                J[:, g.rows.T[:, None, :], g.cols.T[None, :, :]] = np.moveaxis(g.kind.Phi_q(P, F), -1, 0)
        return Phi.T, (J[:, :, : self.n] if jacobian else None)

    @cached_property
    def entries(self):
        """(rows, cols) of every value :meth:`values` returns, group by group, each group's in
        the kernels' block order (row, column, joint) (cols = n for the ground: a dump column)."""
        rows, cols = [], []
        for g in self.groups:
            K, nr, nc = g.rows.shape[0], g.rows.shape[1], g.cols.shape[1]
            rows.append(np.broadcast_to(g.rows.T[:, None, :], (nr, nc, K)).ravel())
            cols.append(np.broadcast_to(g.cols.T[None, :, :], (nr, nc, K)).ravel())
        if not rows:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(rows), np.concatenate(cols)

    @cached_property
    def block_spans(self):
        """(start, end, shape) of each group's Jacobian block in the values: (n_rows, 3 nb, K)."""
        out, at = [], 0
        for g in self.groups:
            shape = (g.kind.n_rows, g.cols.shape[1], g.rows.shape[0])
            out.append((at, at + shape[0] * shape[1] * shape[2], shape))
            at = out[-1][1]
        return out

    def values(self, q, u=None, constants=True):
        """Phi (N, m) and the Jacobian as its non-zero pattern: (nnz + 1, N) values, entry first
        in the order of :attr:`entries` (so that the block solves read contiguous rows over the
        configurations), then a row of zeros (the slot of every structurally absent entry).
        The kernels write their blocks straight into it; with ``constants=False`` the entries
        each class has the same at every pose are left unset (see :mod:`planar.joints.base`)."""
        N = q.shape[0]
        Phi = self._rows(N)
        Jv = np.empty((self.entries[0].size + 1, N))
        Jv[-1] = 0.0
        blocks = [Jv[a:b].reshape(shape + (N,)) for a, b, shape in self.block_spans]
        for sl in chunks(N):
            full = self.full(q[sl])
            for g, block in zip(self.groups, blocks):
                Phi[g.rows.T, sl], _ = g.kind.Phi_and_Phi_q(g.params(u, sl), g.frames(full), block[..., sl],
                                                             constants)
        return Phi.T, Jv

    def restrict(self, rows):
        """The system of only the constraints that own one of ``rows`` (global ids kept)."""
        keep = np.zeros(self.m, bool)
        keep[rows] = True
        groups = []
        for g in self.groups:
            sel = keep[g.rows].any(axis=1)
            if sel.any():
                at = (slice(None), sel) if g.per_design else sel
                groups.append(Group(g.kind, g.members[sel], g.bodies[sel], {k: v[at] for k, v in g.P.items()},
                                    g.rows[sel], g.cols[sel], g.inputs[sel], g.per_design))
        return System(self.n_bodies, self.m, tuple(groups))

    def over_designs(self, systems):
        """This system with the parameters of ``systems`` (D of the same structure: each of
        its groups' members among theirs) stacked per design: the configurations (N, n) then
        take inputs u (N, f + 1) whose last column is the design index of each. One batch of
        configurations thus spans many designs, and one Newton loop serves them all.

        >>> from planar.mechanisms import four_bar
        >>> a, b = four_bar(crank=1.0).compile(), four_bar(crank=1.5).compile()
        >>> both = a.system.over_designs([a.system, b.system])
        >>> q = np.stack([a.q0, b.q0])
        >>> u = np.array([[a.u0[0], 0.0], [b.u0[0], 1.0]])
        >>> bool(np.abs(both.evaluate(q, u, jacobian=False)[0]).max() < 1e-12)
        True
        """
        groups = []
        for g in self.groups:
            tables = []
            for s in systems:
                h = next((h for h in s.groups if h.kind is g.kind and np.isin(g.members, h.members).all()), None)
                if h is None or h.P.keys() != g.P.keys():
                    raise ModelError(f"a design has no {g.kind.__name__} joints {g.members.tolist()} with the "
                                     f"parameters {sorted(g.P)}: designs swept together share one structure")
                at = np.searchsorted(h.members, g.members)
                tables.append({k: v[at] for k, v in h.P.items()})
            P = {k: np.stack([t[k] for t in tables]) for k in g.P}
            groups.append(Group(g.kind, g.members, g.bodies, P, g.rows, g.cols, g.inputs, True))
        return System(self.n_bodies, self.m, tuple(groups))

    def gamma(self, q, qd, u=None):
        """gamma (N, m) with Phi_q qdd = gamma, at configurations q and rates qd."""
        out = self._rows(q.shape[0])
        for sl in chunks(q.shape[0]):
            full = self.full(q[sl], qd[sl])
            for g in self.groups:
                out[g.rows.T, sl] = g.kind.gamma(g.params(u, sl), g.frames(full))
        return out.T


# configurations per pass: a group's temporaries stay in the core's cache (1 MB L2) instead
# of streaming through memory; one pass for the sequential walk's batches of one
_CHUNK = 4096


def chunks(N):
    return [slice(a, a + _CHUNK) for a in range(0, N, _CHUNK)] or [slice(0, 0)]


def build_system(constraints, params, body_index, n_bodies, driver_inputs):
    """Group ``constraints`` by class into a :class:`System`.

    ``params[i]`` are constraint i's parameters, ``body_index`` maps body names to ids and
    ``driver_inputs[i]`` is the input column of constraint i (-1 for a joint).
    """
    n = 3 * (n_bodies - 1)
    row_adr, m = [], 0
    for c in constraints:
        row_adr.append(m)
        m += c.n_rows
    by_kind = {}
    for i, c in enumerate(constraints):
        by_kind.setdefault(type(c), []).append(i)
    groups = []
    for kind, members in by_kind.items():
        bodies = np.array([[body_index[b] for b in constraints[i].bodies] for i in members], dtype=int)
        rows = np.array([[row_adr[i] + k for k in range(kind.n_rows)] for i in members], dtype=int)
        cols = np.where(bodies[:, :, None] > 0, 3 * (bodies[:, :, None] - 1) + np.arange(3), n)
        P = {key: np.stack([params[i][key] for i in members]) for key in params[members[0]]}
        inputs = np.array([driver_inputs[i] for i in members], dtype=int)
        groups.append(Group(kind, np.array(members), bodies, P, rows, cols.reshape(len(members), -1), inputs))
    return System(n_bodies, m, tuple(groups)), np.array(row_adr, dtype=int)
