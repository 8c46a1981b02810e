"""The core SimplicialComplex: construction, look-up, boundary maps, bad input."""

from itertools import combinations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import EmptyComplexError, InvalidSimplexError, RaggedInputError, SimplexNotFoundError


def brute_closure(simplices):
    out = set()
    for s in simplices:
        s = tuple(sorted(s))
        for r in range(1, len(s) + 1):
            out.update(combinations(s, r))
    return out


random_complexes = st.lists(
    st.lists(st.integers(0, 9), min_size=1, max_size=5, unique=True), min_size=1, max_size=12
)


@settings(max_examples=60, deadline=None)
@given(random_complexes)
def test_closure_order_and_boundary(simplices):
    X = SimplicialComplex(simplices)
    expected = brute_closure(simplices)
    labels = sorted({v for s in expected for v in s})
    assert X.vertex_labels.tolist() == labels
    total = 0
    for k in range(X.dim + 1):
        rows = X.simplices(k)
        as_labels = [tuple(X.vertex_labels[r].tolist()) for r in rows]
        assert as_labels == sorted(s for s in expected if len(s) == k + 1)  # lexicographic, sorted rows
        total += len(as_labels)
        assert X.index(k, np.asarray(as_labels)[:, ::-1]).tolist() == list(range(len(as_labels)))
    assert total == len(expected)
    for k in range(1, X.dim + 1):
        B = X.boundary(k)
        assert B.shape == (X.n_simplices(k - 1), X.n_simplices(k))
        assert np.issubdtype(B.dtype, np.integer)
        if k >= 2:
            assert abs(X.boundary(k - 1) @ B).sum() == 0  # ∂∂ = 0
        # entries (−1)^i at the face omitting vertex i
        rows = X.simplices(k)
        for col in range(min(3, rows.shape[0])):
            for i in range(k + 1):
                face = np.delete(rows[col], i)
                r = X._row_index(k - 1, face[None, :])[0]
                assert B[r, col] == (-1) ** i
    assert X.euler_characteristic == sum((-1) ** (len(s) - 1) for s in expected)


@settings(max_examples=40, deadline=None)
@given(random_complexes, st.randoms(use_true_random=False))
def test_invariant_under_relabeling(simplices, rnd):
    X = SimplicialComplex(simplices)
    perm = list(range(50))
    rnd.shuffle(perm)
    Y = SimplicialComplex([[perm[v] for v in s] for s in simplices])
    assert X.counts == Y.counts
    assert X.euler_characteristic == Y.euler_characteristic
    assert [m.shape[0] for m in X.maximal_simplices()] == [m.shape[0] for m in Y.maximal_simplices()]


def test_array_input_and_compaction():
    F = np.array([[10, 3, 7], [7, 3, 12]])
    X = SimplicialComplex(F)
    assert X.vertex_labels.tolist() == [3, 7, 10, 12]
    assert X.counts == (4, 5, 2)
    assert X.euler_characteristic == 1
    assert X.index(2, F).tolist() == [0, 1]
    assert X.orientation_of(F).tolist() == [1, -1]  # (10,3,7) is an even permutation of (3,7,10)
    assert X.contains(1, [(3, 12), (10, 12)]).tolist() == [True, False]
    assert X.is_pure


def test_maximal_and_mixed_dimensions():
    X = SimplicialComplex([(0, 1, 2), (2, 3), (5,)])
    maximal = X.maximal_simplices()
    assert maximal[0].tolist() == [[4]]  # compact index of label 5 is 4
    assert X.vertex_labels[maximal[0][0, 0]] == 5
    assert maximal[1].tolist() == [[2, 3]]
    assert not X.is_pure


def test_boundary_zero_and_top():
    X = SimplicialComplex([(0, 1, 2)])
    assert X.boundary(0).shape == (0, 3)
    assert X.boundary(3).shape == (1, 0)
    assert X.coboundary(1).shape == (1, 3)
    assert (X.coboundary(1) != X.boundary(2).T).nnz == 0


def test_large_grid_counts():
    # 3-torus-free check: a Freudenthal cube grid has χ = 1
    m = 6
    idx = np.arange((m + 1) ** 3).reshape(m + 1, m + 1, m + 1)
    base = np.stack(np.meshgrid(*[np.arange(m)] * 3, indexing="ij"), -1).reshape(-1, 3)
    tets = []
    from itertools import permutations

    for p in permutations(range(3)):
        cur = base.copy()
        pts = [cur]
        for ax in p:
            cur = cur.copy()
            cur[:, ax] += 1
            pts.append(cur)
        tets.append(np.stack([idx[q[:, 0], q[:, 1], q[:, 2]] for q in pts], 1))
    X = SimplicialComplex(np.concatenate(tets))
    assert X.counts[3] == 6 * m**3
    assert X.euler_characteristic == 1
    assert abs(X.boundary(2) @ X.boundary(3)).sum() == 0


@pytest.mark.parametrize(
    "bad, err, words",
    [
        ([(0, 1, 1)], InvalidSimplexError, "repeats a vertex"),
        ([(0, -1)], InvalidSimplexError, "non-negative"),
        ([(0, 1.5)], InvalidSimplexError, "integers"),
        ([(0, float("nan"))], InvalidSimplexError, "finite"),
        ([], EmptyComplexError, "no simplices"),
        (np.zeros((0, 3), int), EmptyComplexError, "no simplices"),
        ([()], InvalidSimplexError, "empty"),
        ([("a", "b")], InvalidSimplexError, "integers"),
        (np.array([[0, 1, 1]]), InvalidSimplexError, "(0, 1, 1)"),
        (5, InvalidSimplexError, "iterable"),
        ([(True, False)], InvalidSimplexError, "booleans"),
    ],
)
def test_bad_input(bad, err, words):
    with pytest.raises(err) as info:
        SimplicialComplex(bad)
    assert words in str(info.value)


def test_bad_lookups():
    X = SimplicialComplex([(0, 1, 2)])
    with pytest.raises(SimplexNotFoundError, match=r"\(0, 7\)"):
        X.index(1, [(0, 7)])
    with pytest.raises(SimplexNotFoundError, match="dimension 2"):
        X.index(3, [(0, 1, 2, 3)])
    with pytest.raises(RaggedInputError):
        X.index(1, [(0, 1), (0, 1, 2)])
    with pytest.raises(InvalidSimplexError, match="repeats"):
        X.index(1, [(1, 1)])
    with pytest.raises(InvalidSimplexError, match="2 vertices"):
        X.index(1, [(0, 1, 2)])
    with pytest.raises(ValueError):
        X.boundary(5)
    assert X.simplices(7).shape == (0, 8)


def test_block_input_equals_tuple_input():
    blocks = [np.array([[0, 1, 2], [2, 3, 4]]), np.array([[4, 7]]), np.zeros((0, 2), int), np.array([[9]])]
    tuples = [(0, 1, 2), (2, 3, 4), (4, 7), (9,)]
    assert SimplicialComplex(blocks) == SimplicialComplex(tuples)
    with pytest.raises(InvalidSimplexError, match="repeats"):
        SimplicialComplex([np.array([[0, 1]]), np.array([[3, 3, 4]])])
    with pytest.raises(EmptyComplexError):
        SimplicialComplex([np.zeros((0, 3), int)])
