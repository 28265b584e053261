"""Path generation: a four-bar (or a Stephenson six-bar) whose tracer passes N target points.

The search works on the targets moved to their centre and scaled to unit size, over the
design numbers of :mod:`planar.synthesis.families` (the tracer in closed form, vectorised over
a batch of designs and crank angles). It runs in rounds of ROUND designs, up to ``designs``,
each through the three steps below; the first round with an answer ends it.

1. Global search over shape: the round's designs in the canonical frame (O2 at the origin,
   O4 at (1, 0)), a Latin hypercube over the other numbers from a seeded generator, in
   batches. Without timing, each target takes the crank angle (on a grid of one turn) where
   the coupler curve passes nearest; with timing (the crank angles of the targets relative to
   the first), each first crank angle on the grid is tried. The best similarity z -> a z + b
   (least squares, closed form) then moves each design's points onto the targets (without
   timing, matching the targets again after the move), so the search is over the curve's
   shape only; the distance left is the score. Designs whose targets come out of order, or
   with a stretch between them where the linkage does not assemble, rank last.
2. Local refinement: the best ``refine`` designs, with the crank angles at the targets (free
   timing) or the first one (prescribed timing), go to a Levenberg-Marquardt refinement all
   at once (a batch of normal equations, the Jacobian by forward differences of the
   vectorised closed form) on the distances to the targets, with penalties that keep the
   linkage assembled, away from its limit positions (|cos gamma| <= 1 - MARGIN) at and
   between the targets, and (free timing) the targets in order within one turn. The worse
   half is dropped a few times on the way, so the effort goes to the designs that converge.
3. Check: each refined design within ``tol``, best first, is built with
   :func:`planar.mechanisms.four_bar` (and, for the six-bar, its second loop) and swept by
   planar from the first target's crank angle through every target's, in order; the first
   whose errors are all within ``tol`` of the targets' size and that has no defect is the
   answer.
"""

import inspect
from dataclasses import replace

import numpy as np
from scipy.stats import qmc

from planar import arguments
from planar.analysis import transmission_angle
from planar.errors import InputError, PlanarError, SynthesisError
from planar.model.checks import MAX_ANGLE, SCALE
from planar.synthesis.families import FOUR_BAR, STEPHENSON
from planar.synthesis.result import check, floats, ordered

GRID = 120  # crank angles per turn in the global search
BATCH = 2000  # designs per batch
ROUND = 10000  # designs per round of search and refinement
MATCHES = 2  # matchings of the targets to the curve in the search, each followed by a similarity move
DISORDER = 10.0  # search score added to designs with targets out of order (targets' size 1)
ITERATIONS = 200  # Levenberg-Marquardt iterations of the refinement
HALVINGS = (10, 20, 30)  # iterations at which the refinement drops its worse half
PENALTY = 10.0  # weight of the refinement's assembly and order terms
MARGIN = 1e-3  # smallest 1 - |cos gamma| the refinement keeps at and between the targets
BETWEEN = 3  # crank angles between each two targets where the refinement keeps the linkage assembled
SPACING = 1e-3  # smallest crank angle step between targets the refinement keeps (free timing)
CONVERGED = 1e-6  # the refinement stops a design at this fraction of tol
STALL = 1e-9  # or when a step lowers its sum of squares by less than this fraction
MAX_DESIGNS = 10**7  # designs searched (and refined): minutes of work; more is no search a user waits for
# target points: the refinement's Gauss-Newton is cubic in them (its unknowns hold a crank
# angle each): 50 take ~5 s, 100 about 26 s
MAX_TARGETS = 50
STEP = 1e-7  # forward-difference step of the refinement's Jacobian (the design is of unit size)


def path_check(design, inputs, targets, min_transmission=None):
    """Build ``four_bar(**design)`` (with a coupler point; with ``link_5`` in the design, the
    six-bar :func:`planar.synthesis.stephenson_tracer`) and check it: a
    :class:`planar.synthesis.Synthesis` with its tracer's distance to each target at the crank
    angles ``inputs`` (radians, in target order) and its defects; with ``min_transmission``
    (radians), a transmission angle (at B between coupler and rocker, and at D between links 5
    and 6) further than that from a straight line is one too. ``notes["transmission"]`` holds the worst transmission angle
    over the range (0 to pi/2)."""
    if not isinstance(design, dict):
        raise InputError(f"design must be a dict of four_bar's keyword arguments (with link_5, of "
                         f"stephenson_tracer's), got {type(design).__name__}")
    family = STEPHENSON if "link_5" in design else FOUR_BAR
    params = inspect.signature(family.build).parameters
    unknown = [k for k in design if k not in params]
    missing = [k for k, p in params.items() if p.default is p.empty and k not in design]
    if unknown or missing:
        what = f"has an unknown key {unknown[0]!r}" if unknown else f"lacks {missing[0]!r}"
        raise InputError(f"design {what}: give {family.build.__name__}'s keyword arguments "
                         f"({', '.join(params)})")
    T = _targets(targets)
    u = floats(inputs)
    if u is None or u.shape != (len(T),) or not np.all(np.isfinite(u)):
        raise InputError(f"inputs must hold one finite crank angle (radians) per target ({len(T)}), got {inputs!r}")
    _min_transmission(min_transmission)
    mech = family.build(**design)
    size = float(np.ptp(T, axis=0).max())
    s = check(mech, family.build, design, u, T, lambda res, i: res.position(family.point)[i],
              lambda got, want: np.hypot(*(got - want).T), period=2 * np.pi, point=family.point, size=size)
    mu = np.concatenate([transmission_angle(s.sweep, *pair) for pair in family.transmission])
    mu = np.minimum(mu, np.pi - mu)[np.isfinite(mu)]
    worst = float(mu.min()) if mu.size else float("nan")
    defects = s.defects
    if min_transmission is not None and not worst >= min_transmission:
        defects += (f"transmission angle down to {np.degrees(worst):.3g} deg, below the "
                    f"{np.degrees(min_transmission):.3g} deg asked for",)
    return replace(s, defects=defects, notes={"transmission": worst})


def path_four_bar(targets, *, timing=None, designs=20000, refine=64, tol=1e-6, min_transmission=None, seed=0,
                  progress=None, name="path_four_bar"):
    """A four-bar whose coupler point C passes every target point (N, 2) in order, found as the
    module describes.

    Parameters
    ----------
    targets : (N, 2) array
        The points, in the order the coupler point is to pass them (N >= 2).
    timing : (N,) array, optional
        The crank angles at the targets, relative to the first (radians); default free.
    designs : int
        Designs in the global search at most, in rounds of 10000 (the last may be smaller);
        the first round that yields an answer ends the search.
    refine : int
        Designs of each round refined together, the best of its search.
    tol : float
        Largest distance to a target, relative to the targets' size.
    min_transmission : float, optional
        Smallest transmission angle allowed between the first and last target (radians).
    seed : int
        Seed of the random generator: the same call gives the same linkage (to rounding: with
        fewer equations than unknowns the refinement may end elsewhere on the family of exact
        solutions by ~1e-10, from last-bit differences of numpy's vectorised functions).
    progress : callable, optional
        ``progress(done, total)`` after each batch of the search and each iteration of the
        refinement.

    Returns
    -------
    planar.synthesis.Synthesis
        The first defect-free design within ``tol``; ``notes["candidates"]`` says how many
        refined designs were checked.

    Raises
    ------
    planar.errors.SynthesisError
        When none of the refined designs passes; the message gives the best one's error and
        defects.
    """
    return _path(FOUR_BAR, targets, timing, designs, refine, tol, min_transmission, seed, progress, name)


def path_six_bar(targets, *, timing=None, designs=100000, refine=128, tol=1e-6, min_transmission=None, seed=0,
                 progress=None, name="path_six_bar"):
    """A Stephenson six-bar whose tracer P on link 5 passes every target point in order: as
    :func:`path_four_bar`, with 15 design numbers (see :mod:`planar.synthesis.families`) and a
    larger search and refinement by default (a round lands near an answer less often); the
    result's mechanism is :func:`planar.synthesis.stephenson_tracer`'s. More design freedom
    than a four-bar: 15 + N unknowns for 2N equations without timing, 16 with.

    >>> import numpy as np
    >>> T = [(0.0, 0.0), (1.0, 0.6), (2.0, 0.4), (2.6, -0.5), (2.0, -1.2), (1.0, -1.0), (0.3, -0.6)]
    >>> s = path_six_bar(T, designs=4000)
    >>> s.ok, bool(s.max_error < 1e-9), s.point
    (True, True, 'P')
    """
    return _path(STEPHENSON, targets, timing, designs, refine, tol, min_transmission, seed, progress, name)


def _path(family, targets, timing, designs, refine, tol, min_transmission, seed, progress, name):
    kind = "four-bar" if family is FOUR_BAR else "six-bar"
    T = _targets(targets)
    centre = T.mean(axis=0)
    size = float(np.ptp(T, axis=0).max())
    if size == 0:
        raise InputError("the target points all coincide: give distinct points")
    # (a sketch there holds its rows only to the rounding of its coordinates: the search found
    # no design, and said the best missed by 1e-16)
    if size < 1.0 / SCALE or np.abs(T).max() > MAX_ANGLE * size:
        raise InputError(f"the target points span {size:.3g} and lie up to {np.abs(T).max():.3g} from the origin: "
                         f"give them spanning at least {1.0 / SCALE:g}, within {MAX_ANGLE:g} times their span of the "
                         "origin (in another unit, or moved nearer it)")
    for what, v, most in (("designs", designs, MAX_DESIGNS), ("refine", refine, MAX_DESIGNS)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= most:
            raise InputError(f"{what} must be a whole number from 1 to {most:g}, got {v!r}")
    if not (arguments.finite_number(tol) and tol > 0):
        raise InputError(f"tol must be a positive number (relative to the targets' size), got {tol!r}")
    _min_transmission(min_transmission)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a whole number of at least 0, got {seed!r}")
    if progress is not None and not callable(progress):
        raise InputError(f"progress must be a function progress(done, total), got {progress!r}")
    t = (T - centre) / size
    tz = t[:, 0] + 1j * t[:, 1]
    tau = None if timing is None else _timing(timing, len(T))
    cube = qmc.LatinHypercube(d=family.cube, seed=np.random.default_rng(seed))
    rounds = [min(ROUND, designs - k) for k in range(0, designs, ROUND)]
    total = sum(-(-D // BATCH) + ITERATIONS for D in rounds)

    def report(done):
        if progress is not None:
            progress(done, total)

    best, fits, tried, base = None, [], 0, 0
    for D in rounds:
        # each round searches afresh and refines its own best: a round whose designs all stall
        # leaves the next its full chance
        X, sigma, th = _search(family, tz, tau, D, refine, cube, lambda b: report(base + b))
        base += -(-D // BATCH)
        if not len(X):  # no design of the round reaches the targets at all
            fits.append(np.inf)
            base += ITERATIONS
            continue
        X, th, fit = _refine(family, X, sigma, th, tz, tau, tol, lambda i: report(base + i))
        base += ITERATIONS
        fits.append(np.min(fit, initial=np.inf))
        for i in np.argsort(fit, kind="stable"):
            if not fit[i] <= tol:
                break
            tried += 1
            try:
                s = path_check(family.design(X[i], sigma[i], th[i, 0], centre, size, name), th[i], T,
                               min_transmission)
            except PlanarError:  # it does not even assemble at the first target
                continue
            if s.ok and s.max_error <= tol * size:
                report(total)
                return replace(s, notes={**s.notes, "candidates": tried})
            best = _better(best, (s.max_error / size if np.isfinite(s.max_error) else np.inf, s))
        report(base)
    what = ("no sampled design reaches every target" if best is None and min(fits) == np.inf else
            f"the best refined design misses by {min(fits):.3g} of the targets' size" if best is None else
            f"the best design misses by {best[0]:.3g} of the targets' size"
            + (f" with defects: {'; '.join(best[1].defects)}" if best[1].defects else ""))
    raise SynthesisError(f"path generation through {len(T)} targets found no defect-free {kind} within "
                         f"{tol:g} of their size among {len(rounds) * refine} refined designs ({what}): raise "
                         "designs or refine, try another seed, or relax tol")


def _better(best, new):
    return new if best is None or new[0] < best[0] else best


def _min_transmission(angle):
    if angle is not None and not (arguments.finite_number(angle) and 0 <= angle <= np.pi / 2):
        raise InputError(f"min_transmission must be an angle from 0 to pi/2 radians (or None), got {angle!r}")


def _targets(targets):
    T = floats(targets)
    if T is None:
        raise InputError(f"targets must be an (N, 2) array of finite points, got {targets!r}")
    if T.ndim and len(T) > MAX_TARGETS:
        raise InputError(f"{len(T)} target points, more than the limit of {MAX_TARGETS}: the refinement's cost grows "
                         "as the cube of their number; give fewer, spread along the path")
    if T.ndim != 2 or T.shape[1] != 2 or len(T) < 2:
        raise InputError(f"targets must be an (N, 2) array of finite points with N >= 2, got shape {T.shape}")
    bad = np.flatnonzero(~np.isfinite(T).all(axis=1))
    if bad.size:
        raise InputError(f"target point {bad[0]} is {tuple(T[bad[0]].tolist())}: give finite points")
    if np.abs(T).max() > SCALE:  # (beyond, their spread overflows)
        raise InputError(f"target points reach {np.abs(T).max():.3g}, beyond the numbers a sketch holds "
                         f"(+-{SCALE:g}): give them in another unit")
    return T


def _timing(timing, N):
    tau = floats(timing)
    if tau is None:
        raise InputError(f"timing must hold one finite crank angle per target ({N}), got {timing!r}")
    if tau.shape != (N,) or not np.all(np.isfinite(tau)):
        raise InputError(f"timing must hold one finite crank angle per target ({N}), got shape {tau.shape}")
    turn = np.sort(np.mod(tau - tau[0], 2 * np.pi))
    gaps = np.diff(np.append(turn, 2 * np.pi))
    if gaps.min() < SPACING:
        raise InputError(f"timing gives two targets crank angles {gaps.min():.3g} rad apart (modulo a turn): "
                         f"a crank angle places the coupler point once, so give angles at least {SPACING:g} rad apart")
    return tau - tau[0]


def _search(family, tz, tau, designs, keep, cube, report):
    """The ``keep`` best of ``designs`` designs from the unit cube's sampler ``cube``, best first:
    designs X (keep, n), modes (keep, modes) and crank angles at the targets (keep, N)."""
    grid = np.linspace(-np.pi, np.pi, GRID, endpoint=False)
    scores, found = [], []
    for batch, start in enumerate(range(0, designs, BATCH)):
        X, sigma = family.sample(cube.random(min(BATCH, designs - start)))
        score, a, b, th = (_score_free if tau is None else _score_timed)(family, X, sigma, tz, tau, grid)
        best = np.argsort(score)[:keep]
        best = best[np.isfinite(score[best]) & (np.abs(a[best]) > 0)]  # (a = 0: the design shrunk to a point)
        scores.append(score[best])
        found.append((family.move(X[best], a[best], b[best]), sigma[best], th[best]))
        report(batch + 1)
    order = np.argsort(np.concatenate(scores), kind="stable")[:keep]
    return tuple(np.concatenate(part)[order] for part in zip(*found))


def _similarity(C, tz):
    """The move z -> a z + b (a, b complex (D,)) that brings the points C (D, N) nearest the
    targets tz (N,) in the least squares sense, and the root mean square distance left."""
    Cm = C.mean(axis=1, keepdims=True)
    dc, dt = C - Cm, tz - tz.mean()
    with np.errstate(invalid="ignore", divide="ignore"):
        a = np.sum(np.conj(dc) * dt, axis=1) / np.sum(np.abs(dc) ** 2, axis=1)
    b = tz.mean() - a * Cm[:, 0]
    rms = np.sqrt(np.mean(np.abs(a[:, None] * C + b[:, None] - tz) ** 2, axis=1))
    return a, b, np.where(np.isfinite(rms), rms, np.inf)


def _nearest(C, tz):
    """The index (D, N) of the point of each curve C (D, M) nearest each target (NaN: none)."""
    dist = np.abs(C[:, None, :] - tz[None, :, None])
    return np.argmin(np.where(np.isnan(dist), np.inf, dist), axis=2)


def _score_free(family, X, sigma, tz, tau, grid):
    """Each target takes the nearest point of the coupler curve, the curve moves to the
    targets by the best similarity (twice, matching again), and the score is the distance
    left; designs out of order or broken between the targets rank last."""
    D, M = len(X), len(grid)
    C, reach = family.points(X, sigma, np.broadcast_to(grid, (D, M)))
    C = np.where(reach > 1, np.nan, C)
    k = _nearest(C, tz)
    for _ in range(MATCHES):
        a, b, score = _similarity(np.take_along_axis(C, k, 1), tz)
        k = _nearest(a[:, None] * C + b[:, None], tz)
    a, b, score = _similarity(np.take_along_axis(C, k, 1), tz)
    # in order along one turn, either way, and assemblable between the first and last target
    fine = np.zeros(D, bool)
    bad = np.cumsum(np.concatenate((reach > 1, reach > 1), axis=1), axis=1)
    for sign in (1, -1):
        off = np.mod(sign * (k - k[:, :1]), M)
        inorder = np.all(np.diff(off, axis=1) > 0, axis=1)
        lo = np.where(sign > 0, k[:, 0], k[:, 0] - off[:, -1]) % M
        span = off[:, -1]
        hole = np.take_along_axis(bad, (lo + span)[:, None], 1)[:, 0] - np.take_along_axis(bad, lo[:, None], 1)[:, 0]
        fine |= inorder & (hole == 0)
    # designs out of order or broken between the targets rank after all others: the refinement
    # may still mend them, and the check refuses them if it does not
    score = np.where(fine, score, score + DISORDER)
    return score, a, b, grid[k] + np.angle(a)[:, None]


def _score_timed(family, X, sigma, tz, tau, grid):
    """The first target's crank angle on the grid, the others' by the timing: each start's
    points moved to the targets by the best similarity, the best start's distance left."""
    D, M, N = len(X), len(grid), len(tz)
    th = (grid[:, None] + tau[None, :]).ravel()
    C, reach = family.points(X, sigma, np.broadcast_to(th, (D, M * N)))
    C = np.where(reach > 1, np.nan, C).reshape(D * M, N)
    a, b, err = _similarity(C, tz)
    err = err.reshape(D, M)
    j = np.argmin(err, axis=1)
    pick = np.arange(D) * M + j
    return err[np.arange(D), j], a[pick], b[pick], grid[j][:, None] + tau[None, :] + np.angle(a[pick])[:, None]


def _refine(family, X, sigma, th, tz, tau, tol, report):
    """Levenberg-Marquardt on all designs at once, on the distances to the targets, with the
    linkage kept assembled (|cos gamma| <= 1 - MARGIN) at the targets and at BETWEEN crank
    angles between each two, and (free timing) the targets kept in order within one turn.
    A design stops when it converges or stalls (see STALL); the worse half of those still
    going is dropped at each of HALVINGS. Returns the designs, the crank angles at
    the targets and each design's largest residual (targets' size 1)."""
    B, k, N = len(X), family.n, len(tz)
    sign = np.ones(B)
    if tau is None:
        for i in range(B):  # the crank angles unwrapped the way the targets come
            off, sign[i] = ordered(th[i], 2 * np.pi)
            if off is not None:
                th[i] = th[i, 0] + off
        z = np.column_stack((X, th))
    else:
        z = np.column_stack((X, th[:, :1]))

    def residuals(z, sigma, sign):
        return _residuals(family, tz, tau, z, sigma, sign)

    r = residuals(z, sigma, sign)
    cost = np.sum(r**2, axis=1)
    lam = np.full(B, 1e-3)
    live = np.ones(B, bool)
    n = z.shape[1]
    for it in range(ITERATIONS):
        if it in HALVINGS:
            act = np.flatnonzero(live)
            live[act[np.argsort(cost[act])[(len(act) + 1) // 2:]]] = False
        live &= (np.abs(r).max(axis=1) > CONVERGED * tol) & (lam < 1e10)
        report(it + 1)
        act = np.flatnonzero(live)
        if not act.size:
            break
        za, ra, sa, ga = z[act], r[act], sigma[act], sign[act]
        # the Jacobian by forward differences, every column of every design in one batch
        Z = (za[:, None, :] + STEP * np.eye(n)).reshape(-1, n)
        R = residuals(Z, np.repeat(sa, n, axis=0), np.repeat(ga, n)).reshape(len(act), n, -1)
        J = (R - ra[:, None, :]).transpose(0, 2, 1) / STEP
        A = np.einsum("bmi,bmj->bij", J, J)  # not matmul: small threaded BLAS calls crawl on a busy machine
        g = np.einsum("bmn,bm->bn", J, ra)
        d = np.diagonal(A, axis1=1, axis2=2)
        M = A + (lam[act, None] * (d + 1e-12 * (1 + d.max(axis=1, keepdims=True))))[:, :, None] * np.eye(n)
        with np.errstate(all="ignore"):
            zn = za - _solve(M, g)
            rn = residuals(zn, sa, ga)
        cn = np.sum(rn**2, axis=1)
        up = cn < cost[act]
        live[act[up & (cn > (1 - STALL) * cost[act])]] = False  # a least-squares fit at its minimum
        z[act[up]], r[act[up]], cost[act[up]] = zn[up], rn[up], cn[up]
        lam[act] = np.where(up, np.maximum(lam[act] / 3, 1e-12), lam[act] * 4)
    fit = np.maximum(np.abs(r[:, :N] + 1j * r[:, N:2 * N]).max(axis=1), np.abs(r[:, 2 * N:]).max(axis=1))
    return z[:, :k], _angles(k, tau, z)[0], fit


def _angles(k, tau, z):
    """The crank angles at the targets (B, N) of refinement unknowns z (B, n), and those with
    BETWEEN more between each two."""
    a = z[:, k:] if tau is None else z[:, k:] + tau
    mid = a[:, :-1, None] + np.arange(1, BETWEEN + 1) / (BETWEEN + 1) * np.diff(a, axis=1)[:, :, None]
    return a, np.concatenate((a, mid.reshape(len(z), -1)), axis=1)


def _residuals(family, tz, tau, z, sigma, sign):
    """The refinement's residuals (B, m) of unknowns z (B, n) (designs, then the crank angles
    at the targets or, with timing, the first), modes sigma and directions sign (B,): the
    distances to the targets (x, then y), the assembly penalties and (free timing) the
    order penalties."""
    k, N = family.n, len(tz)
    a, every = _angles(k, tau, z)
    P, reach = family.points(z[:, :k], sigma, every)
    r = P[:, :N] - tz
    out = [r.real, r.imag, PENALTY * np.maximum(reach - (1 - MARGIN), 0)]
    if tau is None:
        step = sign[:, None] * np.diff(a, axis=1)
        out += [PENALTY * np.maximum(SPACING - step, 0),
                PENALTY * np.maximum(step.sum(axis=1, keepdims=True) - (2 * np.pi - SPACING), 0)]
    return np.concatenate(out, axis=1)


def _solve(M, g):
    """x with M x = g for each of a batch of matrices M (B, n, n); least squares where one is
    singular."""
    try:
        return np.linalg.solve(M, g[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:
        return np.array([np.linalg.lstsq(m, v, rcond=None)[0] for m, v in zip(M, g)])
