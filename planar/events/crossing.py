"""Singular positions located and classified along a branch (:func:`cross`: limits,
bifurcations with their tangent cone, singular and near-singular positions), and the way
round a circuit through a limit (:func:`around`)."""

from dataclasses import dataclass, field

import numpy as np

from planar.events import NEAR, NEAR_CURVE, Event
from planar.events.tracer import CROSS_STEP, GAP_CROSS, Tracer

MAX_EVENTS = 8  # singular positions one crossing may locate before it gives the branch up
SAME_EVENT = 1e-8  # scaled input within which two crossings of branches located are one
# consecutive steps closer than GAP_CROSS to another curve, shorter than CROSS_STEP or the input not
# leading (less than LEADS of the unit tangent), before a crossing gives the curve up: a crossing
# is passed in a few such steps, and a curve that runs that close for longer (a crank 1e4 times
# its coupler) gains next to nothing of input per step (two branches crossing at a shallow angle,
# a parallelogram of crank 1 and coupler 1e4, part slowly, in full steps the input leads);
# MAX_CRAWL of them in a row that could not take CROSS_STEP (halved ~15 times, each a corrector
# solve) with the gap unchanged to STEADY: the curve runs alongside the other (a pivot moved 1e7
# away), it does not cross it
MAX_CLOSE = 100
MAX_CRAWL = 10
STEADY = 1e-3
RESUME = 4  # walk steps of input a crossing asked to resume traces at least
LEADS = 0.1  # least share of the input in the unit tangent where the walk resumes


@dataclass
class Crossing:
    """What :func:`cross` found: the pose at the target (``q`` or None), whether a limit
    stopped it (``limit`` event, with the last regular pose before it in ``before``), the
    events met on the way (in order), and (``resume``: (q, u) or None) a regular pose past
    what made the walk ask, where the input leads again and the walk goes on."""

    q: np.ndarray = None
    limit: Event = None
    before: tuple = None
    events: list = field(default_factory=list)
    resume: tuple = None


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


def cross(model, plan, q, u_a, u_b, max_step, *, other=False, index=0, resume=False):
    """Follow the branch from the regular pose (q, u_a) to the input u_b through whatever
    singular positions lie between; see :class:`Crossing`. With ``resume``, stop at the first
    regular pose RESUME walk steps on where the input leads (the arclength steps cost several
    times the walk's: a walk that started next to a limit would be traced all the way)."""
    tr = Tracer(model, plan, q, u_a, u_b, max_step)
    out = Crossing()
    y, t, det = tr.start(q)
    dets = tr.block_dets(y)
    sing_min, y_min = np.min(np.abs(dets)), y
    y_start = y
    h, gap = min(max_step, 0.1 * tr.d), None
    gap_min, y_gap = np.inf, y
    last_regular = (q, np.array(u_a, float))
    at_target = False
    # bounded: a degenerate curve is given up; the allowance covers approaches to crossings, whose
    # certified steps shrink with the gap (~150 steps each from gap 0.1 down to GAP_CROSS)
    stall = _Stall()
    for _ in range(int(20 * tr.d / max_step) + 2000):
        st = tr.step(y, t, h, gap)
        if st is None or stall.stuck(gap, st):
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
                if any(e.kind == "bifurcation" and np.max(np.abs((np.atleast_1d(e.input) - us) * tr.scale)) <= SAME_EVENT
                       for e in out.events):
                    # the same crossing of branches located again: the tracing goes round it (the
                    # branches there apart at rounding), not on; given up as at MAX_EVENTS
                    return out
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
            at_target = y_min is y1
            break
        if resume and y1[-1] >= RESUME * max_step and t1[-1] >= LEADS and sing > NEAR and gap >= NEAR_CURVE:
            out.resume = (tr.q_of(y1), tr.u_of(y1))
            break
        y, t, det = y1, t1, det1
    if not any(e.kind in ("bifurcation", "singular") for e in out.events):
        # (closest at either end, the start or the target: that pose says what it is, a limit
        # there or a near-singular value; not an approach on the way)
        if 0 < sing_min < NEAR and not (at_target or y_min is y_start):
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


class _Stall:
    """A tracing's steps in a row close to another curve (within GAP_CROSS), short or with the
    input not leading, and those of them halved below CROSS_STEP with the gap unchanged: past
    MAX_CLOSE or MAX_CRAWL it is stuck."""

    def __init__(self):
        self.close = self.crawl = 0

    def stuck(self, gap, st):
        """Whether the tracing is stuck after the step ``st`` of :meth:`Tracer.step` taken
        from a point at ``gap`` (None where not known yet)."""
        along = gap is not None and gap < GAP_CROSS and st[3] < CROSS_STEP and abs(st[5] - gap) <= STEADY * gap
        self.crawl = self.crawl + 1 if along else 0
        self.close = self.close + 1 if st[5] < GAP_CROSS and (abs(st[1][-1]) < LEADS or st[3] < CROSS_STEP) else 0
        return self.close > MAX_CLOSE or self.crawl > MAX_CRAWL


def _scalar(u):
    u = np.asarray(u, float)
    return float(u[0]) if u.size == 1 else u


def around(model, plan, q, u, signs, max_step, reach):
    """From the pose q at input u (one input), follow its circuit through the next limit
    position and back to the same input: (the pose there if its block signs are ``signs``
    (the other assembly mode of a dyad, say), else None; the inputs (lo, hi) the tracing
    covered; the block signs it came back in, where it came back both ways in the same ones,
    else None). Tries both ways, each within ``reach`` (scaled input distance) of u."""
    from planar.solver import DISTANT, newton

    u = np.atleast_1d(np.asarray(u, float))
    s = 1.0 / model.L if model.input_lengths[0] else 1.0
    span = [float(u[0]), float(u[0])]
    back = []  # the signs it came back in, each way
    for way in (1.0, -1.0):
        # steps up to 4 max_step: the circuit is only being traced, the acceptance test of
        # Tracer.step still keeps it from jumping to another one
        tr = Tracer(model, plan, q, u, u + way * reach / s, 4 * max_step)
        try:
            y, t, _ = tr.start(q)
        except np.linalg.LinAlgError:
            return None, tuple(span), None
        h, turned, gap = min(max_step, 0.1 * tr.d), False, None
        stall = _Stall()
        for _ in range(int(2 * reach / max_step) + 50):
            st = tr.step(y, t, h, gap)
            if st is None or stall.stuck(gap, st):
                break
            y1, t1, _, _, h, gap = st
            u1 = float(tr.u_of(y1)[0])
            span = [min(span[0], u1), max(span[1], u1)]
            turned = turned or (t1[-1] < 0 < t[-1])
            if turned and y1[-1] <= 0:
                w = y[-1] / (y[-1] - y1[-1])
                qn, conv, _, _ = newton(model, tr.q_of(y + w * (y1 - y))[None], u[None], max_iter=DISTANT, plan=plan)
                # a diverged Newton reads non-finite: its modes are not asked for
                if conv[0]:
                    back.append(plan.factor(plan.evaluate(qn, u[None])[2]).signs[0])
                    if np.all(back[-1] == signs):
                        return qn[0], tuple(span), None
                break
            if y1[-1] >= tr.d:
                break
            y, t = y1, t1
    both = len(back) == 2 and np.array_equal(back[0], back[1])
    return None, tuple(span), back[0] if both else None


__all__ = ["Crossing", "cross", "tangent_cone", "around"]
