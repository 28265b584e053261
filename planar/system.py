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

from planar.geometry import Frames


@dataclass(frozen=True, eq=False)
class Group:
    kind: type  # the joint class: supplies Phi, Phi_q, gamma
    members: np.ndarray  # (K,) constraint indices
    bodies: np.ndarray  # (K, nb) body ids (0 = ground)
    P: dict  # stacked parameters, (K, ...) arrays
    rows: np.ndarray  # (K, n_rows) global row ids
    cols: np.ndarray  # (K, 3 nb) global column ids, ground columns -> n (dumped)
    inputs: np.ndarray  # (K,) input column of each driver, -1 for joints


@dataclass(frozen=True, eq=False)
class System:
    n_bodies: int  # including the ground
    m: int  # rows
    groups: tuple

    @property
    def n(self):
        return 3 * (self.n_bodies - 1)

    def _full(self, q):
        N = q.shape[0]
        full = np.zeros((N, self.n_bodies, 3))
        full[:, 1:, :] = q.reshape(N, self.n_bodies - 1, 3)
        return full

    def _frames(self, full, cs, g, fulld=None):
        B = g.bodies
        F = Frames(full[:, B, :2], full[:, B, 2], cs[0][:, B], cs[1][:, B])
        if fulld is not None:
            F.rd, F.phid = fulld[:, B, :2], fulld[:, B, 2]
        return F

    @staticmethod
    def _params(g, u):
        if g.inputs[0] < 0 or u is None:
            return g.P
        # a driver row is g(q) - u: the input values stand in the constant c
        return dict(g.P, c=u[:, g.inputs][..., None])

    def evaluate(self, q, u=None, jacobian=True, groups=None):
        """Phi (N, m) and, if asked, Phi_q (N, m, n) at configurations q (N, n)."""
        N = q.shape[0]
        full = self._full(q)
        cs = (np.cos(full[..., 2]), np.sin(full[..., 2]))
        Phi = np.zeros((N, self.m))
        J = np.zeros((N, self.m, self.n + 1)) if jacobian else None
        for g in self.groups if groups is None else groups:
            F = self._frames(full, cs, g)
            P = self._params(g, u)
            Phi[:, g.rows] = g.kind.Phi(P, F)
            if jacobian:
                J[:, g.rows[:, :, None], g.cols[:, None, :]] = g.kind.Phi_q(P, F)
        return Phi, (J[:, :, : self.n] if jacobian else None)

    @cached_property
    def entries(self):
        """(rows, cols) of every value :meth:`values` returns, group by group (cols = n for the
        ground: a dump column)."""
        rows, cols = [], []
        for g in self.groups:
            K, nr, nc = g.rows.shape[0], g.rows.shape[1], g.cols.shape[1]
            rows.append(np.broadcast_to(g.rows[:, :, None], (K, nr, nc)).ravel())
            cols.append(np.broadcast_to(g.cols[:, None, :], (K, nr, nc)).ravel())
        if not rows:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(rows), np.concatenate(cols)

    def values(self, q, u=None):
        """Phi (N, m) and the Jacobian as its non-zero pattern: (nnz + 1, N) values, entry first
        in the order of :attr:`entries` (so that the block solves read contiguous rows over the
        configurations), then a row of zeros (the slot of every structurally absent entry)."""
        N = q.shape[0]
        full = self._full(q)
        cs = (np.cos(full[..., 2]), np.sin(full[..., 2]))
        Phi = np.zeros((N, self.m))
        Jv = np.empty((self.entries[0].size + 1, N))
        Jv[-1] = 0.0
        at = 0
        for g in self.groups:
            F = self._frames(full, cs, g)
            P = self._params(g, u)
            Phi[:, g.rows], block = g.kind.Phi_and_Phi_q(P, F)
            size = block[0].size
            Jv[at : at + size] = block.reshape(N, size).T
            at += size
        return Phi, Jv

    def restrict(self, rows):
        """The system of only the constraints that own one of ``rows`` (global ids kept)."""
        keep = np.zeros(self.m, bool)
        keep[rows] = True
        groups = []
        for g in self.groups:
            sel = keep[g.rows].any(axis=1)
            if sel.any():
                groups.append(Group(g.kind, g.members[sel], g.bodies[sel], {k: v[sel] for k, v in g.P.items()},
                                    g.rows[sel], g.cols[sel], g.inputs[sel]))
        return System(self.n_bodies, self.m, tuple(groups))

    def gamma(self, q, qd, u=None):
        """gamma (N, m) with Phi_q qdd = gamma, at configurations q and rates qd."""
        full, fulld = self._full(q), self._full(qd)
        cs = (np.cos(full[..., 2]), np.sin(full[..., 2]))
        out = np.zeros((q.shape[0], self.m))
        for g in self.groups:
            F = self._frames(full, cs, g, fulld)
            out[:, g.rows] = g.kind.gamma(self._params(g, u), F)
        return out


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
