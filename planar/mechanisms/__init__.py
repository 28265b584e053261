"""Textbook mechanisms as builders: each returns an ordinary, driven :class:`planar.Mechanism`.

Builders only draw a sketch (one assembled pose, with geometric constructions) and add
bodies, joints and a driver; every position, rate and sweep comes from the generic solver.
Every builder can be called with no arguments (a demonstration with the seed's dimensions);
``CATALOGUE`` maps each name to its builder.

>>> from planar.mechanisms import CATALOGUE
>>> CATALOGUE["four_bar"]().sweep([0.0, 0.1]).ok.tolist()
[True, True]
"""

from planar.mechanisms.four_bar import four_bar
from planar.mechanisms.geared_five_bar import geared_five_bar
from planar.mechanisms.gears import gear_train, planetary_gear_train, rack_and_pinion, rolling_wheel
from planar.mechanisms.inverted_slider_crank import inverted_slider_crank
from planar.mechanisms.open_chain import open_chain
from planar.mechanisms.six_bar import stephenson_six_bar, two_loop_six_bar, watt_six_bar
from planar.mechanisms.slider_crank import slider_crank

CATALOGUE = {
    "four_bar": four_bar,
    "slider_crank": slider_crank,
    "inverted_slider_crank": inverted_slider_crank,
    "watt_six_bar": watt_six_bar,
    "stephenson_six_bar": stephenson_six_bar,
    "two_loop_six_bar": two_loop_six_bar,
    "geared_five_bar": geared_five_bar,
    "rack_and_pinion": rack_and_pinion,
    "rolling_wheel": rolling_wheel,
    "gear_train": gear_train,
    "planetary_gear_train": planetary_gear_train,
    "open_chain": open_chain,
}

__all__ = ["CATALOGUE"] + sorted(CATALOGUE)
