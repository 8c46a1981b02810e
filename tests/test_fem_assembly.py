"""Global mass and Dirichlet matrices (Theorems 15, 17): reductions, hermiticity, PSD, covariance."""

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import EuclideanComplex, HermitianLineBundle, SimplicialComplex, line_bundle_with_curvature
from dhlb.errors import NonFiniteError, ShapeError
from dhlb.examples import cube_nd, sphere
from dhlb.fem import bundle_matrices, dirichlet_matrix, lumped_mass, mass_matrix
from tests.fem_fixtures import jittered_grid, random_bundle

igl = pytest.importorskip("igl")


@pytest.mark.parametrize("n, m", [(2, 6), (3, 3)])
def test_trivial_bundle_is_the_cotangent_laplacian_and_p1_mass(n, m):
    """Independent implementation: libigl's cotmatrix / full massmatrix."""
    X, P = jittered_grid(n, m, seed=n)
    geo = EuclideanComplex(X, points=P)
    A, M = bundle_matrices(HermitianLineBundle.trivial(X), geo)
    F = X.simplices(n)
    L_igl = igl.cotmatrix(P, F)
    M_igl = igl.massmatrix(P, F, igl.MASSMATRIX_TYPE_FULL)
    assert abs(A + L_igl).max() < 1e-12 * abs(L_igl).max()
    assert abs(M - M_igl).max() < 1e-12 * abs(M_igl).max()
    assert abs(A.imag).max() == 0 and abs(M.imag).max() == 0
    assert np.allclose(mass_matrix(HermitianLineBundle.trivial(X), geo, lumped=True).diagonal(), lumped_mass(geo))


def _check_hermitian_psd(A, M):
    Ad, Md = A.toarray(), M.toarray()
    scale = np.abs(Ad).max()
    assert np.abs(Ad - Ad.conj().T).max() <= 1e-13 * scale
    assert np.abs(Md - Md.conj().T).max() <= 1e-13 * np.abs(Md).max()
    assert np.linalg.eigvalsh(Ad).min() >= -1e-11 * scale
    assert np.linalg.eigvalsh(Md).min() > 0


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10**6), st.sampled_from([(2, 4), (3, 2)]), st.floats(0.1, 12.0))
def test_hermitian_psd_for_random_bundles(seed, shape, scale):
    rng = np.random.default_rng(seed)
    n, m = shape
    X, P = jittered_grid(n, m, seed=seed)
    L = random_bundle(X, rng, scale=scale)
    A, M = bundle_matrices(L, EuclideanComplex(X, points=P))
    _check_hermitian_psd(A, M)
    # the two single-purpose assemblers agree with the shared one
    geo = EuclideanComplex(X, points=P)
    assert abs(A - dirichlet_matrix(L, geo)).max() <= 1e-13 * abs(A).max()
    assert abs(M - mass_matrix(L, geo)).max() <= 1e-13 * abs(M).max()


def test_closed_surface_with_degree_is_psd_and_has_no_kernel():
    X = sphere(2).barycentric_subdivision()[0]
    P = np.random.default_rng(1).standard_normal((X.n_vertices, 3))
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    o = X.orientation()
    L = line_bundle_with_curvature(X, o * 2 * np.pi * 3 / X.n_simplices(2))
    A, M = bundle_matrices(L, EuclideanComplex(X, points=P))
    _check_hermitian_psd(A, M)
    # a nontrivial bundle has no parallel (constant-norm) section: A is positive definite
    assert np.linalg.eigvalsh(A.toarray()).min() > 1e-6


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10**6), st.sampled_from([2, 3]))
def test_gauge_covariance(seed, n):
    """New frames X'_i = g_i X_i: z = G z', so A' = Gᴴ A G and M' = Gᴴ M G."""
    rng = np.random.default_rng(seed)
    X, P = jittered_grid(n, 3 if n == 2 else 2, seed=seed)
    geo = EuclideanComplex(X, points=P)
    L = random_bundle(X, rng)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    A, M = bundle_matrices(L, geo)
    A2, M2 = bundle_matrices(L.gauge(g), geo)
    G = sp.diags(g)
    assert abs(A2 - G.conj() @ A @ G).max() <= 1e-12 * abs(A).max()
    assert abs(M2 - G.conj() @ M @ G).max() <= 1e-12 * abs(M).max()


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10**6), st.sampled_from([2, 3]))
def test_relabeling_invariance(seed, n):
    """Permuting vertex labels permutes the matrices (same frames, same connection per oriented edge)."""
    rng = np.random.default_rng(seed)
    X, P = jittered_grid(n, 3 if n == 2 else 2, seed=seed)
    L = random_bundle(X, rng)
    A, M = bundle_matrices(L, EuclideanComplex(X, points=P))
    perm = rng.permutation(X.n_vertices)  # old vertex v gets label perm[v]
    Y = SimplicialComplex(perm[X.simplices(X.dim)])
    inv = np.argsort(perm)
    QP = P[inv]
    # connection angle per oriented edge (a -> b) in new labels
    E_old = X.simplices(1)
    E_new = perm[E_old]
    sign = np.where(E_new[:, 0] < E_new[:, 1], 1.0, -1.0)
    idx = Y.index(1, E_new)
    ang = np.empty(Y.n_simplices(1))
    ang[idx] = sign * L.connection_angles
    T_old = X.simplices(2)
    T_new = perm[T_old]
    om = np.empty(Y.n_simplices(2))
    om[Y.index(2, T_new)] = Y.orientation_of(T_new) * L.curvature
    L2 = HermitianLineBundle.from_angles(Y, ang, om)
    A2, M2 = bundle_matrices(L2, EuclideanComplex(Y, points=QP))
    Pm = sp.csr_matrix((np.ones(X.n_vertices), (perm, np.arange(X.n_vertices))))
    assert abs(A2 - Pm @ A @ Pm.T).max() <= 1e-12 * abs(A).max()
    assert abs(M2 - Pm @ M @ Pm.T).max() <= 1e-12 * abs(M).max()


def test_weighted_and_lumped_mass():
    X, P = cube_nd(2, 4, return_points=True)
    geo = EuclideanComplex(X, points=P)
    L = HermitianLineBundle.trivial(X)
    one = np.ones(X.n_vertices)
    w = np.arange(X.n_simplices(2), dtype=float)
    Mw = mass_matrix(L, geo, weights=w)
    assert np.isclose((one @ Mw @ one).real, w @ geo.volumes(2))  # ∫ w
    Ml = mass_matrix(L, geo, lumped=True, weights=w)
    assert np.isclose(Ml.diagonal().sum().real, w @ geo.volumes(2))
    with pytest.raises(ShapeError, match="one value per top simplex"):
        mass_matrix(L, geo, weights=w[:-1])
    bad = w.copy()
    bad[3] = np.nan
    with pytest.raises(NonFiniteError, match=r"weights\[3\]"):
        mass_matrix(L, geo, weights=bad)


def test_mismatched_complexes_are_refused():
    X, _P = cube_nd(2, 2, return_points=True)
    Y, Q = cube_nd(2, 3, return_points=True)
    with pytest.raises(ShapeError, match="different complexes"):
        mass_matrix(HermitianLineBundle.trivial(X), EuclideanComplex(Y, points=Q))


def test_one_dimensional_complexes():
    """n = 1: P1 on an interval, and a twisted ring whose lowest eigenvalue is (θ/2π)²."""
    from dhlb.fem import smallest_eigenpairs

    X = SimplicialComplex([(0, 1), (1, 2)])
    geo = EuclideanComplex(X, points=np.array([[0.0], [1.0], [3.0]]))
    A, M = bundle_matrices(HermitianLineBundle.trivial(X), geo)
    assert np.allclose(A.toarray(), [[1, -1, 0], [-1, 1.5, -0.5], [0, -0.5, 0.5]])
    assert np.allclose(M.toarray(), np.array([[2, 1, 0], [1, 6, 2], [0, 2, 4]]) / 6)
    N, theta = 200, np.pi / 2
    ring = SimplicialComplex([(i, (i + 1) % N) for i in range(N)])
    geo = EuclideanComplex(ring, edge_lengths=np.full(ring.n_simplices(1), 2 * np.pi / N))
    ang = np.zeros(ring.n_simplices(1))
    ang[0] = theta  # all holonomy on one edge (a gauge choice)
    L = HermitianLineBundle.from_angles(ring, ang, np.zeros(0))
    A, M = bundle_matrices(L, geo)
    lam = smallest_eigenpairs(A, M, k=1).eigenvalues[0]
    assert abs(lam - (theta / (2 * np.pi)) ** 2) < 1e-4


def test_matrices_own_their_sorted_pattern():
    """A and M get their own writable index arrays (not the cached read-only adjacency), sorted by column."""
    X, P = cube_nd(2, 3, return_points=True)
    A, M = bundle_matrices(HermitianLineBundle.trivial(X), EuclideanComplex(X, points=P))
    adj = X.vertex_adjacency
    for K in (A, M):
        assert K.indices.flags.writeable and K.indptr.flags.writeable
        other = M if K is A else A
        assert not np.shares_memory(K.indices, adj.indices) and not np.shares_memory(K.indices, other.indices)
        assert np.array_equal(K.indices, adj.indices) and np.array_equal(K.indptr, adj.indptr)
        assert np.all(np.diff(K.indices)[np.diff(np.repeat(np.arange(K.shape[0]), np.diff(K.indptr))) == 0] > 0)
    A.data[:] = 0.0
    A.eliminate_zeros()                      # in-place structural change leaves M intact
    assert A.nnz == 0 and M.nnz == adj.indices.size
