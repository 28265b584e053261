"""Every joint type against finite differences: Phi_q and gamma, at random configurations.

gamma is checked against -d2/dt2 Phi(q + qd t) at t = 0 (Phi_q qdd = gamma along any motion).
Kernels take and give arrays components first, configurations last (planar.joints.base).
Then the compiled system that runs them: its sparse values against its dense evaluation.
"""

import numpy as np
import pytest

from planar import system
from planar.geometry import Frames, cos_sin
from planar.joints import JOINT_TYPES
from planar.joints.base import SketchFrames, kernel_params
from planar.mechanisms import CATALOGUE

N = 5  # configurations
K = 3  # joints per group


def random_data(cls, rng):
    """World sketch data for one joint of class ``cls`` (any values: the kernels do not care)."""
    p = lambda: rng.uniform(-2, 2, 2)  # noqa: E731
    line = dict(at=p(), origin=p(), direction=p())
    data = {
        "Revolute": dict(at=p()),
        "Prismatic": line,
        "Slot": line,
        "TravelDriver": line,
        "CarrierGear": dict(radius_a=rng.uniform(0.5, 2), radius_b=rng.uniform(0.5, 2), sign=rng.choice([-1.0, 1.0]),
                            centre_a=p(), centre_b=p(), pressure_angle=rng.uniform(0, 0.5)),
        "Gear": dict(radius_a=rng.uniform(0.5, 2), radius_b=rng.uniform(2.5, 3), sign=rng.choice([-1.0, 1.0]),
                     centre_a=p(), centre_b=p(), pressure_angle=rng.uniform(0, 0.5)),
        "RackPinion": dict(radius=rng.uniform(0.5, 2), centre=p(), through=p(), direction=p(),
                           side=rng.choice([-1.0, 1.0]), pressure_angle=rng.uniform(0, 0.5)),
        "AngleDriver": {},
        "CoordinateDriver": dict(at=p(), axis=(1.0, 0.0) if rng.random() < 0.5 else (0.0, 1.0)),
    }
    data["RollingContact"] = data["Gear"]
    return data[cls.__name__]


def group(cls, rng):
    names = [f"b{k}" for k in range(cls.n_bodies)]
    sketch = SketchFrames({b: rng.uniform(-1, 1, 2) for b in names}, {b: rng.uniform(-3, 3) for b in names})
    joints = [cls(f"j{k}", names, **random_data(cls, rng)) for k in range(K)]
    params = [j.params(sketch) for j in joints]
    return kernel_params({key: np.stack([P[key] for P in params]) for key in params[0]})


def frames(q, qd=None):
    """q (3, nb, K, N): (x, y, phi) of each body slot of each joint -> Frames."""
    F = Frames(q[:2], q[2], np.cos(q[2]), np.sin(q[2]))
    if qd is not None:
        F.rd, F.phid = qd[:2], qd[2]
    return F


@pytest.mark.parametrize("cls", JOINT_TYPES, ids=lambda c: c.__name__)
def test_jacobian_and_gamma_match_finite_differences(cls):
    rng = np.random.default_rng(7)
    P = group(cls, rng)
    nb = cls.n_bodies
    q = rng.uniform(-2, 2, (3, nb, K, N))
    qd = rng.uniform(-2, 2, (3, nb, K, N))
    # constants taken at q, so every row holds there (the wrapped gear row is smooth near 0)
    P["c"] = cls.Phi(dict(P, c=np.zeros_like(P["c"])), frames(q))

    J = cls.Phi_q(P, frames(q))
    assert J.shape == (cls.n_rows, 3 * nb, K, N)
    h = 1e-6
    for col in range(3 * nb):
        e = np.zeros((3, nb, 1, 1))
        e[col % 3, col // 3] = h  # columns are (x, y, phi) per body slot
        up = cls.Phi(P, frames(q + e))
        dn = cls.Phi(P, frames(q - e))
        np.testing.assert_allclose(J[:, col], (up - dn) / (2 * h), atol=1e-7, rtol=1e-6)

    t = 1e-4
    phi = [cls.Phi(P, frames(q + k * t * qd)) for k in (-1, 0, 1)]
    fd = -(phi[2] - 2 * phi[1] + phi[0]) / t**2
    gamma = cls.gamma(P, frames(q, qd))
    assert gamma.shape == (cls.n_rows, K, N)
    np.testing.assert_allclose(gamma, fd, atol=2e-5 * (1 + np.abs(gamma).max()))


@pytest.mark.parametrize("cls", JOINT_TYPES, ids=lambda c: c.__name__)
def test_kernels_broadcast_over_design_axis(cls):
    """Parameters with a trailing configuration axis (one design per configuration) give the
    same rows, Jacobians and gamma."""
    rng = np.random.default_rng(3)
    P = group(cls, rng)
    q, qd = rng.uniform(-2, 2, (2, 3, cls.n_bodies, K, N))
    many = {k: np.broadcast_to(v, v.shape[:-1] + (N,)) for k, v in P.items()}
    for kernel in (cls.Phi, cls.Phi_q):
        np.testing.assert_allclose(kernel(many, frames(q)), kernel(P, frames(q)), rtol=0, atol=1e-15)
    np.testing.assert_allclose(cls.gamma(many, frames(q, qd)), cls.gamma(P, frames(q, qd)), rtol=0, atol=1e-15)


@pytest.mark.parametrize("cls", JOINT_TYPES, ids=lambda c: c.__name__)
def test_combined_kernel_equals_the_two_kernels(cls):
    """... and writes every entry of the array it is given (the system's are not zeroed)."""
    rng = np.random.default_rng(11)
    P = group(cls, rng)
    F = frames(rng.uniform(-2, 2, (3, cls.n_bodies, K, N)))
    out = np.full((cls.n_rows, 3 * cls.n_bodies, K, N), np.nan)
    Phi, J = cls.Phi_and_Phi_q(P, F, out)
    assert J is out
    np.testing.assert_allclose(Phi, cls.Phi(P, F), rtol=0, atol=1e-15)
    np.testing.assert_allclose(J, cls.Phi_q(P, F), rtol=0, atol=1e-15)
    out[:] = np.nan
    np.testing.assert_allclose(cls.Phi_q(P, F, out), J, rtol=0, atol=1e-15)


@pytest.mark.parametrize("cls", JOINT_TYPES, ids=lambda c: c.__name__)
def test_the_entries_a_kernel_may_skip_are_the_same_for_every_joint_and_pose(cls):
    """With constants=False a kernel writes every entry but those its class has the same at
    every pose and for every joint (the block solves take those from the plan)."""
    rng = np.random.default_rng(12)
    skipped, seen = None, []
    for _ in range(3):  # new joints (parameters) and poses each time
        P = group(cls, rng)
        F = frames(rng.uniform(-2, 2, (3, cls.n_bodies, K, N)))
        out = np.full((cls.n_rows, 3 * cls.n_bodies, K, N), np.nan)
        Phi, J = cls.Phi_and_Phi_q(P, F, out, constants=False)
        np.testing.assert_allclose(Phi, cls.Phi(P, F), rtol=0, atol=1e-15)
        full = cls.Phi_q(P, F)
        mask = np.isnan(J)
        assert skipped is None or np.array_equal(mask, skipped)
        skipped = mask
        np.testing.assert_allclose(J[~mask], full[~mask], rtol=0, atol=1e-15)
        assert np.all((full == full[..., :1, :1])[mask])  # the same for every joint and pose
        seen.append(full[mask])
    assert all(np.array_equal(s, seen[0]) for s in seen)  # and for other parameters
    assert skipped.any() == (cls.__name__ in ("Revolute", "Prismatic", "AngleDriver"))


@pytest.mark.parametrize("cls", JOINT_TYPES, ids=lambda c: c.__name__)
def test_scalar_kernels_equal_the_numpy_kernels(cls):
    """The compiled engine's kernels (each class's ``scalar_kernels``: one joint at one
    configuration) give the numpy kernels' rows, Jacobian blocks and gamma, joint by joint."""
    keys, kernel, gamma = cls.scalar_kernels
    rng = np.random.default_rng(5)
    P = group(cls, rng)
    P["c"] = rng.uniform(-1, 1, P["c"].shape)
    nb, nr = cls.n_bodies, cls.n_rows
    q, qd = rng.uniform(-2, 2, (2, 3, nb, K, N))
    F = frames(q, qd)
    Phi, J, G = cls.Phi(P, F), cls.Phi_q(P, F), cls.gamma(P, F)
    flat = lambda v: v[..., 0].T.reshape(K, -1)  # noqa: E731 (kernel layout -> one row per joint)
    par = np.concatenate([flat(P[key]) for key in keys], axis=1) if keys else np.zeros((K, 1))
    c = flat(P["c"])
    for k in range(K):
        for n in range(N):
            f = np.zeros((nb, 8))
            f[:, :3], f[:, 5:] = q[:, :, k, n].T, qd[:, :, k, n].T
            f[:, 3], f[:, 4] = np.cos(f[:, 2]), np.sin(f[:, 2])
            phi, jac, g = np.zeros(nr), np.zeros((nr, 3 * nb)), np.zeros(nr)
            kernel(par[k], c[k], f, np.arange(nb), phi, jac)
            gamma(par[k], c[k], f, np.arange(nb), g)
            np.testing.assert_allclose(phi, Phi[:, k, n], rtol=0, atol=1e-14)
            np.testing.assert_allclose(jac, J[:, :, k, n], rtol=0, atol=1e-14)
            np.testing.assert_allclose(g, G[:, k, n], rtol=0, atol=1e-13 * (1 + np.abs(G).max()))


def test_cos_sin_through_the_half_angle_tangent_is_at_rounding_level():
    phi = np.concatenate((np.linspace(-20, 20, 100001), np.pi * np.arange(-5, 6), [np.pi / 2, 1e6, -1e8]))
    c, s = np.empty_like(phi), np.empty_like(phi)
    cos_sin(phi, c, s)
    assert np.abs(c - np.cos(phi)).max() <= 4e-16
    assert np.abs(s - np.sin(phi)).max() <= 4e-16


@pytest.mark.parametrize("name", ["slider_crank", "rack_and_pinion", "planetary_gear_train", "open_chain"])
def test_system_values_and_gamma_agree_with_the_dense_evaluation(name):
    """Over more configurations than one pass holds: the values scattered by ``entries`` are
    the dense Jacobian, and a configuration's gamma does not depend on its batch."""
    model = CATALOGUE[name]().compile()
    sysm = model.system
    rng = np.random.default_rng(5)
    N = system._CHUNK + 3
    q = model.q0 + rng.normal(size=(N, model.n))
    qd = rng.normal(size=(N, model.n))
    u = model.u0 + rng.normal(size=(N, model.u0.size))
    Phi, Jv = sysm.values(q, u)
    Phi_dense, J = sysm.evaluate(q, u)
    np.testing.assert_allclose(Phi, Phi_dense, rtol=0, atol=1e-14)
    rows, cols = sysm.entries
    assert Jv.shape == (rows.size + 1, N) and not Jv[-1].any()
    scattered = np.zeros((N, sysm.m, sysm.n + 1))
    scattered[:, rows, cols] = Jv[:-1].T  # the dump column n may repeat: it is dropped
    np.testing.assert_allclose(scattered[:, :, : sysm.n], J, rtol=0, atol=1e-14)
    gamma = sysm.gamma(q, qd, u)
    for i in (0, N - 1):
        np.testing.assert_allclose(gamma[i], sysm.gamma(q[i : i + 1], qd[i : i + 1], u[i : i + 1])[0], rtol=0, atol=1e-13)
