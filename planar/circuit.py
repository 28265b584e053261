"""The whole circuit of a one-input mechanism: the input reverses at each limit position.

A circuit is the closed curve of poses the assembled sketch lies on. Where the input cannot
turn fully (a triple rocker, a crank-rocker driven by its rocker, the geared five-bar) the
circuit passes limit positions: there the input stops and turns back, and the mechanism
changes assembly mode. :func:`circuit` follows that curve once round, so one call gives the
complete coupler curve:

1. **Trace**: pseudo-arclength continuation (:class:`planar.events.tracer.Tracer`) from the sketch,
   the input rising first. Each turning point of the input is located on the tangent's input
   component (to ~1e-15); where branches cross (a bifurcation) the trace keeps to the smooth
   branch; it ends where the curve is back at the sketch's pose (angles modulo a turn, so an
   input that turns fully ends one turn on).
2. **Samples**: evenly spaced in arclength along the circuit (in the tracer's scaled
   coordinates: lengths / L, radians and the input), so the coupler curve is as fine at a
   limit as anywhere (evenly spaced inputs would leave a gap there: the pose moves like the
   square root of the input's distance from the limit). The limits split the circuit into
   stretches, each monotone in the input; both ends and each limit are samples.
3. **Solve**: all other samples at once from the traced curve (cubic Hermite, O(h^4) off):
   by Newton at the guess's input through the blocks, checked to stay near the guess and on
   the assembly mode of the trace around it; next to a limit (where a solve at a fixed input
   is ill posed) by Newton across the curve instead. The ends are solved at the sketch's input.
   Rates come from the linear solves, with input rate ``+velocity`` where the input rises
   and ``-velocity`` where it falls (``acceleration`` likewise).

An angle input that turns fully with nothing met on the way (every walk step ``SOLVED`` and
certified, no event) is swept instead, a few walk steps at a time until the pose is back at
the sketch's, and its samples spaced evenly along the chords of those poses: each step is one
Newton solve of a few poses at once, where the tracer steps one pose at a time, with SVDs.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> res = circuit(four_bar(4, 3, 3, 3).compile(), samples=9)   # a triple rocker
>>> [(e.kind, e.index, round(float(np.degrees(e.input)), 6)) for e in res.events]
[('limit', 2, 117.279613), ('limit', 6, -117.279613)]
>>> res.branch.tolist(), res.input_rates[:, 0].tolist()
([-1.0, -1.0, 0.0, 1.0, 1.0, 1.0, 0.0, -1.0, -1.0], [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0])
"""

import numpy as np

from planar import arguments
from planar.blocks import plan as block_plan
from planar.errors import AssemblyError, InputError
from planar.events import HELD, Event, status_of
from planar.events.tracer import Tracer
from planar.model.checks import is_complex
from planar.results import Status, Sweep
from planar.solver import ALONG_TANGENT, PROJECTED, newton
from planar.sweep import Branch, input_scale

TURN = 2 * np.pi
MAX_TURNS = 12  # input travel, in turns, after which a circuit that has not closed is given up
MAX_STEPS = 1e4  # tracer steps the circuit may take at most (one pose at a time: ~0.3 ms each)
MAX_SAMPLES = 10**6  # values of a circuit: ~3 us each, 340 bytes a coordinate
# coordinates a circuit traces at most (an input that turns fully is swept instead): each tracer
# step takes SVDs of their Jacobian, and a train's gears lengthen the curve (a planetary train of
# 30 planets, 96 coordinates: 4,300 steps, ~4 s; of 50, 156 coordinates: a minute)
MAX_COORDINATES = 120
CLOSED = 1e-6  # scaled distance from the sketch's pose that counts as back at the start
CHUNK = 8192


def circuit(model, samples=361, velocity=1.0, acceleration=0.0, tol=1e-12, max_step=0.05):
    """The circuit through the assembled sketch of a one-input ``model``; see
    :meth:`planar.Model.circuit`."""
    if len(model.drivers) != 1:
        raise InputError(f"a circuit needs exactly one input; {model.name!r} has {list(model.input_names)}: "
                         f"sweep it with Model.sweep")
    v, a = _rate(velocity, "velocity"), _rate(acceleration, "acceleration")
    arguments.rates(model, np.array([[v]]), np.array([[a]]))
    if MAX_TURNS * TURN / max_step > MAX_STEPS:
        raise InputError(f"circuit max_step = {max_step:g} would trace up to {MAX_TURNS} turns in "
                         f"{MAX_TURNS * TURN / max_step:.3g} steps, one pose at a time, more than the limit of "
                         f"{MAX_STEPS:g}: give max_step of at least {MAX_TURNS * TURN / MAX_STEPS:.2g}")
    whole = not isinstance(samples, bool) and isinstance(samples, (int, np.integer))
    if not whole or not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"circuit samples must be a whole number from 2 to {MAX_SAMPLES:g}, got {samples!r}")
    p = block_plan(model)
    if not model.input_lengths[0]:
        res = _turns(model, p, samples, v, a, tol, max_step)
        if res is not None:
            return res
    if model.n > MAX_COORDINATES:
        raise InputError(f"the circuit of {model.name!r} would trace its {model.n} coordinates one pose at a time "
                         f"(its input does not turn fully, or its walk meets an event), more than "
                         f"{MAX_COORDINATES} (a minute and more): sweep it with Model.sweep")
    tr = Tracer(model, p, model.q0, model.u0, model.u0 + TURN / input_scale(model)[0], max_step)
    Y, T, limits, marks = _trace(model, p, tr, max_step, tol)
    bounds = np.r_[0, limits, len(Y) - 1].astype(int)
    if samples < bounds.size:
        raise InputError(f"circuit samples must be at least {bounds.size} for {model.name!r} (both ends and its "
                         f"{len(limits)} limit position(s)), got {samples}")
    # arclength along the trace (chords), in the tracer's scaled coordinates
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(Y, axis=0), axis=1))]
    per = _share(np.diff(arc[bounds]), samples - 1)
    stretch = np.repeat(np.arange(per.size), per)
    first = np.r_[0, np.cumsum(per)[:-1]]  # sample index of each stretch's start
    frac = (np.arange(samples - 1) - first[stretch]) / per[stretch]
    s = np.r_[arc[bounds[stretch]] + frac * np.diff(arc[bounds])[stretch], arc[-1]]
    stretch = np.r_[stretch, per.size - 1]
    rising = np.sign(np.diff(Y[bounds, -1]))[stretch]
    on_limit = np.zeros(samples, bool)
    on_limit[first[1:]] = True

    # guesses on the traced curve, each corrected onto it across the curve; limits as located
    k = np.clip(np.searchsorted(arc, s, side="right") - 1, 0, len(Y) - 2)
    y, t = _hermite(Y[k], T[k], Y[k + 1], T[k + 1], (s - arc[k]) / (arc[k + 1] - arc[k]))
    y[on_limit], t[on_limit] = Y[limits], T[limits]
    # the ends at the sketch's input exactly: corrected at that input
    y[[0, -1]], t[[0, -1]] = Y[[0, -1]], np.eye(len(y[0]))[-1]
    Ud, Udd = (rising * v)[:, None], (rising * a)[:, None]
    # the assembly mode each value must keep: that of the trace points around it, where
    # they agree (not across a limit or a singular position)
    br = Branch(model, p, tol)
    signs = br.signs(_poses(tr, Y), _inputs(tr, Y))
    mode = np.where(np.all(signs[k] == signs[k + 1], axis=1)[:, None], signs[k], np.nan)
    U, out = _solve(br, tr, y, t, mode, Ud, Udd, max_step, on_limit)

    events = [Event("limit", float(U[i, 0]), int(i), out[0][i],
                    note="the input turns back here: the circuit goes on in the other assembly mode")
              for i in np.flatnonzero(on_limit)]
    for kind, kk, ym, note in marks:
        i = int(np.searchsorted(s, arc[kk] + np.linalg.norm(ym - Y[kk]) - 1e-12))
        events.append(Event(kind, float(tr.u_of(ym)[0]), min(i, samples - 1), tr.q_of(ym), note=note))
    events.sort(key=lambda e: e.index)
    return Sweep(model, U, Ud, Udd, *out, np.full(samples, np.nan), tuple(events))


def _turns(model, p, samples, v, a, tol, max_step):
    """The circuit of an angle input that turns fully with nothing met on the way, as a
    sweep over its period: whole turns, walked SPARSE steps of ``max_step`` at a time by the
    direct path (:class:`planar.tracking.Direct`: each value one walk step from the pose before,
    with the sweep's acceptance test), until the pose is back at the sketch's (angles modulo a
    turn); the samples evenly spaced along the chords of those poses, swept. None where a
    step is not certified or not SOLVED, or meets an event (a limit, a singular position: the
    trace follows those, and only the steps up to there were spent)."""
    from planar.sweep import SPARSE
    from planar.tracking import Direct

    u0, cs = float(model.u0[0]), model.col_scale[p.cols]
    step = np.linspace(0.0, TURN, int(np.ceil(TURN / max_step)) + 1)[1:]
    direct = Direct(model, dict(tol=tol, max_step=max_step))  # (its solves made once, for every step)
    one, zero = np.ones((SPARSE, 1)), np.zeros((SPARSE, 1))
    U, Q = [np.array([u0])], [model.q0[None]]
    for k in range(MAX_TURNS):
        for j in range(0, step.size, SPARSE):
            u = (u0 + k * TURN + step[j : j + SPARSE])[:, None]
            res = direct(u, one[: len(u)], zero[: len(u)])
            if res is None or res.events or np.any(res.status != Status.SOLVED):
                return None
            U.append(u[:, 0])
            Q.append(res.q)
        if _off_sketch(model, Q[-1][-1]) <= CLOSED:
            break
    else:
        raise _not_closed(model)
    U, Q = np.concatenate(U), np.concatenate(Q)
    Y = np.concatenate((Q[:, p.cols] / cs, (U - u0)[:, None]), axis=1)
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(Y, axis=0), axis=1))]
    values = np.interp(np.linspace(0.0, arc[-1], samples), arc, U)
    values[[0, -1]] = U[[0, -1]]
    res = model.sweep(values, velocity=v, acceleration=a, tol=tol, max_step=max_step)
    return None if res.events or np.any(res.status != Status.SOLVED) else res


def _rate(x, what):
    """One finite number: the input's rate (or acceleration) along its motion."""
    try:
        ok = (np.ndim(x) == 0 and not isinstance(x, (str, bool)) and not is_complex(x)
              and np.isfinite(float(x)))
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise InputError(f"circuit {what} must be one finite number (the input's {what} along its motion: its "
                         f"sign follows the input at each reversal), got {x!r}")
    return float(x)


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


def _inputs(tr, y):
    """Inputs (M, 1) of curve points y (M, n+1)."""
    return tr.u_a + (y[:, -1:] / tr.d) * tr.du


def _hermite(y0, t0, y1, t1, x):
    """Cubic Hermite between curve points y0 and y1 (M, n+1) with unit tangents t0, t1, at
    x in [0, 1] (with the chord as the length scale, x is close to the arclength fraction):
    the points and their unit tangents."""
    ds = np.linalg.norm(y1 - y0, axis=1)[:, None]
    x = x[:, None]
    x2, x3 = x * x, x * x * x
    y = (2 * x3 - 3 * x2 + 1) * y0 + (x3 - 2 * x2 + x) * ds * t0 + (3 * x2 - 2 * x3) * y1 + (x3 - x2) * ds * t1
    t = (6 * x2 - 6 * x) * y0 + (3 * x2 - 4 * x + 1) * ds * t0 + (6 * x - 6 * x2) * y1 + (3 * x2 - 2 * x) * ds * t1
    return y, t / np.linalg.norm(t, axis=1)[:, None]


def _trace(model, p, tr, max_step, tol):
    """Follow the circuit from the sketch back to it. Returns the trace points Y (K, n+1) and
    their unit tangents T, the positions in Y of the limits (located points inserted), and the
    bifurcations and singular positions met: [(kind, trace index before it, y, note)]."""
    y, t, det = tr.start(model.q0)
    Y, T, limits, marks = [y], [t], [], []
    dets = tr.block_dets(y)
    h, travel, gap = min(max_step, 0.1 * tr.d), 0.0, None
    for _ in range(int(MAX_STEPS)):
        st = tr.step(y, t, h, gap)
        if st is None:
            raise AssemblyError(f"the circuit of {model.name!r} could not be followed past input "
                                f"{float(tr.u_of(y)[0]):.12g} (a degenerate pose): sweep it with Model.sweep")
        y1, t1, det1, h_used, h, gap = st
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
        back = _back_at_start(model, p, tr, y, y1, t1, tol)
        if back is not None:
            Y.append(back)
            T.append(tr.tangent(tr.H(back)[1], t1)[0])
            return np.array(Y), np.array(T), limits, marks
        Y.append(y1)
        T.append(t1)
        if travel > MAX_TURNS * TURN:
            raise _not_closed(model)
        y, t, det, dets = y1, t1, det1, dets1
    # (steps short of max_step along the input: a body turns many times as fast as it)
    raise AssemblyError(f"the circuit of {model.name!r} does not come back to its sketch within {MAX_STEPS:g} steps "
                        f"of the trace, {travel / TURN:.3g} turns of the input (its steps along the input stay short: "
                        "a body turns many times as fast as the input, by a gear ratio or links of sizes orders of "
                        "magnitude apart): sweep it with Model.sweep")


def _not_closed(model):
    return AssemblyError(f"the circuit of {model.name!r} does not come back to its sketch within {MAX_TURNS} turns "
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


def _off_sketch(model, q):
    """The scaled distance of pose q (n,) from the sketch's, its angles modulo a turn."""
    d = (q - model.q0) / model.col_scale
    d[2::3] = np.angle(np.exp(1j * (q - model.q0)[2::3]))
    return float(np.max(np.abs(d)))


def _back_at_start(model, p, tr, y, y1, t1, tol):
    """The curve point at the sketch's pose if the step y -> y1 passes it with the input
    rising (the sketch's input, or whole turns on for an angle input), else None."""
    if t1[-1] <= 0:
        return None
    period = np.inf if model.input_lengths[0] else TURN
    s = 0.0 if period == np.inf else period * np.floor(y1[-1] / period)
    if not y[-1] < s <= y1[-1]:
        return None
    w = (s - y[-1]) / (y1[-1] - y[-1])
    u = (model.u0 + s / input_scale(model)[0])[None]
    q, conv, _, _ = newton(model, tr.q_of(y + w * (y1 - y))[None], u, tol=tol, max_iter=ALONG_TANGENT, plan=p)
    if not conv[0] or _off_sketch(model, q[0]) > CLOSED:
        return None
    return np.append(q[0][p.cols] / tr.cs, s)


def _project(model, tr, y0, t, tol, max_iter=PROJECTED):
    """Newton onto the curve from guesses y0 (M, n+1), across it: Phi(y) = 0 and
    t.(y - y0) = 0 (the tracer's corrector, batched). Unlike a solve at a fixed input, this
    is well posed at and next to a limit. Returns (y, converged, iterations)."""
    rows, cs, rs = model.active_rows, tr.cs, model.row_scale[model.active_rows]
    dcol = np.zeros(rows.size)
    dcol[model.driver_rows_active] = -float(tr.du[0]) / tr.d * rs[model.driver_rows_active]
    y = y0.copy()
    M = len(y)
    conv, iters = np.zeros(M, bool), np.zeros(M, int)
    live = np.arange(M)
    with np.errstate(all="ignore"):
        for it in range(max_iter):
            if live.size == 0:
                break
            yl = y[live]
            Phi, J = model.system.evaluate(_poses(tr, yl), _inputs(tr, yl))
            r = Phi[:, rows] * rs
            A = np.concatenate((J[:, rows] * rs[:, None] * cs, np.broadcast_to(dcol[:, None], (live.size, rows.size, 1))), 2)
            A = np.concatenate((A, t[live][:, None, :]), 1)
            b = np.concatenate((r, np.einsum("mi,mi->m", t[live], yl - y0[live])[:, None]), 1)
            dy = _stacked_solve(A, b)
            y[live] = yl - dy
            iters[live] = it + 1
            done = (np.max(np.abs(r), axis=1) <= tol) & (np.max(np.abs(dy), axis=1) <= 1e-10)
            conv[live[done]] = True
            live = live[~done & np.all(np.isfinite(dy), axis=1)]
    return y, conv, iters


def _stacked_solve(A, b):
    """Solves of the stacked systems A x = b; NaN for an exactly singular member."""
    try:
        return np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        ok = np.linalg.slogdet(A)[0] != 0
        x = np.full(b.shape, np.nan)
        x[ok] = np.linalg.solve(A[ok], b[ok][..., None])[..., 0]
        return x


def _solve(br, tr, y, t, mode, Ud, Udd, max_step, on_limit):
    """Final poses, rates and statuses of the curve points near y (tangents t), each checked
    to stay near its guess and on its block assembly ``mode`` (NaN: not checked). Where the
    mode is known (away from limits) Newton at the guess's input, through the blocks; the
    rest, and any that fails, corrected onto the curve across it. On limits the located
    poses stand (rates NaN). Returns the inputs U (N, 1) and (q, qd, qdd, status, residual,
    iterations, singularity, branch)."""
    model, tol = br.m, br.tol
    N, n = len(y), model.n
    qd, qdd = np.full((N, n), np.nan), np.full((N, n), np.nan)
    sing, branch, iters = np.zeros(N), np.zeros(N), np.zeros(N, int)
    status = np.full(N, Status.LIMIT, np.int8)
    free = np.flatnonzero(~on_limit)
    y = y.copy()

    def settle(i, yi, conv):
        """Rates and statuses of the points i at their final yi."""
        with np.errstate(all="ignore"):
            qd_i, qdd_i, signs, sg = br.state(_poses(tr, yi), _inputs(tr, yi), Ud[i], Udd[i])
        good = conv & (np.max(np.abs(yi - y[i]), axis=1) <= 0.1 * max_step)
        good &= np.all((signs == mode[i]) | np.isnan(mode[i]), axis=1)
        st = status_of(sg)
        status[i] = np.where(good, st, Status.NOT_CONVERGED)
        sing[i], branch[i] = sg, np.prod(signs, axis=1)
        rate_ok = (good & (st <= Status.BRANCH_EVENT))[:, None]
        qd[i], qdd[i] = np.where(rate_ok, qd_i, np.nan), np.where(rate_ok, qdd_i, np.nan)
        return good

    for lo in range(0, free.size, CHUNK):
        i = free[lo : lo + CHUNK]
        known = np.all(np.isfinite(mode[i]), axis=1)
        yi = y[i]
        qn, conv, _, iters[i] = br.solve(_poses(tr, yi), _inputs(tr, yi), max_iter=PROJECTED)
        yi[:, :-1] = qn[:, tr.p.cols] / tr.cs
        good = settle(i, yi, conv & known)
        redo = np.flatnonzero(~good)
        if redo.size:
            yi[redo], conv, iters[i[redo]] = _project(model, tr, y[i[redo]], t[i[redo]], tol)
            settle(i[redo], yi[redo], conv)
        y[i] = yi
    q, U = _poses(tr, y), _inputs(tr, y)
    with np.errstate(all="ignore"):
        Phi, _ = model.system.evaluate(q, U, jacobian=False)
    residual = np.max(np.abs(Phi[:, model.active_rows] * model.row_scale[model.active_rows]), axis=1)
    red = model.redundant_rows
    if red.size:
        bad = np.max(np.abs(Phi[:, red] * model.row_scale[red]), axis=1) > HELD * tol
        status[bad & (status != Status.NOT_CONVERGED)] = Status.INCONSISTENT
    # a limit located by the tracer holds the constraints to its corrector's tolerance
    status[on_limit & (residual > HELD * tol)] = Status.NOT_CONVERGED
    sing[on_limit] = 0.0
    lost = (status == Status.NOT_CONVERGED) | (status == Status.INCONSISTENT)
    q[lost], qd[lost], qdd[lost], residual[lost] = np.nan, np.nan, np.nan, np.nan
    return U, (q, qd, qdd, status, residual, iters, sing, branch)
