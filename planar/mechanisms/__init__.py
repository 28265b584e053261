"""Textbook mechanisms as builders: each returns an ordinary, driven :class:`planar.Mechanism`.

Every builder can be called with no arguments (a demonstration with the seed's dimensions);
``CATALOGUE`` maps each name to its builder.

>>> from planar.mechanisms import CATALOGUE
>>> CATALOGUE["four_bar"]().sweep([0.0, 0.1]).ok.tolist()
[True, True]
"""

from planar.mechanisms.four_bar import four_bar

CATALOGUE = {
    "four_bar": four_bar,
}

__all__ = ["CATALOGUE"] + sorted(CATALOGUE)
