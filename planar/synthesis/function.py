"""Function generation: a four-bar or slider-crank whose output follows y = f(x).

x over ``x_range`` maps linearly to the crank angle over ``input_range``; y = f(x) maps
linearly, f(x0) to the start and f(xf) to the end of ``output_range``, to the rocker's
angle (four-bar) or the slider's travel (slider-crank). Through three precision points the
loop equation is linear in three constants and solved exactly; through more, in the least
squares sense (of the loop equation's residual).

Four-bar (O2 at the origin, O4 = (r1, 0); Freudenstein's equation)::

    K1 cos th4 - K2 cos th2 + K3 = cos(th2 - th4),
    K1 = r1 / r2,  K2 = r1 / r4,  K3 = (r1^2 + r2^2 - r3^2 + r4^2) / (2 r2 r4)

Slider-crank (slide line y = e, travel s = x of the pin B)::

    K1 s cos th2 + K2 sin th2 + K3 = s^2,   K1 = 2 r2,  K2 = 2 e r2,  K3 = r3^2 - r2^2 - e^2

>>> import numpy as np
>>> s = function_four_bar(np.log10, (1, 2), np.radians([45, 105]), np.radians([135, 225]))
>>> s.ok, bool(s.max_error < 1e-9)
(True, True)
"""

from dataclasses import replace

import numpy as np

from planar.arguments import finite_number
from planar.errors import InputError, SynthesisError
from planar.mechanisms import four_bar, slider_crank
from planar.mechanisms.sketch import left_of, polar
from planar.model.checks import SCALE
from planar.synthesis.result import check, floats

MAX_POINTS = 10_000  # precision points: a least-squares fit of three constants needs no more


def precision_points(x_range, n=3, spacing="chebyshev"):
    """``n`` precision points over ``x_range``: Chebyshev spacing (the roots of the degree-n
    Chebyshev polynomial mapped to the range, which spread the structural error evenly) or
    ``"even"`` (both ends included).

    >>> precision_points((1, 2)).round(6).tolist()
    [1.066987, 1.5, 1.933013]
    """
    x0, xf = _pair(x_range, "x_range")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_POINTS:
        raise InputError(f"the number of precision points must be a whole number from 1 to {MAX_POINTS}, got {n!r}")
    if not (isinstance(spacing, str) and spacing in ("chebyshev", "even")):  # (an array compared element-wise)
        raise InputError(f"spacing must be 'chebyshev' or 'even', got {spacing!r}")
    if spacing == "chebyshev":
        j = np.arange(1, int(n) + 1)
        return (x0 + xf) / 2 - (xf - x0) / 2 * np.cos((2 * j - 1) * np.pi / (2 * n))
    return np.linspace(x0, xf, int(n))


def freudenstein(th2, th4):
    """K1, K2, K3 of Freudenstein's equation through the (th2, th4) pairs: exact for three,
    least squares for more."""
    th2 = _angles(th2, "th2")
    th4 = _angles(th4, "th4", th2.size)
    M = np.stack((np.cos(th4), -np.cos(th2), np.ones_like(th2)), axis=1)
    return _solve(M, np.cos(th2 - th4), "crank and rocker angles")


def four_bar_lengths(K, ground=1.0):
    """Link lengths (r1, r2, r3, r4) from Freudenstein's K1, K2, K3 and the ground length.
    A negative r2 or r4 is a crank or rocker pointing the other way: its angle is th + pi."""
    try:
        K1, K2, K3 = (float(k) for k in K)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"K must be Freudenstein's three constants K1, K2, K3, got {K!r}") from None
    if not np.all(np.isfinite([K1, K2, K3])):
        raise InputError(f"Freudenstein's constants must be finite, got {K!r}")
    if K1 == 0 or K2 == 0:
        raise SynthesisError(f"Freudenstein's K1 = {K1:.6g}, K2 = {K2:.6g}: a crank or rocker of infinite "
                             "length; shift or widen the angle ranges")
    if not (finite_number(ground) and 0 < ground <= SCALE):
        raise InputError(f"ground must be a positive length up to {SCALE:g}, got {ground!r}")
    r1 = float(ground)
    r2, r4 = r1 / K1, r1 / K2
    with np.errstate(over="ignore", invalid="ignore"):
        r3sq = np.float64(r1)**2 + r2**2 + r4**2 - 2 * r2 * r4 * K3
    if not np.isfinite(r3sq):
        raise SynthesisError(f"Freudenstein's K1 = {K1:.6g}, K2 = {K2:.6g} with ground {r1:g} give links beyond "
                             "float64: give a smaller ground length, or shift or widen the angle ranges")
    if r3sq <= 0:
        raise SynthesisError(f"Freudenstein's K3 = {K3:.6g} gives no real coupler (r3^2 = {r3sq:.6g}): "
                             "shift or widen the angle ranges")
    return r1, r2, float(np.sqrt(r3sq)), r4


def slider_crank_dimensions(th2, s):
    """(crank r2, coupler r3, offset e) of the slider-crank through the (th2, s) pairs: exact
    for three, least squares for more. A negative r2 is a crank pointing the other way."""
    th2 = _angles(th2, "th2")
    s = _angles(s, "s", th2.size)
    if np.abs(s).max() > SCALE:  # (their squares overflowed)
        raise InputError(f"s must be slider travels within +-{SCALE:g}, got {s.tolist()}: give them in another unit")
    M = np.stack((s * np.cos(th2), np.sin(th2), np.ones_like(th2)), axis=1)
    K1, K2, K3 = _solve(M, s**2, "crank angles and slider travels")
    if K1 == 0:
        raise SynthesisError("K1 = 0 gives a crank of zero length: shift the travel range or the crank angles")
    r2, e = K1 / 2, K2 / K1
    r3sq = K3 + r2**2 + e**2
    if r3sq <= 0:
        raise SynthesisError(f"K3 = {K3:.6g} gives no real coupler (r3^2 = {r3sq:.6g}): shift the travel range")
    return float(r2), float(np.sqrt(r3sq)), float(e)


def function_four_bar(f, x_range, input_range, output_range, *, points=3, spacing="chebyshev", ground=1.0,
                      name="function_four_bar"):
    """A four-bar whose rocker angle follows ``f`` (see the module): precision points
    ``points`` (a count, spaced by ``spacing``, or the x values themselves), ``ground`` the
    length r1 (it scales the linkage). Returns a :class:`planar.synthesis.Synthesis` whose
    targets are the rocker angles at the precision points, checked by a sweep of the built
    four-bar over the whole input range; ``notes["structural_error"]`` is the largest rocker
    angle error over that sweep (rad). Where the solution has a negative crank or rocker
    length, that link is built pointing the other way, and its angles (inputs, targets) are
    the ranges' plus pi: ``notes["shift"]`` holds (input shift, output shift)."""
    x, th2, out = _mapped(f, x_range, input_range, output_range, points, spacing)
    r1, r2, r3, r4 = four_bar_lengths(freudenstein(th2, out), ground)
    # a negative length turns its link half a turn: the built link's angle is th + pi
    shift = (np.pi if r2 < 0 else 0.0, np.pi if r4 < 0 else 0.0)
    r2, r4, th2, out = float(abs(r2)), float(abs(r4)), th2 + shift[0], out + shift[1]
    input_range, output_range = np.add(input_range, shift[0]), np.add(output_range, shift[1])
    A, O4 = polar((0, 0), r2, th2[0]), np.array([r1, 0.0])
    crossed = not left_of(A, O4, O4 + polar((0, 0), r4, out[0]))
    design = dict(ground=r1, crank=r2, coupler=r3, rocker=r4, crossed=crossed, start=float(input_range[0]),
                  name=name)
    return _checked(four_bar, design, th2, out, input_range, output_range, x_range, f, shift,
                    lambda res: res.angle("rocker"), lambda a, t: np.abs(np.angle(np.exp(1j * (a - t)))))


def function_slider_crank(f, x_range, input_range, output_range, *, points=3, spacing="chebyshev",
                          name="function_slider_crank"):
    """A slider-crank whose slider travel (x of the pin B on the slide line y = offset)
    follows ``f`` (see the module), as :func:`function_four_bar`; ``output_range`` is the
    travel's (start, end), a length."""
    x, th2, out = _mapped(f, x_range, input_range, output_range, points, spacing)
    r2, r3, e = slider_crank_dimensions(th2, out)
    shift = (np.pi if r2 < 0 else 0.0, 0.0)
    r2, th2, input_range = float(abs(r2)), th2 + shift[0], np.add(input_range, shift[0])
    crossed = bool(out[0] < r2 * np.cos(th2[0]))
    design = dict(crank=r2, coupler=r3, offset=e, crossed=crossed, start=float(input_range[0]), name=name)
    return _checked(slider_crank, design, th2, out, input_range, output_range, x_range, f, shift,
                    lambda res: res.coordinate("slide"), lambda a, t: np.abs(a - t))


def _checked(builder, design, th2, out, input_range, output_range, x_range, f, shift, read, error):
    mech = builder(**design)
    span = tuple(float(v) for v in input_range)
    size = abs(output_range[1] - output_range[0])
    s = check(mech, builder, design, th2, out, lambda res, i: read(res)[i], error, size=size, span=span,
              exact=len(th2) == 3)
    # the whole range: the output asked for at every value of the checking sweep
    u = s.sweep.inputs[:, 0]
    xs = x_range[0] + (u - span[0]) / (span[1] - span[0]) * (x_range[1] - x_range[0])
    want = _map(_evaluate(f, xs), f, x_range, output_range)
    with np.errstate(all="ignore"):  # (NaN where f is undefined between the precision points)
        worst = float(np.max(error(read(s.sweep), want)))
    return replace(s, notes={"structural_error": worst, "shift": shift})


def _mapped(f, x_range, input_range, output_range, points, spacing):
    if not callable(f):
        raise InputError(f"f must be a function of x, got {f!r}")
    x0, xf = _pair(x_range, "x_range")
    a0, af = _pair(input_range, "input_range")
    if abs(af - a0) > 2 * np.pi:  # (the checking sweep held 2.9e9 values for 1e8 rad)
        raise InputError(f"input_range spans {abs(af - a0):.6g} rad, more than a turn: a crank's positions repeat "
                         f"each turn; give at most 2 pi")
    _pair(output_range, "output_range")
    x = precision_points((x0, xf), points, spacing) if np.ndim(points) == 0 else np.asarray(points, float)
    if x.ndim != 1 or len(x) < 3 or not np.all(np.isfinite(x)):
        raise InputError(f"function generation needs at least three finite precision points, got {points!r}")
    th2 = a0 + (x - x0) / (xf - x0) * (af - a0)
    y = _evaluate(f, x)
    if not np.all(np.isfinite(y)):
        raise InputError(f"f is not finite at the precision points {np.round(x[~np.isfinite(y)], 12).tolist()}: "
                         "give an f defined over all of x_range")
    out = _map(y, f, (x0, xf), output_range)
    if not np.all(np.isfinite(out)):
        raise InputError(f"f's values at the precision points {y.tolist()}, mapped onto output_range from its "
                         "values at the ends of x_range, overflow: give f in other units")
    return x, th2, out


def _evaluate(f, x):
    """f at each of x as a float array, f's numpy warnings silenced (its values are checked where used)."""
    try:
        with np.errstate(all="ignore"):
            y = [f(v) for v in x]
    except (TypeError, ValueError) as e:
        raise InputError(f"f must give one number for each x (a real float); it raised {type(e).__name__}: "
                         f"{e}") from None
    a = floats(y)
    if a is None or a.shape != (len(x),):
        k = next((k for k, v in enumerate(y) if np.ndim(v) or floats(v) is None), 0)
        raise InputError(f"f must give one number for each x (a real float), got {y[k]!r} at x = {float(x[k])!r}")
    return a


def _map(y, f, x_range, output_range):
    y0, yf = (float(v) for v in _evaluate(f, x_range))
    if not np.isfinite(y0) or not np.isfinite(yf) or y0 == yf:
        raise InputError(f"f must take different finite values at the ends of x_range {tuple(x_range)}, "
                         f"got {y0!r} and {yf!r}: the output range is mapped onto them")
    with np.errstate(all="ignore"):  # (checked where used)
        return output_range[0] + (y - y0) / (yf - y0) * (output_range[1] - output_range[0])


def _angles(v, what, size=None):
    """``v`` as a 1-D array of at least three finite numbers (of ``size`` values where given)."""
    a = floats(v)
    if a is None:
        raise InputError(f"{what} must be a list of numbers, got {v!r}")
    if a.ndim != 1 or not np.all(np.isfinite(a)) or (size is not None and a.size != size):
        raise InputError(f"{what} must be a list of finite numbers, one per precision point, got {v!r}")
    if a.size < 3:
        raise InputError(f"{what} holds {a.size} precision points: three fix the three constants, more are fitted "
                         "by least squares; give at least three")
    return a


def _pair(v, what):
    p = floats(v)
    if p is None or p.shape != (2,):
        raise InputError(f"{what} must be a pair (start, end) of numbers, got {v!r}")
    a, b = float(p[0]), float(p[1])
    if not (np.isfinite(a) and np.isfinite(b)) or a == b:
        raise InputError(f"{what} must be two different finite numbers, got {v!r}")
    if max(abs(a), abs(b)) > SCALE:  # (beyond, their difference overflows)
        raise InputError(f"{what} must be within +-{SCALE:g}, got ({a:g}, {b:g}): give it in another unit")
    return a, b


def _solve(M, rhs, what):
    if np.linalg.matrix_rank(M) < 3:
        raise InputError(f"the precision points' {what} do not fix the three constants: give three distinct points")
    if len(M) == 3:
        return np.linalg.solve(M, rhs)
    return np.linalg.lstsq(M, rhs, rcond=None)[0]
