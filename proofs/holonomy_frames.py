"""The associated bundle in one simplex: Lemma 4, Eq. 10.1/11.3 and the connection forms 11.4.

Setting: an n-simplex with vertices v_0..v_n, affine coordinates x_1..x_n (x_0 = 1 - Σ x_k, so
v_0 = 0 and v_k = e_k), a closed discrete curvature Ω_abc, and the convention that parallel
transport around an oriented triangle Δ multiplies by exp(i ∫_Δ Ω̃) (docs/conventions.md:
r_ij r_jk r_ki = exp(iΩ_ijk)).  Proved for n = 2 and n = 3, all vertex pairs:

 1. (Lemma 4)  Ω̃ = Σ_{j<k} 2 Ω_0jk dx_j ∧ dx_k integrates to Ω_abc over EVERY face abc
    (faces avoiding 0 need dΩ = 0).
 2. (Eq. 11.3) ∫ over the oriented triangle (v_a, v_b, p) of Ω̃ equals Σ_m Ω_abm x_m(p);
    hence the radially parallel frames satisfy φ_a = r_ab exp(-i Σ_m Ω_abm x_m) φ_b.
 3. (Eq. 11.4) ω_a = Σ_{k,l} Ω_akl x_l dx_k (with ∇φ_a = i ω_a φ_a) vanishes on rays from v_a,
    is compatible with the transition (i ω_a = i ω_b + d log g_ab, g_ab = exp(-i Σ Ω_abm x_m)),
    and dω_a = -Ω̃, so the holonomy exp(-i ∮ ω_a) = exp(i ∫ Ω̃) has the assumed sign.
    The uniqueness of ω_a (radial + transitions) is the argument in the proof of Theorem 14.
 4. The transition functions satisfy the cocycle condition g_ab g_bc g_ca = 1 (with r's).
 5. The local gauge of dhlb.fem.integrals: frames φ_0(v_a) give r'_0a = 1, r'_ab = exp(iΩ_0ab),
    and the local matrices transform as M[b, a] = g_b M'[b, a] conj(g_a) with g_a = r_0a.
"""

from itertools import combinations, permutations

import sympy as sp
from _common import check


def setting(n):
    xs = list(sp.symbols(f"x1:{n + 1}", real=True))
    bary = [1 - sum(xs)] + xs
    tri = list(combinations(range(n + 1), 3))
    free = {t: sp.Symbol(f"W{''.join(map(str, t))}", real=True) for t in tri if t[0] == 0}
    om = dict(free)
    for a, b, c in tri:  # closedness dΩ = 0 on the tetrahedron (0, a, b, c)
        if a > 0:
            om[a, b, c] = free[0, b, c] - free[0, a, c] + free[0, a, b]

    def omega(a, b, c):
        if len({a, b, c}) < 3:
            return sp.Integer(0)
        srt = tuple(sorted((a, b, c)))
        sign = sp.combinatorics.Permutation([srt.index(v) for v in (a, b, c)]).signature()
        return sign * om[srt]

    return xs, bary, omega


def two_form(n, omega):
    """Coefficient matrix C (antisymmetric, n x n) of Ω̃ = Σ_{j<k} C_jk dx_j∧dx_k = Σ 2 Ω_0jk dx_j∧dx_k."""
    return sp.Matrix(n, n, lambda j, k: 2 * omega(0, j + 1, k + 1))


def integral_over_triangle(c, pa, pb, pc):
    """∫ of the constant 2-form (matrix c) over the oriented affine triangle (pa, pb, pc)."""
    u, v = pb - pa, pc - pa
    return sp.Rational(1, 2) * sum(c[j, k] * (u[j] * v[k] - u[k] * v[j])
                                   for j in range(c.rows) for k in range(j + 1, c.rows))


def main() -> None:
    print("Associated bundle on a simplex: Lemma 4, Eq. 11.3, Eq. 11.4")
    for n in (2, 3):
        xs, bary, omega = setting(n)
        c = two_form(n, omega)
        verts = [sp.zeros(n, 1)] + [sp.eye(n)[:, k] for k in range(n)]
        p = sp.Matrix(xs)
        for a, b, d in combinations(range(n + 1), 3):
            assert sp.expand(integral_over_triangle(c, verts[a], verts[b], verts[d]) - omega(a, b, d)) == 0
        check(True, f"n = {n}: Lemma 4, Ω̃ = Σ 2Ω_0jk dx_j∧dx_k has the prescribed integral on every face")

        for a, b in permutations(range(n + 1), 2):
            lhs = integral_over_triangle(c, verts[a], verts[b], p)
            rhs = sum(omega(a, b, m) * bary[m] for m in range(n + 1))
            assert sp.expand(lhs - rhs) == 0, (a, b)
        check(True, f"n = {n}: ∫_(v_a, v_b, p) Ω̃ = Σ_m Ω_abm x_m(p) for all ordered pairs (Eq. 11.3)")

        # 1-forms as coefficient vectors on dx_1..dx_n; dx_0 = -Σ dx_k
        dx = [sp.Matrix([-1] * n)] + [sp.eye(n)[:, k] for k in range(n)]

        def w_form(a):
            return sum((sum(omega(a, k, l) * bary[l] for l in range(n + 1)) * dx[k] for k in range(n + 1)),
                       sp.zeros(n, 1))

        def d_of(alpha):  # exterior derivative, as antisymmetric coefficient matrix
            return sp.Matrix(n, n, lambda j, k: sp.diff(alpha[k], xs[j]) - sp.diff(alpha[j], xs[k]))

        for a in range(n + 1):
            wa = w_form(a)
            radial = p - verts[a]
            assert sp.expand((wa.T * radial)[0]) == 0
            assert sp.expand(d_of(wa) + c) == sp.zeros(n, n)
            for b in range(n + 1):
                if b == a:
                    continue
                phase = -sum(omega(a, b, m) * bary[m] for m in range(n + 1))     # g_ab = r_ab e^{i phase}
                grad = sp.Matrix([sp.diff(phase, x) for x in xs])
                assert sp.expand(wa - (w_form(b) + grad)) == sp.zeros(n, 1), (a, b)
        check(True, f"n = {n}: ω_a is radial-free, dω_a = -Ω̃ and i ω_a = i ω_b + d log g_ab (Eq. 11.4)")

        for a, b, d in combinations(range(n + 1), 3):
            expo = sum((omega(a, b, m) + omega(b, d, m) + omega(d, a, m)) * bary[m] for m in range(n + 1))
            assert sp.expand(expo - omega(a, b, d)) == 0
        check(True, f"n = {n}: cocycle g_ab g_bc g_ca = r_ab r_bc r_ca exp(-iΩ_abc) = 1")

    # local gauge: with g_a = r_0a (g_0 = 1) the local connection is r'_ab = conj(g_b) r_ab g_a
    r01, r02, w = sp.symbols("r01 r02 w")
    r12 = sp.exp(sp.I * w) * r02 / r01          # holonomy r_01 r_12 r_20 = e^{iw} with |r| = 1
    g = {0: 1, 1: r01, 2: r02}
    rp = {(0, 1): 1 / g[1] * r01 * g[0], (0, 2): 1 / g[2] * r02 * g[0], (1, 2): 1 / g[2] * r12 * g[1]}
    check(sp.simplify(rp[0, 1] - 1) == 0 and sp.simplify(rp[0, 2] - 1) == 0
          and sp.simplify(rp[1, 2] - sp.exp(sp.I * w)) == 0,
          "local gauge: r'_0a = 1 and r'_ab = exp(iΩ_0ab) (frames φ_0(v_a))")
    # M[b, a] = r_ab K_ba in any gauge, so M = diag(g) M' diag(conj g):
    kba = sp.Symbol("K")
    check(sp.simplify(r12 * kba - g[2] * (rp[1, 2] * kba) / g[1]) == 0,
          "M[b, a] = g_b M'[b, a] conj(g_a) converts local-gauge matrices to global frames")


if __name__ == "__main__":
    main()
