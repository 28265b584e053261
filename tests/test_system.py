"""The compiled constraint system of every catalogue mechanism against finite differences.

Phi_q is the derivative of Phi, gamma is -d/dt (Phi_q qd) along q + t qd (so Phi_q qdd = gamma
on any motion with constant inputs), a driver row is g(q) - u, and the layout (rows, columns,
the ground's dump column, restriction to some rows) is what :func:`build_system` promises.
Poses are random, near the sketch (a gear row is smooth within half a turn of its own).
"""

import numpy as np
import pytest

from planar import system
from planar.mechanisms import CATALOGUE

NAMES = sorted(CATALOGUE)
N = 4  # random poses per mechanism


def poses(model, rng, N=N, spread=0.3):
    """(q, qd, u): random poses around the sketch, x and y scaled by the model's size."""
    scale = np.tile([model.L, model.L, 1.0], model.n // 3)
    q = model.q0 + spread * rng.normal(size=(N, model.n)) * scale
    qd = rng.normal(size=(N, model.n)) * scale
    u = model.u0 + spread * rng.normal(size=(N, model.u0.size))
    return q, qd, u


@pytest.fixture(scope="module", params=NAMES)
def model(request):
    return CATALOGUE[request.param]().compile()


def test_Phi_q_is_the_derivative_of_Phi(model):
    rng = np.random.default_rng(1)
    q, _, u = poses(model, rng)
    Phi, J = model.system.evaluate(q, u)
    assert Phi.shape == (N, model.m) and J.shape == (N, model.m, model.n)
    for col in range(model.n):
        h = 1e-6 * model.col_scale[col]
        e = np.zeros(model.n)
        e[col] = h
        fd = (model.system.evaluate(q + e, u, jacobian=False)[0] - model.system.evaluate(q - e, u, jacobian=False)[0])
        np.testing.assert_allclose(J[:, :, col], fd / (2 * h), rtol=1e-6, atol=1e-7 * model.col_scale[col],
                                   err_msg=f"{model.name}: column {col}")


def test_gamma_is_minus_the_rate_of_Phi_q_qd(model):
    rng = np.random.default_rng(2)
    q, qd, u = poses(model, rng)
    t = 1e-6
    Jqd = [np.einsum("nij,nj->ni", model.system.evaluate(q + s * t * qd, u)[1], qd) for s in (-1, 1)]
    fd = -(Jqd[1] - Jqd[0]) / (2 * t)
    gamma = model.system.gamma(q, qd, u)
    assert gamma.shape == (N, model.m)
    np.testing.assert_allclose(gamma, fd, rtol=1e-6, atol=1e-6 * (1 + np.abs(fd).max()), err_msg=model.name)


def test_driver_rows_are_g_minus_u_and_no_other_row_reads_u(model):
    rng = np.random.default_rng(3)
    q, qd, u = poses(model, rng)
    du = rng.normal(size=u.shape)
    Phi, J = model.system.evaluate(q, u)
    Phi2, J2 = model.system.evaluate(q, u + du)
    drivers = np.asarray(model.active_rows)[np.asarray(model.driver_rows_active)]
    want = np.zeros_like(Phi)
    want[:, drivers] = -du  # driver k reads input k
    np.testing.assert_allclose(Phi2 - Phi, want, rtol=0, atol=1e-12 * (1 + np.abs(Phi).max()))
    np.testing.assert_array_equal(J2, J)
    np.testing.assert_array_equal(model.system.gamma(q, qd, u + du), model.system.gamma(q, qd, u))


def test_rows_and_columns_follow_the_constraints_and_bodies(model):
    """Each constraint owns consecutive rows from its row address, all rows once; a body's
    columns are its (x, y, phi); the ground's go to the dump column n, and no (row, column)
    of a moving body is written twice."""
    sysm = model.system
    owned = np.zeros(sysm.m, int)
    for g in sysm.groups:
        np.testing.assert_array_equal(g.rows, model.row_adr[g.members][:, None] + np.arange(g.kind.n_rows))
        owned[g.rows.ravel()] += 1
        assert g.bodies.shape == (g.members.size, g.kind.n_bodies)
        want = np.where(g.bodies[:, :, None] > 0, 3 * (g.bodies[:, :, None] - 1) + np.arange(3), sysm.n)
        np.testing.assert_array_equal(g.cols, want.reshape(g.cols.shape))
        assert np.all((g.inputs >= 0) == bool(g.kind.is_driver))
    np.testing.assert_array_equal(owned, np.ones(sysm.m, int))
    rows, cols = sysm.entries
    moving = cols < sysm.n
    pairs = rows[moving] * (sysm.n + 1) + cols[moving]
    assert np.unique(pairs).size == pairs.size


def test_a_restricted_system_evaluates_the_kept_constraints_only(model):
    rng = np.random.default_rng(4)
    q, qd, u = poses(model, rng)
    keep = rng.choice(model.m, size=max(1, model.m // 3), replace=False)
    sub = model.system.restrict(keep)
    owners = np.zeros(model.m, bool)  # every row of a constraint owning a kept row
    for g in model.system.groups:
        sel = np.isin(g.rows, keep).any(axis=1)
        owners[g.rows[sel].ravel()] = True
    assert owners[keep].all()
    Phi, J = model.system.evaluate(q, u)
    Ps, Js = sub.evaluate(q, u)
    np.testing.assert_array_equal(Ps[:, owners], Phi[:, owners])
    np.testing.assert_array_equal(J[:, owners], Js[:, owners])
    assert not Ps[:, ~owners].any() and not Js[:, ~owners].any()
    gs = sub.gamma(q, qd, u)
    np.testing.assert_array_equal(gs[:, owners], model.system.gamma(q, qd, u)[:, owners])
    assert not gs[:, ~owners].any()  # a restricted system's rows start at zero, not garbage
    Pv, _ = sub.values(q, u)
    np.testing.assert_array_equal(Pv, Ps)


def test_evaluate_over_some_groups_writes_only_their_rows():
    model = CATALOGUE["slider_crank"]().compile()
    q, _, u = poses(model, np.random.default_rng(5))
    Phi, J = model.system.evaluate(q, u)
    for g in model.system.groups:
        Pg, Jg = model.system.evaluate(q, u, groups=[g])
        mine = np.zeros(model.m, bool)
        mine[g.rows.ravel()] = True
        np.testing.assert_array_equal(Pg[:, mine], Phi[:, mine])
        np.testing.assert_array_equal(Jg[:, mine], J[:, mine])
        assert not Pg[:, ~mine].any() and not Jg[:, ~mine].any()


@pytest.mark.parametrize("n", [0, 1, system._CHUNK - 1, system._CHUNK, 2 * system._CHUNK + 1])
def test_chunks_cover_every_configuration_once_in_order(n):
    chunks = system.chunks(n)
    assert len(chunks) >= 1
    np.testing.assert_array_equal(np.concatenate([np.arange(n)[s] for s in chunks]), np.arange(n))
    assert all(len(range(n)[s]) <= system._CHUNK for s in chunks)
