"""Singular positions met along a branch: located, classified and stepped through.

Where the natural continuation (input as the parameter) fails, the branch is followed by
pseudo-arclength continuation on the curve ``Phi(q; u_a + (sigma/d) du) = 0`` in the scaled
unknowns ``y = (q / col_scale, sigma)``; ``sigma`` is the scaled input distance from u_a along
the sweep direction. On that curve:

- a *limit position* (turning point) is where the input stops and turns back: the sigma
  component of the unit tangent changes sign. It is located by regula falsi on that component
  (the input error is quadratic in the arclength error, so to ~1e-15);
- a *bifurcation* (change point, parallelogram fold) is where another branch crosses: the sign
  of det [H_y; t] flips while the input keeps going. It is located the same way on that det;
  the two tangents come from the gamma-function quadratic (design notes 3.7), and the tracer,
  which steps over the crossing, stays on the smooth branch;
- a *near-singular* stretch is where the normalised det of the driven system dips below
  :data:`NEAR` without changing sign (an avoided crossing): valid, but sensitive.

>>> Event("limit", 1.5, 10).kind
'limit'
"""

from dataclasses import dataclass, field

import numpy as np

from planar.results import Status

NEAR = 1e-4  # normalised |det| below which a stretch is near-singular
SINGULAR = 1e-10  # ... and below which a point sits on the singular position itself
MAX_EVENTS = 8  # singular positions one crossing may locate before it gives the branch up
# a traced step is certified to stay on its solution curve when it is no longer than MOVE, and
# its correction no larger than CERT, times the distance to the nearest other curve (scaled)
MOVE, CERT = 0.5, 0.1
GAP_CROSS = 1e-5  # scaled distance below which another curve is taken to cross this one
CROSS_STEP = 1e-3  # scaled arclength of a step over a crossing
ROUNDING = 1e-12  # scaled correction at the corrector's own tolerance: no jump
NEAR_CURVE = 1e-2  # scaled distance to another solution curve below which a crossing is reported
# a redundant joint holds, and a pose on a singular position (where Newton converges only
# linearly) is kept, while its scaled residual is within HELD times the tolerance
HELD = 1e3
# the status of a converged pose by how many of NEAR and SINGULAR its singularity measure is below
BY_MEASURE = np.array([Status.SOLVED, Status.NEAR_SINGULAR, Status.SINGULAR])


def status_of(sing, red=0.0, tol=np.inf):
    """The status of converged poses: INCONSISTENT where a redundant joint's scaled residual
    ``red`` exceeds HELD times ``tol``, else by the singularity measure ``sing``: SINGULAR below
    SINGULAR, NEAR_SINGULAR below NEAR, SOLVED. Scalars or arrays, with no branches: both
    engines use this one rule (the compiled engine compiles it into its loop).

    >>> [str(Status(s)) for s in status_of(np.array([0.5, 1e-6, 0.0]))]
    ['SOLVED', 'NEAR_SINGULAR', 'SINGULAR']
    >>> str(Status(status_of(0.5, red=1.0, tol=1e-12)))
    'INCONSISTENT'
    """
    st = BY_MEASURE[(sing < NEAR) * 1 + (sing < SINGULAR) * 1]
    return st + (Status.INCONSISTENT - st) * (red > HELD * tol)


@dataclass(frozen=True, eq=False)
class Event:
    """A singular position met by a sweep.

    ``kind`` is "limit" (the input cannot go further on this branch), "bifurcation" (branches
    cross: the sweep continued on the smooth branch, or on the other one if asked),
    "singular" (a singular position the branch passes smoothly, as the fold of a double
    parallelogram) or "near_singular" (an avoided crossing or a close approach: values valid
    but sensitive).
    ``input`` is the input value there (a float for one input, else (f,)); ``index`` the first
    sweep value at or after it; ``q`` the pose; ``tangents`` (bifurcation) the (followed,
    other) velocities dq/du along the sweep direction per unit input; ``singularity`` the
    normalised |det| there; ``error`` an estimate of the scaled position error of values in
    the stretch (machine epsilon over the singularity).
    """

    kind: str
    input: object
    index: int
    q: np.ndarray = None
    tangents: tuple = ()
    singularity: float = 0.0
    error: float = 0.0
    note: str = ""

    def __repr__(self):
        u = np.round(np.asarray(self.input, float), 12).tolist()
        return f"Event({self.kind!r}, input={u}, index={self.index})"


@dataclass
class Crossing:
    """What :func:`cross` found: the pose at the target (``q`` or None), whether a limit
    stopped it (``limit`` event, with the last regular pose before it in ``before``), and the
    events met on the way (in order)."""

    q: np.ndarray = None
    limit: Event = None
    before: tuple = None
    events: list = field(default_factory=list)


def _quiet(f):
    """Run f with numpy floating-point warnings off: a correction that diverges reads
    non-finite values, which the acceptance tests reject (the step is halved)."""
    def run(*args, **kw):
        with np.errstate(all="ignore"):
            return f(*args, **kw)
    run.__doc__, run.__name__ = f.__doc__, f.__name__
    return run


class Tracer:
    """Pseudo-arclength continuation of one pose along the input path from u_a towards u_b."""

    def __init__(self, model, plan, q, u_a, u_b, max_step):
        self.m, self.p = model, plan
        self.q_full = np.array(q, float)
        self.u_a = np.asarray(u_a, float)
        self.du = np.asarray(u_b, float) - self.u_a
        s = np.where(model.input_lengths, 1.0 / model.L, 1.0)
        self.d = float(np.max(np.abs(self.du * s)))
        self.cs = model.col_scale[plan.cols]
        self.rs = model.row_scale[plan.rows]
        self.h_max = max_step
        dcol = np.zeros(plan.rows.size)
        dcol[plan.drivers] = -self.du[plan.driver_inputs] / self.d
        self.dcol = dcol * self.rs

    # ---- the curve ---------------------------------------------------------------------

    def q_of(self, y):
        q = self.q_full.copy()
        q[self.p.cols] = y[:-1] * self.cs
        return q

    def u_of(self, y):
        return self.u_a + (y[-1] / self.d) * self.du

    def H(self, y):
        """Scaled residual (n,) and Jacobian (n, n+1) at y."""
        q, u = self.q_of(y)[None], self.u_of(y)[None]
        with np.errstate(all="ignore"):  # a diverged correction reads non-finite: callers check
            Phi, J = self.p.system.evaluate(q, u)
            A = J[0][self.p.rows][:, self.p.cols] * self.rs[:, None] * self.cs[None, :]
            return Phi[0, self.p.rows] * self.rs, np.column_stack((A, self.dcol))

    def tangent(self, A, t_prev):
        """Unit tangent oriented along t_prev, and det of the augmented matrix [A; t]."""
        M = np.vstack((A, t_prev))
        e = np.zeros(M.shape[0])
        e[-1] = 1.0
        with np.errstate(all="ignore"):  # non-finite tangents fail the step's acceptance test
            try:
                t = np.linalg.solve(M, e)
            except np.linalg.LinAlgError:
                t = _kernel(A)  # [A; t_prev] exactly singular: the curve's own null direction
            t /= np.linalg.norm(t)
            if t @ t_prev < 0:
                t = -t
            return t, float(np.linalg.det(np.vstack((A, t))))

    @_quiet
    def correct(self, y_pred, t, iters=10):
        """Newton on [H(y); t.(y - y_pred)] = 0; returns (y, A at y) or None."""
        y = y_pred.copy()
        prev, stalls = np.inf, 0
        for _ in range(iters):
            r, A = self.H(y)
            if not np.all(np.isfinite(r)):
                return None
            M = np.vstack((A, t))
            try:
                dy = np.linalg.solve(M, np.append(r, t @ (y - y_pred)))
            except np.linalg.LinAlgError:
                return None
            y = y - dy
            step = np.max(np.abs(dy))
            if step <= 1e-13 and np.max(np.abs(r)) <= 1e-11:
                return y, self.H(y)[1]
            # stop a correction that no longer converges (on degenerate sketches it would
            # spend its whole budget): the residual test below decides, the caller halves h
            stalls = stalls + 1 if step > 0.5 * prev else 0
            if stalls >= 3:
                break
            prev = step
        r, A = self.H(y)
        return (y, A) if np.max(np.abs(r)) <= 1e-12 else None

    @_quiet
    def block_dets(self, y):
        """Normalised signed dets of the driven system's blocks at y."""
        q, u = self.q_of(y)[None], self.u_of(y)[None]
        _, _, Jv = self.p.evaluate(q, u)
        return self.p.factor(Jv).dets[0]

    # ---- stepping and locating ---------------------------------------------------------

    @_quiet
    def start(self, q):
        y = np.append(q[self.p.cols] / self.cs, 0.0)
        _, A = self.H(y)
        # the driven tangent: J x_sigma = -dcol, direction of increasing sigma (at a singular
        # start, the null direction of A oriented the same way)
        try:
            t = np.append(np.linalg.solve(A[:, :-1], -A[:, -1]), 1.0)
        except np.linalg.LinAlgError:
            t = _kernel(A)
            t = -t if t[-1] < 0 else t
        t /= np.linalg.norm(t)
        t, det = self.tangent(A, t)
        return y, t, det

    def gap(self, A, t):
        """The smallest singular value of the augmented matrix [A; t]: near another solution
        curve (an avoided crossing, a crossing branch) it is about the distance to it."""
        with np.errstate(all="ignore"):
            M = np.vstack((A, t))
            if not np.all(np.isfinite(M)):
                return 0.0
            return float(np.linalg.svd(M, compute_uv=False)[-1])

    @_quiet
    def step(self, y, t, h, gap=None):
        """One certified step from (y, t) with step control; returns (y, t, det, h_used,
        h_next, gap at the new point). ``gap`` (:meth:`gap` at y) bounds the step: no longer
        than MOVE times the distance to another solution curve, and the corrector's move no
        more than CERT times that distance at the new point, so the step cannot land on a
        neighbouring curve. Closer than GAP_CROSS the curves are taken to cross: the step is
        at least CROSS_STEP, over the crossing to where the curves are apart again."""
        if gap is None:
            gap = self.gap(self.H(y)[1], t)
        h = min(h, MOVE * gap) if gap >= GAP_CROSS else max(h, CROSS_STEP)
        while h > 1e-13:
            got = self.correct(y + h * t, t)
            if got is not None:
                y1, A1 = got
                t1, det1 = self.tangent(A1, t)
                gap1 = self.gap(A1, t1)
                moved = np.linalg.norm(y1 - (y + h * t))
                if moved <= 0.3 * h and t1 @ t > 0.8 and moved <= max(CERT * gap1, ROUNDING):
                    return y1, t1, det1, h, min(2 * h, self.h_max), gap1
            h /= 2
        return None

    def at(self, y, t, h):
        """The curve point at arclength offset ~h from (y, t): (y_h, t_h, det_h)."""
        got = self.correct(y + h * t, t, iters=30)
        if got is None:
            return None
        y1, A1 = got
        t1, det1 = self.tangent(A1, t)
        return y1, t1, det1

    def locate(self, y, t, h, f):
        """Regula falsi (Illinois) for the zero of f(y_h, t_h, det_h) on (0, h) from (y, t)."""
        a, fa = 0.0, f(y, t, self.tangent(self.H(y)[1], t)[1])
        b, pt = h, self.at(y, t, h)
        if pt is None:
            return None
        fb = f(*pt)
        best = pt
        side = 0
        for _ in range(80):
            if b - a <= 1e-12 * max(1.0, h):
                break
            c = b - fb * (b - a) / (fb - fa) if fb != fa else 0.5 * (a + b)
            if not a < c < b:
                c = 0.5 * (a + b)
            pt = self.at(y, t, c)
            if pt is None:
                break
            fc = f(*pt)
            best = pt
            if fc == 0:
                break
            if (fc > 0) == (fa > 0):
                a, fa = c, fc
                if side == -1:
                    fb /= 2
                side = -1
            else:
                b, fb = c, fc
                if side == 1:
                    fa /= 2
                side = 1
        return best


    def fit_zero(self, y, t, c0, h, f):
        """Refine a zero c0 of f along the branch from four regular points at c0 +- h, +- 2h
        (arclength offsets from (y, t)): a cubic through f gives the zero, cubics through the
        points give y there (at the singular point itself Newton is only ~sqrt(eps) accurate,
        while the branch around it is smooth)."""
        nodes = c0 + h * np.array([-2.0, -1.0, 1.0, 2.0])
        pts = [self.at(y, t, c) for c in nodes]
        if any(pt is None for pt in pts):
            return None
        vals = np.array([f(*pt) for pt in pts])
        coef = np.polyfit(nodes - c0, vals, 3)
        roots = np.roots(coef)
        roots = roots[np.isreal(roots)].real
        if roots.size == 0:
            return None
        x = roots[np.argmin(np.abs(roots))] + c0
        w = np.array([np.prod([(x - nodes[k]) / (nodes[j] - nodes[k]) for k in range(4) if k != j])
                      for j in range(4)])
        ys = w @ np.array([pt[0] for pt in pts])
        ts = w @ np.array([pt[1] for pt in pts])
        return ys, ts / np.linalg.norm(ts)


def tangent_cone(model, plan, q, u, t_in, rate):
    """The two branch tangents dq/dsigma at a bifurcation pose (q, u), for input rate
    ``rate`` = du/dsigma (f,) along the sweep path.

    ``t_in`` (n,) is the incoming tangent (dq/dsigma, full coordinates); the first tangent
    returned is the one nearest it (the smooth branch). Tangents are t_p + lam v where v spans
    the kernel and lam solves the quadratic w.gamma(q, t_p + lam v) = 0 (w the left kernel).
    """
    p = plan
    Phi, J = p.system.evaluate(q[None], u[None])
    cs = model.col_scale[p.cols]
    rs = model.row_scale[p.rows]
    A = J[0][p.rows][:, p.cols] * rs[:, None] * cs[None, :]
    U, s, Vt = np.linalg.svd(A)
    w, v = U[:, -1], Vt[-1]
    nu = np.zeros(p.rows.size)
    nu[p.drivers] = rate[p.driver_inputs]
    nu *= rs
    tp = np.linalg.lstsq(A, nu, rcond=None)[0]

    def g(lam):
        qd = np.zeros(model.n)
        qd[p.cols] = (tp + lam * v) * cs
        gam = p.system.gamma(q[None], qd[None], u[None])[0, p.rows] * rs
        return w @ gam

    g0, g1, gm = g(0.0), g(1.0), g(-1.0)
    a2, a1, a0 = 0.5 * (g1 + gm) - g0, 0.5 * (g1 - gm), g0
    disc = a1 * a1 - 4 * a2 * a0
    if a2 == 0 or disc < 0:
        return ()
    roots = [(-a1 + sgn * np.sqrt(disc)) / (2 * a2) for sgn in (1.0, -1.0)]
    tans = []
    for lam in roots:
        qd = np.zeros(model.n)
        qd[p.cols] = (tp + lam * v) * cs
        tans.append(qd)
    x_in = t_in
    tans.sort(key=lambda T: np.linalg.norm((T - x_in)[p.cols] / cs))
    return tuple(tans)


def cross(model, plan, q, u_a, u_b, max_step, *, other=False, index=0):
    """Follow the branch from the regular pose (q, u_a) to the input u_b through whatever
    singular positions lie between; see :class:`Crossing`."""
    tr = Tracer(model, plan, q, u_a, u_b, max_step)
    out = Crossing()
    y, t, det = tr.start(q)
    dets = tr.block_dets(y)
    sing_min, y_min = np.min(np.abs(dets)), y
    h, gap = min(max_step, 0.1 * tr.d), None
    gap_min, y_gap = np.inf, y
    last_regular = (q, np.array(u_a, float))
    # bounded: a degenerate curve is given up; the allowance covers approaches to crossings, whose
    # certified steps shrink with the gap (~150 steps each from gap 0.1 down to GAP_CROSS)
    for _ in range(int(20 * tr.d / max_step) + 2000):
        st = tr.step(y, t, h, gap)
        if st is None:
            return out
        y1, t1, det1, h_used, h, gap = st
        if t1[-1] < 0 < t[-1]:
            # the input turned back: a limit position between y and y1
            pt = tr.locate(y, t, h_used, lambda yy, tt, dd: tt[-1])
            if pt is None:
                return out
            ys = pt[0]
            if ys[-1] > tr.d + 1e-10:
                # the step passed the target before it turned back: the target is on this side
                # (a limit at the target itself, to 1e-10, is that limit: the walker says so)
                c = float(t @ (ys - y))
                at = tr.locate(y, t, c, lambda yy, tt, dd: yy[-1] - tr.d)
                if at is not None:
                    out.q = tr.q_of(at[0])
                    break
            qs, us = tr.q_of(ys), tr.u_of(ys)
            out.limit = Event("limit", _scalar(us), index, qs, singularity=0.0,
                              note="the input cannot go further on this branch: reverse it to continue")
            out.before = last_regular
            return out
        if np.sign(det1) != np.sign(det) and det != 0:
            det_of = lambda yy, tt, dd: dd  # noqa: E731
            pt = tr.locate(y, t, h_used, det_of)
            if pt is not None:
                c0 = float(t @ (pt[0] - y))
                pt = tr.fit_zero(y, t, c0, min(2e-3, max_step / 4), det_of) or pt
                ys, ts = pt[0], pt[1]
                qs, us = tr.q_of(ys), tr.u_of(ys)
                # tangents per unit sigma, reported per unit input (f = 1) or per unit step
                dq = np.zeros(model.n)
                dq[plan.cols] = ts[:-1] / ts[-1] * tr.cs
                rate = tr.du / tr.d
                raw = tangent_cone(model, plan, qs, us, dq, rate)
                per = rate[0] if rate.size == 1 else np.max(np.abs(rate))
                ev = Event("bifurcation", _scalar(us), index, qs, tangents=tuple(T / per for T in raw),
                           note="branches cross here: continued on the " +
                           ("other branch" if other else "smooth branch (pass branch='other' to take the other)"))
                out.events.append(ev)
                if other and len(raw) == 2:
                    # leave the crossing along the other tangent, towards increasing input
                    T = np.append(raw[1][plan.cols] / tr.cs, 1.0)
                    T /= np.linalg.norm(T)
                    got = tr.correct(ys + min(max_step, 1e-3) * T, T)
                    if got is None:
                        return out
                    y1 = got[0]
                    t1, det1 = tr.tangent(got[1], T)
                    gap = None
        dets1 = tr.block_dets(y1)
        flips = np.flatnonzero(np.sign(dets1) != np.sign(dets))
        if flips.size and not (out.events and out.events[-1].kind == "bifurcation"
                               and np.sign(det1) != np.sign(det)):
            # a block det changes sign with the branch going on smoothly (no crossing of
            # branches seen, e.g. the fold of a double parallelogram): a singular position
            k = int(flips[0])
            dk = lambda yy, tt, dd: tr.block_dets(yy)[k]  # noqa: E731
            pt = tr.locate(y, t, h_used, dk)
            if pt is not None:
                c0 = float(t @ (pt[0] - y))
                pt = tr.fit_zero(y, t, c0, min(2e-3, max_step / 4), dk) or pt
                ys, ts = pt[0], pt[1]
                dq = np.zeros(model.n)
                dq[plan.cols] = ts[:-1] / ts[-1] * tr.cs
                rate = tr.du / tr.d
                per = rate[0] if rate.size == 1 else np.max(np.abs(rate))
                out.events.append(Event("singular", _scalar(tr.u_of(ys)), index, tr.q_of(ys),
                                        tangents=(dq / per,),
                                        note="a singular position the branch passes smoothly: values there "
                                             "come from the branch around it"))
        if len(out.events) > MAX_EVENTS:
            return out  # a degenerate sketch singular all along the way: not followed (NaN, status)
        dets = dets1
        sing = np.min(np.abs(dets1))
        if sing < sing_min:
            sing_min, y_min = sing, y1
        if sing > NEAR:
            last_regular = (tr.q_of(y1), tr.u_of(y1))
        if gap is not None and gap < gap_min:
            gap_min, y_gap = gap, y1
        if y1[-1] >= tr.d:
            # passed the target: back to the input as the parameter, from the nearer point
            w = (tr.d - y[-1]) / (y1[-1] - y[-1]) if y1[-1] != y[-1] else 1.0
            guess = tr.q_of(y + w * (y1 - y))
            out.q = guess
            break
        y, t, det = y1, t1, det1
    if not any(e.kind in ("bifurcation", "singular") for e in out.events):
        if 0 < sing_min < NEAR:
            out.events.append(Event("near_singular", _scalar(tr.u_of(y_min)), index, tr.q_of(y_min),
                                    singularity=float(sing_min), error=float(np.finfo(float).eps / sing_min),
                                    note="the branch passes close to a singular position: values near here are "
                                         "sensitive to small changes of the dimensions"))
        elif gap_min < NEAR_CURVE:
            out.events.append(Event("near_singular", _scalar(tr.u_of(y_gap)), index, tr.q_of(y_gap),
                                    singularity=float(np.min(np.abs(tr.block_dets(y_gap)))),
                                    error=float(np.finfo(float).eps / gap_min),
                                    note=f"an avoided crossing: another branch passes within {gap_min:.2g} "
                                         "(scaled); this one was kept"))
    return out


def _kernel(A):
    """A unit vector of the null space of the (n, n+1) matrix A."""
    return np.linalg.svd(A)[2][-1]


def _scalar(u):
    u = np.asarray(u, float)
    return float(u[0]) if u.size == 1 else u


__all__ = ["Event", "Crossing", "Tracer", "cross", "tangent_cone", "NEAR", "SINGULAR"]


def around(model, plan, q, u, signs, max_step, reach):
    """From the pose q at input u (one input), follow its circuit through the next limit
    position and back to the same input: the pose there if its block signs are ``signs``
    (the other assembly mode of a dyad, say), else None. Tries both ways, each within
    ``reach`` (scaled input distance) of u."""
    from planar.solver import newton

    u = np.atleast_1d(np.asarray(u, float))
    s = 1.0 / model.L if model.input_lengths[0] else 1.0
    for way in (1.0, -1.0):
        # steps up to 4 max_step: the circuit is only being traced, the acceptance test of
        # Tracer.step still keeps it from jumping to another one
        tr = Tracer(model, plan, q, u, u + way * reach / s, 4 * max_step)
        try:
            y, t, _ = tr.start(q)
        except np.linalg.LinAlgError:
            return None
        h, turned, gap = min(max_step, 0.1 * tr.d), False, None
        for _ in range(int(2 * reach / max_step) + 50):
            st = tr.step(y, t, h, gap)
            if st is None:
                break
            y1, t1, _, _, h, gap = st
            turned = turned or (t1[-1] < 0 < t[-1])
            if turned and y1[-1] <= 0:
                w = y[-1] / (y[-1] - y1[-1])
                qn, conv, _, _ = newton(model, tr.q_of(y + w * (y1 - y))[None], u[None], max_iter=30, plan=plan)
                # a diverged Newton reads non-finite: its modes are not asked for
                if conv[0] and np.all(plan.factor(plan.evaluate(qn, u[None])[2]).signs[0] == signs):
                    return qn[0]
                break
            if y1[-1] >= tr.d:
                break
            y, t = y1, t1
    return None
