"""Open chains of the seed (004: acc2 and dyad): links of lengths r_k at absolute angles th_k
turning at w_k with angular accelerations a_k. The tip's position, velocity and acceleration as
magnitude and angle, as acc2 prints them; then dyad_draw's three-link chain with the velocity
(blue) and acceleration (red) arrows on every joint.

Run: ``python examples/open_chain.py [OUTDIR]`` (writes open_chain.png there).
"""

import sys
from pathlib import Path

import numpy as np

from planar import draw
from planar.mechanisms import open_chain


def tip(lengths, th_deg, w, a):
    th = np.radians(th_deg)
    res = open_chain(lengths, start=th).sweep([th], velocity=np.asarray(w, float), acceleration=np.asarray(a, float))
    return res


def main(outdir="."):
    cases = (([5], [10], [20], [0]),
             ([5, 8, 9], [10, 135, 12], [10, 20, 30], [0, 0, 0]),
             ([5, 8, 9], [10, 135, 12], [10, 20, 30], [3, 3, 3]),
             ([5, 10], [30, 50], [2, 4], [0, 0]))
    for lengths, th, w, a in cases:
        res = tip(lengths, th, w, a)
        vecs = [res.position("tip")[0], res.velocity("tip")[0], res.acceleration("tip")[0]]
        mags = "  ".join(f"{np.hypot(*v):.6g}" for v in vecs)
        angs = "  ".join(f"{np.degrees(np.arctan2(v[1], v[0])):.6g}" for v in vecs)
        print(f"r = {lengths}, th = {th} deg, w = {w} rad/s, a = {a} rad/s^2")
        print(f"  |s| |v| |a| = {mags}")
        print(f"  angles (deg) = {angs}")


    res = tip([15, 10, 5], [0, 60, 90], [0.5, 0.8, 0.5], [0, 0, 0])
    ax = draw.figure(res, 0, ["J2", "J3", "tip"], paths=False, size=(6, 5))
    out = Path(outdir) / "open_chain.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
