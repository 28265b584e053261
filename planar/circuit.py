"""The whole circuit of a one-input mechanism: the input reverses at each limit position.

A circuit is the closed curve of poses the assembled sketch lies on. Where the input cannot
turn fully (a triple rocker, a crank-rocker driven by its rocker, the geared five-bar) the
circuit passes limit positions: there the input stops and turns back, and the mechanism
changes assembly mode. :func:`circuit` follows that curve once round, so one call gives the
complete coupler curve:

1. **Trace**: pseudo-arclength continuation (:class:`planar.events.Tracer`) from the sketch,
   the input rising first. Each turning point of the input is located on the tangent's input
   component (to ~1e-15); where branches cross (a bifurcation) the trace keeps to the smooth
   branch; it ends where the curve is back at the sketch's pose (angles modulo a turn, so an
   input that turns fully ends one turn on).
2. **Stretches**: the limits split the circuit into stretches, each monotone in the input.
   Samples are evenly spaced in the input within each stretch, the stretches sharing them in
   proportion to their input span; both ends and each limit are samples.
3. **Solve**: all other samples at once, by Newton from the traced curve (cubic Hermite in
   arclength, O(h^4) off) with the test that each stays on the traced curve (near its guess,
   same assembly mode); rates from the linear solves, with input rate ``+velocity`` where the
   input rises and ``-velocity`` where it falls (``acceleration`` likewise).

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> res = circuit(four_bar(4, 3, 3, 3).compile(), samples=9)   # a triple rocker
>>> np.degrees(res.inputs[:, 0]).round(2).tolist()
[0.0, 58.64, 117.28, 58.64, 0.0, -58.64, -117.28, -58.64, 0.0]
>>> [(e.kind, e.index) for e in res.events], res.branch.tolist()
([('limit', 2), ('limit', 6)], [-1.0, -1.0, 0.0, 1.0, 1.0, 1.0, 0.0, -1.0, -1.0])
"""

import numpy as np

from planar.blocks import plan as block_plan
from planar.errors import AssemblyError, InputError
from planar.events import NEAR, SINGULAR, Event, Tracer
from planar.results import Status, Sweep
from planar.solver import newton
from planar.sweep import _Branch

TURN = 2 * np.pi
MAX_TURNS = 12  # input travel, in turns, after which a circuit that has not closed is given up
CLOSED = 1e-6  # scaled distance from the sketch's pose that counts as back at the start
CHUNK = 8192


def circuit(model, samples=361, velocity=1.0, acceleration=0.0, tol=1e-12, max_step=0.05):
    """The circuit through the assembled sketch of a one-input ``model``; see
    :meth:`planar.Model.circuit`."""
    if len(model.drivers) != 1:
        raise InputError(f"a circuit needs exactly one input; {model.name!r} has {list(model.input_names)}: "
                         f"sweep it with Model.sweep")
    v, a = _rate(velocity, "velocity"), _rate(acceleration, "acceleration")
    whole = not isinstance(samples, bool) and isinstance(samples, (int, np.integer))
    if not whole or samples < 2:
        raise InputError(f"circuit samples must be a whole number of at least 2, got {samples!r}")
    p = block_plan(model)
    tr = Tracer(model, p, model.q0, model.u0, model.u0 + TURN / _scale(model), max_step)
    Y, T, limits, marks = _trace(model, p, tr, max_step, tol)
    bounds = np.r_[0, limits, len(Y) - 1].astype(int)
    if samples < bounds.size:
        raise InputError(f"circuit samples must be at least {bounds.size} for {model.name!r} (both ends and its "
                         f"{len(limits)} limit position(s)), got {samples}")
    # travel: the input distance covered along the circuit (monotone, unlike the input)
    travel = np.r_[0.0, np.cumsum(np.abs(np.diff(Y[:, -1])))]
    per = _share(np.diff(travel[bounds]), samples - 1)
    stretch = np.repeat(np.arange(per.size), per)
    first = np.r_[0, np.cumsum(per)[:-1]]  # sample index of each stretch's start
    frac = (np.arange(samples - 1) - first[stretch]) / per[stretch]
    tau = np.r_[travel[bounds[stretch]] + frac * np.diff(travel[bounds])[stretch], travel[-1]]
    stretch = np.r_[stretch, per.size - 1]
    rising = np.sign(np.diff(Y[bounds, -1]))[stretch]
    on_limit = np.zeros(samples, bool)
    on_limit[first[1:]] = True

    # guesses on the traced curve; limits as located
    k = np.clip(np.searchsorted(travel, tau, side="right") - 1, 0, len(Y) - 2)
    y = _hermite(Y, T, travel, k, tau)
    y[on_limit] = Y[limits]
    y[0], y[-1] = Y[0], Y[-1]
    guess = _poses(tr, y)
    U = model.u0 + y[:, -1:] / _scale(model)
    Ud, Udd = (rising * v)[:, None], (rising * a)[:, None]
    out = _solve(model, p, guess, U, Ud, Udd, tol, max_step, on_limit)

    events = [Event("limit", float(U[i, 0]), int(i), out[0][i],
                    note="the input turns back here: the circuit goes on in the other assembly mode")
              for i in np.flatnonzero(on_limit)]
    for kind, kk, ym, note in marks:
        t_m = travel[kk] + abs(ym[-1] - Y[kk, -1])
        i = int(np.searchsorted(tau, t_m - 1e-12))
        events.append(Event(kind, float(tr.u_of(ym)[0]), min(i, samples - 1), tr.q_of(ym), note=note))
    events.sort(key=lambda e: e.index)
    return Sweep(model, U, Ud, Udd, *out, np.full(samples, np.nan), tuple(events))


def _scale(model):
    """Scaled input per unit input: 1 for an angle, 1/L for a length."""
    return 1.0 / model.L if model.input_lengths[0] else 1.0


def _rate(x, what):
    try:
        x = float(x)
    except (TypeError, ValueError):
        raise InputError(f"circuit {what} must be one number (the input's {what} along its motion: its sign "
                         f"follows the input at each reversal), got {x!r}") from None
    if not np.isfinite(x):
        raise InputError(f"circuit {what} must be finite, got {x!r}")
    return x


def _share(spans, intervals):
    """Intervals per stretch: at least one each, the rest in proportion to the spans
    (largest remainders)."""
    extra = intervals - spans.size
    want = extra * spans / spans.sum() if spans.sum() > 0 else np.full(spans.size, extra / spans.size)
    got = np.floor(want).astype(int)
    got[np.argsort(got - want)[: extra - got.sum()]] += 1
    return got + 1


def _poses(tr, y):
    """Full poses (M, n) of curve points y (M, n+1)."""
    q = np.repeat(tr.q_full[None], y.shape[0], axis=0)
    q[:, tr.p.cols] = y[:, :-1] * tr.cs
    return q


def _hermite(Y, T, travel, k, tau):
    """Points of the traced curve at travel ``tau``: the cubic Hermite in arclength between
    trace points k and k+1 (chord length, unit tangents), its input component matched to the
    target by bisection (it is monotone between two trace points)."""
    y0, y1, t0, t1 = Y[k], Y[k + 1], T[k], T[k + 1]
    ds = np.linalg.norm(y1 - y0, axis=1)[:, None]
    m0, m1 = ds * t0, ds * t1
    # the input component, measured as travel from trace point k
    sgn = np.sign(y1[:, -1] - y0[:, -1])
    target = tau - travel[k]

    def at(s):
        s = s[:, None]
        s2, s3 = s * s, s * s * s
        return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * y1 + (s3 - s2) * m1

    lo, hi = np.zeros(k.size), np.ones(k.size)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = sgn * (at(mid)[:, -1] - y0[:, -1]) < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return at(0.5 * (lo + hi))


def _trace(model, p, tr, max_step, tol):
    """Follow the circuit from the sketch back to it. Returns the trace points Y (K, n+1) and
    their unit tangents T, the positions in Y of the limits (located points inserted), and the
    bifurcations and singular positions met: [(kind, trace index before it, y, note)]."""
    y, t, det = tr.start(model.q0)
    Y, T, limits, marks = [y], [t], [], []
    dets = tr.block_dets(y)
    h, travel = min(max_step, 0.1 * tr.d), 0.0
    phi = np.zeros(model.n, bool)
    phi[2::3] = True
    for _ in range(int(40 * MAX_TURNS * TURN / max_step)):
        st = tr.step(y, t, h)
        if st is None:
            raise AssemblyError(f"the circuit of {model.name!r} could not be followed past input "
                                f"{float(tr.u_of(y)[0]):.12g} (a degenerate pose): sweep it with Model.sweep")
        y1, t1, det1, h_used, h = st
        dets1 = tr.block_dets(y1)
        if np.sign(t1[-1]) != np.sign(t[-1]) and t[-1] != 0:
            # the input turns back between y and y1: a limit position
            pt = tr.locate(y, t, h_used, lambda yy, tt, dd: tt[-1])
            if pt is not None:
                limits.append(len(Y))
                Y.append(pt[0])
                T.append(pt[1])
        elif np.sign(det1) != np.sign(det) and det != 0:
            pt = _zero(tr, y, t, h_used, max_step, lambda yy, tt, dd: dd)
            if pt is not None:
                marks.append(("bifurcation", len(Y) - 1, pt, "branches cross here: the circuit goes on along "
                              "the smooth branch"))
        elif np.any(np.sign(dets1) != np.sign(dets)) and min(abs(t[-1]), abs(t1[-1])) > 1e-6:
            # a block changes mode with the input going on (not a limit just missed)
            kb = int(np.flatnonzero(np.sign(dets1) != np.sign(dets))[0])
            pt = _zero(tr, y, t, h_used, max_step, lambda yy, tt, dd: tr.block_dets(yy)[kb])
            if pt is not None:
                marks.append(("singular", len(Y) - 1, pt, "a singular position the circuit passes smoothly"))
        travel += abs(y1[-1] - y[-1])
        back = _back_at_start(model, p, tr, y, y1, t1, phi, tol)
        if back is not None:
            Y.append(back)
            T.append(tr.tangent(tr.H(back)[1], t1)[0])
            return np.array(Y), np.array(T), limits, marks
        Y.append(y1)
        T.append(t1)
        if travel > MAX_TURNS * TURN:
            break
        y, t, det, dets = y1, t1, det1, dets1
    raise AssemblyError(f"the circuit of {model.name!r} does not come back to its sketch within {MAX_TURNS} turns "
                        f"of the input (a gear ratio that is not a whole number?): sweep it with Model.sweep")


def _zero(tr, y, t, h, max_step, f):
    """The curve point where f changes sign within arclength h of (y, t): regula falsi, then
    the cubic fit through regular points around it (Newton on the singular point itself is
    only ~sqrt(eps) accurate)."""
    pt = tr.locate(y, t, h, f)
    if pt is None:
        return None
    got = tr.fit_zero(y, t, float(t @ (pt[0] - y)), min(2e-3, max_step / 4), f)
    return (got or pt)[0]


def _back_at_start(model, p, tr, y, y1, t1, phi, tol):
    """The curve point at the sketch's pose if the step y -> y1 passes it with the input
    rising (the sketch's input, or whole turns on for an angle input), else None."""
    if t1[-1] <= 0:
        return None
    period = np.inf if model.input_lengths[0] else TURN
    s = 0.0 if period == np.inf else period * np.floor(y1[-1] / period)
    if not y[-1] < s <= y1[-1]:
        return None
    w = (s - y[-1]) / (y1[-1] - y[-1])
    u = (model.u0 + s / _scale(model))[None]
    q, conv, _, _ = newton(model, tr.q_of(y + w * (y1 - y))[None], u, tol=tol, max_iter=20, plan=p)
    d = (q[0] - model.q0) / model.col_scale
    d[phi] = np.angle(np.exp(1j * (q[0] - model.q0)[phi]))
    if not conv[0] or np.max(np.abs(d)) > CLOSED:
        return None
    return np.append(q[0][p.cols] / tr.cs, s)


def _solve(model, p, guess, U, Ud, Udd, tol, max_step, on_limit):
    """Final poses, rates and statuses: Newton from the guesses except on limits (their
    located poses stand, rates NaN), each pose checked to stay near its guess and on its
    assembly mode. Returns (q, qd, qdd, status, residual, iterations, singularity, branch)."""
    N, n = guess.shape
    br = _Branch(model, p, tol)
    q, qd, qdd = guess.copy(), np.full((N, n), np.nan), np.full((N, n), np.nan)
    sing, branch, iters = np.zeros(N), np.zeros(N), np.zeros(N, int)
    status = np.full(N, Status.LIMIT, np.int8)
    free = np.flatnonzero(~on_limit)
    cs = model.col_scale
    for lo in range(0, free.size, CHUNK):
        i = free[lo : lo + CHUNK]
        with np.errstate(all="ignore"):
            qn, conv, _, it = br.solve(guess[i], U[i], max_iter=20)
            mode = br.signs(guess[i], U[i])
            qd_i, qdd_i, signs, sg = br.state(qn, U[i], Ud[i], Udd[i])
        near = np.max(np.abs(qn - guess[i]) / cs, axis=1) <= 0.1 * max_step
        good = conv & near & np.all(signs == mode, axis=1)
        st = np.where(sg < NEAR, Status.NEAR_SINGULAR, Status.SOLVED)
        st = np.where(sg < SINGULAR, Status.SINGULAR, st)
        status[i] = np.where(good, st, Status.NOT_CONVERGED)
        q[i], iters[i], sing[i], branch[i] = qn, it, sg, np.prod(signs, axis=1)
        rate_ok = (good & (st <= Status.BRANCH_EVENT))[:, None]
        qd[i], qdd[i] = np.where(rate_ok, qd_i, np.nan), np.where(rate_ok, qdd_i, np.nan)
    with np.errstate(all="ignore"):
        Phi, _ = model.system.evaluate(q, U, jacobian=False)
    residual = np.max(np.abs(Phi[:, model.active_rows] * model.row_scale[model.active_rows]), axis=1)
    red = model.redundant_rows
    if red.size:
        bad = np.max(np.abs(Phi[:, red] * model.row_scale[red]), axis=1) > 1e3 * tol
        status[bad & (status != Status.NOT_CONVERGED)] = Status.INCONSISTENT
    # a limit located by the tracer holds the constraints to its corrector's tolerance
    status[on_limit & (residual > 1e3 * tol)] = Status.NOT_CONVERGED
    sing[on_limit] = 0.0
    lost = (status == Status.NOT_CONVERGED) | (status == Status.INCONSISTENT)
    q[lost], qd[lost], qdd[lost], residual[lost] = np.nan, np.nan, np.nan, np.nan
    return q, qd, qdd, status, residual, iters, sing, branch
