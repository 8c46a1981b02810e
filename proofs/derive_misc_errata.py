r"""Small seed errata settled by a short computation (part 3 §3, §7, §8; part 1 §6.1.2; part 2 §3.2, App. B).

1. Part 3, Proposition 2.  Over the boundary of a triangle (a cycle graph), bundles are classified by
   the conjugacy class of their holonomy.  With E of rank 2 and holonomy H = diag(1, -1):
   * the parallel sections of End(E) = E ⊗ E* are the commutant of H, of dimension 2 < 4 = rank,
     so E ⊗ E* is *not* trivial (Proposition 1) -- "in particular, E ⊗ E* is trivial" is false for
     rank >= 2 (true for line bundles: dimension 1 = rank);
   * for the trivial rank-2 bundle T, Hom(T, E) = E ⊗ T* has non-vanishing parallel sections although
     T ≇ E (holonomies I and H are not conjugate): the first half needs a parallel section that is
     *invertible at every vertex*, not merely non-vanishing.
2. Part 3, proof of Theorem 11: with ξ_ij = arg(z_j / (ω_ij z_i)), ``exp(i dξ_ijk) = 1/dω_ijk``
   (multiplicative dω = ω_ij ω_jk ω_ki); the printed ``exp(2πi dξ)`` is false.
3. Part 3, Remark 5: ``z -> exp(2πi z)`` maps C onto C* (not "onto C"), kernel Z.
4. Part 1, §6.1.2: the Hopf differential q of S = H·I + Q has ``|q| = |κ1 - κ2| / 2`` --
   proportional to |κ1 - κ2|, not to (κ1 - κ2)²; and the transport coefficient of a 2-vector is
   ``e^{2iθ}`` (unit modulus), not the printed ``e^{2θ}``.
5. Part 2, Eq. 3.3 (and Alg. 6 line 7): with θ_ji the polar angle at j of the edge *from j to i*,
   the extrinsic Eq. 3.2 ``ω_ij = ½(<e_ij, Z_i> + <e_ij, Z_j>)`` equals
   ``½ ℓ_ij (ν_i cos(φ_i - θ_ij) - ν_j cos(φ_j - θ_ji))`` (flat plane, random data); the printed
   ``+ ν_j`` is wrong.
6. Part 2, §4.3: with ``δ̂_ij = arg(P̂_ij(ψ_i)/ψ_j)``, ``P̂_ij = e^{iω̂_ij}``, the spinning form must be
   ``σ̂ = ω̂ - δ̂`` (as the seed's own σ̃ := ω̃ - δ) so that ``e^{iσ̂} ψ_i/|ψ_i| = ψ_j/|ψ_j|``; the printed
   ``σ̂ := ω̂ + δ̂`` fails.
7. Part 2, App. B (branch triangles): from ``α̃_s = α̃_p + ξ`` and ``e^{iα̃_s} = e^{-iα̃_p}`` it follows
   ``ξ + α̃_p = -α̃_p + 2aπ`` and ``α̃_p + ξ/2 = aπ``; the printed ``ξ + α̃_s = -α̃_s + 2aπ`` and
   ``α̃_m := α̃_s + ξ/2`` (equal to aπ) are wrong -- α̃_s must be α̃_p there.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import sympy as sp
from _derive_util import summary


def parallel_hom_sections(etaE, etaF, edges):
    """Parallel sections f of Hom(E, F) over a graph: f_j η^E_ij = η^F_ij f_i (basis of the solution space)."""
    k = etaE[edges[0]].shape[0]
    nv = 1 + max(max(e) for e in edges)
    unknowns = sp.symbols(f"f0:{nv * k * k}")
    f = [sp.Matrix(k, k, unknowns[v * k * k:(v + 1) * k * k]) for v in range(nv)]
    eqs = []
    for i, j in edges:
        eqs += list(f[j] * etaE[i, j] - etaF[i, j] * f[i])
    A, _ = sp.linear_eq_to_matrix(eqs, unknowns)
    return [[sp.Matrix(k, k, list(v[u * k * k:(u + 1) * k * k])) for u in range(nv)] for v in A.nullspace()]


def proposition_2():
    edges = [(0, 1), (1, 2), (2, 0)]
    Id, H = sp.eye(2), sp.diag(1, -1)
    E = {(0, 1): Id, (1, 2): Id, (2, 0): H}
    Tr = {(0, 1): Id, (1, 2): Id, (2, 0): Id}
    # End(E) = Hom(E, E): dimension of the parallel sections vs. rank 4
    end = parallel_hom_sections(E, E, edges)
    assert len(end) == 2 < 4
    # line bundle: End(L) is trivial (one parallel section = rank 1)
    r = sp.exp(sp.I * sp.Rational(7, 5))
    L = {(0, 1): sp.Matrix([[1]]), (1, 2): sp.Matrix([[1]]), (2, 0): sp.Matrix([[r]])}
    assert len(parallel_hom_sections(L, L, edges)) == 1
    # Hom(T, E): non-vanishing parallel sections exist, none is invertible, and T ≇ E
    hom = parallel_hom_sections(Tr, E, edges)
    assert hom and all(any(m != sp.zeros(2, 2) for m in sec) for sec in hom)
    c = sp.symbols(f"c0:{len(hom)}")
    general0 = sp.zeros(2, 2)
    for ci, sec in zip(c, hom):
        general0 += ci * sec[0]
    assert sp.expand(general0.det()) == 0                 # every parallel section is singular at vertex 0
    assert (H.trace(), H.det()) != (Id.trace(), Id.det())  # holonomies not conjugate
    return ("Prop. 2: dim parallel End(E) = 2 < 4 (E ⊗ E* not trivial); Hom(T, E) has non-vanishing "
            "but no invertible parallel sections")


def theorem_11(rng):
    worst_good, n_bad = 0.0, 0
    for _ in range(200):
        z = rng.normal(size=3) + 1j * rng.normal(size=3)
        om = np.exp(1j * rng.uniform(-np.pi, np.pi, size=3))        # ω_ij, ω_jk, ω_ki
        pairs = ((0, 1), (1, 2), (2, 0))
        dxi = sum(np.angle(z[b] / (o * z[a])) for (a, b), o in zip(pairs, om))
        d_om = np.prod(om)
        worst_good = max(worst_good, abs(np.exp(1j * dxi) - 1 / d_om))
        n_bad += abs(np.exp(2j * np.pi * dxi) - 1 / d_om) > 1e-6
    assert worst_good < 1e-13
    assert n_bad >= 190, n_bad                              # the printed identity fails almost always
    # a concrete failure of the printed exp(2πi dξ)
    z = np.array([1.0, 1j, -1.0])
    om = np.exp(1j * np.array([0.3, -0.2, 0.4]))
    dxi = sum(np.angle(z[b] / (o * z[a])) for (a, b), o in zip(((0, 1), (1, 2), (2, 0)), om))
    assert abs(np.exp(2j * np.pi * dxi) - 1 / np.prod(om)) > 0.1
    return (f"Theorem 11 proof: exp(i dξ) = 1/dω (max err {worst_good:.1e}); the printed exp(2πi dξ) = 1/dω "
            f"fails on {n_bad}/200 random triangles")


def remark_5():
    z = sp.Symbol("z")
    w = sp.Symbol("w", nonzero=True)
    assert sp.simplify(sp.exp(2 * sp.pi * sp.I * (sp.log(w) / (2 * sp.pi * sp.I))) - w) == 0   # onto C*
    assert sp.exp(2 * sp.pi * sp.I * z).subs(z, 3) == 1                                   # Z in the kernel
    assert all(sp.exp(2 * sp.pi * sp.I * z) != 0 for z in (0, sp.I, -5 * sp.I))       # never 0
    return "Remark 5: exp(2πi·): C -> C* onto, kernel ⊇ Z, 0 not attained (codomain C*)"


def hopf_differential():
    s11, s12, s22 = sp.symbols("s11 s12 s22", real=True)
    S = sp.Matrix([[s11, s12], [s12, s22]])                # shape operator in an orthonormal frame
    H = S.trace() / 2
    Q = S - H * sp.eye(2)                                  # trace-free part
    # anti-linear Q(a ∂x) = q ā ∂x  <=>  real matrix [[Re q, Im q], [Im q, -Re q]]
    q = Q[0, 0] + sp.I * Q[0, 1]
    assert sp.simplify(Q - sp.Matrix([[sp.re(q), sp.im(q)], [sp.im(q), -sp.re(q)]])) == sp.zeros(2, 2)
    k1, k2 = list(S.eigenvals())
    assert sp.simplify(sp.Abs(q) ** 2 - ((k1 - k2) / 2) ** 2) == 0    # |q| = |κ1 - κ2| / 2
    # not proportional to (κ1 - κ2)²: the ratio |q| / (κ1 - κ2)² is not constant
    rat = [sp.Abs(q).subs({s11: a, s12: 0, s22: 0}) / a ** 2 for a in (1, 2)]
    assert rat[0] != rat[1]
    theta = sp.Symbol("theta", real=True)
    assert sp.simplify(sp.Abs(sp.exp(2 * sp.I * theta)) - 1) == 0
    assert sp.Abs(sp.exp(2 * sp.Rational(1, 3))) != 1
    return "§6.1.2: |q| = |κ1 - κ2|/2 (not ∝ (κ1 - κ2)²); e^{2iθ} is unit, e^{2θ} is not"


def stripe_eq_3_3(rng):
    worst_ok, n_bad = 0.0, 0
    for _ in range(200):
        pi_, pj = rng.normal(size=2), rng.normal(size=2)
        beta_i, beta_j = rng.uniform(-np.pi, np.pi, size=2)          # reference edge directions (polar 0)
        phi_i, phi_j = rng.uniform(-np.pi, np.pi, size=2)
        nu_i, nu_j = rng.uniform(0.2, 3, size=2)
        Zi = nu_i * np.array([np.cos(beta_i + phi_i), np.sin(beta_i + phi_i)])
        Zj = nu_j * np.array([np.cos(beta_j + phi_j), np.sin(beta_j + phi_j)])
        e = pj - pi_
        ell = np.linalg.norm(e)
        th_ij = np.arctan2(e[1], e[0]) - beta_i                        # polar angle of e_ij at i
        th_ji = np.arctan2(-e[1], -e[0]) - beta_j                      # polar angle of e_ji at j
        extrinsic = 0.5 * (e @ Zi + e @ Zj)                            # Eq. 3.2
        fixed = 0.5 * ell * (nu_i * np.cos(phi_i - th_ij) - nu_j * np.cos(phi_j - th_ji))
        printed = 0.5 * ell * (nu_i * np.cos(phi_i - th_ij) + nu_j * np.cos(phi_j - th_ji))
        worst_ok = max(worst_ok, abs(fixed - extrinsic))
        n_bad += abs(printed - extrinsic) > 1e-6
    assert worst_ok < 1e-13 and n_bad >= 190, (worst_ok, n_bad)
    return f"part 2 Eq. 3.3: '- ν_j cos(φ_j - θ_ji)' matches Eq. 3.2 ({worst_ok:.0e}); printed '+' fails {n_bad}/200"


def stripe_spinning_form(rng):
    n_ok = n_bad = 0
    for _ in range(200):
        psi_i, psi_j = rng.normal(size=2) + 1j * rng.normal(size=2)
        om = rng.uniform(-6, 6)
        delta = np.angle(np.exp(1j * om) * psi_i / psi_j)
        target = psi_j / abs(psi_j)
        n_ok += abs(np.exp(1j * (om - delta)) * psi_i / abs(psi_i) - target) < 1e-12
        n_bad += abs(np.exp(1j * (om + delta)) * psi_i / abs(psi_i) - target) > 1e-6
    assert n_ok == 200 and n_bad >= 190, (n_ok, n_bad)
    return f"part 2 §4.3: σ̂ = ω̂ - δ̂ transports ψ_i to ψ_j (200/200); printed ω̂ + δ̂ fails {n_bad}/200"


def stripe_appendix_b():
    a_p, xi, a = sp.symbols("alpha_p xi a", real=True)
    a_s = a_p + xi
    # e^{iα_s} = e^{-iα_p}  <=>  α_s = -α_p + 2aπ
    sol = sp.solve(sp.Eq(a_s, -a_p + 2 * a * sp.pi), xi)[0]
    assert sp.simplify((a_p + sol / 2) - a * sp.pi) == 0                 # α̃_m = α̃_p + ξ/2 = aπ
    val = (a_s + xi / 2).subs(xi, sol).subs({a_p: sp.Rational(3, 10), a: 1})
    assert sp.simplify(val / sp.pi).is_integer is False                  # α̃_s + ξ/2 is not aπ
    return "part 2 App. B: α̃_p + ξ/2 = aπ (printed α̃_s + ξ/2 is not a multiple of π)"


def main() -> int:
    t0 = time.time()
    lines = [proposition_2(), theorem_11(np.random.default_rng(11)), remark_5(), hopf_differential(),
             stripe_eq_3_3(np.random.default_rng(33)), stripe_spinning_form(np.random.default_rng(43)),
             stripe_appendix_b(), f"time {time.time() - t0:.1f} s"]
    summary("derive_misc_errata", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
