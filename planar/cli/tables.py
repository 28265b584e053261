"""The tables a run writes: one column per output, one row per sweep value, as CSV or JSON."""

import csv
import io
import json
import math
from pathlib import Path

import numpy as np

from planar.analysis import outputs
from planar.progress import Progress
from planar.results import Status


def table(res, units):
    """Columns of a sweep as [(name, unit, values (N,))]: inputs, status, every body's angle,
    rate and acceleration, every slider's or slot's travel and rates, every named point's
    position, velocity and acceleration."""
    model = res.model
    cols = []
    for k, (name, is_len) in enumerate(zip(model.input_names, model.input_lengths)):
        x = units.input_from_internal(np.asarray(res.inputs[:, k]), bool(is_len))
        cols.append((f"input:{name}", units.input_label(bool(is_len)), np.asarray(x, float)))
    cols.append(("status", "", np.array([Status(s).name for s in res.status])))
    moving = [p for p, (b, _) in model.points.items() if b != 0]
    columns = _name_by_name(model, ("angle", "omega", "alpha"), model.body_names[1:])
    columns += _name_by_name(model, ("travel", "travel_rate", "travel_accel"), model.coordinates)
    columns += _name_by_name(model, ("x", "y", "vx", "vy", "ax", "ay"), moving)
    for spec in columns:
        cols.append((spec, outputs.label(spec, units), outputs.output_values(res, spec, units)))
    return cols


def _name_by_name(model, kinds, names):
    """The outputs ``kinds`` the model has of each of ``names``, name by name (from one
    :func:`planar.analysis.outputs.specs`: a file may name thousands of points)."""
    have = set(outputs.specs(model, kinds, names))
    return [f"{k}:{n}" for n in names for k in kinds if f"{k}:{n}" in have]


def force_table(forces, units):
    """Columns of a sweep's kinetostatics: each driver's effort, each joint's reaction on its
    second body from its first (x, y, and the components it carries), the shaking force and
    moment (about the origin)."""
    model = forces.sweep.model
    F, M = units.label("force"), units.label("moment")
    cols = [(f"effort:{d}", F if ln else M, forces.driver_effort(d)) for d, ln in zip(model.input_names, model.input_lengths)]
    for j, comps in forces.reactions.items():
        cols += [(f"Fx:{j}", F, comps["force"][:, 0]), (f"Fy:{j}", F, comps["force"][:, 1])]
        cols += [(f"{c}:{j}", M if c == "moment" else F, v) for c, v in comps.items() if c != "force"]
    S = forces.shaking_force()
    return cols + [("shaking:Fx", F, S[:, 0]), ("shaking:Fy", F, S[:, 1]), ("shaking:moment", M, forces.shaking_moment())]


def _header(name, unit):
    return f"{name} [{unit}]" if unit else name


ROWS = 4096  # rows of a table formatted at once


def csv_chunks(cols):
    """The CSV text of ``cols`` in pieces: the header (quoted as the csv module quotes), then
    ROWS rows at a time, each value a column's number by ``repr`` (the shortest text that reads
    back to the same float) and an unsolved (non-finite) one empty. Yields (text, rows so far)."""
    head = io.StringIO()
    csv.writer(head).writerow([_header(n, u) for n, u, _ in cols])
    yield head.getvalue(), 0
    N = len(cols[0][2]) if cols else 0
    for lo in range(0, N, ROWS):
        cells = [_cells(np.asarray(v[lo : lo + ROWS])) for _, _, v in cols]
        yield "".join(",".join(row) + "\r\n" for row in zip(*cells)), min(N, lo + ROWS)


def _cells(v):
    """One column's values as text: numbers by repr, non-finite ones empty, text as it is."""
    if v.dtype.kind not in "fiub":
        return [str(x) for x in v.tolist()]
    a = v.astype(float)
    out = list(map(repr, a.tolist()))
    for i in np.flatnonzero(~np.isfinite(a)).tolist():
        out[i] = ""
    return out


def write_csv(cols, path):
    progress, N = Progress(f"writing {Path(path).name}: rows"), len(cols[0][2]) if cols else 0
    with open(path, "w", newline="", encoding="utf-8") as f:
        for text, done in csv_chunks(cols):
            f.write(text)
            if done:
                progress(done, N)


def write_json(cols, path, name):
    def clean(v):
        return v if isinstance(v, str) else (float(v) if math.isfinite(v) else None)

    data = {"mechanism": name, "units": {n: u for n, u, _ in cols if u},
            "columns": {n: [clean(x) for x in v] for n, _, v in cols}}
    Path(path).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
