"""What a study gives: :class:`DesignSweep`, the (D, N, ...) arrays of every design, and
:class:`Models`, each design's model compiled when asked for."""

from dataclasses import dataclass, field

import numpy as np

from planar.designs.tables import compile_unplanned
from planar.errors import InputError
from planar.geometry import perp, rotate
from planar.results import POSED, VALID, Sweep


def design_index(d, D):
    """Design ``d`` of ``D`` as an index from 0 (a negative one counts from the end)."""
    if isinstance(d, (bool, np.bool_)) or not isinstance(d, (int, np.integer)) or not -D <= d < D:
        raise InputError(f"a design is picked by its index, a whole number from 0 to {D - 1} (or from -{D}), "
                         f"got {d!r}")
    return int(d) % D


class Models:
    """Each design's :class:`planar.Model`, compiled when first asked for (the batch builds
    its tables without one); None for a design that could not be built."""

    def __init__(self, build, fixed, designs, errors, known):
        self.build, self.fixed, self.designs, self.errors, self.known = build, fixed, designs, errors, known

    def __len__(self):
        return len(self.designs)

    def __getitem__(self, d):
        d = design_index(d, len(self))
        if self.errors[d] is not None:
            return None
        if d not in self.known:
            self.known[d] = compile_unplanned(self.build(**self.fixed, **self.designs[d]))
        return self.known[d]

    def __iter__(self):
        return (self[d] for d in range(len(self)))


@dataclass(frozen=True, eq=False)
class DesignSweep:
    """Results of :func:`sweep_designs`, all arrays with a leading design axis: ``inputs``
    (D, N, f), ``q``, ``qd``, ``qdd`` (D, N, n), ``status``, ``residual``, ``iterations``,
    ``singularity``, ``branch``, ``gap`` (D, N), as :class:`planar.Sweep` holds them for one
    design; ``models`` (each design's :class:`planar.Model`, compiled when asked for; None
    where ``errors`` says why the design could not be built or assembled: NaN, status
    NOT_ASSEMBLABLE), ``batched`` (D,) True for the designs swept in the batch, ``events`` per
    design, ``points`` name -> (body, (D, 2) the point in the body's frame), ``template`` the
    first design's model. ``position(name)`` (D, N, 2), ``angle(body)`` (D, N), ... name the
    outputs; ``study[d]`` is design d's :class:`planar.Sweep`.
    """

    designs: tuple
    models: Models
    errors: tuple
    batched: np.ndarray
    events: tuple
    input_rates: np.ndarray
    input_accelerations: np.ndarray
    inputs: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    status: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray
    singularity: np.ndarray
    branch: np.ndarray
    gap: np.ndarray
    points: dict  # name -> (body name, (D, 2) the point in the body's frame, per design)
    template: object  # the first design's model: the bodies' names and coordinates
    _offsets: dict = field(default_factory=dict, init=False, repr=False)  # name -> _point's, once

    def __post_init__(self):
        for v in vars(self).values():
            if isinstance(v, np.ndarray):
                v.flags.writeable = False

    @property
    def N(self):
        return self.status.shape[1]

    def __len__(self):
        return len(self.designs)

    def __getitem__(self, d):
        """Design d's :class:`planar.Sweep` (None for a design that could not be built)."""
        d = design_index(d, len(self))
        if self.errors[d] is not None:
            return None
        return Sweep(self.models[d], self.inputs[d], self.input_rates, self.input_accelerations, self.q[d],
                     self.qd[d], self.qdd[d], self.status[d], self.residual[d], self.iterations[d],
                     self.singularity[d], self.branch[d], self.gap[d], self.events[d])

    @property
    def sweeps(self):
        return tuple(self[d] for d in range(len(self)))

    def __repr__(self):
        bad = sum(e is not None for e in self.errors)
        return f"DesignSweep(D={len(self)}, N={self.N}, batched={int(self.batched.sum())}, failed designs={bad})"

    @property
    def ok(self):
        """(D, N) True where positions, velocities and accelerations are valid."""
        return VALID[self.status]

    @property
    def posed(self):
        """(D, N) True where positions are valid."""
        return POSED[self.status]

    def _body(self, body, arr):
        """(x, y, phi) of ``body`` in ``arr`` (D, N, n)."""
        b = self.template.body_id(body)
        if b == 0:
            return (np.zeros(arr.shape[:2]),) * 3
        return arr[..., 3 * b - 3], arr[..., 3 * b - 2], arr[..., 3 * b - 1]

    def _point(self, name):
        """(body name, S): the point's world offset from its body's frame (D, N, 2)."""
        if not isinstance(name, str) or name not in self._offsets:
            if not isinstance(name, str) or name not in self.points:
                self.template.point(name)  # raises, naming the points there are
            body, s = self.points[name]
            S = rotate(self._body(body, self.q)[2], s[:, None, :])
            S.flags.writeable = False
            self._offsets[name] = body, S
        return self._offsets[name]

    def position(self, name):
        body, S = self._point(name)
        x, y, _ = self._body(body, self.q)
        return np.stack((x, y), axis=-1) + S

    def velocity(self, name):
        body, S = self._point(name)
        xd, yd, w = self._body(body, self.qd)
        return np.stack((xd, yd), axis=-1) + perp(S) * w[..., None]

    def acceleration(self, name):
        body, S = self._point(name)
        _, _, w = self._body(body, self.qd)
        xdd, ydd, a = self._body(body, self.qdd)
        return np.stack((xdd, ydd), axis=-1) + perp(S) * a[..., None] - S * (w**2)[..., None]

    def angle(self, body):
        return self._body(body, self.q)[2]

    def omega(self, body):
        return self._body(body, self.qd)[2]

    def alpha(self, body):
        return self._body(body, self.qdd)[2]

    def coordinate(self, joint, derivative=0):
        out = np.full((len(self), self.N), np.nan)
        for d in range(len(self)):
            if self.errors[d] is None:
                out[d] = self[d].coordinate(joint, derivative)
        return out
