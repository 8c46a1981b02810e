"""Seed part 3, Theorems 15 and 17: the local mass and Dirichlet products of piecewise-linear sections.

With ψ̃ = Σ_a z_a x_a φ_a (φ_a radially parallel from vertex a, ∇φ_a = i ω_a φ_a,
ω_a = Σ_{k,l} Ω_akl x_l dx_k, φ_a = r_ab exp(-i Σ_m Ω_abm x_m) φ_b; proofs/holonomy_frames.py)
the integrand of A[b, a] = ∫ <∇(x_b φ_b), ∇(x_a φ_a)> (antilinear in the first slot) is

    <dx_b + i x_b ω_b, dx_a + i x_a ω_a> <φ_b, φ_a>
  = r_ab e^{-i Σ_m Ω_abm x_m} [ G_ab + Σ_{l,l'} (W^aᵀ G W^b)_{ll'} x_a x_b x_l x_l'
                               + i Σ_l ((G W^a)_{bl} x_a x_l - (G W^b)_{al} x_b x_l) ],

G_kl = <dx_k, dx_l>, W^a[k, l] = Ω_akl; integrating gives Theorem 17 (Eq. 11.5) with Θ, Λ, Ξ.
Checked symbolically for n = 2 and n = 3 (closed Ω, general metric, all ordered pairs):
  1. the expansion above (the bracket of Eq. 11.5);
  2. an independent route: the same section written in the single frame φ_0,
     ψ̃ = F φ_0, ∇ψ̃ = (dF + i F ω_0) φ_0, gives the same integrand (uses dΩ = 0);
  3. Hermitian symmetry A[a, b] = conj(A[b, a]) pointwise, and the mass integrand of Theorem 15
     x_a x_b <φ_b, φ_a> = r_ab x_a x_b e^{-i Σ Ω_abm x_m} (both routes);
  4. the convention of docs/conventions.md: with Ω = 0, A[b, a] = r_ab vol G_ab = -w r_ab with
     w = -vol G_ab the cotangent weight, i.e. the edge term |z_b - r_ab z_a|².
"""

from itertools import combinations

import sympy as sp
from _common import check

I = sp.I


def setting(n):
    xs = list(sp.symbols(f"x0:{n + 1}", real=True))     # all barycentrics, treated as independent
    free = {t: sp.Symbol(f"W{''.join(map(str, t))}", real=True) for t in combinations(range(n + 1), 3) if t[0] == 0}
    om = dict(free)
    for a, b, c in combinations(range(n + 1), 3):
        if a > 0:
            om[a, b, c] = free[0, b, c] - free[0, a, c] + free[0, a, b]

    def omega(a, b, c):
        if len({a, b, c}) < 3:
            return sp.Integer(0)
        srt = tuple(sorted((a, b, c)))
        perm = [srt.index(v) for v in (a, b, c)]
        inversions = sum(1 for p in range(3) for q in range(p + 1, 3) if perm[p] > perm[q])
        return (-1) ** inversions * om[srt]

    gred = sp.Matrix(n, n, lambda i, j: sp.Symbol(f"g{min(i, j) + 1}{max(i, j) + 1}", real=True))
    d = sp.Matrix.hstack(-sp.ones(n, 1), sp.eye(n))
    gram = d.T * gred * d                                 # rows sum to zero
    rho = [sp.Integer(0)] + list(sp.symbols(f"rho1:{n + 1}", real=True))   # r_0a = exp(i rho_a)
    return xs, omega, gram, rho


def main() -> None:
    print("Theorems 15 and 17: local mass and Dirichlet integrands")
    for n in (2, 3):
        xs, omega, G, rho = setting(n)
        nv = n + 1
        W = {a: sp.Matrix(nv, nv, lambda k, l: omega(a, k, l)) for a in range(nv)}
        xv = sp.Matrix(xs)
        wvec = {a: W[a] * xv for a in range(nv)}          # ω_a = Σ_k wvec_a[k] dx_k
        e = lambda a: sp.eye(nv)[:, a]
        conj = lambda ex: ex.subs(I, -I)

        def r(a, b):                                      # connection consistent with the holonomy
            return sp.exp(I * (rho[b] - rho[a] + omega(0, a, b)))

        def bracket(a, b):
            quad = W[a].T * G * W[b]
            return (G[a, b] + sum(quad[l, q] * xs[a] * xs[b] * xs[l] * xs[q] for l in range(nv) for q in range(nv))
                    + I * sum((G * W[a])[b, l] * xs[a] * xs[l] - (G * W[b])[a, l] * xs[b] * xs[l] for l in range(nv)))

        def phase(a, b):
            return -sum(omega(a, b, m) * xs[m] for m in range(nv))

        for a in range(nv):
            for b in range(nv):
                # 1. expansion of <dx_b + i x_b ω_b, dx_a + i x_a ω_a>
                u_b = e(b) + I * xs[b] * wvec[b]
                u_a = e(a) + I * xs[a] * wvec[a]
                direct = sp.expand((conj(u_b).T * G * u_a)[0])
                assert sp.expand(direct - bracket(a, b)) == 0, (n, a, b)
                # 2. single frame φ_0: x_a φ_a = x_a r_a0 e^{iθ_a} φ_0, θ_a = -Σ Ω_a0m x_m
                chat = {}
                for v in (a, b):
                    th = -sum(omega(v, 0, m) * xs[m] for m in range(nv))
                    chat[v] = sp.Matrix([sp.KroneckerDelta(v, k) + I * xs[v] * (sp.diff(th, xs[k]) + wvec[0][k])
                                         for k in range(nv)])
                frame0 = sp.expand((conj(chat[b]).T * G * chat[a])[0])
                on_simplex = {xs[0]: 1 - sum(xs[1:])}
                assert sp.expand((frame0 - bracket(a, b)).subs(on_simplex)) == 0, (n, a, b)
                th_a = -sum(omega(a, 0, m) * xs[m] for m in range(nv))
                th_b = -sum(omega(b, 0, m) * xs[m] for m in range(nv))
                # exponent of frame-0 route: i(θ_a - θ_b) + (-i rho_a) - (-i rho_b); of Theorem 17: r_ab e^{i phase}
                lhs = sp.expand(th_a - th_b - rho[a] + rho[b])
                rhs = sp.expand(rho[b] - rho[a] + omega(0, a, b) + phase(a, b))
                diff = sp.expand(lhs - rhs)
                # the difference is a multiple of (1 - Σ x) (it vanishes on the simplex)
                assert sp.expand(diff.subs(xs[0], 1 - sum(xs[1:]))) == 0, (n, a, b)
                # 3. Hermitian symmetry of the full integrand r_ab e^{i phase} bracket
                full_ab = bracket(a, b) * sp.exp(I * phase(a, b))
                full_ba = bracket(b, a) * sp.exp(I * phase(b, a))
                assert sp.expand(conj(full_ab) - full_ba) == 0, (n, a, b)
        check(True, f"n = {n}: Eq. 11.5 bracket = <dx_b + i x_b ω_b, dx_a + i x_a ω_a> for all pairs")
        check(True, f"n = {n}: the single-frame (φ_0) route gives the same integrand and phase (needs dΩ = 0)")
        check(True, f"n = {n}: the integrand is Hermitian, A[a, b] = conj(A[b, a])")
        # 4. flat limit and sign convention
        flat = {s: 0 for s in set().union(*[W[a].free_symbols for a in range(nv)])}
        check(all(sp.expand(bracket(a, b).subs(flat) - G[a, b]) == 0 for a in range(nv) for b in range(nv)),
              f"n = {n}: Ω = 0 gives A[b, a] = r_ab vol G_ab, i.e. -w r_ab with w = -vol G_ab "
              "(edge term |z_b - r_ab z_a|²)")


if __name__ == "__main__":
    main()
