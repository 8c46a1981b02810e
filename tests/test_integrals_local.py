"""The local mass and Dirichlet matrices of dhlb.fem.integrals (seed part 3, §11-§12).

References: Gauss quadrature of the piecewise-linear section written in a single radially parallel
frame (``tests/integral_references.py``), exact P1 values, gauge and relabeling covariance.
"""

from itertools import combinations, permutations, product
from math import comb

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.fem.integrals import (
    curvature_tensor,
    local_dirichlet_matrices,
    local_edges,
    local_gauge_connection,
    local_mass_matrices,
    local_matrices,
    local_triangles,
)
from tests.integral_references import closed_data, quadrature_matrices, simplex

# ------------------------------------------------------------------------------------------------
# local matrices
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("n,order", [(1, 30), (2, 36), (3, 22)])
def test_local_matrices_against_quadrature(n, order):
    rng = np.random.default_rng(20 + n)
    for scale in (0.2, 1.5):
        _, gram, vol = simplex(rng, n)
        om, r = closed_data(rng, n, scale)
        mass_q, dir_q = quadrature_matrices(gram, vol, om, r, order)
        mass, dirichlet = local_matrices(gram, vol, om, r)
        assert np.abs(mass - mass_q).max() <= 1e-12 * np.abs(mass_q).max()
        assert np.abs(dirichlet - dir_q).max() <= 1e-12 * np.abs(dir_q).max()


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_flat_curvature_gives_p1_matrices(n):
    rng = np.random.default_rng(30 + n)
    _, gram, vol = simplex(rng, n)
    om = np.zeros(comb(n + 1, 3))
    mass, dirichlet = local_matrices(gram, vol, om)
    p1 = vol / ((n + 1) * (n + 2)) * (np.ones((n + 1, n + 1)) + np.eye(n + 1))
    np.testing.assert_allclose(mass, p1, rtol=1e-15, atol=0)
    np.testing.assert_allclose(dirichlet, vol * gram, rtol=1e-15, atol=1e-15 * np.abs(vol * gram).max())
    # with a flat connection r_ab = conj(g_b) g_a the matrices are conjugated by the gauge
    g = np.exp(1j * rng.uniform(0, 2 * np.pi, n + 1))
    e = local_edges(n)
    r = np.conj(g[e[:, 1]]) * g[e[:, 0]]
    np.testing.assert_allclose(local_mass_matrices(vol, om, r, dim=n), np.outer(np.conj(g), g) * p1, rtol=1e-14)


def test_flat_sign_convention_edge_term():
    """Ω = 0: A[b, a] = -w r_ab with w = -vol G_ab, so a parallel pair z_b = r_ab z_a has no energy."""
    rng = np.random.default_rng(5)
    _, gram, vol = simplex(rng, 2)
    r = np.exp(1j * np.array([0.4, -1.0, -1.4]))          # flat: r_12 = r_02 conj(r_01)
    a = local_dirichlet_matrices(gram, vol, [0.0], r)
    assert a[1, 0] == pytest.approx(vol * gram[0, 1] * r[0], rel=1e-14)
    z = np.array([1.0, r[0], r[1]])                         # parallel section
    assert abs(z.conj() @ a @ z) < 1e-14 * np.abs(a).max()


@settings(max_examples=25, deadline=None)
@given(n=st.sampled_from([2, 3]), seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1e-6, 0.3, 2.0, 9.0, 60.0]))
def test_hermitian_psd_and_definite_mass(n, seed, scale):
    rng = np.random.default_rng(seed)
    _, gram, vol = simplex(rng, n)
    om, r = closed_data(rng, n, scale)
    mass, dirichlet = local_matrices(gram, vol, om, r)
    for mat in (mass, dirichlet):
        np.testing.assert_allclose(mat, mat.conj().T, rtol=0, atol=1e-15 * np.abs(mat).max())
    ev = np.linalg.eigvalsh(dirichlet)
    assert ev.min() >= -1e-12 * ev.max()
    if np.abs(om).max() > 1e-3:      # with curvature no section is parallel: positive definite
        assert ev.min() > 0
    assert np.linalg.eigvalsh(mass).min() > 0


def test_local_gauge_and_gauge_covariance():
    rng = np.random.default_rng(7)
    for n in (2, 3):
        _, gram, vol = simplex(rng, n)
        om, r = closed_data(rng, n, 1.3)
        m_loc, a_loc = local_matrices(gram, vol, om)                    # local gauge
        m2, a2 = local_matrices(gram, vol, om, local_gauge_connection(om))
        np.testing.assert_array_equal(m_loc, m2)
        np.testing.assert_array_equal(a_loc, a2)
        # global frames: g_a = r_0a (g_0 = 1), M = diag(g) M_loc diag(conj g)
        e = {tuple(v): q for q, v in enumerate(local_edges(n))}
        g = np.array([1.0] + [r[e[0, a]] for a in range(1, n + 1)])
        conj = np.outer(g, np.conj(g))
        m_glob, a_glob = local_matrices(gram, vol, om, r)
        np.testing.assert_allclose(m_glob, conj * m_loc, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(a_glob, conj * a_loc, rtol=1e-13, atol=1e-14 * np.abs(a_loc).max())
        # a further gauge transformation h: r' = conj(h_b) r h_a, z' = conj(h) z, M' = diag(conj h) M diag(h)
        h = np.exp(1j * rng.uniform(0, 2 * np.pi, n + 1))
        ev = local_edges(n)
        r2 = np.conj(h[ev[:, 1]]) * r * h[ev[:, 0]]
        m3, a3 = local_matrices(gram, vol, om, r2)
        tr = np.outer(np.conj(h), h)
        np.testing.assert_allclose(m3, tr * m_glob, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(a3, tr * a_glob, rtol=1e-13, atol=1e-14 * np.abs(a_glob).max())


def test_relabeling_covariance():
    """Renumbering the vertices of a simplex permutes the matrices (Ω and r follow the orientation)."""
    rng = np.random.default_rng(8)
    n = 3
    _p, gram, vol = simplex(rng, n)
    edges = [tuple(e) for e in local_edges(n)]
    alpha = dict(zip(edges, rng.normal(size=len(edges))))
    alpha_full = lambda a, b: alpha[a, b] if a < b else -alpha[b, a]  # noqa: E731
    m0, a0 = local_matrices(gram, vol, [alpha_full(b, c) - alpha_full(a, c) + alpha_full(a, b)
                                        for a, b, c in local_triangles(n)],
                            np.exp(1j * np.array([alpha[e] for e in edges])))
    for perm in list(permutations(range(n + 1)))[1::5]:
        q = np.array(perm)                 # new vertex s is old vertex q[s]
        gram_q = gram[np.ix_(q, q)]
        om_q = [alpha_full(q[b], q[c]) - alpha_full(q[a], q[c]) + alpha_full(q[a], q[b])
                for a, b, c in local_triangles(n)]
        r_q = np.exp(1j * np.array([alpha_full(q[a], q[b]) for a, b in edges]))
        m1, a1 = local_matrices(gram_q, vol, om_q, r_q)
        np.testing.assert_allclose(m1, m0[np.ix_(q, q)], rtol=1e-13, atol=1e-16)
        np.testing.assert_allclose(a1, a0[np.ix_(q, q)], rtol=1e-12, atol=1e-13 * np.abs(a0).max())


def test_batched_equals_single_and_broadcasting():
    rng = np.random.default_rng(9)
    n, m = 3, 6
    data = [simplex(rng, n) for _ in range(m)]
    gram = np.stack([d[1] for d in data])
    vol = np.array([d[2] for d in data])
    om, r = zip(*[closed_data(rng, n, s) for s in (0.0, 1e-7, 0.3, 2.0, 8.0, 100.0)])
    om, r = np.array(om), np.array(r)
    mass, dirichlet = local_matrices(gram, vol, om, r)
    assert mass.shape == dirichlet.shape == (m, n + 1, n + 1)
    np.testing.assert_allclose(local_mass_matrices(vol, om, r), mass, rtol=1e-15)
    np.testing.assert_allclose(local_dirichlet_matrices(gram, vol, om, r), dirichlet, rtol=1e-15)
    for s in range(m):
        ms, ds = local_matrices(gram[s], vol[s], om[s], r[s])
        np.testing.assert_allclose(ms, mass[s], rtol=1e-14, atol=1e-17)
        np.testing.assert_allclose(ds, dirichlet[s], rtol=1e-14, atol=1e-14 * np.abs(ds).max())
    # one curvature for many simplices broadcasts
    one = local_mass_matrices(vol, om[3])
    assert one.shape == (m, n + 1, n + 1)
    np.testing.assert_allclose(one[2] / vol[2], one[4] / vol[4], rtol=1e-14)


def test_empty_stack():
    out = local_mass_matrices(np.zeros(0), np.zeros((0, 1)))
    assert out.shape == (0, 3, 3)


def test_n1_is_p1_on_segments():
    mass, dirichlet = local_matrices(np.array([[4.0, -4.0], [-4.0, 4.0]]), 0.5, np.zeros(0), [np.exp(0.3j)])
    np.testing.assert_allclose(mass, 0.5 / 6 * np.array([[2, np.exp(-0.3j)], [np.exp(0.3j), 2]]), rtol=1e-15)
    np.testing.assert_allclose(dirichlet, 2 * np.array([[1, -np.exp(-0.3j)], [-np.exp(0.3j), 1]]), rtol=1e-15)


def test_curvature_helpers():
    assert local_triangles(3).tolist() == [list(c) for c in combinations(range(4), 3)]
    t = curvature_tensor(np.array([[1.0, 2.0, 3.0, 2.0]]))
    assert t.shape == (1, 4, 4, 4)
    for a, b, c in product(range(4), repeat=3):
        assert t[0, a, b, c] == -t[0, b, a, c] == -t[0, a, c, b]
    rg = local_gauge_connection([[0.5], [1.0]])
    assert rg.shape == (2, 3)
    np.testing.assert_allclose(rg[:, 2], np.exp(1j * np.array([0.5, 1.0])))
