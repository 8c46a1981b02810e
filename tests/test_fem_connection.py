"""The cotangent connection Laplacian of vector bundles (dhlb.fem.connection)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import HermitianLineBundle, SimplicialComplex
from dhlb.bundles import VectorBundle
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.examples import cube_nd
from dhlb.fem import connection_laplacian, connection_mass, cotan_edge_weights, dirichlet_matrix, lumped_mass
from dhlb.geometry import EuclideanComplex
from tests.fem_fixtures import jittered_grid


def geometry(n, m, seed):
    X, P = jittered_grid(n, m, seed=seed) if n >= 2 else cube_nd(1, m, return_points=True)
    return X, EuclideanComplex(X, points=P)


def random_orthogonal(rng, e, k, field):
    Z = rng.normal(size=(e, k, k)) + (1j * rng.normal(size=(e, k, k)) if field == "C" else 0)
    Q, _R = np.linalg.qr(Z)
    return Q


def direct_energy(bundle_T, X, w, v):
    """Σ_e w_e |v_j − η_e v_i|² edge by edge (the definition)."""
    E = X.simplices(1)
    r = v[E[:, 1]] - np.einsum("eab,eb->ea", bundle_T, v[E[:, 0]])
    return float(np.sum(w * np.sum(np.abs(r) ** 2, axis=1)))


# ---------------------------------------------------------------------- exact reference
@pytest.mark.parametrize("n,m", [(1, 5), (2, 4), (3, 2)])
def test_trivial_rank_one_bundle_is_exactly_the_stiffness_matrix(n, m):
    X, geo = geometry(n, m, seed=n)
    A = connection_laplacian(VectorBundle.trivial(X, 1), geo)
    K = geo.stiffness_matrix()
    assert A.dtype == np.float64
    A.sort_indices()
    K.sort_indices()
    assert np.array_equal(A.indptr, K.indptr) and np.array_equal(A.indices, K.indices)
    assert np.array_equal(A.data, K.data)  # bit for bit
    A3 = connection_laplacian(VectorBundle.trivial(X, 3, metric=True), geo)  # rank 3: K ⊗ I
    K3 = sp.kron(K, sp.identity(3), format="csr")
    C = A3.tocoo()
    assert np.sum(C.row // 3 == C.col // 3) == 3 * X.n_vertices  # diagonal blocks: no stored zeros
    assert abs(A3 - K3).max() <= 4 * np.finfo(float).eps * abs(K).max()  # the same sums, another order


def test_cotan_weights_of_a_triangle_are_half_cotangents():
    rng = np.random.default_rng(1)
    P = rng.normal(size=(3, 2))
    geo = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), points=P)
    w = cotan_edge_weights(geo)
    for e, (i, j) in enumerate([(0, 1), (0, 2), (1, 2)]):
        o = 3 - i - j
        a, b = P[i] - P[o], P[j] - P[o]
        assert np.isclose(w[e], 0.5 * np.dot(a, b) / abs(a[0] * b[1] - a[1] * b[0]), rtol=1e-13)


# ---------------------------------------------------------------------- the energy
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([1, 2, 3]), k=st.integers(1, 3),
       field=st.sampled_from(["R", "C"]), kind=st.sampled_from(["orthogonal", "general"]))
def test_quadratic_form_is_the_edge_energy(seed, n, k, field, kind):
    rng = np.random.default_rng(seed)
    X, geo = geometry(n, 2 if n == 3 else 3, seed % 7)
    e = X.n_simplices(1)
    if kind == "orthogonal":
        T = random_orthogonal(rng, e, k, field)
    else:
        T = rng.normal(size=(e, k, k)) + (1j * rng.normal(size=(e, k, k)) if field == "C" else 0) + 2 * np.eye(k)
    bundle = VectorBundle(X, T, field, metric=kind == "orthogonal")
    sw = rng.uniform(0, 2, X.n_simplices(X.dim)) * (rng.random(X.n_simplices(X.dim)) < 0.8)
    A = connection_laplacian(bundle, geo, simplex_weights=sw)
    assert A.shape == (k * X.n_vertices,) * 2
    assert A.dtype == (np.float64 if field == "R" else np.complex128)
    assert abs(A - A.conj().T).max() <= 1e-14 * abs(A).max()
    w = cotan_edge_weights(geo, simplex_weights=sw)
    v = rng.normal(size=(X.n_vertices, k)) + (1j * rng.normal(size=(X.n_vertices, k)) if field == "C" else 0)
    x = v.reshape(-1)  # interleaved: x[i k + a] = v_i[a]
    got = complex(x.conj() @ (A @ x))
    want = direct_energy(bundle.transports, X, w, v)
    assert abs(got.imag) <= 1e-12 * max(1.0, want)
    assert np.isclose(got.real, want, rtol=1e-11, atol=1e-12)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_rotation_bundle_is_the_realification_of_the_line_bundle(seed):
    rng = np.random.default_rng(seed)
    X, geo = geometry(2, 4, seed % 5)
    om = rng.uniform(-3, 3, X.n_simplices(1))
    L = HermitianLineBundle(X, np.exp(1j * om), X.coboundary(1) @ om)
    c, s = np.cos(om), np.sin(om)
    R = VectorBundle(X, np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], axis=1), metric=True)
    Ac = connection_laplacian(L, geo)
    Ar = connection_laplacian(R, geo)
    real = sp.kron(Ac.real, np.eye(2)) + sp.kron(Ac.imag, np.array([[0.0, -1.0], [1.0, 0.0]]))
    assert abs(Ar - real).max() <= 1e-14 * abs(Ar).max()
    assert abs(Ac - connection_laplacian(L.vector_bundle(), geo)).max() == 0


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([2, 3]))
def test_flat_bundles_are_gauge_equivalent_to_the_stiffness_matrix(seed, n):
    rng = np.random.default_rng(seed)
    X, geo = geometry(n, 2 if n == 3 else 4, seed % 5)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    E = X.simplices(1)
    r = g[E[:, 1]] * np.conj(g[E[:, 0]])  # parallel sections z_j = r_ij z_i: z = c g
    L = HermitianLineBundle(X, r, np.zeros(X.n_simplices(2)))
    A = connection_laplacian(L, geo)
    D = sp.diags(g)
    assert abs(A - D @ geo.stiffness_matrix() @ D.conj()).max() <= 1e-13
    assert abs(A @ g).max() <= 1e-12  # the parallel section has zero energy
    assert abs(A - dirichlet_matrix(L, geo)).max() <= 1e-12  # Ω = 0: the FEM matrix agrees


def test_simplex_weights_are_linear_and_zero_removes_simplices():
    X, geo = geometry(2, 3, 0)
    rng = np.random.default_rng(0)
    T = random_orthogonal(rng, X.n_simplices(1), 2, "R")
    B = VectorBundle(X, T, metric=True)
    m = X.n_simplices(2)
    s1, s2 = rng.uniform(0, 1, m), rng.uniform(0, 1, m)
    A1, A2 = connection_laplacian(B, geo, simplex_weights=s1), connection_laplacian(B, geo, simplex_weights=s2)
    assert abs(connection_laplacian(B, geo, simplex_weights=s1 + s2) - A1 - A2).max() <= 1e-14
    assert abs(connection_laplacian(B, geo, simplex_weights=0.0)).max() == 0
    assert abs(connection_laplacian(B, geo, simplex_weights=2.0) - 2 * connection_laplacian(B, geo)).max() <= 1e-14


@pytest.mark.parametrize("k,field", [(1, "C"), (2, "R"), (3, "C")])
def test_an_array_of_transports_is_the_bundle(k, field):
    X, geo = geometry(2, 3, 1)
    rng = np.random.default_rng(k)
    T = random_orthogonal(rng, X.n_simplices(1), k, field)
    sw = rng.uniform(0, 2, X.n_simplices(2))
    A = connection_laplacian(VectorBundle(X, T, field, metric=True), geo, simplex_weights=sw)
    B = connection_laplacian(T if k > 1 else T[:, 0, 0], geo, simplex_weights=sw)
    assert B.dtype == A.dtype and abs(A - B).max() == 0
    G = T + 0.5 * np.eye(k)                                  # not orthogonal: the general assembly, the same matrix
    assert abs(connection_laplacian(G, geo) - connection_laplacian(VectorBundle(X, G, field), geo)).max() == 0
    with pytest.raises(ShapeError, match="transports"):
        connection_laplacian(T[:-1], geo)
    bad = T.copy()
    bad[4, 0, 0] = np.nan
    with pytest.raises(NonFiniteError, match="row 4"):
        connection_laplacian(bad, geo)
    with pytest.raises(TypeError, match="EuclideanComplex"):
        connection_laplacian(T, X)


def test_connection_mass():
    X, geo = geometry(2, 3, 0)
    M = connection_mass(geo, 2)
    assert np.array_equal(M.diagonal(), np.repeat(lumped_mass(geo), 2)) and M.nnz == 2 * X.n_vertices
    Mc = connection_mass(geo, 3, lumped=False)
    assert abs(Mc - sp.kron(geo.mass_matrix(), sp.identity(3))).max() == 0
    assert abs(connection_mass(geo) - geo.mass_matrix(lumped=True)).max() == 0
    with pytest.raises(InvalidParameterError):
        connection_mass(geo, 0)


# ---------------------------------------------------------------------- bad input
def test_bad_input():
    X, geo = geometry(2, 2, 0)
    _Y, geo_y = geometry(2, 3, 0)
    B = VectorBundle.trivial(X, 2)
    with pytest.raises(ShapeError, match="different complexes"):
        connection_laplacian(B, geo_y)
    with pytest.raises(ShapeError, match="one number per top simplex"):
        connection_laplacian(B, geo, simplex_weights=np.ones(3))
    sw = np.ones(X.n_simplices(2))
    sw[4] = np.nan
    with pytest.raises(NonFiniteError, match=r"simplex_weights\[4\]"):
        connection_laplacian(B, geo, simplex_weights=sw)
    sw[4] = -1
    with pytest.raises(InvalidParameterError, match="negative"):
        connection_laplacian(B, geo, simplex_weights=sw)
    with pytest.raises(InvalidParameterError, match="over R or C"):
        connection_laplacian(VectorBundle.trivial(X, 1, ("GF", 5)), geo)
    with pytest.raises(TypeError):
        connection_laplacian(B, "not a geometry")
    with pytest.raises(TypeError):
        connection_laplacian(object(), geo)
