"""Θ, Λ, Ξ of Definitions 18-19 for tetrahedra (n = 3), in closed form.

For the pair (i, j) of a tetrahedron {i, j, k, l} put s = Ω_ijk and t = Ω_ijl; the exponent of
Definitions 18-19 is -i(s x_k + t x_l).  By Hermite-Genocchi (proofs/hermite_genocchi.py)

    Λ_ij = 3! exp[0^(2), -is, -it],   Θ_ij(k', l') = 3! p! exp[0^(μ_0), (-is)^(μ_k), (-it)^(μ_l)],
    Ξ_ij(k', l') likewise with p = e_i + e_j + e_k' + e_l',

(μ_0 = p_i + p_j + 2, μ_k = p_k + 1, μ_l = p_l + 1), and the residue formula gives the closed forms
printed below, e.g.

    Λ_ij = -6 (st + is + it)/(s²t²) - 6i e^{-is}/(s²(s - t)) + 6i e^{-it}/(t²(s - t)).

This script prints the closed forms, re-derives three of them by exact integration over the
tetrahedron (all 21 are covered by proofs/hermite_genocchi.py), and compares dhlb's values with the exact ones
(60 digits) in all regimes: generic, tiny, huge, s = t, s = 0, s ≈ t, |s|, |t| ≫ π.
"""

from itertools import combinations_with_replacement

import numpy as np
import sympy as sp
from _common import check, exp_divided_difference, same_exponential_sum, simplex_integral

s, t = sp.symbols("s t", real=True, nonzero=True)
I = sp.I


def requests():
    """(name, p) for Λ, Θ_ij(a, ·), Ξ_ij(·, ·) with local i, j, k, l = 0, 1, 2, 3."""
    out = [("Λ_ij", (0, 0, 0, 0))]
    for u, v in combinations_with_replacement(range(4), 2):
        p = [0, 0, 0, 0]
        p[u] += 1
        p[v] += 1
        out.append((f"Θ_ij({'ijkl'[u]},{'ijkl'[v]})", tuple(p)))
        q = [p[0] + 1, p[1] + 1, p[2], p[3]]
        out.append((f"Ξ_ij({'ijkl'[u]},{'ijkl'[v]})", tuple(q)))
    return out


def closed_form(p, ss, tt):
    """3! p! exp[0^(p_i+p_j+2), (-i ss)^(p_k+1), (-i tt)^(p_l+1)] by residues (distinct nodes)."""
    fac = 6 * sp.Mul(*[sp.factorial(k) for k in p])
    dd = exp_divided_difference([(0, p[0] + p[1] + 2), (-I * ss, p[2] + 1), (-I * tt, p[3] + 1)])
    return {key: fac * val for key, val in dd.items()}


def main() -> None:
    print("Θ, Λ, Ξ for n = 3")
    x1, x2, x3 = sp.symbols("x1:4", real=True)
    b = [1 - x1 - x2 - x3, x1, x2, x3]
    expo = -I * (s * b[2] + t * b[3])
    forms = {name: (p, closed_form(p, s, t)) for name, p in requests()}
    # all 21 are covered by proofs/hermite_genocchi.py; re-derive three of them here directly
    for name in ("Λ_ij", "Θ_ij(i,j)", "Ξ_ij(k,l)"):
        p, rhs = forms[name]
        poly = sp.Mul(*[bb ** k for bb, k in zip(b, p)])
        lhs = {key: 6 * val for key, val in simplex_integral(poly, expo, [x1, x2, x3]).items()}
        assert same_exponential_sum(lhs, rhs), name
    check(True, "Λ_ij, Θ_ij(i,j), Ξ_ij(k,l) by exact integration equal their residue closed forms")
    lam = forms["Λ_ij"][1]
    print("    Λ_ij = " + " + ".join(f"exp({k})*({sp.factor(v)})" for k, v in lam.items()))

    from dhlb.fem.integrals import lambda_, theta, xi
    cases = [(0.3, -1.1), (1e-7, 2e-7), (5.0, 5.0), (0.0, 3.0), (2.0, 2.0 + 1e-9), (40.0, -700.0),
             (6.283185307179586, 12.566370614359172), (1e-4, 250.0), (-3.0, 9.0), (0.0, 0.0)]
    worst = 0.0
    for sv, tv in cases:
        om = np.array([sv, tv, 0.0, 0.0])            # Ω_ijk, Ω_ijl on triangles (0,1,2), (0,1,3)
        om[3] = om[2] - om[1] + om[0]                # Ω_123 from dΩ = 0 (Ω_023 = 0 chosen)
        for name, (p, _) in forms.items():
            # exact value with merged classes for coinciding nodes
            classes: dict = {}
            for node, mult in ((sp.Integer(0), p[0] + p[1] + 2), (-I * sp.Rational(sv), p[2] + 1),
                               (-I * sp.Rational(tv), p[3] + 1)):
                classes[node] = classes.get(node, 0) + mult
            dd = exp_divided_difference(list(classes.items()))
            fac = 6 * np.prod([float(sp.factorial(k)) for k in p])
            ref = complex(sp.N(sum(sp.exp(k) * v for k, v in dd.items()), 60)) * fac
            if name == "Λ_ij":
                got = lambda_(om, 0, 1)
            else:
                u, v = ("ijkl".index(name[5]), "ijkl".index(name[7]))
                got = (theta if name[0] == "Θ" else xi)(om, 0, 1, u, v)
            worst = max(worst, abs(complex(got) - ref) / abs(ref))
    check(worst < 1e-12, f"dhlb theta/lambda_/xi match exact values incl. confluent and huge curvature "
                         f"(max rel. error {worst:.1e})")


if __name__ == "__main__":
    main()
