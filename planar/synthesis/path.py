"""Path generation: a four-bar (or a Stephenson six-bar) whose tracer passes N target points.

The search works on the targets moved to their centre and scaled to unit size. A four-bar
design is nine numbers: the crank pivot O2, the logarithms of the link lengths r1 ... r4 (so
they stay positive), the frame angle th1 and the coupler point (p, q) in the coupler's frame,
with an assembly mode sigma (+1: B left of the directed line A -> O4). The coupler point
follows in closed form, vectorised over a batch of designs and crank angles::

    A = O2 + r2 e^{i th2},  d = O4 - A,  cos(gamma) = (r3^2 + |d|^2 - r4^2) / (2 r3 |d|)
    th3 = arg d + sigma gamma,  C = A + (p + i q) e^{i th3}

The Stephenson six-bar (:func:`path_six_bar`) adds six numbers: link 5 from C to D, link 6
from D to a third ground pivot O6 (its position, the logarithms of r5 and r6) and the tracer
P on link 5 (p5 along C -> D, q5 to its left), with a second mode (D left of C -> O6); D is
the same circle intersection again.

1. Global search: ``designs`` random designs from a seeded generator, in batches. Without
   timing, each target takes the crank angle (on a grid of one turn) where the coupler curve
   passes nearest; with timing (the crank angles of the targets relative to the first), the
   first target's crank angle is searched on the grid. Designs whose targets come out of
   order, or with a stretch between them where the linkage does not assemble, rank last.
2. Local refinement: the best ``refine`` designs, with the crank angles at the targets (free
   timing) or the first one (prescribed timing), go to :func:`scipy.optimize.least_squares`
   on the distances to the targets (and a penalty where a target's pose does not assemble).
3. Check: each refined design is built with :func:`planar.mechanisms.four_bar` (and, for the
   six-bar, its second loop) and swept by planar from the first target's crank angle through
   every target's, in order; the first whose errors are all within ``tol`` of the targets'
   size and that has no defect is the answer.

>>> import numpy as np
>>> from planar.synthesis.path import coupler_points
>>> X = np.array([[0.0, 0.0, np.log(4), 0.0, np.log(2), np.log(3), np.log(4), 1.0, 0.5]])
>>> C, gap = coupler_points(X, np.array([1.0]), np.array([[np.pi / 3]]))
>>> np.round(C, 6).tolist(), gap.tolist()   # four_bar(4, 2, 3, 4, coupler_point=(1, 0.5)) at 60 deg
([[(1.333494+2.799188j)]], [[0.0]])
"""

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from planar.analysis import transmission_angle
from planar.errors import InputError, SynthesisError
from planar.mechanisms import four_bar
from planar.mechanisms.six_bar import _dyad
from planar.mechanisms.sketch import along
from planar.synthesis.result import check

GRID = 120  # crank angles per turn in the global search
BATCH = 2000  # designs per batch
PENALTY = 10.0  # weight of the assembly gap at a target in the refinement
DISORDER = 10.0  # search score added to designs with targets out of order (targets' size 1)
STEP = 1e-6  # central-difference step of the refinement's Jacobian (the design is of unit size)


def coupler_points(X, sigma, th2):
    """Coupler points C (D, K) complex and assembly gaps (D, K) (max(|cos gamma| - 1, 0): 0
    where the pose exists) of designs X (D, 9) in modes sigma (D,) at crank angles th2 (D, K).
    Where the gap is positive, C is that of the nearest pose (cos gamma clipped to +-1)."""
    O2 = X[:, 0] + 1j * X[:, 1]
    r1, r2, r3, r4 = (_length(X[:, k])[:, None] for k in (2, 4, 5, 6))
    O4 = (O2 + r1[:, 0] * np.exp(1j * X[:, 3]))[:, None]
    A = O2[:, None] + r2 * np.exp(1j * th2)
    d = O4 - A
    L = np.maximum(np.abs(d), 1e-300)
    c = (r3**2 + L**2 - r4**2) / (2 * r3 * L)
    gap = np.maximum(np.abs(c) - 1, 0.0)
    th3 = np.angle(d) + sigma[:, None] * np.arccos(np.clip(c, -1, 1))
    return A + (X[:, 7] + 1j * X[:, 8])[:, None] * np.exp(1j * th3), gap


def _length(log_length):
    """A length from its logarithm; a refinement wandering far keeps finite numbers."""
    return np.exp(np.clip(log_length, -20.0, 20.0))


def tracer_points(X, sigma, th2):
    """Tracer points P (D, K) and summed assembly gaps of Stephenson six-bars X (D, 15) in modes
    sigma (D, 2) at crank angles th2 (D, K) (see the module)."""
    C, gap = coupler_points(X[:, :9], sigma[:, 0], th2)
    O6 = (X[:, 9] + 1j * X[:, 10])[:, None]
    r5, r6 = _length(X[:, 11])[:, None], _length(X[:, 12])[:, None]
    d = O6 - C
    L = np.maximum(np.abs(d), 1e-300)
    c = (r5**2 + L**2 - r6**2) / (2 * r5 * L)
    th5 = np.angle(d) + sigma[:, 1:2] * np.arccos(np.clip(c, -1, 1))
    return C + (X[:, 13] + 1j * X[:, 14])[:, None] * np.exp(1j * th5), gap + np.maximum(np.abs(c) - 1, 0.0)


def stephenson_tracer(ground, crank, coupler, rocker, *, coupler_point, link_5, link_6, pivot_6, tracer,
                      frame_angle=0.0, crossed=False, crossed_2=False, start=0.0, pivot=(0.0, 0.0),
                      name="path_six_bar"):
    """The Stephenson six-bar of :func:`planar.mechanisms.stephenson_six_bar` with its crank
    pivot at ``pivot`` and a tracer point ``P`` on link 5 (``tracer`` = (p, q): p along C -> D,
    q to its left)."""
    m = four_bar(ground, crank, coupler, rocker, frame_angle=frame_angle, crossed=crossed, start=start,
                 pivot=pivot, name=name)
    pts = {k: v[1] for k, v in m.sketch().points.items()}
    C = along(pts["A"], pts["B"], *coupler_point)
    _dyad(m, ("C", "D", "O6"), ("link5", "link6", "coupler", m.ground), C, np.asarray(pivot_6, float), link_5,
          link_6, crossed_2, "the six-bar's dyad C-D-O6")
    m.add_point("P", "link5", at=along(C, m.sketch().points["D"][1], *tracer))
    return m


@dataclass(frozen=True)
class Family:
    """A linkage structure for the search: ``n`` design numbers, ``modes`` assembly modes, the
    closed form of its tracer, the builder and its keyword arguments, the tracer's name and the
    point pairs of its transmission angles."""

    n: int
    modes: int
    points: object
    sample: object
    design: object
    build: object
    point: str
    transmission: tuple


def _sample_four_bar(rng, D):
    """D random four-bars around unit-size targets centred on the origin."""
    X = np.empty((D, 9))
    X[:, 0:2] = rng.uniform(-1.5, 1.5, (D, 2))
    X[:, [2, 4, 5, 6]] = rng.uniform(np.log(0.15), np.log(2.5), (D, 4))
    X[:, 3] = rng.uniform(-np.pi, np.pi, D)
    X[:, 7:9] = rng.uniform(-1.5, 1.5, (D, 2))
    return X, rng.choice([-1.0, 1.0], (D, 1))


def _sample_six_bar(rng, D):
    X4, s4 = _sample_four_bar(rng, D)
    X = np.empty((D, 15))
    X[:, :9] = X4
    X[:, 9:11] = rng.uniform(-1.5, 1.5, (D, 2))
    X[:, 11:13] = rng.uniform(np.log(0.15), np.log(2.5), (D, 2))
    X[:, 13:15] = rng.uniform(-1.5, 1.5, (D, 2))
    return X, np.column_stack((s4, rng.choice([-1.0, 1.0], D)))


def _design_four_bar(X, sigma, start, centre, size, name):
    """The four_bar keyword arguments of a normalised design, at the targets' place and size."""
    L = np.exp(X[[2, 4, 5, 6]]) * size
    return dict(ground=float(L[0]), crank=float(L[1]), coupler=float(L[2]), rocker=float(L[3]),
                frame_angle=float(X[3]), coupler_point=(float(X[7] * size), float(X[8] * size)),
                crossed=bool(sigma[0] < 0), start=float(start),
                pivot=(float(centre[0] + X[0] * size), float(centre[1] + X[1] * size)), name=name)


def _design_six_bar(X, sigma, start, centre, size, name):
    d = _design_four_bar(X, sigma, start, centre, size, name)
    d.update(link_5=float(np.exp(X[11]) * size), link_6=float(np.exp(X[12]) * size),
             pivot_6=(float(centre[0] + X[9] * size), float(centre[1] + X[10] * size)),
             tracer=(float(X[13] * size), float(X[14] * size)), crossed_2=bool(sigma[1] < 0))
    return d


FOUR_BAR = Family(9, 1, lambda X, sigma, th: coupler_points(X, sigma[:, 0], th), _sample_four_bar,
                  _design_four_bar, four_bar, "C", ((("B", "A"), ("B", "O4")),))
STEPHENSON = Family(15, 2, tracer_points, _sample_six_bar, _design_six_bar, stephenson_tracer, "P",
                    ((("B", "A"), ("B", "O4")), (("D", "C"), ("D", "O6"))))


def path_check(design, inputs, targets, min_transmission=None):
    """Build ``four_bar(**design)`` (with a coupler point; with ``link_5`` in the design, the
    six-bar :func:`stephenson_tracer`) and check it: a :class:`planar.synthesis.Synthesis`
    with its tracer's distance to each target at the crank angles ``inputs`` (radians, in
    target order) and its defects; with ``min_transmission`` (radians), a transmission angle
    (at B between coupler and rocker, and at D between links 5 and 6) further than that from
    a straight line is one too. ``notes["transmission"]`` holds the worst transmission angle
    over the range (0 to pi/2)."""
    family = STEPHENSON if "link_5" in design else FOUR_BAR
    T = _targets(targets)
    mech = family.build(**design)
    size = float(np.ptp(T, axis=0).max())
    s = check(mech, family.build, design, inputs, T, lambda res, i: res.position(family.point)[i],
              lambda got, want: np.hypot(*(got - want).T), period=2 * np.pi, point=family.point, size=size)
    mu = np.concatenate([transmission_angle(s.sweep, *pair) for pair in family.transmission])
    mu = np.minimum(mu, np.pi - mu)[np.isfinite(mu)]
    worst = float(mu.min()) if mu.size else float("nan")
    defects = s.defects
    if min_transmission is not None and not worst >= min_transmission:
        defects += (f"transmission angle down to {np.degrees(worst):.3g} deg, below the "
                    f"{np.degrees(min_transmission):.3g} deg asked for",)
    return replace(s, defects=defects, notes={"transmission": worst})


def path_four_bar(targets, *, timing=None, designs=20000, refine=16, tol=1e-6, min_transmission=None, seed=0,
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
        Random designs in the global search.
    refine : int
        Designs refined and checked, best first.
    tol : float
        Largest distance to a target, relative to the targets' size.
    min_transmission : float, optional
        Smallest transmission angle allowed between the first and last target (radians).
    seed : int
        Seed of the random generator: the same call gives the same linkage (to rounding: with
        fewer equations than unknowns the refinement may end elsewhere on the family of exact
        solutions by ~1e-10, from last-bit differences of numpy's vectorised functions).
    progress : callable, optional
        ``progress(done, total)`` after each batch of the search and each refinement.

    Returns
    -------
    planar.synthesis.Synthesis
        The first defect-free design within ``tol``; ``notes["candidates"]`` says how many
        were refined and checked.

    Raises
    ------
    planar.errors.SynthesisError
        When none of the refined designs passes; the message gives the best one's error and
        defects.
    """
    return _path(FOUR_BAR, targets, timing, designs, refine, tol, min_transmission, seed, progress, name)


def path_six_bar(targets, *, timing=None, designs=20000, refine=48, tol=1e-6, min_transmission=None, seed=0,
                 progress=None, name="path_six_bar"):
    """A Stephenson six-bar whose tracer P on link 5 passes every target point in order: as
    :func:`path_four_bar`, with 15 design numbers (see the module) and more designs refined
    by default (its search lands near an answer less often); the result's mechanism is
    :func:`stephenson_tracer`'s. More design freedom than a four-bar: 15 + N unknowns for 2N
    equations without timing, 16 with.

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
    for what, v in (("designs", designs), ("refine", refine)):
        if not isinstance(v, (int, np.integer)) or v < 1:
            raise InputError(f"{what} must be a positive integer, got {v!r}")
    if not tol > 0:
        raise InputError(f"tol must be a positive number (relative to the targets' size), got {tol!r}")
    t = (T - centre) / size
    tz = t[:, 0] + 1j * t[:, 1]
    tau = None if timing is None else _timing(timing, len(T))
    rng = np.random.default_rng(seed)
    batches = -(-designs // BATCH)
    total = batches + refine
    pool = _search(family, tz, tau, designs, refine, rng, progress, total)
    best, tried = None, 0
    for X, sigma, th in pool:
        X, th, fit = _refine(family, X, sigma, th, tz, tau)
        tried += 1
        if progress is not None:
            progress(total if tried == len(pool) else batches + tried, total)
        if fit > 1e3 * tol:
            best = _better(best, (fit, None))
            continue
        s = path_check(family.design(X, sigma, th[0], centre, size, name), th, T, min_transmission)
        score = (s.max_error / size if np.isfinite(s.max_error) else np.inf, s)
        if s.ok and s.max_error <= tol * size:
            if progress is not None and tried < len(pool):
                progress(total, total)
            return replace(s, notes={**s.notes, "candidates": tried})
        best = _better(best, score)
    what = "the search found no design with the targets in order" if best is None else (
        f"the best design misses by {best[0]:.3g} of the targets' size"
        + (f" with defects: {'; '.join(best[1].defects)}" if best[1] is not None and best[1].defects else ""))
    raise SynthesisError(f"path generation through {len(T)} targets found no defect-free {kind} within "
                         f"{tol:g} of their size after {tried} refined designs ({what}): raise designs or refine, "
                         "try another seed, or relax tol")


def _better(best, new):
    return new if best is None or new[0] < best[0] else best


def _targets(targets):
    T = np.asarray(targets, float)
    if T.ndim != 2 or T.shape[1] != 2 or len(T) < 2 or not np.all(np.isfinite(T)):
        raise InputError(f"targets must be an (N, 2) array of finite points with N >= 2, got shape {T.shape}")
    return T


def _timing(timing, N):
    tau = np.asarray(timing, float)
    if tau.shape != (N,) or not np.all(np.isfinite(tau)):
        raise InputError(f"timing must hold one finite crank angle per target ({N}), got shape {tau.shape}")
    return tau - tau[0]


def _search(family, tz, tau, designs, keep, rng, progress, total):
    """The ``keep`` best designs of the global search, best first, as (X, sigma, crank angles)."""
    grid = np.linspace(-np.pi, np.pi, GRID, endpoint=False)
    scores, found = [], []
    done = 0
    for batch in range(-(-designs // BATCH)):
        D = min(BATCH, designs - done)
        done += D
        X, sigma = family.sample(rng, D)
        score, th = (_score_free if tau is None else _score_timed)(family, X, sigma, tz, tau, grid)
        best = np.argsort(score)[:keep]
        best = best[np.isfinite(score[best])]
        scores.append(score[best])
        found += [(X[i], sigma[i], th[i]) for i in best]
        if progress is not None:
            progress(batch + 1, total)
    scores = np.concatenate(scores)
    return [found[i] for i in np.argsort(scores, kind="stable")[:keep]]


def _score_free(family, X, sigma, tz, tau, grid):
    D, M = len(X), len(grid)
    C, gap = family.points(X, sigma, np.broadcast_to(grid, (D, M)))
    C = np.where(gap > 0, np.nan, C)
    dist = np.abs(C[:, None, :] - tz[None, :, None])  # (D, N, M)
    dist = np.where(np.isnan(dist), np.inf, dist)
    k = np.argmin(dist, axis=2)  # (D, N)
    dmin = np.take_along_axis(dist, k[..., None], axis=2)[..., 0]
    score = np.sqrt(np.mean(dmin**2, axis=1))
    # in order along one turn, either way, and assemblable between the first and last target
    fine = np.zeros(D, bool)
    bad = np.cumsum(np.concatenate((gap > 0, gap > 0), axis=1), axis=1)
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
    return score, grid[k]


def _score_timed(family, X, sigma, tz, tau, grid):
    D, M, N = len(X), len(grid), len(tz)
    th = (grid[:, None] + tau[None, :]).ravel()
    C, gap = family.points(X, sigma, np.broadcast_to(th, (D, M * N)))
    err = np.abs(C - np.tile(tz, M)[None, :]) ** 2 + np.where(gap > 0, np.inf, 0.0)
    err = np.sqrt(err.reshape(D, M, N).mean(axis=2))
    j = np.argmin(err, axis=1)
    return err[np.arange(D), j], grid[j][:, None] + tau[None, :]


def _refine(family, X, sigma, th, tz, tau):
    """Least squares on the distances to the targets from one searched design; returns the
    design, the crank angles at the targets and the largest distance (targets' size 1)."""
    n, k = len(tz), family.n

    def unpack(z):
        return z[:k], (z[k:] if tau is None else z[k] + tau)

    def residuals(Xs, ths):
        C, gap = family.points(Xs, np.repeat(sigma[None], len(Xs), axis=0), ths)
        r = C - tz
        return np.concatenate((r.real, r.imag, PENALTY * gap), axis=1)

    def residual(z):
        x, angles = unpack(z)
        return residuals(x[None], angles[None])[0]

    def jacobian(z):
        # central differences, all in one batch: each target's residuals depend on the design
        # numbers and on its own crank angle only, so one shift of every angle at once gives
        # their columns
        x, angles = unpack(z)
        Xs, ths = np.repeat(x[None], 2 * k + 2, axis=0), np.repeat(angles[None], 2 * k + 2, axis=0)
        for j in range(k):
            Xs[2 * j, j] += STEP
            Xs[2 * j + 1, j] -= STEP
        ths[2 * k] += STEP
        ths[2 * k + 1] -= STEP
        R = residuals(Xs, ths)
        dR = (R[0::2] - R[1::2]) / (2 * STEP)
        J = np.zeros((3 * n, len(z)))
        J[:, :k] = dR[:k].T
        if tau is None:
            rows = np.arange(3 * n)
            J[rows, k + rows % n] = dR[k]
        else:
            J[:, k] = dR[k]
        return J

    z0 = np.concatenate((X, th if tau is None else th[:1]))
    # Levenberg-Marquardt where there are as many residuals as unknowns, else the trust region
    method = "lm" if 3 * n >= len(z0) else "trf"
    sol = least_squares(residual, z0, jac=jacobian, method=method, xtol=1e-15, ftol=1e-15, gtol=1e-15,
                        max_nfev=100 * len(z0))
    x, angles = unpack(sol.x)
    r = residual(sol.x)
    fit = max(np.max(np.hypot(r[:n], r[n:2 * n])), np.max(r[2 * n:]))
    return x, angles, fit
