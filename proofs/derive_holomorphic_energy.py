r"""Seed part 1, Eq. 4.1/6.8 and Appendices C, D.4: E_A − E_H, its boundary term, and the signs.

Definitions. A section ψ of a hermitian line bundle over an oriented surface, in a local unitary
gauge on a planar chart with orthonormal oriented coordinates (x, y): ``∇ψ = dψ − i a ψ`` for a
real 1-form ``a = a_x dx + a_y dy``; the curvature density is ``F = ∂_x a_y − ∂_y a_x`` (the
holonomy of a small positive loop is ``exp(i∫F)``, in the convention ``z_j = r_ij z_i`` of a
parallel section). ``∂ψ = (∇_x ψ − i∇_y ψ)/√2`` and ``∂̄ψ = (∇_x ψ + i∇_y ψ)/√2`` so that
``|∇ψ|² = |∂ψ|² + |∂̄ψ|²`` and ``E_D = E_H + E_A`` with ``E_H = ½∫|∂̄ψ|²``, ``E_A = ½∫|∂ψ|²``.
Hermitian products are antilinear in the first slot: ``⟨u, v⟩ = ū v``.

Derived and asserted:

1. (symbolic, ψ and a with arbitrary 2-jets: generic quadratic polynomials) the pointwise identity
   ``|∂ψ|² − |∂̄ψ|² = F|ψ|² − div(J)`` with ``J = (−Im(ψ̄ ∇_y ψ), Im(ψ̄ ∇_x ψ))``; by Stokes
   ``∫_M div J = ∮_{∂M} J·ν ds = ∮_{∂M} Im⟨∇ψ, ψ⟩`` (ν the outer normal, the boundary run with
   the surface on its left, ``J·ν = −Im(ψ̄ ∇_T ψ) = Im⟨∇_T ψ, ψ⟩``). Hence
   ``2(E_A − E_H) = ∫ F|ψ|² − ∮ Im⟨∇ψ, ψ⟩`` — Appendix C with ``F = nK``.
2. (symbolic) on a boundary edge j → k, in a parallel frame ``ψ = ((1−t) z_j + t r̄_jk z_k) e``:
   ``−∫_0^1 Im⟨ψ', ψ⟩ dt = Im(z̄_j r̄_jk z_k)``, the Hermitian form with ``B[j,k] = −(i/2) r̄_jk``.
   The seed's Eq. 6.8 prints the entry as ``ε_jk r̄_jk / 2`` (no factor i): that matrix is not
   the imaginary part of the edge form (its form is ``Re(z̄_j r̄_jk z_k)``).
3. (numeric, the package) flat planar meshes: ψ = z (holomorphic vector field z∂_z) has
   ``ψᴴ A_{+1} ψ = 0`` and ψ = z̄ has ``ψᴴ A_{−1} ψ = 0`` to rounding, while ``ψᴴ A_0 ψ = 2·area``;
   round sphere: A_{±1} positive semidefinite, ``dim ker A_{+1}`` → 3 (n = 1, the conformal
   vector fields) and 5 (n = 2, holomorphic quadratic differentials of O(4)): the 3rd/4th and
   5th/6th eigenvalues separate by a factor > 100.
"""

from __future__ import annotations

import sys
import time

import _common  # noqa: F401  (puts the source tree on sys.path)
import numpy as np
import sympy as sp


def pointwise_identity() -> None:
    x, y = sp.symbols("x y", real=True)
    monomials = [sp.Integer(1), x, y, x * x, x * y, y * y]

    def generic(name):  # a real polynomial of degree 2 with symbolic coefficients: every 2-jet at a point
        c = sp.symbols(f"{name}0:6", real=True)
        return sum(ci * m for ci, m in zip(c, monomials))

    u, v, ax, ay = generic("u"), generic("v"), generic("ax"), generic("ay")
    psi = u + sp.I * v
    Dx = sp.diff(psi, x) - sp.I * ax * psi
    Dy = sp.diff(psi, y) - sp.I * ay * psi
    d = (Dx - sp.I * Dy) / sp.sqrt(2)
    dbar = (Dx + sp.I * Dy) / sp.sqrt(2)
    F = sp.diff(ay, x) - sp.diff(ax, y)

    def sq(w):
        w = sp.expand(w)
        return sp.expand(sp.re(w) ** 2 + sp.im(w) ** 2)

    lhs = sq(d) - sq(dbar)
    Jx = -sp.im(sp.expand(sp.conjugate(psi) * Dy))
    Jy = sp.im(sp.expand(sp.conjugate(psi) * Dx))
    rhs = F * sq(psi) - sp.diff(Jx, x) - sp.diff(Jy, y)
    assert sp.expand(lhs - rhs) == 0, "pointwise Weitzenböck identity"
    # boundary flux: outer normal ν = (T_y, −T_x) for a tangent T with the surface on the left
    Tx, Ty = sp.symbols("T_x T_y", real=True)
    flux = Jx * Ty + Jy * (-Tx)
    DT = Tx * Dx + Ty * Dy
    im_inner = sp.im(sp.expand(sp.conjugate(DT) * psi))     # Im⟨∇_T ψ, ψ⟩, antilinear first slot
    assert sp.expand(flux - im_inner) == 0, "J·ν = Im⟨∇_T ψ, ψ⟩"
    print("1. |∂ψ|² − |∂̄ψ|² = F|ψ|² − div J and J·ν = Im⟨∇_T ψ, ψ⟩: verified symbolically")


def edge_term() -> None:
    t = sp.symbols("t", real=True)
    zj, zk, r = sp.symbols("z_j z_k r")
    f = (1 - t) * zj + t * sp.conjugate(r) * zk
    integrand = sp.conjugate(sp.diff(f, t)) * f                  # ⟨ψ', ψ⟩
    val = sp.integrate(sp.expand(integrand), (t, 0, 1))
    neg_im = -(val - sp.conjugate(val)) / (2 * sp.I)
    target = (sp.conjugate(zj) * sp.conjugate(r) * zk - zj * r * sp.conjugate(zk)) / (2 * sp.I)
    # |r| = 1 is not needed: the |z|² terms are real and drop out of the imaginary part
    assert sp.simplify(sp.expand(neg_im - target)) == 0, "edge term"
    # as a Hermitian form: B[j,k] = −(i/2) r̄, B[k,j] = (i/2) r
    z = sp.Matrix([zj, zk])
    B = sp.Matrix([[0, -sp.I / 2 * sp.conjugate(r)], [sp.I / 2 * r, 0]])
    form = (z.H * B * z)[0]
    assert sp.simplify(sp.expand(form - target)) == 0, "edge Hermitian form"
    # the seed's printed entry ε r̄/2 gives Re(z̄_j r̄ z_k), not the imaginary part
    Bs = sp.Matrix([[0, sp.conjugate(r) / 2], [r / 2, 0]])
    seed = (z.H * Bs * z)[0]
    re_part = (sp.conjugate(zj) * sp.conjugate(r) * zk + zj * r * sp.conjugate(zk)) / 2
    assert sp.simplify(sp.expand(seed - re_part)) == 0
    print("2. −∫_e Im⟨∇ψ, ψ⟩ = Im(z̄_j r̄_jk z_k), B[j,k] = −(i/2) r̄_jk (Eq. 6.8 misses the i): verified")


def _planar_mesh(k: int):
    g = np.linspace(0.0, 1.0, k + 1)
    X, Y = np.meshgrid(g, g, indexing="ij")
    rng = np.random.default_rng(3)
    P = np.c_[X.ravel(), Y.ravel()]
    inner = (P[:, 0] > 0) & (P[:, 0] < 1) & (P[:, 1] > 0) & (P[:, 1] < 1)
    P[inner] += rng.uniform(-0.25, 0.25, (inner.sum(), 2)) / k
    idx = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    return np.c_[P, np.zeros(len(P))], F


def _icosphere(levels: int):
    t = (1 + 5 ** 0.5) / 2
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(levels):
        cache, out = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                cache[key] = len(V) - 1
            return cache[key]

        for a, b, c in F:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = out
    return np.array(V), np.array(F)


def numeric_checks() -> None:
    import scipy.linalg as sla

    from dhlb.fields import energy_matrices
    from dhlb.mesh import tangent_bundle

    V, F = _planar_mesh(6)
    tb = tangent_bundle(V, F, n=1)
    x = tb.frames[:, 0, 0] + 1j * tb.frames[:, 0, 1]         # the frame X_i as a complex number
    z = V[:, 0] + 1j * V[:, 1]
    u_hol, u_anti = z * x.conj(), z.conj() * x.conj()        # coefficients of z ∂_z and z̄ ∂_z
    A1, _ = energy_matrices(tb, s=1.0)
    Am, _ = energy_matrices(tb, s=-1.0)
    A0, _ = energy_matrices(tb, s=0.0)
    assert abs(u_hol.conj() @ (A1 @ u_hol)) < 1e-12
    assert abs(u_anti.conj() @ (Am @ u_anti)) < 1e-12
    assert abs((u_hol.conj() @ (A0 @ u_hol)).real - 2.0) < 1e-12       # ∫|∇z|² = 2 · area
    print("3a. flat unit square: z∂_z in ker A_{+1}, z̄∂_z in ker A_{-1}, E_D(z) = area: verified")

    V, F = _icosphere(2)
    for n, dim in ((1, 3), (2, 5)):
        for s in (-1.0, 1.0):
            A, M = energy_matrices(V, F, n=n, s=s)
            w = sla.eigh(A.toarray(), M.toarray(), eigvals_only=True)
            assert w[0] > -1e-10 * w[-1], f"A_{s} not PSD (n={n}): {w[0]}"
            if s == 1.0:
                assert w[dim] > 100 * w[dim - 1], f"n={n}: kernel dimension {dim} not separated: {w[:dim + 2]}"
        print(f"3b. icosphere (642 vertices) n = {n}: A_±1 PSD, holomorphic kernel of dimension {dim}: verified")


def main() -> int:
    t0 = time.perf_counter()
    pointwise_identity()
    edge_term()
    numeric_checks()
    print(f"all holomorphic-energy identities verified in {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
