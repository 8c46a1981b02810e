"""Hermite–Genocchi: simplex moments of exp(linear) are confluent divided differences of exp.

For the standard n-simplex Δ (volume 1/n!) and x^p = Π_m x_m^{p_m},

    ∫_Δ x^p exp(Σ_m a_m x_m) dx = Π_m p_m! · exp[a_0^(p_0+1), ..., a_n^(p_n+1)],

so that (1/vol) ∫_σ x^p exp(i Σ θ_m x_m) = n! Π p_m! exp[iθ^(p+1)] — the formula behind
dhlb.fem.integrals.expi_moment, hence behind Θ, Λ, Ξ of Definitions 18–19.

Proved here by exact iterated integration (Fubini + Lemma 7, proofs/_common.py) against the
residue formula for divided differences with repeated nodes:
  * n = 1, 2, 3 with generic distinct symbolic exponents, all monomials of degree <= 4, 2, 1;
  * n = 2, 3 with the exponent structure of the finite elements (a_i = a_j = 0 for the pair ij,
    the other exponents generic), all monomials of degree <= 4 that Θ, Λ, Ξ use.
Finally dhlb's numerical evaluation is compared with the exact expressions (40-digit mpmath).
"""

from itertools import product
from math import factorial

import mpmath as mp
import numpy as np
import sympy as sp
from _common import check, exp_divided_difference, same_exponential_sum, simplex_integral


def monomials(n, max_degree):
    return [p for p in product(range(max_degree + 1), repeat=n + 1) if sum(p) <= max_degree]


def identity_holds(p, exps) -> bool:
    n = len(p) - 1
    xs = sp.symbols(f"x1:{n + 1}", real=True)
    bary = [1 - sum(xs)] + list(xs)
    poly = sp.Mul(*[b ** k for b, k in zip(bary, p)])
    lhs = simplex_integral(poly, sum(a * b for a, b in zip(exps, bary)), list(xs))
    # group equal exponents (confluent nodes) into classes with multiplicities
    classes: dict = {}
    for a, k in zip(exps, p):
        classes[a] = classes.get(a, 0) + k + 1
    rhs = exp_divided_difference(list(classes.items()))
    fac = sp.Mul(*[sp.factorial(k) for k in p])
    return same_exponential_sum(lhs, {key: fac * v for key, v in rhs.items()})


def main() -> None:
    print("Hermite-Genocchi formula for simplex moments")
    for n, deg in [(1, 4), (2, 2), (3, 1)]:
        a = sp.symbols(f"a0:{n + 1}")
        for p in monomials(n, deg):
            assert identity_holds(p, a), (n, p)
        check(True, f"n = {n}: generic exponents, all monomials of degree <= {deg}")
    for n in (2, 3):
        t = sp.symbols(f"t2:{n + 1}")
        exps = (0, 0) + t                       # pair (i, j) = (0, 1): both exponents vanish
        for p in monomials(n, 4):
            if sum(p) in (0, 2, 4) and (sum(p) < 4 or (p[0] >= 1 and p[1] >= 1)) and \
                    (sum(p) != 2 or p[0] + p[1] >= 1):
                assert identity_holds(p, exps), (n, p)
        check(True, f"n = {n}: pair exponents (0, 0, t...), all monomials of Θ(i,·), Θ(j,·), Λ, Ξ")

    # numerical evaluation in dhlb against the exact residue formula
    from dhlb.fem.integrals import expi_moment
    mp.mp.dps = 40
    rng = np.random.default_rng(7)
    worst = 0.0
    for _trial in range(60):
        n = int(rng.integers(1, 4))
        th = rng.choice([-1, 1], n + 1) * 10.0 ** rng.uniform(-6, 3, n + 1)
        th[rng.integers(n + 1)] = 0.0
        p = [int(v) for v in rng.integers(0, 3, n + 1)]
        classes: dict = {}
        for v, k in zip(th, p):
            classes[float(v)] = classes.get(float(v), 0) + k + 1
        z = sp.Symbol("z")
        nodes = [(sp.I * sp.Rational(v), m) for v, m in classes.items()]
        exact = exp_divided_difference(nodes)
        val = sum(sp.exp(key) * coeff for key, coeff in exact.items())
        ref = complex(sp.N(val * factorial(n) * np.prod([factorial(k) for k in p]), 40))
        got = complex(expi_moment(th, p))
        worst = max(worst, abs(got - ref) / abs(ref))
        del z
    check(worst < 1e-12, f"dhlb.fem.integrals.expi_moment matches the exact value (max rel. error {worst:.1e})")


if __name__ == "__main__":
    main()
