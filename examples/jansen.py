"""Theo Jansen's leg (the Strandbeest linkage) from its 13 published lengths ("holy numbers"):
a = 38, b = 41.5, c = 39.3, d = 40.1, e = 55.8, f = 39.4, g = 36.7, h = 65.7, i = 49,
j = 50, k = 61.9, l = 7.8, m = 15.

The crank (m) turns about O; the fixed pivot B is a to the left of O and l below it. Link j
joins the crank pin M to C, link k joins M to E; the triangle b-d-e (B, C, D) and link c
(B to E) pivot on B; link f joins D to F; the triangle g-h-i (E, F, G) carries the foot G.
Every joint but the pivots is a :class:`planar.Dyad`: two distances and a side, so the leg
is its published numbers and nothing else. One crank turn traces the foot path.

Run: ``python examples/jansen.py [OUTDIR]`` (writes jansen.png).
"""

import sys
from pathlib import Path

import numpy as np

import planar
from planar import draw

HOLY = dict(a=38.0, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7, i=49.0, j=50.0, k=61.9, l=7.8,
            m=15.0)


def jansen_leg(start=0.0, n=HOLY):
    """The leg with its crank at angle ``start`` (radians), driven by the crank's angle."""
    leg = planar.Mechanism("Jansen's leg")
    crank, link_j, link_k = leg.add_body("crank"), leg.add_body("link_j"), leg.add_body("link_k")
    bde, link_c, link_f, ghi = leg.add_body("bde"), leg.add_body("link_c"), leg.add_body("link_f"), leg.add_body("ghi")
    leg.add_revolute("O", leg.ground, crank, at=(0, 0))
    leg.add_revolute("B", leg.ground, bde, at=(-n["a"], -n["l"]))
    leg.add_revolute("Bc", leg.ground, link_c, at="B")
    leg.add_revolute("M", crank, link_j, at=n["m"] * np.array([np.cos(start), np.sin(start)]))
    leg.add_revolute("Mk", crank, link_k, at="M")
    leg.distance("O", "M", n["m"])
    leg.add_revolute("C", link_j, bde, at=planar.Dyad("M", n["j"], "B", n["b"], side="right"))
    leg.add_revolute("D", bde, link_f, at=planar.Dyad("B", n["d"], "C", n["e"], side="left"))
    leg.add_revolute("E", link_k, link_c, at=planar.Dyad("Mk", n["k"], "Bc", n["c"], side="left"))
    leg.add_revolute("Eg", link_c, ghi, at="E")
    leg.add_revolute("F", link_f, ghi, at=planar.Dyad("D", n["f"], "Eg", n["g"], side="right"))
    leg.add_point("G", ghi, at=planar.Dyad("Eg", n["i"], "F", n["h"], side="left"))
    leg.drive("O", start=start)
    return leg


def main(outdir="."):
    leg = jansen_leg()
    model = leg.compile()
    print(f"{model.name}: {len(model.body_names) - 1} bodies, {len(model.joints)} joints, dof {model.dof}")
    for name in ("C", "D", "E", "F", "G"):
        x, y = model.sketch.position(name)
        print(f"  {name} = ({x:.6f}, {y:.6f}) at crank 0 deg")

    res = leg.sweep(np.radians(np.arange(0.0, 361.0, 1.0)))
    foot = res.position("G")
    low = foot[:, 1].min()
    contact = foot[:, 1] < low + 1.0  # the foot within 1 of its lowest height: on the ground
    print(f"one crank turn, 361 values: all solved {bool(res.ok.all())}")
    print(f"  foot path: x {foot[:, 0].min():.6f} to {foot[:, 0].max():.6f}, "
          f"y {low:.6f} to {foot[:, 1].max():.6f}")
    print(f"  on the ground (within 1 of the lowest point) for {int(contact.sum())} of 361 degrees, "
          f"stride {np.ptp(foot[contact, 0]):.6f}")

    ax = draw.figure(res, 0, ["G"], size=(7, 5.5))
    out = Path(outdir) / "jansen.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
