r"""Closed forms of Θ, Λ, Ξ (seed part 3, Definitions 18 and 19) for n = 2 and n = 3.

Definitions (normalized integrals over an n-simplex σ with barycentric coordinates x_0..x_n):

    Θ_ij(k, l) = (1/vol) ∫_σ x_k x_l         exp(-i Σ_m Ω_ijm x_m)          (Definition 18)
    Λ_ij       = (1/vol) ∫_σ                  exp(-i Σ_m Ω_ijm x_m)          (Definition 19)
    Ξ_ij(k, l) = (1/vol) ∫_σ x_i x_j x_k x_l  exp(-i Σ_m Ω_ijm x_m)          (Definition 19)

with Ω extended antisymmetrically from the canonically oriented triangles and Ω_ijm = 0 when two
indices coincide.  The normalized integral does not depend on the metric (an affine map changes
the volume form by a constant, Remark 11), so everything is computed on the reference simplex.

Derivation: exact iterated integration (Fubini) with Lemma 7 (``derive_lemma7.py``) gives the
generic closed forms -- sums of rational functions of the curvatures times exponentials.

* n = 2: every Θ_ij(k,l), Λ_ij, Ξ_ij(k,l) for all 9 ordered pairs (i, j) is integrated
  directly from the definition, symbolic in w = Ω_012.
* n = 3: the moments ``J_p(a, b) = (1/vol) ∫ x^p exp(-i(a x_2 + b x_3))`` are integrated
  symbolically in (a, b); Θ/Λ/Ξ for the pair (i, j) is ``J`` after relabelling the vertices
  (i, j, k, l) -> (0, 1, 2, 3) (k < l the other two), with ``a = Ω_ijk``, ``b = Ω_ijl``.  The
  relabelling is an affine automorphism of the simplex; it is checked numerically below by a
  quadrature of the *unrelabelled* definition.

Checks (all asserted):

1. Hermitian symmetry ``Θ_ji(k,l) = conj Θ_ij(k,l)`` (and Λ, Ξ) -- symbolically for n = 2;
2. flat limit Ω -> 0 equals the polynomial moment (exact iterated integral) -- sympy series for
   n = 2, 250-digit evaluation at curvature ~1e-15 for n = 3;
3. the closed forms (evaluated with 100-digit arithmetic) equal the code's
   ``dhlb.fem.integrals.theta / lambda_ / xi`` to relative 1e-12 at rational curvatures,
   including tiny curvature and nearly confluent (a ≈ b) cases where the closed forms cancel
   catastrophically in double precision;
4. the closed forms equal a Duffy-transformed Gauss rule applied to the definitions (1e-12).
"""

from __future__ import annotations

import sys
import time
from itertools import combinations_with_replacement, permutations

import mpmath as mp
import numpy as np
import sympy as sp
from _derive_util import flat_moment, from_terms, integrate_simplex, simplex_rule, summary, to_terms

from dhlb.fem.integrals import lambda_, theta, xi

I = sp.I
TOL = 1e-12


def omega_tensor(n, values):
    """Ω[a][b][c] (sympy) from the values on the canonically oriented triangles a < b < c."""
    T = [[[sp.Integer(0)] * (n + 1) for _ in range(n + 1)] for _ in range(n + 1)]
    for (a, b, c), v in values.items():
        for perm in permutations(range(3)):
            idx = [(a, b, c)[p] for p in perm]
            sign = sp.combinatorics.Permutation(list(perm)).signature()
            T[idx[0]][idx[1]][idx[2]] = sign * v
    return T


def mono(p, xs):
    return sp.Mul(*[x ** e for x, e in zip(xs, p)])


def pairs_kl(n):
    return list(combinations_with_replacement(range(n + 1), 2))


# --------------------------------------------------------------------------- n = 2
def derive_n2():
    w = sp.Symbol("w", real=True)
    y1, y2 = sp.symbols("y1 y2")
    X = [1 - y1 - y2, y1, y2]
    Om = omega_tensor(2, {(0, 1, 2): w})
    forms = {}
    for i in range(3):
        for j in range(3):
            phase = sp.exp(-I * sp.Add(*[Om[i][j][m] * X[m] for m in range(3)]))
            forms["L", i, j] = integrate_simplex(phase, (y1, y2))
            for k, l in pairs_kl(2):
                forms["T", i, j, k, l] = integrate_simplex(X[k] * X[l] * phase, (y1, y2))
                forms["X", i, j, k, l] = integrate_simplex(X[i] * X[j] * X[k] * X[l] * phase, (y1, y2))
    return w, forms


def check_n2(w, forms):
    # 1. hermitian symmetry, 2. flat limits
    for key, f in forms.items():
        i, j = key[1], key[2]
        g = forms[(key[0], j, i) + key[3:]]
        assert all(sp.cancel(r) == 0 for r in to_terms(g - sp.conjugate(f)).values()), key
        if i > j:       # the flat limit of the conjugate pair follows
            continue
        p = [0, 0, 0]
        for v in key[3:]:
            p[v] += 1
        if key[0] == "X":
            p[i] += 1
            p[j] += 1
        lim = sp.series(f, w, 0, 1).removeO()
        assert sp.simplify(lim - flat_moment(p)) == 0, (key, lim)
    # 3. code values and 4. quadrature
    ws = [sp.Rational(-7, 3), sp.Rational(-1, 2), sp.Rational(1, 1000), sp.Rational(3, 2), sp.Integer(5),
          sp.Rational(31, 2), sp.Rational(1, 10 ** 7)]
    om = np.array([[float(v)] for v in ws])
    bary, wts = simplex_rule(2, 30)
    worst_code = worst_quad = 0.0
    for key, f in forms.items():
        fn = sp.lambdify(w, f, "mpmath")
        i, j = key[1], key[2]
        if key[0] == "L":
            code = lambda_(om, i, j)
        elif key[0] == "T":
            code = theta(om, i, j, *key[3:])
        else:
            code = xi(om, i, j, *key[3:])
        with mp.workdps(100):
            exact = [complex(fn(mp.mpf(v.p) / v.q)) if f.has(w) else complex(f) for v in ws]
        worst_code = max(worst_code, max(abs(c - e) / abs(e) for c, e in zip(code, exact)))
        # quadrature of the definition at the moderate curvatures
        poly = np.ones(len(wts))
        for v in key[3:]:
            poly = poly * bary[:, v]
        if key[0] == "X":
            poly = poly * bary[:, i] * bary[:, j]
        sgn = [float(omega_tensor(2, {(0, 1, 2): 1})[i][j][m]) for m in range(3)]
        for v, e in zip(ws[:5], exact[:5]):
            q = np.sum(wts * poly * np.exp(-1j * float(v) * (bary @ np.array(sgn))))
            worst_quad = max(worst_quad, abs(q - e) / abs(e))
    assert worst_code < TOL, worst_code
    assert worst_quad < TOL, worst_quad
    return worst_code, worst_quad


# --------------------------------------------------------------------------- n = 3
def derive_n3_moments():
    a, b = sp.symbols("a b", real=True)
    y1, y2, y3 = sp.symbols("y1 y2 y3")
    X = [1 - y1 - y2 - y3, y1, y2, y3]
    ps = set()
    for k, l in pairs_kl(3):
        p = [0, 0, 0, 0]
        p[k] += 1
        p[l] += 1
        ps.add(tuple(p))
        p[0] += 1
        p[1] += 1
        ps.add(tuple(p))
    ps.add((0, 0, 0, 0))
    J = {}
    for p in sorted(ps):
        J[p] = integrate_simplex(mono(p, X) * sp.exp(-I * (a * X[2] + b * X[3])), (y1, y2, y3), simplify=False)
    return a, b, J


def n3_values(a, b, J, om_vals, dps=100):
    """Exact Θ/Λ/Ξ for n = 3 at closed rational curvature (dict of ordered pairs -> values)."""
    Om = omega_tensor(3, dict(zip([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)], om_vals)))
    fns = {p: sp.lambdify((a, b), f, "mpmath") for p, f in J.items()}
    out = {}
    with mp.workdps(dps):
        for i, j in permutations(range(4), 2):
            k, l = [m for m in range(4) if m not in (i, j)]
            role = {i: 0, j: 1, k: 2, l: 3}
            av, bv = Om[i][j][k], Om[i][j][l]
            args = (mp.mpf(av.p) / av.q, mp.mpf(bv.p) / bv.q)

            def J_of(verts):
                p = [0, 0, 0, 0]
                for v in verts:
                    p[role[v]] += 1
                return complex(fns[tuple(p)](*args))

            out["L", i, j] = J_of(())
            for s, t in pairs_kl(3):
                out["T", i, j, s, t] = J_of((s, t))
                out["X", i, j, s, t] = J_of((i, j, s, t))
    return out


def closed_omega(o012, o013, o023):
    return (o012, o013, o023, o023 - o013 + o012)          # dΩ = 0 on the tetrahedron


def check_n3(a, b, J):
    R = sp.Rational
    cases = [closed_omega(R(7, 10), R(-13, 10), R(5, 4)), closed_omega(R(3), R(-2), R(9, 2)),
             closed_omega(R(1, 1000), R(-1, 500), R(3, 1000)),                # small curvature
             closed_omega(R(2), R(2) + R(1, 10 ** 5), R(1, 3)),               # nearly confluent
             closed_omega(R(-11, 2), R(17, 3), R(1, 7))]
    om = np.array([[float(v) for v in c] for c in cases])
    exact = [n3_values(a, b, J, c) for c in cases]
    worst = 0.0
    for key in exact[0]:
        i, j = key[1], key[2]
        if key[0] == "L":
            code = lambda_(om, i, j)
        elif key[0] == "T":
            code = theta(om, i, j, *key[3:])
        else:
            code = xi(om, i, j, *key[3:])
        for c, e in zip(code, exact):
            worst = max(worst, abs(c - e[key]) / abs(e[key]))
    assert worst < TOL, worst
    # quadrature of the definition itself (no relabelling) at the first two curvatures
    bary, wts = simplex_rule(3, 22)
    worst_q = 0.0
    for c, e in zip(cases[:2], exact[:2]):
        Om = omega_tensor(3, dict(zip([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)], c)))
        for key, val in e.items():
            i, j = key[1], key[2]
            phase = np.exp(-1j * (bary @ np.array([float(Om[i][j][m]) for m in range(4)])))
            poly = np.ones(len(wts))
            for v in key[3:] + ((i, j) if key[0] == "X" else ()):
                poly = poly * bary[:, v]
            q = np.sum(wts * poly * phase)
            worst_q = max(worst_q, abs(q - val) / abs(val))
    assert worst_q < TOL, worst_q
    # flat limit
    with mp.workdps(250):
        for p, f in J.items():
            v = complex(sp.lambdify((a, b), f, "mpmath")(mp.mpf("1e-15"), mp.mpf("-2.5e-15")))
            assert abs(v - float(flat_moment(p))) < 1e-13, (p, v)
    # Hermitian symmetry: Θ_ji = conj Θ_ij
    for e in exact:
        for key, val in e.items():
            other = (key[0], key[2], key[1]) + key[3:]
            assert abs(e[other] - np.conj(val)) <= 1e-14 * abs(val), key
    return worst, worst_q, len(exact[0]) * len(cases)


def main() -> int:
    t0 = time.time()
    w, f2 = derive_n2()
    wc2, wq2 = check_n2(w, f2)
    t_ij = f2["T", 0, 1, 0, 1]
    lines = [f"n = 2: {len(f2)} closed forms from the definitions (all 9 ordered pairs); "
             f"code vs exact max rel. {wc2:.1e}, quadrature vs exact {wq2:.1e}; flat limits and "
             "Θ_ji = conj Θ_ij verified symbolically",
             f"n = 2: Θ_01(0,1) = {sp.simplify(t_ij)}  (== 2(e^(-iw) - 1 + iw + w²/2 - i w³/6)/w⁴)"]
    ref = 2 * (sp.exp(-I * w) - 1 + I * w + w ** 2 / 2 - I * w ** 3 / 6) / w ** 4
    assert sp.simplify(t_ij - ref) == 0
    a, b, J = derive_n3_moments()
    wc3, wq3, cnt = check_n3(a, b, J)
    lines.append(f"n = 3: {len(J)} generic moments J_p(a,b); {cnt} code values (incl. |Ω| ~ 1e-3 and "
                 f"a - b ~ 1e-5) vs exact max rel. {wc3:.1e}; quadrature of the definition {wq3:.1e}")
    lines.append(f"n = 3: Λ_01 (a = Ω_012, b = Ω_013) = {from_terms(to_terms(J[(0, 0, 0, 0)]))}")
    lines.append(f"time {time.time() - t0:.1f} s")
    summary("derive_theta_lambda_xi", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
