"""The four-bar of the seeds (000: movef4centros [4 2 3 4]; 003: f4bar with the acceleration
errata fixed): r1 = 4, r2 = 2, r3 = 3, r4 = 4, crank at 60 deg turning at 10 rad/s, coupler
point C 2 from A at 30 deg off A->B; both assembly modes; the frame turned by 25 deg; the
instant centres (centros) at 60 deg and their loci, as movef4centros draws them.

Run: ``python examples/four_bar.py [OUTDIR]`` (writes four_bar.png and four_bar_centres.png).
"""

import sys
from pathlib import Path

import numpy as np

from planar import draw
from planar.analysis import instant_centres
from planar.mechanisms import four_bar

C = (2 * np.cos(np.radians(30)), 2 * np.sin(np.radians(30)))  # p along A->B, q to its left


def report(res, with_point=True):
    deg = np.degrees
    print(f"  th3 = {deg(res.angle('coupler')[0]):.6f} deg, th4 = {deg(res.angle('rocker')[0]):.6f} deg")
    print(f"  w3 = {res.omega('coupler')[0]:.6f}, w4 = {res.omega('rocker')[0]:.6f} rad/s")
    print(f"  a3 = {res.alpha('coupler')[0]:.6f}, a4 = {res.alpha('rocker')[0]:.6f} rad/s^2")
    if with_point:
        for what, v in (("C", res.position("C")), ("v_C", res.velocity("C")), ("a_C", res.acceleration("C"))):
            print(f"  {what} = ({v[0, 0]:.6f}, {v[0, 1]:.6f})")


def main(outdir="."):
    th2 = np.radians(60.0)
    for crossed in (False, True):
        for a2 in (0.0, 5.0):
            print(f"crank 60 deg, w2 = 10 rad/s, a2 = {a2:g} rad/s^2, B {'right' if crossed else 'left'} of A->O4:")
            m = four_bar(4, 2, 3, 4, coupler_point=C, crossed=crossed, start=th2)
            report(m.sweep([th2], velocity=10.0, acceleration=a2))

    print("frame at 25 deg, crank 100 deg, w2 = -3 rad/s, a2 = 1 rad/s^2:")
    th2 = np.radians(100.0)
    m = four_bar(4, 2, 3, 4, frame_angle=np.radians(25.0), start=th2)
    report(m.sweep([th2], velocity=-3.0, acceleration=1.0), with_point=False)


    res = four_bar(4, 2, 3, 4, coupler_point=C).sweep(np.radians(np.arange(0.0, 361.0, 5.0)), velocity=10.0)
    ax = draw.figure(res, 12, ["A", "B", "C"], size=(7, 5.5))
    out = Path(outdir) / "four_bar.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)

    print("instant centres at crank 60 deg (1 ground, 2 crank, 3 coupler, 4 rocker):")
    names = res.model.body_names
    for (a, b), locus in instant_centres(res).items():
        x, y = np.round(locus[12], 6) + 0.0  # no "-0.000000" from round-off
        print(f"  I{names.index(a) + 1}{names.index(b) + 1} = ({x:.6f}, {y:.6f})")
    ax = draw.draw(res, 12)
    draw.draw_instant_centres(res, 12, ax=ax, loci=True)
    out = Path(outdir) / "four_bar_centres.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
