"""Structural operations: skeleta, stars, links, components, boundary, subdivision, relabeling."""

from itertools import combinations, pairwise
from math import factorial

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import InvalidSimplexError, NonManifoldError, SimplexNotFoundError
from dhlb.topology.structure import (
    boundary_complex,
    closed_star,
    coface_counts,
    components,
    connected_components,
    incidence,
    link,
    link_component_counts,
    parent_indices,
    skeleton,
    star,
    subcomplex,
    subfaces,
)
from dhlb.topology.subdivision import barycentric_subdivision, relabeled
from tests.strategies import balls, complexes, pure_simplex_lists, simplex_lists, sphere, torus7


def simplex_set(X, labels=None):
    """All simplices of X as sorted tuples of labels (X's input labels by default)."""
    lab = X.vertex_labels if labels is None else np.asarray(labels)
    return {tuple(sorted(lab[r].tolist())) for k in range(X.dim + 1) for r in X.simplices(k)}


def sub_set(X, Y):
    """Simplices of a subcomplex Y (labels = X's compact indices) in X's input labels."""
    return simplex_set(Y, X.vertex_labels[np.asarray(Y.vertex_labels)])


def closure(simplices):
    return {f for s in simplices for r in range(1, len(s) + 1) for f in combinations(sorted(s), r)}


def nx_components(S):
    g = nx.Graph()
    g.add_nodes_from(s[0] for s in S if len(s) == 1)
    g.add_edges_from(s for s in S if len(s) == 2)
    return [set(c) for c in nx.connected_components(g)]


# ---------------------------------------------------------------------------- brute-force agreement
@given(complexes())
def test_star_link_closed_star_brute_force(X):
    S = simplex_set(X)
    for k in range(X.dim + 1):
        lcc = link_component_counts(X, k)
        cc = coface_counts(X, k)
        for row in range(X.n_simplices(k)):
            sigma = tuple(X.vertex_labels[X.simplices(k)[row]].tolist())
            above = {t for t in S if set(sigma) <= set(t)}
            st_rows = star(X, k, row)
            assert len(st_rows) == X.dim + 1
            got = set()
            for j, rows in enumerate(st_rows):
                assert np.all(np.diff(rows) > 0)
                got |= {tuple(X.vertex_labels[X.simplices(j)[r]].tolist()) for r in rows}
            assert got == above
            assert [sum(len(t) == j + 1 for t in above) for j in range(X.dim + 1)] == cc[row].tolist()
            assert sub_set(X, closed_star(X, k, row)) == closure(above)
            expected_link = {tuple(sorted(set(t) - set(sigma))) for t in above if t != sigma}
            L = link(X, k, row)
            if not expected_link:
                assert L is None and lcc[row] == 0
            else:
                assert sub_set(X, L) == expected_link
                assert lcc[row] == len(nx_components(expected_link))


@given(complexes(), st.data())
def test_skeleton_subcomplex_incidence(X, data):
    S = simplex_set(X)
    for k in range(X.dim + 1):
        Sk = skeleton(X, k)
        assert np.array_equal(Sk.vertex_labels, X.vertex_labels)
        assert simplex_set(Sk) == {t for t in S if len(t) <= k + 1}
        idx = data.draw(st.lists(st.integers(0, X.n_simplices(k) - 1), max_size=4))
        Y = subcomplex(X, k, idx)
        chosen = [tuple(X.vertex_labels[X.simplices(k)[i]].tolist()) for i in idx]
        if not idx:
            assert Y is None
        else:
            assert sub_set(X, Y) == closure(chosen)
            assert sorted(parent_indices(X, Y, k).tolist()) == sorted(set(idx))
        for j in range(k, X.dim + 1):
            inc = incidence(X, k, j).toarray()
            brute = [[set(a) <= set(b) for b in X.simplices(j)] for a in X.simplices(k)]
            assert np.array_equal(inc, np.array(brute, dtype=int).reshape(inc.shape))
    assert skeleton(X, X.dim) is X
    for j in range(1, X.dim + 1):  # subfaces: columns in lexicographic order of the vertex subsets
        for k in range(j + 1):
            sub = subfaces(X, j, k)
            for row, s in enumerate(X.simplices(j)):
                expect = [X.index(k, X.vertex_labels[list(c)])[0] for c in combinations(s.tolist(), k + 1)]
                assert sub[row].tolist() == expect


@given(complexes())
def test_components_partition_the_complex(X):
    S = simplex_set(X)
    n, lab = connected_components(X)
    expected = nx_components(S)
    assert n == len(expected)
    assert {frozenset(X.vertex_labels[lab == c].tolist()) for c in range(n)} == {frozenset(c) for c in expected}
    first = [int(np.argmax(lab == c)) for c in range(n)]
    assert first == sorted(first)  # numbered by smallest vertex
    parts = components(X)
    sets = [sub_set(X, C) for C in parts]
    assert set().union(*sets) == S and sum(map(len, sets)) == len(S)
    assert all(connected_components(C)[0] == 1 for C in parts)
    assert sum(C.euler_characteristic for C in parts) == X.euler_characteristic


@given(pure_simplex_lists(dim=3, max_vertices=7) | pure_simplex_lists(dim=2, max_vertices=6))
def test_boundary_complex_brute_force(simplices):
    X = SimplicialComplex(simplices)
    n = X.dim
    faces = [f for s in simplices for f in combinations(sorted(s), n)]
    once = [f for f in set(faces) if faces.count(f) == 1]
    B = boundary_complex(X)
    if not once:
        assert B is None
    else:
        assert sub_set(X, B) == closure(once)


def test_boundary_complex_examples():
    assert boundary_complex(SimplicialComplex(sphere(3))) is None
    B = boundary_complex(SimplicialComplex([(0, 1, 2, 3)]))
    assert B.counts == (4, 6, 4) and B.euler_characteristic == 2
    assert boundary_complex(SimplicialComplex([(4,), (7,)])) is None
    with pytest.raises(NonManifoldError, match=r"\(2, 5\)"):
        boundary_complex(SimplicialComplex([(0, 1, 2), (2, 5)]))


# ---------------------------------------------------------------------------- barycentric subdivision
def flag_counts(S):
    """Number of chains s_0 < s_1 < ... < s_j in the face poset, per j (brute force)."""
    faces = sorted(S, key=len)
    chains = [[(s,) for s in faces]]
    while chains[-1]:
        chains.append([c + (t,) for c in chains[-1] for t in faces if len(t) > len(c[-1]) and set(c[-1]) <= set(t)])
    return [len(c) for c in chains[:-1]]


@settings(max_examples=15)
@given(complexes(max_vertices=6, max_dim=3, max_size=6))
def test_barycentric_subdivision_brute_force(X):
    Sd, vmap = barycentric_subdivision(X)
    assert Sd.euler_characteristic == X.euler_characteristic
    assert list(Sd.counts) == flag_counts(simplex_set(X))
    assert vmap.shape == (Sd.n_vertices, 2)
    assert np.array_equal(np.bincount(vmap[:, 0]), X.counts)
    for top in Sd.maximal_simplices()[Sd.dim]:  # a top simplex of Sd is a full flag
        chain = [set(X.simplices(k)[r]) for k, r in vmap[top]]
        assert all(a < b for a, b in pairwise(chain))
    if X.is_pure:
        assert Sd.n_simplices(X.dim) == factorial(X.dim + 1) * X.n_simplices(X.dim)


@settings(max_examples=10)
@given(balls(3, max_moves=2))
def test_barycentric_subdivision_of_ball_is_ball(simplices):
    X = SimplicialComplex(simplices)
    Sd, _ = barycentric_subdivision(X)
    assert Sd.is_manifold() and Sd.euler_characteristic == 1
    assert boundary_complex(Sd).euler_characteristic == 2


@settings(max_examples=10)
@given(complexes(max_vertices=6, max_dim=3, max_size=6))
def test_barycentric_subdivision_preserves_homology(X):
    pytest.importorskip("dhlb.topology.homology")
    Sd, _ = barycentric_subdivision(X)
    assert Sd.homology() == X.homology()


# ---------------------------------------------------------------------------- relabeling invariance
@given(simplex_lists(), st.randoms(use_true_random=False))
def test_relabeling_invariance(simplices, rnd):
    X = SimplicialComplex(simplices)
    perm = np.array(rnd.sample(range(3 * X.n_vertices + 3), X.n_vertices))
    Y = relabeled(X, perm)
    assert simplex_set(Y) == simplex_set(X, perm)
    assert Y.counts == X.counts and Y.euler_characteristic == X.euler_characteristic
    assert connected_components(Y)[0] == connected_components(X)[0]
    assert sorted(c.counts for c in components(Y)) == sorted(c.counts for c in components(X))
    for k in range(X.dim + 1):
        rows_y = Y.index(k, perm[X.simplices(k)])  # row in Y of the image of each X-simplex
        assert np.array_equal(link_component_counts(Y, k)[rows_y], link_component_counts(X, k))
        assert np.array_equal(coface_counts(Y, k)[rows_y], coface_counts(X, k))
        for row in range(min(3, X.n_simplices(k))):
            LX, LY = link(X, k, row), link(Y, k, int(rows_y[row]))
            assert (LX is None) == (LY is None)
            if LX is not None:  # both in the new labels
                assert simplex_set(LX, perm[np.asarray(LX.vertex_labels)]) == \
                    simplex_set(LY, Y.vertex_labels[np.asarray(LY.vertex_labels)])
    assert X.is_manifold() == Y.is_manifold()
    assert X.is_pseudomanifold() == Y.is_pseudomanifold()
    assert X.is_orientable() == Y.is_orientable()
    assert barycentric_subdivision(X)[0].counts == barycentric_subdivision(Y)[0].counts


# ---------------------------------------------------------------------------- shims and bad input
def test_complex_methods_delegate():
    X = SimplicialComplex(torus7())
    assert X.skeleton(1).counts == (7, 21)
    assert next(s.tolist() for s in X.star(0, 0)) == [0]
    assert X.link(0, 0).counts == (6, 6)
    assert X.connected_components()[0] == 1
    assert X.boundary_complex() is None
    assert X.barycentric_subdivision()[0].euler_characteristic == 0


def test_bad_input_names_the_element():
    X = SimplicialComplex([(0, 1, 2), (2, 3)])
    with pytest.raises(SimplexNotFoundError, match="dimension 2; it has no 5-simplices"):
        star(X, 5, 0)
    with pytest.raises(SimplexNotFoundError, match="no 1-simplex number 99"):
        link(X, 1, 99)
    with pytest.raises(SimplexNotFoundError, match="number -1"):
        subcomplex(X, 1, [0, -1])
    with pytest.raises(InvalidSimplexError, match="integer"):
        star(X, 1.5, 0)
    with pytest.raises(InvalidSimplexError, match="integer row numbers"):
        subcomplex(X, 1, [0.5])
    with pytest.raises(InvalidSimplexError, match="vertices 0 and 2 both get the new label 7"):
        relabeled(X, [7, 1, 7, 3])
    with pytest.raises(InvalidSimplexError, match="one label per vertex"):
        relabeled(X, [0, 1])
    with pytest.raises(InvalidSimplexError, match="new label -2 of vertex 1"):
        relabeled(X, [0, -2, 1, 3])
    with pytest.raises(SimplexNotFoundError):
        skeleton(X, 3)
    with pytest.raises(InvalidSimplexError, match="k <= j"):
        incidence(X, 2, 1)
