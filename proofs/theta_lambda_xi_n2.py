"""Θ, Λ, Ξ of Definitions 18-19 for triangles (n = 2), in closed form; seed Eq. 12.1 and §12.

On a triangle σ = {i, j, k} with w = Ω_ijk the exponent of Definitions 18-19 for the pair (i, j) is
-i Σ_m Ω_ijm x_m = -i w x_k.  Every quantity is integrated exactly over the standard triangle
(Fubini + Lemma 7; the normalized integral (1/vol)∫ is affine invariant, Remark 11) and
compared with the printed formulas of §12:

  printed correctly:  Θ_ii(i,i) = 1/6, Λ_ii = 1, Ξ_ii(j,j) = Ξ_ii(k,k) = 1/90, Ξ_ii(j,k) = 1/180,
                      Λ_ij, Ξ_ij(k,k), Ξ_ij(i,j) + Ξ_ij(j,k).
  misprinted:         Eq. 12.1  Θ_ij(i,j): the w^3 term is -(i/6) w^3, not -(1/6) w^3;
                      Θ_ij(j,k) = Θ_ij(k,i): the factor of exp(-iw) is (-3 - iw), not (-3 + iw).

Then dhlb's Θ, Λ, Ξ are compared with the exact expressions (evaluated with 100 digits) for
curvatures from 1e-6 to 1e3, including multiples of 2π.
"""

import numpy as np
import sympy as sp
from _common import as_expr, check, simplex_integral

w = sp.Symbol("w", positive=True)
I = sp.I
E = sp.exp(-I * w)


def derived():
    x1, x2 = sp.symbols("x1 x2", real=True)
    b = {"i": 1 - x1 - x2, "j": x1, "k": x2}        # pair (i, j) = local (0, 1), k = 2
    expo = -I * w * b["k"]

    def norm_int(poly):
        return sp.simplify(2 * as_expr(simplex_integral(poly, expo, [x1, x2])))

    out = {"Λ_ij": norm_int(sp.Integer(1))}
    for u, v in [("i", "i"), ("i", "j"), ("i", "k"), ("j", "j"), ("j", "k"), ("k", "k")]:
        out[f"Θ_ij({u},{v})"] = norm_int(b[u] * b[v])
        out[f"Ξ_ij({u},{v})"] = norm_int(b["i"] * b["j"] * b[u] * b[v])
    return out


PRINTED = {
    "Θ_ij(i,j)": 2 * (E - 1 + I * w + w**2 / 2 - w**3 / 6) / w**4,                          # Eq. 12.1
    "Θ_ij(j,k)": 2 / w**4 * (3 - 2 * I * w - w**2 / 2 + (-3 + I * w) * E),
    "Λ_ij": 2 / w**4 * (w**2 - I * w**3 - w**2 * E),
    "Ξ_ij(k,k)": 2 / w**6 * (20 - 12 * I * w - 3 * w**2 + I * w**3 / 3 + (-20 - 8 * I * w + w**2) * E),
    "Ξ_ij(i,j)+Ξ_ij(j,k)": 2 / w**6 * (-6 + 4 * I * w + w**2 + w**4 / 12 - I * w**5 / 30 + (6 + 2 * I * w) * E),
}
CORRECTED = {
    "Θ_ij(i,j)": 2 * (E - 1 + I * w + w**2 / 2 - I * w**3 / 6) / w**4,
    "Θ_ij(j,k)": 2 / w**4 * (3 - 2 * I * w - w**2 / 2 + (-3 - I * w) * E),
}


def equal(a, b) -> bool:
    return sp.simplify(sp.expand(a - b)) == 0


def main() -> None:
    print("Θ, Λ, Ξ for n = 2")
    d = derived()
    d["Θ_ij(k,i)"] = d["Θ_ij(i,k)"]
    d["Ξ_ij(i,j)+Ξ_ij(j,k)"] = d["Ξ_ij(i,j)"] + d["Ξ_ij(j,k)"]
    for key in ("Λ_ij", "Ξ_ij(k,k)", "Ξ_ij(i,j)+Ξ_ij(j,k)"):
        check(equal(d[key], PRINTED[key]), f"§12 {key} as printed")
    for key in ("Θ_ij(i,j)", "Θ_ij(j,k)"):
        check(not equal(d[key], PRINTED[key]) and equal(d[key], CORRECTED[key]),
              f"§12 {key} misprinted; corrected: {CORRECTED[key]}")
    check(equal(d["Θ_ij(k,i)"], d["Θ_ij(j,k)"]), "Θ_ij(k,i) = Θ_ij(j,k) as stated")
    # no curvature in the exponent for the pair (i, i): the rational values of §12
    x1, x2 = sp.symbols("x1 x2", real=True)
    bi, bj, bk = 1 - x1 - x2, x1, x2

    def flat(poly):  # the pair (i, i): Ω_iim = 0, no exponent
        return sp.nsimplify(2 * as_expr(simplex_integral(poly, sp.Integer(0), [x1, x2])))

    check(flat(bi * bi) == sp.Rational(1, 6) and flat(sp.Integer(1)) == 1 and flat(bi**2 * bj**2) == sp.Rational(1, 90)
          and flat(bi**2 * bk**2) == sp.Rational(1, 90) and flat(bi**2 * bj * bk) == sp.Rational(1, 180),
          "§12: Θ_ii(i,i) = 1/6, Λ_ii = 1, Ξ_ii(j,j) = Ξ_ii(k,k) = 1/90, Ξ_ii(j,k) = 1/180")
    lim = {key: sp.limit(val, w, 0) for key, val in d.items() if "+" not in key}
    check(lim["Θ_ij(i,j)"] == sp.Rational(1, 12) and lim["Λ_ij"] == 1 and lim["Ξ_ij(k,k)"] == sp.Rational(1, 180),
          "Ω -> 0: Θ_ij(i,j) -> 1/12, Λ_ij -> 1, Ξ_ij(k,k) -> 1/180 (P1 values)")

    from dhlb.fem.integrals import lambda_, theta, xi
    loc = {"i": 0, "j": 1, "k": 2}
    ws = [1e-6, 1e-3, 0.3, 1.7, 2 * np.pi, 9.0, 31.4, 1e3, -2.5]
    worst = 0.0
    for key, val in d.items():
        if "+" in key:
            continue
        for wv in ws:
            ref = complex(sp.N(val.subs(w, sp.Rational(abs(wv))), 100))
            if wv < 0:
                ref = ref.conjugate()
            if key == "Λ_ij":
                got = lambda_([wv], 0, 1)
            else:
                u, v = key[key.index("(") + 1], key[key.index(",") + 1]
                got = (theta if key[0] == "Θ" else xi)([wv], 0, 1, loc[u], loc[v])
            worst = max(worst, abs(complex(got) - ref) / abs(ref))
    check(worst < 1e-12, f"dhlb theta/lambda_/xi match the closed forms for |w| in [1e-6, 1e3] "
                         f"(max rel. error {worst:.1e})")


if __name__ == "__main__":
    main()
