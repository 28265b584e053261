"""Topology recognition: which textbook mechanism a model's graph of bodies and joints is.

>>> from planar.mechanisms import four_bar, slider_crank
>>> four_bar_links(four_bar(4, 2, 3, 4).compile())
((4.0, 2.0, 3.0, 4.0), 'crank')
>>> four_bar_links(slider_crank().compile()) is None
True
"""

import numpy as np

from planar.errors import InputError


def four_bar_links(model):
    """(ground, crank, coupler, rocker) lengths and the input link ("crank", "coupler",
    "rocker" or None) when the model is one loop of four revolutes, read from its sketch; else
    None. The crank is the driven link next to the ground (either, when the coupler is driven)."""
    from planar.model import Model

    if not isinstance(model, Model):
        raise InputError(f"four_bar_links needs a Model (Mechanism.compile()), got {type(model).__name__}")
    joints = model.joints
    if len(joints) != 4 or len(model.body_names) != 4 or not all(j.pin for j in joints):
        return None
    pins = {}
    for j in joints:
        for b in j.bodies:
            pins.setdefault(b, []).append(j)
    if any(len(v) != 2 for v in pins.values()):
        return None
    loop, body, joint = [], "ground", pins["ground"][0]
    for _ in range(4):  # walk the loop: ground -> first link -> ... -> back to the ground
        nxt = next(b for b in joint.bodies if b != body)
        loop.append(joint)
        body, joint = nxt, next(k for k in pins[nxt] if k is not joint)
    if body != "ground":
        return None
    links = [next(b for b in loop[k].bodies if b in loop[(k + 1) % 4].bodies) for k in range(4)]  # ground last
    lengths = [float(np.hypot(*(loop[k].data["at"] - loop[(k + 1) % 4].data["at"]))) for k in range(4)]
    driven = None
    if len(model.drivers) == 1 and "ground" in model.drivers[0].bodies and model.drivers[0].bodies != ("ground",):
        driven = next((b for b in model.drivers[0].bodies if b != "ground"), None)
    if driven == links[2]:  # the link at the far side of the loop is driven: walk the other way
        links, lengths = [links[2], links[1], links[0], links[3]], [lengths[2], lengths[1], lengths[0], lengths[3]]
    role = {links[0]: "crank", links[1]: "coupler", links[2]: "rocker"}.get(driven)
    return (lengths[3], lengths[0], lengths[1], lengths[2]), role
