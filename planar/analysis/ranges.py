"""Motion range of a one-input mechanism: every interval of the input where it assembles.

The input is swept from the sketch over one turn (an angle) or over a travel both ways (a
length). Each stretch of values that assembles on the chosen branch (the block assembly modes
of the sketch) is an interval; its ends are limit positions, located by the sweep's arclength
tracer where the branch runs into them, and by walking back from the first value of a stretch
the sweep re-entered. Disjoint intervals stay apart (the seed's merged slider-crank ranges
come out as the two intervals they are). :func:`swept_ranges` reads the same intervals off a
sweep already made, as far as it went.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> [np.round(np.degrees(iv), 6).tolist() for iv in motion_range(four_bar(4, 3, 3, 2.5))]
[[-102.635625, 102.635625]]
"""

import numpy as np

from planar import arguments
from planar.blocks import plan as block_plan
from planar.errors import InputError
from planar.results import POSED, Status, as_sweep
from planar.sweep import Branch, Walker, input_scale
from planar.sweep.periods import whole_turns
from planar.sweep.walk import WALK_STEPS

TURN = 2 * np.pi
# sweep values per turn or per travel: far more than any range needs (its ends are located
# events, not samples); a four-bar's range of 1e5 took 3-6 s, of 1e6 over 40 s and 640 MB
MAX_SAMPLES = 10**4
# turns of an angle input whose pose does not repeat each turn (a rack's travel, a geared
# linkage) looked along for the ends of the sketch's stretch: one walk's reach at the default
# step (planar.sweep.walk.WALK_STEPS)
FAR_TURNS = 15


def motion_range(mechanism, *, travel=None, samples=720, tol=1e-12, max_step=0.05):
    """Intervals (lo, hi) of the one input where ``mechanism`` assembles on its sketched branch.

    Parameters
    ----------
    mechanism : planar.Mechanism or planar.Model
    travel : float, optional
        For a length input: how far to look each way from the sketch (default: twice the sum
        of the model's characteristic length over its bodies, beyond any reachable travel).
    samples : int
        Sweep values per turn (or per travel): intervals shorter than a sample step can be
        missed.

    Returns
    -------
    tuple of (float, float)
        Sorted intervals; an angle interval starts in [-pi, pi) and may run past pi; a full
        turn is ``((-pi, pi),)``. Ends are limit positions, to about 1e-12. Where the sketch's
        stretch runs a turn and its pose does not repeat (a rack or a gear drives a linkage),
        the input's own ends, within ``FAR_TURNS`` turns of the sketch's input each way.
    """
    model = mechanism.compile() if hasattr(mechanism, "compile") else mechanism
    if not hasattr(model, "drivers"):
        raise InputError(f"motion_range needs a Mechanism or a Model, got {type(mechanism).__name__}")
    if len(model.drivers) != 1:
        raise InputError(f"motion_range needs exactly one input; {model.name!r} has {list(model.input_names)}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"motion_range samples must be a whole number from 2 to {MAX_SAMPLES:g} (values per turn "
                         f"or per travel; the default is 720), got {samples!r}")
    tol, max_step = arguments.tolerance(tol), arguments.max_step(max_step)  # (numpy's uint8 overflowed in the walk)
    u0 = float(model.u0[0])
    if travel is not None and not model.input_lengths[0]:
        raise InputError(f"motion_range travel is for a length input; {model.input_names[0]!r} is an angle, looked "
                         f"for over a turn: leave travel out, got {travel!r}")
    if model.input_lengths[0]:
        R = _travel(travel) if travel is not None else 2.0 * model.L * len(model.body_names)
        up, _ = _stretches(model, u0 + np.linspace(0, R, samples + 1), tol, max_step)
        down, _ = _stretches(model, u0 - np.linspace(0, R, samples + 1), tol, max_step)
        # the stretch through the sketch is the first of each sweep; one that runs to the end
        # of the travel ends there
        end = lambda v, e: e if v is None else v  # noqa: E731
        first = (end(down[0][1], u0 - R), end(up[0][1], u0 + R))
        out = [first] + [(lo, end(hi, u0 + R)) for lo, hi in up[1:]] + [(end(hi, u0 - R), lo) for lo, hi in down[1:]]
        return tuple(sorted((min(a, b), max(a, b)) for a, b in out))
    grid = u0 + np.linspace(0, TURN, samples + 1)
    stretches, back = _stretches(model, grid, tol, max_step, turn=True)
    first, rest = stretches[0], stretches[1:]
    if first[1] is None and not back:
        # the sketch's stretch runs a turn without coming back to its pose (a rack or a gear
        # drives the linkage): the input's own ends, as far as FAR_TURNS each way
        (lo, reach), (hi, _) = (_far_end(model, way, tol, max_step) for way in (-1, 1))
        if lo is not None or hi is not None:
            return ((u0 - reach if lo is None else lo, u0 + reach if hi is None else hi),)
    if first[1] is None:  # (the sketch's stretch turns fully)
        return ((-np.pi, np.pi),)
    into = [st for st in rest if st[1] is None]
    if into:  # a stretch runs through the end of the turn into the first (the sketch's pose a turn on)
        # (where it reaches back over the sketch's input with no limit, a geared linkage's, the
        # first's lower end is below the turn's: walked down to from the sketch)
        lo = into[0][0]
        first = (_lower_end(model, u0, tol, max_step) if lo is None else lo - TURN, first[1])
        rest = [st for st in rest if st[1] is not None]
    else:
        # the sketch's stretch started at u0 but did not come back around: find its lower end
        first = (_lower_end(model, u0, tol, max_step), first[1])
    return tuple(sorted(_turn(lo, hi) for lo, hi in [first] + rest))


def _travel(travel):
    """``travel``: a positive finite length."""
    if not (arguments.finite_number(travel) and travel > 0):
        raise InputError(f"motion_range travel must be a positive length (how far to look each way from the "
                         f"sketch), got {travel!r}")
    return float(travel)


def runs(mask):
    """(first, last) index of each run of True in ``mask``.

    >>> runs([False, True, True, False, True])
    [(1, 2), (4, 4)]
    """
    edges = np.flatnonzero(np.diff(np.r_[0, np.asarray(mask, int), 0]))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


def swept_ranges(res):
    """[(start, end)] of the first input over each stretch of the sweep ``res`` that assembled,
    in sweep order (start > end where the input went down); an end next to a limit position
    the sweep located is moved onto it.

    >>> import numpy as np
    >>> from planar.mechanisms import four_bar
    >>> res = four_bar(4, 3, 3, 3).sweep(np.radians(np.arange(0, 361, 5.0)))
    >>> [np.round(np.degrees(r), 4).tolist() for r in swept_ranges(res)]
    [[0.0, 117.2796], [242.7204, 360.0]]
    """
    u = np.asarray(as_sweep(res, "swept_ranges").inputs[:, 0], float)
    limits = [float(np.ravel(e.input)[0]) for e in res.events if e.kind == "limit"]
    out = []
    for a, b in runs(POSED[np.asarray(res.status)]):
        ends = []
        for inside, outside in ((a, a - 1), (b, b + 1)):
            end = float(u[inside])
            if 0 <= outside < len(u):
                end = next((v for v in limits if _between(v, u[inside], u[outside])), end)
            ends.append(end)
        out.append(tuple(ends))
    return out


def _turn(lo, hi):
    start = (lo + np.pi) % TURN - np.pi
    return float(start), float(start + (hi - lo))


def _stretches(model, grid, tol, max_step, turn=False):
    """(stretches, back): the stretches of ``grid`` (from the sketch's input on) that assemble,
    [(lo, hi)], hi the limit that ends a stretch (None when it runs to the end of the grid), lo
    the limit that starts it (the grid's first value for the first stretch; None for one that
    runs into the first a turn on and reaches back past the grid's start); ``back``: whether
    the pose at the grid's end is the sketch's a whole turn on (``turn``: an angle grid of a
    turn), so that a stretch running to the end runs into the first. A stretch that reaches
    over the inputs of another (a geared linkage's, past a gap) is one of its own."""
    res = model.sweep(grid, tol=tol, max_step=max_step)
    posed = POSED[res.status]
    limits = [float(np.ravel(e.input)[0]) for e in res.events if e.kind == "limit"]
    walker = Walker(Branch(model, block_plan(model), tol), max_step, False)

    def walk(i, target):
        q, u = res.q[i], res.inputs[i]
        return walker.walk(q, u, walker.br.signs(q[None], u[None])[0], np.array([target]), i)

    def limit(i, target):
        """The limit the walk from value i's pose towards ``target`` meets, or None."""
        got = walk(i, target)
        return float(np.ravel(got[1].input)[0]) if got[0] == "limit" else None

    def same(q, p):
        """Whether poses q and p are one up to whole turns of their angles."""
        return whole_turns(walker.br, q - p) is not None

    def continues(b):
        """Whether value b is on the stretch of value b - 1 (both posed): the walk from b - 1
        comes to b's pose, where b was not entered past a gap nor lies past a limit."""
        if res.status[b] != Status.JUMPED and not any(_between(v, grid[b - 1], grid[b]) for v in limits):
            return True
        got = walk(b - 1, grid[b])
        return got[0] == "ok" and same(got[1], res.q[b])

    pieces = []  # (first, last) value of each stretch the sweep posed
    for a, last in runs(posed):
        cut = [b for b in range(a + 1, last + 1) if not continues(b)]
        pieces += list(zip([a] + cut, [b - 1 for b in cut] + [last]))
    back = turn and bool(posed[-1]) and same(res.q[-1], model.q0)
    beyond = None  # where a stretch past the grid's end ends, where it is not the first a turn on
    out = []
    for a, e in pieces:
        # back to the limit that starts it, as far as the sweep's start (values just inside
        # may have been missed by the sweep, or posed on another stretch over them)
        lo = grid[0] if a == 0 else limit(a, grid[0])
        hi = None
        if e + 1 < len(grid):
            ends = [v for v in limits if _between(v, grid[e], grid[e + 1])]
            # (on past a value posed on another stretch, as far as the grid's end)
            hi = ends[0] if ends and not posed[e + 1] else limit(e, grid[-1])
        if lo is None and not (hi is None and back):
            lo = 0.5 * (grid[a - 1] + grid[a])  # (a geared linkage's stretch back over the sketch's)
        if hi is None and turn and not back and a > 0:
            # a geared linkage's stretch over the end of the turn (its pose does not repeat
            # each turn): on to its end, within another turn
            beyond = limit(len(grid) - 1, grid[-1] + TURN) if beyond is None else beyond
            hi = beyond if beyond is not None else lo + TURN
        if not any(_near(lo, p) and _near(hi, h) for p, h in out):
            out.append((lo if lo is None else float(lo), hi if hi is None else float(hi)))
    return (out or [(grid[0], grid[0])]), back


def _near(a, b):
    """Whether two stretch ends (None: not located) are one."""
    return a is None if b is None else a is not None and abs(a - b) <= 1e-9


def _between(u, a, b):
    return min(a, b) <= u <= max(a, b)


def _lower_end(model, u0, tol, max_step):
    """The limit that ends the sketch's stretch below its input (the sweep went up from it):
    within a turn where the pose repeats each turn, else as far as FAR_TURNS."""
    (_, end), *_ = _stretches(model, u0 - np.linspace(0, TURN, 361), tol, max_step)[0]
    if end is None:
        end, reach = _far_end(model, -1, tol, max_step)
        end = u0 - reach if end is None else end
    return end


def _far_end(model, way, tol, max_step):
    """(the limit the walk from the sketch meets going ``way`` (+-1) or None, how far it
    looked): FAR_TURNS turns of the input, less where that is beyond one walk's reach (steps
    smaller than the default)."""
    walker = Walker(Branch(model, block_plan(model), tol), max_step, False)
    signs = walker.br.signs(model.q0[None], model.u0[None])[0]
    reach = min(FAR_TURNS * TURN, 0.99 * WALK_STEPS * max_step / float(input_scale(model)[0]))
    got = walker.walk(model.q0, model.u0, signs, model.u0 + way * reach, 0)
    return (float(np.ravel(got[1].input)[0]) if got[0] == "limit" else None), reach
