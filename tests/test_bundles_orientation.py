"""Degree with a user orientation, typed errors of index sums, float-conditioning guard."""
import numpy as np
import pytest

from dhlb import HermitianLineBundle, VectorBundle, examples, find_isomorphism, line_bundle_with_curvature
from dhlb.bundles import index_sum
from dhlb.errors import ConvergenceError, NonManifoldError, NonOrientableError


def _degree_bundle(X, d):
    o = X.orientation()
    Omega = o * (2 * np.pi * d / X.n_simplices(2))
    return line_bundle_with_curvature(X, Omega)


def test_degree_follows_the_given_orientation():
    X = examples.sphere(2)
    L = _degree_bundle(X, 3)
    o = X.orientation()
    assert L.degree() == 3
    assert L.degree(orientation=o) == 3
    assert L.degree(orientation=-o) == -3
    bad = o.copy()
    bad[0] *= -1
    with pytest.raises(NonOrientableError, match="not consistent at edge"):
        L.degree(orientation=bad)
    with pytest.raises(NonOrientableError, match="one ±1 per triangle"):
        L.degree(orientation=o[:-1])


def test_index_sum_needs_a_closed_surface_or_a_cycle():
    X = examples.cube_nd(3, 2)
    L = HermitianLineBundle.trivial(X)
    z = np.ones(X.n_vertices, complex)
    with pytest.raises(NonManifoldError, match="dimension 3"):
        index_sum(L, z)
    # over each tet boundary the index sum is 0
    d3 = X.boundary(3).toarray()
    assert all(index_sum(L, z, cycle=d3[:, t]) == 0 for t in range(X.n_simplices(3)))


def test_poincare_hopf_with_mesh_orientation():
    X = examples.torus()
    L = _degree_bundle(X, 2)
    rng = np.random.default_rng(1)
    z = rng.standard_normal(X.n_vertices) + 1j * rng.standard_normal(X.n_vertices)
    assert index_sum(L, z) == L.degree() == 2
    assert index_sum(L, z, cycle=-X.orientation()) == L.degree(orientation=-X.orientation()) == -2


def test_ill_conditioned_float_bundles_raise_instead_of_guessing():
    X = examples.torus_nd(1, 6)  # a hexagon: one loop
    huge = np.array([[1e6, 0.0], [0.0, 1e-6]])
    T = np.broadcast_to(np.eye(2), (X.n_simplices(1), 2, 2)).copy()
    T[0] = huge @ np.array([[0.0, -1.0], [1.0, 0.0]])
    E = VectorBundle(X, T)
    F = VectorBundle(X, np.broadcast_to(np.eye(2), T.shape).copy())
    with pytest.raises(ConvergenceError, match="condition number"):
        find_isomorphism(E, F)
    # well-conditioned non-isomorphic bundles still give None
    R = np.broadcast_to(np.eye(2), T.shape).copy()
    R[0] = [[0.0, -1.0], [1.0, 0.0]]
    assert find_isomorphism(VectorBundle(X, R), F) is None


def test_nullspace_of_many_generators_is_memory_light():
    X = examples.torus_nd(2, 40)
    L = HermitianLineBundle.trivial(X).vector_bundle()
    P = L.parallel_sections()
    assert P.shape[-1] == 1
