"""Where a sweep looks for its branch past a gap in the range: the walk's steps out from a limit,
and the images of values past a gap whole periods back."""

import numpy as np

from planar.sweep.branch import input_scale
from planar.sweep.reentry import SPREAD

# a turn of the scaled input: the reach of a search past a gap, of the walk home to the origin's
# stretch and of the walk back for a limit behind a jump
TURN = 2 * np.pi


def past_gap(model, u_limit, u_next, max_step):
    """(M, 1) inputs a walk step apart from a limit at ``u_limit`` (1,) towards the next value
    ``u_next`` (1,), before it, over at most a turn (scaled): where a sweep with values all the
    way would look for the range past the gap. Empty for another input count or a value within
    a step."""
    if u_limit.size != 1:
        return np.zeros((0, 1))
    scale = float(input_scale(model)[0])
    h, d = max_step / scale, float(u_next[0] - u_limit[0])
    steps = np.arange(1, int(min(abs(d), TURN / scale) / h) + 1) * h
    steps = steps[steps < abs(d) - 0.5 * h]
    return (u_limit[0] + np.sign(d) * steps)[:, None]


def steps_out(model, u_limit, V, max_step, bare=None):
    """(M, 1) walk steps from a limit at ``u_limit`` (1,) (:func:`past_gap`) out to the last
    of the first values ``V`` (K, 1) past it that lie each no nearer to it than the one before
    (within a turn, scaled): those between values (or the limit and the first) more than SPREAD
    steps apart, where the search of the values is coarser than a sweep with values all the
    way, half a step or more from both, and not inside ``bare`` (lo, hi); None where none are.

    >>> from planar.mechanisms import four_bar
    >>> V = np.array([[1.01], [1.05], [1.5], [0.9]])
    >>> steps_out(four_bar().compile(), np.array([1.0]), V, 0.1)[:, 0].round(3).tolist()
    [1.1, 1.2, 1.3, 1.4]
    """
    if u_limit.size != 1:
        return None
    on = np.diff((V[:, 0] - u_limit[0]) * np.sign(V[0, 0] - u_limit[0])) >= 0
    r = int(np.argmin(on)) + 1 if not on.all() else len(V)
    steps = past_gap(model, u_limit, V[r - 1], max_step)[:, 0]
    ends = np.sort(np.r_[u_limit[0], V[:r, 0]])
    k = np.clip(np.searchsorted(ends, steps), 1, ends.size - 1)
    lo, hi = ends[k - 1], ends[k]
    scale = float(input_scale(model)[0])
    keep = ((hi - lo) * scale > SPREAD * max_step) & (np.minimum(steps - lo, hi - steps) * scale >= 0.5 * max_step)
    if bare is not None:
        keep &= (steps < bare[0]) | (steps > bare[1])
    return steps[keep][:, None] if keep.any() else None


def images(model, walker, targets, u):
    """(V, n): the images of ``targets`` (M, 1) past a gap from ``u`` that
    :func:`planar.sweep.entries.enter_by_images` sweeps, n whole periods back (reversed: from the sketch
    outwards, the way the walk there goes); None where the input has no period."""
    per = walker.period() if targets.shape[1] == 1 else None
    if per is None:
        return None
    P, _ = per
    k = np.sign(targets[0, 0] - u[0])
    n = k * max(1.0, np.ceil(k * (targets[0, 0] - model.u0[0]) / P))
    return targets[::-1] - n * P, n
