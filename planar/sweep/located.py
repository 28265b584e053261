"""The sweep's values against the singular positions located on the way: which values sit on
one, which lie past a limit the walk met, and the index an event gets."""

import numpy as np

from planar.sweep.branch import scaled_norm

EVENT_TOL = 1e-9  # scaled input distance within which a value is on a located event


def event_index(U, lo, i, u_from, u_star):
    """First index in (lo, i] whose value is at or past u_star, walking from u_from to U[i]."""
    d = U[i] - u_from
    ks = np.arange(lo + 1, i + 1)
    proj = (U[ks] - u_from) @ d
    star = (np.atleast_1d(u_star) - u_from) @ d
    past = np.flatnonzero(proj >= star - 1e-12 * max(1.0, abs(star)))
    return int(ks[past[0]]) if past.size else int(i)


def same_event(a, b, model):
    """Events a and b are one: the same kind at the same input, to 1e-8 scaled."""
    return a.kind == b.kind and scaled_norm(model, np.atleast_1d(a.input) - np.atleast_1d(b.input)) <= 1e-8


def at_events(model, U, events):
    """Values that sit on a located limit or bifurcation: index -> event."""
    out = {}
    for ev in events:
        if ev.kind in ("limit", "bifurcation", "singular"):
            for i in np.flatnonzero(scaled_norm(model, U - np.atleast_1d(ev.input)) <= EVENT_TOL):
                out[int(i)] = ev
    return out


def on_event(model, U, events):
    """(M,) True for the values U (M, f) that sit on a located limit or bifurcation."""
    on = np.zeros(len(U), bool)
    for ev in events:
        if ev.kind in ("limit", "bifurcation", "singular"):
            on |= scaled_norm(model, U - np.atleast_1d(ev.input)) <= EVENT_TOL
    return on


def past_limit(limits, u_from, u_to, period=None):
    """(M,) True where a limit found moving in direction d lies between u_from and u_to (M, f).
    ``period`` (P, D) of a pose periodic in its one input (:meth:`planar.sweep.walk.Walker.period`): as the walk
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
