"""Named scalar outputs of a sweep: a body's angle, a joint's coordinate, a point's x or y.

>>> import numpy as np
>>> from planar.mechanisms import slider_crank
>>> res = slider_crank(2, 5, offset=1).sweep([0.0, np.pi / 2])
>>> output(res, "B.x").round(6).tolist(), output(res, "slide", 1).round(6).tolist()
([6.898979, 4.898979], [0.408248, -2.0])
"""

from planar.errors import ModelError


def output(res, name, derivative=0):
    """(N,) value of the output ``name`` over the sweep ``res``, or its first or second time
    derivative (``derivative`` 1 or 2).

    ``name`` is a body (its absolute angle), a joint with a coordinate (a revolute's relative
    angle, a slider's travel), or a point with an axis, "P.x" or "P.y" (a world coordinate).
    With the sweep's default unit input rate and zero input acceleration the derivatives are
    the first and second kinematic coefficients d(output)/du and d2(output)/du2.
    """
    if derivative not in (0, 1, 2):
        raise ModelError(f"derivative must be 0, 1 or 2, got {derivative!r}")
    model = res.model
    if name in model.body_names:
        return (res.angle, res.omega, res.alpha)[derivative](name)
    if name in model.coordinates:
        return res.coordinate(name, derivative)
    point, _, axis = str(name).rpartition(".")
    if axis in ("x", "y") and point in model.points:
        return (res.position, res.velocity, res.acceleration)[derivative](point)[:, "xy".index(axis)]
    raise ModelError(f"unknown output {name!r}: give a body {list(model.body_names)}, a joint with a coordinate "
                     f"{sorted(model.coordinates)}, or a point with an axis such as "
                     f"'{sorted(model.points)[0]}.x'")
