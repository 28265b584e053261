"""Mechanism files: one JSON document holds a mechanism, its units and its sweep settings.

The format (version 1) mirrors the builder calls of :class:`planar.Mechanism`, so a file reads
like the script that would build it::

    {
      "version": 1,
      "name": "four-bar",
      "units": {"length": "mm", "angle": "deg", "rate": "rpm"},
      "bodies": [{"name": "crank", "mass": 0.5, "com": [0.5, 0.87], "inertia": 0.02}, {"name": "coupler"},
                 {"name": "rocker", "line": ["O4", "B"]}, {"name": "gear", "angle": 30}, {"name": "lever", "offset": 90}],
      "points": [{"name": "C", "body": "coupler", "at": [1.48, 3.67]}],
      "joints": [
        {"type": "revolute", "name": "O2", "bodies": ["ground", "crank"], "at": [0, 0]},
        {"type": "prismatic", "name": "S", "bodies": ["ground", "slider"], "at": [3, 1],
         "direction": [1, 0], "origin": [0, 1]},
        {"type": "slot", ...the same fields as prismatic...},
        {"type": "gear", "name": "g", "bodies": ["sun", "planet"], "radius_a": 2, "radius_b": 1,
         "internal": false, "carrier": "arm", "centre_a": [0, 0], "centre_b": [3, 0],
         "hold_distance": false, "pressure_angle": 20},
        {"type": "rack_pinion", "name": "rp", "bodies": ["pinion", "rack"], "radius": 1,
         "centre": [0, 1], "through": [0, 0], "direction": [1, 0], "side": "left",
         "pressure_angle": 20},
        {"type": "rolling", ...the same fields as rack_pinion, bodies [wheel, body]...}
      ],
      "dimensions": [{"between": ["O2", "A"], "length": 2}, {"between": ["A", "B"], "length": 3}],
      "drivers": [{"joint": "O2", "start": 60}, {"body": "crank"}, {"point": "C", "axis": "x", "name": "Cx"}],
      "gravity": [0, -9.81],
      "loads": [{"body": "rocker", "force": [0, -20], "at": [4, 1], "torque": 0, "fixed": "world"}],
      "sweep": {"start": 0, "stop": 360, "num": 73, "speed": 60, "acceleration": 0,
                "rocking": false}
    }

- Every joint entry is ``{"type", "name", "bodies"}`` plus the keyword arguments of the
  builder method ``add_<type>``; ``bodies`` are its two body arguments in order. Optional fields
  may be left out.
- A body's ``mass``, ``com`` (a sketch point) and ``inertia`` (about the centre of mass) are
  optional, as in :meth:`planar.Mechanism.add_body`; ``gravity`` (a world vector, default none)
  and ``loads`` (constant forces and torques: :meth:`planar.Mechanism.add_load`; ``torque`` and
  ``fixed``, "world" or "body", optional) are for :meth:`planar.Sweep.forces`. Mass, length and
  time units are the user's (kg, m, s give forces in N); only angles are converted.
- A gear's or rack's ``pressure_angle`` is in ``units.angle`` (``pressure_angle_rad`` in
  radians); default 20 degrees (a ``rolling`` contact has none).
- Points are world coordinates of the sketch, in ``units.length``: "m", "cm", "mm" or "in"
  convert (``load(path, length_unit="mm")`` restates every length of the file in mm, and the
  mass properties, gravity and loads with them), any other label only names them. With
  ``dimensions`` (each the length ``between`` two joints or points of one body, as
  :meth:`planar.Mechanism.distance`) they are rough guesses, and loading assembles them: editing
  a length re-assembles the mechanism.
- A body's angle comes from its coordinates: the direction of its reference line (by default
  from its joint nearest the ground to its next joint, see
  :meth:`planar.Mechanism.reference_line`; ``line`` names another, [p, q]), plus ``offset``
  (``units.angle``) if given. Only a body with no line (fewer than two named places, like a gear
  on its axle alone) takes an ``angle`` (its sketch angle, ``units.angle``). ``offset_rad`` and
  ``angle_rad`` give them in radians whatever the units (files written by planar use them where
  degrees would not round-trip).
- A driver's ``start`` is its input value in the sketch (``units.angle`` or length), as
  ``drive(start=)``: files written by planar give it with ``dimensions`` only (without, the
  coordinates show it).
- ``sweep``: ``start``/``stop`` of each input (a number, or a list with one per input) in
  ``units.angle`` for angle inputs and lengths for travel and coordinate inputs; ``num`` values;
  ``speed`` the input's speed (``units.rate``, or length/s; the rate points from start to stop)
  and ``acceleration`` (rad/s^2, or deg/s^2 when the rate unit is deg/s, or length/s^2); ``rocking`` sweeps start -> stop -> start (a back and forth motion).
- ``units``: ``length`` any short label ("" for none), ``angle`` "deg" or "rad", ``rate``
  "rad/s", "deg/s" or "rpm". Defaults: "", "deg", "rad/s".

Saving and loading are exact: a file read and written again is the same document, and a
mechanism written and read again has the same bodies, points, joints and drivers, bit for bit
(numbers are written with Python's shortest round-trip repr).

:mod:`planar.io.schema` holds the field kinds and the checker, :mod:`planar.io.read` and
:mod:`planar.io.write` the two directions, :mod:`planar.io.document` what a loaded file is.

>>> import planar, planar.io
>>> m = planar.Mechanism("pendulum")
>>> _ = m.add_body("bob", angle=0.5)
>>> m.add_revolute("O", m.ground, "bob", at=(0, 0))
>>> m.add_point("P", "bob", at=(1.0, 0.0))
>>> m.drive("O")
>>> text = planar.io.dumps(m)
>>> doc = planar.io.loads(text)
>>> doc.mechanism.compile().dof, planar.io.dumps(doc) == text
(1, True)
"""

from planar.io.document import MechanismFile, SweepSettings
from planar.io.read import MAX_DEPTH, convert_lengths, from_dict, load, loads
from planar.io.schema import VERSION
from planar.io.write import dumps, save, to_dict

__all__ = ["MAX_DEPTH", "MechanismFile", "SweepSettings", "VERSION", "convert_lengths", "dumps", "from_dict", "load",
           "loads", "save", "to_dict"]
