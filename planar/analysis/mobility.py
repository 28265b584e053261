"""Mobility report of a mechanism: Grubler's count against the rank of the joint Jacobian.

>>> from planar.mechanisms import planetary_gear_train
>>> print(mobility(planetary_gear_train(planets=3)))
15 coordinates, 16 joint rows: Grubler -1, rank 14, 1 degree(s) of freedom; redundant joints: planet2_ring, planet3_ring; inputs: sun
"""

from dataclasses import dataclass

from planar.errors import ModelError


@dataclass(frozen=True)
class Mobility:
    """``coordinates`` n (3 per moving body), ``joint_rows`` (rows the joints add), ``grubler``
    = n - joint rows (the Grubler-Kutzbach count), ``rank`` of the joint Jacobian at the sketch,
    ``dof`` = n - rank, ``redundant_joints`` (rows that repeat others: their joints' names, kept
    out of Newton and checked after every solve), ``inputs`` (the drivers' names)."""

    coordinates: int
    joint_rows: int
    grubler: int
    rank: int
    dof: int
    redundant_joints: tuple
    inputs: tuple

    def __str__(self):
        red = ", ".join(self.redundant_joints) or "none"
        return (f"{self.coordinates} coordinates, {self.joint_rows} joint rows: Grubler {self.grubler}, "
                f"rank {self.rank}, {self.dof} degree(s) of freedom; redundant joints: {red}; "
                f"inputs: {', '.join(self.inputs) or 'none'}")


def mobility(source):
    """The :class:`Mobility` of a Mechanism, a Model or the model of a sweep result."""
    model = getattr(source, "model", source)
    if hasattr(model, "compile"):
        model = model.compile()
    if not hasattr(model, "rank"):
        raise ModelError(f"mobility needs a Mechanism, a Model or a sweep result, got {type(source).__name__}")
    return Mobility(coordinates=model.n, joint_rows=model.n - model.grubler, grubler=model.grubler, rank=model.rank,
                    dof=model.dof, redundant_joints=tuple(model.redundant_joints), inputs=tuple(model.input_names))
