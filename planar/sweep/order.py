"""The order a sweep solves its values in (each walked to from its neighbour in input, from the
start out) and, in that order, the solved value each one is walked to from."""

import numpy as np


def input_order(U, u0, both=True):
    """(order, b): the order in which to solve the values U (N, 1) of one input (None where it
    is the order given) and the first position b in it of the values walked from the start
    again (N for none). Values on both sides of the start's input ``u0`` (with ``both``): each
    side from the start out (the side whose far end is nearer first, whatever the order asked),
    the second walked from the start again, not from the first's far end. Values on one side: sorted,
    ascending or descending from the end nearer the start (stable: repeated values keep their
    order); values in order from their far end, reversed. So the walk from the start takes the
    values of the start's own stretch, on both sides of it, before a stretch entered past a gap
    can (one over the same inputs, reached first from the far end of the values).

    >>> U, V = np.array([[0.0], [2.0], [1.0]]), np.array([[0.0], [1.0], [2.0]])
    >>> input_order(U, 0.0)[0].tolist(), input_order(U, 3.0)[0].tolist()
    ([0, 2, 1], [1, 2, 0])
    >>> input_order(V, 0.0), input_order(V, 2.0)[0].tolist()
    ((None, 3), [2, 1, 0])
    >>> order, b = input_order(np.array([[0.0], [1.0], [2.0], [3.0]]), 1.2); order.tolist(), b
    ([1, 0, 2, 3], 2)
    """
    N = U.shape[0]
    if U.shape[1] != 1 or N < 2:
        return None, N
    v = U[:, 0]
    if both and v.min() < u0 < v.max():
        up = np.flatnonzero(v >= u0)
        down = np.flatnonzero(v < u0)
        up, down = up[np.argsort(v[up], kind="stable")], down[np.argsort(-v[down], kind="stable")]
        sides = (down, up) if u0 - v.min() < v.max() - u0 else (up, down)
        return np.concatenate(sides), sides[0].size
    d = np.diff(v)
    if np.all(d >= 0) or np.all(d <= 0):
        # (in order: reversed only where its far end is strictly nearer the start)
        return (np.arange(N)[::-1].copy() if abs(v[-1] - u0) < abs(v[0] - u0) else None), N
    down = v.max() - u0 < u0 - v.min()
    return np.argsort(-v if down else v, kind="stable"), N


def last_solved(solved, side):
    """(N,) the index of the last solved value at or before each on its side of the start
    (``side``: the first value of each one's side), -1 for none."""
    last = np.maximum.accumulate(np.where(solved, np.arange(solved.size), -1))
    return np.where(last >= side, last, -1)


def input_before(u0, U, last, idx, side):
    """(M, f) the input of the last solved value before each of ``idx`` on its side of the
    start (``last``: :func:`last_solved`; ``side``: the first value of each one's side), the
    start's ``u0`` where none."""
    prev = np.where(idx > side[idx], last[np.maximum(idx - 1, 0)], -1)
    return np.where((prev >= 0)[:, None], U[np.maximum(prev, 0)], u0)


def further(failed, j, u_j, u):
    """The walk from value j to ``u`` goes the way a walk from j failed (``failed``: (j, its
    target)) and at least as far: not tried (values out of order on the near side are)."""
    if failed[0] != j or failed[1] is None:
        return False
    d, f = u - u_j, failed[1] - u_j
    return bool(np.all(d * f >= 0) and np.max(np.abs(d)) >= np.max(np.abs(f)))


def apart(part, before):
    """The values (walk order) in another part than the value asked before each (``before``:
    its index, -1 for none): parts that a limit separates."""
    return np.flatnonzero((before >= 0) & (part != part[np.maximum(before, 0)]))
