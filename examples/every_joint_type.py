"""A custom machine that uses every joint type of planar's files, driven by one input.

- gear1 (on a ground pivot O1) meshes with gear2 (on O2): a gear pair on the ground as carrier;
- a crank pin A on gear2 drives a connecting rod to a slider block B on a ground guide (prismatic);
- a rack on top of the slider turns a pinion on a ground pivot P (rack and pinion);
- a rocker pivoted at O1 carries a slot that a pin K of the rod runs in (pin in slot);
- a planet gear on the rocker rolls on gear1 (a gear pair whose centres sit on different bodies);
- a push rod from the slider rolls a wheel along the floor (rolling without slip).
(A wheel rolling inside a ring with no arm, the gear option ``hold_distance``, is the catalogue's
``rolling_wheel(track_radius=...)``.)

Run: ``python examples/every_joint_type.py [OUTDIR]`` (writes every_joint_type.png there, and
the machine as a mechanism file, every_joint_type.json: try ``planar run every_joint_type.json``).
"""

import sys
from pathlib import Path

import numpy as np

import planar
from planar import draw


def build():
    """The machine, sketched with gear2's crank pin at 60 deg, driven by gear1's angle."""
    m = planar.Mechanism("every joint type")
    for body in ("gear1", "gear2", "rod", "slider", "pinion", "rocker", "planet", "pushrod", "wheel"):
        m.add_body(body)
    m.add_revolute("O1", m.ground, "gear1", at=(0, 0))
    m.add_revolute("O2", m.ground, "gear2", at=(3, 0))
    m.add_gear("g12", "gear1", "gear2", 1.0, 2.0, carrier=m.ground)

    A = np.array([3 + 1.5 * np.cos(np.radians(60)), 1.5 * np.sin(np.radians(60))])
    B = np.array([A[0] + np.sqrt(4.5**2 - A[1] ** 2), 0.0])  # rod 4.5 long, slider on y = 0
    m.add_revolute("A", "gear2", "rod", at=A)
    m.add_revolute("B", "rod", "slider", at=B)
    m.add_prismatic("S", m.ground, "slider", at=B, direction=(1, 0))

    m.add_revolute("P", m.ground, "pinion", at=(B[0], 1.0))
    m.add_rack_pinion("rp", "pinion", "slider", 0.5, centre=(B[0], 1.0), through=(B[0], 0.5), direction=(1, 0))

    K = A + 0.4 * (B - A)
    m.add_revolute("O3", m.ground, "rocker", at=(0, 0))
    m.add_slot("K", "rocker", "rod", at=K, direction=K)
    u = K / np.hypot(*K)
    m.add_revolute("Q", "rocker", "planet", at=1.4 * u)
    m.add_gear("g1p", "gear1", "planet", 1.0, 0.4, centre_a=(0, 0), centre_b=1.4 * u)
    m.add_point("T", "rocker", at=5.6 * u)

    W = B + (1.5, -1.5)
    m.add_revolute("B2", "slider", "pushrod", at=B)
    m.add_revolute("W", "pushrod", "wheel", at=W)
    m.add_rolling("roll", "wheel", m.ground, 0.5, centre=W, through=(0, -2), direction=(1, 0))
    m.drive("O1")
    return m


def main(outdir="."):

    from planar import io
    from planar.units import Units

    mech = build()
    model = mech.compile()
    print(f"{model.name}: {len(model.body_names) - 1} moving bodies, {len(model.joints)} joints, "
          f"{model.dof} degree of freedom")
    print("joint types:", ", ".join(sorted({type(j).__name__ for j in model.joints})))
    # the contact's tangency row repeats what the pinion's pivot and the rack's slider hold: the
    # joint added last of those that repeat is the one called redundant
    print("redundant joints (a pinion on a fixed pivot over a rack that stays level):", list(model.redundant_joints))

    # gear1 turns twice while gear2 (twice its radius) turns once: one full cycle
    th1 = np.linspace(0.0, 4 * np.pi, 121)
    res = model.sweep(th1, velocity=2 * np.pi)  # gear1 at 1 rev/s
    print("all poses valid:", bool(res.ok.all()))
    print(f"slider stroke {np.ptp(res.position('B')[:, 0]):.6f}")
    print(f"gear2 turns {np.degrees(res.angle('gear2')[-1] - res.angle('gear2')[0]):.6f} deg")
    print(f"pinion turns {np.degrees(np.ptp(res.angle('pinion'))):.6f} deg (range)")
    print(f"wheel turns {np.degrees(np.ptp(res.angle('wheel'))):.6f} deg (range)")
    print(f"rocker swings {np.degrees(np.ptp(res.angle('rocker'))):.6f} deg")
    print(f"largest slider speed {np.max(np.abs(res.coordinate('S', 1))):.6f} per s")

    ax = draw.figure(res, 10, ["T"], vectors=False, size=(9, 5))
    out = Path(outdir) / "every_joint_type.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)

    sweep = io.SweepSettings(start=(0.0,), stop=(720.0,), num=121, speed=(60.0,))
    path = io.save(mech, Path(outdir) / "every_joint_type.json", Units(rate="rpm"), sweep)
    again = io.load(path).mechanism.sweep(th1[::10], velocity=2 * np.pi)
    print("wrote", path.name, "- read back, it sweeps the same:", bool(np.allclose(again.q, res.q[::10], atol=1e-12)))


if __name__ == "__main__":
    main(*sys.argv[1:])
