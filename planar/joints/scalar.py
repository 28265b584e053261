"""Every joint type's rows as scalar code, one joint at one configuration: the kernels of the
compiled path (:mod:`planar.compiled`), which loops over configurations in machine code.

The numpy kernels of each class stay the reference (and the path used without numba); these
are the same rows written for one joint. Per joint type (:data:`KERNELS`), a kernel
``kernel(p, c, f, s, phi, jac)`` writes the residual rows ``phi`` (n_rows,) and the Jacobian
block ``jac`` (n_rows, 3 nb) in the class's slot order (x, y, phi per body), and its gamma
kernel ``gamma(p, c, f, s, g)`` the acceleration right-hand side:

- ``p`` the joint's parameters flattened in the order :data:`KERNELS` lists (each (a, b)
  parameter row-major, e.g. ``s`` as s_a.x, s_a.y, s_b.x, s_b.y);
- ``c`` its row constants (a driver's input value in c[0]);
- ``f`` (bodies, 8) the rows x, y, phi, cos phi, sin phi, xd, yd, phid of every body (the
  ground's first) and ``s`` the joint's body ids, slot by slot.

Plain Python without numba (so the tests compare them with the numpy kernels anywhere); with
numba each is compiled where the compiled path calls it.

>>> import numpy as np
>>> f = np.zeros((2, 8)); f[:, 3] = 1.0; f[1, 0] = 2.0  # body 1 2 to the right, both unrotated
>>> phi, jac = np.zeros(2), np.zeros((2, 9))
>>> revolute(np.array([1.0, 0.0, -1.0, 0.0]), np.zeros(2), f, np.array([0, 1]), phi, jac)
>>> phi.tolist()  # pin at a's (1, 0) and b's (-1, 0): they meet
[0.0, 0.0]
"""

from math import atan2, pi

from planar.joints.driver import AngleDriver, CoordinateDriver, TravelDriver
from planar.joints.gear import CarrierGear, Gear, RollingContact
from planar.joints.prismatic import Prismatic, Slot
from planar.joints.rack import RackPinion
from planar.joints.revolute import Revolute

try:  # compiled inline into the jitted callers; plain functions without numba
    import numba

    _jitable = numba.njit(inline="always", cache=True, error_model="numpy")
except ImportError:  # pragma: no cover - numba is optional
    def _jitable(fn):
        return fn


@_jitable
def _vec(f, s, k, x, y):
    """World vector A_k (x, y) of a body-fixed vector on slot k."""
    return f[s[k], 3] * x - f[s[k], 4] * y, f[s[k], 4] * x + f[s[k], 3] * y


@_jitable
def _pair(p, f, s):
    """d = P_b - P_a of the body points p[0:2] (slot 0) and p[2:4] (slot 1), and S_a, S_b."""
    sax, say = _vec(f, s, 0, p[0], p[1])
    sbx, sby = _vec(f, s, 1, p[2], p[3])
    return f[s[1], 0] + sbx - f[s[0], 0] - sax, f[s[1], 1] + sby - f[s[0], 1] - say, sax, say, sbx, sby


@_jitable
def _pair_rates(f, s, sax, say, sbx, sby):
    """d_dot and the qdd-free part of d_ddot of d = P_b - P_a."""
    wa, wb = f[s[0], 7], f[s[1], 7]
    ddx = f[s[1], 5] - sby * wb - f[s[0], 5] + say * wa
    ddy = f[s[1], 6] + sbx * wb - f[s[0], 6] - sax * wa
    return ddx, ddy, sax * wa * wa - sbx * wb * wb, say * wa * wa - sby * wb * wb


@_jitable
def _pair_row(jac, r, gx, gy, g_pa, g_pb):
    jac[r, 0], jac[r, 1], jac[r, 2] = -gx, -gy, g_pa
    jac[r, 3], jac[r, 4], jac[r, 5] = gx, gy, g_pb


@_jitable
def _line(p, f, s):
    """(d, S_a, S_b, u, n) of a point (slot 1) against the line of slot 0 (p: s (4), u (2))."""
    dx, dy, sax, say, sbx, sby = _pair(p, f, s)
    ux, uy = _vec(f, s, 0, p[4], p[5])
    return dx, dy, sax, say, sbx, sby, ux, uy, -uy, ux


@_jitable
def _h_row(p, f, s, jac, r):
    """Write the gradient of h = n.d into row r; returns h."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = _line(p, f, s)
    _pair_row(jac, r, nx, ny, -(ux * (dx + sax) + uy * (dy + say)), ux * sbx + uy * sby)
    return nx * dx + ny * dy


@_jitable
def _t_row(p, f, s, jac, r):
    """Write the gradient of t = u.d into row r; returns t."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = _line(p, f, s)
    _pair_row(jac, r, ux, uy, ux * (dy + say) - uy * (dx + sax), sbx * uy - sby * ux)
    return ux * dx + uy * dy


@_jitable
def _line_gammas(p, f, s):
    """(gamma of h, gamma of t)."""
    dx, dy, sax, say, sbx, sby, ux, uy, nx, ny = _line(p, f, s)
    ddx, ddy, qx, qy = _pair_rates(f, s, sax, say, sbx, sby)
    w = f[s[0], 7]
    h = w * w * (nx * dx + ny * dy) + 2 * w * (ux * ddx + uy * ddy) - (nx * qx + ny * qy)
    t = w * w * (ux * dx + uy * dy) - 2 * w * (nx * ddx + ny * ddy) - (ux * qx + uy * qy)
    return h, t


@_jitable
def _lock_row(jac, r):
    """The gradient of the relative angle phi_b - phi_a."""
    for k in range(6):
        jac[r, k] = 0.0
    jac[r, 2], jac[r, 5] = -1.0, 1.0


@_jitable
def _wrap(a):
    return (a + pi) % (2 * pi) - pi


@_jitable
def _rolling(p, c, f, s, jac, r):
    """The no-slip row of two circles (centres p[0:4], signed radii p[4:6]) with its gradient
    in row r; ``c`` its constant. Returns (row, d, S_a, S_b)."""
    dx, dy, sax, say, sbx, sby = _pair(p, f, s)
    Ri, Rj = p[4], p[5]
    K = Ri + Rj
    L2 = dx * dx + dy * dy
    est = (Ri * f[s[0], 2] + Rj * f[s[1], 2] - c) / K
    KL = K / L2
    _pair_row(jac, r, KL * dy, -KL * dx, Ri + KL * (dx * sax + dy * say), Rj - KL * (dx * sbx + dy * sby))
    return -K * _wrap(atan2(dy, dx) - est), dx, dy, sax, say, sbx, sby


@_jitable
def _rolling_gamma(p, f, s):
    dx, dy, sax, say, sbx, sby = _pair(p, f, s)
    ddx, ddy, qx, qy = _pair_rates(f, s, sax, say, sbx, sby)
    L2 = dx * dx + dy * dy
    theta_dot = (dx * ddy - dy * ddx) / L2
    g = (p[4] + p[5]) * ((dx * qy - dy * qx) / L2 - 2 * theta_dot * (dx * ddx + dy * ddy) / L2)
    return g, dx, dy, ddx, ddy, qx, qy


# ---- the kernels, one pair per joint type -------------------------------------------------


@_jitable
def revolute(p, c, f, s, phi, jac):
    dx, dy, sax, say, sbx, sby = _pair(p, f, s)
    phi[0], phi[1] = dx - c[0], dy - c[1]
    jac[0, 0], jac[0, 1], jac[0, 2], jac[0, 3], jac[0, 4], jac[0, 5] = -1.0, 0.0, say, 1.0, 0.0, -sby
    jac[1, 0], jac[1, 1], jac[1, 2], jac[1, 3], jac[1, 4], jac[1, 5] = 0.0, -1.0, -sax, 0.0, 1.0, sbx


@_jitable
def revolute_gamma(p, c, f, s, g):
    sax, say = _vec(f, s, 0, p[0], p[1])
    sbx, sby = _vec(f, s, 1, p[2], p[3])
    wa2, wb2 = f[s[0], 7] * f[s[0], 7], f[s[1], 7] * f[s[1], 7]
    g[0], g[1] = sbx * wb2 - sax * wa2, sby * wb2 - say * wa2


@_jitable
def slot(p, c, f, s, phi, jac):
    phi[0] = _h_row(p, f, s, jac, 0) - c[0]  # the normal distance n.d


@_jitable
def travel_driver(p, c, f, s, phi, jac):
    phi[0] = _t_row(p, f, s, jac, 0) - c[0]  # the travel u.d


@_jitable
def slot_gamma(p, c, f, s, g):
    g[0] = _line_gammas(p, f, s)[0]


@_jitable
def travel_driver_gamma(p, c, f, s, g):
    g[0] = _line_gammas(p, f, s)[1]


@_jitable
def prismatic(p, c, f, s, phi, jac):
    slot(p, c, f, s, phi, jac)  # and the relative angle locked
    _lock_row(jac, 1)
    phi[1] = f[s[1], 2] - f[s[0], 2] - c[1]


@_jitable
def prismatic_gamma(p, c, f, s, g):
    g[0], g[1] = _line_gammas(p, f, s)[0], 0.0


@_jitable
def carrier_gear(p, c, f, s, phi, jac):
    Ri, Rj = p[0], p[1]
    phi[0] = Ri * (f[s[0], 2] - f[s[2], 2]) + Rj * (f[s[1], 2] - f[s[2], 2]) - c[0]
    for k in range(9):
        jac[0, k] = 0.0
    jac[0, 2], jac[0, 5], jac[0, 8] = Ri, Rj, -(Ri + Rj)


@_jitable
def linear_gamma(p, c, f, s, g):
    """A row linear in the coordinates: no velocity-squared terms."""
    g[0] = 0.0


@_jitable
def gear(p, c, f, s, phi, jac):
    phi[0] = _rolling(p, c[0], f, s, jac, 0)[0]


@_jitable
def gear_gamma(p, c, f, s, g):
    g[0] = _rolling_gamma(p, f, s)[0]


@_jitable
def rolling_contact(p, c, f, s, phi, jac):
    row, dx, dy, sax, say, sbx, sby = _rolling(p, c[1], f, s, jac, 1)
    D = abs(p[4] + p[5])
    phi[0], phi[1] = (dx * dx + dy * dy - D * D) / (2 * D) - c[0], row
    _pair_row(jac, 0, dx / D, dy / D, (dx * say - dy * sax) / D, (sbx * dy - sby * dx) / D)


@_jitable
def rolling_contact_gamma(p, c, f, s, g):
    roll, dx, dy, ddx, ddy, qx, qy = _rolling_gamma(p, f, s)
    g[0] = -(ddx * ddx + ddy * ddy + dx * qx + dy * qy) / abs(p[4] + p[5])
    g[1] = roll


@_jitable
def rack_pinion(p, c, f, s, phi, jac):
    sR = p[6]
    phi[0] = _h_row(p, f, s, jac, 0) - c[0]
    phi[1] = _t_row(p, f, s, jac, 1) + sR * (f[s[1], 2] - f[s[0], 2]) - c[1]
    jac[1, 2] -= sR
    jac[1, 5] += sR


@_jitable
def rack_pinion_gamma(p, c, f, s, g):
    g[0], g[1] = _line_gammas(p, f, s)


@_jitable
def angle_driver(p, c, f, s, phi, jac):
    _lock_row(jac, 0)
    phi[0] = f[s[1], 2] - f[s[0], 2] - c[0]


@_jitable
def coordinate_driver(p, c, f, s, phi, jac):
    sx, sy = _vec(f, s, 0, p[0], p[1])
    phi[0] = (f[s[0], 0] + sx) * p[2] + (f[s[0], 1] + sy) * p[3] - c[0]
    jac[0, 0], jac[0, 1], jac[0, 2] = p[2], p[3], sx * p[3] - sy * p[2]


@_jitable
def coordinate_driver_gamma(p, c, f, s, g):
    sx, sy = _vec(f, s, 0, p[0], p[1])
    g[0] = (sx * p[2] + sy * p[3]) * f[s[0], 7] * f[s[0], 7]


# joint type -> (the parameters it reads, in the order they are flattened into p; its kernel;
# its gamma kernel), by name: the generated code of planar.compiled imports them
KERNELS = {
    Revolute: (("s",), "revolute", "revolute_gamma"),
    Prismatic: (("s", "u"), "prismatic", "prismatic_gamma"),
    Slot: (("s", "u"), "slot", "slot_gamma"),
    CarrierGear: (("R",), "carrier_gear", "linear_gamma"),
    Gear: (("s", "R"), "gear", "gear_gamma"),
    RollingContact: (("s", "R"), "rolling_contact", "rolling_contact_gamma"),
    RackPinion: (("s", "u", "sR"), "rack_pinion", "rack_pinion_gamma"),
    AngleDriver: ((), "angle_driver", "linear_gamma"),
    TravelDriver: (("s", "u"), "travel_driver", "travel_driver_gamma"),
    CoordinateDriver: (("s", "e"), "coordinate_driver", "coordinate_driver_gamma"),
}
