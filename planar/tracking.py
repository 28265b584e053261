"""Poses on demand: sweeps that start from the nearest pose a model knows on its branch, and
the :class:`Tracker` that follows an input moved by hand.

A one-input model remembers, per branch option and tolerance, poses its sweeps solved on the
branch drawn in the sketch (:class:`Poses`, at most ``CAP``). A pose is remembered only when
the continuation reached it from the sketch with no limit, bifurcation or singular position
and no invalid value on the way, so the remembered poses span one interval of the unwrapped
input, around the sketch's, on which the branch is a smooth function of the input (for a
crank that turns fully, u and u + 2 pi are different inputs, and for a geared train
different poses). A sweep walks from the remembered pose nearest its first value: inside that
interval the pose at any input is the branch's, whichever way it is reached; outside, the
walk from the interval's end nearest the value is the tail of the walk from the sketch. Where
that walk meets a limit or a branch event (past which the way on depends on the whole walk:
where the range is re-entered, which branch is taken) the sweep is done again from the sketch.
So the results, statuses and events are those of the sweep from the sketch, at the cost of the
distance from the nearest known pose on the branch. Models with more inputs sweep from the
sketch.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> m = four_bar()
>>> tracker = m.track()
>>> res = tracker.move(np.pi)          # walks from the sketch
>>> res = tracker.move(np.pi + 0.01)   # one step from the pose before
>>> res.ok.tolist(), bool(np.allclose(res.q, m.sweep([np.pi + 0.01]).q, atol=1e-12))
([True], True)
"""

import numpy as np

from planar.results import Status

CAP = 256  # poses kept per branch option: a turn of the crank at the default max_step is ~126
KEYS = 4  # branch options and tolerances remembered per model (the oldest is forgotten)
CLEAN = (Status.SOLVED, Status.NEAR_SINGULAR)  # values reached on the branch, no event at them
BREAKS = ("limit", "bifurcation", "singular")  # events past which the branch is not a function of the input


class Poses:
    """Poses of one model known on one branch: inputs ``u`` (K,) sorted, poses ``q`` (K, n);
    the sketch's among them, always."""

    def __init__(self, model):
        self.u0 = float(model.u0[0])
        self.u, self.q = np.array([self.u0]), model.q0[None].copy()

    def nearest(self, u):
        """(q, u) of the known pose nearest the input value u."""
        k = int(np.argmin(np.abs(self.u - u)))
        return self.q[k], self.u[k : k + 1]

    def learn(self, res):
        """Remember the poses of a sweep (one started from a known pose) up to its first
        event that breaks the branch or its first value not reached on it."""
        end = _clean_end(res)
        if end == 0:
            return
        take = np.unique(np.linspace(0, end - 1, min(end, CAP // 2)).astype(int))
        u = np.r_[self.u, res.inputs[take, 0]]
        q = np.vstack((self.q, res.q[take]))
        # at an input known already the known pose stays (the sketch's, at the sketch's input)
        u, first = np.unique(u, return_index=True)
        q = q[first]
        if u.size > CAP:
            # the sketch, the newest (where the next move starts) and evenly spaced others
            keep = np.zeros(u.size, bool)
            keep[np.unique(np.linspace(0, u.size - 1, CAP // 2).astype(int))] = True
            keep[np.searchsorted(u, np.r_[res.inputs[take, 0], self.u0])] = True
            u, q = u[keep], q[keep]
        self.u, self.q = u, q


def sweep(model, U, Ud, Udd, **options):
    """:func:`planar.sweep.run_sweep` from the known pose nearest U[0] (see the module), and
    the poses it reaches remembered. Sweeps that ask only for some ``outputs`` (the other
    coordinates are not solved) start from a known pose but teach none."""
    from planar.sweep import run_sweep

    if U.shape[1] != 1:
        return run_sweep(model, U, Ud, Udd, **options)
    poses = _poses(model, options.get("branch", "smooth"), options.get("tol", 1e-12))
    start = poses.nearest(U[0, 0])
    if start[1][0] == poses.u0:
        start = None  # the sketch itself (the sweep from it checks it)
    res = run_sweep(model, U, Ud, Udd, start, **options)
    if start is not None and not _clean(res):
        # past a limit or a branch event the way on (re-entering the range, the branch taken)
        # depends on the whole walk: the walk from the sketch decides
        res = run_sweep(model, U, Ud, Udd, **options)
    if options.get("outputs") is None:
        poses.learn(res)
    return res


def _clean_end(res):
    """The number of values of ``res`` before its first event that breaks the branch and its
    first value not reached on it."""
    stop = [e.index for e in res.events if e.kind in BREAKS]
    bad = np.flatnonzero(~np.isin(res.status, CLEAN))
    return min(stop + bad[:1].tolist() + [res.status.size])


def _clean(res):
    return _clean_end(res) == res.status.size and not any(e.kind in BREAKS for e in res.events)


def _poses(model, branch, tol):
    known = model._poses  # the model's private cache: {(branch, tol): Poses}, oldest first
    key = (branch, float(tol))
    if key not in known:
        if len(known) >= KEYS:
            del known[next(iter(known))]
        known[key] = Poses(model)
    return known[key]


class Tracker:
    """An input moved by hand: each :meth:`move` goes on from the last pose (or the known pose
    nearest the new value), with the statuses, events and branch of a sweep from the sketch.
    ``pose`` is the last result (None before the first move). Made by :meth:`planar.Model.track`;
    ``options`` are the sweep's (``branch``, ``tol``, ``max_step``, ``rates``, ``engine``)."""

    def __init__(self, model, **options):
        from planar import arguments
        from planar.sweep import run_sweep

        self.model = model
        self.options = arguments.sweep_options(options, run_sweep)
        self.pose = None

    def __repr__(self) -> str:
        return f"<Tracker of {self.model.name!r}: {self.pose!r}>"

    def move(self, value, velocity=1.0, acceleration=0.0):
        """The pose at input ``value`` (a number, or one per input): a :class:`planar.Sweep`
        of one value, as ``model.sweep([value], velocity, acceleration)`` gives it."""
        value = np.asarray(value, dtype=float)
        self.pose = self.model.sweep(value.reshape(1, -1) if value.ndim else [value], velocity, acceleration,
                                     **self.options)
        return self.pose
