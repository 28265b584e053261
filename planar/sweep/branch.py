"""Solves on one plan (:class:`Branch`): Newton, assembly modes, rates, predictors, the acceptance
test, and the final step that gives a pose its certificate, status and rates."""

import numpy as np

from planar.acceptance import ROUND, certified, on_course
from planar.errors import InputError
from planar.events import HELD, status_of
from planar.results import Status
from planar.solver import DISTANT, PREDICTED, acceleration, converged, newton, velocity


def input_scale(model):
    """(f,) the factor that scales each input: 1 / L (the model's length scale) for a length, 1 for an angle."""
    return np.where(model.input_lengths, 1.0 / model.L, 1.0)


def scaled_norm(model, du):
    """The largest scaled component of input differences du (..., f)."""
    return np.max(np.abs(du * input_scale(model)), axis=-1)


class Branch:
    """Solves on one plan: Newton, modes, rates, predictors and the acceptance test."""

    def __init__(self, model, plan, tol, rates=True, engine="numpy"):
        self.m, self.p, self.tol, self.rates = model, plan, tol, rates
        self.compiled = None  # planar.compiled for engine="numba": the per-value work runs there
        if engine == "numba":
            from planar import compiled

            compiled.check(plan)
            self.compiled = compiled
        elif engine != "numpy":
            raise InputError(f"engine must be 'numpy' or 'numba', got {engine!r}")
        self.cs = model.col_scale[plan.cols]
        self._last = (None, None)

    def _at(self, q, u):
        """The factored blocks (:class:`planar.blocks.Factors`) at poses q. A walk asks twice
        at each accepted pose (its modes, then the next prediction; a walk of one pose, or of
        many designs at once): the last answer is kept."""
        last = self._last[0]
        if last is not None and last[0].shape == q.shape and np.array_equal(last[0], q) and np.array_equal(last[1], u):
            return self._last[1]
        with np.errstate(all="ignore"):  # poses of failed solves read non-finite: rejected later
            _, _, Jv = self.p.evaluate(q, u)
            lu = self.p.factor(Jv)
        self._last = ((q.copy(), u.copy()), lu)
        return lu

    def state(self, q, u, ud, udd=None):
        """(qd, qdd, signs, sing) at solved poses for input rates ud (qdd for udd = 0)."""
        udd = np.zeros_like(ud) if udd is None else udd
        if self.compiled is not None:
            f = self.compiled.final(self.m, self.p, q, u, ud, udd)
            return f["qd"], f["qdd"], f["signs"], f["sing"]
        lu = self._at(q, u)
        qd, qdd = _rates(self.p, lu, q, u, ud, udd)
        return qd, qdd, lu.signs, lu.sing

    def predict(self, q, u, du):
        qd, qdd, signs, _ = self.state(q, u, du)
        return q + qd + 0.5 * qdd, signs

    def solve(self, q_pred, u, max_iter=PREDICTED):
        """Newton from ``q_pred``: (q, converged, residual, iterations). A pose within the
        tolerance that holds as :func:`final_step` keeps it (:func:`_holds`: near-singular or
        singular, where Newton's steps stay above the step test) is converged."""
        q, conv, res, its = newton(self.m, q_pred, u, tol=self.tol, max_iter=max_iter, plan=self.p, engine=self.compiled)
        held = np.flatnonzero(~conv & (res <= self.tol))
        if held.size:
            conv[held] = _holds(status_of(self.modes(q[held], u[held])[1]), res[held], self.tol)
        return q, conv, res, its

    def modes(self, q, u):
        """(signs, sing): the blocks' det signs and the singularity measure at poses q."""
        if self.compiled is not None:
            f = self.compiled.final(self.m, self.p, q, u, u, u, rates=False)
            return f["signs"], f["sing"]
        lu = self._at(q, u)
        return lu.signs, lu.sing

    def signs(self, q, u):
        return self.modes(q, u)[0]

    def accept(self, q, q_pred, origin, conv, signs, signs_ref, sing, off=None):
        """Converged, in the same assembly modes, no further from the predictor than JUMP
        times the predicted move (``origin(rows)``: the poses the steps of those rows started
        from; asked only where the solve moved off the predictor by more than 1e-9; ``off``:
        that distance, scaled, when the solve knows it), and certified: the correction no more
        than CERT times the singularity measure ``sing`` at the solution (about the scaled
        distance to the nearest other solution), so that it cannot have come from a
        neighbouring branch."""
        c = self.p.cols
        if off is None:
            off = np.max(np.abs((q - q_pred)[:, c] / self.cs), axis=1)
        # the modes agree where the signs differ nowhere (a NaN det reads 0: it differs): block by
        # block, whole columns of poses (a reduction over rows of a few blocks costs ~2x more)
        ok = conv & certified(off, sing)
        for j in range(signs.shape[1]):
            ok &= signs[:, j] == signs_ref[:, j]
        far = np.flatnonzero(ok & ~(off <= 1e-9))
        if far.size:
            move = np.max(np.abs((q_pred[far] - origin(far))[:, c] / self.cs), axis=1)
            ok[far] = on_course(off[far], move)
        return ok


def _rates(p, lu, q, U, Ud, Udd):
    with np.errstate(all="ignore"):
        qd = velocity(p, lu, Ud)
        return qd, acceleration(p, lu, q, qd, U, Udd)


def _step(br, q, U, Ud, Udd, steps=1):
    """One Newton step from poses q and, with the factorisation at q, the rates at the
    corrected poses: a dict of q (corrected where the step is finite), qd, qdd (NaN without
    rates), the scaled residual ``res`` at q, the scaled ``step`` and ``off`` (its size over
    the finite components: how far the pose moved), the largest scaled redundant row ``red``,
    the blocks' det ``signs``, the singularity measure ``sing``, the ``branch`` and the
    Newton steps taken ``iters``. With ``steps`` > 1, Newton: up to that many steps, each
    pose's until its residual is below the tolerance and its step at rounding level (ROUND),
    the dict's values those of its last step (so a guess at rounding level takes one step:
    its correction, certificate and rates from one factorisation). The compiled engine
    computes the same in :func:`planar.compiled.final`."""
    if br.compiled is not None:
        return br.compiled.final(br.m, br.p, q, U, Ud, Udd, br.rates, steps=steps, tol=br.tol, step_tol=ROUND)
    N = q.shape[0]
    nan = np.broadcast_to(np.nan, q.shape)  # (positions only: no velocity and acceleration solves)
    out, idx = None, np.arange(N)
    for it in range(1, steps + 1):
        f, lu = _one_step(br, q if out is None else out["q"][idx], U[idx])
        # a pose stops where it converged to rounding or is no longer finite, or at the last step
        stop = ((f["res"] <= br.tol) & (f["step"] <= ROUND)) | ~(f["step"] < np.inf) | ~(f["res"] < np.inf)
        if it == steps:
            stop[:] = True
        if out is None and stop.all():  # (most calls: one step)
            f["qd"], f["qdd"] = _rates(br.p, lu, f["q"], U, Ud, Udd) if br.rates else (nan, nan)
            f["iters"] = np.ones(N, int)
            return f
        if out is None:
            out = {k: np.array(v) for k, v in f.items()}
            out["qd"], out["qdd"] = (np.full(q.shape, np.nan), np.full(q.shape, np.nan)) if br.rates else (nan, nan)
            out["iters"] = np.ones(N, int)
        else:
            for k, v in f.items():
                out[k][idx] = v
            out["iters"][idx] = it
        if br.rates and stop.any():  # the rates of the poses that stop, with this step's factorisation
            qd, qdd = _rates(br.p, lu, f["q"], U[idx], Ud[idx], Udd[idx])
            out["qd"][idx[stop]], out["qdd"][idx[stop]] = qd[stop], qdd[stop]
        idx = idx[~stop]
        if idx.size == 0:
            return out
    return out


def _one_step(br, q, U):
    """The step of :func:`_step` but its rates and ``iters``, and the factorisation at q."""
    m, p = br.m, br.p
    with np.errstate(all="ignore"):
        Phi, full, Jv = p.evaluate(q, U)
        lu = p.factor(Jv)
        dq = lu.solve(Phi)
        res = np.max(np.abs(Phi * m.row_scale[p.rows]), axis=1)  # rows outside the plan read 0
        dq_p = np.abs(dq[:, p.cols] / m.col_scale[p.cols])
        step = np.max(dq_p, axis=1)
        # where the step is finite so is every component of the correction (the columns
        # outside the plan read 0): only the others need masking
        bad = np.flatnonzero(~np.isfinite(step))
        off = step.copy()
        if bad.size:
            off[bad] = np.max(np.where(np.isfinite(dq_p[bad]), dq_p[bad], 0.0), axis=1)
            dq[bad] = np.where(np.isfinite(dq[bad]), dq[bad], 0.0)
        q = q - dq
    return dict(q=q, res=res, step=step, off=off, red=_redundant(m, full), signs=lu.signs, sing=lu.sing,
                branch=np.prod(lu.signs, axis=1)), lu


def final_step(br, q, U, Ud, Udd, steps=1):
    """Final poses from good guesses q, with their rates and statuses. One evaluation and one
    factorisation serve a Newton step, its certificate (the residual at the guess and the size
    of the correction) and, where the correction is at rounding level (ROUND, scaled), the
    velocity and acceleration solves: the Jacobian at the guess differs from the one at the
    final pose by that little. The other points take the general Newton and one more step at
    its solution for their modes and rates. ``steps`` > 1: guesses from a predictor (a walk's
    step), Newton first (see :func:`_step`), so that one call solves and finishes them."""
    m, p, tol = br.m, br.p, br.tol
    guess = q
    f = _step(br, q, U, Ud, Udd, steps)
    q, qd, qdd, res, step, off = f["q"], f["qd"], f["qdd"], f["res"], f["step"], f["off"]
    red_res, signs, sing, branch = f["red"], f["signs"], f["sing"], f["branch"]
    iters = np.array(f["iters"], int)
    if steps > 1:  # (how far from the guess, over all the steps)
        with np.errstate(invalid="ignore"):
            off = np.max(np.abs((q - guess)[:, p.cols] / br.cs), axis=1)
    # a guess that holds the constraints where the Jacobian is singular (the correction is not
    # finite) is a pose on the singular position itself: kept, status SINGULAR, no rates
    on_singular = (res <= tol) & ~np.isfinite(step)
    # (angles counted to 1e5 rad hold their rows to their rounding only)
    conv = converged(m, q, p.cols, res, step, tol, ROUND) | ((res <= tol) & on_singular)
    sing = np.where(on_singular, 0.0, sing)
    slow = np.flatnonzero(~conv)
    if slow.size:
        qs, cv, _, it = newton(m, q[slow], U[slow], tol=tol, max_iter=DISTANT, plan=p, engine=br.compiled)
        q[slow], conv[slow], iters[slow] = qs, cv, iters[slow] + it
        g = _step(br, qs, U[slow], Ud[slow], Udd[slow])
        res[slow], red_res[slow] = g["res"], g["red"]
        if br.rates:
            qd[slow], qdd[slow] = g["qd"], g["qdd"]
        signs[slow], sing[slow], branch[slow] = g["signs"], g["sing"], g["branch"]
        off[slow] = np.max(np.abs((qs - guess[slow])[:, p.cols] / m.col_scale[p.cols]), axis=1)
    st = status_of(sing, red_res, tol)
    st = np.where(conv | _holds(st, res, tol), st, Status.NOT_CONVERGED)
    if br.rates:
        qd[st > Status.BRANCH_EVENT] = qdd[st > Status.BRANCH_EVENT] = np.nan
    return dict(q=q, qd=qd, qdd=qdd, conv=conv, off=off,
                res=res, iters=iters, signs=signs, sing=sing, branch=branch, status=st)


def _holds(st, res, tol):
    """Poses of status ``st`` and scaled residual ``res`` that hold though Newton's step test
    failed: a point on a singular position converges only linearly (within HELD times ``tol``),
    and next to one (singularity s) Newton's steps stay at the rounding over s, above the step
    test (within ``tol``)."""
    return ((st == Status.SINGULAR) & (res <= HELD * tol)) | ((st == Status.NEAR_SINGULAR) & (res <= tol))


def _redundant(model, full):
    """(N,) largest scaled residual of the redundant rows in ``full`` (N, m) (0 without any)."""
    red = model.redundant_rows
    if not red.size:
        return np.zeros(full.shape[0])
    return np.max(np.abs(full[:, red] * model.row_scale[red]), axis=1)
