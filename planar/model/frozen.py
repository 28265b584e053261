"""What the builder hands on, frozen: the :class:`Body` handle, the :class:`Sketch` (a mechanism
as drawn or as assembled) and the compiled :class:`Model` (index arrays, joint tables, the
mobility report). The model calls the algorithms (sweep, tracking, circuit) from its methods,
importing them there: the model sits below them."""

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from planar.errors import InputError, MobilityError, ModelError
from planar.model.checks import floats, not_real

if TYPE_CHECKING:
    from planar.results import Sweep
    from planar.tracking import Tracker

GROUND = "ground"


@dataclass(frozen=True)
class Body:
    """Handle of a body in a :class:`Mechanism` (anywhere a body is asked for, its name works too)."""

    name: str

    def __str__(self):
        return self.name



@dataclass(frozen=True)
class Sketch:
    """A mechanism as drawn or as assembled: ``bodies`` name -> angle (the ground first; as
    given when drawn, in radians when assembled), ``points`` name -> (body, world point)
    (joints' points included), ``joints`` and ``drivers`` in the order they were added, the
    stated ``dimensions`` and the drivers' ``starts`` (name -> value); ``mass`` body -> (mass,
    sketch centre of mass, inertia), ``loads`` (body, sketch point, force, torque, fixed) and
    ``gravity`` as given to the builder (centres and load points carried with their bodies when
    assembled), and ``sides`` (name, a, b, side) of each joint or point placed by a Dyad."""

    bodies: dict
    points: dict
    joints: tuple
    drivers: tuple
    dimensions: tuple = ()
    starts: dict | None = None
    mass: dict | None = None
    loads: tuple = ()
    gravity: tuple | None = None
    sides: tuple = ()

    def position(self, name):
        """World position (2,) of a joint or point."""
        if not isinstance(name, str) or name not in self.points:
            raise ModelError(f"unknown joint or point {name!r}: known are {sorted(self.points)}")
        return self.points[name][1]


# ---- the compiled model ---------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Model:
    """Immutable compiled mechanism: index arrays, joint tables and the assembled sketch.

    Attributes give the mobility report: ``n`` coordinates, ``m`` rows, ``rank`` of the joint
    Jacobian at the sketch, ``dof = n - rank``, ``grubler = n - (rows of the joints)`` and the
    names of ``redundant_joints`` (rows kept out of Newton but checked after every solve).
    ``sketch`` is the :class:`Sketch` as assembled: every stated distance holds there, and
    ``sketch.bodies`` are the bodies' angles in radians. ``mass``, ``com``, ``inertia``,
    ``gravity`` and ``loads`` are what :meth:`planar.Sweep.forces` balances (read-only).
    """

    name: str
    body_names: tuple
    body_angles0: np.ndarray  # sketch angle per body
    points: dict  # name -> (body id, local vector)
    joints: tuple
    drivers: tuple
    system: object
    row_adr: np.ndarray
    q0: np.ndarray  # assembled sketch (n,)
    u0: np.ndarray  # input values at the sketch (f,)
    L: float  # characteristic length
    row_scale: np.ndarray  # (m,)
    col_scale: np.ndarray  # (n,)
    active_rows: np.ndarray  # rows of the Newton system (independent joint rows, then drivers)
    driver_rows_active: np.ndarray  # positions of the driver rows inside active_rows
    redundant_rows: np.ndarray
    input_lengths: np.ndarray  # (f,) True where the input is a length
    rank: int
    grubler: int
    redundant_joints: tuple
    coordinates: dict  # joint name -> (system of its coordinate rows, row)
    sketch: Sketch
    mass: np.ndarray | None = None  # (n_bodies,) masses (0: massless)
    com: np.ndarray | None = None  # (n_bodies, 2) centres of mass in the body frames
    inertia: np.ndarray | None = None  # (n_bodies,) moments of inertia about the centres of mass
    gravity: np.ndarray | None = None  # (2,) world gravitational acceleration
    loads: tuple = ()  # planar.mass.Load
    # poses solved on the branch, per branch option: planar.tracking's mutable cache, made with
    # the model; the model's other fields stay as built
    known_poses: dict = field(default_factory=dict, init=False, repr=False)

    def __repr__(self) -> str:
        return (f"<Model {self.name!r}: {len(self.body_names) - 1} moving bodies, {len(self.joints)} joints, "
                f"dof {self.dof}, inputs {list(self.input_names)}>")

    @property
    def n(self):
        return self.system.n

    @property
    def m(self):
        return self.system.m

    @property
    def dof(self) -> int:
        return self.n - self.rank

    @cached_property
    def Phi_q_norm(self):
        """The largest sum of a row's scaled Jacobian entries (|Phi_q| scaled by ``row_scale``
        and ``col_scale``) at the sketch, twice over (a lever's components change as its body
        turns): what a rounding of the coordinates moves a row by, at most, per unit of
        their scaled size (:func:`planar.solver.rounding`)."""
        with np.errstate(all="ignore"):
            _, J = self.system.evaluate(self.q0[None], self.u0[None])
        Js = np.abs(J[0][self.active_rows]) * self.row_scale[self.active_rows, None] * self.col_scale
        return 2.0 * float(np.max(np.sum(Js, axis=1), initial=1.0))

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(d.name for d in self.drivers)

    def body_id(self, body: Body | str) -> int:
        name = body.name if isinstance(body, Body) else body
        try:
            return self.body_names.index(name)
        except ValueError:
            raise ModelError(f"unknown body {name!r}: the bodies are {list(self.body_names)}") from None

    def point(self, name):
        try:
            return self.points[name]
        except (KeyError, TypeError):
            raise ModelError(f"unknown point or joint {name!r}: known are {sorted(self.points)}") from None

    def joint(self, name):
        for j in self.joints:
            if isinstance(name, str) and j.name == name:  # (an array would compare element by element)
                return j
        raise ModelError(f"unknown joint {name!r}: the joints are {[j.name for j in self.joints]}")

    def require_driver(self):
        """Raise the :class:`planar.errors.MobilityError` that says what to do if the model has no
        driver, as a sweep would (for callers that check before they sweep)."""
        if self.drivers:
            return
        if self.dof == 0:
            raise MobilityError(f"mechanism {self.name!r} has no driver and nothing to drive (no degree of "
                                f"freedom): add moving bodies")
        raise MobilityError(f"mechanism {self.name!r} has no driver: add {self.dof} with drive()")

    def sweep(self, values: ArrayLike, velocity: ArrayLike = 1.0, acceleration: ArrayLike = 0.0,
              **options: Any) -> "Sweep":
        """Positions, velocities and accelerations for each row of input ``values``.

        ``values`` is (N,) for one input or (N, f); ``velocity`` and ``acceleration`` are the
        input rates (scalars, (f,), (N,) or (N, f)); the default unit velocity makes the rates
        kinematic coefficients. The solve follows the branch drawn in the sketch through the
        values in order; a one-input model starts it from the nearest pose it has solved on
        the branch before, with the same results as from the sketch (:mod:`planar.tracking`).
        Returns a frozen :class:`planar.results.Sweep`.
        Options: ``tol`` (scaled residual, 1e-12; a pose whose angles are counted to 1e5 rad
        holds its rows to their rounding: see :func:`planar.solver.rounding`), ``max_step``
        (largest input step between continuation anchors: radians, or lengths / L; 0.05),
        ``outputs`` (names of the bodies, points or joints wanted: only the blocks they need
        are solved), ``branch``
        ("smooth" or "other" at a bifurcation), ``rates`` (False: positions only, velocities
        and accelerations NaN: the velocity and acceleration solves are skipped), ``engine``
        ("numpy", or "numba": the per-value work in one loop of machine code; needs the ``fast``
        extra; the first sweep of an installation compiles it, about half a minute, then every
        mechanism loads it from disk; see :mod:`planar.compiled`).
        """
        from planar import arguments, tracking
        from planar.sweep import run_sweep

        self.require_driver()
        options = arguments.sweep_options(options, run_sweep)
        U = self.as_inputs(values, "values")
        arguments.values(self, U, options["max_step"])
        N = U.shape[0]
        Ud, Udd = self.as_inputs(velocity, "velocity", N), self.as_inputs(acceleration, "acceleration", N)
        arguments.rates(self, Ud, Udd)
        return tracking.sweep(self, U, Ud, Udd, **options)

    def track(self, **options: Any) -> "Tracker":
        """A :class:`planar.tracking.Tracker` for moving the input by hand: ``tracker.move(value)``
        returns the pose at ``value`` as a one-value :class:`planar.results.Sweep`, going on from
        the last pose; ``tracker.pose`` is the last. ``options`` are the sweep's.

        >>> from planar.mechanisms import four_bar
        >>> tracker = four_bar().track(branch="smooth")
        >>> [bool(tracker.move(u).ok[0]) for u in (0.5, 0.6, 0.7)], bool(tracker.pose.ok[0])
        ([True, True, True], True)
        """
        from planar.tracking import Tracker

        self.require_driver()
        return Tracker(self, **options)

    def circuit(self, samples: int = 361, velocity: float = 1.0, acceleration: float = 0.0, tol: float = 1e-12,
                max_step: float = 0.05, **options: Any) -> "Sweep":
        """The whole circuit through the assembled sketch of a one-input model, in one sweep.

        The input starts at the sketch and rises; where it cannot go further (a limit
        position) it turns back, and the mechanism goes on in the other assembly mode, until
        it is back at the sketch's pose: for an input that turns fully, one turn (or the
        whole turns it takes to come back); for a triple rocker, up to one limit, down to the
        other and back up. ``samples`` values in all, evenly spaced along the circuit (so the
        coupler curve is as fine at a limit as elsewhere); both ends and the limits are among
        them (status LIMIT: positions valid, rates NaN). ``velocity`` and ``acceleration`` (scalars) are the
        input's rate and acceleration along its motion: their sign follows the input's
        direction on each stretch. ``events`` lists the limits (kind "limit", with the index
        of their value) and any bifurcation met (the circuit keeps to the smooth branch).
        Returns a frozen :class:`planar.results.Sweep`; see :mod:`planar.circuit`.

        >>> import numpy as np
        >>> from planar.mechanisms import four_bar
        >>> res = four_bar(4, 3, 3, 3).circuit(samples=101)   # a triple rocker: +-117.28 deg
        >>> np.degrees([e.input for e in res.events]).round(6).tolist()
        [117.279613, -117.279613]
        """
        from planar import arguments
        from planar.circuit import circuit

        if options:  # (the sweep's other options mean nothing to a circuit: named, not a bare TypeError)
            raise InputError(f"unknown circuit option {sorted(options)[0]!r}: the options are tol, max_step")
        arguments.size(self, samples, "the circuit", arguments.CIRCUIT_BYTES_PER_COORDINATE)
        return circuit(self, samples, velocity, acceleration, tol=arguments.tolerance(tol),
                       max_step=arguments.max_step(max_step))

    def as_inputs(self, values, what, N=None):
        """``values`` as a new C-contiguous (N, f) array (the sweep keeps it: a copy, so the
        caller's array can change later; one memory layout, so the compiled loop is compiled
        for one), or, for a rate given once for every value (a number, or one per input), that
        one row broadcast to N rows: read-only and no N-sized copy (the compiled loop reads
        the row itself)."""
        f = len(self.drivers)
        read, dtype = values, getattr(values, "dtype", None)
        if dtype is None:  # (a list: strings, bools and None in it are no numbers, though numpy reads them as ones)
            try:
                read = np.asarray(values)  # (converted once: the numbers below are read from it)
                dtype = read.dtype
            except (TypeError, ValueError, OverflowError):  # (ragged: the conversion below names it)
                dtype = np.dtype(float)
            if dtype.kind == "O" and any(v is None for v in read.ravel()):
                raise InputError(f"sweep {what} must be numbers, got None among them")
        got = not_real(values, dtype)
        if got is not None:
            raise InputError(f"sweep {what} must be real numbers, got {got}")
        if N is None and getattr(read, "ndim", 1) >= 1 and hasattr(read, "__len__"):
            from planar import arguments

            arguments.size(self, len(read))  # (before the copy as floats: 1e9 values of int8 are 8 GB of them)
        try:
            a = floats(read)  # (inf where beyond float64: refused below)
        except (TypeError, ValueError):
            raise InputError(f"sweep {what} must be numbers, got {type(values).__name__}") from None
        except OverflowError:  # (an integer beyond any float)
            raise InputError(f"sweep {what} must be finite; found an integer beyond any float") from None
        if a.ndim == 0:
            if N is None:
                raise InputError(f"sweep {what} must be a sequence of input values, got a scalar")
            a = np.broadcast_to(np.full((1, f), float(a)), (N, f))
        elif a.ndim == 1 and f == 1 and (N is None or a.shape[0] == N):
            a = a[:, None]
        elif a.ndim == 1 and a.shape[0] == f and N is not None:
            a = np.broadcast_to(a[None], (N, f))
        if a.ndim != 2 or a.shape[1] != f or (N is not None and a.shape[0] != N):
            want = f"({N}, {f})" if N is not None else f"(N,) or (N, {f})"
            raise InputError(f"sweep {what} have shape {np.shape(values)} but {f} input(s) "
                             f"{list(self.input_names)} need {want}")
        if not np.all(np.isfinite(a)):
            raise InputError(f"sweep {what} must be finite; found NaN or infinity")
        return a

