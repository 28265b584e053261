"""Checks of the arguments of :meth:`planar.Model.sweep` and :meth:`planar.Model.circuit`, made
before any work: each bad argument is an :class:`planar.InputError` naming it and the fix, and a
sweep too large for the machine's memory, or whose walk through its values would take more
continuation steps than :data:`MAX_STEPS`, is refused up front with the limit named.

>>> from planar.mechanisms import four_bar
>>> four_bar().sweep([0.0, 0.1], max_step=0)
Traceback (most recent call last):
...
planar.errors.InputError: max_step must be a positive number of radians (or of the mechanism's size for a length input), got 0: the default is 0.05
>>> four_bar().sweep([0.0, 1e300])
Traceback (most recent call last):
...
planar.errors.InputError: the walk through these sweep values is 2e+301 continuation steps of max_step = 0.05, more than the limit of 1e+08: sweep a shorter span of the input, with fewer jumps between far values
"""

import functools
import inspect
import math
import os
from numbers import Integral, Real

import numpy as np

from planar.errors import InputError
from planar.model.checks import MAX_ANGLE

TOL_RANGE = (1e-15, 1e-3)  # scaled residual: below 1e-15 rounding cannot meet it; above 1e-3 a pose is off
MAX_STEPS = 1e8  # continuation steps of max_step through the sweep's values
MIN_STEP = 1e-4  # max_step, scaled: a turn of a four-bar at 1e-4 takes 0.7 s, at 1e-5 3 s, at 1e-7 minutes
# input rates and accelerations (per the mechanism's size for lengths): beyond, v**2 overflows
MAX_RATE, MAX_ACCELERATION = 1e100, 1e200
BYTES_PER_COORDINATE = 40  # per value and coordinate: positions, rates, accelerations and the work arrays
# a circuit's: its tracing and the sweep along it (1e6 samples of a four-bar: 1.3 GB)
CIRCUIT_BYTES_PER_COORDINATE = 4 * BYTES_PER_COORDINATE


def finite_number(value):
    """Whether ``value`` is a finite real number (an integer beyond any float is not)."""
    try:
        return not isinstance(value, bool) and isinstance(value, Real) and math.isfinite(value)
    except OverflowError:
        return False


def _number(value, name, fix):
    if not finite_number(value):
        raise InputError(f"{name} must be a finite number, got {value!r}: {fix}")
    return float(value)


def tolerance(tol):
    """``tol``: a number within :data:`TOL_RANGE`."""
    lo, hi = TOL_RANGE
    fix = f"give a scaled residual from {lo:g} to {hi:g} (the default is 1e-12)"
    tol = _number(tol, "tol", fix)
    if not lo <= tol <= hi:
        raise InputError(f"tol must be from {lo:g} to {hi:g}, got {tol!r}: {fix}")
    return tol


def max_step(step):
    """``max_step``: a number of at least MIN_STEP."""
    fix = "the default is 0.05"
    what = "max_step must be a positive number of radians (or of the mechanism's size for a length input)"
    if not finite_number(step) or step <= 0:
        raise InputError(f"{what}, got {step!r}: {fix}")
    if step < MIN_STEP:
        raise InputError(f"max_step must be at least {MIN_STEP:g}, got {step!r}: the walk shortens its own steps where "
                         f"the branch needs it (halvings, then the arclength tracer), so a smaller cap only multiplies "
                         f"them (a turn at 1e-7 took minutes); {fix}")
    return float(step)


@functools.cache
def _options(run):
    """{name: default} of ``run``'s keyword-only parameters but its private ones (``_name``; read
    once: a tracker asks per move)."""
    return {k: p.default for k, p in inspect.signature(run).parameters.items()
            if p.kind == p.KEYWORD_ONLY and not k.startswith("_")}


def sweep_options(options, run):
    """The options of a sweep checked: names among ``run``'s keyword-only parameters, ``tol``,
    ``max_step``, ``rates``, ``branch`` and ``engine`` of their kinds; the others are checked
    where they are used.
    Returns them with ``max_step`` filled in."""
    known = _options(run)
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise InputError(f"unknown sweep option {unknown[0]!r}: the options are {', '.join(known)}")
    out = dict(options)
    if "tol" in out:
        out["tol"] = tolerance(out["tol"])
    out["max_step"] = max_step(out.get("max_step", known["max_step"]))
    if "rates" in out and not isinstance(out["rates"], (bool, np.bool_)):
        raise InputError(f"rates must be True or False, got {out['rates']!r}")
    if "branch" in out and not (isinstance(out["branch"], str) and out["branch"] in ("smooth", "other")):
        # (here, not only where the sweep runs: the known poses are kept by branch)
        raise InputError(f"branch must be 'smooth' or 'other', got {out['branch']!r}")
    if "engine" in out and not (isinstance(out["engine"], str) and out["engine"] in ("numpy", "numba")):
        # (here too: a tracker's direct path asks for the engine before the sweep runs)
        raise InputError(f"engine must be 'numpy' or 'numba', got {out['engine']!r}")
    return out


def rates(model, Ud, Udd):
    """Refuse input rates and accelerations so large that the accelerations overflow."""
    scale = np.where(model.input_lengths, model.L, 1.0)
    for what, a, limit in (("velocity", Ud, MAX_RATE), ("acceleration", Udd, MAX_ACCELERATION)):
        big = float(np.max(np.abs(a) / scale)) if a.size else 0.0
        if big > limit:
            raise InputError(f"sweep {what} reaches {big:.3g} (radians, or the mechanism's size, per second"
                             f"{'' if what == 'velocity' else ' squared'}): beyond {limit:g} the accelerations "
                             f"overflow; give it in larger units of time")


def _memory():
    """Bytes of memory this process may have: the machine's physical memory, or the process's
    address-space limit (RLIMIT_AS, ``ulimit -v``) where that is less; None where the system
    says neither."""
    limits = []
    try:
        limits.append(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        pass
    try:
        import resource  # (POSIX only)

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft != resource.RLIM_INFINITY and soft > 0:
            limits.append(soft)
    except (ImportError, AttributeError, ValueError, OSError):
        pass
    return min(limits, default=None)


def size(model, N, what="the sweep", per_coordinate=BYTES_PER_COORDINATE, fix="sweep fewer values, or in chunks"):
    """Refuse ``N`` values of ``model`` when their results cannot fit in memory (a count that is
    not an integer is refused where it is read); ``per_coordinate``: bytes per value and
    coordinate; ``what`` names the work (its values counted after it), ``fix`` the way out."""
    if isinstance(N, bool) or not isinstance(N, Integral):
        return
    need = (float(max(N, 0)) if N < 2**1000 else math.inf) * max(model.n, 1) * per_coordinate
    have = _memory()
    if have is not None and need > have:
        raise InputError(f"{what} of {N if N < 10**15 else f'~1e{len(str(N)) - 1}'} values needs about {need / 2**30:.3g} GiB for its results, more than "
                         f"the {have / 2**30:.3g} GiB of memory this process may have: {fix}")


def values(model, U, step):
    """Refuse no values, more values (N, f) than fit in memory, and values whose walk from the
    sketch, value after value (one input's values turning back: in the order of the input, as
    the sweep solves them), takes more than :data:`MAX_STEPS` steps of ``step`` (radians, or lengths
    over the mechanism's size)."""
    if len(U) == 0:
        raise InputError("the sweep has no values: give at least one input value")
    size(model, len(U))
    scale = np.where(model.input_lengths, model.L, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        jumps = np.abs(np.diff(np.vstack([model.u0[None], U]), axis=0)) / scale
        steps = float(np.sum(np.max(jumps, axis=1))) / step
        d = np.diff(U[:, 0])
        if U.shape[1] == 1 and len(U) >= 3 and not (np.all(d >= 0) or np.all(d <= 0)):
            # solved in the order of the input (planar.sweep.order.input_order): to the nearer end, then across
            u, u0 = U[:, 0] / scale[0], model.u0[0] / scale[0]
            steps = float(min(abs(u0 - u.min()), abs(u.max() - u0)) + u.max() - u.min()) / step
    if not steps <= MAX_STEPS:
        raise InputError(f"the walk through these sweep values is {steps:.3g} continuation steps of max_step = "
                         f"{step:g}, more than the limit of {MAX_STEPS:g}: sweep a shorter span of the input, "
                         f"with fewer jumps between far values")
    with np.errstate(invalid="ignore"):
        far = ~model.input_lengths & np.any(np.abs(U) > MAX_ANGLE, axis=0)
    if far.any():
        k = int(np.argmax(far))
        raise InputError(f"sweep values of input {model.input_names[k]!r} reach {np.abs(U[:, k]).max():.6g} rad, beyond "
                         f"+-{MAX_ANGLE:.6g} rad (float64 rounds them by more than the rows' tolerance): sweep "
                         f"within a few turns of the start")

