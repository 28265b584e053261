"""The sequential walk of one pose along its branch (:class:`Walker`): steps, events, re-entry
past a gap, the input's period and whole turns of angles; one class with the helpers it alone uses."""

import numpy as np

from planar.acceptance import CERT, ROUND
from planar.events import NEAR
from planar.events.crossing import around, cross
from planar.solver import DISTANT, GAP, REENTRY, RESTARTED, least_squares_gap, newton, rounding
from planar.sweep.anchors import MAX_WAVE, WAVE, solve_wave
from planar.sweep.branch import input_scale, scaled_norm

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
SPREAD = 4  # walk steps between the values a search past a gap tries, at most (0.2 rad by default)
MAX_SPREAD = 256  # values it tries spread over the rest, at most
# inputs tried between the neighbours of a dip of the gap that has no target between them, and
# such dips tried a search, at most (see _folds)
BETWEEN, MAX_DIPS = 8, 4
FOLD_LEVELS = 3  # narrowings of a fold's search onto its least gap (8 inputs, then 8 of 1/9 the spacing...)
PERIODS = 12  # whole turns of an angle input within which the pose is looked for returning to itself
MODE_PERIODS = 4  # periods the walk from the sketch may go on in other modes before it comes back
SAME = 1e-8  # scaled distance within which a pose after a period is the pose it started from
RESTARTS = 64  # guesses of a re-entry that landed in other modes, from its pose with angles drawn at random
WALK_STEPS = 2000  # steps of one walk without a period to shorten it: farther targets are entered directly


class Walker:
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

    def symmetry(self):
        """(P, D): an input period P and the pose shift D over it where the sketch shifted by D
        solves the constraints at its input plus P in the same assembly modes, the constraints
        themselves unchanged by the shift. Either whole turns P of one angle input, D whole turns
        of the angles of the bodies that turn with it (the revolute and slider rows of a pure
        linkage read angles through their sines and cosines, while a gear or a slider's
        relative angle passes the input on linearly: a gear pair of ratio 7/6 comes back after
        7 turns); or, where the rows read some coordinates only linearly (a gear's angle about
        its own pivot, a rack's travel), an input P after which the angles read through sines
        and cosines are back by whole turns, the others moved along the tangent (a gear train
        of any ratio, a planetary train a turn of its carrier on). None where neither holds (a
        geared linkage of ratio pi)."""
        if self._symmetry is None:
            self._symmetry = _symmetry(self.br) or False
        return self._symmetry or None

    def period(self):
        """(P, D): whole periods of :meth:`symmetry` after which the walk from the sketch comes
        back to the sketch up to whole turns D of its angles (a full-turn crank: its coupler and
        rocker may turn too), in its modes: after one, or after several where each passes a
        change point on the smooth branch and comes out in other modes (a Watt six-bar on the
        Grashof boundary: in the sketch's again after two). Or the symmetry's where the first
        period's walk meets a limit (a rocking input: values a period apart are the same pose,
        reached by re-entry). None otherwise (a circuit that closes after more turns)."""
        if self._period is None:
            self._period = False
            sym = self.symmetry()
            if sym is not None:
                m = self.br.m
                P = sym[0]
                k, rounds = len(self.events), self.rounds
                s0 = self.br.signs(m.q0[None], m.u0[None])[0]
                q, u, s = m.q0, m.u0, s0
                for j in range(1, MODE_PERIODS + 1):
                    got = self.walk(q, u, s, u + P, 0)
                    if got[0] == "limit" and j == 1:
                        self._period, self.limit = sym, float(np.ravel(got[1].input)[0])
                    if got[0] != "ok":
                        break
                    q, u, s = got[1], u + P, got[2]
                    if np.all(s == s0):
                        D = whole_turns(self.br, q - m.q0, j * sym[1])
                        self._period = False if D is None else (j * P, D)
                        self.turns = D is not None
                        break
                del self.events[k:]  # those turns are no part of the sweep
                self.rounds = rounds
        return self._period or None

    def keep_period(self, P, D, limit):
        """Take (P, D) as the period (found by a sweep where :meth:`period`'s walk meets a limit;
        ``limit``: the input of a limit that sweep met, None where the input turns fully)."""
        self._period, self.turns, self.limit = (P, D), limit is None, limit

    def _shorten(self, q, u, signs, k):
        """(q, u) moved by k whole periods of the input (:meth:`period`): the pose there is
        the pose at u shifted by whole turns. None where it does not solve there."""
        P, D = self.period()
        uk = add_periods(u, k, P)
        qk, conv, _, _ = self.br.solve(add_periods(q, k, D)[None], uk[None])
        if conv[0] and np.all(self.br.signs(qk, uk[None])[0] == signs):
            return qk[0], uk
        return None

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

    def enter_any(self, guesses, signs, targets, tries=4, poses=None, circuit=True):
        """((index, pose) of the first of ``targets`` (M, f) where the branch can be entered,
        or None if none found; whether any target searched assembles at all): a batched
        least-squares search from each guess, then Newton, the mode test and, on another mode,
        Newton from ``poses`` of the branch solved elsewhere and (``circuit``) the way round
        through a limit (:meth:`enter`)."""
        # (a value asked again is searched once: repeats would take the places of the values
        # spread over the rest)
        _, first = np.unique(targets, axis=0, return_index=True)
        if first.size < len(targets):
            keep = np.sort(first)
            best, assembles = self.enter_any(guesses, signs, targets[keep], tries, poses, circuit)
            return (None if best is None else (int(keep[best[0]]), best[1])), assembles
        br = self.br
        best, assembles = None, False
        # the first few targets and some spread over the rest, at most SPREAD walk steps apart
        # along the input, and every target next to those where the gap dips (_dips): a
        # least-squares search of each of hundreds of values would cost more than the walk
        along = np.r_[0.0, np.cumsum(scaled_norm(br.m, np.diff(targets, axis=0)))]
        marks = np.searchsorted(along, np.arange(0.0, along[-1], SPREAD * self.max_step)[:MAX_SPREAD])
        pick = np.unique(np.r_[np.arange(min(len(targets), 4 * tries)), marks,
                               np.linspace(0, len(targets) - 1, 2 * tries).astype(int)])
        for g in guesses:
            if best is not None:  # (a later guess can only enter earlier)
                pick = pick[pick < best[0]]
                if not pick.size:
                    break
            ql, gap = least_squares_gap(br.m, np.repeat(g[None], pick.size, 0), targets[pick], decide=GAP)
            pick, ql, gap = _dips(br.m, g, targets, pick, ql, gap, self.periodic())
            between = False
            if not np.any(gap <= GAP):
                ql, gap, between = self._folds(g, signs, targets, pick, ql, gap, poses, circuit)
            near = np.flatnonzero(gap <= GAP)
            assembles |= near.size > 0 or between
            # the first few, and a few spread over the rest: next to a limit's far side Newton
            # may find only the other mode, where a value further on enters the branch
            for c in np.unique(np.r_[near[:tries], near[np.linspace(0, near.size - 1, tries).astype(int)]]
                               if near.size else near):
                if best is not None and pick[c] >= best[0]:
                    break
                qe = self.enter([ql[c]], signs, targets[pick[c]], poses, circuit)
                if qe is not None:
                    best = (int(pick[c]), qe)
                    break
        return best, assembles

    def _folds(self, g, signs, targets, pick, ql, gap, poses, circuit):
        """The least-squares poses ``ql`` and gaps of the search's values ``pick`` (indices into
        ``targets``), where none assembles from ``g``, with a pose of the branch at the pick next
        to an input that assembles between the neighbours of a dip of the gap with no target
        between them: least squares from ``g`` at inputs between them (:meth:`_fold`), the first
        that assembles entered (:meth:`enter`) and walked on from to the pick past it, else back
        to the one before within SPREAD walk steps; and whether any input between assembles, in
        any modes (as a target there would have: the search's ``assembles``).
        Past the fold at a gap's far end the minimum least squares finds from a pose before the
        gap may touch zero only within a few hundredths of a radian (a Watt six-bar, there in
        other modes: its values a walk step apart past a gap of 0.73 rad were all
        NOT_ASSEMBLABLE, where values 0.02 apart entered the range at its far end)."""
        met = False
        if pick.size < 2:
            return ql, gap, met
        # inner minima (next to the limit the gap is least for the limit's sake) steep enough
        # to reach zero between the neighbours, as a V: the minimum at most as far above zero
        # as the steeper side rises over one step
        mid, lo, hi = gap[1:-1], gap[:-2], gap[2:]
        inner = np.flatnonzero((mid < lo) & (mid < hi) & (2 * mid <= np.maximum(lo, hi))) + 1
        for d in inner[:MAX_DIPS]:
            a, b = d - 1, d + 1
            if pick[b] - pick[a] > 2:  # (targets between them: _dips searched those)
                continue
            span = targets[pick[b]] - targets[pick[a]]
            found = self._fold(g, targets[pick[a]], targets[pick[b]], gap[a], gap[b])
            if found is None:
                continue
            met = True
            u_e, q_l = found
            qe = self.enter([q_l], signs, u_e, poses, circuit)
            if qe is None:
                continue
            # the pick past the entry (the dip's, or its far neighbour's) walked to from it, else
            # the pick before it, within SPREAD walk steps: the entry may lie in an interval
            # narrower than the picks' spacing, past the last pick in it (a Stephenson six-bar's
            # [1.838, 1.942] inside a gap, entered at 1.931 from picks 1.918 and 2.006)
            past_dip = (u_e - targets[pick[d]]) @ span > 0
            after, before = (b, d) if past_dip else (d, a)
            back = scaled_norm(self.br.m, targets[pick[before]] - u_e) <= SPREAD * self.max_step
            for c in (after, before) if back else (after,):
                got = self.walk(qe, u_e, signs, targets[pick[c]], int(pick[c]))
                if got[0] == "ok":
                    ql, gap = ql.copy(), gap.copy()
                    ql[c], gap[c] = got[1], 0.0
                    return ql, gap, met
        return ql, gap, met

    def _fold(self, g, ua, ub, ga, gb):
        """(input, least-squares pose from ``g``) of the first of BETWEEN inputs between ``ua``
        and ``ub`` (gaps ``ga``, ``gb``) that assembles; where none does, the same between the
        neighbours of their least gap while it dips as a V, FOLD_LEVELS times (the gap falls
        to zero at the end of an interval narrower than the inputs' spacing: a Stephenson
        six-bar's [1.838, 1.942], searched from 1.93 to 2.07, had its least gap 1.7e-4 at
        1.946). None where none is found."""
        w = np.linspace(0.0, 1.0, BETWEEN + 2)[1:-1, None]
        for _ in range(FOLD_LEVELS):
            u = ua + w * (ub - ua)
            qm, gm = least_squares_gap(self.br.m, np.repeat(g[None], BETWEEN, 0), u, decide=GAP)
            ok = np.flatnonzero(gm <= GAP)
            if ok.size:
                return u[ok[0]], qm[ok[0]]
            G, V = np.r_[ga, gm, gb], np.vstack((ua, u, ub))
            j = int(np.argmin(G))
            if j in (0, G.size - 1) or not 2 * G[j] <= max(G[j - 1], G[j + 1]):
                return None
            ua, ub, ga, gb = V[j - 1], V[j + 1], G[j - 1], G[j + 1]
        return None

    def enter_by_period(self, qs, us, signs, targets, tries=8):
        """(index, pose, modes) of a target (M, 1) near a pose solved on the branch (``qs``,
        ``us``, ``signs``) moved by whole periods of the input (:meth:`period`): the same pose
        shifted by whole turns, walked to from there. The first of ``targets`` within a walk
        step of such a pose, else the nearest one within SPREAD steps (the walk to a value next
        to the pose may meet the limit of an interval narrower than a step's spacing of the
        poses solved, where the walk to one further in goes on). Exact where the search of
        :meth:`enter_any` finds only another circuit (values past a limit pair that are a turn
        on from the stretch already solved), or nothing. None if none."""
        if targets.shape[1] != 1 or not len(us) or self.period() is None:
            return None
        P, _ = self.period()
        t = targets[:4096, 0]
        n = np.round((t[:, None] - us[None, :, 0]) / P)
        off = np.where(n != 0, np.abs(t[:, None] - us[None, :, 0] - n * P), np.inf)
        j = np.argmin(off, axis=1)
        near = off[np.arange(t.size), j]
        within = np.flatnonzero(near <= SPREAD * self.max_step)
        further = near[within] > self.max_step
        met = []  # (input, direction) of the limits the tries' walks met
        for c in within[np.lexsort((np.where(further, near[within], within), further))]:
            k = int(j[c])
            v = float(add_periods(us[k], n[c, k], P)[0])
            d = np.sign(t[c] - v)
            # (a target past a limit met the same way from before it is not a try: the targets
            # next to a limit, tried first, would spend them all on it)
            if any(w == d and (lim - v) * d > 0 and (t[c] - lim) * d >= 0 for lim, w in met):
                continue
            if tries == 0:
                break
            tries -= 1
            image = self._shorten(qs[k], us[k], signs[k], n[c, k])
            if image is None:
                continue
            got = self.walk(*image, signs[k], targets[c], int(c))
            if got[0] == "ok":
                return int(c), got[1], got[2]
            if got[0] == "limit":
                met.append((float(np.ravel(got[1].input)[0]), d))
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
        # (q counted hundreds of turns on holds its rows only to the rounding of its angles)
        slack = float(rounding(self.br.m, q[None], cols)[0])
        if conv[0] and np.all(self.br.signs(qn, u[None])[0] == signs) and whole_turns(self.br, qn[0] - q, slack=slack) is not None:
            return qn[0]
        return q

    def enter(self, guesses, signs, target, poses=None, circuit=True):
        """Re-enter the motion range at ``target`` from guesses of the same branch, each by
        Newton (from a least-squares minimum where Newton from it fails); where each lands in
        other modes, from ``poses`` (G, n) in one batch (poses of the branch solved elsewhere:
        where the loop closes at many poses in the same modes, as a geared linkage's, one of
        them lands in ours); then, for a :meth:`periodic` linkage, from a landing with its
        angles drawn anew (:meth:`_restarts`), else (``circuit``) round through a limit from
        the modes found. The pose found has its angles counted within half a turn of its
        guess's where it can (:meth:`near_turns`)."""
        br = self.br
        other = []
        for g in guesses:
            qn, conv, _, _ = newton(br.m, g[None], target[None], tol=br.tol, max_iter=REENTRY, max_step=0.3, plan=br.p)
            if not conv[0]:
                # far from the guess: least squares first, Newton from its minimum
                ql, gap = least_squares_gap(br.m, g[None], target[None], decide=GAP)
                if gap[0] > GAP:
                    continue
                qn, conv, _, _ = newton(br.m, ql, target[None], tol=br.tol, max_iter=REENTRY, plan=br.p)
                if not conv[0]:
                    continue
            found = br.signs(qn, target[None])[0]
            if np.all(found == signs):
                return self.near_turns(qn[0], target, signs, g)
            other.append((qn[0], found, g))
        if poses is not None and len(poses):
            T = np.repeat(target[None], len(poses), 0)
            # (undamped: its first step puts the coordinates the rows read linearly, the driven
            # angle and those geared to it, where the target has them)
            qn, conv, _, _ = newton(br.m, poses, T, tol=br.tol, max_iter=REENTRY, plan=br.p)
            ours = np.flatnonzero(_in_modes(br, qn, T, conv, signs))
            if ours.size:
                # the one that moved least from its guess: an undamped step from afar may
                # count an angle hundreds of turns on (a pose as valid, and as arbitrary)
                c = br.p.cols
                move = np.max(np.abs(qn[ours][:, c] - poses[ours][:, c]) / br.m.col_scale[c], axis=1)
                k = ours[np.argmin(move)]
                return self.near_turns(qn[k], target, signs, poses[k])
        if other and self.periodic():
            # a linkage whose rows read its angles through their cosines and sines closes in a
            # few ways at one input, and Newton from one landing with its angles drawn anew
            # finds them all: ours, or none, and then no way round a circuit (hundreds of
            # solves) comes to ours there either
            got = self._restarts(other[0][0], signs, target)
            return None if got is None else self.near_turns(got, target, signs, other[0][2])
        for qn, found, _ in other:
            # another mode of the same circuit: go round through a limit to ours; not again in
            # modes and inputs a tracing that did not come back to ours has covered, or whole
            # periods of the input from those (the same circuit, most likely: the tracings are
            # few, each costs ~100s of solves). Where it came back in the same modes both ways,
            # it has covered the other side of the circuit too, from limit to limit: a tracing
            # from there would go round the same way (a Stephenson six-bar traced one circuit
            # four times from its two sides, 0.2 s each)
            covered = any(np.array_equal(found, f) and _within(target[0], lo, hi, P) for f, (lo, hi), P in self._round)
            if circuit and target.size == 1 and self.rounds > 0 and not covered:
                self.rounds -= 1
                got, span, back = around(br.m, br.p, qn, target, signs, self.max_step, np.pi)
                if got is not None:
                    return got
                P = self._period[0] if self._period else None
                self._round += [(f, span, P) for f in (found, back) if f is not None]
        return None

    def periodic(self):
        """Whether the rows but the drivers' (which set the inputs) read every angle the plan
        solves through its cosine and sine: a turn of any one of them leaves them as they
        were. So a linkage of revolutes and pins in slots; not one with a slider, which locks
        its angle, or with gears, whose rolling rows read their angles as they are (a geared
        train closes at many poses in the same modes at one input, a turn of its gears apart)."""
        if self._periodic is None:
            m, p = self.br.m, self.br.p
            angles = p.cols[p.cols % 3 == 2]
            turned = np.repeat(m.q0[None], angles.size, 0)
            turned[np.arange(angles.size), angles] += 2 * np.pi
            with np.errstate(all="ignore"):
                Phi, _ = p.system.evaluate(turned, np.repeat(m.u0[None], angles.size, 0))
            rows = np.delete(p.rows, p.drivers)
            self._periodic = bool(np.max(np.abs(Phi[:, rows]) * m.row_scale[rows], initial=0.0) <= SAME)
        return self._periodic

    def _restarts(self, root, signs, target):
        """A pose at ``target`` in the modes ``signs`` of a :meth:`periodic` linkage, where
        ``root`` is one there in other modes: Newton in one batch from RESTARTS guesses, each
        ``root`` with its angles drawn at random (a loop's other closure lies a reflection
        away: no step from ``root`` reaches it); of those that land in our modes, the nearest
        ``root``, else None."""
        br = self.br
        p = br.p
        cols = p.cols[p.cols % 3 == 2]
        G = np.repeat(root[None], RESTARTS, 0)
        G[:, cols] += np.random.default_rng(0).uniform(-np.pi, np.pi, (RESTARTS, cols.size))
        T = np.repeat(target[None], RESTARTS, 0)
        qn, conv, _, _ = newton(br.m, G, T, tol=br.tol, max_iter=RESTARTED, plan=p)
        ours = np.flatnonzero(_in_modes(br, qn, T, conv, signs))
        if not ours.size:
            return None
        return qn[ours[np.argmin(np.max(np.abs(qn[ours][:, p.cols] - root[p.cols]) / br.m.col_scale[p.cols], axis=1))]]


# 2 pi = A1 + A2 + B: A1 with 27 significant bits (n A1 is exact for |n| < 2^26 turns), B the
# rounding of 2 pi to a double, so that whole turns are added to angles of 1e6 rad without the
# 1e-10 rad that n times the rounded 2 pi would carry
TWO_PI_A1 = np.round(2 * np.pi * 2.0**24) / 2.0**24
TWO_PI_A2 = 2 * np.pi - TWO_PI_A1
TWO_PI_B = 2.4492935982947064e-16


def add_turns(x, n):
    """x + 2 pi n (n whole turns) to the rounding of the result, for x small next to 2 pi n.

    >>> x = -0.357564167085735  # 1e6 less 159155 turns (the naive 1e6 - 159155 * 2 * np.pi is 8e-11 off)
    >>> float(x + 159155 * 2 * np.pi), float(add_turns(x, 159155.0))
    (999999.9999999999, 1000000.0)
    """
    if np.all(n == 0):
        return x
    return ((x + n * TWO_PI_B) + n * TWO_PI_A2) + n * TWO_PI_A1


def add_periods(x, n, P):
    """x + n P (P per component, or one) to the rounding of the result, for x small next to
    n P: whole turns by :func:`add_turns`, another period split into a head of 26 significant
    bits (n times it is exact for |n| < 2^26) and the rest.

    >>> float(add_periods(0.25, 3.0, 2 * np.pi)) == float(add_turns(0.25, 3.0)), float(add_periods(1.0, -2.0, 0.75))
    (True, -0.5)
    """
    if np.all(n == 0):
        return x
    whole, turns, head = _split(P)
    return np.where(whole, add_turns(x, n * turns), (x + n * (P - head)) + n * head)


def less_periods(u, k, P):
    """u - k P for u near k P (a far input brought back by whole periods: the large terms
    first, so the small result keeps its rounding).

    >>> float(less_periods(1e6, 159155.0, 2 * np.pi)), float(less_periods(1e6 + 0.5, 1e6, 1.0))
    (-0.357564167085735, 0.5)
    """
    whole, turns, head = _split(P)
    t = k * turns
    return np.where(whole, ((u - t * TWO_PI_A1) - t * TWO_PI_A2) - t * TWO_PI_B, (u - k * head) - k * (P - head))


def _within(u, lo, hi, P=None):
    """Whether lo <= u <= hi, or, with a period P of the input, u lies whole periods from such a value.

    >>> _within(7.0, 0.5, 1.0, 2 * np.pi), _within(7.0, 0.5, 1.0)
    (True, False)
    """
    return lo <= u <= hi if P is None else (u - lo) % P <= hi - lo


def _dips(model, g, targets, pick, ql, gap, edge):
    """The search past a gap's values ``pick`` (indices into ``targets``), their least-squares
    poses ``ql`` and gaps, with every target between the neighbours of each local minimum of
    the gap, before the first value that assembles, and (``edge``) between that value and the
    one before it, searched from ``g`` too and merged in order. An interval of the range
    narrower than the picks' spacing lies next to such a minimum: the gap falls towards it from
    both sides (a slider-crank whose short coupler reaches two intervals a turn, each 0.04-0.2
    rad wide: values tried every fourth walk step miss them); or just before the first value
    that assembles, where that assembles only in other modes (a Stephenson six-bar's interval
    [2.6174, 2.7456] in ours, the first pick that assembles at 2.803 in others). Not ``edge``
    for a linkage that is not :meth:`Walker.periodic`: a geared one closes at many poses in
    our modes, and an earlier value tried would choose another of its stretches to enter.

    >>> from planar.mechanisms import slider_crank
    >>> m = slider_crank(4.0, 0.15, offset=0.0, start=0.0).compile()
    >>> targets = np.arange(0.05, 3.3, 0.05)[:, None]   # past the limit at 0.0375 up to pi
    >>> pick = np.arange(0, targets.shape[0], 4)         # every fourth: none in [3.104, 3.179]
    >>> ql, gap = least_squares_gap(m, np.repeat(m.q0[None], pick.size, 0), targets[pick], decide=GAP)
    >>> bool(np.any(gap <= GAP))
    False
    >>> pick, ql, gap = _dips(m, m.q0, targets, pick, ql, gap, edge=True)
    >>> targets[pick[gap <= GAP], 0].round(2).tolist()
    [3.15]
    """
    near = np.flatnonzero(gap <= GAP)
    end = near[0] if near.size else pick.size
    if end < 1 or pick.size < 2:
        return pick, ql, gap
    left, right = np.r_[np.inf, gap[:-1]], np.r_[gap[1:], np.inf]
    dips = np.flatnonzero((gap <= left) & (gap <= right))
    dips = dips[dips < end]
    lo, hi = pick[np.maximum(dips - 1, 0)], pick[np.minimum(dips + 1, pick.size - 1)]
    if edge and end < pick.size:  # (and those before the first that assembles: the range may begin there in ours)
        lo, hi = np.r_[lo, pick[end - 1]], np.r_[hi, pick[end]]
    more = np.setdiff1d(np.concatenate([np.arange(a + 1, b) for a, b in zip(lo, hi)] + [np.zeros(0, int)]), pick)
    if not more.size:
        return pick, ql, gap
    more = more[np.unique(np.linspace(0, more.size - 1, min(more.size, MAX_SPREAD)).astype(int))]
    qm, gm = least_squares_gap(model, np.repeat(g[None], more.size, 0), targets[more], decide=GAP)
    order = np.argsort(np.r_[pick, more], kind="stable")
    return np.r_[pick, more][order], np.concatenate((ql, qm))[order], np.r_[gap, gm][order]


def _split(P):
    """Whether each P is whole turns, their number, and P's head of 26 significant bits."""
    turns = np.round(P / (2 * np.pi))
    frac, e = np.frexp(P)
    return np.abs(P - 2 * np.pi * turns) <= 4e-16 * np.abs(P), turns, np.ldexp(np.round(frac * 2.0**26) / 2.0**26, e)


def _symmetry(br):
    """See :meth:`Walker.symmetry`: from the sketch, the driven angle moved by k turns and a
    Newton solve at the input plus k turns, for k = 1 .. PERIODS; else :func:`_linear_symmetry`."""
    m, p = br.m, br.p
    if m.input_lengths.size != 1 or p.drivers.size != 1:
        return None
    q0, u0 = m.q0, m.u0
    s0 = br.signs(q0[None], u0[None])[0]
    if m.input_lengths[0]:  # (a length input turns nothing by whole turns of itself)
        return _linear_symmetry(br, s0)
    with np.errstate(all="ignore"):
        _, J = p.system.evaluate(q0[None], u0[None])
    row = J[0][p.rows[p.drivers[0]]]
    col = p.cols[np.argmax(np.abs(row[p.cols]))]  # the driven angle
    # (the PERIODS candidates in one batch: a solve costs about what one candidate's does)
    P = 2 * np.pi * np.arange(1.0, PERIODS + 1)
    U = u0[None] + P[:, None]
    G = np.repeat(q0[None], PERIODS, 0)
    with np.errstate(all="ignore"):
        Phi, _ = p.system.evaluate(G, U)
    G[:, col] -= Phi[:, p.rows[p.drivers[0]]] / row[col]
    qn, conv, _, _ = br.solve(G, U, max_iter=DISTANT)
    for k in np.flatnonzero(_in_modes(br, qn, U, conv, s0)):
        D = whole_turns(br, qn[k] - q0)
        if D is not None:
            return float(P[k]), D
    return _linear_symmetry(br, s0)


def _linear_symmetry(br, s0):
    """(P, D) of :meth:`Walker.symmetry` where the constraints read some coordinates only
    linearly: from the sketch along its tangent v (unit input rate) by P, Newton there, and the
    change d = D kept where each coordinate is back by whole turns (an angle), back (a position)
    or moved by P v (a coordinate read linearly), and the constraints unchanged by D away from
    the sketch too. P: a turn of the input (2 pi scaled), else the input that turns a body by a
    turn (a planetary train's carrier) or takes a point of uniform circular motion round (a
    wheel's centre rolling inside a circle: 2 pi speed / acceleration)."""
    m, p = br.m, br.p
    q0, u0 = m.q0, m.u0
    cols = p.cols
    with np.errstate(all="ignore"):
        v, a = (x[0] for x in br.state(q0[None], u0[None], np.ones((1, 1)))[:2])
    if not np.all(np.isfinite(v[cols]) & np.isfinite(a[cols])):
        return None
    known = np.zeros(m.n, bool)
    known[cols] = True
    rate = np.abs(v[2::3][known[2::3]])
    speed, acc = (np.hypot(x[0::3], x[1::3])[known[0::3] & known[1::3]] for x in (v, a))
    turn = 2 * np.pi / float(input_scale(m)[0])
    cands = np.r_[turn, 2 * np.pi / rate[rate > 1e-9 * turn], 2 * np.pi * speed[acc > 0] / acc[acc > 0]]
    # (a point at rest moves by rounding: its speed over its acceleration is no period)
    Ps = np.array(list(dict.fromkeys(float(x) for x in cands if np.isfinite(x) and x > 1e-6 * turn)))
    if not Ps.size:
        return None
    lins = np.zeros((Ps.size, m.n))
    lins[:, cols] = Ps[:, None] * v[cols]
    U = u0[None] + Ps[:, None]
    # (the candidates in one batch, then taken in turn)
    Q, conv, _, _ = br.solve(q0[None] + lins, U, max_iter=DISTANT)
    same = _in_modes(br, Q, U, conv, s0)
    for P, lin, q in zip(Ps[same], lins[same], Q[same]):
        P = float(P)
        d = q - q0
        D = whole_turns(br, d)
        if D is None:
            near = np.abs(d - lin) / m.col_scale <= SAME * (1.0 + np.abs(lin) / m.col_scale)
            back = whole_turns(br, np.where(near, 0.0, d))
            D = None if back is None else np.where(near, d, back)
        if D is not None and _invariant(br, P, D):
            return P, D
    return None


def _in_modes(br, Q, U, conv, signs):
    """(N,) whether each pose Q (N, n) at inputs U converged (``conv``) in the modes ``signs``
    (the modes asked only of the converged: a diverged pose reads non-finite)."""
    out = np.zeros(len(Q), bool)
    ok = np.flatnonzero(conv)
    if ok.size:
        out[ok] = np.all(br.signs(Q[ok], U[ok]) == signs, axis=1)
    return out


def _invariant(br, P, D):
    """Whether the shift by D at the input plus P also solves the constraints at a second pose
    of the branch, a fifth of a turn (scaled) from the sketch, to rounding of the shift: a
    symmetry of the branch, not only a pose that happens to solve."""
    m, p = br.m, br.p
    u = m.u0 + 0.2 * np.pi / input_scale(m)
    q_pred, _ = br.predict(m.q0[None], m.u0[None], (u - m.u0)[None])
    q, conv, _, _ = br.solve(q_pred, u[None], max_iter=DISTANT)
    if not conv[0]:
        return False
    with np.errstate(all="ignore"):
        Phi, _ = p.system.evaluate(add_periods(q, 1.0, D), add_periods(u, 1.0, P)[None])
    size = 1.0 + np.max(np.abs(D[p.cols]) / m.col_scale[p.cols])
    return bool(np.max(np.abs(Phi[0, p.rows]) * m.row_scale[p.rows]) <= 1e3 * np.finfo(float).eps * size)


def whole_turns(br, d, base=0.0, slack=0.0):
    """base + the change d - base (n,) of a pose rounded to whole turns of its angles, None
    where it is not whole turns (to SAME + ``slack``, scaled) or moves a position."""
    m, cols = br.m, br.p.cols
    dc = (d - base)[cols]
    turns = np.where(cols % 3 == 2, np.round(dc / (2 * np.pi)), 0.0)
    if not np.max(np.abs(dc - 2 * np.pi * turns) / m.col_scale[cols]) <= SAME + slack:
        return None
    D = np.zeros(m.n) + base
    D[cols] += 2 * np.pi * turns
    return D
