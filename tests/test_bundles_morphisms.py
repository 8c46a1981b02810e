"""Morphisms and the classification by monodromy (Theorem 2, Propositions 2, 4, 6)."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.bundles import (
    VectorBundle,
    direct_sum,
    dual,
    find_isomorphism,
    hom,
    is_isomorphic,
    is_morphism,
    tensor,
)
from dhlb.bundles.finite_field import inv_mod
from dhlb.errors import InvalidConnectionError
from tests.strategies import closed_surfaces, rich_complexes, torus7


def random_matrices(rng, n, K, field):
    """n random invertible K×K matrices over the field."""
    if field == "R":
        return rng.standard_normal((n, K, K)) + 3 * np.eye(K)
    if field == "C":
        return rng.standard_normal((n, K, K)) + 1j * rng.standard_normal((n, K, K)) + 3 * np.eye(K)
    p = field[1]
    g = rng.integers(0, p, (n, K, K))
    g[inv_mod(g, p)[1]] = np.eye(K, dtype=np.int64)
    return g


def random_gauge(rng, X, K, field):
    return random_matrices(rng, X.n_vertices, K, field)


def random_bundle(X, rng, K, field):
    return VectorBundle(X, random_matrices(rng, X.n_simplices(1), K, field), field)


def perturbed(E):
    """Multiply the transport of the first loop generator by diag(2, 1, ..): det of its monodromy doubles."""
    eta = np.array(E.transports)
    e = E.forest.nontree[0]
    eta[e][:, 0] *= 2
    if E.ops.exact:
        eta %= E.ops.p
    return VectorBundle(E.X, eta, E.field, metric=E.metric)


FIELDS = st.sampled_from(["R", "C", ("GF", 5), ("GF", 3)])


# ------------------------------------------------------------------ gauge invariance
@settings(max_examples=20, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), FIELDS)
def test_monodromy_conjugated_by_gauge(X, seed, field):
    """Proposition 4/6: gauge g changes the monodromy at the root by conjugation with g_root."""
    rng = np.random.default_rng(seed)
    E = random_bundle(X, rng, 2, field)
    g = random_gauge(rng, X, 2, field)
    F = E.gauge(g)
    ops = E.ops
    ME, MF = E.monodromy_representation(), F.monodromy_representation()
    groot = g[E.forest.roots[E.forest.component[X.simplices(1)[E.forest.nontree, 0]]]] if ME.size else g[:0]
    ginv = ops.inv(groot)[0]
    assert np.all(ops.close(MF, ops.matmul(groot, ops.matmul(ME, ginv))))
    if not ops.exact:  # class functions agree
        assert np.allclose(np.trace(MF, axis1=1, axis2=2), np.trace(ME, axis1=1, axis2=2))


# ------------------------------------------------------------------ isomorphism search
@settings(max_examples=25, deadline=None)
@given(rich_complexes(3), st.integers(0, 2**32 - 1), FIELDS, st.integers(1, 3))
def test_gauge_copies_are_isomorphic_and_perturbed_are_not(X, seed, field, K):
    """Theorem 2: isomorphic ⇔ conjugate monodromy; the isomorphism makes every edge diagram commute."""
    rng = np.random.default_rng(seed)
    E = random_bundle(X, rng, K, field)
    F = E.gauge(random_gauge(rng, X, K, field))
    f = find_isomorphism(E, F, rng=rng)
    assert f is not None and is_morphism(E, F, f)
    assert not np.any(E.ops.inv(f)[1])  # invertible at every vertex
    if E.forest.nontree.size:
        assert find_isomorphism(E, perturbed(F), rng=rng) is None


def test_metric_bundles_rotation_vs_other_rotation():
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])

    def rot(a):
        return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])

    E = VectorBundle(X, [np.eye(2), np.eye(2), rot(0.7)], metric=True)
    F = VectorBundle(X, [rot(0.3), np.eye(2), rot(0.4)], metric=True)  # same total rotation
    G = VectorBundle(X, [np.eye(2), np.eye(2), rot(-0.7)], metric=True)  # conjugate by a reflection
    H = VectorBundle(X, [np.eye(2), np.eye(2), rot(0.8)], metric=True)
    assert is_isomorphic(E, F) and is_isomorphic(E, G) and not is_isomorphic(E, H)


def test_gf_enumeration_detects_non_conjugate_same_characteristic_polynomial():
    """[[1,1],[0,1]] and the identity over GF(2) share char. polynomial but are not conjugate."""
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    J = np.array([[1, 1], [0, 1]])
    I = np.eye(2, dtype=np.int64)
    E = VectorBundle(X, [I, I, J], ("GF", 2))
    assert find_isomorphism(E, VectorBundle.trivial(X, 2, ("GF", 2))) is None
    F = VectorBundle(X, [I, I, np.array([[1, 0], [1, 1]])], ("GF", 2))
    f = find_isomorphism(E, F)
    assert f is not None and is_morphism(E, F, f)


def test_mismatched_bundles_raise():
    X = SimplicialComplex([(0, 1, 2)])
    with pytest.raises(InvalidConnectionError, match="ranks"):
        find_isomorphism(VectorBundle.trivial(X, 1), VectorBundle.trivial(X, 2))
    with pytest.raises(InvalidConnectionError, match="fields"):
        find_isomorphism(VectorBundle.trivial(X, 1), VectorBundle.trivial(X, 1, "C"))
    with pytest.raises(InvalidConnectionError, match="different complexes"):
        find_isomorphism(VectorBundle.trivial(X, 1), VectorBundle.trivial(SimplicialComplex([(0, 1)]), 1))
    with pytest.raises(InvalidConnectionError, match="singular at vertex 1"):
        VectorBundle.trivial(X, 1).gauge(np.array([1.0, 0.0, 1.0]))


# ------------------------------------------------------------------ constructions (Prop. 2)
@settings(max_examples=15, deadline=None)
@given(closed_surfaces(max_moves=2), st.integers(0, 2**32 - 1), st.sampled_from(["R", "C", ("GF", 7)]))
def test_line_bundle_times_dual_is_trivial(surf, seed, field):
    X = SimplicialComplex(surf[0])
    L = random_bundle(X, np.random.default_rng(seed), 1, field)
    assert tensor(L, dual(L)).is_trivial()


@settings(max_examples=15, deadline=None)
@given(rich_complexes(2), st.integers(0, 2**32 - 1))
def test_hom_parallel_sections_are_the_morphisms(X, seed):
    """Prop. 2: parallel sections of Hom(E, F) = F ⊗ E* are exactly the morphisms E → F."""
    rng = np.random.default_rng(seed)
    E = random_bundle(X, rng, 2, "R")
    F = direct_sum(E.gauge(random_gauge(rng, X, 2, "R")), random_bundle(X, rng, 1, "R"))
    P = hom(E, F).parallel_sections()
    assert P.shape[2] >= E.forest.n_components  # at least the inclusion E ≅ E' ⊂ F
    for j in range(P.shape[2]):
        assert is_morphism(E, F, P[:, :, j].reshape(X.n_vertices, 3, 2))


def test_end_bundle_is_not_trivial_in_rank_two():
    """Seed Prop. 2 claims E ⊗ E* is always trivial; false for K >= 2: only the commutant of the
    monodromy is parallel (the identity always is, so E ≅ E)."""
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    R = np.array([[0.0, -1.0], [1.0, 0.0]])
    E = VectorBundle(X, [np.eye(2), np.eye(2), R], metric=True)
    End = tensor(E, dual(E))
    P = End.parallel_sections()
    assert not End.is_trivial() and P.shape[2] == 2  # commutant of a quarter turn: a I + b R
    ident = np.broadcast_to(np.eye(2).ravel(), (3, 4))
    assert End.is_parallel(ident)


def test_tensor_direct_sum_dual_monodromies():
    rng = np.random.default_rng(5)
    X = SimplicialComplex(torus7())
    E, F = random_bundle(X, rng, 2, "C"), random_bundle(X, rng, 3, "C")
    ME, MF = E.monodromy_representation(), F.monodromy_representation()
    MT = tensor(E, F).monodromy_representation()
    assert np.allclose(MT, np.einsum("gij,gkl->gikjl", ME, MF).reshape(-1, 6, 6))
    MS = direct_sum(E, F).monodromy_representation()
    assert np.allclose(MS[:, :2, :2], ME) and np.allclose(MS[:, 2:, 2:], MF) and np.allclose(MS[:, :2, 2:], 0)
    assert np.allclose(dual(E).monodromy_representation(), np.linalg.inv(ME).transpose(0, 2, 1))


def test_gf_line_bundles_on_small_graph_count():
    """Enumerate all GF(p) line bundles on K4 (b₁ = 3): |GF(p)*|^{b₁} isomorphism classes."""
    X = SimplicialComplex(list(itertools.combinations(range(4), 2)))
    for p in (3, 5):
        units = range(1, p)
        bundles = [VectorBundle(X, np.array(c), ("GF", p)) for c in itertools.product(units, repeat=X.n_simplices(1))]
        classes = {tuple(L.monodromy_representation()[:, 0, 0].tolist()) for L in bundles}
        assert len(classes) == (p - 1) ** 3
        # isomorphism search agrees with the class invariant on a sample
        rng = np.random.default_rng(p)
        for i, j in rng.integers(0, len(bundles), (30, 2)):
            same = np.array_equal(bundles[i].monodromy_representation(), bundles[j].monodromy_representation())
            assert is_isomorphic(bundles[i], bundles[j]) == same
