"""What the app's page edits: a catalogue mechanism's dimensions (or a mechanism file's stated
lengths) typed with units, read and checked as they are typed, and the mechanism they build.

Nothing here needs Bokeh: the page only shows what these functions return. Every refusal is a
:class:`planar.PlanarError` whose message names the field and the fix; the page shows it as is.

>>> form = FORMS["four_bar"]
>>> values = form.read({"rocker": "10"})            # the other fields at their defaults
>>> design = Design(form, values, Units("cm"))
>>> design.checks()[0]
'Grashof class: triple-rocker (s + l - p - q = 5): the crank cannot turn fully'
>>> design.build()
Traceback (most recent call last):
...
planar.errors.AssemblyError: the four-bar at crank angle 0 rad cannot be placed: circles of radii 3 and 10 with centres 2 apart do not meet; choose a start inside the motion range or other dimensions
>>> form.read({"crank": "-4"})
Traceback (most recent call last):
...
planar.errors.InputError: crank: -4 cm is refused: a length must be positive
"""

import json
import math
from dataclasses import dataclass, field

from planar.analysis import grashof
from planar.errors import InputError
from planar.mechanisms import CATALOGUE
from planar.units import Units, convert_length


@dataclass(frozen=True)
class Field:
    """One typed number: ``name`` on the page; ``arg`` the builder's keyword and ``slot`` its
    index when the keyword takes a tuple; ``kind`` "length" (positive), "signed" (a length of
    either sign, as an offset or a point's coordinate) or "angle"; ``default`` in the page's
    units (lengths are numbers in whatever length unit is chosen)."""

    name: str
    arg: str
    default: float
    kind: str = "length"
    slot: int | None = None


@dataclass(frozen=True)
class Form:
    """The fields of one catalogue builder. ``loop`` names the four fields of its first
    four-bar (ground, crank, coupler, rocker) for the Grashof class; ``slider`` the crank,
    coupler and offset fields of a slider-crank."""

    builder: str
    fields: tuple
    loop: tuple = ()
    slider: tuple = ()

    def field(self, name):
        return next(f for f in self.fields if f.name == name)

    def read(self, texts, length="cm"):
        """Field values from the page's texts (a dict name -> text; a missing name keeps its
        default); a text that is not a finite number, or a length that is not positive, is
        refused with an :class:`InputError` naming the field."""
        return {f.name: read_number(texts.get(f.name, repr(f.default)), f, length) for f in self.fields}


def read_number(text, f, length="cm"):
    """The number typed into field ``f``, or an :class:`InputError` naming the field."""
    try:
        v = float(str(text).strip())
    except ValueError:
        raise InputError(f"{f.name}: {str(text).strip()!r} is not a number: type a number like 2.5") from None
    if not math.isfinite(v):
        raise InputError(f"{f.name}: {text!r} is not a finite number")
    if f.kind == "length" and v <= 0:
        raise InputError(f"{f.name}: {v:g} {length} is refused: a length must be positive")
    return v


def _four_bar(ground=4.0, crank=2.0, coupler=3.0, rocker=4.0):
    return (Field("ground", "ground", ground), Field("crank", "crank", crank), Field("coupler", "coupler", coupler),
            Field("rocker", "rocker", rocker))


def _point(arg, label, p, q):
    return (Field(f"{label} p (along)", arg, p, "signed", 0), Field(f"{label} q (left)", arg, q, "signed", 1))


START = Field("start", "start", 0.0, "angle")
LOOP = ("ground", "crank", "coupler", "rocker")

FORMS = {
    "four_bar": Form("four_bar", _four_bar() + _point("coupler_point", "coupler point", 1.732, 1.0) + (START,),
                     loop=LOOP),
    "slider_crank": Form("slider_crank", (Field("crank", "crank", 2.0), Field("coupler", "coupler", 5.0),
                                          Field("offset", "offset", 1.0, "signed"))
                         + _point("coupler_point", "coupler point", 2.5, 1.0) + (START,),
                         slider=("crank", "coupler", "offset")),
    "watt_six_bar": Form("watt_six_bar", _four_bar(4.0, 1.5, 4.0, 3.5)
                         + _point("coupler_point", "coupler point", 2.0, 1.5)
                         + _point("rocker_point", "rocker point", 1.5, -1.5)
                         + (Field("link 5", "link_5", 3.0), Field("link 6", "link_6", 3.0), START), loop=LOOP),
    "stephenson_six_bar": Form("stephenson_six_bar", _four_bar(4.0, 1.5, 4.0, 3.5)
                               + _point("coupler_point", "coupler point", 2.0, 1.5)
                               + (Field("link 5", "link_5", 4.0), Field("link 6", "link_6", 3.0),
                                  Field("pivot O6 x", "pivot_6", 2.0, "signed", 0),
                                  Field("pivot O6 y", "pivot_6", 6.0, "signed", 1), START), loop=LOOP),
    "two_loop_six_bar": Form("two_loop_six_bar", tuple(
        Field(f"r{k + 1}", "lengths", v, "length", k) for k, v in enumerate((4.0, 1.5, 4.0, 3.5, 5.0, 2.0, 5.0, 3.5)))
        + (START,), loop=("r1", "r2", "r3", "r4")),
}


def grashof_line(lengths, driver="crank"):
    """The Grashof class of four link lengths (ground, crank, coupler, rocker) and what it
    means for the input, in one line."""
    g = grashof(*lengths, driver=driver)
    turns = "turns fully" if g.input_turns else "cannot turn fully"
    return f"Grashof class: {g.kind} (s + l - p - q = {g.excess:.6g}): the {driver} {turns}"


def slider_line(crank, coupler, offset):
    """Whether a slider-crank's crank turns fully and whether it can be put together at all."""
    if abs(offset) > crank + coupler:
        return f"cannot be assembled: |offset| {abs(offset):g} > crank + coupler {crank + coupler:g}"
    if crank + abs(offset) <= coupler:
        return f"the crank turns fully (crank + |offset| = {crank + abs(offset):g} <= coupler {coupler:g})"
    return (f"the crank cannot turn fully (crank + |offset| = {crank + abs(offset):g} > coupler {coupler:g}): "
            f"it rocks between limit positions")


@dataclass
class Design:
    """A catalogue mechanism as typed: its :class:`Form`, the field ``values`` (numbers, in
    the ``units`` of the page: lengths in ``units.length``, the start in ``units.angle``) and
    the assembly modes ``crossed`` and ``crossed_2``."""

    form: Form
    values: dict
    units: Units
    crossed: bool = False
    crossed_2: bool = False

    def kwargs(self):
        """The builder's keyword arguments (the start in radians)."""
        out = {}
        for f in self.form.fields:
            v = self.values[f.name]
            if f.kind == "angle":
                out[f.arg] = float(self.units.angle_to_internal(v))
            elif f.slot is None:
                out[f.arg] = v
            else:
                out.setdefault(f.arg, {})[f.slot] = v
        out = {k: tuple(v[i] for i in sorted(v)) if isinstance(v, dict) else v for k, v in out.items()}
        out["crossed"] = self.crossed
        if self.form.builder != "four_bar" and self.form.builder != "slider_crank":
            out["crossed_2"] = self.crossed_2
        return out

    def build(self):
        """The :class:`planar.Mechanism` (it raises the builder's own errors)."""
        return CATALOGUE[self.form.builder](**self.kwargs())

    def checks(self):
        """Lines on what the lengths allow, before any solve: the Grashof class of the first
        loop, or a slider-crank's rotation condition."""
        v = self.values
        if self.form.loop:
            return [grashof_line([v[n] for n in self.form.loop])]
        if self.form.slider:
            return [slider_line(*(v[n] for n in self.form.slider))]
        return []

    def restated(self, length):
        """The same design with its lengths in unit ``length`` (m, cm, mm or in)."""
        values = {f.name: (self.values[f.name] if f.kind == "angle"
                           else float(convert_length(self.values[f.name], self.units.length, length)))
                  for f in self.form.fields}
        units = Units(length, self.units.angle, self.units.rate)
        return Design(self.form, values, units, self.crossed, self.crossed_2)


@dataclass
class FileDesign:
    """A mechanism file as opened: its document ``data`` (:func:`planar.io.to_dict` form), whose
    stated lengths (``dimensions``) are the fields, named by their two points."""

    data: dict
    source: str = "<mechanism file>"
    fields: tuple = field(init=False)

    def __post_init__(self):
        self.fields = tuple(Field("-".join(d["between"]), f"dimensions[{k}]", float(d["length"]))
                            for k, d in enumerate(self.data.get("dimensions", [])))

    @property
    def units(self):
        u = self.data.get("units", {})
        return Units(u.get("length", ""), u.get("angle", "deg"), u.get("rate", "rad/s"))

    def read(self, texts):
        length = self.units.length
        return {f.name: read_number(texts.get(f.name, repr(f.default)), f, length) for f in self.fields}

    def with_values(self, values):
        """The document with the stated lengths set to ``values`` (name -> number)."""
        data = json.loads(json.dumps(self.data))
        for f, d in zip(self.fields, data.get("dimensions", [])):
            d["length"] = values[f.name]
        return FileDesign(data, self.source)

    def build(self):
        from planar.io import from_dict

        return from_dict(self.data, self.source).mechanism

    def checks(self):
        return []

    def restated(self, length):
        from planar.io import convert_lengths

        return FileDesign(convert_lengths(self.data, length, self.source), self.source)
