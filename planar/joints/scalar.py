"""The scalar kernels' contract and their shared pieces: one joint at one configuration, for
the compiled engine (:mod:`planar.compiled`), which loops over configurations in machine code.

The numpy kernels of each class stay the reference (and the path used without numba); the
scalar kernels are the same rows written for one joint, plain Python next to each joint class
(its ``scalar`` attribute: the parameters it reads, in the order they are flattened into p;
its kernel; its gamma kernel). A kernel ``kernel(p, c, f, s, phi, jac)`` writes the residual
rows ``phi`` (n_rows,) and the Jacobian block ``jac`` (n_rows, 3 nb) in the class's slot
order (x, y, phi per body), and its gamma kernel ``gamma(p, c, f, s, g)`` the acceleration
right-hand side:

- ``p`` the joint's parameters flattened in the order its ``scalar`` lists them (each (a, b)
  parameter row-major, e.g. ``s`` as s_a.x, s_a.y, s_b.x, s_b.y);
- ``c`` its row constants (a driver's input value in c[0]);
- ``f`` (bodies, 8) the rows x, y, phi, cos phi, sin phi, xd, yd, phid of every body (the
  ground's first) and ``s`` the joint's body ids, slot by slot.

They import no numba (the tests compare them with the numpy kernels anywhere, and ``import
planar`` stays light); :mod:`planar.compiled` compiles them, and the pieces here
(:data:`PIECES`), where it calls them.

>>> import numpy as np
>>> from planar.joints.revolute import revolute
>>> f = np.zeros((2, 8)); f[:, 3] = 1.0; f[1, 0] = 2.0  # body 1 2 to the right, both unrotated
>>> phi, jac = np.zeros(2), np.zeros((2, 9))
>>> revolute(np.array([1.0, 0.0, -1.0, 0.0]), np.zeros(2), f, np.array([0, 1]), phi, jac)
>>> phi.tolist()  # pin at a's (1, 0) and b's (-1, 0): they meet
[0.0, 0.0]
"""

from math import atan2, pi


def vec(f, s, k, x, y):
    """World vector A_k (x, y) of a body-fixed vector on slot k."""
    return f[s[k], 3] * x - f[s[k], 4] * y, f[s[k], 4] * x + f[s[k], 3] * y


def pair(p, f, s):
    """d = P_b - P_a of the body points p[0:2] (slot 0) and p[2:4] (slot 1), and S_a, S_b."""
    sax, say = vec(f, s, 0, p[0], p[1])
    sbx, sby = vec(f, s, 1, p[2], p[3])
    return f[s[1], 0] + sbx - f[s[0], 0] - sax, f[s[1], 1] + sby - f[s[0], 1] - say, sax, say, sbx, sby


def pair_rates(f, s, sax, say, sbx, sby):
    """d_dot and the qdd-free part of d_ddot of d = P_b - P_a."""
    wa, wb = f[s[0], 7], f[s[1], 7]
    ddx = f[s[1], 5] - sby * wb - f[s[0], 5] + say * wa
    ddy = f[s[1], 6] + sbx * wb - f[s[0], 6] - sax * wa
    return ddx, ddy, sax * wa * wa - sbx * wb * wb, say * wa * wa - sby * wb * wb


def pair_row(jac, r, gx, gy, g_pa, g_pb):
    jac[r, 0], jac[r, 1], jac[r, 2] = -gx, -gy, g_pa
    jac[r, 3], jac[r, 4], jac[r, 5] = gx, gy, g_pb


def line(p, f, s):
    """(d, S_a, S_b, u, n) of a point (slot 1) against the line of slot 0 (p: s (4), u (2))."""
    dx, dy, sax, say, sbx, sby = pair(p, f, s)
    ux, uy = vec(f, s, 0, p[4], p[5])
    return dx, dy, sax, say, sbx, sby, ux, uy, -uy, ux


def h_row(p, f, s, jac, r):
    """Write the gradient of h = n.d into row r; returns h."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = line(p, f, s)
    pair_row(jac, r, nx, ny, -(ux * (dx + sax) + uy * (dy + say)), ux * sbx + uy * sby)
    return nx * dx + ny * dy


def t_row(p, f, s, jac, r):
    """Write the gradient of t = u.d into row r; returns t."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = line(p, f, s)
    pair_row(jac, r, ux, uy, ux * (dy + say) - uy * (dx + sax), sbx * uy - sby * ux)
    return ux * dx + uy * dy


def line_gammas(p, f, s):
    """(gamma of h, gamma of t)."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = line(p, f, s)
    ddx, ddy, qx, qy = pair_rates(f, s, sax, say, sbx, sby)
    w = f[s[0], 7]
    h = w * w * (nx * dx + ny * dy) + 2 * w * (ux * ddx + uy * ddy) - (nx * qx + ny * qy)
    t = w * w * (ux * dx + uy * dy) - 2 * w * (nx * ddx + ny * ddy) - (ux * qx + uy * qy)
    return h, t


def lock_row(jac, r):
    """The gradient of the relative angle phi_b - phi_a."""
    for k in range(6):
        jac[r, k] = 0.0
    jac[r, 2], jac[r, 5] = -1.0, 1.0


def wrap(a):
    return (a + pi) % (2 * pi) - pi


def rolling(p, c, f, s, jac, r):
    """The no-slip row of two circles (centres p[0:4], signed radii p[4:6]) with its gradient
    in row r; ``c`` its constant. Returns (row, d, S_a, S_b)."""
    dx, dy, sax, say, sbx, sby = pair(p, f, s)
    Ri, Rj = p[4], p[5]
    K = Ri + Rj
    L2 = dx * dx + dy * dy
    est = (Ri * f[s[0], 2] + Rj * f[s[1], 2] - c) / K
    KL = K / L2
    pair_row(jac, r, KL * dy, -KL * dx, Ri + KL * (dx * sax + dy * say), Rj - KL * (dx * sbx + dy * sby))
    return -K * wrap(atan2(dy, dx) - est), dx, dy, sax, say, sbx, sby


def rolling_gamma(p, f, s):
    dx, dy, sax, say, sbx, sby = pair(p, f, s)
    ddx, ddy, qx, qy = pair_rates(f, s, sax, say, sbx, sby)
    L2 = dx * dx + dy * dy
    theta_dot = (dx * ddy - dy * ddx) / L2
    g = (p[4] + p[5]) * ((dx * qy - dy * qx) / L2 - 2 * theta_dot * (dx * ddx + dy * ddy) / L2)
    return g, dx, dy, ddx, ddy, qx, qy


def linear_gamma(p, c, f, s, g):
    """A row linear in the coordinates: no velocity-squared terms."""
    g[0] = 0.0


# what the kernels call: compiled with them
PIECES = (vec, pair, pair_rates, pair_row, line, h_row, t_row, line_gammas, lock_row, wrap, rolling, rolling_gamma,
          linear_gamma)
