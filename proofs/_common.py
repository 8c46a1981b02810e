"""Shared helpers of the proof scripts: exact integration over simplices, divided differences, quadrature.

Nothing here is taken from dhlb; the scripts compare the package against these independent routes.
"""

from __future__ import annotations

import sys
from collections import defaultdict
from math import factorial
from pathlib import Path

import numpy as np
import sympy as sp

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:  # run from a source tree without installation
    sys.path.insert(0, str(ROOT))


# ----------------------------------------------------------------------------------------------
# Exact iterated integration of Σ P(x) exp(L(x)) over the standard simplex (Fubini + Lemma 7)
# ----------------------------------------------------------------------------------------------

def lemma7_antiderivative(k: int, c, v):
    """Seed Lemma 7: an antiderivative of ``v^k e^{cv}`` is ``k!/c^{k+1} Σ_j (-1)^j (cv)^{k-j}/(k-j)! e^{cv}``.

    Returned without the factor ``e^{cv}`` (a polynomial in ``v`` over ``c``).
    """
    return factorial(k) / c ** (k + 1) * sum((-1) ** j * (c * v) ** (k - j) / factorial(k - j) for j in range(k + 1))


def _integrate_variable(terms: dict, v, upper) -> dict:
    """∫_0^upper of ``Σ_E terms[E] exp(E)`` dv, with every ``E`` linear in ``v``."""
    out: dict = defaultdict(lambda: sp.Integer(0))
    for expo, poly in terms.items():
        a = sp.expand(sp.diff(expo, v))
        rest = sp.expand(expo - a * v)
        for (k,), coeff in sp.Poly(sp.expand(poly), v).terms():
            if a == 0:
                key = rest
                out[key] += coeff * upper ** (k + 1) / (k + 1)
            else:
                anti = lemma7_antiderivative(k, a, v)
                out[sp.expand(rest + a * upper)] += coeff * anti.subs(v, upper)
                out[rest] -= coeff * anti.subs(v, 0)
    return {key: sp.expand(val) for key, val in out.items()}


def simplex_integral(poly, exponent, xs) -> dict:
    """∫ over the standard simplex {x_i >= 0, Σ x_i <= 1} of ``poly * exp(exponent)``.

    ``xs`` are the n integration variables (the barycentric coordinates x_1..x_n; x_0 = 1 - Σ x_i
    must already be substituted).  Returns ``{E: coefficient}`` meaning ``Σ coefficient * exp(E)``.
    """
    terms = {sp.expand(exponent): sp.expand(poly)}
    n = len(xs)
    for i in range(n - 1, -1, -1):          # innermost: last variable, upper limit 1 - Σ previous
        upper = 1 - sum(xs[:i])
        terms = _integrate_variable(terms, xs[i], upper)
    return terms


def as_expr(terms: dict):
    return sum(val * sp.exp(key) for key, val in terms.items())


def same_exponential_sum(d1: dict, d2: dict) -> bool:
    """Whether two sums ``Σ c_E exp(E)`` agree: coefficients compared per exponent, exactly.

    The coefficients are rational functions; they are compared in the field of rational functions
    over Q (or Q(i)) in their free symbols, which is exact and much faster than ``cancel``.
    """
    keys = {sp.expand(k) for k in list(d1) + list(d2)}
    merged = {k: sp.Integer(0) for k in keys}
    for d, sign in ((d1, 1), (d2, -1)):
        for k, v in d.items():
            merged[sp.expand(k)] += sign * sp.sympify(v)
    exprs = list(merged.values())
    syms = sorted(set().union(*[e.free_symbols for e in exprs]) or {sp.Symbol("_dummy")}, key=str)
    dom = sp.QQ_I if any(e.has(sp.I) for e in exprs) else sp.QQ
    field = dom.frac_field(*syms)
    return all(field.from_sympy(e) == field.zero for e in exprs)


# ----------------------------------------------------------------------------------------------
# Confluent divided differences of exp by the residue (partial fraction) formula
# ----------------------------------------------------------------------------------------------

def exp_divided_difference(nodes_mult) -> dict:
    """``exp[z_1^(μ_1), ..., z_C^(μ_C)]`` for DISTINCT symbolic nodes, as ``{z_j: rational coefficient}``.

    Residue formula: ``Σ_j 1/(μ_j - 1)! d^{μ_j-1}/dz^{μ_j-1} [e^z / Π_{l≠j} (z - z_l)^{μ_l}]_{z=z_j}``.
    """
    z = sp.Symbol("z_")
    out = {}
    for j, (zj, mj) in enumerate(nodes_mult):
        rest = sp.Integer(1)
        for l, (zl, ml) in enumerate(nodes_mult):
            if l != j:
                rest *= (z - zl) ** ml
        # d^{m-1}/dz^{m-1} (e^z g) = e^z Σ_k C(m-1, k) g^{(k)} with g = 1/rest
        val = sum(sp.binomial(mj - 1, k) * sp.diff(1 / rest, z, k) for k in range(mj)) / factorial(mj - 1)
        out[sp.expand(zj)] = sp.together(val.subs(z, zj))
    return out


# ----------------------------------------------------------------------------------------------
# Numerical quadrature on simplices: collapsed (Duffy) tensor Gauss-Legendre rule
# ----------------------------------------------------------------------------------------------

def simplex_rule(n: int, order: int):
    """Points (barycentric, shape (q, n+1)) and weights summing to 1 on the n-simplex.

    Collapsed coordinates ``x_1 = u_1, x_2 = (1-u_1) u_2, ...`` with Jacobian ``Π (1-u_k)^{n-k}``
    and a Gauss-Legendre rule of ``order`` points per direction.
    """
    g, w = np.polynomial.legendre.leggauss(order)
    g, w = 0.5 * (g + 1), 0.5 * w
    grids = np.meshgrid(*([g] * n), indexing="ij")
    wgrid = np.meshgrid(*([w] * n), indexing="ij")
    u = np.stack([a.ravel() for a in grids], axis=1)
    weight = np.prod(np.stack([a.ravel() for a in wgrid], axis=1), axis=1)
    x = np.zeros((u.shape[0], n + 1))
    rem = np.ones(u.shape[0])
    for k in range(n):
        x[:, k + 1] = rem * u[:, k]
        weight = weight * (1 - u[:, k]) ** (n - 1 - k)
        rem = rem * (1 - u[:, k])
    x[:, 0] = rem
    return x, weight * factorial(n)


def random_simplex(rng, n: int):
    """Random n-simplex in R^n: (points, gram of barycentric gradients, volume)."""
    while True:
        p = rng.normal(size=(n + 1, n))
        e = p[1:] - p[0]
        g = e @ e.T
        if np.linalg.cond(g) < 1e3:
            break
    vol = np.sqrt(np.linalg.det(g)) / factorial(n)
    d = np.hstack([-np.ones((n, 1)), np.eye(n)])
    return p, d.T @ np.linalg.solve(g, d), vol


def closed_curvature(rng, n: int, scale: float):
    """Random edge angles α and the closed (exact) curvature Ω = dα on the local triangles; r = exp(iα)."""
    from itertools import combinations
    edges = list(combinations(range(n + 1), 2))
    alpha = dict(zip(edges, rng.normal(size=len(edges)) * scale))
    om = np.array([alpha[b, c] - alpha[a, c] + alpha[a, b] for a, b, c in combinations(range(n + 1), 3)])
    return om, np.exp(1j * np.array([alpha[e] for e in edges]))


def check(cond: bool, what: str) -> None:
    """Assert with a message, and report success."""
    assert cond, what
    print(f"  ok: {what}")


