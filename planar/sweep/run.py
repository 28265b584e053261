"""The sweep's entry point (:func:`run_sweep`): the walk over the anchors, the bulk from them,
the rest one by one and the gaps walked back, each a pass of one sweep (:class:`_Run`) over the
arrays they share (its entries past gaps and out of reach: :mod:`planar.sweep.entries`); the
periods a far sweep moves its values by."""

import functools
from dataclasses import replace

import numpy as np

from planar.blocks import plan as block_plan
from planar.errors import InputError
from planar.sweep.anchors import (MAX_WAVE, WAVE, Kin, from_anchors, solve_stations, solve_wave, sweep_anchors,
                                  walk_anchors)
from planar.sweep.branch import Branch, input_scale, scaled_norm
from planar.sweep.checks import check_sketch, output_columns
from planar.sweep.entries import MAX_ENTRIES, Entries
from planar.sweep.finish import Out, finish
from planar.sweep.gaps import TURN
from planar.sweep.located import at_events, event_index, on_event, past_limit, same_event
from planar.sweep.order import apart, further, input_before, input_order, last_solved
from planar.sweep.periods import MODE_PERIODS, less_periods, whole_turns
from planar.sweep.walk import WALK_STEPS, Walker

FINER = 4  # finer anchors per walk anchor interval: Hermite error down ~4^6
HEAP_KEEP = (32 << 20) - (8 << 10)  # bytes: see _keep_freed_memory
SPARSE = 4  # anchors further apart than SPARSE * max_step are reached through stations, not tried in a wave
FAR = 100.0  # scaled input from the sketch beyond which a periodic input is solved periods back
ROCKING = 4 * np.pi  # the same for an input that rocks (its walk would meet two limits a period)


def run_sweep(model, U, Ud, Udd, start=None, *, tol=1e-12, max_step=0.05, outputs=None, branch="smooth", rates=True,
              engine="numpy", _nested=False, _reached=None, _bare=None):
    """See :meth:`planar.Model.sweep`. ``start``: a known pose (q, u) of the branch to walk
    from instead of the sketch, reached from the sketch by continuation with no event between
    (:mod:`planar.tracking` picks it); the sweep is then the one from the sketch. ``_nested``: a
    sweep made by another for what it asks of the branch (:func:`planar.sweep.entries.enter_by_images`,
    :func:`_period_by_sweep`), which makes no such sweeps itself (a Walker: the one of the sweep
    that made it, whose tracings round a circuit it shares). ``_reached``: a list, to
    which the sweep appends (N,) True for the values its walk reached from the start by
    continuation, before any limit, bifurcation or singular position, jump, direct entry or
    move by whole periods of an input that does not turn fully (what :mod:`planar.tracking`
    may remember). ``_bare``: a list, to which the sweep adds (limit event, (lo, hi)) for each
    stretch from a limit it met where its search past the gap found nothing that assembles, in
    any modes (none where it moved values by whole periods, nor on a linkage with a joint that
    ``rolls``, a geared one: it closes on many stretches, far apart, and least squares from the
    limit cannot tell that none reaches a value)."""
    if branch not in ("smooth", "other"):
        raise InputError(f"branch must be 'smooth' or 'other', got {branch!r}")
    options = dict(tol=tol, max_step=max_step, outputs=outputs, branch=branch, engine=engine)
    run = _Run(model, U, Ud, Udd, start, options, rates, _nested)
    run.walk_over_anchors()
    run.bulk()
    run.one_by_one()
    run.back_over_gaps()
    run.limit_pairs()
    res = run.result(_reached)
    if _bare is not None and run.shift is None and not any(j.rolls for j in model.joints):
        _bare.extend(run.bare)
    return res


class _Run(Entries):
    """One sweep's passes over the arrays they share (the poses ``q``, which values are
    ``solved``, the blocks' modes ``signs`` at each, the ``events`` met) and what its walks
    learn on the way (the limits met, the gaps searched, the values entered directly):
    :meth:`walk_over_anchors`, :meth:`bulk`, :meth:`one_by_one`, :meth:`back_over_gaps`,
    :meth:`limit_pairs` and :meth:`result`, in that order."""

    def __init__(self, model, U, Ud, Udd, start, options, rates, nested):
        max_step = options["max_step"]
        p = block_plan(model, output_columns(model, options["outputs"]))
        br = Branch(model, p, options["tol"], bool(rates), options["engine"])
        walker = Walker(br, max_step, options["branch"] == "other")
        if isinstance(nested, Walker):
            walker.share(nested)
        _keep_freed_memory()
        N = U.shape[0]
        self.model, self.p, self.br, self.walker, self.options, self.nested = model, p, br, walker, options, nested
        self.max_step, self.N = max_step, N
        self.q = np.empty((N, model.n))  # rows not posed at the end are set NaN then
        self.solved = np.zeros(N, bool)
        self.signs = np.zeros((N, len(p.blocks)), np.int8)  # the blocks' modes at each solved value
        self.events = []

        # far values of an input whose pose is periodic (the same up to whole turns of its angles,
        # or moved along the tangent where the rows read a coordinate linearly: an input that turns
        # fully, a rocking input's range a period on, a gear train) are solved whole periods back,
        # nearer the sketch, and shifted back at the end: angles of 1e6 rad would carry rounding of
        # 1e-10 rad into the constraints
        # (a rocking input's from two turns on: the walk through each period would meet its limits
        # and search past its gaps again, several seconds for a six-bar swept over +-20 rad)
        U_in, shift = U, None
        reach = np.max(np.abs(U[:, 0] - model.u0[0])) * input_scale(model)[0] if U.shape[1] == 1 else 0.0
        if reach > ROCKING:
            per = walker.period() or (None if nested else _period_by_sweep(model, walker, options))
            if per is not None and (reach > FAR or not walker.turns):
                start = None  # the sketch, whole periods back, is nearer than any known pose
                P, u0 = per[0], model.u0[0]
                if walker.turns:
                    block = P * np.ceil(FAR / (P * input_scale(model)[0]))
                    k = np.trunc((U[:, 0] - u0) / block) * (block / P)
                else:
                    # a rocking input: into the period that starts at a limit below the sketch's
                    # input (so two values in different periods have a limit between them)
                    c = walker.limit - np.ceil((walker.limit - u0) / P) * P
                    k = np.floor((U[:, 0] - c) / P)
                U = less_periods(U[:, 0], k, P)[:, None]
                shift = (k, per)

        self.chosen = br.signs(model.q0[None], model.u0[None])[0]
        if start is None:  # (a known pose was reached from the sketch: it passed)
            check_sketch(model, p)
        self.origin = (model.q0, model.u0, self.chosen) if start is None else (start[0], start[1], self.chosen)
        # values given out of order (one input) are solved in the order of the input, from the end
        # nearer the start, and put back in the asked order at the end: each is walked to from its
        # neighbour in input, where a jumping sweep would walk back and forth across the range and
        # search again for the range past each gap it meets
        # (values solved whole periods back: in the one period from a limit below the start, the
        # walk through it in the order of the input, as the walk through every period would go)
        order, split = input_order(U, self.origin[1][0], both=shift is None)
        self.side = np.where(np.arange(N) >= split, split, 0)  # the first value of each value's side of the start
        if order is not None:
            U, Ud, Udd, U_in = U[order], Ud[order], Udd[order], U_in[order]
            shift = None if shift is None else (shift[0][order], shift[1])
        self.U, self.Ud, self.Udd, self.U_in, self.shift, self.order, self.split = U, Ud, Udd, U_in, shift, order, split
        self.limits = []  # (limit event, direction of the input that hit it)
        self.round_limits = []  # the same, met only by the walk the other way round a period on
        self.entries = 0  # ranges entered at a gap's far end
        self.searched = []  # (input, direction, what) of the limits the gaps past which were searched
        self.bare = []  # (limit event, (lo, hi)): stretches from a limit where nothing assembles
        self.stops = []  # indices of the limits the walk stopped at, moving with the sweep
        self.direct = []  # values entered directly: too far to walk, or where the walk lost the branch
        self.past_cap = []  # values entered directly past MAX_GAPS gaps on the way to one value
        self.unentered = []  # values too far to walk where the branch's modes were not found
        self.periods = []  # values walked to moved by whole periods of a rocking input, past their limits
        self.anchors = np.union1d(sweep_anchors(model, U, max_step), np.arange(split, min(split + 1, N)))
        self.kin = Kin()  # the anchors' kinematic coefficients where known (one input)

    def walk(self, start, i, lo, back=None, periodic=True, to=None):
        """Walk from ``start`` (q, u, signs) to value i (or to the input ``to``); events get the
        index of the first value after ``lo`` at or past them (walking back from value ``back``
        >= i: the first value from i on at or past them in the sweep's own direction)."""
        model, U, walker, events, origin = self.model, self.U, self.walker, self.events, self.origin
        k = len(walker.events)
        got = walker.walk(*start, U[i] if to is None else to, int(i), periodic=periodic)
        if (got[0] == "far" and start is not origin
                and scaled_norm(model, U[i] - origin[1]) <= WALK_STEPS * self.max_step):
            # too far from that pose to walk, not from the sketch: walked from the sketch
            start = origin
            got = walker.walk(*start, U[i], int(i), periodic=periodic)
        if got[0] == "ok" and walker.jumped:
            self.periods.append(i)  # (moved by whole periods of a rocking input, past their limits: JUMPED)

        def index(u_star):
            if back is None:
                return event_index(U, lo, i, start[1], u_star)
            return event_index(U, i - 1, back, U[i], u_star)

        for j in range(k, len(walker.events)):
            ev = walker.events[j]
            if not any(same_event(ev, e, model) for e in events):
                events.append(replace(ev, index=index(ev.input)))
        if got[0] == "limit":
            ev = replace(got[1], index=index(got[1].input))
            if not any(same_event(ev, e, model) for e in events):
                events.append(ev)
            if back is None:  # (a limit met before too: value i, if re-entered, is past it all the same)
                self.stops.append(ev.index)
            # (each limit and direction once: the searches past gaps ask past() hundreds of times)
            _once(self.limits, (ev, np.sign(U[i] - start[1])))
            if walker.also is not None:  # (the other way round a limit too: both bound the value)
                _once(self.round_limits, walker.also)
        return got

    def further(self, failed, j, u_j, u):
        """:func:`planar.sweep.order.further`, where the walk to ``u`` goes the way the failed one did: not
        for a value more than half a turn away of an input with a period (the walk may go the
        other way round, a period on, nearer to one value than to another)."""
        if not further(failed, j, u_j, u):
            return False
        return not (self.U.shape[1] == 1 and abs(float(u[0] - u_j[0])) > np.pi and self.walker.period() is not None)

    def past(self, u_from, u_to, met=None):
        """A limit the walk met (``met``: those limits, else ``limits``) lies between u_from and
        u_to, periods of the input apart (asked only of values more than half a turn apart:
        nearer ones the walk goes to directly)."""
        met = self.limits if met is None else met
        far = met and self.U.shape[1] == 1 and np.any(np.abs(u_to - u_from) > np.pi)
        return past_limit(met, u_from, u_to, self.walker.period() if far else None)

    def walk_over_anchors(self):
        """1. The sequential walk over the anchors, from the assembled sketch (or the known pose
        given): in waves where they pass, step by step where not, each gap's far range entered
        where a sweep with values all the way would enter it; then the start's other side, and
        the ranges passed over for the origin's own stretch. The walk's place: anchor ``k``
        below the bound ``end`` (the start's first side, then its second; a range skipped
        before, up to its end), the pose ``at`` (q, u, modes) and its kinematic coefficients
        ``coef`` where known, the value ``lo`` walked from, the ``wave`` size."""
        self.at, self.coef = self.origin, None
        self.lo, self.k, self.wave = -1, 0, WAVE
        self.end = int(np.searchsorted(self.anchors, self.split))
        self.gaps = {}  # anchor index -> ranges entered at a gap's far end on the way to it
        self.skipped = []  # (k, upto, u): anchors past a gap from u, passed over for the origin's stretch further on
        self.unreached = []  # (k, upto, None): anchors the walk found no way into, tried again at the end
        second = self.split >= self.N  # (on the second side, or none)
        while True:
            while self.k < self.end:
                if not self.wave_on() and not self.walk_on():
                    self.unreached.append((self.k, self.end, None))
                    break
            if self.skipped:
                self.enter_passed(*self.skipped.pop())
            elif second and self.unreached:
                # (values solved since, on the other side of the start, may be their images)
                self.enter_passed(*self.unreached.pop())
            elif second:
                break
            else:
                # the other side of the start: walked from the start again
                second = True
                self.k, self.end = int(np.searchsorted(self.anchors, self.split)), self.anchors.size
                self.at, self.lo, self.coef, self.wave = self.origin, self.split - 1, None, WAVE

    def wave_on(self):
        """The anchors from k that the walk passes in one wave (or, to sparse ones, through
        stations): whether the walk goes on from there, else it takes anchor k itself."""
        model, U, q, solved, signs, br = self.model, self.U, self.q, self.solved, self.signs, self.br
        k, end, at, max_step = self.k, self.end, self.at, self.max_step
        idx = self.anchors[k : min(k + self.wave, end)]
        stop = np.flatnonzero(self.past(at[1][None], U[idx]) | on_event(model, U[idx], self.events))
        tried = stop[0] if stop.size else idx.size
        # an anchor several steps from the one before (sparse values) is not tried in a wave
        # (it would not reach it): it is reached through stations, or walked to
        far = np.flatnonzero(scaled_norm(model, np.diff(U[idx[:tried]], axis=0, prepend=at[1][None]))
                             > SPARSE * max_step)
        tried = far[0] if far.size else tried
        if tried == 0 and far.size:
            # sparse values: the stations between them in waves, many gaps a batch (each
            # within half a turn of the one before: the walk would go the direct way there)
            near = idx[: stop[0] if stop.size else idx.size]
            d = np.diff(U[near], axis=0, prepend=at[1][None])
            ok = (scaled_norm(model, d) < TURN) & np.all(np.abs(d) <= np.pi, axis=1)
            near = near[: int(np.argmin(ok)) if not ok.all() else near.size]
            b, qb, kb, last = solve_stations(br, at, U, near, max_step, self.coef)
            if last is not None:
                if b:
                    q[near[:b]], solved[near[:b]], signs[near[:b]] = qb, True, at[2]
                    if kb is not None:
                        self.kin.add(near[:b], *kb)
                    self.lo, self.k = near[b - 1], k + b
                self.at, self.coef = (last[0], last[1], at[2]), last[2]
                return True
        a, qa, ka = solve_wave(br, at, U, idx[:tried], self.coef)
        if a:
            q[idx[:a]], solved[idx[:a]], signs[idx[:a]] = qa, True, at[2]
            self.at, self.lo, self.k = (qa[-1], U[idx[a - 1]], at[2]), idx[a - 1], k + a
            if ka is not None:
                self.kin.add(idx[:a], *ka)
                self.coef = ka[0][-1], ka[1][-1]
        self.wave = min(2 * self.wave, MAX_WAVE) if a == idx.size else max(a, WAVE)
        # a wave that stopped part way goes on as a new wave from its last anchor (or through
        # stations, where it stopped short of a sparse one); the walk takes the anchor where
        # one accepted none (or where an event was located)
        return bool(self.k >= end or a == idx.size or 0 < a < tried or (a and far.size))

    def walk_on(self):
        """The walk to anchor k; where it is out of reach, the next anchor that assembles on
        the branch entered (:meth:`enter_out_of_reach`). False where none is."""
        model, U = self.model, self.U
        self.coef = None
        i = self.anchors[self.k]
        beyond = self.past(self.at[1][None], U[i][None])[0]
        got = ("lost",) if beyond else self.walk(self.at, i, self.lo)
        self.lo = i
        if at_events(model, U[i : i + 1], self.events):
            self.k += 1
            return True  # a value on a singular position is no pose to go on from
        if got[0] == "ok":
            self.q[i], self.solved[i], self.signs[i] = got[1], True, got[2]
            self.at = (got[1], U[i], got[2])
            self.k += 1
            return True
        if got[0] == "limit":
            self.at = (got[2][0], got[2][1], self.at[2])
        return self.enter_out_of_reach(got, beyond)

    def bulk(self):
        """2. Every other value from an anchor of its own stretch (no event in between): first a
        finer set of anchors, so that the interpolation is at rounding level for the rest."""
        model, U, Ud, Udd, q, solved, signs = self.model, self.U, self.Ud, self.Udd, self.q, self.solved, self.signs
        br, p, events, kin, N, split, anchors = self.br, self.p, self.events, self.kin, self.N, self.split, self.anchors
        max_step, tol, engine = self.max_step, self.options["tol"], self.options["engine"]
        at_event = at_events(model, U, events)
        solved[list(at_event)] = False
        out = Out(N, model.n, br.rates)
        q_pred = {}  # index -> the best guess of a value left for the walk
        done = np.zeros(N, bool)
        todo = ~solved  # all but the solved anchors and the values on events
        todo[list(at_event)] = False
        # (and the start between its two sides: each side's values from its own anchors)
        cuts = np.array(sorted({e.index for e in events if e.kind in ("limit", "bifurcation", "singular")}
                               | ({split} if split < N else set())), int)
        fill = dict(br=br, U=U, Ud=Ud, Udd=Udd, q=q, signs=signs, solved=solved, done=done, out=out, q_pred=q_pred,
                    cuts=cuts, kin=kin)
        if U.shape[1] == 1:
            finer, _ = walk_anchors(U, input_scale(model), max_step / FINER)
            finer = finer[todo[finer]]
            # their poses and modes only (the table needs no more): their rates and statuses come
            # with the bulk pass, which takes them again, or with the final step at the end
            from_anchors(anchors=anchors, targets=finer, **dict(fill, br=Branch(model, p, tol, False, engine)))
            finer = finer[solved[finer]]
            done[finer] = False
            anchors = np.union1d(anchors, finer)
            todo[finer] = False
        # the anchors too: their final step is due anyway, and the bulk's chunks become runs of
        # consecutive values (slices where the results are written, not scatters)
        from_anchors(anchors=anchors, targets=np.flatnonzero(todo | solved), **fill)
        self.out, self.q_pred, self.done = out, q_pred, done

    def one_by_one(self):
        """3. The rest one by one, from the solved value before each; values on an event or
        past a limit from there are set aside in one pass (out of range, there may be many)."""
        model, U, q, solved, signs, events = self.model, self.U, self.q, self.solved, self.signs, self.events
        origin, side, past = self.origin, self.side, self.past
        rest = np.flatnonzero(~solved)
        if rest.size:  # (the last solved value before each on its side of the start: N-sized, so only when needed)
            last = last_solved(solved, side)
            u_from = input_before(origin[1], U, last, rest, side)
            rest = rest[~on_event(model, U[rest], events) & ~past(u_from, U[rest])]
        failed, newest, failed_far = (None, None), -1, False
        for i in rest:
            if at_events(model, U[i : i + 1], events):
                continue
            j = max(int(last[i - 1]) if i > side[i] else -1, newest if newest >= side[i] else -1)
            j = None if j < 0 else j
            start = origin if j is None else (q[j], U[j], signs[j])
            if self.further(failed, j, start[1], U[i]):
                if failed_far:  # (further than a far value the search did not enter: as far out of reach)
                    self.unentered.append(i)
                continue  # the walk from this pose failed nearer that way already
            if past(start[1][None], U[i][None])[0]:
                continue  # a limit lies between
            got = self.walk(start, i, -1 if j is None else j)
            if got[0] == "far":
                got = self.enter_far(start, i)
            if got[0] == "limit" and self.entries < MAX_ENTRIES:
                got = self.enter_past(got[2], i, -1 if j is None else j)
            if got[0] != "ok":
                failed, failed_far = (j, U[i]), got[0] == "far"
                continue
            if at_events(model, U[i : i + 1], events):
                continue  # (the walk located a singular position at the value: no pose to go on from)
            q[i], solved[i], signs[i], newest = got[1], True, got[2], i

    def back_over_gaps(self):
        """Values still unreached past a gap in the range (re-entered further on): walked back
        from the solved value after them, so the branch is re-entered as far back as it reaches
        and the limit on the gap's far side is located."""
        model, U, q, solved, signs, events = self.model, self.U, self.q, self.solved, self.signs, self.events
        N, split, past = self.N, self.split, self.past
        rest = np.flatnonzero(~solved)
        if rest.size:
            nxt = np.minimum.accumulate(np.where(solved, np.arange(N), N)[::-1])[::-1]
        failed, newest = (None, None), N
        for i in rest[::-1]:
            j = min(int(nxt[i + 1]) if i + 1 < N else N, newest)
            j = N if i < split <= j else j  # (a value after i on its side of the start, or none)
            if j >= N or at_events(model, U[i : i + 1], events):
                continue
            if self.further(failed, j, U[j], U[i]) or past(U[j][None], U[i][None])[0]:
                continue
            got = self.walk((q[j], U[j], signs[j]), i, -1, back=j)
            if got[0] == "far":
                got = self.enter_far((q[j], U[j], signs[j]), i)
            if got[0] != "ok":
                failed = (j, U[i])
                continue
            if at_events(model, U[i : i + 1], events):
                continue  # (as in one_by_one)
            q[i], solved[i], signs[i], newest = got[1], True, got[2], i

    def limit_pairs(self):
        """A limit with no value between it and the re-entered branch (a pair of limits inside
        one step): the limit on the gap's far side, located walking back from the value past it,
        up to a turn of the input."""
        model, U, q, solved, signs, events = self.model, self.U, self.q, self.solved, self.signs, self.events
        origin, side, N, split, stops = self.origin, self.side, self.N, self.split, self.stops
        at_event = at_events(model, U, events)
        for f in {0, split} & set(stops):
            if f < N and solved[f] and f not in at_event and U.shape[1] == 1:
                # (the first value of a side of the start, past a limit pair from it: walked back
                # towards the start)
                self.walk((q[f], U[f], signs[f]), f, -1, back=f, periodic=False, to=origin[1])
        for j in dict.fromkeys(stops):  # (once each: a walk meets many limits on its way to one value)
            if side[j] < j < N and solved[j] and solved[j - 1] and j not in at_event and U.shape[1] == 1:
                reach = side[j] + np.flatnonzero(scaled_norm(model, U[side[j]:j] - U[j]) <= TURN)
                # (the direct way: only the limit it meets is wanted)
                a = int(reach[0] if reach.size else j - 1)
                got = self.walk((q[j], U[j], signs[j]), a, -1, back=j, periodic=False)
                # the values that walk passed over unsolved: another stretch of the branch, over
                # the same inputs, held the value before j, where the walk back past the gap
                # stopped (those are still that stretch's)
                over = np.arange(a, j)[~solved[a:j]]
                if got[0] == "limit":
                    u_star = float(np.ravel(got[1].input)[0])
                    over = over[(U[over, 0] - u_star) * (U[j, 0] - u_star) > 0]
                b = j
                for i in over[::-1]:
                    if at_events(model, U[i : i + 1], events):
                        continue
                    got = self.walk((q[b], U[b], signs[b]), i, -1, back=b, periodic=False)
                    if got[0] != "ok":
                        break
                    if not at_events(model, U[i : i + 1], events):  # (as in one_by_one)
                        q[i], solved[i], signs[i], b = got[1], True, got[2], i

    def result(self, _reached):
        """The :class:`planar.Sweep` (:func:`planar.sweep.finish.finish`): the values on events
        posed there, those out of the branch's reach, the jumps; ``_reached`` as
        :func:`run_sweep`'s."""
        model, U, Ud, Udd, U_in, q, solved, events = self.model, self.U, self.Ud, self.Udd, self.U_in, self.q, \
            self.solved, self.events
        br, walker, origin, side, N, max_step, past = self.br, self.walker, self.origin, self.side, self.N, \
            self.max_step, self.past
        out, q_pred, done, order, shift = self.out, self.q_pred, self.done, self.order, self.shift
        limits, direct, stops, periods, past_cap = self.limits, self.direct, self.stops, self.periods, self.past_cap
        at_event = at_events(model, U, events)
        for i, ev in at_event.items():
            q[i], solved[i], done[i] = ev.q, True, True
        events.sort(key=lambda e: e.index)
        # values left unsolved past a limit the walk met (from the solved value before them) are
        # out of the branch's reach, however small their least-squares gap (the limits met the
        # other way round a period on count here only: they are not the branch's events there)
        beyond = np.zeros(N, bool)
        miss = np.flatnonzero(~solved)
        if miss.size and limits:
            # (a value entered directly, too far to walk, is no walk's start: the gaps between it
            # and the value are not known)
            walked = solved.copy()
            walked[direct] = False
            last = last_solved(walked, side)
            beyond[miss] = past(input_before(origin[1], U, last, miss, side), U[miss], limits + self.round_limits)
        # (and those too far to walk where the search found other modes or nothing: out of the
        # branch's reach as far as it knows, whatever their least-squares gap)
        beyond[np.intersect1d(miss, self.unentered).astype(int)] = True
        jumps = (stops + direct + periods + past_cap, None)
        if order is not None:
            # values asked one after the other with a limit the walk met between them (the direct
            # way), or entered too far to walk: a jump
            inv = np.empty_like(order)
            inv[order] = np.arange(N)
            prev = np.where(order > 0, inv[np.maximum(order - 1, 0)], -1)  # the value asked before each
            cand = np.flatnonzero(prev >= 0)
            if limits and cand.size:
                # (either way: asked back over a limit the walk met, the two are on different stretches)
                a, b = U[prev[cand]], U[cand]
                cand = cand[past_limit(limits, a, b) | past_limit(limits, b, a)]
            cand = cand if limits else np.zeros(0, int)
            # (a value entered directly is a jump from the value asked before it where that one too
            # is out of the walk's reach)
            reach = WALK_STEPS * max_step
            far = [j for j in direct if prev[j] >= 0 and scaled_norm(model, U[j] - U[prev[j]]) > reach]
            # (and one on the other side of a move by whole periods of a rocking input)
            moved = apart(np.cumsum(np.isin(np.arange(N), periods)), prev)
            jumps = (np.union1d(np.union1d(cand, far), np.union1d(moved, past_cap)).astype(int), prev)
        if shift is not None and not walker.turns:
            # values of a rocking input solved whole periods back: one in another period than the
            # value asked before it has the limit that starts its period between them
            before = prev if order is not None else np.arange(N) - 1
            jumps = (np.union1d(jumps[0], apart(shift[0], before)).astype(int), jumps[1])
        if _reached is not None:
            # (values solved whole periods back are a move by whole periods from the start)
            cut = stops + direct + periods + past_cap + [e.index for e in events
                                                         if e.kind in ("limit", "bifurcation", "singular")]
            reached = np.arange(N) < (0 if shift is not None and not walker.turns else min(cut, default=N))
            _reached.append(reached if order is None else reached[np.argsort(order)])
        if isinstance(self.nested, Walker):
            self.nested.rounds = walker.rounds
        return finish(model, br, U, Ud, Udd, q, solved, done, out, q_pred, events, at_event, beyond, jumps, U_in, shift,
                       order, origin[1])


def _once(met, limit):
    """Append (limit event, direction) to ``met`` unless it holds that limit and direction."""
    ev, d = limit
    u = np.atleast_1d(ev.input)
    if not any(np.array_equal(np.atleast_1d(e.input), u) and np.array_equal(s, d) for e, s in met):
        met.append(limit)


def _period_by_sweep(model, walker, options):
    """(P, D) of the input's period where the walk from the sketch over the symmetry's periods
    (:meth:`planar.sweep.walk.Walker.period`) meets a limit before it is back in the sketch's
    modes: the first of up to MODE_PERIODS of them after which the sweep from the sketch (with
    its re-entries past gaps) is back at the sketch's pose, up to whole turns, and modes (a Watt
    six-bar whose smooth branch passes a change point every turn, in modes that meet a limit
    pair every other turn: two). Kept as the walker's period; None if there is none."""
    sym = walker.symmetry()
    if sym is None:
        return None
    P = sym[0]
    V = model.u0[0] + P * np.arange(1.0, MODE_PERIODS + 1)[:, None]
    zero = np.zeros_like(V)
    res = run_sweep(model, V, zero, zero, rates=False, _nested=True, **options)
    s0 = walker.br.signs(model.q0[None], model.u0[None])[0]
    for j in np.flatnonzero(res.ok):
        q = np.where(np.isnan(res.q[j]), model.q0, res.q[j])  # (columns the outputs leave unsolved)
        D = whole_turns(walker.br, q - model.q0, (j + 1) * sym[1])
        if D is not None and np.all(walker.br.signs(q[None], V[j][None])[0] == s0):
            lims = [float(np.ravel(e.input)[0]) for e in res.events if e.kind == "limit"]
            walker.keep_period((j + 1) * P, D, lims[0] if lims else None)
            return walker.period()
    return None


@functools.cache
def _keep_freed_memory():
    """Once per process, free one untouched block of HEAP_KEEP bytes, so that glibc's malloc
    keeps what a sweep frees for its next chunk and its next call instead of handing it back to
    the system: its mmap threshold follows the largest mmapped block freed, up to 32 MiB and
    only for blocks no larger than that (hence 8 KiB under it: malloc's header and page
    rounding), and it trims the heap's free top beyond twice that (64 MiB), above a numpy
    sweep's heap at N = 1e5. Below it, each chunk and each call faulted its memory in afresh.
    The threshold only rises, so once is enough. The process may keep up to 2 HEAP_KEEP of
    freed memory; with other allocators this costs one mmap and munmap."""
    np.empty(HEAP_KEEP, np.uint8)
