"""Θ, Λ, Ξ and the local FEM matrices of dhlb.fem.integrals (seed part 3, §11-§12).

References: 60-digit mpmath (divided differences as exp of the Opitz matrix), Gauss quadrature of
the piecewise-linear section written in a single radially parallel frame, exact P1 values.
"""

from itertools import combinations, permutations, product
from math import comb, factorial

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import errors
from dhlb.fem.integrals import (
    curvature_tensor,
    expi_divided_difference,
    expi_moment,
    lambda_,
    local_dirichlet_matrices,
    local_edges,
    local_gauge_connection,
    local_mass_matrices,
    local_matrices,
    local_triangles,
    theta,
    xi,
)

RTOL = 1e-12


# ------------------------------------------------------------------------------------------------
# references and builders
# ------------------------------------------------------------------------------------------------

def mp_divided_difference(nodes, dps=60):
    """exp[nodes] as the (0, N) entry of exp of the Opitz matrix, in mpmath."""
    with mp.workdps(dps):
        k = len(nodes)
        t = mp.matrix(k, k)
        for i, z in enumerate(nodes):
            t[i, i] = mp.mpc(z.real, z.imag)
            if i + 1 < k:
                t[i, i + 1] = 1
        return complex(mp.expm(t)[0, k - 1])


def mp_pair_moment(omega_tensor, a, b, p):
    """(1/vol) ∫ x^p exp(-i Σ_m Ω_abm x_m) by Hermite-Genocchi in mpmath (one simplex)."""
    n = len(p) - 1
    nodes = []
    for m in range(n + 1):
        nodes += [-1j * omega_tensor[a, b, m]] * (p[m] + 1)
    return factorial(n) * np.prod([factorial(k) for k in p]) * mp_divided_difference(nodes)


def simplex(rng, n, cond=1e3):
    """Random n-simplex in R^n: (points, gram of barycentric gradients, volume)."""
    while True:
        p = rng.normal(size=(n + 1, n))
        e = p[1:] - p[0]
        g = e @ e.T
        if np.linalg.cond(g) < cond:
            d = np.hstack([-np.ones((n, 1)), np.eye(n)])
            return p, d.T @ np.linalg.solve(g, d), np.sqrt(np.linalg.det(g)) / factorial(n)


def closed_data(rng, n, scale):
    """Exact (closed) curvature Ω = dα on the local triangles and the consistent connection exp(iα)."""
    edges = [tuple(e) for e in local_edges(n)]
    alpha = dict(zip(edges, rng.normal(size=len(edges)) * scale))
    om = np.array([alpha[b, c] - alpha[a, c] + alpha[a, b] for a, b, c in local_triangles(n)])
    return om, np.exp(1j * np.array([alpha[e] for e in edges]))


def simplex_rule(n, order):
    g, w = np.polynomial.legendre.leggauss(order)
    g, w = 0.5 * (g + 1), 0.5 * w
    u = np.stack([a.ravel() for a in np.meshgrid(*([g] * n), indexing="ij")], axis=1)
    wt = np.prod(np.stack([a.ravel() for a in np.meshgrid(*([w] * n), indexing="ij")], axis=1), axis=1)
    x = np.zeros((u.shape[0], n + 1))
    rem = np.ones(u.shape[0])
    for k in range(n):
        x[:, k + 1] = rem * u[:, k]
        wt = wt * (1 - u[:, k]) ** (n - 1 - k)
        rem = rem * (1 - u[:, k])
    x[:, 0] = rem
    return x, wt * factorial(n)


def quadrature_matrices(gram, vol, om, r, order):
    """∫|ψ̃|², ∫|∇ψ̃|² with ψ̃ = F φ_0 (single frame), by Gauss quadrature."""
    n = gram.shape[0] - 1
    x, wt = simplex_rule(n, order)
    t = curvature_tensor(om, dim=n)
    e = {tuple(v): q for q, v in enumerate(local_edges(n))}
    rr = lambda a, b: 1.0 if a == b else (r[e[a, b]] if a < b else np.conj(r[e[b, a]]))  # noqa: E731
    vals, grads = [], []
    for a in range(n + 1):
        ph = np.exp(-1j * x @ t[a, 0])
        f = x[:, a] * rr(a, 0) * ph
        df = np.outer(f, -1j * t[a, 0])
        df[:, a] += rr(a, 0) * ph
        grads.append(df + 1j * f[:, None] * (x @ t[0].T))
        vals.append(f)
    mass = np.array([[vol * np.sum(wt * np.conj(vals[b]) * vals[a]) for a in range(n + 1)] for b in range(n + 1)])
    dirichlet = np.array([[vol * np.sum(wt * np.einsum("pk,kl,pl->p", np.conj(grads[b]), gram, grads[a]))
                           for a in range(n + 1)] for b in range(n + 1)])
    return mass, dirichlet


# ------------------------------------------------------------------------------------------------
# divided differences and moments against mpmath
# ------------------------------------------------------------------------------------------------

def test_divided_difference_against_mpmath_all_regimes():
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(150):
        c = int(rng.integers(1, 4))
        mult = rng.integers(1, 5, c)
        th = rng.choice([-1, 1], c) * 10.0 ** rng.uniform(-9, 3.5, c)
        if rng.random() < 0.3:
            th[0] = 0.0
        for q in range(1, c):
            if rng.random() < 0.4:   # nearly coinciding or far-but-clustered nodes
                th[q] = th[rng.integers(q)] + rng.choice([-1, 1]) * 10.0 ** rng.uniform(-9, 1.2)
        ref = mp_divided_difference(list(1j * np.repeat(th, mult)))
        worst = max(worst, abs(expi_divided_difference(th, mult) - ref) / abs(ref))
    assert worst < RTOL


def test_divided_difference_exact_values():
    assert expi_divided_difference(np.zeros(3), [2, 3, 1]) == 1 / factorial(5)
    t = 3.7
    assert np.isclose(expi_divided_difference([0.0, t], [1, 1]), (np.exp(1j * t) - 1) / (1j * t), rtol=1e-15, atol=0)
    # confluent: exp[z^(m)] = e^z / (m-1)!
    assert np.isclose(expi_divided_difference([5.0], [4]), np.exp(5j) / 6, rtol=1e-15, atol=0)
    # batched shape
    assert expi_divided_difference(np.zeros((2, 5, 2)), [1, 1]).shape == (2, 5)


def test_divided_difference_modulus_bound():
    """|exp[iθ...]| <= 1/N! (Hermite-Genocchi with |e^{iθ·x}| = 1)."""
    rng = np.random.default_rng(1)
    th = rng.normal(size=(500, 3)) * 20
    v = expi_divided_difference(th, [3, 2, 2])
    assert np.all(np.abs(v) <= 1 / factorial(6) * (1 + 1e-12))


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_expi_moment_against_mpmath(n):
    rng = np.random.default_rng(n)
    for _ in range(10):
        th = rng.choice([-1, 1], n + 1) * 10.0 ** rng.uniform(-8, 3, n + 1)
        p = rng.integers(0, 3, n + 1)
        nodes = [1j * th[m] for m in range(n + 1) for _ in range(p[m] + 1)]
        ref = factorial(n) * np.prod([factorial(int(k)) for k in p]) * mp_divided_difference(nodes)
        assert abs(expi_moment(th, p) - ref) <= RTOL * abs(ref)


@pytest.mark.parametrize("n", [2, 3])
def test_theta_lambda_xi_against_mpmath_tiny_and_huge_curvature(n):
    rng = np.random.default_rng(10 + n)
    for scale in (1e-9, 1e-3, 0.5, 3.0, 40.0, 1e3):
        om, _ = closed_data(rng, n, scale)
        t = curvature_tensor(om)
        for i, j in [(0, 1), (1, 0), (0, n), (n - 1, n), (1, 1)]:
            ref = mp_pair_moment(t, i, j, [0] * (n + 1))
            assert abs(lambda_(om, i, j) - ref) <= RTOL * abs(ref)
            for k, l in [(i, j), (i, i), (j, n), (0, n - 1)]:
                p = [0] * (n + 1)
                p[k] += 1
                p[l] += 1
                ref = mp_pair_moment(t, i, j, p)
                assert abs(theta(om, i, j, k, l) - ref) <= RTOL * abs(ref)
                for v in (i, j):
                    p[v] += 1
                ref = mp_pair_moment(t, i, j, p)
                assert abs(xi(om, i, j, k, l) - ref) <= RTOL * abs(ref)


def test_theta_vectorized_matches_single():
    rng = np.random.default_rng(3)
    om = np.stack([closed_data(rng, 3, s)[0] for s in (0.01, 1.0, 7.0, 300.0)])
    batch = theta(om, 0, 2, 1, 3)
    assert batch.shape == (4,)
    for s in range(4):
        assert theta(om[s], 0, 2, 1, 3) == pytest.approx(batch[s], rel=1e-15)


def test_theta_hermitian_in_pair_and_flat_values():
    om = np.array([0.3, -1.2, 0.4, 0.0])
    om[3] = om[2] - om[1] + om[0]
    assert theta(om, 2, 1, 0, 3) == pytest.approx(np.conj(theta(om, 1, 2, 0, 3)), rel=1e-14)
    assert xi(om, 3, 0, 1, 1) == pytest.approx(np.conj(xi(om, 0, 3, 1, 1)), rel=1e-14)
    zero = np.zeros(4)
    # Dirichlet moments n! p! / (n + |p|)!
    assert theta(zero, 0, 1, 0, 1) == pytest.approx(6 / 120, rel=1e-15)
    assert theta(zero, 0, 1, 2, 2) == pytest.approx(12 / 120, rel=1e-15)
    assert lambda_(zero, 0, 1) == 1
    assert xi(zero, 0, 1, 0, 1) == pytest.approx(6 * 4 / factorial(7), rel=1e-15)


def test_single_theta_scalar_and_dim_one():
    assert np.ndim(theta([0.2], 0, 1, 0, 1)) == 0
    assert lambda_(np.zeros(0), 0, 1, dim=1) == 1
    assert theta(np.zeros(0), 0, 1, 0, 1) == pytest.approx(1 / 6, rel=1e-15)   # n = 1: 1!/3!


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


# ------------------------------------------------------------------------------------------------
# errors
# ------------------------------------------------------------------------------------------------

G2 = np.array([[2.0, -1.0, -1.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])


@pytest.mark.parametrize("call,exc,text", [
    (lambda: local_mass_matrices(1.0, [0.1, 0.2]), errors.ShapeError, "C(n+1, 3)"),
    (lambda: local_mass_matrices(1.0, [np.nan]), errors.NonFiniteError, "simplex 0"),
    (lambda: local_mass_matrices(1.0, [1j]), errors.CurvatureMismatchError, "real"),
    (lambda: local_mass_matrices(-1.0, [0.0]), errors.DegenerateSimplexError, "simplex 0"),
    (lambda: local_mass_matrices([1.0, 0.0], [[0.0], [0.0]]), errors.DegenerateSimplexError, "simplex 1"),
    (lambda: local_mass_matrices([1.0, 2.0, 3.0], [[0.0], [0.0]]), errors.ShapeError, "inconsistent"),
    (lambda: local_mass_matrices(1.0, [0.1, 0.2, 0.3, 0.0]), errors.NotClosedError, "tetrahedron (0, 1, 2, 3)"),
    (lambda: local_mass_matrices(1.0, [0.0, 0.0, 0.0, 2 * np.pi]), errors.NotClosedError, "vortex"),
    (lambda: local_mass_matrices(1.0, [0.3], [1, 1, 1]), errors.CurvatureMismatchError, "triangle (0, 1, 2)"),
    (lambda: local_mass_matrices(1.0, [0.0], [2, 2, 1]), errors.InvalidConnectionError, "unit"),
    (lambda: local_mass_matrices(1.0, [0.0], [1, 1]), errors.ShapeError, "connection"),
    (lambda: local_dirichlet_matrices(G2[:2], 1.0, [0.0]), errors.ShapeError, "gram"),
    (lambda: local_dirichlet_matrices(G2 + np.eye(3), 1.0, [0.0]), errors.InvalidMetricError, "sum"),
    (lambda: local_dirichlet_matrices(-G2, 1.0, [0.0]), errors.InvalidMetricError, "semidefinite"),
    (lambda: local_dirichlet_matrices(G2, 1.0, [0.0, 0, 0, 0]), errors.ShapeError, "curvature"),
    (lambda: theta([0.1], 0, 1, 0, 3), errors.InvalidParameterError, "out of range"),
    (lambda: theta([0.1], 0, 1.0, 0, 1), errors.InvalidParameterError, "out of range"),
    (lambda: expi_divided_difference([0.0, 1.0], [1, 0]), errors.InvalidParameterError, "multiplicities"),
    (lambda: expi_divided_difference([0.0, np.inf], [1, 1]), errors.NonFiniteError, "finite"),
    (lambda: expi_moment([0.0, 1.0], [1, -1]), errors.InvalidParameterError, "powers"),
    (lambda: local_mass_matrices(1.0, [0.0], dim=3), errors.ShapeError, "triangles"),
    (lambda: local_edges(0), errors.InvalidParameterError, "dimension"),
])
def test_typed_errors(call, exc, text):
    with pytest.raises(exc, match=None) as info:
        call()
    assert text in str(info.value)


def test_no_warnings_on_extreme_but_valid_input(recwarn):
    om = np.array([[1e-300], [1e6], [0.0]])
    out = local_dirichlet_matrices(np.stack([G2] * 3), np.ones(3), om)
    assert np.all(np.isfinite(out))
    assert len(recwarn) == 0
