"""The geared five-bar of the seed (000: f5link, examples 7.1 and 7.2): gear 2 (pitch radius R2)
on the input pivot meshes with gear 4 (R4), carried by the arm O2-B; gear 4 carries link 4
(B-C, length R4), and link 5 (O5-C) closes the loop to the ground. Reference configuration:
links 3 and 4 in line with th2 = 0. The seed's Newton loop stopped at a residual of 0.01, so
its printed angles are off by up to 0.04 deg; these are the converged values.

Run: ``python examples/geared_five_bar.py [OUTDIR]`` (writes geared_five_bar.png there).
"""

import sys
from pathlib import Path

import numpy as np

from planar import draw
from planar.mechanisms import geared_five_bar

deg = np.degrees


def main(outdir="."):
    for r1, R2, R4, r5, th2 in ((8, 3, 3.5, 6, 60.0), (50, 12, 14, 50, 30.0)):
        m = geared_five_bar(r1, R2, R4, r5)
        ref = m.compile()
        res = ref.sweep(np.radians(np.linspace(0.0, th2, 61)), velocity=10.0)
        print(f"r1 = {r1}, R2 = {R2}, R4 = {R4}, r5 = {r5}: reference th3 = th4 = "
              f"{deg(res.angle('arm')[0]):.6f} deg, th5 = {deg(res.angle('link5')[0]):.6f} deg")
        print(f"  th2 = {th2:g} deg: th3 = {deg(res.angle('arm')[-1]):.6f}, th4 = {deg(res.angle('gear4')[-1]):.6f}, "
              f"th5 = {deg(res.angle('link5')[-1]):.6f} deg")
        print(f"  w2 = 10 rad/s: w3 = {res.omega('arm')[-1]:.6f}, w4 = {res.omega('gear4')[-1]:.6f}, "
              f"w5 = {res.omega('link5')[-1]:.6f} rad/s")


    res = geared_five_bar().sweep(np.radians(np.linspace(0.0, 60.0, 31)), velocity=10.0)
    ax = draw.figure(res, 30, ["B", "C"], vectors=False, size=(7, 5))
    out = Path(outdir) / "geared_five_bar.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
