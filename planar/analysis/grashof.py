"""Grashof classification of a four-bar: a classification of four link lengths.

>>> grashof(4, 2, 3, 4)
Grashof(kind='crank-rocker', excess=-1.0, input_turns=True)
"""

from dataclasses import dataclass
from numbers import Real

from planar.errors import InputError
from planar.mechanisms import checks

KINDS = ("drag-link", "crank-rocker", "double-rocker", "rocker-crank")  # by the shortest link
LINKS = ("ground", "crank", "coupler", "rocker")


@dataclass(frozen=True)
class Grashof:
    """``kind``: crank-rocker, drag-link, double-rocker, rocker-crank (Grashof, named by the
    shortest link: crank, ground, coupler, rocker), change-point (s + l = p + q) or
    triple-rocker (s + l > p + q). ``excess`` = s + l - (p + q). ``input_turns``: whether the
    input link can turn a full turn relative to the ground."""

    kind: str
    excess: float
    input_turns: bool


def grashof(ground, crank, coupler, rocker, *, driver="crank", rtol=1e-12):
    """Grashof class of the four-bar with these link lengths, and whether ``driver`` (the
    input link: "crank", "coupler" or "rocker") turns fully.

    s + l = p + q counts as a change point within ``rtol`` times the longest link. A link turns
    fully relative to the ground when s + l <= p + q and the shortest link is that link or the
    ground (Grashof's theorem: the shortest link turns fully relative to every other). At a
    change point the branches meet once a turn: a sweep passes it on the branch it follows.

    Examples
    --------
    >>> grashof(2, 4, 3.5, 3).kind, grashof(2, 4, 3.5, 3, driver="coupler").input_turns
    ('drag-link', True)
    >>> grashof(4, 3, 3, 3).kind, grashof(4, 3, 3, 3).input_turns
    ('triple-rocker', False)
    """
    r = checks.lengths(ground=ground, crank=crank, coupler=coupler, rocker=rocker)
    checks.choice(driver, LINKS[1:], "driver")
    if isinstance(rtol, bool) or not isinstance(rtol, Real) or not 0 <= rtol < 1:
        raise InputError(f"rtol must be a number from 0 to 1 (of the longest link), got {rtol!r}")
    s, p, q, l = sorted(r)
    excess = (s + l) - (p + q)
    tied = abs(excess) <= rtol * l
    shortest = [name for name, v in zip(LINKS, r) if v - s <= rtol * l]
    turns = (excess < 0 or tied) and ("ground" in shortest or driver in shortest)
    if tied:
        kind = "change-point"
    elif excess > 0:
        kind = "triple-rocker"
    else:
        kind = KINDS[LINKS.index(shortest[0])]  # Grashof: the shortest link is unique
    return Grashof(kind, excess, bool(turns))
