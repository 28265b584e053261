"""The mutable builder :class:`Mechanism` and the immutable compiled :class:`Model`.

A mechanism is sketched in world coordinates: every point and joint is placed where it is in
one assembled pose (the sketch). The sketch fixes the link lengths, is the first guess of
every solve and picks the assembly mode; lengths stated with :meth:`Mechanism.distance` make
it a rough guess that compile assembles exactly (see :mod:`planar.dimensions`).

A body's angle is the world direction of the line from its joint nearest the ground to its
next joint (joints ordered by the graph distance from the ground of the body they lead to, then
by order of addition; its named points follow its joints), unless ``angle=`` is given: so the
angles of a four-bar are the textbook's theta2, theta3 and theta4. Angles are radians.

>>> import numpy as np, planar
>>> m = planar.Mechanism()
>>> crank, coupler, rocker = m.add_body("crank"), m.add_body("coupler"), m.add_body("rocker")
>>> m.add_revolute("O2", m.ground, crank, at=(0, 0))
>>> m.add_revolute("A", crank, coupler, at=(1, 1.7320508075688772))
>>> m.add_revolute("B", coupler, rocker, at=(3.0809504341380123, 3.8929870145543637))
>>> m.add_revolute("O4", rocker, m.ground, at=(4, 0))
>>> m.drive("O2")
>>> res = m.sweep(np.radians([60.0, 90.0]))
>>> res.ok.tolist()
[True, True]
>>> np.degrees([res.angle(b)[0] for b in ("crank", "coupler", "rocker")]).round(2).tolist()
[60.0, 46.08, 103.28]
"""

from planar.model.builder import Mechanism
from planar.model.frozen import GROUND, Body, Model, Sketch

__all__ = ["GROUND", "Body", "Mechanism", "Model", "Sketch"]
