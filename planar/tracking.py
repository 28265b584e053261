"""Poses on demand: sweeps that start from the nearest pose a model knows on its branch, and
the :class:`Tracker` that follows an input moved by hand.

A one-input model remembers, per branch option and tolerance, poses its sweeps solved on the
branch drawn in the sketch (:class:`Poses`, at most ``CAP``). A pose is remembered only when
the continuation reached it from the sketch with no limit, bifurcation, singular position or
close approach to one (a walk step may pass over a limit pair narrower than the step there,
and a walk with other steps meet it), no jump or move by whole periods of a rocking input, and
no invalid value on the way, so the remembered poses span one interval of the unwrapped input,
around the sketch's, on which the branch is a smooth function of the input (for a crank that
turns fully, u and u + 2 pi are different inputs, and for a geared train different poses). A
sweep walks from the remembered pose nearest its first value: inside that interval the pose at
any input is the branch's, whichever way it is reached; outside, the walk from the interval's
end nearest the value is the tail of the walk from the sketch. Where that walk meets a limit or
a branch event (past which the way on depends on the whole walk: where the range is re-entered,
which branch is taken) the sweep is done again from the sketch. So the results, statuses and
events are those of the sweep from the sketch, at the cost of the distance from the nearest
known pose on the branch. Values each within the sweep's direct reach of a known pose (a move
of a dragged input; a sweep over a stretch the model has swept) are solved in one batch, each
as one walk step from the known pose nearest it (:func:`direct`, the direct path: none of the
sweep's machinery), with the sweep's acceptance test; what it cannot certify goes to the sweep.
A value past a limit the walk from the sketch meets, inside a stretch where a sweep from the
sketch found nothing that assembles (:meth:`Poses.learn_bare`; not on a geared linkage), gets
that sweep's result with its own gap (past a second limit, equal to rounding: the walk there
locates it from an entry searched at inputs that depend on the value asked). Models with more
inputs sweep from the sketch.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> m = four_bar()
>>> tracker = m.track()
>>> res = tracker.move(np.pi)          # walks from the sketch
>>> res = tracker.move(np.pi + 0.01)   # one step from the pose before
>>> res.ok.tolist(), bool(np.allclose(res.q, m.sweep([np.pi + 0.01]).q, atol=1e-12))
([True], True)
"""

import math
from dataclasses import replace

import numpy as np

from planar import arguments
from planar.errors import InputError
from planar.events import NEAR_CURVE
from planar.model.checks import not_real
from planar.results import Status, Sweep

CAP = 256  # poses kept per branch option: a turn of the crank at the default max_step is ~126
KEYS = 4  # branch options and tolerances remembered per model (the oldest is forgotten)
CLEAN = (Status.SOLVED, Status.NEAR_SINGULAR)  # values reached on the branch, no event at them
# events past which the branch is not a function of the input, or not one every walk follows
BREAKS = ("limit", "bifurcation", "singular", "near_singular")
NEWTON = 8  # Newton steps of the direct path (the sweep's walk step allows as many)
SLOWEST = np.sqrt(np.finfo(float).tiny)  # input rates below this teach no kinematic coefficients
DIRECT = 4096  # values the direct path takes in one batch: more are the sweep's (its bulk is made for them)
NUMBER = (int, float, np.float64)  # a move's value and rates as numbers (the others, and bools, go by the sweep's checks)


def _read_only(a):
    a.setflags(write=False)
    return a


# a move's unit input rate and no acceleration, and a posed value's assembly gap: read-only
# arrays the moves' results share
UNIT = _read_only(np.ones((1, 1))), _read_only(np.zeros((1, 1)))
NO_GAP = _read_only(np.full(1, np.nan))


class Poses:
    """Poses of one model known on one branch: inputs ``u`` (K,), poses ``q`` (K, n) and their
    kinematic coefficients ``qu``, ``quu`` (K, n), dq/du and d2q/du2 (NaN where not computed
    yet); the sketch's among them, always. A sweep's poses are merged in (sorted, at most CAP
    kept); the poses of moves are appended after them, up to CAP before the next merge.
    ``rows`` (K, 3, n): each pose's q, qu, quu together (as the compiled engine reads them).
    ``signs``: the blocks' modes on the branch (the sketch's), once the direct path has
    asked; ``refused``: the value it could not certify last, while no pose has been learned
    since (the sweep it goes to asks again); ``complete``: whether every known pose has its
    coefficients; ``broken``: whether a sweep learned from met a limit or an event that breaks
    the branch."""

    def __init__(self, model):
        from planar.sweep import input_scale

        self.u0 = self.newest = float(model.u0[0])
        nan = np.full_like(model.q0[None], np.nan)
        self._keep(np.array([self.u0]), np.stack((model.q0[None], nan, nan), axis=1))
        self.signs, self.broken = None, False
        self.bare = {}  # (limit input, max_step, upwards) -> (lo, hi, sweep): see learn_bare
        self.scale = float(input_scale(model)[0])  # (limits within 1e-8 of the input's scale are one)

    def _keep(self, u, rows):
        """Hold the known poses u (K,) and their rows (K, 3, n), with room for CAP more after them."""
        K = u.size
        self.size, self.refused = K, None
        self._u = np.empty(K + CAP)
        self._u[:K] = u
        self._rows = np.empty((K + CAP,) + rows.shape[1:])
        self._rows[:K] = rows
        self.complete = bool(np.isfinite(rows[:, 1:, 0]).all())

    @property
    def u(self):
        return self._u[: self.size]

    @property
    def rows(self):
        return self._rows[: self.size]

    @property
    def q(self):
        return self._rows[: self.size, 0]

    @property
    def qu(self):
        return self._rows[: self.size, 1]

    @property
    def quu(self):
        return self._rows[: self.size, 2]

    def nearest(self, u):
        """(K,) the index of the known pose nearest each input value u (K,)."""
        order = np.argsort(self.u, kind="stable")
        known = self.u[order]
        j = np.clip(np.searchsorted(known, u), 1, max(known.size - 1, 1))
        left = np.abs(u - known[j - 1]) <= np.abs(known[np.minimum(j, known.size - 1)] - u)
        return order[np.where(left, j - 1, np.minimum(j, known.size - 1))]

    def learn(self, res, reached):
        """Remember the poses of a sweep (one started from a known pose) up to its first
        event that breaks the branch or its first value not reached on it, of those its walk
        ``reached`` (N,) by continuation from its start (no jump, no move by whole periods of a
        rocking input: values solved out of order may be asked before those)."""
        self.broken = self.broken or not _clean(res)
        end = _clean_end(res)
        take = np.flatnonzero(reached[:end])
        if take.size == 0:
            return
        take = take[np.unique(np.linspace(0, take.size - 1, min(take.size, CAP // 2)).astype(int))]
        # the kinematic coefficients from the rates: qd = v q_u, qdd = v^2 q_uu + a q_u
        v, a = res.input_rates[take], res.input_accelerations[take]
        # (NaN where the rates are not known, or the input rate too small for v^2 to be a normal
        # number: computed when needed)
        with np.errstate(all="ignore"):
            qu = np.where(np.abs(v) >= SLOWEST, res.qd[take] / v, np.nan)
            quu = (res.qdd[take] - a * qu) / v**2
        known = np.isfinite(qu).all(axis=1) & np.isfinite(quu).all(axis=1)  # (rates of 1e200 overflow)
        qu[~known] = quu[~known] = np.nan
        self.merge(res.inputs[take, 0], (res.q[take], qu, quu))

    def merge(self, u, rows):
        """Remember poses at inputs u (M,) with their rows (q, qu, quu), each (M, n), sorted
        with the known ones (at an input known already the known pose stays: the sketch's, at
        the sketch's input)."""
        uu, first = np.unique(np.r_[self.u, u], return_index=True)
        rows = np.concatenate((self.rows, np.stack(rows, axis=1)))[first]
        if uu.size > CAP:
            # the sketch, the newest (where the next move starts) and evenly spaced others
            keep = np.zeros(uu.size, bool)
            keep[np.unique(np.linspace(0, uu.size - 1, CAP // 2).astype(int))] = True
            keep[np.searchsorted(uu, np.r_[u, self.newest, self.u0])] = True
            uu, rows = uu[keep], rows[keep]
        self._keep(uu, rows)

    def append(self, u, row):
        """Remember the pose of a move to input u: its row (3, n), q and its coefficients."""
        if self.size == self._u.size:
            self.merge(np.zeros(0), np.zeros((3, 0, row.shape[1])))
        self._u[self.size] = self.newest = u
        self._rows[self.size] = row
        self.size += 1
        self.refused = None

    def learn_bare(self, res, bare, max_step):
        """Remember, from the sweep ``res`` of one value from the sketch, out of reach past the
        last of the limits its walk met (its events, all limits), the stretch from that limit
        where its search found nothing that assembles, in any modes (``bare``, as
        :func:`planar.sweep.run_sweep` gives it): the sweep of any value in that stretch walks
        the same way to the same limit (located to rounding: past a gap before it, the entry
        into the next interval is searched at inputs spread out to the value asked) and
        searches the part of it up to the value, at the walk's steps from the limit as this one
        did. A limit known already (the same to 1e-8, scaled) keeps its widest stretch."""
        if res.status[0] != Status.NOT_ASSEMBLABLE or not res.events or any(e.kind != "limit" for e in res.events):
            return
        L = float(np.ravel(res.events[-1].input)[0])
        for ev, (lo, hi) in bare:
            if float(np.ravel(ev.input)[0]) != L or not lo <= res.inputs[0, 0] <= hi:
                continue
            key = next((k for k in self.bare if k[1:] == (max_step, lo == L) and abs(k[0] - L) * self.scale <= 1e-8),
                       (L, max_step, lo == L))  # (one stretch each way from each limit: the widest)
            known = self.bare.get(key)
            if known is None or hi - lo > known[1] - known[0]:
                self.bare.pop(key, None)
                self.bare[(L, max_step, lo == L)] = (lo, hi, res)

    def past_limit(self, model, U, Ud, Udd, max_step):
        """The sweep of one value U (1, 1) in a stretch past a limit where nothing assembles
        (:meth:`learn_bare`), or None: the sweep that found it with this value, its rates and
        its gap (least squares from the limit's pose), as the sweep from the sketch gives it (to
        rounding past a limit after the first)."""
        from planar.solver import least_squares_gap

        res = self.bare_at(U[0, 0], max_step)
        if res is None:
            return None
        gap = least_squares_gap(model, res.events[-1].q[None], U)[1]
        return replace(res, inputs=U, input_rates=Ud, input_accelerations=Udd, gap=gap)

    def bare_at(self, u, max_step):
        """The sweep that found a stretch past a limit where nothing assembles holding input u
        (past the limit), or None."""
        if not self.bare:  # (none known, as on most models: every move asks)
            return None
        return next((res for (L, step, _), (lo, hi, res) in self.bare.items()
                     if step == max_step and lo <= u <= hi and u != L), None)

    def coefficients(self, br):
        """Every known pose's coefficients, where not known yet (with the branch's solves ``br``)."""
        new = np.flatnonzero(np.isnan(self.qu[:, 0]))
        if new.size:
            one = np.ones((new.size, 1))
            self._rows[new, 1], self._rows[new, 2] = br.state(self.q[new], self.u[new, None], one)[:2]
        self.complete = True


def sweep(model, U, Ud, Udd, **options):
    """:func:`planar.sweep.run_sweep` from the known pose nearest U[0] (see the module), and
    the poses it reaches remembered. Values each near a known pose take the direct path
    (:func:`direct`). Sweeps that ask only for some ``outputs`` (the other coordinates are not
    solved) start from a known pose but teach none."""
    from planar.sweep import ROCKING, input_scale, run_sweep

    if U.shape[1] != 1:
        return run_sweep(model, U, Ud, Udd, **options)
    res = direct(model, U, Ud, Udd, options)
    if res is not None:
        return res
    poses = _poses(model, options.get("branch", "smooth"), options.get("tol", 1e-12))
    one = U.shape[0] == 1 and options.get("outputs") is None
    if one:
        res = poses.past_limit(model, U, Ud, Udd, options.get("max_step", 0.05))
        if res is not None:
            return res
    k = poses.nearest(U[:1, 0])[0]
    start = poses.q[k], poses.u[k : k + 1]
    known = poses.u
    past = poses.broken and (U[:, 0].min() < known.min() or U[:, 0].max() > known.max())
    if start[1][0] == poses.u0 or np.max(np.abs(U[:, 0] - poses.u0)) * input_scale(model)[0] > ROCKING or past:
        # the sketch itself (the sweep from it checks it), values the sweep may solve whole
        # periods back, from the sketch, or values past the known poses on a branch that meets
        # limits (the sweep from a known pose would meet one and be done again from the sketch)
        start = None
    reached, bare = [], []
    res = run_sweep(model, U, Ud, Udd, start, _reached=reached, _bare=bare if start is None else None, **options)
    if start is not None and not _clean(res):
        # past a limit or a branch event the way on (re-entering the range, the branch taken)
        # depends on the whole walk: the walk from the sketch decides
        start = None
        res = run_sweep(model, U, Ud, Udd, _reached=reached, _bare=bare, **options)
    if options.get("outputs") is None:
        poses.learn(res, reached[-1])
    if one and start is None:
        poses.learn_bare(res, bare, options.get("max_step", 0.05))
    return res


def direct(model, U, Ud, Udd, options):
    """The direct path: the poses at the input values U (M, 1) of a one-input model, each as
    one walk step of the sweep from the known pose nearest it, a :class:`planar.Sweep` equal to
    the sweep's (None where the path does not apply; the caller sweeps). See :class:`Direct`."""
    return Direct(model, options)(U, Ud, Udd)


class Direct:
    """The direct path of ``model`` under the sweep ``options`` (what does not change from
    call to call, worked out once: a :class:`Tracker` keeps it). Called with input values U
    (M, 1) and their rates, it applies where each value lies within the sweep's direct reach
    of a known pose (SPARSE walk steps of ``max_step``, where the sweep too solves a value from
    the Taylor predictor rather than walking to it), M is at most DIRECT, whole results are
    asked for (no ``outputs``), and the inputs are within the sweep's FAR of the sketch's.
    Then, all values in one batch: the predictor from the known pose and its kinematic
    coefficients, then the sweep's final step with Newton first (Newton on the model's blocks
    to a rounding-level guess, and the pose, its status and its rates from one factorisation)
    with the sweep's acceptance test (converged, certified, the branch's assembly modes, close
    to the predictor): :func:`planar.sweep.final_step` and :meth:`planar.sweep.Branch.accept`
    in the numpy engine, :meth:`planar.compiled.Compiled.direct` (one call) in the compiled one. Where a
    value is not certified, or its status is not SOLVED or NEAR_SINGULAR, all are left to the
    sweep (None)."""

    def __init__(self, model, options):
        from planar.sweep import FAR, SPARSE, input_scale

        self.model, self.options = model, options
        self.engine = options.get("engine", "numpy")
        self.applies = (options.get("outputs") is None and self.engine in ("numpy", "numba") and model.u0.size == 1
                        and options.get("branch", "smooth") in ("smooth", "other"))
        # (the sweep refuses the options it does not know)
        self.key = (options.get("branch", "smooth"), options.get("tol", 1e-12))
        self.u0 = float(model.u0[0])
        # the inputs the path takes: within FAR of the sketch's, scaled (the sweep solves those
        # further whole periods back, where the input is periodic)
        scale = float(input_scale(model)[0])
        self.max_step = options.get("max_step", 0.05)
        self.far, self.reach = FAR / scale, SPARSE * self.max_step / scale
        self.rates = options.get("rates", True)
        self._br = self._plan = None

    def branch(self):
        """The solves of the model's plan (:class:`planar.sweep.Branch`)."""
        if self._br is None:
            from planar.blocks import plan
            from planar.sweep import Branch

            self._br = Branch(self.model, plan(self.model), self.key[1], engine=self.engine)
            if self._br.compiled is not None:  # (the plan as the compiled loop takes it)
                self._plan = self._br.compiled.plan_of(self.model, self._br.p)
        return self._br

    def __call__(self, U, Ud, Udd):
        if not self.applies or U.shape[0] > DIRECT:
            return None
        M, u = U.shape[0], U[:, 0]
        first = float(u[0])
        if not (abs(first - self.u0) if M == 1 else np.max(np.abs(u - self.u0))) <= self.far:
            return None  # (NaN inputs: the sweep's)
        poses = _poses(self.model, *self.key)
        if M == 1 and (first == poses.refused or poses.bare_at(first, self.max_step) is not None):
            return None  # (the sweep's: it knows the stretch past a limit with nothing there)
        br = self.branch()
        if poses.signs is None:
            from planar.sweep import check_sketch

            check_sketch(self.model, br.p)  # (a sketch on a singular position is refused, as the sweep does)
            poses.signs = np.ascontiguousarray(br.signs(self.model.q0[None], self.model.u0[None]), np.int8)
            # (as either engine gave them: the compiled engine reads them as they are)
        if not poses.complete:  # (the predictor reads every known pose's coefficients)
            poses.coefficients(br)
        r = self._compiled(br, poses, U) if self.engine == "numba" else self._numpy(br, poses, U)
        if r is None:
            poses.refused = first if M == 1 else None
            return None
        rows, status, res, iters, sing, branch = r
        if M == 1:
            poses.append(first, rows[:, 0])
        else:
            poses.merge(u, rows)
        q, qu, quu = rows[0], rows[1], rows[2]
        if not self.rates:
            qd = qdd = np.broadcast_to(np.nan, q.shape)
        elif Ud.size == 1 and Ud.item() == 1.0 and Udd.item() == 0.0:
            qd, qdd = qu, quu  # (a unit rate: the coefficients are the rates)
        else:
            qd, qdd = qu * Ud, quu * Ud**2 + qu * Udd
        events = ()
        if (sing.item() < NEAR_CURVE) if M == 1 else (sing < NEAR_CURVE).any():
            from planar.sweep import near_stretches

            events = tuple(near_stretches(self.model, U, sing, status, ()))
        gap = NO_GAP if M == 1 else np.full(M, np.nan)
        return Sweep(self.model, U, Ud, Udd, q, qd, qdd, status, res, iters, sing, branch, gap, events)

    def _numpy(self, br, poses, U):
        """(rows, status, res, iters, sing, branch) of the values U (rows (3, M, n): their q, qu
        and quu), or None (see the class)."""
        from planar.sweep import final_step

        k = poses.nearest(U[:, 0])
        du = (U[:, 0] - poses.u[k])[:, None]
        if not np.max(np.abs(du)) <= self.reach:
            return None
        qk = poses.q[k]
        q_pred = qk + poses.qu[k] * du + 0.5 * poses.quu[k] * du**2
        # Newton and the sweep's final step at a unit input rate: its rates are the kinematic
        # coefficients of the new poses (the next moves' predictor); the asked rates follow from
        # them linearly
        one, zero = np.ones((U.shape[0], 1)), np.zeros((U.shape[0], 1))
        r = final_step(br, q_pred, U, one, zero, steps=NEWTON)
        ok = br.accept(r["q"], q_pred, lambda rows: qk[rows], r["conv"], r["signs"], poses.signs, r["sing"], r["off"])
        if not (ok.all() and (r["status"] <= Status.NEAR_SINGULAR).all()):  # (CLEAN)
            return None
        return (np.stack((r["q"], r["qd"], r["qdd"])), r["status"].astype(np.int8), r["res"], r["iters"], r["sing"],
                r["branch"])

    def _compiled(self, br, poses, U):
        """As :meth:`_numpy`, in one call of the compiled engine."""
        return self._plan.direct(poses.u, poses.rows, poses.signs, U, self.key[1], self.reach, NEWTON)


def _clean_end(res):
    """The number of values of ``res`` before its first event that breaks the branch and its
    first value not reached on it."""
    stop = [e.index for e in res.events if e.kind in BREAKS]
    bad = np.flatnonzero(~np.isin(res.status, CLEAN))
    return min(stop + bad[:1].tolist() + [res.status.size])


def _clean(res):
    return _clean_end(res) == res.status.size and not any(e.kind in BREAKS for e in res.events)


def _poses(model, branch, tol):
    known = model.known_poses  # {(branch, tol): Poses}, oldest first
    key = (branch, float(tol))
    if key not in known:
        if len(known) >= KEYS:
            del known[next(iter(known))]
        known[key] = Poses(model)
    return known[key]


class Tracker:
    """An input moved by hand: each :meth:`move` goes on from the last pose (or the known pose
    nearest the new value), with the statuses, events and branch of a sweep from the sketch.
    ``pose`` is the last result (None before the first move); ``direct`` whether it came by
    the direct path (:func:`direct`, for a value and rates given as numbers) rather than a
    sweep. Made by :meth:`planar.Model.track`; ``options`` are the sweep's (``branch``,
    ``tol``, ``max_step``, ``rates``, ``engine``)."""

    def __init__(self, model, **options):
        from planar.sweep import run_sweep

        self.model = model
        self.options = arguments.sweep_options(options, run_sweep)
        self.pose = None
        self.direct = False
        self._direct = Direct(model, self.options)
        # the largest input rate and acceleration taken without the sweep's checks (in the
        # units of the one input)
        scale = float(model.L) if model.input_lengths.size == 1 and model.input_lengths[0] else 1.0
        self._limits = (arguments.MAX_RATE * scale, arguments.MAX_ACCELERATION * scale)

    def __repr__(self) -> str:
        return f"<Tracker of {self.model.name!r}: {self.pose!r}>"

    def move(self, value, velocity=1.0, acceleration=0.0):
        """The pose at input ``value`` (a number, or one per input): a :class:`planar.Sweep`
        of one value, as ``model.sweep([value], velocity, acceleration)`` gives it."""
        res = None
        if type(value) in NUMBER and type(velocity) in NUMBER and type(acceleration) in NUMBER:
            try:
                u, v, a = float(value), float(velocity), float(acceleration)
            except OverflowError:  # (an integer beyond any float: the sweep's checks say so)
                u = v = a = math.nan
            # (a NaN or infinite rate is beyond its limit)
            if math.isfinite(u) and abs(v) <= self._limits[0] and abs(a) <= self._limits[1]:
                # (a unit rate and no acceleration, as a drag asks: arrays shared by the moves, read only)
                unit = v == 1.0 and a == 0.0
                res = self._direct(np.array([[u]]), UNIT[0] if unit else np.array([[v]]),
                                   UNIT[1] if unit else np.array([[a]]))
        self.direct = res is not None
        if res is None:  # the sweep, with its checks of the arguments
            try:
                # (None read as an object; more numbers than inputs refused before they are
                # copied as floats)
                given = np.asarray(value)
                if not_real(value, given.dtype) or given.dtype.kind == "O" or given.size > self.model.u0.size:
                    raise TypeError(value)
                given = given.astype(float)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"move takes a number (one per input), got {value!r}") from None
            res = self.model.sweep(given.reshape(1, -1) if given.ndim else [given], velocity, acceleration,
                                   **self.options)
        self.pose = res
        return res
