"""Derivations (sympy) of the closed forms used by dhlb.strategies, cross-checked on the constructions.

* face counts of the mesh families and their Euler characteristics (``dhlb/strategies/meshes.py``);
* the degree of ``(exp(iω), dω + 2πm)`` on a closed oriented surface is ``Σ_t o_t m_t``
  (``dhlb/strategies/bundles.py``);
* the homology records of the product seeds follow from Künneth's formula
  (``dhlb/strategies/complexes.py``).
"""

from __future__ import annotations

import itertools
from math import gcd

import numpy as np
import pytest
import sympy as sp

from dhlb import SimplicialComplex
from dhlb.strategies import _seeds as sd
from dhlb.strategies.complexes import _seeds
from dhlb.strategies.meshes import _board, _board_squares, _torus, _uv_sphere


def _euler(F) -> int:
    """V − E + F of a triangle list, counted directly (no dhlb)."""
    F = np.asarray(F)
    E = {tuple(sorted(e)) for t in F.tolist() for e in itertools.combinations(t, 2)}
    return len(np.unique(F)) - len(E) + len(F)


def test_board_face_count_derivation():
    g, sx, sy, sz = sp.symbols("g s_x s_y s_z", positive=True, integer=True)
    # cross-section of the board: (2g+1) × 3 cells minus g holes; boundary edges of the cross-section
    cells = (2 * g + 1) * 3 - g
    x_edges = 2 * 3 + 2 * g  # edges with normal ±x: two outer sides of length 3 and two per hole
    y_edges = 2 * (2 * g + 1) + 2 * g  # normal ±y: two outer sides of length 2g+1 and two per hole
    squares = 2 * cells * sx * sy + x_edges * sy * sz + y_edges * sx * sz  # top/bottom + walls (height 1)
    assert sp.expand(squares - _board_squares(g, sx, sy, sz)) == 0
    for gv, s in itertools.product(range(4), itertools.product(range(1, 3), repeat=3)):
        _, F, _ = _board(gv, *s, None)
        assert len(F) == 2 * _board_squares(gv, *s)
        assert _euler(F) == 2 - 2 * gv


def test_sphere_and_torus_counts():
    nu, nv = sp.symbols("n_u n_v", positive=True, integer=True)
    Fs = 2 * nu * (nv - 1)  # two fans of nu triangles and nv − 2 bands of 2 nu
    Vs = 2 + nu * (nv - 1)
    assert sp.simplify(Vs - sp.Rational(3, 2) * Fs + Fs) == 2  # closed: E = 3F/2
    Ft, Vt = 2 * nu * nv, nu * nv
    assert sp.simplify(Vt - sp.Rational(3, 2) * Ft + Ft) == 0
    for a, b in [(3, 2), (4, 5), (7, 3)]:
        V, F = _uv_sphere(a, b)
        assert len(F) == Fs.subs({nu: a, nv: b}) and len(V) == Vs.subs({nu: a, nv: b}) and _euler(F) == 2
    for a, b in [(3, 3), (5, 4)]:
        assert len(_torus(a, b)[1]) == Ft.subs({nu: a, nv: b}) and _euler(_torus(a, b)[1]) == 0


@pytest.mark.parametrize("tris", [sd.sphere(2), sd.torus7(), sd.connected_sum(sd.torus7(), sd.torus7())])
def test_degree_is_the_oriented_sum_of_m(tris):
    X = SimplicialComplex(tris)
    w = sp.symbols(f"w0:{X.n_simplices(1)}")
    m = sp.symbols(f"m0:{X.n_simplices(2)}", integer=True)
    d1 = sp.Matrix(X.boundary(2).T.toarray().tolist())
    o = X.orientation().tolist()
    Omega = d1 * sp.Matrix(w) + 2 * sp.pi * sp.Matrix(m)
    degree = sp.expand(sum(oi * Oi for oi, Oi in zip(o, Omega)) / (2 * sp.pi))
    assert degree == sp.expand(sum(oi * mi for oi, mi in zip(o, m)))  # the ω terms cancel: ∂(Σ o_t t) = 0


# ----------------------------------------------------------------------------- Künneth
def _tensor(A, B):
    (ra, ta), (rb, tb) = A, B
    tors = [t for t in ta for _ in range(rb)] + [t for t in tb for _ in range(ra)]
    tors += [gcd(a, b) for a in ta for b in tb if gcd(a, b) > 1]
    return ra * rb, tors


def _tor(A, B):
    return [gcd(a, b) for a in A[1] for b in B[1] if gcd(a, b) > 1]


def kunneth(HA, HB):
    """H_n(A × B) = ⊕_{i+j=n} H_i ⊗ H_j ⊕ ⊕_{i+j=n−1} Tor(H_i, H_j), as (rank, sorted torsion)."""
    out = []
    for n in range(len(HA) + len(HB) - 1):
        rank, tors = 0, []
        for i in range(len(HA)):
            j = n - i
            if 0 <= j < len(HB):
                r, t = _tensor(HA[i], HB[j])
                rank, tors = rank + r, tors + t
            if 0 <= n - 1 - i < len(HB):
                tors += _tor(HA[i], HB[n - 1 - i])
        out.append((rank, tuple(sorted(tors))))
    return tuple(out)


SPHERE = {n: tuple((1 if k in (0, n) else 0, ()) for k in range(n + 1)) for n in (1, 2, 3)}
RP2 = ((1, ()), (0, (2,)), (0, ()))


@pytest.mark.parametrize("dim, key, factors", [
    (3, "product(S1,S2)", (SPHERE[1], SPHERE[2])),
    (3, "product(rp2,S1)", (RP2, SPHERE[1])),
    (4, "product(S1,S3)", (SPHERE[1], SPHERE[3])),
    (4, "product(S2,S2)", (SPHERE[2], SPHERE[2])),
    (3, "kuhn(3,3,3)", (SPHERE[1], SPHERE[1], SPHERE[1])),
])
def test_product_records_follow_from_kunneth(dim, key, factors):
    seed = next(s for s in _seeds(dim) if s.key == key)
    H = factors[0]
    for f in factors[1:]:
        H = kunneth(H, f)
    assert seed.homology == H
    assert seed.euler == sum((-1) ** k * r for k, (r, _) in enumerate(H))
