"""Symbolic checks of the closed forms used by dhlb/fem/kernels_closed.py and dhlb/fem/_fast_moments.py.

Run: python proofs/fast_local_closed_forms.py   (asserts; exits non-zero on failure).

1. Pair reduction (n = 2, 3).  With a generic symmetric G (no row-sum identity used), generic
   curvature values (closedness not used) and the moments as free symbols ``F[α, β, γ]`` of the
   Hermite–Genocchi formula ``(1/vol) ∫ x^p e^{-iΣ Ω_abm x_m} = n! Π p! F[p_a+p_b+2, p_c+1, (p_d+1)]``,
   Theorem 17 in the form of dhlb.fem.integrals,

       A[b,a]/(r vol) = G_ab Λ + Σ_{l,l'} (W^aᵀ G W^b)_{ll'} Ξ(l,l')
                        + i Σ_l [(G W^a)_{bl} Θ(a,l) - (G W^b)_{al} Θ(b,l)],

   equals the compact expression of _block_3d / _block_2d, for every pair (a, b).
2. Diagonal: G_aa + Σ (W^aᵀ G W^a)_{ll'} Ξ_aa(l,l') equals the closed form of the blocks.
3. 2-D: φ(-w) = conj φ(w) (real Taylor coefficients in z = -iw) and the pair with w -> -w.
4. Moments: the Taylor coefficients Σ_{j,k} C(j+β-1,β-1) C(k+γ-1,γ-1) z^j y^k / (j+k+N)! of
   exp[0^α, z^β, y^γ], the recurrence z F(α,β,γ) = F(α-1,β,γ) - F(α,β-1,γ) and the shift
   exp[z^β, y^γ] = e^z exp[0^β, (y-z)^γ], checked against the residue (contour) definition.
"""

from __future__ import annotations

import sys
from itertools import combinations
from math import factorial

import sympy as sp

I = sp.I


def tri_sign(n, x, y, z):
    tris = list(combinations(range(n + 1), 3))
    inv = sum(1 for i, j in combinations((x, y, z), 2) if i > j)
    return tris.index(tuple(sorted((x, y, z)))), (-1) ** inv


def setup(n):
    k = n + 1
    G = sp.Matrix(k, k, lambda i, j: sp.Symbol(f"g{min(i, j)}{max(i, j)}"))
    om = sp.symbols(f"o0:{len(list(combinations(range(k), 3)))}")

    def Om(x, y, z):
        if len({x, y, z}) < 3:
            return 0
        t, s = tri_sign(n, x, y, z)
        return s * om[t]

    W = [sp.Matrix(k, k, lambda p, q, a=a: Om(a, p, q)) for a in range(k)]
    return G, om, Om, W


def moment(n, a, b, p, F):
    """(1/vol) ∫ x^p exp(-iΣ Ω_abm x_m) as n! Π p! F[pattern] (free symbols)."""
    others = [v for v in range(n + 1) if v not in (a, b)]
    key = (p[a] + p[b] + 2,) + tuple(p[o] + 1 for o in others)
    if key not in F:
        F[key] = sp.Symbol("F" + "_".join(map(str, key)))
    return factorial(n) * sp.prod([factorial(v) for v in p]) * F[key]


def unit(n, *idx):
    p = [0] * (n + 1)
    for v in idx:
        p[v] += 1
    return p


def theorem17(n, a, b, G, W, F):
    k = n + 1
    lam = moment(n, a, b, unit(n), F)
    Q = W[a].T * G * W[b]
    xi = sum(Q[l, q] * moment(n, a, b, unit(n, a, b, l, q), F) for l in range(k) for q in range(k))
    pa, pb = G * W[a], G * W[b]
    th = sum(pa[b, l] * moment(n, a, b, unit(n, a, l), F) - pb[a, l] * moment(n, a, b, unit(n, b, l), F)
             for l in range(k))
    return G[a, b] * lam + xi + I * th


def check_pairs_3d():
    G, _, Om, W = setup(3)
    for a, b in combinations(range(4), 2):
        F = {}
        ref = theorem17(3, a, b, G, W, F)
        c, d = [v for v in range(4) if v not in (a, b)]
        A1, A2, A3, B3 = Om(a, b, c), Om(a, b, d), Om(a, c, d), Om(b, c, d)
        gab, gcc, gdd, gcd = G[a, b], G[c, c], G[d, d], G[c, d]
        gac, gad, gbc, gbd = G[a, c], G[a, d], G[b, c], G[b, d]
        u1, u2, sab = gac + gbc, gad + gbd, G[a, a] + G[b, b]
        a11, a22, a12, a33, dd = A1 * A1, A2 * A2, A1 * A2, A3 * B3, B3 - A3
        b1, b2, b3, b4 = A1 * B3, A1 * A3, A2 * B3, A2 * A3
        c_re = [gab,
                -(a11 * gcc + 2 * a12 * gcd + a22 * gdd),
                a11 * u1 + a12 * u2 + dd * (A1 * gcd + A2 * gdd),
                a12 * u1 + a22 * u2 - dd * (A1 * gcc + A2 * gcd),
                b2 * gad - b1 * gbd + a33 * gdd - a11 * gab,
                b3 * gbc - b4 * gac + a33 * gcc - a22 * gab,
                b1 * gbc - b2 * gac + b4 * gad - b3 * gbd - 2 * (a12 * gab + a33 * gcd)]
        c_im = [-(A1 * u1 + A2 * u2), A1 * sab - A3 * gbd + B3 * gad, A2 * sab + A3 * gbc - B3 * gac]
        pats = [(6, 2, 1, 1), (6, 4, 1, 1), (6, 3, 2, 1), (6, 3, 1, 2), (24, 6, 1, 1),
                (12, 5, 2, 1), (12, 5, 1, 2), (12, 4, 3, 1), (12, 4, 1, 3), (6, 4, 2, 2)]
        mom = [w * F.setdefault(p, sp.Symbol("F" + "_".join(map(str, p)))) for w, p in
               [(w, (a_, b_, c_)) for w, a_, b_, c_ in pats]]
        mine = sum(cc * mom[f] for cc, f in zip(c_re, (0, 4, 5, 6, 7, 8, 9)))
        mine += I * sum(cc * mom[f] for cc, f in zip(c_im, (1, 2, 3)))
        assert sp.expand(ref - mine) == 0, (a, b)
        # the mass entry Θ_ab(a, b) = 6 F411 = mom[1]
        assert sp.expand(moment(3, a, b, unit(3, a, b), F) - mom[1]) == 0
    print("3-D pair reduction: OK (6 pairs)")


def check_pairs_2d():
    G, om, Om, W = setup(2)
    w = sp.Symbol("w", real=True)
    E = {}
    for p, (a, b) in enumerate(combinations(range(3), 2)):
        F = {}
        ref = theorem17(2, a, b, G, W, F)
        c = 3 - a - b
        e = {key: F.setdefault(key, sp.Symbol(f"F{key[0]}_{key[1]}"))
             for key in ((2, 1), (4, 1), (3, 2), (6, 1), (5, 2), (4, 3))}
        phi = [2 * e[4, 1], 2 * e[2, 1] - 4 * w**2 * e[4, 3], 4 * w**2 * e[5, 2] - 2 * I * w * e[4, 1],
               2 * I * w * e[3, 2], -8 * w**2 * e[6, 1]]
        mine = (G[a, b] * phi[1] + (G[a, c] + G[b, c]) * phi[2] + (G[a, a] + G[b, b]) * phi[3]
                + G[c, c] * phi[4])
        mine = mine.subs(w, Om(a, b, c))
        assert sp.expand(ref - mine) == 0, (a, b)
        assert sp.expand(moment(2, a, b, unit(2, a, b), F) - phi[0]) == 0
        assert Om(a, b, c) == (-om[0] if p == 1 else om[0])      # the sign used by _block_2d
        E.update(F)
    print("2-D pair reduction: OK (3 pairs)")


def check_diagonal():
    for n, denom in ((2, 180), (3, 420)):
        G, _, Om, W = setup(n)
        k = n + 1
        for a in range(k):
            quad = W[a].T * G * W[a]
            ref = 0
            for l in range(k):
                for q in range(k):
                    p = unit(n, a, a, l, q)
                    ref += quad[l, q] * sp.Rational(factorial(n) * sp.prod([factorial(v) for v in p]),
                                                    factorial(n + 4))
            oth = [v for v in range(k) if v != a]
            if n == 2:
                b, c = oth
                x = Om(a, b, c)
                mine = x**2 / 90 * (G[b, b] + G[c, c] - G[b, c])
            else:
                b, c, d = oth
                x, y, z = Om(a, b, c), Om(a, b, d), Om(a, c, d)
                s1, s2, s3 = x + y, z - x, -(y + z)
                mine = (G[b, b] * (x * x + y * y + s1 * s1) + G[c, c] * (x * x + z * z + s2 * s2)
                        + G[d, d] * (y * y + z * z + s3 * s3)
                        + 2 * (G[b, c] * (y * z + s1 * s2) + G[b, d] * (s1 * s3 - x * z)
                               + G[c, d] * (x * y + s2 * s3))) / denom
            assert sp.expand(ref - mine) == 0, (n, a)
    print("diagonal closed forms: OK")


def dd_residue(alpha, beta, gamma, z, y):
    """exp[0^α, z^β, y^γ] = Σ residues of e^t / (t^α (t-z)^β (t-y)^γ) (distinct symbolic z, y)."""
    t = sp.Symbol("t")
    f = sp.exp(t) / (t**alpha * (t - z) ** beta * (t - y) ** gamma)
    tot = 0
    for pole, mult in ((0, alpha), (z, beta), (y, gamma)):
        if mult:
            g = sp.simplify(f * (t - pole) ** mult)
            tot += sp.diff(g, t, mult - 1).subs(t, pole) / factorial(mult - 1)
    return tot


def check_moments():
    z, y = sp.symbols("z y")
    zz, yy = sp.Rational(3, 10) * I, -sp.Rational(7, 10) * I      # distinct test nodes
    for al, be, ga in ((2, 1, 1), (3, 2, 1), (4, 1, 2), (2, 2, 2)):
        exact = dd_residue(al, be, ga, z, y)
        N = al + be + ga - 1
        series = sum(sp.binomial(j + be - 1, be - 1) * sp.binomial(k + ga - 1, ga - 1) * zz**j * yy**k
                     / sp.factorial(j + k + N) for j in range(40) for k in range(40 - j))
        val = sp.N(exact.subs({z: zz, y: yy}), 40)
        assert abs(sp.N(val - series, 40)) < 1e-30, (al, be, ga)
        # recurrence z F(α, β, γ) = F(α-1, β, γ) - F(α, β-1, γ)
        lhs = z * exact
        rhs = dd_residue(al - 1, be, ga, z, y) - dd_residue(al, be - 1, ga, z, y)
        assert abs(sp.N((lhs - rhs).subs({z: zz, y: yy}), 40)) < 1e-30, ("recurrence", al, be, ga)
    # shift: exp[z^β, y^γ] = e^z exp[0^β, (y - z)^γ]
    for be, ga in ((1, 1), (2, 1), (1, 3), (2, 2)):
        lhs = dd_residue(0, be, ga, z, y)
        rhs = sp.exp(z) * dd_residue(be, ga, 0, y - z, y)     # nodes 0^β, (y-z)^γ
        assert abs(sp.N((lhs - rhs).subs({z: zz, y: yy}), 40)) < 1e-30, ("shift", be, ga)
    # φ(-w) = conj φ(w): every E(α, β)(-iw) has real Taylor coefficients in z = -iw
    w = sp.Symbol("w", real=True)
    e21 = dd_residue(2, 1, 0, -I * w, y)
    s = sp.series(e21, w, 0, 6).removeO()
    assert sp.simplify(s.subs(w, -w) - sp.conjugate(s)) == 0
    print("moment series, recurrence, shift, conjugation: OK")


def main() -> int:
    check_pairs_3d()
    check_pairs_2d()
    check_diagonal()
    check_moments()
    return 0


if __name__ == "__main__":
    sys.exit(main())
