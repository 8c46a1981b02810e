"""Integral homology against hand-made complexes and theorems: generators, torsion orders, Künneth.

Cohomology (Z, R, Z/m, S¹ coefficients) is tested in ``test_cohomology.py``; the complexes are in
``tests/homology_complexes.py``.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology._sparse_elim import sparse_solve_integer
from dhlb.topology.homology import (
    HomologyGroup,
    betti_numbers,
    cohomology,
    homology,
    homology_from_boundaries,
)
from dhlb.topology.intlinalg import integer_kernel_basis, smith_normal_form, solve_integer
from tests.homology_complexes import CIRCLE, EXPECTED, KLEIN, RP2, SPHERE, TORUS7, boundaries, obj
from tests.strategies import balls, closed_manifolds, closed_surfaces, complexes


# ----------------------------------------------------------------------------- generator checks
def check_homology_group(X, k, H):
    """Generators are cycles, together with im ∂_{k+1} they span exactly ker ∂_k, and the
    torsion generator i has order exactly torsion[i] in H_k."""
    n = X.n_simplices(k)
    G = obj(H.generators)
    b, t = H.rank, len(H.torsion)
    assert G.shape == (n, b + t)
    dk = obj(X.boundary(k)) if k else np.zeros((0, n), dtype=object)
    dk1 = obj(X.boundary(k + 1)) if k < X.dim else np.zeros((n, 0), dtype=object)
    assert not dk.dot(G).any()
    K = obj(integer_kernel_basis(dk))
    # coordinates in the kernel basis (exist because generators and boundaries are cycles)
    cg = solve_integer(K, G) if G.shape[1] else np.zeros((K.shape[1], 0), dtype=object)
    cb = solve_integer(K, dk1) if dk1.shape[1] else np.zeros((K.shape[1], 0), dtype=object)
    assert cg is not None and cb is not None
    # generators + boundaries span the kernel: SNF of the coordinate matrix is (I | 0)
    allc = np.concatenate([obj(cg), obj(cb)], axis=1)
    if K.shape[1]:
        _, D, _ = smith_normal_form(allc)
        assert [int(D[i, i]) for i in range(K.shape[1])] == [1] * K.shape[1]
    # the quotient by the boundaries alone is Z^b ⊕ ⊕ Z/torsion
    _, D, _ = smith_normal_form(obj(cb)) if cb.size else (None, np.zeros((K.shape[1], 0), int), None)
    inv = [int(D[i, i]) for i in range(min(D.shape)) if D[i, i] > 1]
    free = K.shape[1] - sum(1 for i in range(min(D.shape)) if D[i, i] != 0)
    assert free == b and tuple(inv) == H.torsion
    for j, d in enumerate(H.torsion):
        g = G[:, b + j]
        assert solve_integer(dk1, d * g) is not None
        for p in sympy.primefactors(d):
            assert solve_integer(dk1, (d // p) * g) is None


@pytest.mark.parametrize("name", list(EXPECTED))
def test_homology_of_known_complexes(name):
    simplices, expected = EXPECTED[name]
    X = SimplicialComplex(simplices)
    H = homology(X)
    assert [(h.rank, h.torsion) for h in H] == expected
    assert all(isinstance(h, HomologyGroup) and h.degree == k for k, h in enumerate(H))
    for k, h in enumerate(H):
        check_homology_group(X, k, h)
    assert betti_numbers(X) == tuple(e[0] for e in expected)


def test_group_strings():
    H = homology(SimplicialComplex(KLEIN))
    assert [str(h) for h in H] == ["Z", "Z ⊕ Z/2", "0"]
    assert str(homology(SimplicialComplex(TORUS7))[1]) == "Z^2"
    assert "Z ⊕ Z/2" in repr(H[1]) or "torsion=(2,)" in repr(H[1])


def test_dhlb_examples():
    from dhlb import examples as ex

    cases = [
        (ex.dunce_hat(), [(1, ()), (0, ()), (0, ())]),
        (ex.klein_bottle(), [(1, ()), (1, (2,)), (0, ())]),
        (ex.projective_plane(), [(1, ()), (0, (2,)), (0, ())]),
        (ex.torus(), [(1, ()), (2, ()), (1, ())]),
        (ex.lens_space(5, 2), [(1, ()), (0, (5,)), (0, ()), (1, ())]),
        (ex.projective_space(3), [(1, ()), (0, (2,)), (0, ()), (1, ())]),
        (ex.torus_nd(3), [(1, ()), (3, ()), (3, ()), (1, ())]),
    ]
    for X, expected in cases:
        H = homology(X)
        assert [(h.rank, h.torsion) for h in H] == expected
        for k, h in enumerate(H):
            assert not (obj(X.boundary(k)).dot(obj(h.generators))).any() if k else True


# ----------------------------------------------------------------------------- property tests
@settings(max_examples=40, deadline=None)
@given(complexes())
def test_random_complexes(X):
    H = homology(X)
    assert len(H) == X.dim + 1
    assert sum((-1) ** k * h.rank for k, h in enumerate(H)) == X.euler_characteristic
    for k, h in enumerate(H):  # rational Betti numbers from floating ranks of the small matrices
        n = X.n_simplices(k)
        rk = np.linalg.matrix_rank(X.boundary(k).toarray()) if k and n else 0
        rk1 = np.linalg.matrix_rank(X.boundary(k + 1).toarray()) if k < X.dim else 0
        assert h.rank == n - rk - rk1
        assert all(t > 1 for t in h.torsion)
        assert all(h.torsion[i + 1] % h.torsion[i] == 0 for i in range(len(h.torsion) - 1))
        check_homology_group(X, k, h)


@settings(max_examples=15, deadline=None)
@given(closed_surfaces())
def test_random_closed_surfaces(surface):
    tris, chi, orientable = surface
    H = homology(SimplicialComplex(tris))
    if orientable:
        assert [(h.rank, h.torsion) for h in H] == [(1, ()), (2 - chi, ()), (1, ())]
    else:
        assert [(h.rank, h.torsion) for h in H] == [(1, ()), (1 - chi, (2,)), (0, ())]


@settings(max_examples=10, deadline=None)
@given(st.integers(3, 4).flatmap(lambda d: st.tuples(st.just(d), closed_manifolds(d, max_moves=2))))
def test_random_closed_manifolds(case):
    dim, (simplices, name) = case
    H = homology(SimplicialComplex(simplices))
    expected = {"sphere": [1] + [0] * (dim - 1) + [1], "torus": [1, 3, 3, 1]}[name]
    assert [h.rank for h in H] == expected and all(h.torsion == () for h in H)


@settings(max_examples=10, deadline=None)
@given(st.integers(1, 4).flatmap(balls))
def test_random_balls_are_acyclic(simplices):
    H = homology(SimplicialComplex(simplices))
    assert [(h.rank, h.torsion) for h in H] == [(1, ())] + [(0, ())] * (len(H) - 1)
    assert H[0].generators.shape[1] == 1


def test_kunneth_rp2_times_circle():
    """H_*(RP² × S¹) by Künneth: Z, Z ⊕ Z/2, Z/2, 0 (Tor(Z/2, Z) = 0)."""
    from dhlb import examples as ex

    X = ex.product(SimplicialComplex(RP2), SimplicialComplex(CIRCLE))
    H = homology(X)
    assert [(h.rank, h.torsion) for h in H] == [(1, ()), (1, (2,)), (0, (2,)), (0, ())]
    for k, h in enumerate(H):
        check_homology_group(X, k, h)


# ----------------------------------------------------------------------------- larger sparse cases
def grid_torus_with_crosscap(N):
    """N×N grid torus with one square replaced by an annulus to a 6-vertex RP² minus a triangle."""
    lab = lambda i, j: (i % N) * N + j % N  # noqa: E731
    T = []
    for i in range(N):
        for j in range(N):
            if (i, j) != (0, 0):
                T += [(lab(i, j), lab(i + 1, j), lab(i + 1, j + 1)), (lab(i, j), lab(i + 1, j + 1), lab(i, j + 1))]
    a, b, c, d = lab(0, 0), lab(1, 0), lab(1, 1), lab(0, 1)
    M = N * N
    rp2 = [tuple(v + M for v in t) for t in RP2[1:]]  # hole bounded by M, M+1, M+2
    x, y, z = M, M + 1, M + 2
    return T + rp2 + [(a, b, x), (b, x, y), (b, c, y), (c, y, z), (c, d, z), (d, z, x), (d, a, x)]


def test_medium_surface_with_torsion():
    X = SimplicialComplex(grid_torus_with_crosscap(40))
    H = homology(X)
    assert [(h.rank, h.torsion) for h in H] == [(1, ()), (2, (2,)), (0, ())]
    assert not abs(X.boundary(1) @ H[1].generators).max()
    S = cohomology(X, "S1")[1]
    assert S.rank == 2 and S.torsion == (2,)
    t = H[1].generators[:, 2].astype(float)
    assert np.isclose(np.cos(t @ S.cocycles[:, 2]), -1.0)
    Z2 = cohomology(X, "Z")[2]
    assert Z2.rank == 0 and Z2.torsion == (2,)


def test_surface_fundamental_class_from_kernel():
    """ker ∂_2 of a closed orientable surface is spanned by the fundamental cycle (±1 everywhere)."""
    X = SimplicialComplex(_torus_grid(30))
    K = integer_kernel_basis(X.boundary(2))
    assert K.shape == (X.n_simplices(2), 1)
    assert set(np.abs(K.toarray()).ravel().tolist()) == {1}


def _torus_grid(N):
    lab = lambda i, j: (i % N) * N + j % N  # noqa: E731
    return [t for i in range(N) for j in range(N)
            for t in ((lab(i, j), lab(i + 1, j), lab(i + 1, j + 1)), (lab(i, j), lab(i + 1, j + 1), lab(i, j + 1)))]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 6).flatmap(lambda m: st.tuples(
    st.just(m), st.integers(0, 6), st.lists(st.integers(-3, 3), min_size=36, max_size=36),
    st.lists(st.integers(-4, 4), min_size=6, max_size=6))))
def test_sparse_solver_matches_dense(case):
    m, n, vals, x0 = case
    A = np.array(vals[: m * n], dtype=np.int64).reshape(m, n) if m * n else np.zeros((m, n), dtype=np.int64)
    A[np.abs(A) > 1] = 0  # mostly unit entries, like boundary matrices
    b = A @ np.array(x0[:n], dtype=np.int64) if n else np.zeros(m, dtype=np.int64)
    x = sparse_solve_integer(sp.csr_matrix(A), obj(b.reshape(m, 1)))
    assert x is not None and np.array_equal(obj(A).dot(obj(x[:, 0])), obj(b))
    if m:
        b2 = b.copy()
        b2[0] += 1
        dense = solve_integer(A, b2)
        sparse = sparse_solve_integer(sp.csr_matrix(A), obj(b2.reshape(m, 1)))
        assert (dense is None) == (sparse is None)


# ----------------------------------------------------------------------------- bad input
def test_bad_input():
    X = SimplicialComplex(SPHERE)
    B = boundaries(X)
    with pytest.raises(InvalidMatrixError, match="chain complex"):
        homology_from_boundaries([B[0], B[1], 2 * B[2] + sp.csr_matrix(np.eye(6, 4, dtype=np.int64))])
    with pytest.raises(ShapeError, match="∂_0"):
        homology_from_boundaries(B[1:])
    with pytest.raises(ShapeError):
        homology_from_boundaries([B[0], B[2]])
    with pytest.raises(ShapeError):
        homology_from_boundaries([])
    with pytest.raises(InvalidMatrixError):
        homology_from_boundaries([B[0], B[1] * 0.5])
