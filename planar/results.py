"""Frozen sweep results with named access, and the per-point :class:`Status`."""

from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING

import numpy as np

from planar.errors import InputError, ModelError
from planar.geometry import perp, rotate

if TYPE_CHECKING:
    from planar.kinetostatics import Forces
    from planar.model import Body, Model


class Status(IntEnum):
    """What happened at one input value (printed by its name: ``print(Status.SOLVED)`` shows
    SOLVED; compared and stored as its integer code).

    SOLVED, NEAR_SINGULAR, BRANCH_EVENT and JUMPED points carry valid positions, velocities
    and accelerations. A SINGULAR point has valid positions; its rates are NaN (the Jacobian is
    singular there). The others are NaN in every output.
    """

    SOLVED = 0
    NEAR_SINGULAR = 1  # valid, but the Jacobian is close to singular: expect larger errors
    BRANCH_EVENT = 2  # valid, at a point where branches meet
    SINGULAR = 3  # positions valid, rates undefined
    NOT_ASSEMBLABLE = 4  # the input is outside the motion range: see the assembly gap
    NOT_CONVERGED = 5  # assemblable, but not reached on the tracked branch
    INCONSISTENT = 6  # a redundant joint does not hold at the solved pose
    LIMIT = 7  # positions valid at a limit position (the input cannot go further), rates NaN
    # valid, but not continuously reachable from the value before it: the branch was re-entered
    # past limit positions that lie between the two (plots break their lines there)
    JUMPED = 8

    def __str__(self) -> str:
        return self.name

    def __format__(self, spec: str) -> str:
        # a numeric format (f"{s:d}", f"{s:3d}") gives the code, any other the name
        return format(int(self), spec) if spec[-1:] in ("d", "x", "o", "b", "n") else format(self.name, spec)

    @property
    def valid(self) -> bool:
        return self <= Status.BRANCH_EVENT or self == Status.JUMPED

    @property
    def posed(self) -> bool:
        """Positions valid (rates may not be)."""
        return self <= Status.SINGULAR or self in (Status.LIMIT, Status.JUMPED)


VALID = np.array([s.valid for s in Status])
POSED = np.array([s.posed for s in Status])


def is_derivative(order):
    """Whether ``order`` is 0, 1 or 2: a whole number (an array compared with ``in`` is
    ambiguous, a bool equals 0 or 1, and a float counts no derivatives)."""
    return isinstance(order, (int, np.integer)) and not isinstance(order, bool) and order in (0, 1, 2)


def as_sweep(res, who):
    """``res`` where it is a :class:`Sweep`, else an InputError saying ``who`` needs one."""
    if not isinstance(res, Sweep):
        raise InputError(f"{who} needs a sweep result (the Sweep of Model.sweep or Mechanism.sweep), got "
                         f"{type(res).__name__}: sweep the mechanism first")
    return res


@dataclass(frozen=True, eq=False)
class Sweep:
    """Results of :meth:`planar.Model.sweep`: one row per input value, all arrays read-only.

    ``status`` (N,) holds :class:`Status` codes, ``residual`` the scaled constraint residual,
    ``iterations`` the Newton iterations, ``singularity`` the normalised |det| of the scaled
    Jacobian (0 at a singular position), ``branch`` its sign (the assembly mode), ``gap`` the
    scaled assembly gap of points that did not assemble (NaN elsewhere). ``events`` lists the
    singular positions met, in sweep order (:class:`planar.events.Event`: limit positions,
    bifurcations, near-singular stretches).
    """

    model: "Model"
    inputs: np.ndarray  # (N, f)
    input_rates: np.ndarray
    input_accelerations: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    status: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray
    singularity: np.ndarray
    branch: np.ndarray
    gap: np.ndarray
    events: tuple = ()

    def __init__(self, model, inputs, input_rates, input_accelerations, q, qd, qdd, status, residual, iterations,
                 singularity, branch, gap, events=()):
        # (the fields set at once: the frozen dataclass's own __init__ sets each through
        # object.__setattr__, a sixth of a tracker's move)
        self.__dict__.update(model=model, inputs=inputs, input_rates=input_rates,
                             input_accelerations=input_accelerations, q=q, qd=qd, qdd=qdd, status=status,
                             residual=residual, iterations=iterations, singularity=singularity, branch=branch, gap=gap,
                             events=events)
        for v in (inputs, input_rates, input_accelerations, q, qd, qdd, status, residual, iterations, singularity,
                  branch, gap):
            if isinstance(v, np.ndarray) and v.flags.writeable:
                v.setflags(write=False)

    def __len__(self) -> int:
        return self.status.shape[0]

    def __repr__(self) -> str:
        counts = {Status(s).name: int(c) for s, c in zip(*np.unique(self.status, return_counts=True))}
        return f"Sweep({self.model.name!r}, N={len(self)}, inputs={list(self.model.input_names)}, {counts})"

    @property
    def ok(self) -> np.ndarray:
        """(N,) True where positions, velocities and accelerations are all valid (positions
        only for a sweep asked for no rates)."""
        return VALID[self.status]

    @property
    def nearest_limit(self) -> np.ndarray:
        """(N,) input value of the nearest limit position found, for points that did not
        assemble (NaN elsewhere, and where no limit was met). One input only."""
        out = np.full(len(self), np.nan)
        lims = np.array([e.input for e in self.events if e.kind == "limit"], float).ravel()
        miss = self.status == Status.NOT_ASSEMBLABLE
        if lims.size and miss.any() and self.inputs.shape[1] == 1:
            u = self.inputs[miss, 0]
            out[miss] = lims[np.argmin(np.abs(u[:, None] - lims[None, :]), axis=1)]
        return out

    # ---- bodies and points -----------------------------------------------------------------

    def _body(self, body, arr):
        b = self.model.body_id(body)
        if b == 0:
            return np.zeros(len(self)), np.zeros(len(self)), np.zeros(len(self))
        return arr[:, 3 * b - 3], arr[:, 3 * b - 2], arr[:, 3 * b - 1]

    def angle(self, body: "Body | str") -> np.ndarray:
        """Absolute angle of ``body`` (radians, unwrapped: its sketch angle plus its rotation)."""
        return self._body(body, self.q)[2]

    def omega(self, body: "Body | str") -> np.ndarray:
        """Angular velocity of ``body``."""
        return self._body(body, self.qd)[2]

    def alpha(self, body: "Body | str") -> np.ndarray:
        """Angular acceleration of ``body``."""
        return self._body(body, self.qdd)[2]

    def _point(self, name):
        b, s = self.model.point(name)
        x, y, phi = self._body(self.model.body_names[b], self.q)
        return b, rotate(phi, np.asarray(s, float))

    def position(self, name: str) -> np.ndarray:
        """(N, 2) world position of a named point or joint."""
        b, S = self._point(name)
        x, y, _ = self._body(self.model.body_names[b], self.q)
        return np.stack((x, y), axis=-1) + S

    def velocity(self, name: str) -> np.ndarray:
        """(N, 2) velocity of a named point or joint."""
        b, S = self._point(name)
        xd, yd, w = self._body(self.model.body_names[b], self.qd)
        return np.stack((xd, yd), axis=-1) + perp(S) * w[:, None]

    def acceleration(self, name: str) -> np.ndarray:
        """(N, 2) acceleration of a named point or joint."""
        b, S = self._point(name)
        _, _, w = self._body(self.model.body_names[b], self.qd)
        xdd, ydd, a = self._body(self.model.body_names[b], self.qdd)
        return np.stack((xdd, ydd), axis=-1) + perp(S) * a[:, None] - S * (w**2)[:, None]

    def forces(self) -> "Forces":
        """Driving efforts and joint reactions at every value, from the model's masses, gravity
        and loads (:mod:`planar.kinetostatics`): one linear solve per value, so keep the result."""
        from planar.kinetostatics import forces

        return forces(self)

    def coordinate(self, joint: str, derivative: int = 0) -> np.ndarray:
        """(N,) a joint's own coordinate (a revolute's relative angle, a slider's or slot's
        travel from its origin), or its first or second time derivative."""
        coords = self.model.coordinates
        if not isinstance(joint, str) or joint not in coords:
            raise ModelError(f"joint {joint!r} has no coordinate: the joints with one are {sorted(coords)}")
        if not is_derivative(derivative):
            raise ModelError(f"derivative must be 0, 1 or 2, got {derivative!r}")
        sys_, row = coords[joint]
        # NaN where a coordinate the row reads is NaN (a value not solved, or a body the
        # sweep's outputs left out), and only there: the row's Jacobian is 0 off what it reads
        with np.errstate(invalid="ignore"):
            Phi, J = sys_.evaluate(self.q, jacobian=derivative > 0)
            if derivative == 0:
                return Phi[:, row]
            Jr = J[:, row]
            rate = self.qd if derivative == 1 else self.qdd
            out = np.sum(np.where(Jr != 0, Jr * rate, 0.0), axis=1)
            return out if derivative == 1 else out - sys_.gamma(self.q, self.qd)[:, row]
