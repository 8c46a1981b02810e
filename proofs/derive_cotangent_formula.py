r"""Theorem 16 (cotangent formula), Lemma 8 and Eq. 11.1 / Definition 16 (seed part 3, §11).

From the definitions (barycentric coordinates x_i of a Euclidean simplex σ, their gradients, the
dihedral angle α_ij between the facets σ∖{i} and σ∖{j}, heights h_i, volumes):

1. Lemma 8: ``grad x_i = -N_i / h_i`` (N_i the outward unit normal of σ∖{i}) -- exact, n = 2, 3.
2. Theorem 16: ``c_ij = ∫_σ <dx_i, dx_j> = -cot α_ij vol(σ∖{i,j}) / (n(n-1))`` (i ≠ j) and
   ``c_ii = vol(σ∖{i}) / (n h_i)``.  n = 2 fully symbolic (general triangle); n = 3 exact
   arithmetic on random rational tetrahedra; n = 4 numerically.  The dihedral angle is computed
   from the facets themselves (components of facet vectors orthogonal to the common ridge), not
   from the barycentric gradients.
3. The identities of the proof: ``n vol σ = h_i vol(σ∖{i})`` and
   ``n! sin α_ij vol σ = (n-2)! h_i h_j vol(σ∖{i,j})`` hold; the printed
   ``n! vol σ = (n-2)! h_i h_j sin α_ij vol(σ∖{i,j})`` is false (counterexamples, n = 2 and 3).
4. Eq. 11.1 (polarization): ``S^f`` satisfies ``S^f(P_j - P_i, P_j - P_i) = f_ij`` for every edge
   (Lemma 6); it is the Euclidean metric iff ``f = ℓ²``.  With ``f = ℓ`` (as Definition 16 is
   printed) the lengths (1, 1, 3) give a positive-definite ``S^ℓ`` although no such triangle exists.
5. The code (``dhlb.geometry.simplex.SimplexStack``: cotan_weights, heights, dihedral_angles,
   volumes, from points and from squared lengths) agrees with the exact values to 1e-12.
"""

from __future__ import annotations

import sys
import time
from itertools import combinations

import numpy as np
import sympy as sp
from _derive_util import barycentric_gradients, summary

from dhlb.geometry.simplex import SimplexStack, metric_from_squared_lengths

TOL = 1e-12


def gram_volume(vectors):
    """k-volume of the simplex spanned by ``vectors`` (list of sympy column vectors) from a vertex."""
    if not vectors:
        return sp.Integer(1)
    E = sp.Matrix.hstack(*vectors)
    return sp.sqrt((E.T * E).det()) / sp.factorial(len(vectors))


def geometry(P):
    """Exact volume, facet volumes, ridge volumes, dihedral angles (cos, sin) of σ = P."""
    P = sp.Matrix(P)
    N = P.shape[0]
    pts = [P[a, :].T for a in range(N)]

    def face_vol(verts):
        verts = list(verts)
        return gram_volume([pts[v] - pts[verts[0]] for v in verts[1:]])

    vol = face_vol(range(N))
    facet = [face_vol([v for v in range(N) if v != i]) for i in range(N)]
    ridge, cosa, sina = {}, {}, {}
    for i, j in combinations(range(N), 2):
        rest = [v for v in range(N) if v not in (i, j)]
        ridge[i, j] = face_vol(rest)
        # components of (P_j - P_r0) and (P_i - P_r0) orthogonal to the ridge span: they lie in the
        # facets σ∖{i} and σ∖{j} respectively and are both normal to the ridge -> the dihedral angle
        R = [pts[v] - pts[rest[0]] for v in rest[1:]]

        def perp(v):
            if not R:
                return v
            Rm = sp.Matrix.hstack(*R)
            return v - Rm * (Rm.T * Rm).inv() * (Rm.T * v)

        u, w = perp(pts[j] - pts[rest[0]]), perp(pts[i] - pts[rest[0]])
        nu, nw = sp.sqrt(u.dot(u)), sp.sqrt(w.dot(w))
        cosa[i, j] = u.dot(w) / (nu * nw)
        sina[i, j] = sp.sqrt(sp.factor(1 - cosa[i, j] ** 2))
    return vol, facet, ridge, cosa, sina


def heights_direct(P):
    """Distance from each vertex to the affine hull of the opposite facet (projection)."""
    P = sp.Matrix(P)
    N = P.shape[0]
    out = []
    for i in range(N):
        rest = [v for v in range(N) if v != i]
        R = sp.Matrix.hstack(*[(P[v, :] - P[rest[0], :]).T for v in rest[1:]])
        d = (P[i, :] - P[rest[0], :]).T
        perp = d - R * (R.T * R).inv() * (R.T * d)
        out.append(sp.sqrt(perp.dot(perp)))
    return out, P


def check_simplex(P, exact=True):
    N = len(P)
    n = N - 1
    vol, facet, ridge, cosa, sina = geometry(P)
    h, Pm = heights_direct(P)
    grad = barycentric_gradients(P)
    simp = sp.simplify if exact else (lambda e: sp.N(e, 30))
    zero = (lambda e: sp.simplify(e) == 0) if exact else (lambda e: abs(sp.N(e, 30)) < 1e-25)
    for i in range(N):
        # Lemma 8: grad x_i = -N_i / h_i with N_i the outward unit normal of σ∖{i}
        rest = [v for v in range(N) if v != i]
        R = sp.Matrix.hstack(*[(Pm[v, :] - Pm[rest[0], :]).T for v in rest[1:]])
        d = (Pm[rest[0], :] - Pm[i, :]).T                      # from vertex i towards the facet
        perp = d - R * (R.T * R).inv() * (R.T * d)
        normal = perp / sp.sqrt(perp.dot(perp))                # outward normal of facet i
        assert all(zero(e) for e in (grad[i, :].T + normal / h[i])), ("Lemma 8", i)
        assert zero(n * vol - h[i] * facet[i]), ("n vol = h_i vol(σ∖i)", i)
        c_ii = vol * grad[i, :].dot(grad[i, :])
        assert zero(c_ii - facet[i] / (n * h[i])), ("c_ii", i)
    bad_printed = 0
    for i, j in combinations(range(N), 2):
        c_ij = vol * grad[i, :].dot(grad[j, :])
        cot = cosa[i, j] / sina[i, j]
        assert zero(c_ij + cot * ridge[i, j] / (n * (n - 1))), ("c_ij", i, j)
        good = sp.factorial(n) * sina[i, j] * vol - sp.factorial(n - 2) * h[i] * h[j] * ridge[i, j]
        assert zero(good), ("proof identity", i, j)
        printed = sp.factorial(n) * vol - sp.factorial(n - 2) * h[i] * h[j] * sina[i, j] * ridge[i, j]
        bad_printed += not zero(printed)
    return bad_printed, simp


def symbolic_triangle():
    p, _q, t = sp.symbols("p q t", positive=True)
    s = sp.Symbol("s", real=True)
    P = [[0, 0], [p, 0], [s, t]]
    vol = p * t / 2
    grad = barycentric_gradients(P)
    for i, j in combinations(range(3), 2):
        k = 3 - i - j
        # α_ij for n = 2 is the interior angle at the third vertex k
        u = sp.Matrix(P[i]) - sp.Matrix(P[k])
        w = sp.Matrix(P[j]) - sp.Matrix(P[k])
        cross = u[0] * w[1] - u[1] * w[0]
        cot = u.dot(w) / sp.Abs(cross)
        c_ij = vol * grad[i, :].dot(grad[j, :])
        assert sp.simplify(c_ij + cot / 2) == 0, (i, j)
    return "n = 2 symbolic triangle: c_ij = -cot(α_k)/2 (angle at the third vertex)"


def random_rational_simplex(rng, n):
    while True:
        P = [[sp.Rational(int(v), 3) for v in row] for row in rng.integers(-6, 7, size=(n + 1, n))]
        if sp.Matrix([[1] + r for r in P]).det() != 0:
            return P


def facet_definition_16():
    # Eq. 11.1: S^f = Σ f_0j dx_j⊗dx_j + Σ_{j≠k} ½(f_0j + f_0k - f_jk) dx_j⊗dx_k in the edge basis
    n = 3
    f = {e: sp.Symbol(f"f{e[0]}{e[1]}", positive=True) for e in combinations(range(n + 1), 2)}
    F = lambda a, b: f[tuple(sorted((a, b)))]
    S = sp.zeros(n, n)
    for j in range(1, n + 1):
        for k in range(1, n + 1):
            S[j - 1, k - 1] = F(0, j) if j == k else (F(0, j) + F(0, k) - F(j, k)) / 2
    # Lemma 6 property: S(P_b - P_a) = f_ab, P_b - P_a has edge-basis coordinates e_b - e_a
    for a, b in combinations(range(n + 1), 2):
        v = sp.zeros(n, 1)
        if b:
            v[b - 1] += 1
        if a:
            v[a - 1] -= 1
        assert sp.expand((v.T * S * v)[0, 0] - F(a, b)) == 0
    # with f = ℓ² it is the Gram matrix of the edge vectors (the Euclidean metric)
    rng = np.random.default_rng(5)
    P = sp.Matrix(random_rational_simplex(rng, 3))
    E = sp.Matrix.hstack(*[(P[a, :] - P[0, :]).T for a in range(1, 4)])
    L2 = {e: (P[e[0], :] - P[e[1], :]).dot(P[e[0], :] - P[e[1], :]) for e in f}
    assert sp.simplify(S.subs({f[e]: L2[e] for e in f}) - E.T * E) == sp.zeros(3, 3)
    code_g = metric_from_squared_lengths(np.array([[[float(L2[tuple(sorted((a, b)))]) if a != b else 0.0
                                                     for b in range(4)] for a in range(4)]]))[0]
    assert np.allclose(code_g, np.array((E.T * E).tolist(), dtype=float), rtol=1e-14, atol=1e-14)
    # with f = ℓ (as printed in Definition 16): lengths (1, 1, 3) are no triangle, yet S^ℓ is PD
    S_l = sp.Matrix([[1, sp.Rational(1, 2) * (1 + 1 - 3)], [sp.Rational(1, 2) * (1 + 1 - 3), 1]])
    assert all(ev > 0 for ev in S_l.eigenvals()) and 1 + 1 < 3
    S_l2 = sp.Matrix([[1, sp.Rational(1, 2) * (1 + 1 - 9)], [sp.Rational(1, 2) * (1 + 1 - 9), 1]])
    assert any(ev < 0 for ev in S_l2.eigenvals())           # f = ℓ² correctly rejects it
    return ("Eq. 11.1: S^f(P_b - P_a) = f_ab for all edges; S^{ℓ²} = Euclidean metric (= code "
            "metric_from_squared_lengths); f = ℓ admits lengths (1, 1, 3) (S^ℓ PD, no triangle)")


def code_comparison(rng):
    worst = 0.0
    for n in (2, 3):
        for _ in range(3):
            P = random_rational_simplex(rng, n)
            vol, _facet, _ridge, cosa, _sina = geometry(P)
            h, _ = heights_direct(P)
            grad = barycentric_gradients(P)
            C = np.array((vol * grad * grad.T).evalf(30).tolist(), dtype=float)
            alpha = np.zeros((n + 1, n + 1))
            for (i, j), cv in cosa.items():
                alpha[i, j] = alpha[j, i] = float(sp.acos(cv).evalf(30))
            Pf = np.array(P, dtype=float)[None]
            for S in (SimplexStack.from_points(Pf),
                      SimplexStack.from_squared_lengths(((Pf[:, :, None] - Pf[:, None]) ** 2).sum(-1))):
                worst = max(worst, np.abs(S.cotan_weights[0] - C).max() / np.abs(C).max(),
                            np.abs(S.volumes[0] - float(vol)) / float(vol),
                            np.abs(S.dihedral_angles[0] - alpha).max(),
                            np.abs(S.heights[0] - np.array([float(v) for v in h])).max())
    assert worst < TOL, worst
    return worst


def main() -> int:
    t0 = time.time()
    rng = np.random.default_rng(16)
    lines = [symbolic_triangle()]
    bad = 0
    for n in (2, 3):
        for _ in range(3):
            b, _ = check_simplex(random_rational_simplex(rng, n))
            bad += b
    assert bad > 0                               # the printed identity fails on these simplices
    for _ in range(2):                           # n = 4, 30-digit numerics
        P = [[sp.Rational(int(v), 4) for v in row] for row in rng.integers(-8, 9, size=(5, 4))]
        b, _ = check_simplex(P, exact=False)
        bad += b
    lines.append("Lemma 8, Theorem 16 (c_ij and c_ii), n vol σ = h_i vol(σ∖i) and the corrected identity "
                 "n! sin α vol σ = (n-2)! h_i h_j vol(σ∖{i,j}): exact for n = 2, 3 (rational simplices), "
                 "30 digits for n = 4")
    lines.append(f"printed identity n! vol σ = (n-2)! h_i h_j sin α vol(σ∖{{i,j}}) fails on {bad} vertex pairs")
    lines.append(facet_definition_16())
    lines.append(f"code SimplexStack (points and squared lengths) vs exact: max rel. {code_comparison(rng):.1e}")
    lines.append(f"time {time.time() - t0:.1f} s")
    summary("derive_cotangent_formula", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
