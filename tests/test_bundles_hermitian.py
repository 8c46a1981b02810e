"""Hermitian line bundles with curvature: validation, degree, integrality (Theorem 7), isomorphism."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import HermitianLineBundle, check_integrality
from dhlb.errors import (
    CurvatureMismatchError,
    InvalidConnectionError,
    NonFiniteError,
    NonManifoldError,
    NonOrientableError,
    NotClosedError,
)
from dhlb.forms import wrap_angle
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology.homology import cohomology
from tests.strategies import closed_manifolds, closed_surfaces, rich_complexes, rp2, sphere, torus7

TET = SimplicialComplex(sphere(2))  # boundary of the tetrahedron, fundamental cycle [1, -1, 1, -1]


def random_bundle(X, rng, spread=2):
    """Random connection; Ω = wrapped holonomy + 2π·(random integer cocycle)."""
    w = rng.uniform(-np.pi, np.pi, X.n_simplices(1))
    hol = coboundary(X, 1, w)[0]
    if X.dim == 2:
        n = rng.integers(-spread, spread + 1, X.n_simplices(2))
    elif X.dim >= 3:
        Z = cohomology(X, "Z")[2]
        n = np.asarray(Z.cocycles[:, : Z.rank], np.int64) @ rng.integers(-spread, spread + 1, Z.rank)
    else:
        n = np.zeros(X.n_simplices(2))
    return HermitianLineBundle.from_angles(X, w, hol + 2 * np.pi * n), n


# ------------------------------------------------------------------ validation
def test_connection_errors_name_the_edge():
    with pytest.raises(InvalidConnectionError, match="length n_1 = 6"):
        HermitianLineBundle(TET, np.ones(5), np.zeros(4))
    r = np.ones(6, complex)
    r[2] = 1.1
    with pytest.raises(InvalidConnectionError, match=r"edge \(0, 3\) is not unitary"):
        HermitianLineBundle(TET, r, np.zeros(4))
    r[2] = np.nan
    with pytest.raises(NonFiniteError):
        HermitianLineBundle(TET, r, np.zeros(4))
    with pytest.raises(NonFiniteError):
        HermitianLineBundle(TET, np.ones(6), [0, np.inf, 0, 0])


def test_curvature_mismatch_names_triangle_and_value():
    r = np.ones(6, complex)
    r[5] = np.exp(0.5j)  # edge (2, 3): triangles (0,2,3) and (1,2,3) see it
    Om = np.array([0.0, 0.0, 0.5, 0.5])
    HermitianLineBundle(TET, r, Om)
    HermitianLineBundle(TET, r, Om + 2 * np.pi * np.array([0, 0, 3, -1]))  # any lift is fine
    with pytest.raises(CurvatureMismatchError, match=r"triangle \(1, 2, 3\).*mismatch = -0\.1"):
        HermitianLineBundle(TET, r, [0.0, 0.0, 0.5, 0.4])


def test_curvature_not_closed_names_tetrahedron():
    X = SimplicialComplex([(0, 1, 2, 3)])
    Om = np.zeros(4)
    Om[0] = 2 * np.pi  # holonomy fine (exp(2πi) = 1), but dΩ = ±2π on the tetrahedron
    with pytest.raises(NotClosedError, match=r"tetrahedron \(0, 1, 2, 3\)"):
        HermitianLineBundle(X, np.ones(6), Om)


# ------------------------------------------------------------------ degree and integrals
@settings(max_examples=20, deadline=None)
@given(closed_surfaces(max_moves=4), st.integers(0, 2**32 - 1))
def test_degree_is_sum_of_lifts(surf, seed):
    tris, _chi, orientable = surf
    X = SimplicialComplex(tris)
    L, n = random_bundle(X, np.random.default_rng(seed))
    if not orientable:
        with pytest.raises(NonOrientableError):
            L.degree()
        return
    o = X.orientation()
    assert L.degree() == int(o @ n)
    assert np.isclose(L.integrate_curvature(o), 2 * np.pi * L.degree())
    assert L.tensor(L).degree() == 2 * L.degree() and L.dual().degree() == -L.degree()
    assert L.power(-3).degree() == -3 * L.degree()


def test_degree_needs_closed_surface():
    L = HermitianLineBundle.trivial(SimplicialComplex([(0, 1, 2), (0, 2, 3)]))
    with pytest.raises(NonManifoldError, match="one triangle"):
        L.degree()
    with pytest.raises(NonManifoldError, match="dimension 3"):
        HermitianLineBundle.trivial(SimplicialComplex([(0, 1, 2, 3)])).degree()
    with pytest.raises(NotClosedError, match="not a cycle"):
        HermitianLineBundle.trivial(TET).integrate_curvature([1, 0, 0, 0])


@settings(max_examples=25, deadline=None)
@given(rich_complexes(), st.integers(0, 2**32 - 1))
def test_curvature_of_every_bundle_is_integral(X, seed):
    """Theorem 7 on random complexes: the periods over an integer basis of 2-cycles are in 2πZ."""
    L, _ = random_bundle(X, np.random.default_rng(seed))
    periods = L.check_integrality()
    assert periods.dtype == np.int64


@settings(max_examples=10, deadline=None)
@given(closed_manifolds(3, max_moves=2), st.integers(0, 2**32 - 1))
def test_integrality_on_3_manifolds(M, seed):
    X = SimplicialComplex(M[0])
    L, _ = random_bundle(X, np.random.default_rng(seed))
    check_integrality(X, L.curvature)


# ------------------------------------------------------------------ isomorphism and views
@settings(max_examples=15, deadline=None)
@given(closed_surfaces(max_moves=3), st.integers(0, 2**32 - 1))
def test_gauge_is_an_isomorphism(surf, seed):
    rng = np.random.default_rng(seed)
    X = SimplicialComplex(surf[0])
    L, _ = random_bundle(X, rng)
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    M = L.gauge(g)
    h = L.find_isomorphism(M)
    assert h is not None and np.allclose(L.gauge(h).connection, M.connection)
    assert np.allclose(wrap_angle(L.class_angles() - M.class_angles()), 0, atol=1e-9)
    # same curvature, different class: add a closed non-exact real 1-form (if b₁ > 0)
    eps = cohomology(X, "R")[1].cocycles
    if eps.shape[1]:
        N = HermitianLineBundle.from_angles(X, L.connection_angles + 0.3 * eps[:, 0], L.curvature)
        assert not L.is_isomorphic(N) and L.find_isomorphism(N) is None
    other = HermitianLineBundle(X, L.connection, L.curvature + 2 * np.pi * (np.arange(X.n_simplices(2)) == 0))
    assert not L.is_isomorphic(other)  # same connection, different curvature lift


def test_vector_bundle_view_monodromy_is_exp_i_omega():
    rng = np.random.default_rng(2)
    X = SimplicialComplex(torus7())
    L, _ = random_bundle(X, rng)
    E = L.vector_bundle()
    assert E.rank == 1 and E.metric and E.field == "C"
    assert np.allclose(E.triangle_monodromy()[:, 0, 0], np.exp(1j * L.curvature))
    assert np.allclose(wrap_angle(np.angle(E.monodromy_representation()[:, 0, 0]) - L.class_angles()), 0)


def test_holonomy_of_generator_loop_on_rp2():
    X = SimplicialComplex(rp2())
    from dhlb.topology.homology import homology

    z = homology(X)[1].generators[:, 0]
    with pytest.raises(NotClosedError):
        HermitianLineBundle.trivial(X).holonomy(np.eye(X.n_simplices(1), dtype=int)[0])
    assert HermitianLineBundle.trivial(X).holonomy(z) == 0.0


def test_cochain_interop():
    from dhlb.forms import Cochain

    rng = np.random.default_rng(7)
    X = SimplicialComplex(torus7())
    L, _ = random_bundle(X, rng)
    M = HermitianLineBundle(X, L.connection_form(), L.curvature_form())
    assert np.allclose(M.connection, L.connection) and np.array_equal(M.curvature, L.curvature)
    assert L.connection_form().d().allclose(L.curvature_form().to_group("S1"))
    with pytest.raises(InvalidConnectionError, match="expected a 1-form"):
        HermitianLineBundle(X, Cochain(X, 2, L.curvature, "R"), L.curvature)
