"""The linkages path generation (:mod:`planar.synthesis.path`) searches over, each a
:class:`Family`: its design numbers, its tracer in closed form, the map of the unit cube to
designs, the similarity move of designs and its builder's arguments.

A four-bar design is nine numbers: the crank pivot O2, the logarithms of the link lengths
r1 ... r4 (so they stay positive), the frame angle th1 and the coupler point (p, q) in the
coupler's frame, with an assembly mode sigma (+1: B left of the directed line A -> O4). The
coupler point follows in closed form, vectorised over a batch of designs and crank angles::

    A = O2 + r2 e^{i th2},  d = O4 - A,  cos(gamma) = (r3^2 + |d|^2 - r4^2) / (2 r3 |d|)
    th3 = arg d + sigma gamma,  C = A + (p + i q) e^{i th3}

The Stephenson six-bar (:func:`planar.synthesis.path_six_bar`) adds six numbers: link 5 from C
to D, link 6 from D to a third ground pivot O6 (its position, the logarithms of r5 and r6) and
the tracer P on link 5 (p5 along C -> D, q5 to its left), with a second mode (D left of
C -> O6); D is the same circle intersection again.

>>> import numpy as np
>>> from planar.synthesis.families import coupler_points
>>> X = np.array([[0.0, 0.0, np.log(4), 0.0, np.log(2), np.log(3), np.log(4), 1.0, 0.5]])
>>> C, reach = coupler_points(X, np.array([1.0]), np.array([[np.pi / 3]]))
>>> np.round(C, 6).tolist(), np.round(reach, 6).tolist()  # four_bar(4, 2, 3, 4, coupler_point=(1, 0.5)) at 60 deg
([[(1.333494+2.799188j)]], [[0.240563]])
"""

from dataclasses import dataclass

import numpy as np

from planar.mechanisms import four_bar
from planar.mechanisms.six_bar import dyad
from planar.mechanisms.sketch import along
from planar.model import checks

RATIO = (0.2, 4.0)  # range of the sampled lengths against the ground link's
BOX = (-2.0, 2.0)  # range of the sampled points' coordinates (the ground link O2 -> O4 is (0, 0) -> (1, 0))


def coupler_points(X, sigma, th2):
    """Coupler points C (D, K) complex and reaches (D, K) (|cos gamma|: the pose exists where
    it is at most 1) of designs X (D, 9) in modes sigma (D,) at crank angles th2 (D, K).
    Where the reach is above 1, C is that of the nearest pose (cos gamma clipped to +-1)."""
    O2 = X[:, 0] + 1j * X[:, 1]
    r1, r2, r3, r4 = (_length(X[:, k])[:, None] for k in (2, 4, 5, 6))
    O4 = (O2 + r1[:, 0] * np.exp(1j * X[:, 3]))[:, None]
    A = O2[:, None] + r2 * np.exp(1j * th2)
    C, reach = _dyad_point(A, O4, r3, r4, sigma[:, None], X[:, 7] + 1j * X[:, 8])
    return C, reach


def _dyad_point(A, O, r, s, sigma, pq):
    """The point pq (complex, in the frame of link A -> B) of the dyad A-B-O (link r from A,
    link s from the ground pivot O) in mode sigma, and the reach |cos gamma| at A."""
    d = O - A
    L = np.maximum(np.abs(d), 1e-300)
    c = (r**2 + L**2 - s**2) / (2 * r * L)
    th = np.angle(d) + sigma * np.arccos(np.clip(c, -1, 1))
    return A + pq[:, None] * np.exp(1j * th), np.abs(c)


def _length(log_length):
    """A length from its logarithm; a refinement wandering far keeps finite numbers."""
    return np.exp(np.clip(log_length, -20.0, 20.0))


def tracer_points(X, sigma, th2):
    """Tracer points P (D, K) and the larger reach of the two loops of Stephenson six-bars
    X (D, 15) in modes sigma (D, 2) at crank angles th2 (D, K) (see the module)."""
    C, reach = coupler_points(X[:, :9], sigma[:, 0], th2)
    O6 = (X[:, 9] + 1j * X[:, 10])[:, None]
    P, reach_5 = _dyad_point(C, O6, _length(X[:, 11])[:, None], _length(X[:, 12])[:, None], sigma[:, 1:2],
                             X[:, 13] + 1j * X[:, 14])
    return P, np.maximum(reach, reach_5)


def stephenson_tracer(ground, crank, coupler, rocker, *, coupler_point, link_5, link_6, pivot_6, tracer,
                      frame_angle=0.0, crossed=False, crossed_2=False, start=0.0, pivot=(0.0, 0.0),
                      name="path_six_bar"):
    """The Stephenson six-bar of :func:`planar.mechanisms.stephenson_six_bar` with its crank
    pivot at ``pivot`` and a tracer point ``P`` on link 5 (``tracer`` = (p, q): p along C -> D,
    q to its left)."""
    m = four_bar(ground, crank, coupler, rocker, frame_angle=frame_angle, crossed=crossed, start=start,
                 pivot=pivot, name=name)
    coupler_point, tracer = checks.point(coupler_point, "coupler_point"), checks.point(tracer, "tracer")
    link_5, link_6 = checks.length(link_5, "link_5"), checks.length(link_6, "link_6")
    pts = {k: v[1] for k, v in m.sketch().points.items()}
    C = along(pts["A"], pts["B"], *coupler_point)
    dyad(m, ("C", "D", "O6"), ("link5", "link6", "coupler", m.ground), C, checks.point(pivot_6, "pivot_6"), link_5,
          link_6, crossed_2, "the six-bar's dyad C-D-O6")
    m.add_point("P", "link5", at=along(C, m.sketch().points["D"][1], *tracer))
    return m


@dataclass(frozen=True)
class Family:
    """A linkage structure for the search: ``n`` design numbers, ``modes`` assembly modes, the
    closed form of its tracer, the map of the unit cube to designs in the canonical frame, the
    similarity move of designs, the builder's keyword arguments of a design, the builder, the
    tracer's name and the point pairs of its transmission angles."""

    n: int
    modes: int
    points: object
    sample: object
    move: object
    design: object
    build: object
    point: str
    transmission: tuple

    @property
    def cube(self):
        """The dimension of the unit cube the designs are sampled from: the design numbers but
        the four the canonical frame fixes (O2, the ground link's length and angle), and the
        modes."""
        return self.n - 4 + self.modes


def _sample_four_bar(U):
    """Four-bars from points U (D, 6) of the unit cube, in the canonical frame: O2 at the
    origin, O4 at (1, 0) (the search moves each to the targets)."""
    D = len(U)
    X = np.zeros((D, 9))
    X[:, [4, 5, 6]] = np.log(RATIO[0]) + U[:, 0:3] * np.log(RATIO[1] / RATIO[0])
    X[:, 7:9] = BOX[0] + U[:, 3:5] * (BOX[1] - BOX[0])
    return X, np.where(U[:, 5:6] < 0.5, -1.0, 1.0)


def _sample_six_bar(U):
    X4, s4 = _sample_four_bar(U[:, :6])
    X = np.empty((len(U), 15))
    X[:, :9] = X4
    X[:, 9:11] = BOX[0] + U[:, 6:8] * (BOX[1] - BOX[0])
    X[:, 11:13] = np.log(RATIO[0]) + U[:, 8:10] * np.log(RATIO[1] / RATIO[0])
    X[:, 13:15] = BOX[0] + U[:, 10:12] * (BOX[1] - BOX[0])
    return X, np.column_stack((s4, np.where(U[:, 12] < 0.5, -1.0, 1.0)))


def _move_four_bar(X, a, b):
    """Designs X (D, 9) moved by z -> a z + b (a, b complex (D,)): their coupler points move
    alike, their crank angles turn by arg a."""
    X = X.copy()
    O2 = a * (X[:, 0] + 1j * X[:, 1]) + b
    X[:, 0], X[:, 1] = O2.real, O2.imag
    X[:, [2, 4, 5, 6]] += np.log(np.abs(a))[:, None]
    X[:, 3] += np.angle(a)
    X[:, 7:9] *= np.abs(a)[:, None]
    return X


def _move_six_bar(X, a, b):
    X = np.column_stack((_move_four_bar(X[:, :9], a, b), X[:, 9:]))
    O6 = a * (X[:, 9] + 1j * X[:, 10]) + b
    X[:, 9], X[:, 10] = O6.real, O6.imag
    X[:, 11:13] += np.log(np.abs(a))[:, None]
    X[:, 13:15] *= np.abs(a)[:, None]
    return X


def _design_four_bar(X, sigma, start, centre, size, name):
    """The four_bar keyword arguments of a normalised design, at the targets' place and size."""
    L = np.exp(X[[2, 4, 5, 6]]) * size
    return dict(ground=float(L[0]), crank=float(L[1]), coupler=float(L[2]), rocker=float(L[3]),
                frame_angle=float(X[3]), coupler_point=(float(X[7] * size), float(X[8] * size)),
                crossed=bool(sigma[0] < 0), start=float(start),
                pivot=(float(centre[0] + X[0] * size), float(centre[1] + X[1] * size)), name=name)


def _design_six_bar(X, sigma, start, centre, size, name):
    d = _design_four_bar(X, sigma, start, centre, size, name)
    d.update(link_5=float(np.exp(X[11]) * size), link_6=float(np.exp(X[12]) * size),
             pivot_6=(float(centre[0] + X[9] * size), float(centre[1] + X[10] * size)),
             tracer=(float(X[13] * size), float(X[14] * size)), crossed_2=bool(sigma[1] < 0))
    return d


FOUR_BAR = Family(9, 1, lambda X, sigma, th: coupler_points(X, sigma[:, 0], th), _sample_four_bar, _move_four_bar,
                  _design_four_bar, four_bar, "C", ((("B", "A"), ("B", "O4")),))
STEPHENSON = Family(15, 2, tracer_points, _sample_six_bar, _move_six_bar, _design_six_bar, stephenson_tracer, "P",
                    ((("B", "A"), ("B", "O4")), (("D", "C"), ("D", "O6"))))
