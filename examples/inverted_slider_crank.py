"""The inverted slider-crank of the seed (000: sldinv): r1 = 20 (O2 to O4), r2 = 8.5, no offset;
the block pinned to the crank at A slides on link 3, which turns about O4. First the crank
drives (60 deg, 2.5 rad/s), then link 3 (154.95 deg, 0.10546 rad/s, 3.3012 rad/s^2).

Run: ``python examples/inverted_slider_crank.py [OUTDIR]`` (writes inverted_slider_crank.png).
"""

import sys
from pathlib import Path

import numpy as np

from planar import draw
from planar.mechanisms import inverted_slider_crank

deg = np.degrees


def report(res, driven):
    other = "link3" if driven == "crank" else "crank"
    print(f"  th{'3' if other == 'link3' else '2'} = {deg(res.angle(other)[0]):.6f} deg, "
          f"r3 = {res.coordinate('slide')[0]:.6f}")
    print(f"  w = {res.omega(other)[0]:.6f} rad/s, r3' = {res.coordinate('slide', 1)[0]:.6f} /s")
    print(f"  a = {res.alpha(other)[0]:.6f} rad/s^2, r3'' = {res.coordinate('slide', 2)[0]:.6f} /s^2 "
          f"(with the Coriolis term)")


def main(outdir="."):
    print("crank driven: th2 = 60 deg, w2 = 2.5 rad/s, a2 = 0")
    th2 = np.radians(60.0)
    report(inverted_slider_crank(20, 8.5, start=th2).sweep([th2], velocity=2.5), "crank")
    print("link 3 driven: th3 = 154.95 deg, w3 = 0.10546 rad/s, a3 = 3.3012 rad/s^2")
    th3 = np.radians(154.95)
    report(inverted_slider_crank(20, 8.5, driver="link3", start=th3).sweep([th3], velocity=0.10546,
                                                                          acceleration=3.3012), "link3")


    res = inverted_slider_crank(20, 8.5).sweep(np.radians(np.arange(0.0, 361.0, 5.0)), velocity=2.5)
    ax = draw.figure(res, 12, ["A"], paths=False, size=(7, 4))
    out = Path(outdir) / "inverted_slider_crank.png"
    ax.figure.savefig(out, dpi=80)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
