"""Seed part 3, Lemma 7: an antiderivative of x^n exp(cx).

    ∫_a^b x^n e^{cx} dx = n!/c^{n+1} ( Σ_{k=0}^n (-1)^k (cx)^{n-k}/(n-k)! ) e^{cx} |_a^b ,   c ≠ 0.

Proof (telescoping, for every n): with S_n(x) = Σ_k (-1)^k (cx)^{n-k}/(n-k)! one has
S_n' = -c (S_n - (cx)^n/n!), hence (S_n e^{cx})' = c (cx)^n/n! e^{cx} and the claim.  This script
checks the telescoping identity and the derivative symbolically for n = 0..20, and the definite
integral numerically for complex c (the case used by the finite elements, c = -iΩ).
"""

import mpmath as mp
import sympy as sp
from _common import check, lemma7_antiderivative


def main() -> None:
    x = sp.Symbol("x", real=True)
    c = sp.Symbol("c", nonzero=True)
    print("Lemma 7")
    for n in range(21):
        s_n = sum((-1) ** k * (c * x) ** (n - k) / sp.factorial(n - k) for k in range(n + 1))
        assert sp.expand(sp.diff(s_n, x) + c * (s_n - (c * x) ** n / sp.factorial(n))) == 0
        anti = lemma7_antiderivative(n, c, x) * sp.exp(c * x)
        assert sp.expand(sp.simplify(sp.diff(anti, x) * sp.exp(-c * x)) - x ** n) == 0
    check(True, "S_n' = -c (S_n - (cx)^n/n!) and d/dx[antiderivative] = x^n e^{cx} for n = 0..20")

    mp.mp.dps = 40
    cases = [(0, 2 * sp.I, 0, 1), (3, -sp.Rational(3, 2) * sp.I, 0, 1),
             (5, sp.Rational(3, 10) - 7 * sp.I, -1, 2), (8, -40 * sp.I, 0, 1)]
    for n, cv, a, b in cases:
        cm = mp.mpc(sp.re(cv), sp.im(cv))
        exact = mp.quad(lambda t: t ** n * mp.exp(cm * t), [a, b])
        f = sp.lambdify(x, lemma7_antiderivative(n, cv, x) * sp.exp(cv * x), "mpmath")
        val = f(mp.mpf(b)) - f(mp.mpf(a))
        assert abs(val - exact) <= mp.mpf(10) ** -25 * max(1, abs(exact)), (n, cv)
    check(True, "definite integrals agree with mpmath quadrature to 1e-25 (complex c, n up to 8)")


if __name__ == "__main__":
    main()
