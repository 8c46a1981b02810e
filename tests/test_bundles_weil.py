"""Weil's theorem (Theorem 8), integrality, and the H¹(X; S¹) parametrization (Remark 7)."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import (
    HermitianLineBundle,
    bundles_with_curvature,
    check_integrality,
    flat_line_bundles,
    integer_cycle_basis,
    line_bundle_with_curvature,
)
from dhlb.errors import IntegralityError, NotClosedError
from dhlb.examples import klein_bottle, lens_space, projective_plane, projective_space, torus
from dhlb.forms import wrap_angle
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology.homology import cohomology, homology
from tests.strategies import closed_manifolds, closed_surfaces, connected_sum, rich_complexes, torus7


def integral_form(X, rng):
    """A random closed integral Ω: exact part + 2π·(integer cocycle) (+ 2π·anything on 2-complexes)."""
    Om = coboundary(X, 1, rng.uniform(-4, 4, X.n_simplices(1)))[0]
    Z = cohomology(X, "Z")[2]
    if Z.rank:
        Om = Om + 2 * np.pi * np.asarray(Z.cocycles[:, : Z.rank], float) @ rng.integers(-3, 4, Z.rank)
    if X.dim == 2:
        Om = Om + 2 * np.pi * rng.integers(-2, 3, X.n_simplices(2))
    return Om


GENUS3 = connected_sum(torus7(), connected_sum(torus7(), torus7()))


# ------------------------------------------------------------------ Theorem 8
@settings(max_examples=30, deadline=None)
@given(rich_complexes(), st.integers(0, 2**32 - 1))
def test_line_bundle_with_curvature_reproduces_omega(X, seed):
    if X.dim < 2:
        return
    Om = integral_form(X, np.random.default_rng(seed))
    L = line_bundle_with_curvature(X, Om)
    assert np.array_equal(L.curvature, Om)  # exactly the given form
    mis = wrap_angle(coboundary(X, 1, L.connection_angles)[0] - Om)
    assert np.max(np.abs(mis), initial=0) < 1e-9


@settings(max_examples=15, deadline=None)
@given(st.one_of(closed_surfaces(max_moves=4).map(lambda s: s[0]), st.just(GENUS3),
                 closed_manifolds(3, max_moves=2).map(lambda m: m[0])), st.integers(0, 2**32 - 1))
def test_weil_on_closed_manifolds(simplices, seed):
    X = SimplicialComplex(simplices)
    Om = integral_form(X, np.random.default_rng(seed))
    L = line_bundle_with_curvature(X, Om)
    assert np.array_equal(L.curvature, Om)


@settings(max_examples=25, deadline=None)
@given(rich_complexes(), st.integers(0, 2**32 - 1), st.floats(0.05, 3.0))
def test_non_integral_rejected_with_violating_cycle(X, seed, shift):
    if X.dim < 2:
        return
    R = cohomology(X, "R")[2].cocycles
    if R.shape[1] == 0:
        return
    Om = integral_form(X, np.random.default_rng(seed)) + shift * R[:, 0]
    with pytest.raises(IntegralityError) as info:
        line_bundle_with_curvature(X, Om)
    c, defect = info.value.cycle, info.value.defect
    assert c.dtype == np.int64 and not np.any(X.boundary(2) @ c)
    period = c @ Om
    assert abs(defect) > 1e-6
    assert np.isclose(period - 2 * np.pi * np.round(period / (2 * np.pi)), defect)


def test_not_closed_rejected_naming_tetrahedron():
    X = SimplicialComplex([(0, 1, 2, 3), (1, 2, 3, 4)])
    Om = np.zeros(X.n_simplices(2))
    Om[X.index(2, [(1, 2, 3)])] = 0.5
    with pytest.raises(NotClosedError, match="tetrahedron"):
        line_bundle_with_curvature(X, Om)
    Om[X.index(2, [(1, 2, 3)])] = 2 * np.pi  # integral on every tet boundary, but not closed
    with pytest.raises(NotClosedError):
        line_bundle_with_curvature(X, Om)
    check_integrality(X, Om)  # integrality alone holds


def test_integrality_reports_tet_boundary():
    X = SimplicialComplex([(0, 1, 2, 3)])
    Om = np.array([0.5, 0, 0, 0])
    with pytest.raises(IntegralityError) as info:
        check_integrality(X, Om)
    assert info.value.cycle.tolist() == (X.boundary(3).toarray()[:, 0]).tolist()
    assert np.isclose(info.value.defect, -0.5)


def test_surface_fast_path_basis_and_periods():
    X = torus()
    C = integer_cycle_basis(X)
    assert C.shape == (X.n_simplices(2), 1)
    assert np.array_equal(C.toarray()[:, 0], X.orientation())
    assert check_integrality(X, 2 * np.pi * 5 / X.n_simplices(2) * X.orientation()).tolist() == [5]
    assert integer_cycle_basis(projective_plane()).shape[1] == 0
    two = SimplicialComplex(torus7() + [tuple(v + 7 for v in t) for t in torus7()] + [(20, 21, 22)])
    assert integer_cycle_basis(two).shape[1] == 2
    bouquet = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 1, 4), (0, 2, 3), (1, 2, 3)])  # edge in 3 triangles
    B = integer_cycle_basis(bouquet).toarray()
    assert B.shape[1] == homology(bouquet)[2].rank and not np.any(bouquet.boundary(2) @ B)


def test_large_torus_grid_degree():
    n = 60
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    v = lambda a, b: (a % n) * n + (b % n)  # noqa: E731
    X = SimplicialComplex(np.concatenate([np.stack([v(i, j), v(i + 1, j), v(i + 1, j + 1)], 1),
                                          np.stack([v(i, j), v(i, j + 1), v(i + 1, j + 1)], 1)]))
    Om = X.orientation() * (2 * np.pi * 11 / X.n_simplices(2))
    L = line_bundle_with_curvature(X, Om)
    assert L.degree() == 11 and check_integrality(X, Om).tolist() == [11]


# ------------------------------------------------------------------ Remark 7: H¹(X; S¹)
def test_two_flat_bundles_over_rp2():
    X = projective_plane()
    A, B = flat_line_bundles(X)
    g = homology(X)[1].generators[:, 0]
    assert np.isclose(A.holonomy(g), 0) and np.isclose(abs(B.holonomy(g)), np.pi)
    assert not A.is_isomorphic(B)
    assert A.is_isomorphic(HermitianLineBundle.trivial(X))
    # every flat bundle is one of the two: a random gauge of B is recognized
    rng = np.random.default_rng(0)
    C = B.gauge(np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices)))
    P = bundles_with_curvature(X, np.zeros(X.n_simplices(2)))
    assert P.coordinates(C)[1] == (1,) and P.coordinates(A)[1] == (0,)


def test_flat_bundles_over_torus_form_a_2_torus():
    X = torus()
    P = bundles_with_curvature(X, np.zeros(X.n_simplices(2)))
    assert P.b1 == 2 and P.torsion_orders == ()
    rng = np.random.default_rng(1)
    for _ in range(5):
        theta = rng.uniform(-np.pi, np.pi, 2)
        L = P.bundle(theta)
        assert np.allclose(wrap_angle(P.coordinates(L)[0] - theta), 0, atol=1e-9)
        assert np.allclose([L.holonomy(g) for g in P.generators.T], theta)
        assert not L.is_isomorphic(P.bundle(theta + [0.1, 0]))
    assert len(flat_line_bundles(X, [0.3, -1.0])) == 1


def test_klein_bottle_circle_times_z2():
    X = klein_bottle()
    P = bundles_with_curvature(X, np.zeros(X.n_simplices(2)))
    assert P.b1 == 1 and P.torsion_orders == (2,)
    bundles = flat_line_bundles(X, [0.7])
    assert len(bundles) == 2 and not bundles[0].is_isomorphic(bundles[1])
    assert [P.coordinates(L)[1] for L in bundles] == [(0,), (1,)]


@pytest.mark.parametrize("X, p", [(projective_space(3), 2), (lens_space(3, 1), 3), (lens_space(5, 2), 5)])
def test_flat_bundles_over_lens_spaces(X, p):
    bundles = flat_line_bundles(X)
    assert len(bundles) == p
    for A, B in itertools.combinations(bundles, 2):
        assert not A.is_isomorphic(B)
    g = homology(X)[1].generators[:, 0]
    hol = sorted(np.round(wrap_angle([L.holonomy(g) for L in bundles]) * p / (2 * np.pi)).astype(int) % p)
    assert hol == list(range(p))  # holonomies: the p-th roots of unity


def test_nonflat_family_on_torus_degree_two():
    X = SimplicialComplex(torus7())
    Om = X.orientation() * (4 * np.pi / X.n_simplices(2))
    P = bundles_with_curvature(X, Om)
    rng = np.random.default_rng(3)
    theta = rng.uniform(-np.pi, np.pi, 2)
    L = line_bundle_with_curvature(X, Om, holonomy=(theta, ()))
    assert L.degree() == 2 and np.array_equal(L.curvature, Om)
    assert np.allclose(wrap_angle(P.coordinates(L)[0] - theta), 0, atol=1e-9)
    assert L.is_isomorphic(P.bundle(theta)) and not L.is_isomorphic(P.bundle(-theta + 0.5))


def test_a_complex_without_triangles_has_no_2_cycles():
    # issue 27's audit: integer_cycle_basis raised IndexError below dimension 2
    from dhlb.topology import SimplicialComplex

    for X in (SimplicialComplex([(0, 1), (1, 2), (2, 0)]), SimplicialComplex([(0,), (1,)])):
        assert integer_cycle_basis(X).shape == (0, 0)
