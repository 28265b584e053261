"""The pseudo-arclength tracer (:class:`Tracer`): certified steps along the solution curve
through singular positions, and the locating of a zero along it. One class: its steps, its
corrector and its locating share the curve's scaling and state."""

import numpy as np

from planar.acceptance import CERT

# a traced step is certified to stay on its solution curve when it is no longer than MOVE times
# the distance along the curve at which the nearest other curve would meet it, and its
# correction no larger than CERT (planar.acceptance's) times the distance to that curve (scaled)
MOVE = 0.5
GAP_CROSS = 1e-5  # scaled distance below which another curve is taken to cross this one
CROSS_STEP = 1e-3  # scaled arclength of a step over a crossing
OVER = 3.0  # a step over a crossing, in distances to it
ROUNDING = 1e-12  # scaled correction at the corrector's own tolerance: no jump
SLOPE = 0.01  # least rate of change of the gap along the curve that a step is sized for


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
        self.scale = np.where(model.input_lengths, 1.0 / model.L, 1.0)  # (each input's, as the sweep scales it)
        self.d = float(np.max(np.abs(self.du * self.scale)))
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
            # converged: the step at rounding, or converging quadratically (a step before to
            # compare with) with the next step (~ step^3 / prev^2) below it; A taken where it
            # was evaluated, a step of at most 1e-9 away (the tangent and gap differ as little)
            res = np.max(np.abs(r))
            if (step <= 1e-13 and res <= 1e-11) or (step <= 1e-9 and prev < np.inf and step**3 <= 1e-16 * prev**2 and res <= 1e-8):
                return y, A
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
        h_next, gap at the new point). ``gap`` (:meth:`gap` at y) bounds the step so that it
        cannot land on a neighbouring curve: the corrector's move is no more than CERT times
        the distance to another solution curve at the new point, and the step no longer than
        MOVE times the distance at which that curve would meet this one, at the rate the gap
        is seen to change (taken as 1 at the first step, and at least SLOPE: two curves
        side by side, crossing at a shallow angle, are passed in long steps, checked at their
        midpoint). Closer than GAP_CROSS the curves are taken to cross: the step is at least
        CROSS_STEP, and with the gap closing, OVER times the distance to the crossing, over it
        to where the curves are as far apart again. Each step is predicted with the curve's
        curvature (:meth:`bend`): where two branches cross at a shallow angle (the gap there
        ~1 / k of their distance, a parallelogram of links k times its ground), the tangent's
        own error over the step, growing as its square, is above the certificate."""
        A = self.H(y)[1]
        if gap is None:
            gap = self.gap(A, t)
            h = min(h, MOVE * gap)
        if gap < GAP_CROSS:
            h = max(h, CROSS_STEP)
        bend = self.bend(y, A, t)
        while h > 1e-13:
            got = self._landed(y, t, bend, h, gap)
            if got is not None:
                y1, t1, det1, gap1, rate = got
                h_next = min(2 * h, self.h_max, MOVE * gap1 / max(rate, SLOPE))
                if gap1 < min(gap, GAP_CROSS):
                    # closing in on a crossing, gap1 / rate ahead: the next step goes over it
                    # from here, where the tangent and bend are still accurate (closer, they err
                    # as the poses' rounding over the gap and its square)
                    h_next = max(h_next, min(self.h_max, OVER * gap1 / rate))
                return y1, t1, det1, h, h_next, gap1
            h /= 2
        return None

    def bend(self, y, A, t):
        """The curve's second derivative y'' in arclength at y (A the Jacobian there, t the unit
        tangent): [A; t] y'' = [rs gamma(q, q'); 0], the constraints' second derivative along the
        curve (the input enters them linearly). A step predicted as y + h t + h^2/2 y'' errs as
        h^3, not h^2, on the same hyperplane (t.y'' = 0). Zero where [A; t] is singular."""
        qd = np.zeros(self.m.n)
        qd[self.p.cols] = t[:-1] * self.cs
        gam = self.p.system.gamma(self.q_of(y)[None], qd[None], self.u_of(y)[None])[0, self.p.rows] * self.rs
        try:
            b = np.linalg.solve(np.vstack((A, t)), np.append(gam, 0.0))
        except np.linalg.LinAlgError:
            return np.zeros_like(y)
        return b if np.all(np.isfinite(b)) else np.zeros_like(y)

    def _landed(self, y, t, bend, h, gap):
        """The step of length h from (y, t) (``bend`` the curve's y'' there) if it is
        certified: (y1, t1, det1, gap1, the rate of change of the gap over it), else None."""
        y_pred = y + h * t + 0.5 * h * h * bend
        got = self.correct(y_pred, t)
        if got is None:
            return None
        y1, A1 = got
        t1, det1 = self.tangent(A1, t)
        gap1 = self.gap(A1, t1)
        moved = np.linalg.norm(y1 - y_pred)
        if not (moved <= 0.3 * h and t1 @ t > 0.8 and moved <= max(CERT * gap1, ROUNDING)):
            return None
        rate = abs(gap1 - gap) / h
        if h <= MOVE * gap or gap < GAP_CROSS:
            return y1, t1, det1, gap1, rate
        # a long step: the gap at its midpoint too, and the step within MOVE times the
        # distance at which it would close at the steepest rate seen on either half
        ym_pred = y + 0.5 * h * t + 0.125 * h * h * bend
        mid = self.correct(ym_pred, t)
        if mid is None:
            return None
        ym, Am = mid
        gm = self.gap(Am, self.tangent(Am, t)[0])
        rate = max(abs(gm - gap), abs(gap1 - gm)) / (0.5 * h)
        if np.linalg.norm(ym - ym_pred) > max(CERT * gm, ROUNDING):
            return None
        if h > MOVE * min(gap, gm, gap1) / max(rate, SLOPE):
            return None
        return y1, t1, det1, gap1, rate

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


def _kernel(A):
    """A unit vector of the null space of the (n, n+1) matrix A."""
    return np.linalg.svd(A)[2][-1]


__all__ = ["Tracer"]
