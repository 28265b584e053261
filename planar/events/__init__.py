"""Singular positions met along a branch: located, classified and stepped through.

Where the natural continuation (input as the parameter) fails, the branch is followed by
pseudo-arclength continuation on the curve ``Phi(q; u_a + (sigma/d) du) = 0`` in the scaled
unknowns ``y = (q / col_scale, sigma)``; ``sigma`` is the scaled input distance from u_a along
the sweep direction. On that curve:

- a *limit position* (turning point) is where the input stops and turns back: the sigma
  component of the unit tangent changes sign. It is located by regula falsi on that component
  (the input error is quadratic in the arclength error, so to ~1e-15);
- a *bifurcation* (change point, parallelogram fold) is where another branch crosses: the sign
  of det [H_y; t] flips while the input keeps going. It is located the same way on that det;
  the two tangents come from the gamma-function quadratic (design notes 3.7), and the tracer,
  which steps over the crossing, stays on the smooth branch;
- a *near-singular* stretch is where the normalised det of the driven system dips below
  :data:`NEAR` without changing sign (an avoided crossing): valid, but sensitive.

This package holds what a sweep reports of them, the :class:`Event`, and the status rule both
engines share (:func:`status_of`); :mod:`planar.events.tracer` the pseudo-arclength tracer and
:mod:`planar.events.crossing` the locating and classifying (:func:`~planar.events.crossing.cross`)
and the way round a circuit through a limit (:func:`~planar.events.crossing.around`).

>>> Event("limit", 1.5, 10).kind
'limit'
"""

from dataclasses import dataclass

import numpy as np

from planar.results import Status

NEAR = 1e-4  # normalised |det| below which a stretch is near-singular
SINGULAR = 1e-10  # ... and below which a point sits on the singular position itself
NEAR_CURVE = 1e-2  # scaled distance to another solution curve below which a crossing is reported
# a redundant joint holds, and a pose on a singular position (where Newton converges only
# linearly) is kept, while its scaled residual is within HELD times the tolerance
HELD = 1e3
# the status of a converged pose by how many of NEAR and SINGULAR its singularity measure is below
BY_MEASURE = np.array([Status.SOLVED, Status.NEAR_SINGULAR, Status.SINGULAR])


def status_of(sing, red=0.0, tol=np.inf):
    """The status of converged poses: INCONSISTENT where a redundant joint's scaled residual
    ``red`` exceeds HELD times ``tol``, else by the singularity measure ``sing``: SINGULAR below
    SINGULAR, NEAR_SINGULAR below NEAR, SOLVED. Scalars or arrays, with no branches: both
    engines use this one rule (the compiled engine compiles it into its loop).

    >>> [str(Status(s)) for s in status_of(np.array([0.5, 1e-6, 0.0]))]
    ['SOLVED', 'NEAR_SINGULAR', 'SINGULAR']
    >>> str(Status(status_of(0.5, red=1.0, tol=1e-12)))
    'INCONSISTENT'
    """
    st = BY_MEASURE[(sing < NEAR) * 1 + (sing < SINGULAR) * 1]
    return st + (Status.INCONSISTENT - st) * (red > HELD * tol)


@dataclass(frozen=True, eq=False)
class Event:
    """A singular position met by a sweep.

    ``kind`` is "limit" (the input cannot go further on this branch), "bifurcation" (branches
    cross: the sweep continued on the smooth branch, or on the other one if asked),
    "singular" (a singular position the branch passes smoothly, as the fold of a double
    parallelogram) or "near_singular" (an avoided crossing or a close approach: values valid
    but sensitive).
    ``input`` is the input value there (a float for one input, else (f,)); ``index`` the first
    sweep value at or after it; ``q`` the pose; ``tangents`` (bifurcation) the (followed,
    other) velocities dq/du along the sweep direction per unit input; ``singularity`` the
    normalised |det| there; ``error`` an estimate of the scaled position error of values in
    the stretch (machine epsilon over the singularity).
    """

    kind: str
    input: object
    index: int
    q: np.ndarray = None
    tangents: tuple = ()
    singularity: float = 0.0
    error: float = 0.0
    note: str = ""

    def __repr__(self):
        u = np.round(np.asarray(self.input, float), 12).tolist()
        return f"Event({self.kind!r}, input={u}, index={self.index})"


__all__ = ["Event", "status_of", "HELD", "NEAR", "NEAR_CURVE", "SINGULAR"]
