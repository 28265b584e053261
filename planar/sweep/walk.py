"""The sequential walk of one pose along its branch (:class:`Walker`): its steps, in batched
waves while they are accepted, and the tracer through what they cannot take; its re-entry past
a gap is :class:`planar.sweep.reentry.Reentry`, its input's period
:class:`planar.sweep.periods.Periods`."""

import numpy as np

from planar.acceptance import CERT, ROUND
from planar.events import NEAR
from planar.events.crossing import cross
from planar.solver import DISTANT, rounding
from planar.sweep.anchors import MAX_WAVE, WAVE, solve_wave
from planar.sweep.branch import input_scale, scaled_norm
from planar.sweep.periods import Periods
from planar.sweep.reentry import Reentry

HALVINGS = 5  # natural-parameter step halvings before the arclength tracer takes over
# ... but in a near-singular stretch (the singularity measure s below NEAR), where the steps'
# certificate (a correction within CERT s) asks for short steps and the tracer's steps are held
# to the same measure, the walk goes on while its solves converge and the certificate stands
# clear of the corrections' rounding (the residual's over s: within CLEAR of it), in steps down
# to 2**-MAX_HALVINGS of a full one (two long links over a short base are near-singular all
# along: no turning point to pass)
MAX_HALVINGS, CLEAR = 12, 0.1
# tracings round a circuit one sweep may make to re-enter its branch: next to a limit's far
# side the first tries may fail where a value further on enters
ROUNDS = 5
WALK_STEPS = 2000  # steps of one walk without a period to shorten it: farther targets are entered directly


class Walker(Periods, Reentry):
    """Sequential continuation of one pose (batch of one), with events."""

    def __init__(self, br, max_step, other, rounds=ROUNDS):
        self.br, self.max_step, self.other = br, max_step, other
        self.events = []
        self.rounds = rounds  # tracings round a circuit left to this sweep (each costs ~100s of solves)
        self._symmetry = self._period = None  # (P, D) or False, found when first asked
        self._periodic = None  # whether the rows read every angle through its cosine and sine (periodic)
        self.turns = False  # the walk went round a whole period (no limit): the input turns fully
        self.limit = None  # else the input of a limit the walk over a period met (one input)
        # the last walk moved by whole periods of an input that does not turn fully: past the
        # limits of those periods (its target not reached continuously: a jump)
        self.jumped, self.also = False, None
        # (modes, inputs covered, the input's period where known) of the tracings round a
        # circuit that did not come back to ours
        self._round = []
        self._met = {}  # (input, modes, pose) a walk started from -> (direction, the limit it met there)
        self.images = []  # (values, sweep) of the sweeps of values' images a period back past a gap

    def share(self, other):
        """Take ``other``'s tracings round a circuit (a nested sweep of its images): the
        budget it has left and the modes and inputs its failed tracings covered."""
        self.rounds, self._round = other.rounds, other._round

    def walk(self, q, u, signs, target, index, periodic=False):
        """Follow the branch from (q, u) to ``target``. With ``periodic``, where the pose is
        periodic in the input (:meth:`period`), the whole periods between them are one move
        and the walk goes on less than a period the same way, so a far target costs what a
        near one does; for a rocking input that meets a limit that way, the other way round
        (a period less or more). Returns ("ok", q, signs), ("limit", event, (q_before, u_before)),
        ("lost",) or ("far",) for a target more than WALK_STEPS steps away with no period to
        shorten the way (the work is bounded: the sweep enters it directly). ``jumped`` says
        whether a target reached moved by whole periods of a rocking input; ``also``, for a
        limit met both ways, (the limit the other way round met, its direction)."""
        self.jumped, self.also = False, None
        if periodic and u.size == 1:
            d = float(target[0] - u[0])
            per = self.period() if abs(d) * float(input_scale(self.br.m)[0]) >= 2 * np.pi else None
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
                    self.jumped = bool(k) and not self.turns
                    return got
                kept = self.events[n:]
                del self.events[n:]
                again = self.walk(*other, signs, target, index)
                # the other way round keeps the assembly modes: through a change point it comes
                # back in other modes, where the walk the direct way would re-enter in these
                if again[0] == "limit" or (again[0] == "ok" and not np.all(again[2] == signs)):
                    self.events[n:] = kept
                    self.jumped = bool(k) and not self.turns
                    if again[0] == "limit":
                        self.also = (again[1], np.sign(target[0] - other[1][0]))
                    return got
                self.jumped = True  # (a period more or less than the value is away: past a limit)
                return again
        total = float(scaled_norm(self.br.m, target - u))
        if total <= 1e-14:  # the target is this pose up to rounding (the final Newton polishes it)
            return "ok", q, signs
        if total > WALK_STEPS * self.max_step:
            return ("far",)
        # a walk from this pose that met a limit short of the target meets it again: values
        # tried one by one from one pose would each trace to it
        key = (u.tobytes(), signs.tobytes(), np.round(q, 9).tobytes()) if u.size == 1 else None
        met = self._met.get(key)
        if met is not None and (target[0] - np.ravel(met[1][1].input)[0]) * met[0] > 0:
            return met[1]
        got = self._walk(q, u, signs, target, index, total)
        if key is not None and got[0] == "limit":
            self._met[key] = (np.sign(target[0] - u[0]), got)
        return got

    def _walk(self, q, u, signs, target, index, total):
        """The walk the direct way (see :meth:`walk`), ``total`` its scaled length; where it
        asked the tracer through a singular stretch, on from where the tracer gives it back."""
        while True:
            got = self._steps(q, u, signs, target, index, total)
            if got[0] != "resume":
                return got
            _, q, u, signs = got
            total = float(scaled_norm(self.br.m, target - u))

    def _steps(self, q, u, signs, target, index, total):
        br = self.br
        full = min(1.0, self.max_step / total)
        h, t = full, 0.0
        u0 = u
        halvings = 0
        wave = WAVE
        sing = None  # the singularity measure at q, where known
        while t < 1.0:
            if halvings == 0 and 1.0 - t > h:
                # the full steps ahead in one batch, as the anchors are: the walk's own steps
                # while each is accepted (a batch costs about one step); the rest one by one
                ts = np.minimum(t + h * np.arange(1, wave + 1), 1.0)
                ts = ts[: int(np.searchsorted(ts, 1.0)) + 1]
                a, qa, _ = solve_wave(self.br, (q, u, signs), u0 + ts[:, None] * (target - u0), np.arange(ts.size))
                if a:
                    q, u, t, sing = qa[-1], u0 + ts[a - 1] * (target - u0), ts[a - 1], None
                wave = min(2 * wave, MAX_WAVE) if a == ts.size else max(a, WAVE)
                if a:
                    continue
            dt = min(h, 1.0 - t)
            u_next = u0 + (t + dt) * (target - u0)
            q_pred, _ = br.predict(q[None], u[None], (u_next - u)[None])
            qn, conv, _, _ = br.solve(q_pred, u_next[None])
            sn, sg = br.modes(qn, u_next[None])
            if br.accept(qn, q_pred, lambda k: q[None], conv, sn, signs[None], sg)[0]:
                if halvings > HALVINGS:
                    # in a near-singular stretch, the step the certificate allows: the
                    # predictor's error grows as the step cubed
                    off = np.max(np.abs((qn[0] - q_pred[0])[br.p.cols] / br.cs))
                    h = min(h * min(2.0, 0.8 * np.cbrt(CERT * sg[0] / max(off, ROUND))), full)
                else:
                    h = min(2 * h, full)
                q, u, t, sing = qn[0], u_next, t + dt, sg[0]
                # the count starts again at a full step only: towards a turning point steps
                # that pass at half the size fail again at the full one, and the walk would
                # creep up on the limit, a batch and two steps per halving of its distance
                halvings = 0 if h == full else halvings
                continue
            flipped = bool(conv[0]) and not np.all(sn[0] == signs)
            halvings += 1
            h /= 2
            # a sign flip, repeated failures, or steps shrinking towards a turning point (but
            # in a near-singular stretch), or too short to go on
            if flipped or h * total < self.max_step / 2**MAX_HALVINGS:
                return self._cross(q, u, signs, target, index)
            if halvings > HALVINGS or h * total < self.max_step / 2**HALVINGS:
                if conv[0] and sing is None:
                    sing = br.modes(q[None], u[None])[1][0]
                if not (conv[0] and sing < NEAR and rounding(br.m, q[None], br.p.cols)[0] <= CLEAR * CERT * sing**2):
                    return self._cross(q, u, signs, target, index)
        return "ok", q, signs

    def _cross(self, q, u, signs, target, index, resume=True):
        """Through the stretch the walk's steps could not take, by the tracer: the walk's
        result, or ("resume", q, u, signs) where the tracer gives the walk back."""
        br, m = self.br, self.br.m
        k = len(self.events)
        got = cross(m, br.p, q, u, target, self.max_step, other=self.other, index=index, resume=resume)
        self.events.extend(got.events)
        if got.resume is not None:
            q1, u1 = got.resume
            qn, conv, _, _ = br.solve(q1[None], u1[None], max_iter=DISTANT)
            if conv[0]:
                return "resume", qn[0], u1, br.signs(qn, u1[None])[0]
            del self.events[k:]  # (traced again, all the way)
            return self._cross(q, u, signs, target, index, resume=False)
        if got.limit is not None:
            ev = got.limit
            if scaled_norm(m, np.atleast_1d(ev.input) - target) <= 1e-10:
                # the value is the limit position itself
                self.events.append(ev)
                return "ok", ev.q, signs
            return "limit", ev, got.before
        if got.q is None:
            return ("lost",)
        qn, conv, _, _ = br.solve(got.q[None], target[None], max_iter=DISTANT)
        if not conv[0]:
            return ("lost",)
        return "ok", qn[0], br.signs(qn, target[None])[0]
