"""The input's period and whole turns: where the pose comes back to itself a period of the
input on (:class:`Periods`, the :class:`planar.sweep.walk.Walker`'s), and whole turns and
periods added to inputs and angles to the rounding of the result."""

import numpy as np

from planar.solver import DISTANT
from planar.sweep.branch import input_scale

PERIODS = 12  # whole turns of an angle input within which the pose is looked for returning to itself
MODE_PERIODS = 4  # periods the walk from the sketch may go on in other modes before it comes back
SAME = 1e-8  # scaled distance within which a pose after a period is the pose it started from


class Periods:
    """The :class:`planar.sweep.walk.Walker`'s input period: its symmetry, the period the walk
    from the sketch comes back after, and the walk moved by whole periods."""

    def symmetry(self):
        """(P, D): an input period P and the pose shift D over it where the sketch shifted by D
        solves the constraints at its input plus P in the same assembly modes, the constraints
        themselves unchanged by the shift. Either whole turns P of one angle input, D whole turns
        of the angles of the bodies that turn with it (the revolute and slider rows of a pure
        linkage read angles through their sines and cosines, while a gear or a slider's
        relative angle passes the input on linearly: a gear pair of ratio 7/6 comes back after
        7 turns); or, where the rows read some coordinates only linearly (a gear's angle about
        its own pivot, a rack's travel), an input P after which the angles read through sines
        and cosines are back by whole turns, the others moved along the tangent (a gear train
        of any ratio, a planetary train a turn of its carrier on). None where neither holds (a
        geared linkage of ratio pi)."""
        if self._symmetry is None:
            self._symmetry = _symmetry(self.br) or False
        return self._symmetry or None

    def period(self):
        """(P, D): whole periods of :meth:`symmetry` after which the walk from the sketch comes
        back to the sketch up to whole turns D of its angles (a full-turn crank: its coupler and
        rocker may turn too), in its modes: after one, or after several where each passes a
        change point on the smooth branch and comes out in other modes (a Watt six-bar on the
        Grashof boundary: in the sketch's again after two). Or the symmetry's where the first
        period's walk meets a limit (a rocking input: values a period apart are the same pose,
        reached by re-entry). None otherwise (a circuit that closes after more turns)."""
        if self._period is None:
            self._period = False
            sym = self.symmetry()
            if sym is not None:
                m = self.br.m
                P = sym[0]
                k, rounds = len(self.events), self.rounds
                s0 = self.br.signs(m.q0[None], m.u0[None])[0]
                q, u, s = m.q0, m.u0, s0
                for j in range(1, MODE_PERIODS + 1):
                    got = self.walk(q, u, s, u + P, 0)
                    if got[0] == "limit" and j == 1:
                        self._period, self.limit = sym, float(np.ravel(got[1].input)[0])
                    if got[0] != "ok":
                        break
                    q, u, s = got[1], u + P, got[2]
                    if np.all(s == s0):
                        D = whole_turns(self.br, q - m.q0, j * sym[1])
                        self._period = False if D is None else (j * P, D)
                        self.turns = D is not None
                        break
                del self.events[k:]  # those turns are no part of the sweep
                self.rounds = rounds
        return self._period or None

    def keep_period(self, P, D, limit):
        """Take (P, D) as the period (found by a sweep where :meth:`period`'s walk meets a limit;
        ``limit``: the input of a limit that sweep met, None where the input turns fully)."""
        self._period, self.turns, self.limit = (P, D), limit is None, limit

    def _shorten(self, q, u, signs, k):
        """(q, u) moved by k whole periods of the input (:meth:`period`): the pose there is
        the pose at u shifted by whole turns. None where it does not solve there."""
        P, D = self.period()
        uk = add_periods(u, k, P)
        qk, conv, _, _ = self.br.solve(add_periods(q, k, D)[None], uk[None])
        if conv[0] and np.all(self.br.signs(qk, uk[None])[0] == signs):
            return qk[0], uk
        return None


# 2 pi = A1 + A2 + B: A1 with 27 significant bits (n A1 is exact for |n| < 2^26 turns), B the
# rounding of 2 pi to a double, so that whole turns are added to angles of 1e6 rad without the
# 1e-10 rad that n times the rounded 2 pi would carry
TWO_PI_A1 = np.round(2 * np.pi * 2.0**24) / 2.0**24
TWO_PI_A2 = 2 * np.pi - TWO_PI_A1
TWO_PI_B = 2.4492935982947064e-16


def add_turns(x, n):
    """x + 2 pi n (n whole turns) to the rounding of the result, for x small next to 2 pi n.

    >>> x = -0.357564167085735  # 1e6 less 159155 turns (the naive 1e6 - 159155 * 2 * np.pi is 8e-11 off)
    >>> float(x + 159155 * 2 * np.pi), float(add_turns(x, 159155.0))
    (999999.9999999999, 1000000.0)
    """
    if np.all(n == 0):
        return x
    return ((x + n * TWO_PI_B) + n * TWO_PI_A2) + n * TWO_PI_A1


def add_periods(x, n, P):
    """x + n P (P per component, or one) to the rounding of the result, for x small next to
    n P: whole turns by :func:`add_turns`, another period split into a head of 26 significant
    bits (n times it is exact for |n| < 2^26) and the rest.

    >>> float(add_periods(0.25, 3.0, 2 * np.pi)) == float(add_turns(0.25, 3.0)), float(add_periods(1.0, -2.0, 0.75))
    (True, -0.5)
    """
    if np.all(n == 0):
        return x
    whole, turns, head = _split(P)
    return np.where(whole, add_turns(x, n * turns), (x + n * (P - head)) + n * head)


def less_periods(u, k, P):
    """u - k P for u near k P (a far input brought back by whole periods: the large terms
    first, so the small result keeps its rounding).

    >>> float(less_periods(1e6, 159155.0, 2 * np.pi)), float(less_periods(1e6 + 0.5, 1e6, 1.0))
    (-0.357564167085735, 0.5)
    """
    whole, turns, head = _split(P)
    t = k * turns
    return np.where(whole, ((u - t * TWO_PI_A1) - t * TWO_PI_A2) - t * TWO_PI_B, (u - k * head) - k * (P - head))


def within(u, lo, hi, P=None):
    """Whether lo <= u <= hi, or, with a period P of the input, u lies whole periods from such a value.

    >>> within(7.0, 0.5, 1.0, 2 * np.pi), within(7.0, 0.5, 1.0)
    (True, False)
    """
    return lo <= u <= hi if P is None else (u - lo) % P <= hi - lo


def _split(P):
    """Whether each P is whole turns, their number, and P's head of 26 significant bits."""
    turns = np.round(P / (2 * np.pi))
    frac, e = np.frexp(P)
    return np.abs(P - 2 * np.pi * turns) <= 4e-16 * np.abs(P), turns, np.ldexp(np.round(frac * 2.0**26) / 2.0**26, e)


def _symmetry(br):
    """See :meth:`Walker.symmetry`: from the sketch, the driven angle moved by k turns and a
    Newton solve at the input plus k turns, for k = 1 .. PERIODS; else :func:`_linear_symmetry`."""
    m, p = br.m, br.p
    if m.input_lengths.size != 1 or p.drivers.size != 1:
        return None
    q0, u0 = m.q0, m.u0
    s0 = br.signs(q0[None], u0[None])[0]
    if m.input_lengths[0]:  # (a length input turns nothing by whole turns of itself)
        return _linear_symmetry(br, s0)
    with np.errstate(all="ignore"):
        _, J = p.system.evaluate(q0[None], u0[None])
    row = J[0][p.rows[p.drivers[0]]]
    col = p.cols[np.argmax(np.abs(row[p.cols]))]  # the driven angle
    # (the PERIODS candidates in one batch: a solve costs about what one candidate's does)
    P = 2 * np.pi * np.arange(1.0, PERIODS + 1)
    U = u0[None] + P[:, None]
    G = np.repeat(q0[None], PERIODS, 0)
    with np.errstate(all="ignore"):
        Phi, _ = p.system.evaluate(G, U)
    G[:, col] -= Phi[:, p.rows[p.drivers[0]]] / row[col]
    qn, conv, _, _ = br.solve(G, U, max_iter=DISTANT)
    for k in np.flatnonzero(in_modes(br, qn, U, conv, s0)):
        D = whole_turns(br, qn[k] - q0)
        if D is not None:
            return float(P[k]), D
    return _linear_symmetry(br, s0)


def _linear_symmetry(br, s0):
    """(P, D) of :meth:`Walker.symmetry` where the constraints read some coordinates only
    linearly: from the sketch along its tangent v (unit input rate) by P, Newton there, and the
    change d = D kept where each coordinate is back by whole turns (an angle), back (a position)
    or moved by P v (a coordinate read linearly), and the constraints unchanged by D away from
    the sketch too. P: a turn of the input (2 pi scaled), else the input that turns a body by a
    turn (a planetary train's carrier) or takes a point of uniform circular motion round (a
    wheel's centre rolling inside a circle: 2 pi speed / acceleration)."""
    m, p = br.m, br.p
    q0, u0 = m.q0, m.u0
    cols = p.cols
    with np.errstate(all="ignore"):
        v, a = (x[0] for x in br.state(q0[None], u0[None], np.ones((1, 1)))[:2])
    if not np.all(np.isfinite(v[cols]) & np.isfinite(a[cols])):
        return None
    known = np.zeros(m.n, bool)
    known[cols] = True
    rate = np.abs(v[2::3][known[2::3]])
    speed, acc = (np.hypot(x[0::3], x[1::3])[known[0::3] & known[1::3]] for x in (v, a))
    turn = 2 * np.pi / float(input_scale(m)[0])
    cands = np.r_[turn, 2 * np.pi / rate[rate > 1e-9 * turn], 2 * np.pi * speed[acc > 0] / acc[acc > 0]]
    # (a point at rest moves by rounding: its speed over its acceleration is no period)
    Ps = np.array(list(dict.fromkeys(float(x) for x in cands if np.isfinite(x) and x > 1e-6 * turn)))
    if not Ps.size:
        return None
    lins = np.zeros((Ps.size, m.n))
    lins[:, cols] = Ps[:, None] * v[cols]
    U = u0[None] + Ps[:, None]
    # (the candidates in one batch, then taken in turn)
    Q, conv, _, _ = br.solve(q0[None] + lins, U, max_iter=DISTANT)
    same = in_modes(br, Q, U, conv, s0)
    for P, lin, q in zip(Ps[same], lins[same], Q[same]):
        P = float(P)
        d = q - q0
        D = whole_turns(br, d)
        if D is None:
            near = np.abs(d - lin) / m.col_scale <= SAME * (1.0 + np.abs(lin) / m.col_scale)
            back = whole_turns(br, np.where(near, 0.0, d))
            D = None if back is None else np.where(near, d, back)
        if D is not None and _invariant(br, P, D):
            return P, D
    return None


def in_modes(br, Q, U, conv, signs):
    """(N,) whether each pose Q (N, n) at inputs U converged (``conv``) in the modes ``signs``
    (the modes asked only of the converged: a diverged pose reads non-finite)."""
    out = np.zeros(len(Q), bool)
    ok = np.flatnonzero(conv)
    if ok.size:
        out[ok] = np.all(br.signs(Q[ok], U[ok]) == signs, axis=1)
    return out


def _invariant(br, P, D):
    """Whether the shift by D at the input plus P also solves the constraints at a second pose
    of the branch, a fifth of a turn (scaled) from the sketch, to rounding of the shift: a
    symmetry of the branch, not only a pose that happens to solve."""
    m, p = br.m, br.p
    u = m.u0 + 0.2 * np.pi / input_scale(m)
    q_pred, _ = br.predict(m.q0[None], m.u0[None], (u - m.u0)[None])
    q, conv, _, _ = br.solve(q_pred, u[None], max_iter=DISTANT)
    if not conv[0]:
        return False
    with np.errstate(all="ignore"):
        Phi, _ = p.system.evaluate(add_periods(q, 1.0, D), add_periods(u, 1.0, P)[None])
    size = 1.0 + np.max(np.abs(D[p.cols]) / m.col_scale[p.cols])
    return bool(np.max(np.abs(Phi[0, p.rows]) * m.row_scale[p.rows]) <= 1e3 * np.finfo(float).eps * size)


def whole_turns(br, d, base=0.0, slack=0.0):
    """base + the change d - base (n,) of a pose rounded to whole turns of its angles, None
    where it is not whole turns (to SAME + ``slack``, scaled) or moves a position."""
    m, cols = br.m, br.p.cols
    dc = (d - base)[cols]
    turns = np.where(cols % 3 == 2, np.round(dc / (2 * np.pi)), 0.0)
    if not np.max(np.abs(dc - 2 * np.pi * turns) / m.col_scale[cols]) <= SAME + slack:
        return None
    D = np.zeros(m.n) + base
    D[cols] += 2 * np.pi * turns
    return D
