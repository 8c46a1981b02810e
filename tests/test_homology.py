"""Integral homology and cohomology (Z, R, Z/m, S¹) against hand-made complexes and theorems."""

from math import gcd

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
    cohomology_from_boundaries,
    homology,
    homology_from_boundaries,
)
from dhlb.topology.intlinalg import integer_kernel_basis, smith_normal_form, solve_integer
from tests.strategies import balls, closed_manifolds, closed_surfaces, complexes


# ----------------------------------------------------------------------------- explicit complexes
def polygon_word(word, n=3):
    """A triangle-free polygon whose sides, read around the boundary, are the letters of ``word``
    (``'a'`` or ``'A'`` = a⁻¹), every side glued to one loop ``a`` cut into ``n`` edges.  The disc is
    an annulus of fresh vertices ``q`` plus a cone from a centre, so the result is simplicial."""
    loop = list(range(n))
    boundary = []
    for letter in word:
        boundary += loop if letter == "a" else [loop[0]] + loop[:0:-1]
    L = len(boundary)
    q = [n + t for t in range(L)]
    centre = n + L
    tris = []
    for t in range(L):
        p0, p1 = boundary[t], boundary[(t + 1) % L]
        tris += [(p0, p1, q[t]), (p1, q[(t + 1) % L], q[t]), (centre, q[t], q[(t + 1) % L])]
    return tris


CIRCLE = [(0, 1), (1, 2), (0, 2)]
SPHERE = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]
TORUS7 = [(i, (i + 1) % 7, (i + 3) % 7) for i in range(7)] + [(i, (i + 2) % 7, (i + 3) % 7) for i in range(7)]
RP2 = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 1, 5), (1, 2, 4), (2, 3, 5), (1, 3, 4), (1, 3, 5), (2, 4, 5)]
# Klein bottle: 3×3 grid of squares (vertex (i, j) = 3i + j), the j-direction glued with a flip i -> -i
KLEIN = []
for _i in range(3):
    for _j in range(3):
        def _lab(i, j):
            return ((-i if j >= 3 else i) % 3) * 3 + j % 3
        _a, _b, _c, _d = _lab(_i, _j), _lab(_i + 1, _j), _lab(_i + 1, _j + 1), _lab(_i, _j + 1)
        KLEIN += [(_a, _b, _c), (_a, _c, _d)]
DUNCE_HAT = polygon_word("aaA")
PSEUDO_PROJECTIVE_3 = polygon_word("aaa")  # H_1 = Z/3
S3 = [tuple(c) for c in __import__("itertools").combinations(range(5), 4)]

EXPECTED = {
    "point": ([(0,)], [(1, ())]),
    "two points": ([(0,), (1,)], [(2, ())]),
    "circle": (CIRCLE, [(1, ()), (1, ())]),
    "S2": (SPHERE, [(1, ()), (0, ()), (1, ())]),
    "torus": (TORUS7, [(1, ()), (2, ()), (1, ())]),
    "RP2": (RP2, [(1, ()), (0, (2,)), (0, ())]),
    "Klein bottle": (KLEIN, [(1, ()), (1, (2,)), (0, ())]),
    "dunce hat": (DUNCE_HAT, [(1, ()), (0, ()), (0, ())]),
    "Z/3 Moore space": (PSEUDO_PROJECTIVE_3, [(1, ()), (0, (3,)), (0, ())]),
    "S3": (S3, [(1, ()), (0, ()), (0, ()), (1, ())]),
    "torus ∨ circle ⊔ point": (TORUS7 + [(0, 7), (7, 8), (0, 8), (9,)], [(2, ()), (3, ()), (1, ())]),
}


def obj(A):
    return np.asarray(A.toarray() if sp.issparse(A) else A, dtype=object)


def boundaries(X):
    return [X.boundary(k) for k in range(X.dim + 1)]


def coboundary(X, k):
    """d_k = ∂_{k+1}ᵀ (zero map above the top dimension)."""
    if k + 1 <= X.dim:
        return obj(X.boundary(k + 1).T)
    return np.zeros((0, X.n_simplices(k)), dtype=object)


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


# ----------------------------------------------------------------------------- cohomology
def rank_mod_p(A, p):
    M = [[int(x) % p for x in row] for row in obj(A)]
    r, cols = 0, len(M[0]) if M else 0
    for c in range(cols):
        piv = next((i for i in range(r, len(M)) if M[i][c]), None)
        if piv is None:
            continue
        M[r], M[piv] = M[piv], M[r]
        inv = pow(M[r][c], -1, p)
        M[r] = [x * inv % p for x in M[r]]
        for i in range(len(M)):
            if i != r and M[i][c]:
                f = M[i][c]
                M[i] = [(x - f * y) % p for x, y in zip(M[i], M[r])]
        r += 1
    return r


@pytest.mark.parametrize("name", ["circle", "S2", "torus", "RP2", "Klein bottle", "dunce hat",
                                  "Z/3 Moore space", "torus ∨ circle ⊔ point"])
def test_integral_cohomology_universal_coefficients(name):
    X = SimplicialComplex(EXPECTED[name][0])
    H = homology(X)
    C = cohomology(X, "Z")
    for k, c in enumerate(C):
        # H^k = Hom(H_k, Z) ⊕ Ext(H_{k-1}, Z) = Z^{b_k} ⊕ T_{k-1}
        assert c.rank == H[k].rank and c.torsion == (H[k - 1].torsion if k else ())
        W = obj(c.cocycles)
        assert W.shape == (X.n_simplices(k), c.rank + len(c.torsion)) and c.n_hom == c.rank
        assert not coboundary(X, k).dot(W).any()  # cocycles
        # the free cocycles are the dual basis of the free cycles (Kronecker pairing)
        pair = W[:, :c.rank].T.dot(obj(H[k].generators))
        assert np.array_equal(pair, np.concatenate([np.eye(c.rank, dtype=object),
                                                    np.zeros((c.rank, len(H[k].torsion)), dtype=object)], 1))
        # torsion cocycle of order d: d τ exact, (d/p) τ not
        dprev = coboundary(X, k - 1) if k else np.zeros((X.n_simplices(0), 0), dtype=object)
        for j, d in enumerate(c.torsion):
            tau = W[:, c.rank + j]
            assert solve_integer(dprev, d * tau) is not None
            for p in sympy.primefactors(d):
                assert solve_integer(dprev, (d // p) * tau) is None
    assert [str(c) for c in cohomology(SimplicialComplex(RP2), "Z")] == ["Z", "0", "Z/2"]


@pytest.mark.parametrize("name", ["RP2", "Klein bottle", "torus", "Z/3 Moore space", "dunce hat", "S3"])
@pytest.mark.parametrize("m", [2, 3, 4, 6])
def test_cohomology_mod_m(name, m):
    X = SimplicialComplex(EXPECTED[name][0])
    H = homology(X)
    C = cohomology(X, ("Z", m))
    for k, c in enumerate(C):
        expected = [m] * H[k].rank + [gcd(d, m) for d in H[k].torsion if gcd(d, m) > 1]
        n_hom = len(expected)
        expected += [gcd(d, m) for d in (H[k - 1].torsion if k else ()) if gcd(d, m) > 1]
        assert c.torsion == tuple(expected) and c.n_hom == n_hom and c.rank == 0
        assert c.coefficients == f"Z/{m}"
        W = obj(c.cocycles)
        assert W.shape == (X.n_simplices(k), len(expected)) and ((W >= 0) & (W < m)).all()
        assert not (coboundary(X, k).dot(W) % m).any()  # cocycles mod m
        if sympy.isprime(m):  # dimension over the field F_p from ranks mod p
            n = X.n_simplices(k)
            rk = rank_mod_p(X.boundary(k).toarray(), m) if k else 0
            rk1 = rank_mod_p(X.boundary(k + 1).toarray(), m) if k < X.dim else 0
            assert len(c.torsion) == n - rk - rk1
    assert cohomology(X, f"Z/{m}")[0].torsion == C[0].torsion


@pytest.mark.parametrize("name", ["RP2", "Klein bottle", "torus", "Z/3 Moore space", "circle"])
def test_cohomology_real_and_circle(name):
    X = SimplicialComplex(EXPECTED[name][0])
    H = homology(X)
    R = cohomology(X, "R")
    S = cohomology(X, "S1")
    for k in range(X.dim + 1):
        assert R[k].rank == H[k].rank and R[k].cocycles.dtype == float
        assert np.allclose(coboundary(X, k).astype(float) @ R[k].cocycles, 0)
        # H^k(X; S¹) = Hom(H_k, S¹) = (S¹)^{b_k} × torsion of H_k
        s = S[k]
        assert s.rank == H[k].rank and s.torsion == H[k].torsion
        angles = s.cocycles[:, s.rank:]
        assert np.all((angles > -np.pi - 1e-12) & (angles <= np.pi + 1e-12))
        dtheta = coboundary(X, k).astype(float) @ s.cocycles
        assert np.allclose(np.exp(1j * dtheta), 1)  # flat: S¹-cocycles
        # finite part: holonomy 2π/d on its torsion generator, 0 on the other generators
        vals = H[k].generators.T.astype(float) @ angles
        expected = np.zeros_like(vals)
        for j, d in enumerate(s.torsion):
            expected[H[k].rank + j, j] = 2 * np.pi / d
        assert np.allclose(np.exp(1j * vals), np.exp(1j * expected))


def test_rp2_flat_bundle_has_holonomy_pi():
    X = SimplicialComplex(RP2)
    H1 = cohomology(X, "S1")[1]
    assert str(H1) == "Z/2" and H1.rank == 0 and H1.torsion == (2,)
    z = homology(X)[1].generators[:, 0]
    theta = H1.cocycles[:, 0]
    assert set(np.round(np.abs(theta), 12)) <= {0.0, round(np.pi, 12)}
    assert np.isclose(np.cos(z @ theta), -1.0)
    assert str(cohomology(SimplicialComplex(TORUS7), "S1")[1]) == "(S¹)^2"
    assert str(cohomology(SimplicialComplex(KLEIN), "S1")[1]) == "S¹ × Z/2"


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
    for bad in ["Q", ("Z", 1), ("Z", 2.0), "Z/x", ("R", 2)]:
        with pytest.raises(InvalidMatrixError, match="coefficients"):
            cohomology(X, bad)
    assert [str(c) for c in cohomology_from_boundaries(B, "Z/2")] == ["Z/2", "0", "Z/2"]
