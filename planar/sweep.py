"""Sweeps: continuation along the branch drawn in the sketch, batched where it can be.

1. Anchors: a predictor-corrector walk from the assembled sketch through the input values in
   order, in steps no longer than ``max_step`` (scaled input units). Anchors are tried in
   batched waves (each solved from the Taylor predictor at the wave's start, then checked as
   one walk step from the anchor before it; one that stops part way is followed by a new wave
   from its last anchor); where a wave accepts none, the walk goes step by step, halving a
   step whose solution changes assembly mode (the sign of a block det) or lands far from its
   predictor. Where that fails a singular position lies ahead:
   :func:`planar.events.cross` follows the branch by arclength, locates it and says what it is
   (a limit stops the branch; at a bifurcation the sweep goes on along the smooth branch, or
   the other one if asked).
2. Every other value is solved in batch from the anchors of its own stretch (no event in
   between): by quintic Hermite interpolation between two anchors in the kinematic
   coefficients ``q_u``, ``q_uu`` (the velocity and acceleration solutions at unit input rate),
   or the Taylor predictor ``q + q_u du + 1/2 q_uu du^2`` from the nearer one, and passes the
   same acceptance test; failures are walked to one by one. A finer level of anchors
   (``FINER`` per interval) comes first, so that for the rest the interpolation is at rounding
   level and one evaluation and one factorisation give the pose, its certificate and its rates.
3. Velocities and accelerations by forward substitution through the blocks with the final
   Jacobian. Points on a limit position keep their positions (status LIMIT, rates NaN); points
   on a bifurcation get their values from the smooth branch around them; points that cannot
   be reached get NaN everywhere, their status, the assembly gap and the nearest limit.

Only the blocks the asked-for ``outputs`` need are solved; the other coordinates are NaN.
"""

import bisect
from dataclasses import replace

import numpy as np

from planar.blocks import plan as block_plan
from planar.errors import AssemblyError, InputError
from planar.events import HELD, NEAR, NEAR_CURVE, SINGULAR, Event, around, cross, status_of
from planar.progress import Progress
from planar.results import POSED as POSED_MASK
from planar.results import VALID as VALID_MASK
from planar.results import Status, Sweep
from planar.solver import least_squares_gap, newton, velocity, acceleration

CHUNK = 16384
GAP = 1e-8  # scaled residual above which a least-squares minimum is not an assembly
JUMP = 0.2  # accepted distance from the predictor, as a fraction of the predicted move
HALVINGS = 5  # natural-parameter step halvings before the arclength tracer takes over
EVENT_TOL = 1e-9  # scaled input distance within which a value is on a located event
BRANCH_H = 4e-2  # scaled input radius around a bifurcation where values come from the branch
ROUND = 1e-13  # scaled Newton correction below which a guess is at rounding level
FINER = 4  # finer anchors per walk anchor interval: Hermite error down ~4^6
HEAP_KEEP = (32 << 20) - (8 << 10)  # bytes: see _keep_freed_memory
TURN = 2 * np.pi  # scaled input reach of the search for a limit behind a jump
CERT = 0.1  # accepted correction, as a fraction of the singularity measure at the solution
SPARSE = 4  # anchors further apart than SPARSE * max_step are walked to, not tried in a wave
# tracings round a circuit one sweep may make to re-enter its branch: next to a limit's far
# side the first tries may fail where a value further on enters
ROUNDS = 5
WAVE, MAX_WAVE = 16, 256  # anchors tried in one batch: first, and at most (doubled while all pass)
PERIODS = 12  # whole turns of an angle input within which the pose is looked for returning to itself
SAME = 1e-8  # scaled distance within which a pose after a period is the pose it started from
FAR = 100.0  # radians of input from the sketch beyond which a full-turn input is solved periods back
WALK_STEPS = 20000  # steps of one walk without a period to shorten it: farther targets are not reached


def certified(off, sing):
    """A solve that moved its guess by ``off`` (scaled) to a pose of singularity measure
    ``sing`` stayed on the guess's branch: the move is at rounding level or no more than CERT
    times the distance to the nearest other solution, which ``sing`` estimates (scalars or
    arrays; the compiled engine's loop calls it too).

    >>> bool(certified(1e-3, 0.3)), bool(certified(1e-3, 3e-3)), bool(certified(1e-14, 0.0))
    (True, False, True)
    """
    return (off <= CERT * sing) | (off <= ROUND)


def on_course(off, move):
    """A solve that moved its guess by ``off`` (scaled) from a prediction that moved the pose by
    ``move`` stayed near that prediction: within 1e-9, or JUMP times the predicted move
    (scalars or arrays; the compiled engine's loop calls it too).

    >>> bool(on_course(0.01, 0.1)), bool(on_course(0.05, 0.1))
    (True, False)
    """
    return (off <= 1e-9) | (off <= JUMP * move + 1e-9)


def input_scale(model):
    return np.where(model.input_lengths, 1.0 / model.L, 1.0)


def _scaled_norm(model, du):
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

    def solve(self, q_pred, u, max_iter=8):
        return newton(self.m, q_pred, u, tol=self.tol, max_iter=max_iter, plan=self.p, engine=self.compiled)

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


class Walker:
    """Sequential continuation of one pose (batch of one), with events."""

    def __init__(self, br, max_step, other, rounds=ROUNDS):
        self.br, self.max_step, self.other = br, max_step, other
        self.events = []
        self.rounds = rounds  # tracings round a circuit left to this sweep (each costs ~100s of solves)
        self._symmetry = self._period = None  # (P, D) or False, found when first asked
        self.turns = False  # the walk went round a whole period (no limit): the input turns fully

    def symmetry(self):
        """(P, D): the input period P (whole turns of one angle input) and the pose shift D over
        it (whole turns of the angles of the bodies that turn with the input, 0 elsewhere) where
        the sketch shifted by D solves the constraints at its input plus P in the same assembly
        modes: the revolute and slider rows of a pure linkage read angles through their sines
        and cosines, while a gear or a slider's relative angle passes the input on linearly
        (a gear pair of ratio 7/6 comes back after 7 turns). None where no pose within PERIODS
        turns is the sketch's shifted by whole turns (a gear train of ratio pi)."""
        if self._symmetry is None:
            self._symmetry = _symmetry(self.br) or False
        return self._symmetry or None

    def period(self):
        """(P, D) of :meth:`symmetry`, checked on the branch: the walk from the sketch through
        one period comes back to the sketch up to whole turns D of its angles (a full-turn
        crank: its coupler and rocker may turn too), or meets a limit (a rocking input: values
        a period apart are the same pose, reached by re-entry). None otherwise (a circuit that
        closes after more turns than the symmetry's period)."""
        if self._period is None:
            self._period = False
            sym = self.symmetry()
            if sym is not None:
                m = self.br.m
                P, D = sym
                k, rounds = len(self.events), self.rounds
                s0 = self.br.signs(m.q0[None], m.u0[None])[0]
                got = self.walk(m.q0, m.u0, s0, m.u0 + P, 0)
                del self.events[k:]  # that turn is no part of the sweep
                self.rounds = rounds
                if got[0] == "limit":
                    self._period = sym
                elif got[0] == "ok" and np.all(got[2] == s0):
                    D = _turns(self.br, got[1] - m.q0)
                    self._period = False if D is None else (P, D)
                    self.turns = D is not None
        return self._period or None

    def _shorten(self, q, u, signs, k):
        """(q, u) moved by k whole periods of the input (:meth:`period`): the pose there is
        the pose at u shifted by whole turns. None where it does not solve there."""
        P, D = self.period()
        uk = u + k * P
        qk, conv, _, _ = self.br.solve((q + k * D)[None], uk[None])
        if conv[0] and np.all(self.br.signs(qk, uk[None])[0] == signs):
            return qk[0], uk
        return None

    def walk(self, q, u, signs, target, index, periodic=False):
        """Follow the branch from (q, u) to ``target``. With ``periodic``, where the pose is
        periodic in the input (:meth:`period`), the whole periods between them are one move
        and the walk goes on less than a period the same way, so a far target costs what a
        near one does; for a rocking input that meets a limit that way, the other way round
        (a period less or more). Returns ("ok", q, signs), ("limit", event, (q_before, u_before)) or ("lost",)
        (also for a target more than WALK_STEPS steps away with no period to shorten the way:
        the work is bounded and the value left unreached)."""
        if periodic and u.size == 1:
            d = float(target[0] - u[0])
            per = self.period() if abs(d) >= 2 * np.pi else None
            k = np.trunc(d / per[0]) if per is not None else 0.0
            start = self._shorten(q, u, signs, k) if k else (q, u)
            if start is not None:
                n = len(self.events)
                got = self.walk(*start, signs, target, index)
                # (a value within half a turn, no whole period away, goes the direct way only)
                per = self.period() if got[0] == "limit" and (k or abs(d) > np.pi) else None
                # the other way round when the value was far (whole periods away: either way is
                # as good) or the other way is the shorter (P / 2 >= pi): a rocking input's value in the next
                # period's range, but not a value in the gap just past the limit met
                rest = 0.0 if per is None or self.turns else d - k * per[0]
                rest = rest if k or abs(rest) > np.pi else 0.0
                other = self._shorten(q, u, signs, k + np.sign(rest)) if rest else None
                if other is None:
                    return got
                kept = self.events[n:]
                del self.events[n:]
                again = self.walk(*other, signs, target, index)
                # the other way round keeps the assembly modes: through a change point it comes
                # back in other modes, where the walk the direct way would re-enter in these
                if again[0] == "limit" or (again[0] == "ok" and not np.all(again[2] == signs)):
                    self.events[n:] = kept
                    return got
                return again
        br, m = self.br, self.br.m
        total = float(_scaled_norm(m, target - u))
        if total <= 1e-14:  # the target is this pose up to rounding (the final Newton polishes it)
            return "ok", q, signs
        if total > WALK_STEPS * self.max_step:
            return ("lost",)
        h = min(1.0, self.max_step / total)
        t = 0.0
        u0 = u
        halvings = 0
        wave = WAVE
        while t < 1.0:
            if halvings == 0 and 1.0 - t > h:
                # the full steps ahead in one batch, as the anchors are: the walk's own steps
                # while each is accepted (a batch costs about one step); the rest one by one
                ts = np.minimum(t + h * np.arange(1, wave + 1), 1.0)
                ts = ts[: int(np.searchsorted(ts, 1.0)) + 1]
                a, qa, _ = _wave(self.br, (q, u, signs), u0 + ts[:, None] * (target - u0), np.arange(ts.size))
                if a:
                    q, u, t = qa[-1], u0 + ts[a - 1] * (target - u0), ts[a - 1]
                wave = min(2 * wave, MAX_WAVE) if a == ts.size else max(a, WAVE)
                if a:
                    continue
            dt = min(h, 1.0 - t)
            u_next = u0 + (t + dt) * (target - u0)
            q_pred, _ = br.predict(q[None], u[None], (u_next - u)[None])
            qn, conv, _, _ = br.solve(q_pred, u_next[None])
            sn, sg = br.modes(qn, u_next[None])
            if br.accept(qn, q_pred, lambda k: q[None], conv, sn, signs[None], sg)[0]:
                q, u, t = qn[0], u_next, t + dt
                h = min(2 * h, self.max_step / total)
                halvings = 0
                continue
            flipped = bool(conv[0]) and not np.all(sn[0] == signs)
            halvings += 1
            h /= 2
            # a sign flip, repeated failures, or steps shrinking towards a turning point
            if flipped or halvings > HALVINGS or h * total < self.max_step / 2**HALVINGS:
                return self._cross(q, u, signs, target, index)
        return "ok", q, signs

    def _cross(self, q, u, signs, target, index):
        br, m = self.br, self.br.m
        got = cross(m, br.p, q, u, target, self.max_step, other=self.other, index=index)
        self.events.extend(got.events)
        if got.limit is not None:
            ev = got.limit
            if _scaled_norm(m, np.atleast_1d(ev.input) - target) <= 1e-10:
                # the value is the limit position itself
                self.events.append(ev)
                return "ok", ev.q, signs
            return "limit", ev, got.before
        if got.q is None:
            return ("lost",)
        qn, conv, _, _ = br.solve(got.q[None], target[None], max_iter=30)
        if not conv[0]:
            return ("lost",)
        return "ok", qn[0], br.signs(qn, target[None])[0]

    def enter_any(self, guesses, signs, targets, tries=4):
        """(index, pose) of the first of ``targets`` (M, f) where the branch can be entered:
        a batched least-squares search from each guess, then Newton, the mode test and, on
        another mode, the way round through a limit. None if none found."""
        br = self.br
        best = None
        # the first few targets and a few spread over the rest: a least-squares search of each
        # of hundreds of values would cost more than the walk
        pick = np.unique(np.r_[np.arange(min(len(targets), 4 * tries)),
                               np.linspace(0, len(targets) - 1, 2 * tries).astype(int)])
        for g in guesses:
            ql, gap = least_squares_gap(br.m, np.repeat(g[None], pick.size, 0), targets[pick])
            near = np.flatnonzero(gap <= GAP)
            # the first few, and a few spread over the rest: next to a limit's far side Newton
            # may find only the other mode, where a value further on enters the branch
            for c in np.unique(np.r_[near[:tries], near[np.linspace(0, near.size - 1, tries).astype(int)]]
                               if near.size else near):
                if best is not None and pick[c] >= best[0]:
                    break
                qe = self.enter([ql[c]], signs, targets[pick[c]])
                if qe is not None:
                    best = (int(pick[c]), qe)
                    break
        return best

    def enter_by_period(self, qs, us, signs, targets, tries=8):
        """(index, pose, modes) of the first of ``targets`` (M, 1) within a step of a pose solved
        on the branch (``qs``, ``us``, ``signs``) moved by whole periods of the input
        (:meth:`period`): the same pose shifted by whole turns, walked to from there. Exact where
        the search of :meth:`enter_any` finds only another circuit (values past a limit pair that
        are a turn on from the stretch already solved). None if none."""
        if targets.shape[1] != 1 or not len(us) or self.period() is None:
            return None
        P, _ = self.period()
        t = targets[:4096, 0]
        n = np.round((t[:, None] - us[None, :, 0]) / P)
        off = np.where(n != 0, np.abs(t[:, None] - us[None, :, 0] - n * P), np.inf)
        j = np.argmin(off, axis=1)
        for c in np.flatnonzero(off[np.arange(t.size), j] <= self.max_step)[:tries]:
            k = int(j[c])
            image = self._shorten(qs[k], us[k], signs[k], n[c, k])
            if image is None:
                continue
            got = self.walk(*image, signs[k], targets[c], int(c))
            if got[0] == "ok":
                return int(c), got[1], got[2]
        return None

    def near_turns(self, q, u, signs, ref):
        """The re-entered pose q (at u) with its angles moved by whole turns to lie within half
        a turn of those of ``ref`` (the pose before the gap), where it still solves there in the
        same modes: the same positions, its angles counted as the branch counted them before the
        gap, whichever search found it. q itself otherwise."""
        p = self.br.p
        with np.errstate(all="ignore"):
            _, J = p.system.evaluate(q[None], u[None])
        rows = np.concatenate([np.atleast_1d(p.rows[d]) for d in p.drivers]) if p.drivers.size else []
        free = ~np.any(np.atleast_2d(J[0][rows]) != 0, axis=0)  # the drivers' own angles stay
        cols = p.cols[free[p.cols]]
        d = (ref - q)[cols]
        shift = np.zeros_like(q)
        shift[cols] = np.where(cols % 3 == 2, 2 * np.pi * np.round(d / (2 * np.pi)), 0.0)
        if not shift.any():
            return q
        qn, conv, _, _ = self.br.solve((q + shift)[None], u[None])
        if conv[0] and np.all(self.br.signs(qn, u[None])[0] == signs) and _turns(self.br, qn[0] - q) is not None:
            return qn[0]
        return q

    def enter(self, guesses, signs, target):
        """Re-enter the motion range at ``target`` from guesses of the same branch."""
        br = self.br
        for g in guesses:
            qn, conv, _, _ = newton(br.m, g[None], target[None], tol=br.tol, max_iter=40, max_step=0.3, plan=br.p)
            if not conv[0]:
                # far from the guess: least squares first, Newton from its minimum
                ql, gap = least_squares_gap(br.m, g[None], target[None])
                if gap[0] > GAP:
                    continue
                qn, conv, _, _ = newton(br.m, ql, target[None], tol=br.tol, max_iter=40, plan=br.p)
                if not conv[0]:
                    continue
            if np.all(br.signs(qn, target[None])[0] == signs):
                return qn[0]
            if target.size == 1 and self.rounds > 0:
                # another mode of the same circuit: go round through a limit to ours
                self.rounds -= 1
                got = around(br.m, br.p, qn[0], target, signs, self.max_step, np.pi)
                if got is not None:
                    return got
        return None


# 2 pi = _A1 + _A2 + _B: _A1 with 27 significant bits (n _A1 is exact for |n| < 2^26 turns),
# _B the rounding of 2 pi to a double, so that whole turns are added to angles of 1e6 rad
# without the 1e-10 rad that n times the rounded 2 pi would carry
_A1 = np.round(2 * np.pi * 2.0**24) / 2.0**24
_A2 = 2 * np.pi - _A1
_B = 2.4492935982947064e-16


def _add_turns(x, n):
    """x + 2 pi n (n whole turns) to the rounding of the result, for x small next to 2 pi n.

    >>> x = -0.357564167085735  # 1e6 less 159155 turns (the naive 1e6 - 159155 * 2 * np.pi is 8e-11 off)
    >>> float(x + 159155 * 2 * np.pi), float(_add_turns(x, 159155.0))
    (999999.9999999999, 1000000.0)
    """
    if np.all(n == 0):
        return x
    return ((x + n * _B) + n * _A2) + n * _A1


def _symmetry(br):
    """See :meth:`Walker.symmetry`: from the sketch, the driven angle moved by k turns and a
    Newton solve at the input plus k turns, for k = 1 .. PERIODS."""
    m, p = br.m, br.p
    if m.input_lengths.size != 1 or m.input_lengths[0] or p.drivers.size != 1:
        return None
    q0, u0 = m.q0, m.u0
    s0 = br.signs(q0[None], u0[None])[0]
    with np.errstate(all="ignore"):
        _, J = p.system.evaluate(q0[None], u0[None])
    row = J[0][p.rows[p.drivers[0]]]
    col = p.cols[np.argmax(np.abs(row[p.cols]))]  # the driven angle
    for k in range(1, PERIODS + 1):
        P = 2 * np.pi * k
        g = q0.copy()
        with np.errstate(all="ignore"):
            Phi, _ = p.system.evaluate(q0[None], (u0 + P)[None])
        g[col] -= Phi[0, p.rows[p.drivers[0]]] / row[col]
        qn, conv, _, _ = br.solve(g[None], (u0 + P)[None], max_iter=30)
        if not conv[0]:
            continue
        D = _turns(br, qn[0] - q0)
        if D is not None and np.all(br.signs(qn, (u0 + P)[None])[0] == s0):
            return P, D
    return None


def _turns(br, d):
    """The change d (n,) of a pose rounded to whole turns of its angles, None where it is not
    whole turns (to SAME, scaled) or moves a position."""
    m, cols = br.m, br.p.cols
    dc = d[cols]
    turns = np.where(cols % 3 == 2, np.round(dc / (2 * np.pi)), 0.0)
    if not np.max(np.abs(dc - 2 * np.pi * turns) / m.col_scale[cols]) <= SAME:
        return None
    D = np.zeros(m.n)
    D[cols] = 2 * np.pi * turns
    return D


def sweep_anchors(model, U, max_step):
    """Indices of the values where the sequential walk stops: the first, the last, values no
    further than ``max_step`` apart (:func:`_walk_anchors`, so each is one walk step) and (one
    input) each value where the input turns back, so the walk covers every value."""
    idx, monotone = _walk_anchors(U, input_scale(model), max_step)
    turns = np.zeros(0, int)
    if not monotone and U.shape[1] == 1:
        d = np.sign(np.diff(U[:, 0]))
        nz = np.flatnonzero(d)
        turns = nz[1:][d[nz[1:]] != d[nz[:-1]]]
    return np.unique(np.r_[idx, turns, len(U) - 1]).astype(int)


def _walk_anchors(U, scale, max_step):
    """(indices, monotone): value 0 and values after it, each within ``max_step`` (scaled) of
    the one before where the values allow; ``monotone``: one input that never turns back.

    One monotone input whose values lie closer than max_step / 2: the last value at or before
    each point of a grid of spacing max_step - g (g the largest gap between values), so
    consecutive picks lie less than max_step apart, in a few whole-array passes. Otherwise
    greedily, the last value within max_step of the previous pick.
    """
    if U.shape[1] == 1:
        v = U[:, 0]
        step = max_step / scale[0]
        d = np.diff(v)
        lo, hi = (d.min(), d.max()) if d.size else (0.0, 0.0)
        if lo >= 0 or hi <= 0:
            v, gap = (v, hi) if lo >= 0 else (-v, -lo)
            if gap < step / 2:
                grid = v[0] + (step - gap) * np.arange(1, np.ceil((v[-1] - v[0]) / (step - gap)) + 1)
                return np.unique(np.r_[0, np.searchsorted(v, grid, side="right") - 1]), True
            # (fewer than two values per max_step: a short list, searched with bisect)
            vl, idx, i = v.tolist(), [0], 0
            while True:
                j = bisect.bisect_right(vl, vl[i] + step)
                if j >= len(vl):
                    return np.array(idx), True
                i = max(i + 1, j - 1)
                idx.append(i)
    V = U * scale
    idx, i, span = [0], 0, 64
    while True:
        far = np.flatnonzero(np.max(np.abs(V[i + 1 : i + 1 + span] - V[i]), axis=1) > max_step)
        if far.size:
            i += max(1, int(far[0]))
            idx.append(i)
        elif i + 1 + span >= len(V):
            return np.array(idx), False
        else:
            span *= 2


def output_columns(model, outputs):
    """Coordinates the named bodies, points, joints or inputs depend on."""
    if outputs is None:
        return None
    if isinstance(outputs, str):
        outputs = [outputs]
    cols = set()
    for name in outputs:
        bodies = []
        if name in model.body_names:
            bodies = [model.body_id(name)]
        elif name in model.points:
            bodies = [model.points[name][0]]
        elif name in model.coordinates or name in model.input_names:
            j = next((d for d in model.drivers if d.name == name), None) or model.joint(name)
            bodies = [model.body_id(b) for b in j.bodies]
        else:
            raise InputError(f"unknown output {name!r}: name bodies {list(model.body_names[1:])}, points or "
                             f"joints {sorted(model.points)}")
        for b in bodies:
            if b > 0:
                cols.update(range(3 * b - 3, 3 * b))
    # outputs fixed to the ground depend on no coordinate: the whole model is solved (the
    # statuses still say whether each value assembles)
    return sorted(cols) or None


def run_sweep(model, U, Ud, Udd, start=None, *, tol=1e-12, max_step=0.05, outputs=None, branch="smooth", rates=True,
              engine="numpy"):
    """See :meth:`planar.Model.sweep`. ``start``: a known pose (q, u) of the branch to walk
    from instead of the sketch, reached from the sketch by continuation with no event between
    (:mod:`planar.tracking` picks it); the sweep is then the one from the sketch."""
    if branch not in ("smooth", "other"):
        raise InputError(f"branch must be 'smooth' or 'other', got {branch!r}")
    cols = output_columns(model, outputs)
    p = block_plan(model, cols)
    br = Branch(model, p, tol, bool(rates), engine)
    walker = Walker(br, max_step, branch == "other")
    _keep_freed_memory()
    N, n = U.shape[0], model.n
    q = np.empty((N, n))  # rows not posed at the end are set NaN then
    solved = np.zeros(N, bool)
    signs = np.zeros((N, len(p.blocks)), np.int8)  # the blocks' modes at each solved value
    events = []

    def walk(start, i, lo, back=None, periodic=True):
        """Walk from ``start`` (q, u, signs) to value i; events get the index of the first
        value after ``lo`` at or past them (walking back from value ``back`` > i: the first
        value from i on at or past them in the sweep's own direction)."""
        k = len(walker.events)
        got = walker.walk(*start, U[i], int(i), periodic=periodic)

        def index(u_star):
            if back is None:
                return _event_index(U, lo, i, start[1], u_star)
            return _event_index(U, i - 1, back, U[i], u_star)

        for j in range(k, len(walker.events)):
            ev = walker.events[j]
            if not any(_same(ev, e, model) for e in events):
                events.append(replace(ev, index=index(ev.input)))
        if got[0] == "limit":
            ev = replace(got[1], index=index(got[1].input))
            if not any(_same(ev, e, model) for e in events):
                events.append(ev)
            if back is None:  # (a limit met before too: value i, if re-entered, is past it all the same)
                stops.append(ev.index)
            limits.append((ev, np.sign(U[i] - start[1])))
        return got

    def past(u_from, u_to):
        """A limit the walk met lies between u_from and u_to, periods of the input apart (asked
        only of values more than half a turn apart: nearer ones the walk goes to directly)."""
        far = limits and U.shape[1] == 1 and np.any(np.abs(u_to - u_from) > np.pi)
        return _past_limit(limits, u_from, u_to, walker.period() if far else None)

    # far values of an angle input whose pose is periodic (the same up to whole turns of its
    # angles: an input that turns fully, or a rocking input's range a period on) are solved
    # whole periods back, nearer the sketch, and shifted back at the end: angles of 1e6 rad
    # would carry rounding of 1e-10 rad into the constraints
    U_in, shift = U, None
    if U.shape[1] == 1 and not model.input_lengths[0] and np.max(np.abs(U[:, 0] - model.u0[0])) > FAR:
        per = walker.period()
        if per is not None:
            start = None  # the sketch, whole periods back, is nearer than any known pose
            block = per[0] * np.ceil(FAR / per[0])
            k = np.trunc((U[:, 0] - model.u0[0]) / block) * (block / per[0])
            turns = k * round(per[0] / (2 * np.pi))
            U = (((U[:, 0] - turns * _A1) - turns * _A2) - turns * _B)[:, None]  # (the large terms first)
            shift = (k, per)

    # 1. the sequential walk over anchors, from the assembled sketch
    chosen = br.signs(model.q0[None], model.u0[None])[0]
    if start is None:  # (a known pose was reached from the sketch: it passed)
        check_sketch(model, p)
    origin = (model.q0, model.u0, chosen) if start is None else (start[0], start[1], chosen)
    # values given out of order (one input) are solved in the order of the input, from the end
    # nearer the start, and put back in the asked order at the end: each is walked to from its
    # neighbour in input, where a jumping sweep would walk back and forth across the range and
    # search again for the range past each gap it meets
    order = _input_order(U, origin[1][0])
    if order is not None:
        U, Ud, Udd, U_in = U[order], Ud[order], Udd[order], U_in[order]
        shift = None if shift is None else (shift[0][order], shift[1])
    state = origin
    limits = []  # (limit event, direction of the input that hit it)
    stops = []  # indices of the limits the walk stopped at, moving with the sweep
    anchors = sweep_anchors(model, U, max_step)
    kin = _Kin()  # the anchors' kinematic coefficients where known (one input)
    coef = None  # those of the state, where known
    lo, k, wave = -1, 0, WAVE
    while k < anchors.size:
        idx = anchors[k : k + wave]
        stop = np.flatnonzero(past(state[1][None], U[idx]) | _on_event(model, U[idx], events))
        tried = stop[0] if stop.size else idx.size
        # an anchor several steps from the one before (sparse values) is walked to: a wave
        # would not reach it
        far = np.flatnonzero(_scaled_norm(model, np.diff(U[idx[:tried]], axis=0, prepend=state[1][None]))
                             > SPARSE * max_step)
        tried = far[0] if far.size else tried
        a, qa, ka = _wave(br, state, U, idx[:tried], coef)
        if a:
            q[idx[:a]], solved[idx[:a]], signs[idx[:a]] = qa, True, state[2]
            state, lo, k = (qa[-1], U[idx[a - 1]], state[2]), idx[a - 1], k + a
            if ka is not None:
                kin.add(idx[:a], *ka)
                coef = ka[0][-1], ka[1][-1]
        wave = min(2 * wave, MAX_WAVE) if a == idx.size else max(a, WAVE)
        # a wave that stopped part way goes on as a new wave from its last anchor; the walk
        # takes the anchor where one accepted none (or where an event was located)
        if k >= anchors.size or a == idx.size or 0 < a < tried:
            continue
        coef = None
        i = anchors[k]
        got = ("lost",) if past(state[1][None], U[i][None])[0] else walk(state, i, lo)
        lo = i
        if _at_events(model, U[i : i + 1], events):
            k += 1
            continue  # a value on a singular position is no pose to go on from
        if got[0] == "ok":
            q[i], solved[i], signs[i] = got[1], True, got[2]
            state = (got[1], U[i], got[2])
            k += 1
            continue
        if got[0] == "limit":
            state = (got[2][0], got[2][1], state[2])
        # out of reach: the next anchor that assembles on the branch, a whole period on from a
        # value solved, else by one batched search
        known = np.flatnonzero(solved)
        found = walker.enter_by_period(q[known], U[known], signs[known], U[anchors[k:]])
        upto = anchors.size if found is None else k + found[0]
        nearer = walker.enter_any([state[0], model.q0], chosen, U[anchors[k:upto]]) if upto > k else None
        if nearer is not None:
            found = (*nearer, chosen)
        if found is None:
            break
        c, qe, se = found
        k += c
        i = anchors[k]
        qe = walker.near_turns(qe, U[i], se, state[0])
        q[i], solved[i], signs[i] = qe, True, se
        state, lo = (qe, U[i], se), i
        k += 1

    # 2. every other value from an anchor of its own stretch (no event in between): first a
    # finer set of anchors, so that the interpolation is at rounding level for the rest
    at_event = _at_events(model, U, events)
    solved[list(at_event)] = False
    out = _Out(N, n, br.rates)
    q_pred = {}  # index -> the best guess of a value left for the walk
    done = np.zeros(N, bool)
    todo = ~solved  # all but the solved anchors and the values on events
    todo[list(at_event)] = False
    cuts = np.array(sorted({e.index for e in events if e.kind in ("limit", "bifurcation", "singular")}), int)
    fill = dict(br=br, U=U, Ud=Ud, Udd=Udd, q=q, signs=signs, solved=solved, done=done, out=out, q_pred=q_pred,
                cuts=cuts, kin=kin)
    if U.shape[1] == 1:
        finer, _ = _walk_anchors(U, input_scale(model), max_step / FINER)
        finer = finer[todo[finer]]
        # their poses and modes only (the table needs no more): their rates and statuses come
        # with the bulk pass, which takes them again, or with the final step at the end
        _from_anchors(anchors=anchors, targets=finer, **dict(fill, br=Branch(model, p, tol, False, engine)))
        finer = finer[solved[finer]]
        done[finer] = False
        anchors = np.union1d(anchors, finer)
        todo[finer] = False
    # the anchors too: their final step is due anyway, and the bulk's chunks become runs of
    # consecutive values (slices where the results are written, not scatters)
    _from_anchors(anchors=anchors, targets=np.flatnonzero(todo | solved), **fill)

    # 3. the rest one by one, from the solved point before each; values on an event or past a
    # limit from there are set aside in one pass (out of range, there may be many)
    rest = np.flatnonzero(~solved)
    if rest.size:  # (the last solved value before each: N-sized, so only when needed)
        last = np.maximum.accumulate(np.where(solved, np.arange(N), -1))
        u_from = _input_before(origin[1], U, last, rest)
        rest = rest[~_on_event(model, U[rest], events) & ~past(u_from, U[rest])]
    failed, newest = (None, None), -1
    for i in rest:
        if _at_events(model, U[i : i + 1], events):
            continue
        j = max(int(last[i - 1]) if i else -1, newest)
        j = None if j < 0 else j
        start = origin if j is None else (q[j], U[j], signs[j])
        if _further(failed, j, start[1], U[i]) or past(start[1][None], U[i][None])[0]:
            continue  # the walk from this pose failed nearer that way already, or a limit lies between
        got = walk(start, i, -1 if j is None else j)
        if got[0] != "ok":
            failed = (j, U[i])
            continue
        q[i], solved[i], signs[i], newest = got[1], True, got[2], i
    # values still unreached past a gap in the range (re-entered further on): walked back from
    # the solved value after them, so the branch is re-entered as far back as it reaches and
    # the limit on the gap's far side is located
    rest = np.flatnonzero(~solved)
    if rest.size:
        nxt = np.minimum.accumulate(np.where(solved, np.arange(N), N)[::-1])[::-1]
    failed, newest = (None, None), N
    for i in rest[::-1]:
        j = min(int(nxt[i + 1]) if i + 1 < N else N, newest)
        if j >= N or _at_events(model, U[i : i + 1], events):
            continue
        if _further(failed, j, U[j], U[i]) or past(U[j][None], U[i][None])[0]:
            continue
        got = walk((q[j], U[j], signs[j]), i, -1, back=j)
        if got[0] != "ok":
            failed = (j, U[i])
            continue
        q[i], solved[i], signs[i], newest = got[1], True, got[2], i
    # a limit with no value between it and the re-entered branch (a pair of limits inside one
    # step): the limit on the gap's far side, located walking back from the value past it, up
    # to a turn of the input
    at_event = _at_events(model, U, events)
    for j in list(stops):
        if 0 < j < N and solved[j] and solved[j - 1] and j not in at_event and U.shape[1] == 1:
            reach = np.flatnonzero(_scaled_norm(model, U[:j] - U[j]) <= TURN)
            # (the direct way: only the limit it meets is wanted)
            walk((q[j], U[j], signs[j]), int(reach[0] if reach.size else j - 1), -1, back=j, periodic=False)
    at_event = _at_events(model, U, events)
    for i, ev in at_event.items():
        q[i], solved[i], done[i] = ev.q, True, True
    events.sort(key=lambda e: e.index)
    # values left unsolved past a limit the walk met (from the solved value before them) are
    # out of the branch's reach, however small their least-squares gap
    beyond = np.zeros(N, bool)
    miss = np.flatnonzero(~solved)
    if miss.size and limits:
        last = np.maximum.accumulate(np.where(solved, np.arange(N), -1))
        beyond[miss] = past(_input_before(origin[1], U, last, miss), U[miss])
    jumps = (stops, None)
    if order is not None:
        # values asked one after the other with a limit the walk met between them (the direct
        # way): a jump
        inv = np.empty_like(order)
        inv[order] = np.arange(N)
        prev = np.where(order > 0, inv[np.maximum(order - 1, 0)], -1)  # the value asked before each
        cand = np.flatnonzero(prev >= 0)
        if limits and cand.size:
            cand = cand[_past_limit(limits, U[prev[cand]], U[cand])]
        jumps = (cand if limits else [], prev)
    return _finish(model, br, U, Ud, Udd, q, solved, done, out, q_pred, events, at_event, beyond, jumps, U_in, shift,
                   order, origin[1])


def _input_order(U, u0):
    """The order in which to solve the values U (N, 1) of one input given out of order (turning
    back at least once): sorted, ascending or descending from the end nearer the start's
    input ``u0`` (stable: repeated values keep their order). None for values in order.

    >>> _input_order(np.array([[0.0], [2.0], [1.0]]), 0.0).tolist(), _input_order(np.array([[0.0], [2.0], [1.0]]), 3.0).tolist()
    ([0, 2, 1], [1, 2, 0])
    """
    if U.shape[1] != 1 or U.shape[0] < 3:
        return None
    v = U[:, 0]
    d = np.diff(v)
    if np.all(d >= 0) or np.all(d <= 0):
        return None
    down = v.max() - u0 < u0 - v.min()
    return np.argsort(-v if down else v, kind="stable")


def _asked_order(model, U, order, events, u0):
    """The events of values solved in the order of the input (``U``, one input, in that order;
    ``order`` their asked positions), indexed in the asked order: the first value asked at or
    past each singular position seen from the start's input ``u0`` (a near-singular stretch:
    its closest value)."""
    N, tol = len(U), EVENT_TOL / float(input_scale(model)[0])
    out = []
    for e in events:
        i = int(order[min(e.index, N - 1)])
        d = np.sign(float(e.input) - float(u0[0]))
        if e.kind != "near_singular" and d != 0:
            at = np.flatnonzero((U[:, 0] - float(e.input)) * d >= -tol)
            i = int(order[at].min()) if at.size else i
        out.append(replace(e, index=i))
    return sorted(out, key=lambda e: e.index)


def _further(failed, j, u_j, u):
    """The walk from value j to ``u`` goes the way a walk from j failed (``failed``: (j, its
    target)) and at least as far: not tried (values out of order on the near side are)."""
    if failed[0] != j or failed[1] is None:
        return False
    d, f = u - u_j, failed[1] - u_j
    return bool(np.all(d * f >= 0) and np.max(np.abs(d)) >= np.max(np.abs(f)))


def _input_before(u0, U, last, idx):
    """(M, f) the input of the last solved value before each of ``idx`` (``last``: the index
    of the last solved value at or before each value, -1 for none), the start's ``u0`` where none."""
    prev = np.where(idx > 0, last[np.maximum(idx - 1, 0)], -1)
    return np.where((prev >= 0)[:, None], U[np.maximum(prev, 0)], u0)


def _mark_jumps(status, stops, prev=None):
    """JUMPED for the first value past each limit the walk stopped at (``stops``: the events'
    indices) where it is valid and the value before it posed: the branch was re-entered past the
    limit with no unassemblable value between to show the gap (a pair of limits inside one step).
    With ``prev`` (values solved out of the asked order: the index of the value asked before
    each, -1 for none), ``stops`` are the values with a limit between them and that value."""
    posed, valid = POSED_MASK[status], VALID_MASK[status]
    for j in stops:
        if prev is not None:
            if valid[j] and posed[prev[j]]:
                status[j] = Status.JUMPED
            continue
        j += int(j < status.size and status[j] == Status.LIMIT)
        if 0 < j < status.size and valid[j] and posed[j - 1]:
            status[j] = Status.JUMPED


def check_sketch(model, p):
    """A sketch drawn on a singular position leaves the branch to follow undefined (a
    parallelogram drawn flat moves on as a parallelogram or as an antiparallelogram): refused,
    naming the bodies whose loop is singular there."""
    with np.errstate(all="ignore"):
        dets = p.factor(p.evaluate(model.q0[None], model.u0[None])[2]).dets[0]
    bad = np.flatnonzero(~(np.abs(dets) >= SINGULAR))
    if bad.size:
        blk = p.blocks[int(bad[0])]
        bodies = sorted({model.body_names[int(c) // 3 + 1] for c in blk.cols}, key=model.body_names.index)
        raise AssemblyError(
            f"the sketch of {model.name!r} sits on a singular position (bodies {', '.join(bodies)}: normalised det "
            f"{abs(dets[bad[0]]):.1e}), where more than one branch passes and none is the one drawn; sketch it "
            f"off the singular position (for a catalogue mechanism, another start value) and sweep through it: "
            f"the sweep locates the singular position and follows the smooth branch (or branch='other')")


def _keep_freed_memory():
    """Free one untouched block of HEAP_KEEP bytes, so that glibc's malloc keeps what a sweep
    frees for its next chunk and its next call instead of handing it back to the system: its
    mmap threshold follows the largest mmapped block freed, up to 32 MiB and only for blocks no
    larger than that (hence 8 KiB under it: malloc's header and page rounding), and it trims
    the heap's free top beyond twice that (64 MiB), above a numpy sweep's heap at N = 1e5.
    Below it, each chunk and each call faulted its memory in afresh. The process may keep up
    to 2 HEAP_KEEP of freed memory; with other allocators this costs one mmap and munmap."""
    np.empty(HEAP_KEEP, np.uint8)


def _from_anchors(br, U, Ud, Udd, q, signs, solved, done, out, q_pred, cuts, kin, anchors, targets):
    """Solve ``targets`` in batch from the solved anchors of their own stretch (no event in
    between): one input interpolates between two consecutive anchors (quintic Hermite in the
    kinematic coefficients), or extrapolates from the nearer one (second-order Taylor); the
    result passes the walk's acceptance test or is left for the sequential walk."""
    n = q.shape[1]
    one = U.shape[1] == 1
    good = anchors[solved[anchors]]
    rest = targets
    if one and good.size:  # kinematic coefficients at the anchors; singular ones are no source
        QU, QUU, sg = kin.at(br, q, U, good)
        regular = sg >= NEAR
        good, QU, QUU = good[regular], QU[regular], QUU[regular]
    if not (good.size and rest.size):
        return
    # consecutive anchors of one stretch (no failed or singular anchor, no located event between,
    # some input between): the values between them interpolate rather than extrapolate
    seg_of = np.searchsorted(cuts, good, side="right")
    adj = np.zeros(good.size, bool)
    if one:
        adj[:-1] = (np.diff(np.searchsorted(anchors, good)) == 1) & (np.diff(U[good, 0]) != 0) & (np.diff(seg_of) == 0)
    P = _quintic(q[good], QU, QUU, np.diff(U[good, 0])) if one else None
    if br.compiled is not None and adj.any():
        # the interpolated values in one compiled pass, in place; the rest as below
        qd, qdd = (out.qd, out.qdd) if out.rates else (np.empty((0, n)), np.empty((0, n)))
        arrays = dict(q=q, U=U, Ud=Ud, Udd=Udd, qd=qd, qdd=qdd, res=out.residual, signs=signs,
                      sing=out.sing, branch=out.branch, status=out.status, iters=out.iters, solved=solved, done=done)
        ok = br.compiled.fill(br.m, br.p, rest, adj, good, P, signs[good], br.tol, br.rates, arrays)
        rest = rest[~ok & ~solved[rest]]  # (a solved anchor it left gets its final step at the end)
    # each target's anchors before and after (positions in good), and whether each lies in the
    # target's stretch
    pos = np.searchsorted(good, rest) - 1
    prev_k, next_k = np.maximum(pos, 0), np.minimum(pos + 1, good.size - 1)
    same_prev, same_next = pos >= 0, pos + 1 < good.size
    if cuts.size:
        seg = np.searchsorted(cuts, rest, side="right")
        same_prev &= seg_of[prev_k] == seg
        same_next &= seg_of[next_k] == seg
    where = np.where(same_prev, prev_k, next_k)  # the source anchor
    has = same_prev | same_next
    both = same_prev & same_next & adj[prev_k]
    rest, where, both = rest[has], where[has], both[has]
    src = good[where]
    if one and len(P) and rest.size:
        # columns no polynomial moves (pinned coordinates) keep the anchors' common value
        moving = np.any(P[:, 1:] != 0, axis=(0, 1))
        fixed = P[0, 0, ~moving]
        PL = np.ascontiguousarray(P[:, :, moving].transpose(1, 2, 0))  # :func:`_horner`'s table
    progress = Progress("sweep: values")  # (on a terminal, for a bulk over 2 s)
    for a in range(0, rest.size, CHUNK):
        i, s_ = rest[a : a + CHUNK], src[a : a + CHUNK]
        at = slice(i[0], i[-1] + 1) if i[-1] - i[0] + 1 == i.size else i  # i, as a slice when it is a run
        # (np.take gathers rows of a few values ~4x faster than indexing does)
        du = U[at] - np.take(U, s_, axis=0)
        if one:
            k, b = where[a : a + CHUNK], both[a : a + CHUNK]
            qp = np.empty((i.size, n))
            if b.any():
                kb = k[b]
                h = U[good[kb + 1], 0] - U[good[kb], 0]
                qp[:, ~moving] = fixed
                qp[slice(None) if b.all() else np.flatnonzero(b)[:, None], moving] = _horner(PL, kb, du[b, 0] / h)
            if not b.all():
                k, s1, d1 = k[~b], s_[~b], du[~b]
                qp[~b] = q[s1] + QU[k] * d1 + 0.5 * QUU[k] * d1**2
        else:
            qp, _ = br.predict(q[s_], U[s_], du)
        r = final_step(br, qp, U[at], Ud[at], Udd[at])
        ok = br.accept(r["q"], qp, lambda k: q[s_[k]], r["conv"], r["signs"], np.take(signs, s_, axis=0), r["sing"],
                       r["off"])
        if ok.all():
            ok, put = slice(None), at
        else:
            q_pred.update(zip(i[~ok].tolist(), qp[~ok]))
            put = i[ok]
        out.put(put, r, ok)
        q[put], solved[put], signs[put], done[put] = r["q"][ok], True, r["signs"][ok], True
        progress(min(a + CHUNK, rest.size), rest.size)


def _wave(br, state, U, idx, coef=None):
    """Anchors ``idx`` solved in one batch from ``state`` (q, u, signs), each from the Taylor
    predictor at the state, then checked as the sequential walk checks a step: against the
    predictor from the anchor before it, with the same modes. Returns (a, poses, kin) for the
    accepted prefix idx[:a]: a batch of M costs about one sequential step. One input: ``coef``
    are the state's kinematic coefficients (q_u, q_uu) when known, and ``kin`` (q_u, q_uu,
    singularity) those of the accepted anchors (the next wave's and the bulk's); else None."""
    if idx.size == 0:
        return 0, None, None
    q0, u0, s0 = state
    M, f = idx.size, U.shape[1]
    Ut = U[idx]
    with np.errstate(all="ignore"):  # a singular state reads non-finite rates: rejected below
        if f == 1:
            qu, quu = br.state(q0[None], u0[None], np.ones((1, 1)))[:2] if coef is None else coef
            du = Ut - u0
            q_pred = q0 + qu * du + 0.5 * quu * du**2
            qn, conv, _, _ = br.solve(q_pred, Ut)
            # one factorisation at the solutions gives their modes and kinematic coefficients:
            # the walk's predictor from each to the next
            QU, QUU, sn, sg = br.state(qn, Ut, np.ones((M, 1)))
            h = Ut[1:] - Ut[:-1]
            q_step = np.vstack((q_pred[:1], qn[:-1] + QU[:-1] * h + 0.5 * QUU[:-1] * h**2))
        else:
            q_pred, _ = br.predict(np.repeat(q0[None], M, 0), np.repeat(u0[None], M, 0), Ut - u0)
            qn, conv, _, _ = br.solve(q_pred, Ut)
            qd, qdd, sn, sg = br.state(qn, Ut, np.vstack((Ut[1:] - Ut[:-1], np.zeros((1, f)))))
            q_step = np.vstack((q_pred[:1], (qn + qd + 0.5 * qdd)[:-1]))
    q_from = np.vstack((q0[None], qn[:-1]))
    ok = br.accept(qn, q_step, lambda k: q_from[k], conv, sn, s0[None], sg)
    a = M if ok.all() else int(np.argmin(ok))
    return a, qn[:a], ((QU[:a], QUU[:a], sg[:a]) if f == 1 else None)


class _Kin:
    """The kinematic coefficients q_u, q_uu (and the singularity measure) of solved anchors of
    a one-input sweep, kept where they were computed (the waves' acceptance tests, the finer
    pass) so that each anchor's are computed once."""

    def __init__(self):
        self.idx, self.parts = [], []

    def add(self, idx, QU, QUU, sg):
        self.idx.append(idx)
        self.parts.append((QU, QUU, sg))

    def at(self, br, q, U, good):
        """(QU, QUU, sg) at the anchors ``good`` (sorted): kept, or computed now (and kept)."""
        n = q.shape[1]
        QU, QUU, sg = np.empty((good.size, n)), np.empty((good.size, n)), np.empty(good.size)
        have = np.zeros(good.size, bool)
        if self.idx:
            idx = np.concatenate(self.idx)
            pos = np.minimum(np.searchsorted(good, idx), good.size - 1)
            hit = good[pos] == idx
            for out, part in zip((QU, QUU, sg), zip(*self.parts)):
                out[pos[hit]] = np.concatenate(part)[hit]
            have[pos[hit]] = True
        miss = np.flatnonzero(~have)
        for a in range(0, miss.size, CHUNK):
            m = miss[a : a + CHUNK]
            QU[m], QUU[m], _, sg[m] = br.state(q[good[m]], U[good[m]], np.ones((m.size, 1)))
        if miss.size:
            self.add(good[miss], QU[miss], QUU[miss], sg[miss])
        return QU, QUU, sg


def _quintic(Q, D, DD, h):
    """Coefficients (K - 1, 6, n) of t^0 .. t^5 of the quintic Hermite interpolants between
    consecutive poses Q (K, n), with their first and second derivatives D and DD in the input
    and h (K - 1,) the input steps (t = (u - u_k) / h in [0, 1]): its error is O(h^6) where the
    one-sided Taylor predictor's is O(h^3), so one Newton step lands at rounding level. Both
    engines evaluate them by Horner's rule (:func:`_horner`), from the table, without gathering
    the two anchors' rows per value.

    >>> x = np.array([0.0, 0.3])[:, None]
    >>> P = _quintic(np.sin(x), np.cos(x), -np.sin(x), np.array([0.3]))
    >>> PL = np.ascontiguousarray(P.transpose(1, 2, 0))
    >>> bool(abs(_horner(PL, np.array([0]), np.array([0.5]))[0, 0] - np.sin(0.15)) < 1e-8)  # h^6 sin^(6) / 6! ~ 1e-9
    True
    """
    hh = h[:, None]
    q0, dq = Q[:-1], Q[1:] - Q[:-1]
    D0, D1, E0, E1 = hh * D[:-1], hh * D[1:], hh**2 * DD[:-1], hh**2 * DD[1:]
    return np.stack((q0, D0, 0.5 * E0, 10 * dq - 6 * D0 - 4 * D1 - 1.5 * E0 + 0.5 * E1,
                     -15 * dq + 8 * D0 + 7 * D1 + 1.5 * E0 - E1, 6 * dq - 3 * D0 - 3 * D1 - 0.5 * E0 + 0.5 * E1), axis=1)


def _horner(PL, k, t):
    """(M, n) the polynomials of intervals k (M,, non-decreasing) of :func:`_quintic`'s
    table, transposed to PL (6, n, K - 1), at t (M,), highest power first (the compiled
    engine's loop evaluates them in the same order). One coefficient at a time, poses last,
    each interval's repeated over its run of values (a repeat costs ~1/3 of a gather; gathering
    whole (M, 6, n) rows and broadcasting t over rows of n cost ~4x more than gathers)."""
    runs = np.bincount(k - k[0])
    at = slice(k[0], k[0] + runs.size)
    q = np.repeat(PL[5][:, at], runs, axis=1)
    for j in range(4, -1, -1):
        q *= t
        q += np.repeat(PL[j][:, at], runs, axis=1)
    return q.T


def _event_index(U, lo, i, u_from, u_star):
    """First index in (lo, i] whose value is at or past u_star, walking from u_from to U[i]."""
    d = U[i] - u_from
    ks = np.arange(lo + 1, i + 1)
    proj = (U[ks] - u_from) @ d
    star = (np.atleast_1d(u_star) - u_from) @ d
    past = np.flatnonzero(proj >= star - 1e-12 * max(1.0, abs(star)))
    return int(ks[past[0]]) if past.size else int(i)


def _same(a, b, model):
    return a.kind == b.kind and _scaled_norm(model, np.atleast_1d(a.input) - np.atleast_1d(b.input)) <= 1e-8


def _at_events(model, U, events):
    """Values that sit on a located limit or bifurcation: index -> event."""
    out = {}
    for ev in events:
        if ev.kind in ("limit", "bifurcation", "singular"):
            for i in np.flatnonzero(_scaled_norm(model, U - np.atleast_1d(ev.input)) <= EVENT_TOL):
                out[int(i)] = ev
    return out


def _on_event(model, U, events):
    """(M,) True for the values U (M, f) that sit on a located limit or bifurcation."""
    on = np.zeros(len(U), bool)
    for ev in events:
        if ev.kind in ("limit", "bifurcation", "singular"):
            on |= _scaled_norm(model, U - np.atleast_1d(ev.input)) <= EVENT_TOL
    return on


def _past_limit(limits, u_from, u_to, period=None):
    """(M,) True where a limit found moving in direction d lies between u_from and u_to (M, f).
    ``period`` (P, D) of a pose periodic in its one input (:meth:`Walker.period`): as the walk
    goes, u_to less its whole periods from u_from, then the other way round (a period more or
    less), past a limit only where both ways are (the limits taken in the period each way)."""
    if period is None:
        past = np.zeros(len(u_to), bool)
        for ev, d in limits:
            star = np.atleast_1d(ev.input)
            past |= np.all((u_to - star) * d > 0, axis=1) & np.all((star - u_from) * d >= 0, axis=1)
        return past
    P = period[0]
    rem = u_to - u_from
    rem = rem - P * np.trunc(rem / P)
    past = np.ones(len(u_to), bool)
    for way in (rem, rem - np.sign(rem) * P):
        blocked = np.zeros(len(u_to), bool)
        for ev, d in limits:
            star = np.atleast_1d(ev.input)
            s = np.where(way >= 0, np.mod(star - u_from, P), -np.mod(u_from - star, P))  # star - u_from, that way
            blocked |= np.all((way - s) * d > 0, axis=1) & np.all(s * d >= 0, axis=1)
        past &= blocked
    return past


class _Out:
    """Per-point results filled chunk by chunk: allocated, not filled (the bulk pass writes
    nearly every row, on all cores in the compiled engine; :meth:`blank` fills the rest)."""

    def __init__(self, N, n, rates=True):
        # without rates, one read-only NaN that takes no memory (the result's arrays are
        # read-only)
        self.rates = rates
        if rates:
            self.qd, self.qdd = np.empty((N, n)), np.empty((N, n))
        else:
            self.qd = self.qdd = np.broadcast_to(np.nan, (N, n))
        self.residual, self.sing, self.branch = np.empty(N), np.empty(N), np.empty(N)
        self.iters = np.empty(N, int)
        self.status = np.empty(N, dtype=np.int8)

    def put(self, i, r, sel=slice(None)):
        if self.rates:
            self.qd[i], self.qdd[i] = r["qd"][sel], r["qdd"][sel]
        self.residual[i], self.iters[i] = r["res"][sel], r["iters"][sel]
        self.sing[i], self.branch[i], self.status[i] = r["sing"][sel], r["branch"][sel], r["status"][sel]

    def blank(self, rows):
        """The rows nothing was put for: NaN rates, residual and singularity, no iterations,
        no mode, status NOT_CONVERGED (until said otherwise)."""
        if self.rates:
            self.qd[rows] = self.qdd[rows] = np.nan
        self.residual[rows] = self.sing[rows] = np.nan
        self.iters[rows], self.branch[rows], self.status[rows] = 0, 0.0, Status.NOT_CONVERGED


def _rates(p, lu, q, U, Ud, Udd):
    with np.errstate(all="ignore"):
        qd = velocity(p, lu, Ud)
        return qd, acceleration(p, lu, q, qd, U, Udd)


def _step(br, q, U, Ud, Udd):
    """One Newton step from poses q and, with the factorisation at q, the rates at the
    corrected poses: a dict of q (corrected where the step is finite), qd, qdd (NaN without
    rates), the scaled residual ``res`` at q, the scaled ``step`` and ``off`` (its size over
    the finite components: how far the pose moved), the largest scaled redundant row ``red``,
    the blocks' det ``signs``, the singularity measure ``sing`` and the ``branch``. The
    compiled engine computes the same in :func:`planar.compiled.final`."""
    if br.compiled is not None:
        return br.compiled.final(br.m, br.p, q, U, Ud, Udd, br.rates)
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
    if br.rates:
        qd, qdd = _rates(p, lu, q, U, Ud, Udd)
    else:  # positions only: no velocity and acceleration solves, no rate arrays (read-only NaN)
        qd = qdd = np.broadcast_to(np.nan, q.shape)
    return dict(q=q, qd=qd, qdd=qdd, res=res, step=step, off=off, red=_redundant(m, full), signs=lu.signs,
                sing=lu.sing, branch=np.prod(lu.signs, axis=1))


def final_step(br, q, U, Ud, Udd):
    """Final poses from good guesses q, with their rates and statuses. One evaluation and one
    factorisation serve a Newton step, its certificate (the residual at the guess and the size
    of the correction) and, where the correction is at rounding level (ROUND, scaled), the
    velocity and acceleration solves: the Jacobian at the guess differs from the one at the
    final pose by that little. The other points take the general Newton and one more step at
    its solution for their modes and rates."""
    m, p, tol = br.m, br.p, br.tol
    guess = q
    f = _step(br, q, U, Ud, Udd)
    q, qd, qdd, res, step, off = f["q"], f["qd"], f["qdd"], f["res"], f["step"], f["off"]
    red_res, signs, sing, branch = f["red"], f["signs"], f["sing"], f["branch"]
    iters = np.ones(q.shape[0], int)
    # a guess that holds the constraints where the Jacobian is singular (the correction is not
    # finite) is a pose on the singular position itself: kept, status SINGULAR, no rates
    on_singular = (res <= tol) & ~np.isfinite(step)
    conv = (res <= tol) & ((step <= ROUND) | on_singular)
    sing = np.where(on_singular, 0.0, sing)
    slow = np.flatnonzero(~conv)
    if slow.size:
        qs, cv, _, it = newton(m, q[slow], U[slow], tol=tol, max_iter=30, plan=p, engine=br.compiled)
        q[slow], conv[slow], iters[slow] = qs, cv, it + 1
        g = _step(br, qs, U[slow], Ud[slow], Udd[slow])
        res[slow], red_res[slow] = g["res"], g["red"]
        if br.rates:
            qd[slow], qdd[slow] = g["qd"], g["qdd"]
        signs[slow], sing[slow], branch[slow] = g["signs"], g["sing"], g["branch"]
        off[slow] = np.max(np.abs((qs - guess[slow])[:, p.cols] / m.col_scale[p.cols]), axis=1)
    st = status_of(sing, red_res, tol)
    # a point on a singular position converges only linearly, and next to one (singularity s)
    # Newton's steps stay at the rounding over s, above the step test: their positions still hold
    held = ((st == Status.SINGULAR) & (res <= HELD * tol)) | ((st == Status.NEAR_SINGULAR) & (res <= tol))
    st = np.where(conv | held, st, Status.NOT_CONVERGED)
    if br.rates:
        qd[st > Status.BRANCH_EVENT] = qdd[st > Status.BRANCH_EVENT] = np.nan
    return dict(q=q, qd=qd, qdd=qdd, conv=conv, off=off,
                res=res, iters=iters, signs=signs, sing=sing, branch=branch, status=st)


def _redundant(model, full):
    """(N,) largest scaled residual of the redundant rows in ``full`` (N, m) (0 without any)."""
    red = model.redundant_rows
    if not red.size:
        return np.zeros(full.shape[0])
    return np.max(np.abs(full[:, red] * model.row_scale[red]), axis=1)


def _finish(model, br, U, Ud, Udd, q, solved, done, out, q_pred, events, at_event, beyond, jumps, U_in, shift,
            order=None, u0=None):
    """The results of the solved values; ``jumps`` (stops, prev) for :func:`_mark_jumps`;
    ``shift`` (k, (P, D)): value i was solved k[i] periods P back (the input values ``U_in``),
    its pose shifted back by k[i] D; ``order`` (values solved in the order of the input from
    the start's input ``u0``): the asked position of each, where the results are put back."""
    N, n = q.shape
    p = br.p
    idx = np.flatnonzero(solved & ~done)
    for lo in range(0, idx.size, CHUNK):
        i = idx[lo : lo + CHUNK]
        r = final_step(br, q[i], U[i], Ud[i], Udd[i])
        q[i] = r["q"]
        out.put(i, r)
    # every solved value has been put but those on events, which get their values there
    unset = ~solved
    unset[list(at_event)] = True
    out.blank(unset)
    _on_events(model, br, U, Ud, Udd, q, out, events, at_event)
    status = out.status
    q[~POSED_MASK[status]] = np.nan
    if p.cols.size < n:
        drop = np.setdiff1d(np.arange(n), p.cols)
        q[:, drop] = np.nan
        if out.rates:
            out.qd[:, drop] = out.qdd[:, drop] = np.nan

    # unreached points: the assembly gap from the best guess at hand
    miss = np.flatnonzero(~solved)
    gap = np.full(N, np.nan) if miss.size else np.broadcast_to(np.nan, N)  # (read-only, as every result array)
    for lo in range(0, miss.size, CHUNK):
        i = miss[lo : lo + CHUNK]
        guess = np.array([q_pred.get(k, model.q0) for k in i.tolist()]).reshape(i.size, n)
        guess = np.where(np.isnan(guess), model.q0, guess)
        _, g = least_squares_gap(model, guess, U[i])
        gap[i] = g
        status[i] = np.where((g > GAP) | beyond[i], Status.NOT_ASSEMBLABLE, Status.NOT_CONVERGED)
    _mark_jumps(status, *jumps)
    events = tuple(events) + tuple(near_stretches(model, U, out.sing, status, events))
    events = tuple(sorted(events, key=lambda e: e.index))
    residual, iters, sing, branch = out.residual, out.iters, out.sing, out.branch
    qd, qdd = out.qd, out.qdd
    if order is not None:
        events = tuple(_asked_order(model, U, order, events, u0))
        inv = np.empty_like(order)
        inv[order] = np.arange(N)
        q, status, residual, iters, sing, branch = (a[inv] for a in (q, status, residual, iters, sing, branch))
        U, Ud, Udd, U_in, gap = U[inv], Ud[inv], Udd[inv], U_in[inv], gap[inv]
        if out.rates:
            qd, qdd = qd[inv], qdd[inv]
        shift = None if shift is None else (shift[0][inv], shift[1])
    if shift is not None:
        k, (P, D) = shift
        whole = np.round(D / (2 * np.pi))
        q[:] = _add_turns(q, k[:, None] * whole)
        at = lambda e: k[min(e.index, N - 1)]  # noqa: E731
        events = tuple(replace(e, input=_add_turns(e.input, at(e) * round(P / (2 * np.pi))),
                               q=None if e.q is None else _add_turns(e.q, at(e) * whole)) for e in events)
        U = U_in
    return Sweep(model, U, Ud, Udd, q, qd, qdd, status, residual, iters, sing, branch, gap, events)


def _on_events(model, br, U, Ud, Udd, q, out, events, at_event):
    """Values at and around located singular positions. A value on a limit keeps the located
    pose (status LIMIT, rates NaN). Around a bifurcation every value within BRANCH_H takes its
    values from the smooth branch interpolated from regular points (the direct solves lose
    accuracy like 1/distance there); the values on it get status BRANCH_EVENT."""
    for i, ev in at_event.items():
        q[i] = ev.q
        if out.rates:
            out.qd[i] = out.qdd[i] = np.nan
        out.sing[i], out.residual[i] = ev.singularity, np.nan
        out.status[i] = Status.LIMIT if ev.kind == "limit" else Status.SINGULAR
    s = input_scale(model)
    for ev in events:
        if ev.kind not in ("bifurcation", "singular") or U.shape[1] != 1:
            continue
        dist = np.abs(U[:, 0] - ev.input) * s[0]
        near = np.flatnonzero((dist < BRANCH_H / 4) & POSED_MASK[out.status])
        if near.size == 0 or "other branch" in ev.note or not ev.tangents:  # no tangent: no branch to follow
            continue
        got = _on_branch(model, br, ev, U[near, 0], Ud[near, 0], Udd[near, 0])
        if got is None:
            continue
        # the interpolated pose replaces the direct solve only where it holds the constraints
        # to tolerance (its residual is the one reported): never a valid status on a bad pose
        Phi, _, _ = br.p.evaluate(got[0], U[near])
        res = np.max(np.abs(Phi * model.row_scale[br.p.rows]), axis=1)
        fits = res <= 1e2 * br.tol
        near, res = near[fits], res[fits]
        q[near] = got[0][fits]
        if out.rates:
            out.qd[near], out.qdd[near] = got[1][fits], got[2][fits]
        out.residual[near] = res
        # a value on the event, or one the direct solve found singular, now has rates from
        # the branch: valid, flagged as at a branch event
        on = (dist[near] <= EVENT_TOL) | (out.status[near] == Status.SINGULAR)
        out.status[near[on]] = Status.BRANCH_EVENT


def _on_branch(model, br, ev, u, ud, udd):
    """Position, velocity and acceleration at inputs u (one input) on the smooth branch through
    the singular position ``ev``: degree-7 interpolation of eight regular points at
    u* +- k h (k = 1..4, h = BRANCH_H / 4 scaled), each solved from the branch tangent with its
    own rates. Direct solves lose digits like 1/distance (positions), 1/distance^2
    (velocities) and 1/distance^3 (accelerations) there; these nodes are far enough not to."""
    T = ev.tangents[0]
    us = float(ev.input)
    h = BRANCH_H / 4 / float(input_scale(model)[0])
    nodes = us + h * np.array([-4.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 4.0])
    guess = ev.q[None] + (nodes - us)[:, None] * T[None]
    qn, conv, _, _ = br.solve(guess, nodes[:, None], max_iter=20)
    if not conv.all():
        return None
    qu, quu, _, _ = br.state(qn, nodes[:, None], np.ones((nodes.size, 1)))
    K = nodes.size
    W = np.array([[np.prod([(x - nodes[k]) / (nodes[j] - nodes[k]) for k in range(K) if k != j])
                   for j in range(K)] for x in u])
    q_u = W @ qu
    return W @ qn, q_u * ud[:, None], q_u * udd[:, None] + (W @ quu) * (ud**2)[:, None]


def near_stretches(model, U, sing, status, events):
    """One near-singular event per run of valid values closer to another branch than
    NEAR_CURVE (the singularity measure), at its closest value, unless another event lies
    within the run or next to it (a limit or a crossing explains it)."""
    out = []
    with np.errstate(invalid="ignore"):
        flag = VALID_MASK[status] & (sing < NEAR_CURVE)
    if not flag.any():
        return out
    known = [e.index for e in events]
    edges = np.flatnonzero(np.diff(np.r_[0, flag.astype(int), 0]))
    for a, b in zip(edges[::2], edges[1::2]):
        k = a + int(np.nanargmin(sing[a:b]))
        if any(a - 1 <= i <= b + 1 for i in known):
            continue
        near = int(np.sum(status[a:b] == Status.NEAR_SINGULAR))
        out.append(Event("near_singular", U[k, 0] if U.shape[1] == 1 else U[k].copy(), int(k),
                         singularity=float(sing[k]), error=float(np.finfo(float).eps / sing[k]),
                         note=f"{b - a} value(s) close to another branch (an avoided crossing or a close approach, "
                              f"singularity down to {sing[k]:.2g}; {near} of them NEAR_SINGULAR): valid but sensitive; "
                              "the branch was kept"))
    return out
