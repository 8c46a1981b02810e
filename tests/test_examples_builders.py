"""dhlb.examples builders: f-vectors, Kuhn grids against brute force, points, products, mesh wrappers, errors.

The topology of the named complexes (homology, manifold checks, Künneth) is tested in
``test_examples.py``.
"""

from itertools import combinations, permutations
from itertools import product as iproduct
from math import comb, factorial

import numpy as np
import pytest

from dhlb import SimplicialComplex
from dhlb import examples as E
from dhlb.errors import (
    EmptyComplexError,
    InvalidParameterError,
    InvalidSimplexError,
    NonFiniteError,
    UnreferencedVertexWarning,
)
from dhlb.mesh import mesh_complex


# ------------------------------------------------------------------ counts, f-vectors and Euler characteristics
def test_named_counts():
    assert E.torus().counts == (7, 21, 14)
    assert E.projective_plane().counts == (6, 15, 10)
    assert E.moebius_strip().counts == (5, 10, 5)
    assert E.dunce_hat().counts == (8, 24, 17)
    assert E.sphere(3).counts == (5, 10, 10, 5)
    assert E.simplex(4).counts == tuple(comb(5, k + 1) for k in range(5))


@pytest.mark.parametrize("n", range(0, 6))
def test_sphere_and_simplex_counts(n):
    S = E.sphere(n)
    assert S.counts == tuple(comb(n + 2, k + 1) for k in range(n + 1))
    assert S.euler_characteristic == 1 + (-1) ** n
    assert E.simplex(n).euler_characteristic == 1


def _chains(n, k):
    """Number of chains ∅ ⊊ S_1 ⊊ ... ⊊ S_k ⊆ {0..n-1}: each element picks the step it enters at or never."""
    return sum(1 for f in iproduct(range(k + 1), repeat=n) if set(range(1, k + 1)) <= set(f))


@pytest.mark.parametrize("n, m", [(1, 3), (1, 5), (2, 3), (2, 4), (3, 3), (3, (3, 4, 5)), (4, 3)])
def test_torus_nd_f_vector(n, m):
    X = E.torus_nd(n, m)
    cells = int(np.prod(np.broadcast_to(m, (n,))))
    assert X.counts == tuple(cells * _chains(n, k) for k in range(n + 1))
    assert X.euler_characteristic == 0


def _brute_kuhn(n, m, periodic):
    shape = [c if periodic else c + 1 for c in m]
    out = set()
    for cell in iproduct(*[range(c) for c in m]):
        for perm in permutations(range(n)):
            pt, verts = list(cell), []
            for r in range(n + 1):
                if r:
                    pt[perm[r - 1]] += 1
                coords = [c % s for c, s in zip(pt, shape)] if periodic else pt
                verts.append(int(np.ravel_multi_index(coords, shape)))
            out.add(tuple(sorted(verts)))
    return [list(t) for t in sorted(out)]


@pytest.mark.parametrize("n, m", [(1, (2,)), (2, (2, 3)), (3, (2, 1, 2)), (2, (3, 3)), (3, (3, 3, 4))])
def test_grids_match_brute_force(n, m):
    X = E.cube_nd(n, m)
    assert X.simplices(n).tolist() == _brute_kuhn(n, m, periodic=False)
    if min(m) >= 3:
        assert E.torus_nd(n, m).simplices(n).tolist() == _brute_kuhn(n, m, periodic=True)


@pytest.mark.parametrize("n, m", [(1, 4), (2, 3), (3, 2), (4, 2)])
def test_cube_nd_geometry(n, m):
    X, P = E.cube_nd(n, m, return_points=True)
    assert P.shape == ((m + 1) ** n, n) and P.min() == 0.0 and P.max() == 1.0
    assert X.counts[0] == (m + 1) ** n and X.counts[n] == factorial(n) * m**n
    S = X.simplices(n)
    vol = np.abs(np.linalg.det(P[S[:, 1:]] - P[S[:, :1]])) / factorial(n)
    np.testing.assert_allclose(vol, 1.0 / (factorial(n) * m**n), rtol=1e-12)  # no degenerate simplex
    assert vol.sum() == pytest.approx(1.0, rel=1e-12)
    assert X.is_manifold() and X.euler_characteristic == 1


def test_torus_nd_points_are_the_grid():
    X, P = E.torus_nd(3, (3, 4, 5), return_points=True)
    assert P.shape == (60, 3) and P.min() == 0.0 and P.max() < 1.0
    idx = np.round(P * np.array([3, 4, 5])).astype(int)
    assert np.array_equal(np.ravel_multi_index(idx.T, (3, 4, 5)), np.arange(60))
    # every edge is a 0/1 step modulo the period
    E1 = X.simplices(1)
    step = np.mod(idx[E1[:, 1]] - idx[E1[:, 0]], [3, 4, 5])
    step = np.where(step > 1, step - np.array([3, 4, 5]), step)
    assert np.all(np.abs(step) <= 1)


def test_cube_nd_large_is_vectorized():
    X = E.cube_nd(3, 55)
    assert X.counts[3] == 6 * 55**3 and X.counts[0] == 56**3


def test_sphere_and_simplex_points():
    for n in range(0, 5):
        _X, P = E.sphere(n, return_points=True)
        assert P.shape == (n + 2, n + 1)
        np.testing.assert_allclose(np.linalg.norm(P, axis=1), 1.0)
        if n > 0:
            d = [np.linalg.norm(P[a] - P[b]) for a, b in combinations(range(n + 2), 2)]
            np.testing.assert_allclose(d, d[0])
            np.testing.assert_allclose(P.sum(axis=0), 0.0, atol=1e-12)
    _S, Q = E.simplex(3, return_points=True)
    assert Q.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]


def test_projective_space_points_are_distinct_lines():
    for n in range(1, 4):
        X, P = E.projective_space(n, return_points=True)
        assert X.counts[0] == (3 ** (n + 1) - 1) // 2 and X.counts[n] == 2**n * factorial(n + 1)
        np.testing.assert_allclose(np.linalg.norm(P, axis=1), 1.0)
        first = P[np.arange(len(P)), np.argmax(np.abs(P) > 0, axis=1)]
        assert np.all(first > 0)
        assert len({tuple(np.round(p, 9)) for p in P}) == len(P)


# ------------------------------------------------------------------ product triangulations
@pytest.mark.parametrize("a, b, m", [(1, 1, 1), (1, 1, 3), (1, 2, 2), (2, 1, 2), (2, 2, 1), (1, 3, 1)])
def test_product_of_cubes_is_the_kuhn_cube(a, b, m):
    assert E.product(E.cube_nd(a, m), E.cube_nd(b, m)) == E.cube_nd(a + b, m)


def test_product_vertex_numbering_and_projections():
    X, Y = E.projective_plane(), E.moebius_strip()
    P, pairs = E.product(X, Y, return_pairs=True)
    assert np.array_equal(pairs[:, 0] * Y.n_vertices + pairs[:, 1], np.arange(P.n_vertices))
    for k in range(P.dim + 1):
        S = P.simplices(k)
        xs, ys = np.sort(pairs[S, 0], axis=1), np.sort(pairs[S, 1], axis=1)
        for proj, F in ((xs, X), (ys, Y)):  # both projections of every simplex are simplices
            for row in proj[:50]:
                u = np.unique(row)
                assert F.contains(len(u) - 1, u[None, :])[0]
        # vertices of a simplex are a chain of the product order
        assert np.all(np.diff(pairs[S, 0], axis=1) >= 0) and np.all(np.diff(pairs[S, 1], axis=1) >= 0)


def test_product_is_associative():
    A, B, C = E.sphere(1), E.cube_nd(1, 2), E.moebius_strip()
    assert E.product(E.product(A, B), C) == E.product(A, E.product(B, C))


# ------------------------------------------------------------------ mesh wrappers
def test_surface_keeps_orientation_and_index():
    T, P = E.torus_nd(2, 4, return_points=True)
    rng = np.random.default_rng(0)
    F = T.simplices(2)[rng.permutation(T.n_simplices(2))]
    F = np.array([row[rng.permutation(3)] for row in F])
    angle = 2 * np.pi * P
    V = np.stack([(2 + np.cos(angle[:, 1])) * np.cos(angle[:, 0]), (2 + np.cos(angle[:, 1])) * np.sin(angle[:, 0]),
                  np.sin(angle[:, 1])], axis=1)
    M = mesh_complex(V, F, dim=2)
    X = M.complex
    assert X == T
    assert np.array_equal(X.simplices(2)[M.index], np.sort(F, axis=1))
    assert np.array_equal(M.orientation, SimplicialComplex.orientation_of(F))
    np.testing.assert_array_equal(M.points, V)
    # flipping one triangle flips exactly its sign
    G = F.copy()
    G[5] = G[5, [1, 0, 2]]
    flipped = mesh_complex(None, G, dim=2).orientation
    assert np.array_equal(flipped * M.orientation, np.where(np.arange(len(F)) == 5, -1, 1))


def test_tet_mesh_and_unreferenced_vertices():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [9, 9, 9], [1, 1, 1]], float)
    T = np.array([[0, 1, 2, 3], [5, 3, 2, 1]])
    with pytest.warns(UnreferencedVertexWarning):
        M = mesh_complex(V, T, dim=3)
    assert M.complex.vertex_labels.tolist() == [0, 1, 2, 3, 5]
    assert M.points.tolist() == V[[0, 1, 2, 3, 5]].tolist()
    assert M.orientation.tolist() == [1, SimplicialComplex.orientation_of([[5, 3, 2, 1]])[0]]
    assert M.complex.simplices(3)[M.index].tolist() == [[0, 1, 2, 3], [1, 2, 3, 4]]


def test_mesh_bad_input():
    V = np.zeros((4, 3))
    with pytest.raises(InvalidSimplexError, match="shape"):
        mesh_complex(V, [[0, 1, 2, 3]], dim=2)
    with pytest.raises(InvalidSimplexError, match="refers to vertex 7"):
        mesh_complex(V, [[0, 1, 2], [1, 2, 7]], dim=2)
    with pytest.raises(InvalidSimplexError, match="repeats a vertex"):
        mesh_complex(None, [[0, 1, 1]], dim=2)
    with pytest.raises(InvalidSimplexError):
        mesh_complex(None, [[0, -1, 2]], dim=2)
    with pytest.raises(EmptyComplexError):
        mesh_complex(None, np.zeros((0, 4), int), dim=3)
    with pytest.raises(NonFiniteError, match="vertex 2"):
        mesh_complex([[0, 0, 0], [1, 0, 0], [np.nan, 0, 0]], [[0, 1, 2]], dim=2)
    with pytest.raises(InvalidSimplexError):
        mesh_complex(None, [[0, 1, 2]], dim=3)


# ------------------------------------------------------------------ bad parameters
@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: E.torus_nd(2, 2), ">= 3"),
        (lambda: E.torus_nd(1, 1), ">= 3"),
        (lambda: E.torus_nd(2, (3, 2)), r"m\[1\]"),
        (lambda: E.torus_nd(2, (3, 3, 3)), "one cell count per axis"),
        (lambda: E.cube_nd(0, 3), "n must be"),
        (lambda: E.cube_nd(2, 0), ">= 1"),
        (lambda: E.cube_nd(2, 1.5), "integer"),
        (lambda: E.sphere(-1), ">= 0"),
        (lambda: E.sphere(True), "integer"),
        (lambda: E.simplex("3"), "integer"),
        (lambda: E.lens_space(4, 2), "gcd"),
        (lambda: E.lens_space(0, 1), ">= 1"),
        (lambda: E.lens_space(3, 1.0), "integer"),
        (lambda: E.projective_space(-2), ">= 0"),
    ],
)
def test_bad_parameters(call, match):
    with pytest.raises(InvalidParameterError, match=match) as info:
        call()
    assert isinstance(info.value, ValueError)


def test_constructions_validate_their_input():
    with pytest.raises(InvalidSimplexError):
        E.product([(0, 0)], [(0, 1)])
    with pytest.raises(EmptyComplexError):
        E.cone([])
    assert E.product(np.array([[0, 1]]), [(0,)]).counts == (2, 1)  # plain simplex input is accepted
