"""The slider-cranks of the seeds: sldlink (000) with the crank, the coupler or the slider as
input (r2 = 2, r3 = 3, offset r4 = 4), and the offset slider-crank of the student report (003):
r2 = 2, r3 = 5, e = 1, crank at 30 deg and 12 rad/s, with its stroke and time ratio measured
by the stroke analysis.

Run: ``python examples/slider_crank.py [OUTDIR]`` (writes slider_crank.png there).
"""

import sys
from pathlib import Path

import numpy as np

from planar import draw
from planar.analysis import stroke
from planar.mechanisms import slider_crank

deg = np.degrees


def main(outdir="."):
    print("crank driven: th2 = 60 deg, w2 = 10 rad/s")
    res = slider_crank(2, 3, offset=4, start=np.radians(60)).sweep(np.radians([60.0]), velocity=10.0)
    print(f"  r1 = {res.coordinate('slide')[0]:.6f}, th3 = {deg(res.angle('coupler')[0]):.6f} deg")
    print(f"  w3 = {res.omega('coupler')[0]:.6f} rad/s, slider {res.coordinate('slide', 1)[0]:.6f} /s")
    print(f"  a3 = {res.alpha('coupler')[0]:.6f} rad/s^2, slider {res.coordinate('slide', 2)[0]:.6f} /s^2")

    print("coupler driven: th3 = 60 deg, w3 = 10 rad/s")
    res = slider_crank(2, 3, offset=4, driver="coupler", start=np.radians(60)).sweep(np.radians([60.0]), velocity=10.0)
    print(f"  th2 = {deg(res.angle('crank')[0]):.6f} deg, r1 = {res.coordinate('slide')[0]:.6f}")
    print(f"  w2 = {res.omega('crank')[0]:.6f} rad/s, slider {res.coordinate('slide', 1)[0]:.6f} /s")
    print(f"  a2 = {res.alpha('crank')[0]:.6f} rad/s^2, slider {res.coordinate('slide', 2)[0]:.6f} /s^2")

    print("slider driven: r1 = 1, slider at 10 /s (the pose with th2 near 119 deg)")
    res = slider_crank(2, 3, offset=4, driver="slider", start=1.0).sweep([1.0], velocity=10.0)
    print(f"  th2 = {deg(res.angle('crank')[0]):.6f} deg, th3 = {deg(res.angle('coupler')[0]):.6f} deg")
    print(f"  w2 = {res.omega('crank')[0]:.6f}, w3 = {res.omega('coupler')[0]:.6f} rad/s")
    print(f"  a2 = {res.alpha('crank')[0]:.6f}, a3 = {res.alpha('coupler')[0]:.6f} rad/s^2")

    print("offset slider-crank r2 = 2, r3 = 5, e = 1: crank at 30 deg, 12 rad/s")
    m = slider_crank(2, 5, offset=1)
    res = m.sweep(np.radians([30.0]), velocity=12.0)
    print(f"  B = ({res.position('B')[0, 0]:.6f}, {res.position('B')[0, 1]:.6f}), "
          f"v_B = {res.velocity('B')[0, 0]:.6f}, a_B = {res.acceleration('B')[0, 0]:.6f}")
    s = stroke(m, "travel:slide")  # the slider's extremes over one crank turn, located by the solver
    print(f"  stroke {s.stroke:.6f}, time ratio {s.time_ratio:.6f} "
          f"(dead centres at th2 = {deg(s.input_at_maximum):.6f} and {deg(s.input_at_minimum):.6f} deg)")

    res = slider_crank(2, 5, offset=1, coupler_point=(2.5, 0.8)).sweep(np.radians(np.arange(0.0, 361.0, 5.0)),
                                                                        velocity=12.0)
    ax = draw.figure(res, 6, ["C"], vectors=False, size=(7, 4))
    out = Path(outdir) / "slider_crank.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
