"""Rotation form, index form and the discrete Poincaré–Hopf theorem (Theorems 11, 12)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import HermitianLineBundle, index_form, index_sum, line_bundle_with_curvature, rotation_form
from dhlb.errors import NonFiniteError, SectionZeroError
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology.homology import cohomology, homology
from tests.strategies import balls, closed_manifolds, closed_surfaces, connected_sum, rp2, sphere, torus7

GENUS = {0: sphere(2), 1: torus7(), 2: connected_sum(torus7(), torus7()),
         3: connected_sum(torus7(), connected_sum(torus7(), torus7()))}


def random_section(rng, n):
    return rng.standard_normal(n) + 1j * rng.standard_normal(n)


def bundle_with_degree(X, rng, spread=3):
    """Random bundle on a 2-complex: random connection angles, Ω = dω + 2π n."""
    w = rng.uniform(-np.pi, np.pi, X.n_simplices(1))
    n = rng.integers(-spread, spread + 1, X.n_simplices(2))
    return HermitianLineBundle.from_angles(X, w, coboundary(X, 1, w)[0] + 2 * np.pi * n)


# ------------------------------------------------------------------ Poincaré–Hopf on surfaces
@settings(max_examples=25, deadline=None)
@given(st.one_of(st.sampled_from(sorted(GENUS)).map(GENUS.get),
                 closed_surfaces(max_moves=5).filter(lambda s: s[2]).map(lambda s: s[0])),
       st.integers(0, 2**32 - 1))
def test_index_sum_is_degree_on_closed_oriented_surfaces(tris, seed):
    """Theorem 12 for random bundles and random sections on surfaces of genus 0–3."""
    rng = np.random.default_rng(seed)
    X = SimplicialComplex(tris)
    L = bundle_with_degree(X, rng)
    z = random_section(rng, X.n_vertices)
    ind = index_form(L, z)
    assert ind.dtype == np.int64 and ind.shape == (X.n_simplices(2),)
    assert int(X.orientation() @ ind) == L.degree() == index_sum(L, z)
    # a gauge-equivalent description gives the same indices
    g = np.exp(1j * rng.uniform(-np.pi, np.pi, X.n_vertices))
    assert np.array_equal(index_form(L.gauge(g), np.conj(g) * z), ind)


@settings(max_examples=10, deadline=None)
@given(st.sampled_from(sorted(GENUS)), st.integers(-4, 4), st.integers(0, 2**32 - 1))
def test_weil_bundle_of_given_degree(genus, deg, seed):
    """line_bundle_with_curvature + random section: the indices add up to the prescribed degree."""
    X = SimplicialComplex(GENUS[genus])
    o = X.orientation()
    rng = np.random.default_rng(seed)
    weights = rng.uniform(0.5, 1.5, X.n_simplices(2))
    Om = o * weights * (2 * np.pi * deg / weights.sum())
    L = line_bundle_with_curvature(X, Om)
    assert L.degree() == deg
    assert int(o @ L.index_form(random_section(rng, X.n_vertices))) == deg


def test_tangent_like_constant_section_on_sphere():
    X = SimplicialComplex(sphere(2))
    L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
    assert L.degree() == -1 and index_sum(L, np.ones(4)) == -1


# ------------------------------------------------------------------ general 2-cycles and tets
@settings(max_examples=15, deadline=None)
@given(st.one_of(closed_manifolds(3, max_moves=2).map(lambda m: m[0]), balls(3, max_moves=3)),
       st.integers(0, 2**32 - 1))
def test_index_form_closed_on_tet_meshes(simplices, seed):
    """On a tet mesh the faces of each tetrahedron, with boundary signs, carry index sum 0."""
    rng = np.random.default_rng(seed)
    X = SimplicialComplex(simplices)
    w = rng.uniform(-np.pi, np.pi, X.n_simplices(1))
    Om = coboundary(X, 1, w)[0]
    Z = cohomology(X, "Z")[2]
    if Z.rank:
        Om = Om + 2 * np.pi * np.asarray(Z.cocycles[:, : Z.rank], float) @ rng.integers(-3, 4, Z.rank)
    L = line_bundle_with_curvature(X, Om)
    ind = L.index_form(random_section(rng, X.n_vertices))
    assert np.array_equal(coboundary(X, 2, ind)[0], np.zeros(X.n_simplices(3)))
    for g in np.asarray(homology(X)[2].generators, np.int64).T:  # general Poincaré–Hopf
        assert index_sum(L, random_section(rng, X.n_vertices), g) == round(L.integrate_curvature(g) / (2 * np.pi))


def test_index_form_integer_on_nonorientable_surface():
    """Theorem 11 needs no orientation: on RP² the (dξ + Ω)/2π are integers too."""
    rng = np.random.default_rng(4)
    X = SimplicialComplex(rp2())
    for _ in range(20):
        L = bundle_with_degree(X, rng)
        z = random_section(rng, X.n_vertices)
        raw = (coboundary(X, 1, L.rotation_form(z))[0] + L.curvature) / (2 * np.pi)
        ind = L.index_form(z)
        assert np.allclose(raw, ind, atol=1e-9)


# ------------------------------------------------------------------ rotation form details
def test_rotation_form_tie_rule_plus_pi():
    X = SimplicialComplex([(0, 1)])
    L = HermitianLineBundle.trivial(X)
    for z1 in (complex(-1.0, 0.0), complex(-1.0, -0.0)):
        assert rotation_form(L, np.array([1.0 + 0j, z1])).tolist() == [np.pi]
    L2 = HermitianLineBundle(X, [1j], [])
    assert np.isclose(rotation_form(L2, np.array([1.0, -1j]))[0], np.pi)  # η(ψ_0) = i = −ψ_1


def test_rotation_form_definition():
    rng = np.random.default_rng(0)
    X = SimplicialComplex(torus7())
    L = bundle_with_degree(X, rng)
    z = random_section(rng, X.n_vertices)
    xi = rotation_form(L, z)
    E = X.simplices(1)
    assert np.all((xi > -np.pi) & (xi <= np.pi))
    assert np.allclose(np.exp(1j * xi), (z[E[:, 1]] / (L.connection * z[E[:, 0]])) / np.abs(z[E[:, 1]] / z[E[:, 0]]))
    # parallel section along a tree has zero rotation on tree edges
    assert np.allclose(rotation_form(HermitianLineBundle.trivial(X), np.full(X.n_vertices, 2 - 1j)), 0)


def test_section_errors_name_the_vertex():
    X = SimplicialComplex([(3, 5, 8)])
    L = HermitianLineBundle.trivial(X)
    with pytest.raises(SectionZeroError, match="vertex 5"):
        L.index_form(np.array([1.0, 0.0, 1.0]))
    with pytest.raises(NonFiniteError, match="vertex 8"):
        L.rotation_form(np.array([1.0, 1.0, np.nan]))
    with pytest.raises(SectionZeroError, match="length 3"):
        L.index_form(np.ones(4))
