"""Stroke and time ratio of any output that goes back and forth while the input turns.

Over one turn of the input the output's extremes are where its rate d(output)/du changes
sign. Each is bracketed by two samples of the sweep and refined by safeguarded Newton steps on
that rate, whose derivative is the second kinematic coefficient: both come from the solver's
velocity and acceleration solutions at the refined input, along the same branch.

>>> from planar.mechanisms import slider_crank
>>> s = stroke(slider_crank(2, 5, offset=1), "travel:slide")
>>> round(s.stroke, 12), round(s.time_ratio, 12)
(4.099776105529, 1.133434599512)
"""

from dataclasses import dataclass

import numpy as np

from planar.analysis.outputs import output
from planar.analysis.ranges import MAX_SAMPLES
from planar.errors import AssemblyError, InputError
from planar.results import Sweep

TURN = 2 * np.pi
ROUNDING = 1e-12  # a Newton step may leave its bracket by this much (radians)
NEWTON_DONE = 1e-7  # a last Newton step this small (radians) leaves an error of order its square
MAX_ITER = 60


@dataclass(frozen=True)
class Stroke:
    """Extremes of one output over one input turn (inputs in radians, within the turn swept).

    ``stroke`` = ``maximum`` - ``minimum``; ``forward_input`` is the input travel from the
    input at the minimum to the input at the maximum (the output rising, in the direction of
    increasing input), ``return_input`` the rest of the turn; ``time_ratio`` is the longer over
    the shorter (>= 1: at a constant input rate, the slow stroke's time over the quick one's).
    ``extremes`` lists every stationary point as (input, value) in input order: more than two
    means the output wavers on its way, and the ratio still measures from the overall
    minimum to the overall maximum.
    """

    output: str
    stroke: float
    time_ratio: float
    minimum: float
    maximum: float
    input_at_minimum: float
    input_at_maximum: float
    forward_input: float
    return_input: float
    extremes: tuple


def _coefficients(res, name):
    """Output value and its first and second derivatives with respect to the input."""
    ud, udd = res.input_rates[:, 0], res.input_accelerations[:, 0]
    y, yd, ydd = (output(res, name, k) for k in range(3))
    with np.errstate(invalid="ignore", divide="ignore"):
        g = yd / ud
        return y, g, (ydd - g * udd) / ud**2


def _hermite_root(a, b, ga, gb, ha, hb):
    """Root in [a, b] of the cubic with values ga, gb and slopes ha, hb at a, b (of opposite
    signs); the secant root if the cubic has none there."""
    d = b - a
    # p(t) = ga + ha d t + c2 t^2 + c3 t^3 on t in [0, 1]
    c3 = 2 * (ga - gb) + d * (ha + hb)
    c2 = 3 * (gb - ga) - d * (2 * ha + hb)
    t = np.roots([c3, c2, ha * d, ga])
    t = t[(np.abs(t.imag) < 1e-12) & (t.real >= 0) & (t.real <= 1)].real
    secant = ga / (ga - gb)
    return a + d * (t[np.argmin(np.abs(t - secant))] if t.size else secant)


def _one_turn(source, samples, options):
    """A sweep over exactly one increasing turn of the one input angle."""
    from planar.model import Mechanism, Model

    if isinstance(source, Sweep):
        res = source
    elif isinstance(source, (Mechanism, Model)):
        model = source.compile() if isinstance(source, Mechanism) else source
        _check_input(model)
        if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 2 <= samples <= MAX_SAMPLES:
            raise InputError(f"stroke samples must be a whole number from 2 to {MAX_SAMPLES:g} (values over the "
                             f"turn; the default is 360), got {samples!r}")
        u0 = model.u0[0]
        res = model.sweep(np.linspace(u0, u0 + TURN, samples + 1), **options)
    else:
        raise InputError(f"stroke needs a Mechanism, a Model or a sweep result, got {type(source).__name__}")
    _check_input(res.model)
    u = res.inputs[:, 0]
    if u.size < 3 or np.any(np.diff(u) <= 0) or abs(u[-1] - u[0] - TURN) > 1e-9 * TURN:
        raise InputError("stroke needs a sweep over exactly one turn of the input, in increasing order "
                         "(for example np.linspace(u0, u0 + 2 pi, 361)); or pass the mechanism itself")
    if not res.ok.all():
        bad = int(np.flatnonzero(~res.ok)[0])
        raise AssemblyError(f"the input {res.model.input_names[0]!r} does not turn fully on this branch "
                            f"({int((~res.ok).sum())} of {len(res)} points invalid, the first at {u[bad]:.12g} rad): "
                            f"stroke and time ratio need a full turn")
    return res


def _check_input(model):
    if len(model.drivers) != 1 or model.input_lengths[0]:
        raise InputError(f"stroke needs one input angle that turns; mechanism {model.name!r} has inputs "
                         f"{list(model.input_names)}")


def stroke(source, output_name, *, samples=360, **options):
    """Stroke and time ratio of the output ``output_name`` ("kind:name", see
    :func:`planar.analysis.output`: "angle:rocker", "travel:slide", "x:P", ...).

    ``source`` is a mechanism or model (swept over one turn from its sketch, in ``samples``
    steps; ``options`` go to the sweep), or a sweep result over exactly one increasing turn of
    its one input angle. Extremes are located to 1e-12 rad of input or better. Returns a
    :class:`Stroke`; raises :class:`planar.AssemblyError` when the input does not turn fully on
    the branch, :class:`planar.InputError` when the output does not come back after the turn
    or never turns back.

    Examples
    --------
    >>> import numpy as np
    >>> from planar.mechanisms import four_bar
    >>> s = stroke(four_bar(4, 2, 3, 4), "angle:rocker")     # the rocker's swing
    >>> round(float(np.degrees(s.stroke)), 9), round(s.time_ratio, 9)
    (63.002863344, 1.424265796)
    """
    res = _one_turn(source, samples, options)
    model = res.model
    u = res.inputs[:, 0]
    y, g, h = _coefficients(res, output_name)
    if np.ptp(y) <= 1e-12 * max(1.0, model.L, np.max(np.abs(y))):  # (its rates rounding's noise: no extreme to find)
        raise InputError(f"output {output_name!r} does not move over the turn ({y[0]:.12g}): it has no stroke")
    if abs(y[-1] - y[0]) > 1e-8 * max(1.0, np.ptp(y)):
        raise InputError(f"output {output_name!r} does not come back after one turn of the input "
                         f"({y[0]:.12g} -> {y[-1]:.12g}): it does not go back and forth")
    # stationary points: a sample where the rate is exactly zero, or a sign change between two
    # samples (the last sample is the first pose again, one turn on)
    n = len(u) - 1
    g[n], h[n] = g[0], h[0]  # one pose: rounding must not hide a root there from both sides
    at = np.flatnonzero(g[:n] == 0)
    i = np.flatnonzero(np.sign(g[:n]) * np.sign(g[1:]) < 0)  # signs: a product of tiny rates underflows
    if at.size + i.size == 0:
        raise InputError(f"output {output_name!r} has no extreme over the turn: it never turns back")

    # safeguarded Newton on the rate g(u) = 0, each root bracketed by two samples and first
    # guessed from the cubic through g and its slope at both
    lo, hi, g_lo = np.r_[u[at], u[i]], np.r_[u[at], u[i + 1]], np.r_[g[at], g[i]]
    x = np.r_[u[at], [_hermite_root(u[k], u[k + 1], g[k], g[k + 1], h[k], h[k + 1]) for k in i]]
    for _ in range(MAX_ITER):
        order = np.argsort(x)
        r = model.sweep(np.r_[u[0], x[order]], **options)
        if not r.ok[1:].all():
            raise AssemblyError(f"refining the extremes of {output_name!r}: the solve failed at input "
                                f"{x[order][~r.ok[1:]][0]:.12g} rad, inside the turn that was swept")
        yx, gx, hx = (np.empty_like(x) for _ in range(3))
        yx[order], gx[order], hx[order] = (a[1:] for a in _coefficients(r, output_name))
        same = np.sign(gx) == np.sign(g_lo)
        lo, g_lo = np.where(same, x, lo), np.where(same, gx, g_lo)
        hi = np.where(same, hi, x)
        with np.errstate(invalid="ignore", divide="ignore"):
            dx = -gx / hx
        newton = (x + dx >= lo - ROUNDING) & (x + dx <= hi + ROUNDING)
        if newton.all() and np.abs(dx).max() <= NEWTON_DONE:
            # the last Newton step is exact to O(dx^2): take it, and the value by Taylor
            x, yx = x + dx, yx + gx * dx + 0.5 * hx * dx**2
            break
        x = np.where(newton, x + dx, 0.5 * (lo + hi))
    else:
        raise AssemblyError(f"the extremes of {output_name!r} did not converge in {MAX_ITER} solves")
    k = np.argsort(x)
    x, yx = x[k], yx[k]
    a, b = int(np.argmin(yx)), int(np.argmax(yx))
    if yx[a] == yx[b]:  # (an output that comes back after a turn turns back at least twice)
        raise InputError(f"output {output_name!r}: the {n} values over the turn bracket one extreme only "
                         f"(at {x[a]:.12g} rad), too few to find its minimum and maximum: give more samples "
                         f"(or a sweep of more values)")
    forward = (x[b] - x[a]) % TURN
    back = TURN - forward
    return Stroke(output=output_name, stroke=float(yx[b] - yx[a]), time_ratio=float(max(forward, back) / min(forward, back)),
                  minimum=float(yx[a]), maximum=float(yx[b]), input_at_minimum=float(x[a]),
                  input_at_maximum=float(x[b]), forward_input=float(forward), return_input=float(back),
                  extremes=tuple((float(p), float(v)) for p, v in zip(x, yx)))
