"""Argument checks shared by the builders: each failure names the argument and the fix."""

import math

import numpy as np

from planar.errors import ModelError
from planar.model import checks as model_checks

SCALE = model_checks.SCALE  # lengths and numbers of a catalogue mechanism within 1/SCALE..SCALE
# links of a chain or gears of a train: compile()'s rank test of the sketch grows with their cube
# (256 links compile in about a second, 1000 in over 20)
MAX_LINKS = 256


def _real(value):
    """float(value), a TypeError for a complex number (numpy's complex64 too: float() would
    take its real part) or a bool (float() would take True as 1)."""
    if model_checks.is_complex(value) or isinstance(value, (bool, np.bool_)):
        raise TypeError(value)
    return float(value)


def lengths(**named):
    """Check that every named length is a finite positive number; return them as floats."""
    out = []
    for key, value in named.items():
        try:
            v = _real(value)
        except (TypeError, ValueError):
            raise ModelError(f"{key} must be a number, got {value!r}") from None
        except OverflowError:  # (an integer beyond any float)
            raise ModelError(f"{key} must be a positive length, got {value!r}") from None
        if not math.isfinite(v) or v <= 0:
            raise ModelError(f"{key} must be a positive length, got {value!r}")
        if not 1 / SCALE <= v <= SCALE:
            raise ModelError(f"{key} = {v:g} is beyond the lengths a sketch holds ({1 / SCALE:g} to {SCALE:g}): "
                             f"give it in another unit")
        out.append(v)
    return out


def number(value, what):
    """A finite float (an angle, an offset, a travel)."""
    try:
        v = _real(value)
    except (TypeError, ValueError):
        raise ModelError(f"{what} must be a number, got {value!r}") from None
    except OverflowError:  # (an integer beyond any float)
        v = math.inf
    if not math.isfinite(v):
        raise ModelError(f"{what} must be finite, got {value!r}")
    if abs(v) > SCALE:
        raise ModelError(f"{what} = {v:g} is beyond the numbers a sketch holds (+-{SCALE:g}): give it in another unit")
    return v


flag = model_checks.flag  # the catalogue's flags as the builder's


def choice(value, choices, what):
    """``value`` if it is one of ``choices``."""
    if not isinstance(value, str) or value not in choices:  # (an array compared element by element)
        raise ModelError(f"{what} must be one of {list(choices)}, got {value!r}")
    return value


def point_pair(value, what, required=False):
    """A (p, q) pair of numbers (a point along a link and to its left, or x and y), or None
    when not ``required``."""
    if value is None and not required:
        return None
    try:
        p, q = value
    except (TypeError, ValueError):
        raise ModelError(f"{what} must be a pair of two numbers, got {value!r}") from None
    return number(p, f"{what}[0]"), number(q, f"{what}[1]")


def length_list(values, what, count=None, at_least=1):
    """A list of positive lengths: exactly ``count`` of them, or ``at_least`` to MAX_LINKS."""
    try:
        listed = list(values) if not isinstance(values, (str, bytes)) else None  # (a string would split)
    except TypeError:
        listed = None
    if listed is None:
        raise ModelError(f"{what} must be a sequence of lengths, got {values!r}")
    values = listed
    if (count is not None and len(values) != count) or not at_least <= len(values) <= MAX_LINKS:
        need = f"exactly {count}" if count is not None else f"from {at_least} to {MAX_LINKS}"
        raise ModelError(f"{what} must hold {need} lengths, got {len(values)}: {repr(values)[:80]}")
    return lengths(**{f"{what}[{k}]": v for k, v in enumerate(values)})
