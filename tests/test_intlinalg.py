"""Exact integer linear algebra: Smith/Hermite forms, integer kernels, integer solving."""

import numpy as np
import pytest
import scipy.sparse as sp
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy.matrices.normalforms import smith_normal_form as sympy_snf

from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology.intlinalg import (
    hermite_normal_form,
    integer_determinant,
    integer_kernel_basis,
    is_unimodular,
    smith_normal_form,
    solve_integer,
)

# ----------------------------------------------------------------------------- strategies
dims = st.integers(0, 5)


@st.composite
def int_matrices(draw, max_dim=5, max_entry=6):
    """Random integer matrices, often rank-deficient (products of thin factors) or zero."""
    m, n = draw(st.integers(0, max_dim)), draw(st.integers(0, max_dim))
    kind = draw(st.sampled_from(["full", "lowrank", "zero", "sparse"]))
    ent = st.integers(-max_entry, max_entry)
    if kind == "zero":
        return np.zeros((m, n), dtype=np.int64)
    if kind == "lowrank":
        r = draw(st.integers(0, 3))
        L = np.array(draw(st.lists(ent, min_size=m * r, max_size=m * r)), dtype=np.int64).reshape(m, r)
        R = np.array(draw(st.lists(ent, min_size=r * n, max_size=r * n)), dtype=np.int64).reshape(r, n)
        return L @ R
    vals = draw(st.lists(ent, min_size=m * n, max_size=m * n))
    A = np.array(vals, dtype=np.int64).reshape(m, n)
    if kind == "sparse":
        mask = np.array(draw(st.lists(st.booleans(), min_size=m * n, max_size=m * n)), dtype=bool).reshape(m, n)
        A = A * mask
    return A


def rank(A) -> int:
    return int(sympy.Matrix(A.tolist()).rank()) if A.size else 0


def as_obj(A):
    return np.asarray(A, dtype=object)


def assert_saturated_basis_of_kernel(A, K):
    """Columns of K are a Z-basis of ker A ∩ Z^n: A K = 0, n - rank A columns, SNF(K) = (I; 0)."""
    A, K = np.asarray(A), np.asarray(K.toarray() if sp.issparse(K) else K)
    n = A.shape[1]
    assert K.shape == (n, n - rank(A))
    assert not (as_obj(A).dot(as_obj(K))).any()
    if K.shape[1]:
        _, D, _ = smith_normal_form(K)
        assert [int(D[i, i]) for i in range(K.shape[1])] == [1] * K.shape[1]


# ----------------------------------------------------------------------------- Smith normal form
@settings(max_examples=150, deadline=None)
@given(int_matrices())
def test_smith_normal_form_properties(A):
    U, D, V = smith_normal_form(A)
    m, n = A.shape
    assert U.shape == (m, m) and V.shape == (n, n) and D.shape == (m, n)
    assert np.array_equal(as_obj(U).dot(as_obj(A)).dot(as_obj(V)), as_obj(D))
    assert is_unimodular(U) and is_unimodular(V)
    off = D.copy()
    off[np.arange(min(m, n)), np.arange(min(m, n))] = 0
    assert not off.any()
    d = [int(D[i, i]) for i in range(min(m, n))]
    r = rank(A)
    assert all(x > 0 for x in d[:r]) and not any(d[r:])
    assert all(d[i + 1] % d[i] == 0 for i in range(r - 1))
    if m and n:  # invariant factors agree with sympy's (an independent implementation)
        S = sympy_snf(sympy.Matrix(A.tolist()), domain=sympy.ZZ)
        ref = sorted(abs(int(S[i, i])) for i in range(min(m, n)) if S[i, i] != 0)
        assert sorted(d[:r]) == ref


def test_smith_known_examples():
    U, D, V = smith_normal_form([[2, 4, 4], [-6, 6, 12], [10, -4, -16]])
    assert np.diag(D).tolist() == [2, 6, 12]
    for shape in [(0, 3), (3, 0), (0, 0)]:
        U, D, V = smith_normal_form(np.zeros(shape, dtype=int))
        assert U.shape == (shape[0],) * 2 and V.shape == (shape[1],) * 2 and D.shape == shape


def test_smith_big_entries_stay_exact():
    big = 2 ** 70
    A = np.array([[big, 0], [0, 3 * big]], dtype=object)
    U, D, V = smith_normal_form(A)
    assert D.dtype == object and D[0, 0] == big and D[1, 1] == 3 * big
    assert np.array_equal(U.dot(A).dot(V), D)


# ----------------------------------------------------------------------------- Hermite normal form
def assert_hnf_structure(H):
    m, n = H.shape
    nonzero = [j for j in range(n) if H[:, j].any()]
    z = n - len(nonzero)
    assert nonzero == list(range(z, n))  # zero columns first: A U = (0 | H')
    pivots = []
    for j in range(z, n):
        p = max(i for i in range(m) if H[i, j] != 0)  # lowest nonzero entry
        assert H[p, j] > 0
        pivots.append(p)
    assert pivots == sorted(set(pivots))  # strictly increasing pivot rows
    for jj, p in enumerate(pivots):
        j = z + jj
        assert all(0 <= H[p, c] < H[p, j] for c in range(j + 1, n))


@settings(max_examples=150, deadline=None)
@given(int_matrices(), st.randoms(use_true_random=False))
def test_hermite_normal_form_properties(A, rnd):
    H, U = hermite_normal_form(A)
    assert np.array_equal(as_obj(A).dot(as_obj(U)), as_obj(H))
    assert is_unimodular(U)
    assert_hnf_structure(H)
    assert sum(1 for j in range(H.shape[1]) if H[:, j].any()) == rank(A)
    # uniqueness: the HNF depends only on the column lattice, so A W has the same HNF
    n = A.shape[1]
    W = np.eye(n, dtype=np.int64)
    for _ in range(3 * n):
        i, j = rnd.randrange(n), rnd.randrange(n)
        if i != j:
            W[:, i] += rnd.choice([-2, -1, 1, 2]) * W[:, j]
    if n >= 2:
        W[:, [0, 1]] = W[:, [1, 0]]
    H2, _ = hermite_normal_form(as_obj(A).dot(as_obj(W)))
    assert np.array_equal(as_obj(H2), as_obj(H))


# ----------------------------------------------------------------------------- kernels
@settings(max_examples=120, deadline=None)
@given(int_matrices())
def test_kernel_basis_is_a_z_basis(A):
    assert_saturated_basis_of_kernel(A, integer_kernel_basis(A))


@settings(max_examples=60, deadline=None)
@given(int_matrices(max_dim=6, max_entry=2))
def test_sparse_kernel_basis_is_a_z_basis(A):
    K = integer_kernel_basis(sp.csr_matrix(A))
    assert sp.issparse(K)
    assert_saturated_basis_of_kernel(A, K)


graphs = st.lists(st.tuples(st.integers(0, 7), st.integers(0, 7)).filter(lambda e: e[0] != e[1]),
                  min_size=0, max_size=14)


@settings(max_examples=60, deadline=None)
@given(graphs, st.integers(0, 2))
def test_graph_kernel_fundamental_cycles(edges, n_isolated):
    """Incidence matrices (parallel edges, isolated vertices, zero columns) use the BFS-forest path."""
    m = 8 + n_isolated
    cols = [np.zeros(m, dtype=np.int64)]  # a zero column: a trivial kernel vector
    for a, b in edges:
        c = np.zeros(m, dtype=np.int64)
        c[a], c[b] = -1, 1
        cols.append(c)
    A = np.stack(cols, axis=1)
    K = integer_kernel_basis(sp.csc_matrix(A))
    assert_saturated_basis_of_kernel(A, K)
    assert abs(K).max() <= 1 if K.nnz else True  # fundamental cycles have coefficients 0, ±1


def test_kernel_large_grid_graph():
    """∂_1 of a 150×150 periodic grid: first Betti number E - V + 1 in well under a second."""
    N = 150
    idx = np.arange(N * N).reshape(N, N)
    e = np.concatenate([np.stack([idx.ravel(), np.roll(idx, -1, 0).ravel()], 1),
                        np.stack([idx.ravel(), np.roll(idx, -1, 1).ravel()], 1)])
    E = len(e)
    d1 = sp.csc_matrix((np.r_[-np.ones(E), np.ones(E)].astype(np.int64),
                        (np.r_[e[:, 0], e[:, 1]], np.r_[np.arange(E), np.arange(E)])), shape=(N * N, E))
    K = integer_kernel_basis(d1)
    assert K.shape == (E, E - N * N + 1)
    assert abs(d1 @ K).max() == 0
    # each basis vector has exactly one non-tree edge: K restricted to the non-tree edges is I
    nontree = np.flatnonzero(np.asarray(abs(K).sum(axis=1)).ravel() == 1)
    assert len(nontree) >= K.shape[1]


# ----------------------------------------------------------------------------- solving
@settings(max_examples=120, deadline=None)
@given(int_matrices(), st.data())
def test_solve_integer_solvable(A, data):
    n = A.shape[1]
    x0 = np.array(data.draw(st.lists(st.integers(-5, 5), min_size=n, max_size=n)), dtype=np.int64)
    b = A @ x0 if n else np.zeros(A.shape[0], dtype=np.int64)
    for M in (A, sp.csr_matrix(A)):
        x = solve_integer(M, b)
        assert x is not None and x.shape == (n,)
        assert np.array_equal(as_obj(A).dot(as_obj(x)), as_obj(b))


@settings(max_examples=80, deadline=None)
@given(int_matrices(max_entry=4), st.data())
def test_solve_integer_none_means_no_solution(A, data):
    """If solve_integer gives None, no integer solution exists (checked through the Smith form)."""
    m = A.shape[0]
    b = np.array(data.draw(st.lists(st.integers(-6, 6), min_size=m, max_size=m)), dtype=np.int64)
    x = solve_integer(A, b)
    U, D, _V = smith_normal_form(A)
    c = as_obj(U).dot(as_obj(b)) if m else np.zeros(0, dtype=object)
    d = [int(D[i, i]) for i in range(min(D.shape)) if D[i, i]]
    solvable = not any(c[len(d):]) and all(c[i] % d[i] == 0 for i in range(len(d)))
    assert (x is not None) == solvable
    if x is not None:
        assert np.array_equal(as_obj(A).dot(as_obj(x)), as_obj(b))


def test_solve_integer_examples_and_large_sparse():
    assert solve_integer([[2, 0], [0, 2]], [1, 0]) is None
    assert solve_integer([[2, 4]], [6]).tolist() in ([3, 0], [-1, 2], [1, 1])
    X = solve_integer([[1, 0], [0, 3]], [[1, 2], [3, 6]])
    assert X.tolist() == [[1, 2], [1, 2]]
    # d_0 of a long path graph (large sparse): integrate an integer 1-form exactly
    n = 30_000
    d0 = sp.diags([-np.ones(n - 1, dtype=np.int64), np.ones(n - 1, dtype=np.int64)], [0, 1],
                  shape=(n - 1, n), format="csr", dtype=np.int64)
    beta = np.arange(n - 1, dtype=np.int64) % 7 - 3
    f = solve_integer(d0, beta)
    assert f is not None and np.array_equal(d0 @ f, beta)
    # and an inconsistent right-hand side on a cycle graph: no solution
    cyc = sp.lil_matrix((n, n), dtype=np.int64)
    cyc[np.arange(n), np.arange(n)] = -1
    cyc[np.arange(n), (np.arange(n) + 1) % n] = 1
    rhs = np.zeros(n, dtype=np.int64)
    rhs[5] = 1
    assert solve_integer(cyc.tocsr(), rhs) is None


# ----------------------------------------------------------------------------- determinants, errors
@settings(max_examples=80, deadline=None)
@given(st.integers(0, 4).flatmap(lambda n: st.lists(st.integers(-5, 5), min_size=n * n, max_size=n * n)))
def test_integer_determinant_matches_sympy(vals):
    n = round(len(vals) ** 0.5)
    A = np.array(vals, dtype=np.int64).reshape(n, n)
    assert integer_determinant(A) == (int(sympy.Matrix(A.tolist()).det()) if n else 1)


def test_bad_input_is_typed():
    with pytest.raises(InvalidMatrixError, match=r"\[0, 1\]"):
        smith_normal_form([[1, 0.5]])
    with pytest.raises(InvalidMatrixError):
        hermite_normal_form([[1, np.nan]])
    with pytest.raises(InvalidMatrixError):
        integer_kernel_basis(np.array([["a"]], dtype=object))
    with pytest.raises(ShapeError):
        smith_normal_form([1, 2, 3])
    with pytest.raises(ShapeError):
        solve_integer([[1, 0]], [1, 2])
    with pytest.raises(ShapeError):
        integer_determinant([[1, 2]])
    with pytest.raises(InvalidMatrixError):
        integer_kernel_basis(sp.csr_matrix(np.array([[0.5, 1.0]])))
    # integral floats are accepted
    assert smith_normal_form(np.array([[2.0, 0.0], [0.0, 3.0]]))[1].tolist() == [[1, 0], [0, 6]]
