"""An atlas of coupler curves: random four-bar and Watt six-bar designs swept as one batch each
(:func:`planar.sweep_designs`), filtered for validity (the crank turns fully, every value
valid, no branch event), their curves normalised (centred, scaled to unit RMS radius, turned
to their principal axis), stored, reloaded and drawn as a grid. The runtime per design goes
to standard error (it depends on the machine); everything printed is deterministic.

For atlases beyond memory, :func:`planar.cluster.sweep_designs_to_store` runs the same study
in batches on a dask cluster into a Zarr store, and resumes it after an interruption.

Run: ``python examples/atlas.py [OUTDIR]`` (writes atlas.npz and atlas.png).
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import planar  # noqa: E402
from planar.mechanisms import four_bar, watt_six_bar  # noqa: E402

TH = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)  # one crank turn


def random_designs(rng, D, six_bar):
    """D designs with the ground of unit length; lengths and coupler points at random."""
    d = {"crank": rng.uniform(0.1, 0.6, D), "coupler": rng.uniform(0.5, 2.0, D), "rocker": rng.uniform(0.5, 2.0, D),
         "coupler_point": [tuple(p) for p in rng.uniform(-1.0, 1.0, (D, 2)).round(3)]}
    if six_bar:
        d.update(rocker_point=[tuple(p) for p in rng.uniform(-1.0, 1.0, (D, 2)).round(3)],
                 link_5=rng.uniform(0.5, 2.0, D), link_6=rng.uniform(0.5, 2.0, D))
    return {k: np.round(v, 3) if isinstance(v, np.ndarray) else v for k, v in d.items()}


def normalised(curves):
    """(K, N, 2) curves centred, scaled to unit RMS radius and turned so that their principal
    axis is x (the sign chosen so that the third moment along x is positive)."""
    c = curves - curves.mean(axis=1, keepdims=True)
    c /= np.sqrt((c**2).sum(axis=2).mean(axis=1))[:, None, None]
    cov = np.einsum("kni,knj->kij", c, c)
    angle = 0.5 * np.arctan2(2 * cov[:, 0, 1], cov[:, 0, 0] - cov[:, 1, 1])
    rot = np.stack([np.stack([np.cos(angle), np.sin(angle)], -1), np.stack([-np.sin(angle), np.cos(angle)], -1)], 1)
    c = np.einsum("kij,knj->kni", rot, c)
    c[..., 0] *= np.where((c[..., 0] ** 3).sum(axis=1) < 0, -1.0, 1.0)[:, None]
    return c


def study(name, build, point, designs, fixed):
    t = time.perf_counter()
    res = planar.sweep_designs(build, designs, TH, fixed=fixed)
    took = time.perf_counter() - t
    print(f"{name}: {len(res)} designs, {int(res.batched.sum())} swept in the batch, "
          f"{sum(e is not None for e in res.errors)} could not be built or assembled")
    print(f"{name}: runtime {1e3 * took / len(res):.2f} ms per design", file=sys.stderr)
    valid = res.ok.all(axis=1) & np.array([not e for e in res.events])
    print(f"{name}: {int(valid.sum())} valid (full crank turn, no event)")
    return normalised(res.position(point)[valid])


def main(outdir="."):
    rng = np.random.default_rng(2026)
    curves = {"four-bar": study("four-bar", four_bar, "C", random_designs(rng, 48, False), dict(ground=1.0)),
              "six-bar": study("six-bar", watt_six_bar, "E", random_designs(rng, 32, True), dict(ground=1.0))}

    out = Path(outdir) / "atlas.npz"
    np.savez_compressed(out, **{k.replace("-", "_"): v for k, v in curves.items()})
    print("wrote", out.name)
    with np.load(out) as f:
        back = {k: f[k.replace("-", "_")] for k in curves}
    assert all(np.array_equal(back[k], curves[k]) for k in curves)
    for k, c in back.items():
        r = np.sqrt((c**2).sum(axis=2))
        print(f"reloaded {k}: {c.shape[0]} curves of {c.shape[1]} points, RMS radius {np.sqrt((r**2).mean()):.6f}, "
              f"largest radius {r.max():.3f}")

    shown = [(k, c) for k, cs in back.items() for c in cs[:12]]
    cols = 6
    fig, axes = plt.subplots(-(-len(shown) // cols), cols, figsize=(2 * cols, 2 * -(-len(shown) // cols)))
    for ax in axes.ravel():
        ax.set_axis_off()
    for ax, (k, c) in zip(axes.ravel(), shown):
        ax.plot(*np.vstack([c, c[:1]]).T, lw=1.0, color="C0" if k == "four-bar" else "C1")
        ax.set_aspect("equal")
        ax.set_title(k, fontsize=8)
    out = Path(outdir) / "atlas.png"
    fig.savefig(out, dpi=60)
    print("wrote", out.name)


if __name__ == "__main__":
    main(*sys.argv[1:])
