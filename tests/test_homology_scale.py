"""Homology at scale: the acyclic matching, groups without bases, and the Z/p fast path.

The groups are checked against an oracle that reduces nothing (the Smith form of the full
boundary matrices), the Morse complex against the chain-map identities it must satisfy, the
``Z/p`` dimensions against the universal coefficient theorem and, where gudhi is installed,
against gudhi's persistent homology over the same field.
"""

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb import SimplicialComplex
from dhlb.errors import InvalidParameterError
from dhlb.strategies import closed_manifolds
from dhlb.topology import _homology_bases
from dhlb.topology._homology_bases import check_boundaries
from dhlb.topology._morse import MorseMatching
from dhlb.topology.homology import betti_numbers, cohomology, homology, homology_from_boundaries
from dhlb.topology.intlinalg import smith_normal_form
from tests.homology_complexes import EXPECTED, obj
from tests.strategies import complexes

PRIMES = (2, 3, 5, 7)


def full_smith_groups(X):
    """``(rank, torsion)`` per degree from the Smith forms of the whole boundary matrices (no reduction)."""
    inv = [()]
    for k in range(1, X.dim + 1):
        B = obj(X.boundary(k))
        if B.size:
            _, D, _ = smith_normal_form(B)
            inv.append(tuple(int(D[i, i]) for i in range(min(D.shape)) if D[i, i] != 0))
        else:
            inv.append(())
    inv.append(())
    return [(X.n_simplices(k) - len(inv[k]) - len(inv[k + 1]), tuple(d for d in inv[k + 1] if d > 1))
            for k in range(X.dim + 1)]


def rank_mod_p(A, p):
    """Rank of an integer matrix over Z/p (dense Gaussian elimination)."""
    M = np.asarray(A, dtype=np.int64) % p
    r = 0
    for c in range(M.shape[1]):
        piv = np.flatnonzero(M[r:, c]) + r
        if not len(piv):
            continue
        M[[r, piv[0]]] = M[[piv[0], r]]
        M[r] = M[r] * pow(int(M[r, c]), -1, p) % p
        others = np.flatnonzero(M[:, c])
        others = others[others != r]
        M[others] = (M[others] - np.outer(M[others, c], M[r])) % p
        r += 1
        if r == M.shape[0]:
            break
    return r


def uct_dimensions(groups, p):
    """``dim H_k(Z/p) = b_k + #{t | p divides t in H_k} + #{t | p divides t in H_(k-1)}``."""
    div = [sum(1 for t in tors if t % p == 0) for _, tors in groups]
    return tuple(b + div[k] + (div[k - 1] if k else 0) for k, (b, _) in enumerate(groups))


# ----------------------------------------------------------------------------- the groups
@settings(max_examples=40, deadline=None)
@given(complexes())
def test_groups_equal_the_unreduced_smith_form(X):
    assert [(h.rank, h.torsion) for h in homology(X)] == full_smith_groups(X)


@settings(max_examples=15, deadline=None)
@given(st.integers(2, 4).flatmap(lambda d: closed_manifolds(d, max_moves=2)), st.sampled_from(PRIMES))
def test_manifolds_with_torsion(known, p):
    """RP^3, RP^2 × S^1, lens spaces …: the groups, and over Z/p the universal coefficients."""
    X = known.complex
    expected = [tuple(g) for g in known.homology]
    assert [(h.rank, h.torsion) for h in homology(X)] == expected
    assert betti_numbers(X, p=p) == uct_dimensions(expected, p)


def test_groups_build_no_basis(monkeypatch):
    """``homology`` and ``betti_numbers`` read ranks and torsion; no basis is built until asked."""
    built = []
    real = _homology_bases.HomologyBases.degree

    def spy(self, k):
        built.append(k)
        return real(self, k)

    monkeypatch.setattr(_homology_bases.HomologyBases, "degree", spy)
    X = SimplicialComplex(EXPECTED["RP2"][0])
    H = homology(X)
    assert [str(h) for h in H] == ["Z", "Z/2", "0"] and betti_numbers(X) == (1, 0, 0)
    C = cohomology(X)
    assert [str(c) for c in C] == ["Z", "0", "Z/2"]
    assert built == []
    assert H[1].generators.shape == (X.n_simplices(1), 1)
    assert built == [1]
    assert C[2].cocycles.shape == (X.n_simplices(2), 1)


def test_large_first_betti_number():
    """The flag complex of the issue: 300 vertices, b_1 = 583; generators are independent cycles."""
    X = SimplicialComplex.from_graph(nx.gnp_random_graph(300, 0.02, seed=3), max_dim=2)
    H = homology(X)
    assert [(h.rank, h.torsion) for h in H] == [(1, ()), (583, ()), (0, ())]
    G = H[1].generators
    assert G.shape == (921, 583) and not (X.boundary(1) @ G).any()
    B = X.boundary(2).toarray()
    assert rank_mod_p(np.hstack([B, G]), 3) == rank_mod_p(B, 3) + 583


# ----------------------------------------------------------------------------- the Morse complex
@settings(max_examples=40, deadline=None)
@given(complexes(), st.integers(0, 2**32 - 1))
def test_morse_maps_are_chain_maps_and_dual(X, seed):
    """``∂ ι = ι ∂'``, ``δ π^T = π^T δ'`` and ``⟨π^T φ, ι z⟩ = ⟨φ, z⟩`` for random Morse chains."""
    rng = np.random.default_rng(seed)
    mats = check_boundaries([X.boundary(k) for k in range(X.dim + 1)])
    M = MorseMatching(mats)
    D = [None] + [M.residual(k)[0] for k in range(1, X.dim + 1)]

    def dense(vals, n):
        out = np.zeros(n, dtype=object)
        for c, z in vals.items():
            out[c] = z.get(0, 0)
        return out

    for k in range(X.dim + 1):
        crit = M.critical[k].tolist()
        z = {c: {0: int(v)} for c, v in zip(crit, rng.integers(-3, 4, len(crit))) if v}
        phi = {c: {0: int(v)} for c, v in zip(crit, rng.integers(-3, 4, len(crit))) if v}
        iz = dense(M.lift_chains(k, z), X.n_simplices(k))
        pphi = dense(M.lift_cochains(k, phi), X.n_simplices(k))
        assert pphi.dot(iz) == sum(phi[c][0] * z[c][0] for c in z if c in phi)
        if k >= 1:  # ∂_k ι z = ι_{k-1} ∂'_k z
            dz = {}
            for i, row in D[k].items():
                v = sum(w * z[crit[j]][0] for j, w in row.items() if crit[j] in z)
                if v:
                    dz[int(M.critical[k - 1][i])] = {0: v}
            lhs = obj(X.boundary(k)).dot(iz)
            assert (lhs == dense(M.lift_chains(k - 1, dz), X.n_simplices(k - 1))).all()


# ----------------------------------------------------------------------------- Z/p
@settings(max_examples=40, deadline=None)
@given(complexes(), st.sampled_from(PRIMES))
def test_mod_p_dimensions_follow_universal_coefficients(X, p):
    groups = [(h.rank, h.torsion) for h in homology(X)]
    assert betti_numbers(X, p=p) == uct_dimensions(groups, p)


@pytest.mark.parametrize("name", list(EXPECTED))
@pytest.mark.parametrize("p", PRIMES)
def test_mod_p_dimensions_of_known_complexes(name, p):
    simplices, expected = EXPECTED[name]
    X = SimplicialComplex(simplices)
    dims = uct_dimensions(expected, p)
    assert betti_numbers(X, p=p) == dims
    H = homology(X, f"Z/{p}")
    assert tuple(h.rank for h in H) == dims and all(h.torsion == () and h.coefficients == f"Z/{p}" for h in H)


@settings(max_examples=30, deadline=None)
@given(complexes(), st.sampled_from(PRIMES))
def test_mod_p_generators_are_independent_cycles(X, p):
    """The Z/p generators are cycles mod p, independent modulo the boundaries."""
    for k, h in enumerate(homology(X, ("Z", p))):
        G = h.generators
        assert G.shape == (X.n_simplices(k), h.rank) and G.min(initial=0) >= 0 and G.max(initial=0) < p
        if k:
            assert not ((X.boundary(k) @ G) % p).any()
        B = X.boundary(k + 1).toarray() if k < X.dim else np.zeros((X.n_simplices(k), 0), dtype=np.int64)
        assert rank_mod_p(np.hstack([B, G]), p) == rank_mod_p(B, p) + h.rank


def test_mod_p_from_boundaries_and_large_primes():
    X = SimplicialComplex(EXPECTED["RP2"][0])
    B = [X.boundary(k) for k in range(3)]
    assert [str(h) for h in homology_from_boundaries(B, "Z/2")] == ["Z/2", "Z/2", "Z/2"]
    assert [str(h) for h in homology_from_boundaries(B, ("Z", 2**61 - 1))] == ["Z/2305843009213693951", "0", "0"]


@pytest.mark.parametrize("bad", [4, 1, 0, -3, 2.0, True, "2", 2**64 + 13])
def test_p_must_be_prime(bad):
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    with pytest.raises(InvalidParameterError, match="prime"):
        betti_numbers(X, p=bad)


@pytest.mark.parametrize("bad", ["Z/4", ("Z", 6), "Q", "R", "Z/", 3])
def test_homology_coefficients_are_checked(bad):
    X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    with pytest.raises(InvalidParameterError):
        homology(X, bad)


# ----------------------------------------------------------------------------- gudhi as an oracle
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("p", [2, 3])
def test_flag_complexes_against_gudhi(seed, p):
    gudhi = pytest.importorskip("gudhi", reason="gudhi is the oracle here (pip install gudhi)")
    G = nx.gnp_random_graph(40 + 8 * seed, 0.3, seed=seed)
    X = SimplicialComplex.from_graph(G, max_dim=3)
    st_ = gudhi.SimplexTree()
    for v in G.nodes:
        st_.insert([v])
    for u, v in G.edges:
        st_.insert([u, v])
    st_.expansion(3)
    st_.compute_persistence(homology_coeff_field=p, persistence_dim_max=True)
    expected = tuple(st_.betti_numbers()) + (0,) * (X.dim + 1 - len(st_.betti_numbers()))
    assert betti_numbers(X, p=p) == expected[: X.dim + 1]


# ----------------------------------------------------------------------------- chain complexes beyond simplicial ones
@st.composite
def integer_chain_complexes(draw):
    """``[∂_0, ∂_1, ∂_2]`` with small entries (units, 2s, 3s): ∂_2 = K R for a kernel basis K of ∂_1."""
    from dhlb.topology.intlinalg import integer_kernel_basis

    m, n = draw(st.integers(1, 6)), draw(st.integers(1, 7))
    A = np.array(draw(st.lists(st.integers(-3, 3), min_size=m * n, max_size=m * n)), dtype=np.int64).reshape(m, n)
    K = np.asarray(obj(integer_kernel_basis(A)), dtype=np.int64)
    c = draw(st.integers(0, 4))
    R = np.array(draw(st.lists(st.integers(-2, 2), min_size=K.shape[1] * c, max_size=K.shape[1] * c)),
                 dtype=np.int64).reshape(K.shape[1], c)
    return [np.zeros((0, m), dtype=np.int64), A, K @ R]


def smith_groups_of(mats):
    inv = [()]
    for B in mats[1:]:
        if B.size:
            _, D, _ = smith_normal_form(B)
            inv.append(tuple(int(D[i, i]) for i in range(min(D.shape)) if D[i, i] != 0))
        else:
            inv.append(())
    inv.append(())
    sizes = [mats[0].shape[1]] + [B.shape[1] for B in mats[1:]]
    return [(sizes[k] - len(inv[k]) - len(inv[k + 1]), tuple(d for d in inv[k + 1] if d > 1))
            for k in range(len(sizes))]


@settings(max_examples=60, deadline=None)
@given(integer_chain_complexes(), st.sampled_from(PRIMES))
def test_chain_complexes_with_non_unit_entries(mats, p):
    """Entries 2 and 3 leave pairs the matching must not take; groups, generators and Z/p still agree."""
    H = homology_from_boundaries(mats)
    groups = smith_groups_of(mats)
    assert [(h.rank, h.torsion) for h in H] == groups
    for k, h in enumerate(H):
        G = h.generators
        assert G.shape == (mats[k].shape[1], h.rank + len(h.torsion))
        if k:
            assert not (mats[k] @ G).any()
    Hp = homology_from_boundaries(mats, ("Z", p))
    assert tuple(h.rank for h in Hp) == uct_dimensions(groups, p)
