"""Discrete vector bundles with connection: transport, monodromy, parallel sections, π₁ (seed part 3, §3–§4)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import VectorBundle, spanning_forest
from dhlb.bundles.paths import fundamental_cycles, loop_group_presentation
from dhlb.errors import InvalidConnectionError, NotAPathError
from dhlb.topology.homology import homology
from dhlb.topology.intlinalg import smith_normal_form
from tests.strategies import closed_surfaces, rich_complexes, rp2, torus7


def random_orthogonal(rng, n, K):
    Q, R = np.linalg.qr(rng.standard_normal((n, K, K)))
    return Q * np.sign(np.diagonal(R, axis1=1, axis2=2))[:, None, :]


def random_bundle(X, rng, K=2, field="R", metric=False):
    n1 = X.n_simplices(1)
    if field == "R":
        eta = random_orthogonal(rng, n1, K) if metric else rng.standard_normal((n1, K, K)) + 3 * np.eye(K)
    elif field == "C":
        eta = rng.standard_normal((n1, K, K)) + 1j * rng.standard_normal((n1, K, K)) + 3 * np.eye(K)
    else:
        p = field[1]
        eta = (rng.integers(0, p, (n1, K, K)) + np.eye(K, dtype=np.int64)) % p
        from dhlb.bundles.finite_field import inv_mod

        bad = inv_mod(eta, p)[1]
        eta[bad] = np.eye(K, dtype=np.int64)
    return VectorBundle(X, eta, field, metric=metric)


def tree_path(T, v):
    """Vertices root -> v along the forest."""
    out = [v]
    while T.parent[out[-1]] >= 0:
        out.append(int(T.parent[out[-1]]))
    return out[::-1]


def generator_loop(X, T, g):
    u, v = X.simplices(1)[T.nontree[g]]
    return tree_path(T, int(u)) + tree_path(T, int(v))[::-1]


CIRCLE = SimplicialComplex([(0, 1), (1, 2), (0, 2)])


# ------------------------------------------------------------------ construction and errors
def test_rank_one_shorthand_and_read_only():
    E = VectorBundle(CIRCLE, [2.0, 1.0, 1.0])
    assert E.rank == 1 and E.transports.shape == (3, 1, 1)
    with pytest.raises(ValueError):
        E.transports[0, 0, 0] = 5.0


def test_singular_transport_names_edge():
    eta = np.stack([np.eye(2), np.eye(2), np.array([[1.0, 2.0], [2.0, 4.0]])])
    with pytest.raises(InvalidConnectionError, match=r"edge \(1, 2\)"):
        VectorBundle(CIRCLE, eta)


def test_non_orthogonal_metric_transport_names_edge():
    eta = np.stack([np.eye(2), 1.01 * np.eye(2), np.eye(2)])
    with pytest.raises(InvalidConnectionError, match=r"edge \(0, 2\).*not orthogonal"):
        VectorBundle(CIRCLE, eta, metric=True)
    with pytest.raises(InvalidConnectionError, match="unitary"):
        VectorBundle(CIRCLE, np.array([1, 1, 1j * 1.1]), "C", metric=True)


@pytest.mark.parametrize("bad", [np.ones((3, 2, 3)), np.ones((2, 1, 1)), np.ones((3, 0, 0))])
def test_wrong_shape(bad):
    with pytest.raises(InvalidConnectionError, match="shape"):
        VectorBundle(CIRCLE, bad)


def test_bad_fields():
    with pytest.raises(InvalidConnectionError, match="prime"):
        VectorBundle(CIRCLE, [1, 1, 1], ("GF", 4))
    with pytest.raises(InvalidConnectionError, match="unknown field"):
        VectorBundle(CIRCLE, [1, 1, 1], "Q")
    with pytest.raises(InvalidConnectionError, match="not invertible"):
        VectorBundle(CIRCLE, [1, 5, 1], ("GF", 5))
    with pytest.raises(InvalidConnectionError, match="metric"):
        VectorBundle(CIRCLE, [1, 1, 1], ("GF", 5), metric=True)


def test_not_a_path_names_missing_edge():
    X = SimplicialComplex([(0, 1), (1, 2), (2, 3)])
    E = VectorBundle.trivial(X, 1)
    with pytest.raises(NotAPathError, match=r"\(1, 3\) is not an edge"):
        E.transport([0, 1, 3], np.ones(1))
    with pytest.raises(NotAPathError, match="not a vertex"):
        E.transport([0, 9], np.ones(1))
    with pytest.raises(NotAPathError, match=r"\(1, 1\)"):
        E.transport([0, 1, 1], np.ones(1))
    with pytest.raises(NotAPathError, match="start and end"):
        E.monodromy([0, 1, 2])


# ------------------------------------------------------------------ transport and monodromy
def test_transport_composes_and_inverts():
    rng = np.random.default_rng(3)
    E = random_bundle(SimplicialComplex(torus7()), rng, K=3)
    v = rng.standard_normal(3)
    w = E.transport([0, 1, 2], v)
    assert np.allclose(E.transport([2, 1, 0], w), v)
    assert np.allclose(E.transport([0, 1, 2, 0], v), E.monodromy([0, 1, 2, 0]) @ v)
    assert np.allclose(E.edge_transport(2, 1), np.linalg.inv(E.edge_transport(1, 2)))


def test_circle_rotation_monodromy_exact():
    R = np.array([[0.0, -1.0], [1.0, 0.0]])
    E = VectorBundle(CIRCLE, [np.eye(2), np.eye(2), R], metric=True)
    assert np.allclose(E.monodromy([0, 1, 2, 0]), R)
    assert np.allclose(E.monodromy([0, 2, 1, 0]), R.T)
    assert E.parallel_sections().shape == (3, 2, 0) and not E.is_trivial()


@settings(max_examples=15, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), st.sampled_from(["R", "C", ("GF", 7)]))
def test_generator_monodromy_matches_loops(X, seed, field):
    rng = np.random.default_rng(seed)
    E = random_bundle(X, rng, K=2, field=field)
    T = E.forest
    M = E.monodromy_representation()
    assert M.shape == (T.nontree.size, 2, 2)
    for g in range(min(T.nontree.size, 4)):
        loop = generator_loop(X, T, g)
        assert np.all(E.ops.close(E.monodromy(loop), M[g]))


@settings(max_examples=15, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1))
def test_from_monodromy_realizes_representation(X, seed):
    """Theorem 2, surjectivity: any matrices on the generators are a monodromy."""
    rng = np.random.default_rng(seed)
    m = spanning_forest(X).nontree.size
    M = rng.standard_normal((m, 2, 2)) + 3 * np.eye(2)
    E = VectorBundle.from_monodromy(X, M)
    assert np.allclose(E.monodromy_representation(), M)


# ------------------------------------------------------------------ parallel sections
@settings(max_examples=15, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1))
def test_parallel_sections_are_parallel_and_complete(X, seed):
    """Parallel sections of a bundle with monodromy fixing a known subspace."""
    rng = np.random.default_rng(seed)
    T = spanning_forest(X)
    m = T.nontree.size
    # monodromies fixing e_0 (block upper triangular with 1 in the corner): >= 1 parallel section per component
    M = rng.standard_normal((m, 3, 3)) + 3 * np.eye(3)
    M[:, :, 0] = 0
    M[:, 0, 0] = 1
    E = VectorBundle.from_monodromy(X, M)
    E = E.gauge(rng.standard_normal((X.n_vertices, 3, 3)) + 3 * np.eye(3))
    P = E.parallel_sections()
    assert P.shape[2] >= T.n_components
    for j in range(P.shape[2]):
        assert E.is_parallel(P[:, :, j])
    # generically the fixed space of the generators is exactly span(e_0): one section per
    # component with a loop, three per tree component
    has_loop = np.zeros(T.n_components, bool)
    has_loop[T.component[X.simplices(1)[T.nontree, 0]]] = True
    assert P.shape[2] == int(np.sum(np.where(has_loop, 1, 3)))


def test_trivial_iff_K_parallel_sections():
    """Proposition 1."""
    rng = np.random.default_rng(0)
    X = SimplicialComplex(torus7())
    E = VectorBundle.trivial(X, 2).gauge(random_orthogonal(rng, X.n_vertices, 2))
    assert E.is_trivial() and E.parallel_sections().shape[2] == 2
    assert not random_bundle(X, rng, K=2).is_trivial()
    two = SimplicialComplex([(0, 1, 2), (3, 4)])
    assert VectorBundle.trivial(two, 2).is_trivial()
    assert VectorBundle.trivial(two, 2).parallel_sections().shape[2] == 4


def test_gf_parallel_sections_exact():
    p = 5
    E = VectorBundle(CIRCLE, np.array([[[1, 1], [0, 1]], [[1, 0], [0, 1]], [[1, 0], [0, 1]]]), ("GF", p))
    P = E.parallel_sections()
    assert P.shape[2] == 1 and E.is_parallel(P[:, :, 0])
    assert P.dtype == np.int64 and np.all((P >= 0) & (P < p))


# ------------------------------------------------------------------ π₁ and flatness
@settings(max_examples=20, deadline=None)
@given(rich_complexes(3))
def test_presentation_abelianizes_to_h1(X):
    """Relators of the triangle loops abelianize to H₁(X; Z) (generators: non-tree edges)."""
    if X.dim == 0:
        return
    P = loop_group_presentation(X, spanning_forest(X))
    m = P.n_generators
    R = np.zeros((len(P.relators), m), np.int64)
    for i, word in enumerate(P.relators):
        for g, s in word:
            R[i, g] += s
    H1 = homology(X)[1]
    if m == 0:
        assert H1.rank == 0 and H1.torsion == ()
        return
    _, D, _ = smith_normal_form(R) if R.shape[0] else (None, np.zeros((0, m), np.int64), None)
    diag = [int(D[i, i]) for i in range(min(D.shape))]
    nonzero = [d for d in diag if d != 0]
    assert m - len(nonzero) == H1.rank
    assert tuple(d for d in nonzero if d > 1) == tuple(H1.torsion)


def test_fundamental_cycles_basis_of_ker_d1():
    X = SimplicialComplex(torus7())
    T = spanning_forest(X)
    Z = fundamental_cycles(X, T).toarray()
    assert Z.shape == (X.n_simplices(1) - X.n_vertices + 1, X.n_simplices(1))
    assert not np.any(X.boundary(1) @ Z.T)
    assert np.array_equal(Z[:, T.nontree], np.eye(T.nontree.size, dtype=np.int64))


def test_flat_representation_satisfies_relators_rp2():
    from dhlb.bundles import flat_line_bundles

    X = SimplicialComplex(rp2())
    for L in flat_line_bundles(X):
        E = L.vector_bundle()
        P, M = E.fundamental_group_representation()
        for word in P.relators:
            prod = np.eye(1)
            for g, s in word:
                prod = (M[g] if s > 0 else np.linalg.inv(M[g])) @ prod
            assert np.allclose(prod, np.eye(1))
    R = np.array([[0.0, -1.0], [1.0, 0.0]])
    with pytest.raises(InvalidConnectionError, match="not flat"):
        VectorBundle(SimplicialComplex([(0, 1, 2)]), [np.eye(2), np.eye(2), R]).fundamental_group_representation()


@settings(max_examples=10, deadline=None)
@given(closed_surfaces(max_moves=3), st.integers(0, 2**32 - 1))
def test_triangle_monodromy_is_loop_monodromy(surf, seed):
    X = SimplicialComplex(surf[0])
    E = random_bundle(X, np.random.default_rng(seed), K=2, metric=True)
    H = E.triangle_monodromy()
    for t in range(0, X.n_simplices(2), 7):
        a, b, c = X.simplices(2)[t]
        assert np.allclose(H[t], E.monodromy([a, b, c, a]))


def test_rebased_monodromy_is_conjugate_by_transport():
    """Changing the base vertex conjugates the generator monodromies by a path transport."""
    rng = np.random.default_rng(11)
    X = SimplicialComplex(torus7())
    E = random_bundle(X, rng, K=2, metric=True)
    T = spanning_forest(X, base=4)
    M4 = E.monodromy_representation(base=4)
    for g in range(T.nontree.size):
        loop = generator_loop(X, T, g)
        assert loop[0] == 4 and np.allclose(E.monodromy(loop), M4[g])
        P = E.transport(tree_path(E.forest, 4), np.eye(2))  # root 0 -> 4
        based_at_root = tree_path(E.forest, 4) + loop[1:] + tree_path(E.forest, 4)[::-1][1:]
        assert np.allclose(E.monodromy(based_at_root), np.linalg.inv(P) @ M4[g] @ P)
