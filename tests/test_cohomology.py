"""Cohomology with coefficients Z, R, Z/m and S¹ against homology and the universal coefficient theorem.

The complexes are in ``tests/homology_complexes.py``; integral homology is tested in ``test_homology.py``.
"""

from math import gcd

import numpy as np
import pytest
import sympy

from dhlb import SimplicialComplex
from dhlb.errors import InvalidMatrixError
from dhlb.topology.homology import cohomology, cohomology_from_boundaries, homology
from dhlb.topology.intlinalg import solve_integer
from tests.homology_complexes import EXPECTED, KLEIN, RP2, SPHERE, TORUS7, boundaries, coboundary, obj


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


# ----------------------------------------------------------------------------- bad input
def test_bad_coefficients():
    X = SimplicialComplex(SPHERE)
    B = boundaries(X)
    for bad in ["Q", ("Z", 1), ("Z", 2.0), "Z/x", ("R", 2)]:
        with pytest.raises(InvalidMatrixError, match="coefficients"):
            cohomology(X, bad)
    assert [str(c) for c in cohomology_from_boundaries(B, "Z/2")] == ["Z/2", "0", "Z/2"]
