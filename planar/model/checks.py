"""The builder's argument checks: numbers, points, directions, each refused with a
:class:`planar.errors.ModelError` that names the argument."""

import numpy as np

from planar.errors import ModelError

SCALE = 1e100  # sketch coordinates and lengths within +-SCALE: their squares stay finite
# angles (bodies', angle drivers' starts and inputs) within +-MAX_ANGLE radians: float64's
# spacing there (1.9e-9 rad) is the most rounding an angle may add to the rows' 1e-9 tolerance
MAX_ANGLE = 2.0**23
# turns the inner wheel's centre may circle its internal mesh a turn of the wheel: r / (R - r);
# a sweep's steps grow as many times (73 values over a turn: 0.06 s at 10, 2-5 s at 100, 20 s at 1000)
MAX_ORBITS = 100
# radii ratio of a mesh: the small gear's angle grows as many times the other's (at 1e8 a turn
# of the input is 6e8 rad, beyond what float64 holds to the rows' tolerance: a sweep of 5 values 11-17 s)
MAX_RATIO = 1e6


def is_complex(value):
    """Whether numpy reads ``value`` as complex numbers (a ragged list is read as no numbers
    later, where it is converted)."""
    try:
        return np.iscomplexobj(value)
    except ValueError:
        return False


# what a list holds, by the kind of array numpy makes of it
WORDS = {"b": "booleans", "c": "complex ones", "m": "time spans", "M": "dates", "S": "bytes", "U": "strings"}


def not_real(values, dtype):
    """What ``values`` (numpy reads them as ``dtype``) are where they are no real numbers,
    though numpy would read them as numbers (bools, strings, a bytearray's characters' codes,
    complex numbers' real parts, the numbers under a mask); None where they are.

    >>> not_real([1.0, 2.0], np.dtype(float)), not_real(bytearray(b"ab"), np.dtype(np.uint8))
    (None, 'bytearray')
    """
    masked = " with masked values" if np.ma.is_masked(values) else ""
    if isinstance(values, (bytearray, memoryview)):
        return type(values).__name__
    if dtype.kind in "bcmMSU" or masked:
        return (f"an array of {dtype}" if hasattr(values, "dtype") else WORDS.get(dtype.kind, str(dtype))) + masked
    return "complex ones" if is_complex(values) else None


def floats(value):
    """``value`` as a C-ordered float64 array; a longdouble beyond float64 reads inf, for the
    caller to refuse. Raises what numpy raises for no numbers, OverflowError for an integer
    beyond any float."""
    with np.errstate(over="ignore"):
        return np.array(value, dtype=float, order="C")


def finite(value, what, shape=None):
    """``value`` as a float array, finite (and of ``shape`` if given), else a ModelError naming ``what``."""
    if is_complex(value):  # (numpy would read a complex scalar as its real part)
        raise ModelError(f"{what} must be a real number, got {value!r}")
    if isinstance(value, (bool, np.bool_)):  # (numpy would read True as 1)
        raise ModelError(f"{what} must be a number, got {value!r}")
    try:
        a = floats(value)
    except (TypeError, ValueError):
        raise ModelError(f"{what} must be numeric, got {value!r}") from None
    except OverflowError:  # (an integer beyond any float)
        raise ModelError(f"{what} must be finite, got an integer beyond any float") from None
    if shape is not None and a.shape != shape:
        raise ModelError(f"{what} must have shape {shape}, got {value!r}")
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{what} must be finite, got {value!r}")
    return a


def point(value, what):
    """``value`` as a finite world point (2,), its coordinates within +-SCALE."""
    p = finite(value, what, (2,))
    if np.any(np.abs(p) > SCALE):
        raise ModelError(f"{what} = {p.tolist()} is beyond the numbers a sketch holds (+-{SCALE:g}): give it in "
                         f"another unit")
    return p


def flag(value, what):
    """``value`` as a bool where it is one (True, False, numpy's, or the numbers 0 and 1 of a
    table of designs): a string such as "no" is refused, not read as true."""
    if not (isinstance(value, (bool, np.bool_)) or (isinstance(value, (int, float, np.number)) and value in (0, 1))):
        raise ModelError(f"{what} must be True or False, got {value!r}")
    return bool(value)


def length(value, what):
    """``value`` as a positive length, at most SCALE."""
    v = float(finite(value, what, ()))
    if v <= 0:
        raise ModelError(f"{what} must be positive, got {value!r}")
    if v > SCALE:  # (a distance of 1e308 assembled, and the sketch's size overflowed)
        raise ModelError(f"{what} = {v:g} is beyond the lengths a sketch holds ({SCALE:g}): give it in another unit")
    return v


def pressure_angle(value, joint):
    """A gear's pressure angle in [0, pi/2) radians."""
    a = float(finite(value, f"joint {joint!r} pressure_angle", ()))
    if not 0 <= a < np.pi / 2:
        raise ModelError(f"joint {joint!r}: pressure_angle must be in [0, pi/2) radians, got {a!r}")
    return a


def gear_radii(r_a, r_b, internal, joint):
    """Refuse a mesh whose radii are more than MAX_RATIO apart, or an internal one of equal
    radii, or of radii so close that the inner wheel's centre circles more than MAX_ORBITS
    times a turn of the wheel."""
    r, R = sorted((r_a, r_b))
    if R > MAX_RATIO * r:
        raise ModelError(f"gear {joint!r}: the radii {r:.12g} and {R:.12g} are {R / r:.3g} times apart, more than "
                         f"{MAX_RATIO:g}: the small gear would turn that many times a turn of the other (its angle "
                         f"beyond what double precision holds to the tolerance); give radii nearer each other")
    if not internal:
        return
    if R == r:
        raise ModelError(f"gear {joint!r}: an internal mesh needs different radii")
    if r > MAX_ORBITS * (R - r):
        raise ModelError(f"gear {joint!r}: the internal radii {r:.12g} and {R:.12g} are {R - r:.3g} apart: the inner "
                         f"wheel's centre would circle {r / (R - r):.3g} times a turn of the wheel, more than "
                         f"{MAX_ORBITS:g}; give radii more than {r / MAX_ORBITS:.3g} apart")


def direction(value, what):
    """``value`` as a unit vector (2,)."""
    v = point(value, what)
    if np.hypot(*v) == 0:
        raise ModelError(f"{what} must be a non-zero vector, got {value!r}")
    return v / np.hypot(*v)
