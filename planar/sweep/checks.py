"""What a sweep asks of the model before it starts: the coordinates its outputs depend on, and a
sketch off singular positions."""

import numpy as np

from planar.errors import AssemblyError, InputError
from planar.events import SINGULAR


def output_columns(model, outputs):
    """Coordinates the named bodies, points, joints or inputs depend on."""
    if outputs is None:
        return None
    given = outputs
    try:
        outputs = [outputs] if isinstance(outputs, str) else list(outputs)
    except TypeError:
        outputs = [None]
    if not all(isinstance(x, str) for x in outputs):
        raise InputError(f"outputs must be a name or a list of names of bodies, points or joints, got {given!r}")
    cols = set()
    for name in outputs:
        bodies = []
        if name in model.body_names:
            bodies = [model.body_id(name)]
        elif name in model.points:
            bodies = [model.points[name][0]]
        elif name in model.coordinates or name in model.input_names:
            j = next((d for d in model.drivers if d.name == name), None) or model.joint(name)
            bodies = [model.body_id(b) for b in j.bodies]
        else:
            raise InputError(f"unknown output {name!r}: name bodies {list(model.body_names[1:])}, points or "
                             f"joints {sorted(model.points)}")
        for b in bodies:
            if b > 0:
                cols.update(range(3 * b - 3, 3 * b))
    # outputs fixed to the ground depend on no coordinate: the whole model is solved (the
    # statuses still say whether each value assembles)
    return sorted(cols) or None


def check_sketch(model, p):
    """A sketch drawn on a singular position leaves the branch to follow undefined (a
    parallelogram drawn flat moves on as a parallelogram or as an antiparallelogram): refused,
    naming the bodies whose loop is singular there."""
    with np.errstate(all="ignore"):
        dets = p.factor(p.evaluate(model.q0[None], model.u0[None])[2]).dets[0]
    bad = np.flatnonzero(~(np.abs(dets) >= SINGULAR))
    if bad.size:
        blk = p.blocks[int(bad[0])]
        bodies = sorted({model.body_names[int(c) // 3 + 1] for c in blk.cols}, key=model.body_names.index)
        raise AssemblyError(
            f"the sketch of {model.name!r} sits on a singular position (bodies {', '.join(bodies)}: normalised det "
            f"{abs(dets[bad[0]]):.1e}), where more than one branch passes and none is the one drawn; sketch it "
            f"off the singular position (for a catalogue mechanism, another start value) and sweep through it: "
            f"the sweep locates the singular position and follows the smooth branch (or branch='other')")
