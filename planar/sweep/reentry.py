"""Re-entry of the branch past a gap (:class:`Reentry`, the :class:`planar.sweep.walk.Walker`'s):
a batched least-squares search of the values past it, the dips and folds of its gap, Newton
from poses solved elsewhere and from the values' images whole periods back, and the way round
a circuit through a limit."""

import numpy as np

from planar.events.crossing import around
from planar.solver import GAP, REENTRY, RESTARTED, least_squares_gap, newton, rounding
from planar.sweep.branch import scaled_norm
from planar.sweep.periods import SAME, add_periods, in_modes, whole_turns, within

SPREAD = 4  # walk steps between the values a search past a gap tries, at most (0.2 rad by default)
MAX_SPREAD = 256  # values it tries spread over the rest, at most
# inputs tried between the neighbours of a dip of the gap that has no target between them, and
# such dips tried a search, at most (see _folds)
BETWEEN, MAX_DIPS = 8, 4
FOLD_LEVELS = 3  # narrowings of a fold's search onto its least gap (8 inputs, then 8 of 1/9 the spacing...)
RESTARTS = 64  # guesses of a re-entry that landed in other modes, from its pose with angles drawn at random


class Reentry:
    """The :class:`planar.sweep.walk.Walker`'s ways into its branch where a walk cannot go on."""

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
            ours = np.flatnonzero(in_modes(br, qn, T, conv, signs))
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
            covered = any(np.array_equal(found, f) and within(target[0], lo, hi, P) for f, (lo, hi), P in self._round)
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
        ours = np.flatnonzero(in_modes(br, qn, T, conv, signs))
        if not ours.size:
            return None
        return qn[ours[np.argmin(np.max(np.abs(qn[ours][:, p.cols] - root[p.cols]) / br.m.col_scale[p.cols], axis=1))]]


def _dips(model, g, targets, pick, ql, gap, edge):
    """The search past a gap's values ``pick`` (indices into ``targets``), their least-squares
    poses ``ql`` and gaps, with every target between the neighbours of each local minimum of
    the gap, before the first value that assembles, and (``edge``) between that value and the
    one before it, searched from ``g`` too and merged in order. An interval of the range
    narrower than the picks' spacing lies next to such a minimum: the gap falls towards it from
    both sides (a slider-crank whose short coupler reaches two intervals a turn, each 0.04-0.2
    rad wide: values tried every fourth walk step miss them); or between two picks where the
gap falls towards it as steeply as it rises just outside them (a two-loop six-bar's interval
[-0.9913, -0.9388] between picks at -0.849 and -1.042, the gap level at 5e-4 from the limit
at -0.639 to -0.849: no minimum at a pick); or just before the first value
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
    # and between two neighbouring picks where the gap may fall to zero between them as a V
    # whose sides are as steep as the steeper of its slopes just outside them: the sum of
    # their gaps within that slope times their distance (a dip that shows no minimum at the
    # picks, the gap level on one side of it and rising on the other)
    d = scaled_norm(model, np.diff(targets[pick], axis=0))
    slope = np.divide(np.abs(np.diff(gap)), d, out=np.zeros_like(d), where=d > 0)
    steep = np.maximum(np.r_[0.0, slope[:-1]], np.r_[slope[1:], 0.0])
    vee = np.flatnonzero(gap[:-1] + gap[1:] <= steep * d)
    vee = vee[vee + 1 < end]
    lo, hi = np.r_[lo, pick[vee]], np.r_[hi, pick[vee + 1]]
    if edge and end < pick.size:  # (and those before the first that assembles: the range may begin there in ours)
        lo, hi = np.r_[lo, pick[end - 1]], np.r_[hi, pick[end]]
    more = np.setdiff1d(np.concatenate([np.arange(a + 1, b) for a, b in zip(lo, hi)] + [np.zeros(0, int)]), pick)
    if not more.size:
        return pick, ql, gap
    more = more[np.unique(np.linspace(0, more.size - 1, min(more.size, MAX_SPREAD)).astype(int))]
    qm, gm = least_squares_gap(model, np.repeat(g[None], more.size, 0), targets[more], decide=GAP)
    order = np.argsort(np.r_[pick, more], kind="stable")
    return np.r_[pick, more][order], np.concatenate((ql, qm))[order], np.r_[gap, gm][order]
