r"""Seed part 3, Lemma 7: the antiderivative of ``x^n exp(c x)`` -- proof, and its use (Fubini).

Statement (as printed, and correct): for ``c ∈ C*``, ``n ∈ N`` and an interval ``[a, b]``,

    ∫_a^b x^n e^{cx} dx = n!/c^(n+1) · ( Σ_{k=0}^n (-1)^k (cx)^(n-k)/(n-k)! ) e^{cx} |_a^b.

What is derived here, from the definitions only:

1. General ``n`` (symbolic): with ``t_k = (-1)^k (cx)^(n-k)/(n-k)!`` one has
   ``d/dx [t_k e^{cx}] = c e^{cx} (t_k - t_{k+1})`` and ``t_{n+1} = 0`` (``1/Γ(0) = 0``), so the sum
   telescopes to ``d/dx F_n = n!/c^(n+1) · c (cx)^n/n! · e^{cx} = x^n e^{cx}``.
2. Explicit ``n = 0..12``: ``F_n' == x^n e^{cx}`` by sympy differentiation, and the
   integration-by-parts recursion ``F_n = x^n e^{cx}/c - (n/c) F_{n-1}`` (the seed's induction).
3. Agreement with sympy's own integrator (``n <= 5``) and with mpmath quadrature for complex
   ``c`` on random intervals (``n <= 8``), relative error < 1e-20 (30-digit arithmetic).
4. Fubini + Lemma 7 (the seed's suggested route to Θ, Definition 18): the exact simplex
   integrator ``_derive_util.integrate_simplex`` built on Lemma 7 agrees with ``sympy.integrate``
   on the triangle (symbolic curvature) and with a Duffy--Gauss rule on the tetrahedron.

``c = 0`` is excluded by the lemma (``C*``); the integrator treats a vanishing exponent
coefficient separately (polynomial integration).
"""

from __future__ import annotations

import sys
import time

import mpmath as mp
import numpy as np
import sympy as sp
from _derive_util import integrate_simplex, lemma7_antiderivative, rel_err, simplex_rule, summary


def general_n_telescoping():
    n, k = sp.symbols("n k", integer=True, nonnegative=True)
    c = sp.Symbol("c", nonzero=True)
    x = sp.Symbol("x", positive=True)

    def t(j):
        return (-1) ** j * (c * x) ** (n - j) / sp.gamma(n - j + 1)

    lhs = sp.diff(t(k) * sp.exp(c * x), x)
    rhs = c * sp.exp(c * x) * (t(k) - t(k + 1))
    diff = sp.simplify(sp.gammasimp(sp.powsimp(sp.expand(lhs - rhs), force=True)))
    assert diff == 0, f"telescoping step fails: {diff}"
    # t_{n+1} = 0 because 1/Γ(0) = 0, and the telescoped sum is t_0 - t_{n+1} = (cx)^n / n!
    assert sp.simplify(1 / sp.gamma(n - (n + 1) + 1)) == 0
    total = sp.factorial(n) / c ** (n + 1) * c * sp.exp(c * x) * t(0)
    assert sp.simplify(sp.gammasimp(total - x ** n * sp.exp(c * x))) == 0
    return "general n: d/dx[t_k e^{cx}] = c e^{cx}(t_k - t_{k+1}), telescoping gives x^n e^{cx}"


def explicit_n():
    c = sp.Symbol("c", nonzero=True)
    x = sp.Symbol("x")
    prev = None
    for n in range(13):
        F = lemma7_antiderivative(n, c, x)
        assert sp.simplify(sp.diff(F, x) - x ** n * sp.exp(c * x)) == 0, n
        if prev is not None:   # integration by parts: ∫x^n e^{cx} = x^n e^{cx}/c - (n/c) ∫x^{n-1} e^{cx}
            assert sp.simplify(F - (x ** n * sp.exp(c * x) / c - n / c * prev)) == 0, n
        prev = F
    a, b = sp.symbols("a b", real=True)
    for n in range(6):
        ref = sp.integrate(x ** n * sp.exp(c * x), (x, a, b), conds="none")
        F = lemma7_antiderivative(n, c, x)
        assert sp.simplify(ref - (F.subs(x, b) - F.subs(x, a))) == 0, n
    return "n = 0..12: F_n' = x^n e^{cx} and the by-parts recursion; n <= 5 equals sympy.integrate"


def numeric_complex_c():
    rng = np.random.default_rng(7)
    c_s, x_s = sp.symbols("c x")
    worst = 0.0
    mp.mp.dps = 30
    for n in range(9):
        F = sp.lambdify((c_s, x_s), lemma7_antiderivative(n, c_s, x_s), "mpmath")
        for _ in range(4):
            c = mp.mpc(*rng.normal(size=2) * 3)
            a, b = (mp.mpf(float(v)) for v in sorted(rng.uniform(-2, 2, size=2)))
            quad = mp.quad(lambda t: t ** n * mp.exp(c * t), [a, b])
            val = F(c, b) - F(c, a)
            worst = max(worst, float(abs(val - quad) / max(1, abs(quad))))
    assert worst < 1e-20, worst
    return f"complex c, random intervals, n <= 8: max rel. error vs mpmath quadrature {worst:.1e}"


def fubini_route():
    w = sp.Symbol("w", real=True, nonzero=True)
    x1, x2 = sp.symbols("x1 x2")
    x0 = 1 - x1 - x2
    checks = 0
    # Θ_{01}(k, l) of Definition 18 on the triangle: phase -i Ω_{012} x_2 (Ω_{01m} vanishes for m = 0, 1)
    for mono in (x0 * x1, x0 * x0, x1 * x2, x2 * x2, x0 * x1 * x2 * x2, sp.Integer(1)):
        expr = mono * sp.exp(-sp.I * w * x2)
        mine = integrate_simplex(expr, (x1, x2))
        inner = sp.integrate(sp.expand(expr), (x1, 0, 1 - x2), conds="none")
        ref = 2 * sp.integrate(sp.expand(inner), (x2, 0, 1), conds="none")
        assert sp.simplify(sp.expand(mine - ref, complex=True)) == 0, mono
        checks += 1
    # tetrahedron, two independent phases: exact Fubini/Lemma 7 vs a 20-point Duffy-Gauss rule
    a, b = sp.symbols("a b", real=True)
    y1, y2, y3 = sp.symbols("y1 y2 y3")
    y0 = 1 - y1 - y2 - y3
    bary, wts = simplex_rule(3, 20)
    worst = 0.0
    for mono in (sp.Integer(1), y0 * y1, y2 * y3, y0 * y1 * y2 * y3, y3 ** 2 * y0 ** 2):
        exact = integrate_simplex(mono * sp.exp(-sp.I * (a * y2 + b * y3)), (y1, y2, y3), simplify=False)
        f_mono = sp.lambdify((y1, y2, y3), mono, "numpy")
        for av, bv in ((sp.Rational(7, 10), sp.Rational(-13, 10)), (sp.Rational(5, 2), sp.Rational(9, 4))):
            val = complex(exact.subs({a: av, b: bv}).evalf(30))
            fv = np.broadcast_to(f_mono(bary[:, 1], bary[:, 2], bary[:, 3]), wts.shape)
            quad = np.sum(wts * fv * np.exp(-1j * (float(av) * bary[:, 2] + float(bv) * bary[:, 3])))
            worst = max(worst, rel_err(val, quad))
            checks += 1
    assert worst < 1e-13, worst
    return (f"Fubini + Lemma 7 = sympy.integrate (triangle, symbolic Ω) and = Duffy-Gauss "
            f"(tet, {worst:.1e}); {checks} checks")


def main() -> int:
    t0 = time.time()
    lines = [general_n_telescoping(), explicit_n(), numeric_complex_c(), fubini_route()]
    lines.append("Lemma 7 as printed is correct (no erratum)")
    lines.append(f"time {time.time() - t0:.1f} s")
    summary("derive_lemma7", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
