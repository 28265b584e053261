"""The app's motion data: a mechanism's whole circuit solved once (:meth:`planar.Model.circuit`)
and laid out as world points per pose, so that the page animates, scrubs and plots from stored
arrays without solving again; a single value is solved on its own (:func:`pose_lines`).

>>> from planar.mechanisms import four_bar
>>> from planar.units import Units
>>> c = solve(four_bar(4, 3, 3, 3).compile(), Units("cm"), rate=1.0, samples=73)   # a triple rocker
>>> c.X.shape[0], [line.split(":")[0] for line in c.event_lines()]
(73, ['limit position at crank = 117.2796 deg', 'limit position at crank = -117.2796 deg'])
"""

from dataclasses import dataclass

import numpy as np

from planar.analysis import instant_centres
from planar.analysis.outputs import OUTPUTS, names_of, output_values
from planar.draw.pose import arrow_scale, path_points
from planar.draw.scene import Scene, joint_params, local, world
from planar.draw.style import FILLS
from planar.results import Status

WHEEL_SIDES = 32  # polygon sides of a gear's pitch circle


@dataclass
class Circuit:
    """A solved circuit laid out for drawing. ``X``, ``Y`` (N, P): the world coordinates of P
    drawing points at each of the N poses; the index lists say which points make each body's
    outline (``bodies``, with ``colours``), gear circle (``wheels``), guide line (``guides``),
    pin (``pins``; ``grounds`` the pivots on the ground), slider block (``blocks``), named
    point (``points``, ``labels``) and arrow (``arrows``: point, velocity tip, acceleration
    tip), ``centres`` the instant centres (label, point). ``x`` is the input in the page's units and ``time`` the time since the first pose
    at the input's rate; ``paths`` the traced points' paths."""

    res: object
    units: object
    rate: float
    x: np.ndarray
    time: np.ndarray
    X: np.ndarray
    Y: np.ndarray
    bodies: list
    colours: list
    wheels: list
    guides: list
    pins: list
    grounds: list
    blocks: list
    points: list
    labels: list
    arrows: list
    centres: list
    paths: dict
    scales: tuple
    _forces: object = None

    @property
    def model(self):
        return self.res.model

    def series(self, spec):
        """(N,) values of output ``spec`` (see :func:`outputs`) in the page's units."""
        kind, _, name = spec.partition(":")
        if kind in FORCES:
            if self._forces is None:  # one linear solve per pose: only when a force is asked for
                self._forces = self.res.forces()
            f = self._forces
            return f.driver_effort(name) if kind == "effort" else np.hypot(*f.reaction(name).T)
        return output_values(self.res, spec, self.units)

    def input_label(self):
        m = self.model
        unit = self.units.input_label(bool(m.input_lengths[0]))
        return f"{m.input_names[0]}" + (f" [{unit}]" if unit else "")

    def event_lines(self):
        """One line per limit position, bifurcation or singular position met on the circuit."""
        m, out = self.model, []
        name, unit = m.input_names[0], self.units.input_label(bool(m.input_lengths[0]))
        for e in self.res.events:
            u = float(self.units.input_from_internal(float(np.ravel(e.input)[0]), bool(m.input_lengths[0])))
            what = e.note or {"limit": "the input turns back here, the circuit goes on in the other assembly mode",
                              "bifurcation": "branches cross: the circuit keeps to the smooth branch"}.get(e.kind, "")
            out.append(f"{e.kind.replace('_', '-')} position at {name} = {u:.4f} {unit}" + (f": {what}" if what else ""))
        return out

    def event_marks(self):
        """(kind, pose index, input in page units, world positions of the traced points) of
        each event with a pose."""
        out = []
        m = self.model
        for e in self.res.events:
            if e.q is None or not np.all(np.isfinite(e.q)):
                continue
            u = float(self.units.input_from_internal(float(np.ravel(e.input)[0]), bool(m.input_lengths[0])))
            pts = [world(np.asarray(e.q), *m.points[n]) for n in self.paths]
            out.append((e.kind, min(int(e.index), len(self.x) - 1), u, pts))
        return out


# forces the page plots when the mechanism carries masses, gravity or loads (planar.kinetostatics)
FORCES = {"effort": "driving effort", "reaction": "reaction force"}


def _loaded(model):
    return bool(np.any(model.mass > 0) or np.any(model.gravity != 0) or model.loads)


def outputs(model):
    """Output specs the page offers, "kind:name" (:data:`planar.analysis.outputs.OUTPUTS`): each body's
    angle, rate and acceleration, each slider's travel and rates, each moving point's x, y and
    speed; with masses, gravity or loads, each driver's effort and each joint's reaction (its
    size)."""
    specs = [f"{k}:{b}" for b in model.body_names[1:] for k in ("angle", "omega", "alpha")]
    specs += [f"{k}:{j}" for j in names_of(model, "length coordinate")
              for k in ("travel", "travel_rate", "travel_accel")]
    specs += [f"{k}:{p}" for p, (b, _) in model.points.items() if b != 0 for k in ("x", "y", "speed", "accel")]
    if _loaded(model):
        specs += [f"effort:{d}" for d in model.input_names] + [f"reaction:{j.name}" for j in model.joints]
    return specs


def output_label(spec, units, model=None):
    """The axis label of output ``spec``, with its unit (``model`` names a driver's kind)."""
    kind, _, name = spec.partition(":")
    if kind in FORCES:
        moment = kind == "effort" and model is not None and not model.input_lengths[model.input_names.index(name)]
        return f"{FORCES[kind]} of {name} [{units.label('moment' if moment else 'force')}]"
    title, unit_kind = OUTPUTS[kind].title, OUTPUTS[kind].unit
    unit = units.label(unit_kind)
    return f"{title} of {name}" + (f" [{unit}]" if unit else "")


def solve(model, units, rate=1.0, samples=721):
    """The circuit of a one-input ``model`` (``samples`` poses; the input at ``rate`` in the
    page's rate unit) laid out for drawing: a :class:`Circuit`."""
    is_len = bool(model.input_lengths[0])
    w = float(units.input_to_internal(rate, is_len, 1))
    res = model.circuit(samples, velocity=w)
    x = np.asarray(units.input_from_internal(res.inputs[:, 0], is_len), float)
    time = np.r_[0.0, np.cumsum(np.abs(np.diff(res.inputs[:, 0])))] / abs(w)
    scene = Scene(res, labels=False)
    Q = np.asarray(res.q)
    cols = []  # (N, 2) world positions, one per drawing point

    def add(p):
        cols.append(p)
        return len(cols) - 1

    def fixed(b, s):
        return add(world(Q, b, np.asarray(s, float)))

    params = joint_params(model)
    bodies, colours = [], []
    for b in range(1, len(model.body_names)):
        outline = scene.body_outline(model.q0, b)
        if len(outline) >= 2:
            bodies.append([fixed(b, s) for s in local(model.q0, b, outline)])
            colours.append(FILLS[(b - 1) % len(FILLS)])
    wheels, guides, pins, grounds, blocks = [], [], [], [], []
    for j in model.joints:
        P = params[j.name]
        pin, block = j.pin_point(scene, P), j.block_point(scene, P)
        if pin is not None:
            (grounds if 0 in scene.ids(j) else pins).append(fixed(*pin))
        for k, (b, s) in enumerate(j.wheel_centres(scene, P)):
            t = np.linspace(0, 2 * np.pi, WHEEL_SIDES + 1)
            r = abs(float(np.ravel(P["R"])[k]))
            wheels.append([fixed(b, s)] + [fixed(b, s + r * np.array([np.cos(a), np.sin(a)])) for a in t])
        line = j.guide_line(scene, P)
        if line is not None:
            a = line[0]
            guides.append([fixed(a, e) for e in scene.line_ends(j.name)])
        if block is not None:
            blocks.append(fixed(*block))
    joint_names = {j.name for j in model.joints}
    labels = [n for n in model.points if n not in joint_names or model.joint(n).labelled]
    points = [fixed(*model.points[n]) for n in labels]
    traced = path_points(res, None)
    moving = [n for n, (b, _) in model.points.items() if b != 0]
    V = np.stack([res.velocity(n) for n in moving], 1) if moving else np.zeros((len(res), 0, 2))
    A = np.stack([res.acceleration(n) for n in moving], 1) if moving else np.zeros((len(res), 0, 2))
    sv, sa = arrow_scale(V, scene.L), arrow_scale(A, scene.L)
    arrows = []
    for k, n in enumerate(moving):
        p = res.position(n)
        arrows.append((n, add(p), add(p + sv * V[:, k]), add(p + sa * A[:, k])))
    # instant centres, numbered as the textbooks number bodies (the ground is 1)
    ids = {b: str(k + 1) for k, b in enumerate(model.body_names)}
    sep = "," if len(model.body_names) > 9 else ""
    centres = [(f"I{ids[a]}{sep}{ids[b]}", add(np.where(np.isfinite(P), P, np.nan)))
               for (a, b), P in instant_centres(res).items()]
    XY = np.stack(cols, 1) if cols else np.zeros((len(res), 0, 2))
    return Circuit(res, units, rate, x, time, XY[..., 0], XY[..., 1], bodies, colours, wheels, guides, pins,
                   grounds, blocks, points, labels, arrows, centres, {n: res.position(n) for n in traced}, (sv, sa))


def pose_lines(model, units, value, rate=1.0):
    """The pose at input ``value`` (page units), solved on its own by :meth:`planar.Model.sweep`
    from the sketch along its branch: one line per body, slider and moving point.

    >>> from planar.mechanisms import four_bar
    >>> from planar.units import Units
    >>> print("\\n".join(pose_lines(four_bar(4, 2, 3, 4, start=1.0).compile(), Units("cm"), 60.0, 10.0)[:3]))
    crank = 60 deg: SOLVED
    crank: angle 60 deg, rate 10 rad/s, acceleration 0 rad/s^2
    coupler: angle 46.0802514 deg, rate -5.43745617 rad/s, acceleration 73.5391912 rad/s^2
    """
    is_len = bool(model.input_lengths[0])
    u = float(units.input_to_internal(value, is_len))
    res = model.sweep([u], velocity=float(units.input_to_internal(rate, is_len, 1)))
    name, unit = model.input_names[0], units.input_label(is_len)
    lines = [f"{name} = {value:.9g} {unit}: {Status(res.status[0]).name}"]
    g = lambda v: f"{float(v[0]):.9g}"  # noqa: E731
    for b in model.body_names[1:]:
        lines.append(f"{b}: angle {g(output_values(res, 'angle:' + b, units))} {units.angle}, "
                     f"rate {g(output_values(res, 'omega:' + b, units))} {units.rate}, "
                     f"acceleration {g(output_values(res, 'alpha:' + b, units))} {units.acceleration}")
    for j in names_of(model, "length coordinate"):
        lines.append(f"{j}: travel {g(res.coordinate(j))}, rate {g(res.coordinate(j, 1))}, "
                     f"acceleration {g(res.coordinate(j, 2))} ({units.label('length') or 'length'} and /s)")
    for p, (b, _) in model.points.items():
        if b != 0:
            (x, y), (vx, vy) = res.position(p)[0], res.velocity(p)[0]
            lines.append(f"{p}: at ({x:.9g}, {y:.9g}), velocity ({vx:.9g}, {vy:.9g}) {units.label('speed')}")
    return lines


def csv_text(res, units):
    """The sweep as the CSV table ``planar run`` writes (one row per pose)."""
    from planar.cli.tables import csv_chunks, table

    return "".join(text for text, _ in csv_chunks(table(res, units)))
