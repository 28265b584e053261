"""How a sweep enters its branch where its walk cannot go: past a gap in the range (where a
sweep with values all the way would enter it), a whole period on from a value solved, from the
sweep of a value's images a period back, back at the origin's own stretch, or directly where a
value is too far to walk to. :class:`Entries` holds these passes of one sweep's run
(:class:`planar.sweep.run._Run` is one), on the arrays it shares."""

import numpy as np

from planar.sweep.anchors import WAVE
from planar.sweep.branch import input_scale, scaled_norm
from planar.sweep.gaps import TURN, images, past_gap, steps_out
from planar.sweep.located import on_event, past_limit
from planar.sweep.reentry import SPREAD

MAX_ENTRIES = 64  # ranges a sweep enters at a gap's far end; further gaps are entered at the values asked
# ranges entered at a gap's far end on the way to one value: past more gaps (a geared linkage's
# limit pairs every few radians between far values) the value itself is entered, JUMPED either way
MAX_GAPS = 8
GUESSES = 64  # poses solved that a value too far to walk to is entered from, at most


class Entries:
    """The entries of one sweep's run: methods of :class:`planar.sweep.run._Run`, on its
    arrays (``q``, ``solved``, ``signs``, the ``anchors`` and the walk's place ``k``, ``end``,
    ``at``) and what its walks learned (``limits``, ``searched``, ``entries``, ``gaps``)."""

    def enter_out_of_reach(self, got, beyond):
        """Anchor k out of the walk's reach (``got`` the walk's result; ``beyond``: past a limit
        met before): the next anchor that assembles on the branch entered, a whole period on
        from a value solved, else by one batched search, else (where only another circuit or
        mode assembles there) a period the other way round from the sketch. False where none
        is."""
        model, U, q, solved, signs, walker, chosen = (self.model, self.U, self.q, self.solved, self.signs, self.walker,
                                                      self.chosen)
        k = self.k
        found = self.by_period(k, self.end)
        end, anchors = self.end, self.anchors
        bare = None  # (lo, hi) of inputs the search from the limit found nothing assembling in
        far_end = self.entries < MAX_ENTRIES and self.gaps.get(anchors[k], 0) < MAX_GAPS
        if found is None and got[0] == "limit" and far_end:
            entered, bare = self.enter_far_end(got)
            if entered:
                return True
        homed = found is None and got[0] != "far" and not self.nested
        if homed:
            # the origin's own stretch come back to from elsewhere (past a gap, from another
            # interval of the range): walked to from the origin, no limit the walk met between
            found = self.home(k, end)
        upto = end if found is None else k + found[0]
        guesses = [model.q0, self.at[0]] if got[0] == "far" else [self.at[0], model.q0]
        # (one input: every value from anchor k on, not the anchors only: an interval of the
        # range narrower than their spacing may hold values and no anchor)
        seg = np.arange(anchors[k], anchors[upto - 1] + 1) if upto > k and U.shape[1] == 1 else anchors[k:upto]
        if bare is not None:  # (not again where the search from the limit, from the same guesses, found none)
            seg = seg[~((U[seg, 0] >= bare[0]) & (U[seg, 0] <= bare[1]))]
        nearer, assembles = (walker.enter_any(guesses, chosen, U[seg], poses=self.solved_poses(),
                                              circuit=got[0] != "far") if seg.size else (None, False))
        if seg.size and nearer is None and not assembles and got[0] == "limit" and far_end:
            # where no value asked assembles at all (the first in the gap, least squares from
            # there lands nowhere beyond it), the walk steps from the limit out to the values: a
            # sweep with values all the way enters the range between them
            steps = steps_out(model, self.at[1], U[seg], self.max_step, bare)
            if steps is not None:
                # (what assembles there, in any modes, is as good a sign for the images below)
                ahead, assembles = walker.enter_any(guesses, chosen, steps, poses=self.solved_poses())
                if ahead is not None:
                    self.enter_ahead(seg, steps[ahead[0]], ahead[1], upto)
                    return True
        # (entered past gaps not walked through, MAX_GAPS met on the way: a jump, whatever
        # limits the walk met between it and the value asked before it)
        capped = got[0] == "limit" and not far_end and nearer is not None
        if nearer is not None:
            found, homed = (self.anchor_at(seg[nearer[0]]) - k, nearer[1], chosen), False
        if found is None and assembles and not self.nested:
            found = enter_by_images(model, walker, U[self.anchors[k:self.end]], self.at[1], chosen, self.options)
        if found is None and got[0] == "limit" and far_end and U.shape[1] == 1:
            found = self.enter_beyond(got[1])
        if found is None:
            return False
        c, qe, se = found
        if homed and c:
            # (not where the search from the limit found nothing assembling)
            passed = U[self.anchors[k : k + c], 0]
            if bare is None or np.any((passed < bare[0]) | (passed > bare[1])):
                self.skipped.append((k, k + c, self.at[1]))
        k += c
        i = self.anchors[k]
        qe = qe if homed else walker.near_turns(qe, U[i], se, self.at[0])
        q[i], solved[i], signs[i] = qe, True, se
        if got[0] == "far" or (got[0] == "lost" and not beyond):
            # (too far to walk, or where the walk lost the branch: entered, not walked to)
            self.direct.append(i)
        elif capped:
            self.past_cap.append(i)
        self.at, self.lo, self.k = (qe, U[i], se), i, k + 1
        return True

    def enter_far_end(self, got):
        """The range past the gap at the limit the walk met (``got``) towards anchor k entered
        at its far end, as a sweep with values all the way enters it: the first of the walk's
        steps past the limit where the branch can be entered, and walked on from there.
        (whether entered, the (lo, hi) of inputs past the limit where nothing assembles or None)."""
        model, U, walker, chosen, at = self.model, self.U, self.walker, self.chosen, self.at
        a = self.anchors[self.k]
        self.first_search(at[1], U[a])
        grid = past_gap(model, at[1], U[a], self.max_step)
        if grid.size and scaled_norm(model, U[a] - at[1]) <= TURN:
            grid = np.vstack((grid, U[a][None]))  # (and the value itself, a step or so on)
        nearer, assembles = (walker.enter_any([at[0], model.q0], chosen, grid, poses=self.solved_poses())
                             if grid.size else (None, True))
        if nearer is None:  # (from the limit, past the pose before it, to the last step)
            if assembles:
                return False, None
            bare = np.sort([float(np.ravel(got[1].input)[0]), float(grid[-1, 0])])
            self.bare.append((got[1], bare))
            return False, bare
        self.entries += 1
        self.gaps[a] = self.gaps.get(a, 0) + 1
        u_e = grid[nearer[0]]
        self.at, self.coef = (walker.near_turns(nearer[1], u_e, chosen, at[0]), u_e, chosen), None
        return True, None

    def enter_beyond(self, limit):
        """(0, pose, modes) of anchor k's value, within SPREAD walk steps past the limit the
        walk met, reached by the walk back to it from the range entered at the walk's steps
        from the limit out to SPREAD steps, past the value: as a sweep with values on past it
        enters there and walks back. Where the range past the limit starts before it (a fold
        and the stretch back from it, narrower than a step: a geared five-bar's limits 1.82971
        and 1.83134), least squares at a value just past the limit lands on the fold's side,
        and only further on on the stretch beyond. None where nothing is entered there or the
        walk back meets a limit (``limit``, the event; once a sweep each way past it)."""
        model, U, at, chosen = self.model, self.U, self.at, self.chosen
        a = self.anchors[self.k]
        d = float(U[a, 0] - at[1][0])
        h = self.max_step / float(input_scale(model)[0])
        if abs(d) > SPREAD * h or not self.first_search(np.atleast_1d(limit.input), U[a], "beyond"):
            return None
        grid = past_gap(model, at[1], at[1] + np.sign(d) * (SPREAD + 1) * h, self.max_step)
        grid = grid[np.sign(d) * (grid[:, 0] - U[a, 0]) > 0]
        for ev, (lo, hi) in self.bare:  # (not where the search past the limit found nothing, from the same guesses)
            if scaled_norm(model, np.atleast_1d(ev.input) - np.atleast_1d(limit.input)) <= 1e-9:
                grid = grid[(grid[:, 0] < lo) | (grid[:, 0] > hi)]
        nearer, _ = (self.walker.enter_any([at[0], model.q0], chosen, grid, poses=self.solved_poses())
                     if grid.size else (None, False))
        if nearer is None:
            return None
        n = len(self.walker.events)
        got = self.walker.walk(nearer[1], grid[nearer[0]], chosen, U[a], a)
        if got[0] != "ok":
            del self.walker.events[n:]  # (what the tracer met on a way not taken)
            return None
        return 0, got[1], got[2]

    def enter_ahead(self, seg, u_e, qe, upto):
        """The range between the limit and the values ``seg`` entered at the walk's step u_e
        out from the limit (pose qe there): the first value on from it an anchor (the walk from
        the entry solves it, and the stretch's values from it); the anchors before it, in the
        gap or reached back from it, are left to the walk back from the values after them."""
        U, k = self.U, self.k
        self.entries += 1
        self.gaps[self.anchors[k]] = self.gaps.get(self.anchors[k], 0) + 1
        d = np.sign(u_e[0] - self.at[1][0])
        v = seg[d * (U[seg, 0] - u_e[0]) >= 0][:1]
        c = int(np.searchsorted(self.anchors, v[0])) if v.size else self.end
        if v.size and self.anchors[c] != v[0]:
            self.anchors, self.end, upto = np.insert(self.anchors, c, v[0]), self.end + 1, upto + 1
        self.k = k + int(np.argmin(np.r_[d * (U[self.anchors[k:upto], 0] - u_e[0]) < 0, False]))
        self.at, self.coef = (self.walker.near_turns(qe, u_e, self.chosen, self.at[0]), u_e, self.chosen), None

    def enter_passed(self, k0, end, u_gap):
        """A range of anchors passed over (for the origin's stretch further on, past a gap from
        ``u_gap``) or found no way into (``u_gap`` None): entered a whole period on from a value
        solved since, or, passed over, from the sweep of its images a period back where some lie
        in the origin's stretch (no limit met between), and walked on from there. A range the
        search past a gap found nothing in (least squares from the limit stops in another valley)
        may hold the image of an interval entered since (a two-loop six-bar's [6.6658, 6.6879]
        past its limit at 6.3362: [0.3826, 0.4047], entered from the other side of the start)."""
        self.k, self.end = end, end
        found = self.by_period(k0, end)
        if found is None and u_gap is not None and not self.nested:
            V = images(self.model, self.walker, self.U[self.anchors[k0:end]], u_gap)
            if V is not None and np.any(~self.past(self.origin[1][None], V[0])
                                        & (scaled_norm(self.model, V[0] - self.origin[1]) <= TURN)):
                found = enter_by_images(self.model, self.walker, self.U[self.anchors[k0:end]], u_gap, self.chosen,
                                         self.options)
        if found is not None:
            c, qe, se = found
            i = self.anchors[k0 + c]
            self.q[i], self.solved[i], self.signs[i] = qe, True, se
            self.k, self.at, self.lo, self.coef, self.wave = k0 + c + 1, (qe, self.U[i], se), i, None, WAVE

    def by_period(self, k, end):
        """(index from anchor k, pose, modes) of the first value from anchor k on (below
        ``end``) entered a whole period on from a value solved (:meth:`Walker.enter_by_period`),
        made an anchor if it is none; None if none is. Every value, not the anchors only: an
        interval of the range narrower than their spacing may hold values and no anchor."""
        anchors = self.anchors
        seg = np.arange(anchors[k], anchors[end - 1] + 1) if self.U.shape[1] == 1 else anchors[k:end]
        known = np.flatnonzero(self.solved)
        found = self.walker.enter_by_period(self.q[known], self.U[known], self.signs[known], self.U[seg])
        if found is None:
            return None
        c, qe, se = found
        return self.anchor_at(seg[c]) - k, qe, se

    def anchor_at(self, i):
        """The index of value i among the anchors, made one where it is not (a value between them)."""
        c = int(np.searchsorted(self.anchors, i))
        if c == self.anchors.size or self.anchors[c] != i:
            self.anchors, self.end = np.insert(self.anchors, c, i), self.end + 1
        return c

    def home(self, k, end, tries=3):
        """(index from k, pose, modes) of the first anchor from k (below ``end``) that the walk
        reaches from the origin with no limit it met between, or None (a walk that meets a new
        limit on the way tries the next such anchor)."""
        origin = self.origin
        for _ in range(tries):
            # (within a turn, not a value on an event: a limit's pose is no pose to go on from;
            # nor past a limit met the direct way, the way this walk goes)
            V = self.U[self.anchors[k:end]]
            c = np.flatnonzero(~past_limit(self.limits, origin[1][None], V) & ~on_event(self.model, V, self.events)
                               & (scaled_norm(self.model, V - origin[1]) <= TURN))
            if not c.size:
                return None
            # (the direct way: a limit it meets is then one between the origin and the values)
            got = self.walk(origin, self.anchors[k + c[0]], -1, periodic=False)
            if got[0] == "ok":
                return int(c[0]), got[1], got[2]
            if got[0] != "limit":
                return None
        return None

    def enter_far(self, start, i):
        """Value i, too far from ``start`` to walk with no period to shorten the way, entered
        directly in the sketch's modes: past every gap between, the walk would re-enter the
        branch in them, and within a stretch it keeps them."""
        # (its angles counted as the sketch's first; then from up to GUESSES poses solved; not
        # round a circuit, ~100s of solves for one of the many stretches a direct entry may land on)
        qe = self.walker.enter([self.model.q0, self.snapped(start[0])], self.chosen, self.U[i], self.solved_poses(),
                               circuit=False)
        if qe is None:
            self.unentered.append(i)
            return ("far",)
        self.direct.append(i)  # (not reached continuously from the value before it: JUMPED)
        return "ok", qe, self.chosen

    def enter_past(self, limit, i, lo):
        """Value i past the limit ``limit`` (its pose and input) the walk to it met: the range
        past the gap entered where a sweep with values all the way would enter it (the walk's
        steps past the limit, and the value), and walked to i from there; i is not reached
        continuously (JUMPED). ("limit",) where the search finds no entry."""
        U, chosen = self.U, self.chosen
        if not self.first_search(limit[1], U[i]):
            return ("limit",)
        grid = np.vstack((past_gap(self.model, limit[1], U[i], self.max_step), U[i][None]))
        nearer, _ = self.walker.enter_any([limit[0], self.model.q0], chosen, grid, poses=self.solved_poses())
        if nearer is None:
            return ("limit",)
        self.entries += 1
        c, qe = nearer[0], self.walker.near_turns(nearer[1], grid[nearer[0]], chosen, limit[0])
        got = ("ok", qe, chosen) if c == len(grid) - 1 else self.walk((qe, grid[c], chosen), i, lo)
        if got[0] == "ok":
            self.direct.append(i)
        return got

    def first_search(self, u_limit, u, what="gap"):
        """Whether the gap past the limit at ``u_limit`` towards u is searched for the first
        time (it then counts as searched): each limit's gap each way once a sweep, the main
        walk's search past it having found what there is to enter (``what``: the search, the
        gap's or :meth:`enter_beyond`'s)."""
        way = float(np.sign(u[0] - u_limit[0]))
        if any(w == way and k == what and abs(v - u_limit[0]) <= 1e-9 / input_scale(self.model)[0]
               for v, w, k in self.searched):
            return False
        self.searched.append((float(u_limit[0]), way, what))
        return True

    def solved_poses(self):
        """Up to GUESSES of the poses solved, spread over them: where a search's guesses land
        in other modes, Newton from one of these may land in ours (:meth:`Walker.enter`)."""
        known = np.flatnonzero(self.solved)
        return self.snapped(self.q[known[np.linspace(0, known.size - 1, min(known.size, GUESSES)).astype(int)]]
                            if known.size else self.q[:0])

    def snapped(self, Q):
        """Poses to 1e-9 of their scales, as guesses from afar: both engines give them alike,
        where their poses differ at rounding and Newton from afar may land on another pose of
        the loop for that alone."""
        return np.round(Q / self.model.col_scale, 9) * self.model.col_scale


def enter_by_images(model, walker, targets, u, signs, options):
    """(index, pose, modes) of the first of ``targets`` (M, 1), past a gap from ``u``, whose
    image whole periods back (or on: the first just past the sketch, the other way round) the
    sweep from the sketch reaches, its pose moved those periods on (back). The search past a
    gap may find only other circuits where the branch's range a period on is re-entered the
    other way round (a Watt six-bar's second interval: its image a turn back lies past the
    limit the sketch sits next to). None if the input has no period or none is reached."""
    found = images(model, walker, targets, u)
    if found is None:
        return None
    V, n = found
    for W, res in walker.images:
        # (a later search past a gap asks for some of an earlier one's images: its sweep holds them)
        at = {float(w): i for i, w in enumerate(W[:, 0])}
        rows = [at.get(float(v)) for v in V[:, 0]]
        if None not in rows:
            ok, Q = res.ok[rows], res.q[rows]
            break
    else:
        zero = np.zeros_like(V)
        from planar.sweep.run import run_sweep  # (a nested sweep: run imports this module)

        res = run_sweep(model, V, zero, zero, rates=False, _nested=walker, **options)
        walker.images.append((V, res))
        ok, Q = res.ok, res.q
    for c in V.shape[0] - 1 - np.flatnonzero(ok[::-1])[:4]:
        # (columns the outputs leave unsolved are not the plan's: any value does)
        q = np.where(np.isnan(Q[c]), model.q0, Q[c])
        got = walker._shorten(q, V[c], signs, n)
        if got is not None:
            return V.shape[0] - 1 - int(c), got[0], signs
    return None
