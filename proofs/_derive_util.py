"""Shared helpers of the ``proofs/derive_*.py`` scripts (not a script itself).

* :func:`lemma7_antiderivative` -- the antiderivative of ``x^n exp(c x)`` of seed Lemma 7 (part 3),
  proved in ``derive_lemma7.py``;
* :func:`integrate_var` / :func:`integrate_simplex` -- exact iterated integration (Fubini) of
  ``polynomial x exp(linear)`` over the reference simplex, built on Lemma 7;
* :func:`simplex_rule` -- a collapsed (Duffy) Gauss--Legendre rule on the n-simplex, an
  independent numerical check of the exact integrals;
* small geometry helpers computed from scratch (not from ``dhlb``).
"""

from __future__ import annotations

from itertools import product
from math import factorial

import numpy as np
import sympy as sp


# --------------------------------------------------------------------------- Lemma 7 and Fubini
def lemma7_antiderivative(n: int, c, x):
    """``n!/c^(n+1) Σ_k (-1)^k (c x)^(n-k)/(n-k)! exp(c x)`` (seed part 3, Lemma 7), ``c != 0``."""
    return sp.factorial(n) / c ** (n + 1) * sp.Add(
        *[(-1) ** k * (c * x) ** (n - k) / sp.factorial(n - k) for k in range(n + 1)]) * sp.exp(c * x)


_EXP = sp.Function("EXPTAG")   # opaque stand-in for exp: sympy's expand cannot move it into denominators


def _split_exp(term):
    """``term = rest * EXPTAG(E1)^k1 ...`` -> ``(rest, Σ k E)``."""
    rest, expo = sp.Integer(1), sp.Integer(0)
    for f in sp.Mul.make_args(term):
        if isinstance(f, _EXP):
            expo += f.args[0]
        elif isinstance(f, sp.Pow) and isinstance(f.base, _EXP):
            expo += f.base.args[0] * f.exp
        else:
            assert not f.has(_EXP), f"exponential inside {f}"
            rest *= f
    return rest, sp.expand(expo)


def to_terms(expr) -> dict:
    """``expr = Σ_E R_E exp(E)`` as a dict ``{E: R_E}`` (exponentials must not sit in denominators)."""
    tagged = sp.sympify(expr).replace(sp.exp, lambda arg: _EXP(arg))
    groups: dict = {}
    for term in sp.Add.make_args(sp.expand(tagged)):
        rest, expo = _split_exp(term)
        groups[expo] = groups.get(expo, 0) + rest
    return groups


def from_terms(terms: dict, simplify=True):
    """``Σ_E R_E exp(E)``; each ``R_E`` put over a common denominator and factored."""
    out = []
    for e, r in terms.items():
        r = sp.factor(sp.cancel(sp.together(r))) if simplify else r
        if r != 0:
            out.append(r * sp.exp(e))
    return sp.Add(*out)


def integrate_var(terms: dict, x, lo, hi) -> dict:
    """Exact ``∫_lo^hi`` of ``Σ_E R_E(x) exp(E)`` (``R_E`` polynomial in ``x``, ``E`` linear in ``x``).

    A term whose exponent has an ``x``-coefficient ``c`` that is not identically zero is
    integrated with Lemma 7 (so the result is the generic closed form, valid for ``c != 0``);
    ``c == 0`` terms are integrated as polynomials.
    """
    out: dict = {}

    def add(e, r):
        e = sp.expand(e)
        out[e] = out.get(e, 0) + r

    for expo, rest in terms.items():
        c = sp.expand(sp.diff(expo, x))
        if c.has(x):
            raise ValueError("exponent is not linear in the integration variable")
        e0 = sp.expand(expo - c * x)
        poly = sp.Poly(sp.expand(rest), x)
        if c == 0:
            anti = sp.integrate(poly.as_expr(), x)
            add(e0, sp.expand(anti.subs(x, hi) - anti.subs(x, lo)))
            continue
        for (k,), coeff in poly.terms():
            # Lemma 7: ∫ x^k e^{cx} = k!/c^(k+1) Σ_j (-1)^j (cx)^(k-j)/(k-j)! e^{cx}
            q = sp.factorial(k) / c ** (k + 1) * sp.Add(
                *[(-1) ** j * (c * x) ** (k - j) / sp.factorial(k - j) for j in range(k + 1)])
            add(e0 + c * hi, sp.expand(coeff * q.subs(x, hi)))
            add(e0 + c * lo, -sp.expand(coeff * q.subs(x, lo)))
    return out


def integrate_simplex(expr, xs, simplify=True):
    """Exact normalized integral ``(1/vol) ∫_σ expr`` over the reference n-simplex.

    ``xs = (x_1, ..., x_n)`` are the affine coordinates (barycentric coordinates of vertices
    1..n; ``x_0 = 1 - Σ x_a``); ``expr`` (a sum of ``polynomial * exp(linear)``) must already be
    written in them.  Fubini: integrate ``x_1`` over ``[0, 1 - x_2 - ... - x_n]``, then ``x_2``,
    ...; vol = 1/n!.  Returns the closed form ``Σ_E R_E exp(E)``.
    """
    n = len(xs)
    terms = to_terms(expr)
    for a in range(n):
        terms = integrate_var(terms, xs[a], 0, 1 - sp.Add(*xs[a + 1:]))
    terms = {e: r * sp.factorial(n) for e, r in terms.items()}
    return from_terms(terms, simplify)


def flat_moment(p) -> sp.Rational:
    """``(1/vol) ∫_σ Π x_m^{p_m}`` by exact iterated integration (no closed form assumed)."""
    n = len(p) - 1
    xs = sp.symbols(f"y1:{n + 1}")
    x0 = 1 - sp.Add(*xs)
    mono = x0 ** p[0] * sp.Mul(*[xs[a] ** p[a + 1] for a in range(n)])
    return sp.nsimplify(integrate_simplex(mono, xs))


# --------------------------------------------------------------------------- numerics
def simplex_rule(n: int, k: int):
    """Collapsed Gauss--Legendre rule on the n-simplex with ``k`` points per direction.

    Returns ``(bary, w)``: barycentric coordinates ``(N, n+1)`` and weights ``(N,)`` summing to 1,
    so that ``Σ w f(bary) ≈ (1/vol) ∫_σ f``.  Duffy map ``x_1 = t_1``,
    ``x_a = (1-t_1)...(1-t_{a-1}) t_a``, Jacobian ``Π_a (1-t_a)^(n-a)``.
    """
    t, wt = np.polynomial.legendre.leggauss(k)
    t, wt = (t + 1) / 2, wt / 2
    pts, wts = [], []
    for idx in product(range(k), repeat=n):
        ts = t[list(idx)]
        w = np.prod(wt[list(idx)])
        x, scale = [], 1.0
        for a in range(n):
            x.append(scale * ts[a])
            w *= (1 - ts[a]) ** (n - 1 - a)
            scale *= 1 - ts[a]
        pts.append([1 - sum(x)] + x)
        wts.append(w * factorial(n))
    return np.array(pts), np.array(wts)


def rel_err(a, b) -> float:
    """``max|a - b| / max(1, max|b|)``."""
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


def barycentric_gradients(P):
    """Exact (sympy) or float gradients ``∇x_a`` of the barycentric coordinates of the simplex ``P``.

    ``P`` has shape ``(n+1, n)`` (vertices in R^n).  Solves ``[Pᵀ; 1] x = [p; 1]``: the rows of the
    inverse, without the last column, are the gradients.  Returns an ``(n+1, n)`` sympy Matrix.
    """
    P = sp.Matrix(P)
    n = P.shape[1]
    T = P.T.col_join(sp.ones(1, n + 1))
    Ti = T.inv()
    return Ti[:, :n]


def simplex_volume(P):
    P = sp.Matrix(P)
    E = sp.Matrix.hstack(*[(P[a, :] - P[0, :]).T for a in range(1, P.shape[0])])
    return sp.Abs(E.det()) / sp.factorial(P.shape[1])


def qmul(p, q):
    """The quaternion product of ``p = (w, x, y, z)`` and ``q`` (Hamilton: ij = k), componentwise."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw)


def summary(name: str, lines) -> None:
    print(f"{name}: OK")
    for line in lines:
        print("  -", line)
