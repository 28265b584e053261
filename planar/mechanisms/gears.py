"""Rolling contact: rack and pinion, a wheel rolling on a line or inside a circle, gear trains.

Each contact is one rolling joint of the core (pitch circles, no slip); the gears mesh as
sketched. A planetary set with several planets has redundant mesh rows: the model reports them
(``model.redundant_joints``) and checks them after every solve.

>>> import numpy as np
>>> from planar.mechanisms import planetary_gear_train
>>> m = planetary_gear_train(planets=3)
>>> m.compile().redundant_joints
('planet2_ring', 'planet3_ring')
>>> res = m.sweep([0.0, 1.0])
>>> res.omega("carrier").round(12).tolist()   # Rs / (Rs + Rring) of the sun's rate
[0.333333333333, 0.333333333333]
"""

from collections.abc import Sequence

import numpy as np

from planar.errors import ModelError
from planar.mechanisms import checks
from planar.mechanisms.sketch import polar
from planar.model import Mechanism


def rack_and_pinion(radius: float = 1.0, *, rack_angle: float = 0.0, driver: str = "pinion", start: float = 0.0,
                    name: str = "rack_and_pinion") -> Mechanism:
    """A pinion turning about the origin drives a rack sliding on the ground.

    The rack's pitch line runs along ``rack_angle`` at ``radius`` to the right of the pinion
    centre (below it for rack_angle 0); the rack's travel is R (th - th0) along the line.

    Parameters
    ----------
    radius : float
        Pitch radius R of the pinion.
    rack_angle : float
        Direction of the rack's travel (radians).
    driver : {"pinion", "rack"}
        The input: the pinion's absolute angle, or the rack's travel (joint ``slide``).
    start : float
        Input value of the sketch; the other member sits at 0 there.

    The rack's guide and the mesh both hold the pitch line at R from the pinion's centre: one
    redundant row, which the model reports (``redundant_joints``) and checks after every solve.

    Returns
    -------
    planar.Mechanism
        Bodies ``pinion`` and ``rack``; points ``O2`` (the pinion's pivot), ``P`` (the rack's
        point at the pitch point of the sketch), ``slide`` (the rack's prismatic joint) and
        ``mesh`` (the rolling joint, at the pinion centre).

    Examples
    --------
    >>> res = rack_and_pinion(2.0).sweep([0.0, 0.5])
    >>> res.coordinate("slide").tolist()
    [0.0, 1.0]
    """
    (R,) = checks.lengths(radius=radius)
    th = checks.number(rack_angle, "rack_angle")
    checks.choice(driver, ("pinion", "rack"), "driver")
    start = checks.number(start, "start")
    u = polar((0, 0), 1.0, th)
    O2 = np.zeros(2)
    foot = polar(O2, R, th - np.pi / 2)
    travel = start if driver == "rack" else 0.0
    P = foot + travel * u

    m = Mechanism(name)
    m.add_body("pinion", angle=start if driver == "pinion" else 0.0)
    m.add_body("rack", angle=th)
    m.add_revolute("O2", m.ground, "pinion", at=O2)
    m.add_prismatic("slide", m.ground, "rack", at=P, direction=u, origin=foot)
    m.add_point("P", "rack", at=P)
    m.add_rack_pinion("mesh", "pinion", "rack", R, centre=O2, through=P, direction=u, side="left")
    if driver == "pinion":
        m.drive(body="pinion")
    else:
        m.drive("slide")
    return m


def rolling_wheel(radius: float = 1.0, *, track_radius: float | None = None, driver: str = "wheel",
                  start: float = 0.0, name: str = "rolling_wheel") -> Mechanism:
    """A wheel rolling without slip on the ground line y = 0 (above it) or, with
    ``track_radius``, inside a fixed circle of that radius centred at the origin.

    At wheel angle 0 the wheel touches the track at its lowest point: on the line at the
    origin, inside the circle at (0, -track_radius). Rim point ``P`` touches the track there,
    so it traces a cycloid (on the line) or a hypocycloid (inside the circle).

    Parameters
    ----------
    radius : float
        The wheel's radius r.
    track_radius : float, optional
        Radius of the circle the wheel rolls inside (larger than ``radius``); None: a line.
    driver : {"wheel", "centre"}
        The input: the wheel's absolute angle, or the x coordinate of its centre.
    start : float
        Input value of the sketch (the wheel is placed as rolled from angle 0).

    Returns
    -------
    planar.Mechanism
        Body ``wheel``; points ``centre``, ``P`` and ``roll`` (the rolling joint, at the centre).

    Examples
    --------
    >>> import numpy as np
    >>> res = rolling_wheel(1.0).sweep([0.0, -np.pi])
    >>> res.position("centre").round(12).tolist()
    [[0.0, 1.0], [3.14159265359, 1.0]]
    """
    (r,) = checks.lengths(radius=radius)
    checks.choice(driver, ("wheel", "centre"), "driver")
    start = checks.number(start, "start")
    if track_radius is not None:
        (Rt,) = checks.lengths(track_radius=track_radius)
        if Rt <= r:
            raise ModelError(f"track_radius {Rt:.12g} must exceed the wheel's radius {r:.12g} for the wheel "
                             f"to roll inside it")
    # wheel angle phi of the sketch (rolled from angle 0), and where its centre is then
    if track_radius is None:
        phi = start if driver == "wheel" else -start / r
        centre = np.array([-r * phi, r])
    else:
        if driver == "centre":
            raise ModelError("rolling_wheel inside a circle is driven by the wheel's angle: use driver='wheel'")
        phi = start
        # rolling inside: (Rt - r) dpsi = -r dphi, the centre at psi = -pi/2 when phi = 0
        centre = polar((0, 0), Rt - r, -np.pi / 2 - r * phi / (Rt - r))

    m = Mechanism(name)
    m.add_body("wheel", angle=phi)
    m.add_point("centre", "wheel", at=centre)
    m.add_point("P", "wheel", at=polar(centre, r, phi - np.pi / 2))
    if track_radius is None:
        m.add_rolling("roll", "wheel", m.ground, r, centre=centre, through=(0, 0), direction=(1, 0), side="left")
    else:
        m.add_gear("roll", m.ground, "wheel", Rt, r, internal=True, centre_a=(0, 0), centre_b=centre,
                   hold_distance=True)
    if driver == "wheel":
        m.drive(body="wheel")
    else:
        m.drive(point="centre", axis="x")
    return m


def gear_train(radii: Sequence[float] = (1.0, 2.0, 1.5), *, start: float = 0.0,
               name: str = "gear_train") -> Mechanism:
    """A simple train of external gears on fixed axes along the x axis, driven by the first.

    Gear k (2 to 256 of them) has pitch radius ``radii[k-1]``; its centre ``Ok`` lies where it
    meshes with the gear before it; gear k turns at (-1)^(k-1) R1 / Rk times gear 1's rate.

    Returns
    -------
    planar.Mechanism
        Bodies ``gear1`` ... ``gearN``; revolutes ``O1`` ... ``ON``; meshes ``mesh12``,
        ``mesh23``, ... (at the centre of the second gear of each pair).

    Examples
    --------
    >>> res = gear_train((1.0, 2.0, 0.5)).sweep([0.0, 1.0])
    >>> res.omega("gear3").tolist()
    [2.0, 2.0]
    """
    R = checks.length_list(radii, "radii", at_least=2)
    start = checks.number(start, "start")
    x = np.concatenate(([0.0], np.cumsum(np.add(R[:-1], R[1:]))))

    m = Mechanism(name)
    for k, xk in enumerate(x, 1):
        m.add_body(f"gear{k}", angle=start if k == 1 else 0.0)
        m.add_revolute(f"O{k}", m.ground, f"gear{k}", at=(xk, 0.0))
    for k in range(1, len(R)):
        m.add_gear(f"mesh{k}{k + 1}", f"gear{k}", f"gear{k + 1}", R[k - 1], R[k], carrier=m.ground)
    m.drive(body="gear1")
    return m


MEMBERS = ("sun", "carrier", "ring")


MAX_PLANETS = 128  # (a set of 10**40 planets was built planet by planet, for ever)


def planetary_gear_train(sun: float = 1.0, planet: float = 0.5, *, planets: int = 3, fixed: str = "ring",
                         driver: str = "sun", start: float = 0.0,
                         name: str = "planetary_gear_train") -> Mechanism:
    """A planetary (epicyclic) set: sun, ``planets`` equal planets on a carrier, and a ring.

    The sun (radius Rs), the carrier and the ring (radius Rs + 2 Rp) turn about the origin;
    the member named by ``fixed`` is the ground. Planet k turns on the carrier at distance
    Rs + Rp, at angle 2 pi (k - 1) / planets in the sketch. Every planet meshes with the sun
    and the ring, so two or more planets make redundant mesh rows (Willis:
    (w_sun - w_c) Rs = -(w_ring - w_c) (Rs + 2 Rp)).

    Parameters
    ----------
    sun, planet : float
        Pitch radii Rs and Rp.
    planets : int
        Number of planets (1 to MAX_PLANETS, 128).
    fixed : {"ring", "carrier", "sun"}
        The member held to the ground (it is not a body then).
    driver : {"sun", "carrier", "ring"}
        The input member (its absolute angle); not the fixed one.
    start : float
        The input's angle in the sketch.

    Returns
    -------
    planar.Mechanism
        Bodies: the two members not fixed, and ``planet1`` ... ``planetN``; revolutes ``Os``,
        ``Oc``, ``Or`` (of the moving members) and ``P1`` ... ``PN`` (planet pins); meshes
        ``sun_planetK`` and ``planetK_ring``.

    Examples
    --------
    >>> res = planetary_gear_train(fixed="carrier").sweep([0.0, 1.0])
    >>> res.omega("ring").round(12).tolist()
    [-0.5, -0.5]
    """
    Rs, Rp = checks.lengths(sun=sun, planet=planet)
    if not isinstance(planets, (int, np.integer)) or not 1 <= planets <= MAX_PLANETS:
        raise ModelError(f"planets must be a whole number from 1 to {MAX_PLANETS}, got {planets!r}")
    checks.choice(fixed, MEMBERS, "fixed")
    checks.choice(driver, MEMBERS, "driver")
    if driver == fixed:
        raise ModelError(f"the driver {driver!r} is the fixed member: drive one of "
                         f"{[b for b in MEMBERS if b != fixed]}")
    start = checks.number(start, "start")

    m = Mechanism(name)
    body = {b: (m.ground if b == fixed else b) for b in MEMBERS}
    for b in MEMBERS:
        if b != fixed:
            m.add_body(b, angle=start if b == driver else 0.0)
            m.add_revolute(f"O{b[0]}", m.ground, b, at=(0.0, 0.0))
    for k in range(1, planets + 1):
        centre = polar((0, 0), Rs + Rp, 2 * np.pi * (k - 1) / planets)
        m.add_body(f"planet{k}")
        m.add_revolute(f"P{k}", body["carrier"], f"planet{k}", at=centre)
        m.add_gear(f"sun_planet{k}", body["sun"], f"planet{k}", Rs, Rp, carrier=body["carrier"],
                   centre_a=(0.0, 0.0))
        m.add_gear(f"planet{k}_ring", f"planet{k}", body["ring"], Rp, Rs + 2 * Rp, internal=True,
                   carrier=body["carrier"], centre_b=(0.0, 0.0))
    m.drive(body=driver)
    return m
