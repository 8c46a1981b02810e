"""The surface case n = 2 as a special case of Theorems 15 and 17.

Seed part 3 §12 and part 1 (Eq. 6.7, the Dirichlet terms of §6.1.1 with f_1, f_2, and
Appendix D.2-D.3).

Every entry is DERIVED here by exact integration (Fubini + Lemma 7) of the integrand of
proofs/dirichlet_theorem17.py over a triangle σ = {i, j, k} with w = Ω_ijk, and then compared
with the printed formula.  Conventions: part 1 writes M_jk = <<Ψ_j, Ψ_k>> (antilinear left),
Φ_j(v_k) = r_jk Φ_k(v_k); that is dhlb's M[j, k] with η_jk(X_j) = r_jk X_k, and its factor
r̄_jk = conj(r_jk).  §12 writes W_ij with <φ, ψ>_D = Σ W_ij <φ_j, η_ij ψ_i>, i.e. A[j, i] = r_ij W_ij.

Findings (also in proofs/README.md):
  * part 1, Eq. 6.7 M_jk, M_ii: correct.
  * part 1, §6.1.1 Δ_ii, Δ_jk with f_1, f_2, and the flat limit -r̄_jk cot(α_i)/2: correct.
  * part 1, D.3 <∇Ψ_j, ∇Ψ_j>: correct;  <∇Ψ_j, ∇Ψ_k>: the constant of the e^{iΩ} group is
    -(3g11 + 4g12 + 3g22), printed (-3g11 + 4g12 + 3g22).
  * part 3 §12: W_ii correct; the reductions of the Ξ- and Θ-sums and their expansions ("Thus")
    correct; W_ij (c-form) misprinted twice: (1/30) c^kk Ω^4 must be (i/30) c^kk Ω^5, and
    [c^ii - 2c^jj + c^jj] Ω^2 e^{-iΩ} must be [c^ii - 2c^ij + c^jj] Ω^2 e^{-iΩ};  W_ij (g-form,
    "rederived formulas in [33]"): (g11 - 2g12 + g22) Ω^4/60 must be i (g11 - 2g12 + g22) Ω^5/60.
"""

import sympy as sp
from _common import as_expr, check, simplex_integral

I = sp.I
w = sp.Symbol("w", positive=True)
X1, X2 = sp.symbols("x1 x2", real=True)
XS = [1 - X1 - X2, X1, X2]                      # local i, j, k = 0, 1, 2;  Ω_012 = w
EP, EM = sp.exp(I * w), sp.exp(-I * w)


def omega(a, b, c):
    if len({a, b, c}) < 3:
        return sp.Integer(0)
    perm = [sorted((a, b, c)).index(v) for v in (a, b, c)]
    inv = sum(1 for p in range(3) for q in range(p + 1, 3) if perm[p] > perm[q])
    return (-1) ** inv * w


W = {a: sp.Matrix(3, 3, lambda k, l: omega(a, k, l)) for a in range(3)}


def norm_integral(poly, a, b):
    """(1/vol) ∫_σ poly exp(-i Σ_m Ω_abm x_m)."""
    ph = -I * sum(omega(a, b, m) * XS[m] for m in range(3))
    return sp.expand(2 * as_expr(simplex_integral(sp.expand(poly), ph, [X1, X2])))


def dirichlet(a, b, c):
    """A[b, a] / r_ab for the 'stiffness' c = vol·G (any symmetric 3x3 with zero row sums)."""
    quad = W[a].T * c * W[b]
    br = (c[a, b] + sum(quad[l, q] * XS[a] * XS[b] * XS[l] * XS[q] for l in range(3) for q in range(3))
          + I * sum((c * W[a])[b, l] * XS[a] * XS[l] - (c * W[b])[a, l] * XS[b] * XS[l] for l in range(3)))
    return norm_integral(br, a, b)


def same(e1, e2) -> bool:
    """Exact equality of expressions Σ R(w, ...) exp(±iw) (compare the coefficient of each exponential)."""
    d = sp.expand(e1 - e2)
    parts = [d.coeff(EP), d.coeff(EM)]
    parts.append(sp.expand(d - parts[0] * EP - parts[1] * EM))
    syms = sorted(d.free_symbols, key=str)
    field = sp.QQ_I.frac_field(*syms)
    return all(field.from_sympy(sp.together(p)) == field.zero for p in parts)


def stiffness_g(origin):
    """C = vol·G for the metric g (coordinates: barycentrics of the two other vertices), area T."""
    g11, g12, g22, T = sp.symbols("g11 g12 g22 T", positive=True)
    g = sp.Matrix([[g11, g12], [g12, g22]])
    others = [v for v in range(3) if v != origin]
    d = sp.zeros(2, 3)
    for r, v in enumerate(others):
        d[r, origin], d[r, v] = -1, 1
    return (d.T * g.adjugate() * d) / (4 * T), (g11, g12, g22, T)     # vol G = T g^{-1}, det g = 4T^2


def main() -> None:
    print("Surface entries (n = 2)")
    # ---------------- part 1: i at the origin, g11 = |p_ij|^2, g12 = <p_ij, p_ik>, g22 = |p_ik|^2
    c, (g11, g12, g22, T) = stiffness_g(0)
    i, j, k = 0, 1, 2
    m_jk = T * norm_integral(XS[j] * XS[k], k, j)             # M[j, k] / r_kj,  r_kj = r̄_jk
    check(same(m_jk, T * (6 * EP - 6 - 6 * I * w + 3 * w**2 + I * w**3) / (3 * w**4))
          and sp.nsimplify(T * norm_integral(XS[i] ** 2, i, i)) == T / 6, "part 1, Eq. 6.7: M_jk, M_ii")

    d_jj = dirichlet(j, j, c)
    check(same(d_jj, (g22 + w**2 * (3 * g11 - 3 * g12 + g22) / 90) / (4 * T)), "part 1, D.3: <∇Ψ_j, ∇Ψ_j>")
    d_ii = dirichlet(i, i, c)
    p_jk2 = g11 - 2 * g12 + g22                                # |p_jk|^2
    check(same(d_ii, (p_jk2 + w**2 * (g11 + g12 + g22) / 90) / (4 * T)),
          "part 1, §6.1.1: Δ_ii = (|p_jk|² + Ω²(|p_ij|² + <p_ij, p_ik> + |p_ki|²)/90)/(4|t|)")

    d_jk = dirichlet(k, j, c)                                  # A[j, k] / r_kj = Δ_jk / r̄_jk
    f1 = (3 + I * w + w**4 / 24 - I * w**5 / 60 + (-3 + 2 * I * w + w**2 / 2) * EP) / w**4
    f2 = (4 + I * w - I * w**3 / 6 - w**4 / 12 + I * w**5 / 30 + (-4 + 3 * I * w + w**2) * EP) / w**4
    check(same(d_jk, ((g11 + g22) * f1 + g12 * f2) / T), "part 1, §6.1.1: Δ_jk with f_1 and f_2 as printed")
    check(sp.limit(f1, w, 0) == 0 and sp.limit(f2, w, 0) == -sp.Rational(1, 4),
          "part 1: f_1 -> 0, f_2 -> -1/4, so Δ_jk -> -r̄_jk <p_ij, p_ik>/(4|t|) = -r̄_jk cot(α_i)/2")
    s1, s2 = 3 * g11 + 4 * g12 + 3 * g22, g11 - 2 * g12 + g22
    head = s1 + I * w * (g11 + g12 + g22) - I * w**3 * g12 / 6 + w**4 * s2 / 24 - I * w**5 * s2 / 60
    tail_printed = ((-3 * g11 + 4 * g12 + 3 * g22) + I * w * (2 * g11 + 3 * g12 + 2 * g22)
                    + w**2 * (g11 + 2 * g12 + g22) / 2)
    tail_true = -s1 + I * w * (2 * g11 + 3 * g12 + 2 * g22) + w**2 * (g11 + 2 * g12 + g22) / 2
    check(not same(d_jk, (head + tail_printed * EP) / (T * w**4)) and same(d_jk, (head + tail_true * EP) / (T * w**4)),
          "part 1, D.3: <∇Ψ_j, ∇Ψ_k> misprinted; the e^{iΩ} group starts with -(3g11 + 4g12 + 3g22)")

    # ---------------- part 3 §12 in terms of the cotangent weights c^{ab} = vol <dx_a, dx_b>
    cij, cjk, cki = sp.symbols("c_ij c_jk c_ki", real=True)
    cm = sp.Matrix([[-cij - cki, cij, cki], [cij, -cij - cjk, cjk], [cki, cjk, -cjk - cki]])
    cii, cjj, ckk = cm[0, 0], cm[1, 1], cm[2, 2]
    check(same(dirichlet(i, i, cm), cii + (cjj - cjk + ckk) * w**2 / 90),
          "§12: W_ii = c^ii + (c^jj - c^jk + c^kk)Ω²/90")
    xi = lambda u, v: norm_integral(XS[i] * XS[j] * XS[u] * XS[v], i, j)
    th = lambda u, v: norm_integral(XS[u] * XS[v], i, j)
    quad_sum = sp.expand(sum((W[i].T * cm * W[j])[l, q] * xi(l, q) for l in range(3) for q in range(3)))
    check(same(quad_sum, -(cij * xi(k, k) + ckk * (xi(i, j) + xi(j, k))) * w**2),
          "§12: Σ c^{k'k''} Ω_ik'l' Ω_jk''l'' Ξ_ij(l', l'') = -(c^ij Ξ_ij(k,k) + c^kk(Ξ_ij(i,j) + Ξ_ij(j,k)))Ω²")
    quad_thus = 2 / w**4 * (6 * ckk - 20 * cij + (12 * cij - 4 * ckk) * I * w + (3 * cij - ckk) * w**2
                            - cij / 3 * I * w**3
                            - ckk / 12 * w**4 + ckk / 30 * I * w**5
                            + ((20 * cij - 6 * ckk) + (8 * cij - 2 * ckk) * I * w - cij * w**2) * EM)
    check(same(quad_sum, quad_thus), "§12: the expanded Ξ-sum ('Thus,') as printed")
    lin_sum = sp.expand(I * sum(omega(i, kk, l) * cm[j, kk] * th(i, l) - omega(j, kk, l) * cm[i, kk] * th(j, l)
                                for kk in range(3) for l in range(3)))
    check(same(lin_sum, (cii * th(j, k) + cjj * th(k, i) + ckk * th(i, j)) * I * w),
          "§12: i Σ (Ω_ik'l' c^jk' Θ_ij(i,l') - Ω_jk'l' c^ik' Θ_ij(j,l')) "
          "= (c^ii Θ(j,k) + c^jj Θ(k,i) + c^kk Θ(i,j)) iΩ")
    lin_thus = 2 / w**4 * ((3 * (cii + cjj) - ckk) * I * w + (2 * (cii + cjj) - ckk) * w**2
                           + sp.Rational(1, 2) * (ckk - cii - cjj) * I * w**3 + ckk / 6 * w**4
                           + ((ckk - 3 * (cii + cjj)) * I * w + (cii + cjj) * w**2) * EM)
    check(same(lin_sum, lin_thus), "§12: the expanded Θ-sum ('Thus we get') as printed")
    w_ij = dirichlet(i, j, cm)
    printed = 2 / w**4 * ((6 * ckk - 20 * cij) + (12 * cij + 3 * (cii + cjj) - 5 * ckk) * I * w
                          + (4 * cij + 2 * (cii + cjj - ckk)) * w**2
                          + sp.Rational(1, 6) * (3 * (ckk - cii - cjj) - 8 * cij) * I * w**3
                          + ckk / 12 * w**4 + ckk / 30 * w**4
                          + ((20 * cij - 6 * ckk) + (8 * cij - 3 * (cii + cjj) - ckk) * I * w
                             + (cii - 2 * cjj + cjj) * w**2) * EM)
    true = 2 / w**4 * ((6 * ckk - 20 * cij) + (12 * cij + 3 * (cii + cjj) - 5 * ckk) * I * w
                       + (4 * cij + 2 * (cii + cjj - ckk)) * w**2
                       + sp.Rational(1, 6) * (3 * (ckk - cii - cjj) - 8 * cij) * I * w**3
                       + ckk / 12 * w**4 + ckk / 30 * I * w**5
                       + ((20 * cij - 6 * ckk) + (8 * cij - 3 * (cii + cjj) - ckk) * I * w
                          + (cii - 2 * cij + cjj) * w**2) * EM)
    check(not same(w_ij, printed) and same(w_ij, true),
          "§12: W_ij (c-form) misprinted: (1/30) c^kk Ω⁴ must be (i/30) c^kk Ω⁵, and the e^{-iΩ} Ω² "
          "coefficient [c^ii - 2c^jj + c^jj] must be [c^ii - 2c^ij + c^jj]")
    # g-form ("rederived formulas in [33]"): k at the origin, coordinates x_i, x_j
    cg, (h11, h12, h22, T) = stiffness_g(2)
    q = 1 / (4 * T)                                            # 1/(2 sqrt(det g)), det g = 4T^2
    printed_c = {(i, j): -h12 * q, (j, k): -(h11 - h12) * q, (k, i): -(h22 - h12) * q,
                 (k, k): (h11 - 2 * h12 + h22) * q, (i, i): h22 * q, (j, j): h11 * q}
    check(all(sp.simplify(cg[a, b] - v) == 0 for (a, b), v in printed_c.items()),
          "§12: the six cotangent weights in terms of g (k at the origin) as printed")
    w_ij = dirichlet(i, j, cg)
    s1, s2 = 3 * h11 + 4 * h12 + 3 * h22, h11 - 2 * h12 + h22
    common = s1 - (h11 + h12 + h22) * I * w + h12 / 6 * I * w**3 + s2 / 24 * w**4
    tail = -(s1 + (2 * h11 + 3 * h12 + 2 * h22) * I * w - sp.Rational(1, 2) * (h11 + 2 * h12 + h22) * w**2) * EM
    check(not same(w_ij, (common + s2 / 60 * w**4 + tail) / (T * w**4))
          and same(w_ij, (common + s2 / 60 * I * w**5 + tail) / (T * w**4)),
          "§12: W_ij (g-form, '[33]') misprinted: (g11 - 2g12 + g22) Ω⁴/60 must be i(g11 - 2g12 + g22) Ω⁵/60")

    # ---------------- dhlb against the (correct) part-1 formulas, evaluated with 60 digits
    import mpmath as mp
    import numpy as np
    from _common import random_simplex

    from dhlb.fem.integrals import local_matrices
    mp.mp.dps = 60
    rng = np.random.default_rng(3)
    f1m = lambda s: (3 + 1j * s + s**4 / 24 - 1j * s**5 / 60 + (-3 + 2j * s + s**2 / 2) * mp.exp(1j * s)) / s**4
    f2m = lambda s: (4 + 1j * s - 1j * s**3 / 6 - s**4 / 12 + 1j * s**5 / 30
                     + (-4 + 3j * s + s**2) * mp.exp(1j * s)) / s**4
    mjk = lambda s: (6 * mp.exp(1j * s) - 6 - 6j * s + 3 * s**2 + 1j * s**3) / (3 * s**4)
    worst = 0.0
    for wv in (1e-5, 0.01, 0.4, 2.0, 3.1, 7.5, 60.0, -1.3):
        p, gram, area = random_simplex(rng, 2)
        alpha = rng.normal(size=2) * 3                  # r_01, r_02 free; r_12 from the holonomy
        r = np.exp(1j * np.array([alpha[0], alpha[1], alpha[1] - alpha[0] + wv]))
        mass, dir_ = local_matrices(gram, area, [wv], r)
        e1, e2 = p[1] - p[0], p[2] - p[0]
        g11, g12, g22 = e1 @ e1, e1 @ e2, e2 @ e2
        s = mp.mpf(wv)
        ref_d = complex(np.conj(r[2]) / area * ((g11 + g22) * f1m(s) + g12 * f2m(s)))
        ref_m = complex(np.conj(r[2]) * area * mjk(s))
        p_jk2 = (p[2] - p[1]) @ (p[2] - p[1])
        ref_ii = (p_jk2 + wv**2 * (g11 + g12 + g22) / 90) / (4 * area)
        scale = np.abs(dir_).max()
        worst = max(worst, abs(dir_[1, 2] - ref_d) / scale, abs(mass[1, 2] - ref_m) / abs(ref_m),
                    abs(dir_[0, 0] - ref_ii) / scale)
    check(worst < 1e-12, f"dhlb local matrices = part-1 formulas (M_jk, Δ_ii, Δ_jk) on random triangles, "
                         f"Ω from 1e-5 to 60 (max rel. error {worst:.1e})")


if __name__ == "__main__":
    main()
