r"""The conformal section on tet meshes: the phase change per edge, and an energy that no tet makes indefinite.

Quaternions are 4-tuples with the Hamilton product written out here; nothing is imported from dhlb
for the derivations (the last part compares the code).

1. Phase change per edge.  For an imaginary ``v`` with ``|v| = θ`` and any quaternion ``p``:
   ``⟨p, exp(v) p⟩_{R⁴} = |p|² cos θ`` (symbolic).  So a parallel section (``ψ_j = η ψ_i``,
   ``η = exp(−½ g × e)``) turns by ``θ_e = ½ |g × e|`` along the edge; the P1 chord has
   ``|ψ_j − ψ_i| = 2 sin(θ/2)`` and its midpoint the norm ``cos(θ/2)``, so a section turning by
   ``θ = π`` per edge is not resolved at all, and at ``θ = ½`` (``dhlb.conformal.MAX_EDGE_ANGLE``)
   the midpoint loses ``1 − cos(¼) < 3.2 %``; the chord energy ``4 sin²(θ/2)`` misses the arc
   energy ``θ²`` by ``θ²/12 + O(θ⁴)`` relatively (2.1 % at θ = ½).
2. Point charges: ``|grad (q/|x − a|)| = |q|/r²``, hence ``θ_e <= |q| |e| / (2 r²)`` and ``θ_e`` is
   linear in ``q`` (symbolic): scaling the charge by ``s`` scales every ``θ_e`` by ``s``, which is how
   ``default_charge`` and the error messages pick a charge.
3. The energy of one tet in the gauge of its vertex ``k``, ``Σ_ab w_ab |τ_bk ψ_b − τ_ak ψ_a|²``
   (``τ_ak`` the transport ``a → k``), equals ``Σ_ab w_ab |ψ_b − τ_kb τ_ak ψ_a|²`` and is the scalar
   P1 stiffness ``S ⊗ I`` conjugated by the unitary ``diag(τ_ak)``: positive semidefinite for
   every tet, also with negative cotan weights (numerically, on random and sliver tets with random
   SU(2) transports; the plain energy ``Σ w_ab |ψ_b − η_ab ψ_a|²`` of the same tets is indefinite on
   some).  The average over ``k`` is PSD, with the plain diagonal and off-diagonal blocks
   ``−w_ab ¼ (2 η_ab + Σ_{k ∉ {a,b}} η_kb η_ak)``.
4. Flat transports (``η_ab = ρ_b ρ_a⁻¹``): path and edge transports agree and the gauged energy is
   the plain one.
5. The code: ``dhlb.conformal.tet_connection_laplacian`` equals the independent assembly of 3 on a
   tet whose plain energy is indefinite, and the plain energy on a flat bundle.
"""

from __future__ import annotations

import sys
from itertools import combinations
from pathlib import Path

import numpy as np
import sympy as sp

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from proofs._common import check  # noqa: E402
from proofs._derive_util import qmul  # noqa: E402


def part1():
    print("1. phase change per edge")
    th = sp.symbols("theta", positive=True)
    a, b, c = sp.symbols("a b c", real=True)
    p = sp.symbols("p0:4", real=True)
    n = sp.sqrt(a**2 + b**2 + c**2)
    ex = (sp.cos(th), sp.sin(th) * a / n, sp.sin(th) * b / n, sp.sin(th) * c / n)       # exp(θ v̂)
    q = qmul(ex, p)
    inner = sp.simplify(sum(pi * qi for pi, qi in zip(p, q)))
    check(sp.simplify(inner - sp.cos(th) * sum(pi**2 for pi in p)) == 0, "<p, exp(v) p> = |p|^2 cos|v|")
    chord2 = sp.simplify(2 - 2 * sp.cos(th))
    check(sp.simplify(chord2 - 4 * sp.sin(th / 2) ** 2) == 0, "|psi_j - psi_i| = 2 sin(theta/2) for unit psi")
    mid2 = sp.simplify((2 + 2 * sp.cos(th)) / 4)
    check(sp.simplify(mid2 - sp.cos(th / 2) ** 2) == 0, "the chord's midpoint has norm cos(theta/2)")
    check(float(1 - sp.cos(sp.Rational(1, 4))) < 0.032, "at theta = 1/2 the midpoint loses < 3.2 %")
    ratio = sp.series(4 * sp.sin(th / 2) ** 2 / th**2, th, 0, 4).removeO()
    check(sp.simplify(ratio - (1 - th**2 / 12)) == 0, "chord energy / arc energy = 1 - theta^2/12 + O(theta^4)")


def part2():
    print("2. point charges: theta_e <= |q| |e| / (2 r^2), linear in q")
    x = sp.symbols("x0:3", real=True)
    q = sp.symbols("q", real=True)
    r = sp.sqrt(sum(xi**2 for xi in x))
    g = [sp.diff(q / r, xi) for xi in x]
    check(sp.simplify(sum(gi**2 for gi in g) - q**2 / r**4) == 0, "|grad q/|x|| = |q| / |x|^2")
    s = sp.symbols("s", positive=True)
    check(all(sp.simplify(sp.diff(s * q / r, xi) - s * gi) == 0 for xi, gi in zip(x, g)),
          "grad u scales with q, hence so does theta_e = |g x e| / 2 <= |g| |e| / 2")


# ---------------------------------------------------------------------------- numeric: SU(2) as 2×2 matrices
def su2(rng, m, scale):
    v = rng.normal(size=(m, 3)) * scale
    t = np.linalg.norm(v, axis=1)
    w, u = np.cos(t), np.sin(t)[:, None] * v / t[:, None]
    a, b = w + 1j * u[:, 0], u[:, 1] - 1j * u[:, 2]
    return np.stack([np.stack([a, -b.conj()], -1), np.stack([b, a.conj()], -1)], -2)


def stiffness(P):
    """Scalar P1 stiffness of one tet (4×4) from the barycentric gradients."""
    B = P[1:] - P[0]
    G = np.linalg.inv(B)                      # columns: grad λ_1..3
    G = np.c_[-G.sum(axis=1), G]
    return abs(np.linalg.det(B)) / 6 * G.T @ G


def plain(S, eta):
    """Σ w_ab |ψ_b − η_ab ψ_a|² (w_ab = −S_ab), 8×8, section index 2a + i."""
    A = np.zeros((4, 2, 4, 2), complex)
    for a in range(4):
        A[a, :, a, :] = S[a, a] * np.eye(2)
    for a, b in combinations(range(4), 2):
        A[b, :, a, :] = S[a, b] * eta[a, b]
        A[a, :, b, :] = S[a, b] * eta[a, b].conj().T
    return A.reshape(8, 8)


def transports(edge_eta):
    tau = np.zeros((4, 4, 2, 2), complex)
    for a in range(4):
        tau[a, a] = np.eye(2)
    for (a, b), t in zip(combinations(range(4), 2), edge_eta):
        tau[a, b], tau[b, a] = t, t.conj().T
    return tau


def gauged(S, tau):
    """The average over the base vertex k of U_kᴴ (S ⊗ I) U_k, U_k = diag(τ_ak)."""
    A = np.zeros((8, 8), complex)
    for k in range(4):
        U = np.zeros((4, 2, 4, 2), complex)
        for a in range(4):
            U[a, :, a, :] = tau[a, k]
        U = U.reshape(8, 8)
        A += U.conj().T @ np.kron(S, np.eye(2)) @ U / 4
    return A


def part3(rng):
    print("3. the per-tet gauged energy is PSD; the plain one is not always")
    worst_g, worst_p, blocks_ok = np.inf, np.inf, True
    for trial in range(400):
        P = rng.normal(size=(4, 3))
        if trial % 2:                          # slivers: four nearly coplanar points
            P[:, 2] *= 1e-2
        S = stiffness(P)
        tau = transports(su2(rng, 6, 0.6))
        Ap, Ag = plain(S, tau), gauged(S, tau)
        tr = np.trace(Ap).real
        worst_g = min(worst_g, np.linalg.eigvalsh(Ag)[0] / tr)
        worst_p = min(worst_p, np.linalg.eigvalsh(Ap)[0] / tr)
        # the explicit form: diagonal of the plain energy, off-diagonal −w_ab ¼ (2 η_ab + Σ_k η_kb η_ak)
        E = Ag.reshape(4, 2, 4, 2)
        for a, b in combinations(range(4), 2):
            avg = 2 * tau[a, b] + sum(tau[k, b] @ tau[a, k] for k in range(4) if k not in (a, b))
            blocks_ok &= np.allclose(E[b, :, a, :], S[a, b] * avg / 4, atol=1e-12 * abs(S).max())
        blocks_ok &= np.allclose(np.diagonal(Ag), np.diagonal(Ap), atol=1e-12 * abs(S).max())
    check(worst_g > -1e-12, f"gauged: smallest eigenvalue / trace >= {worst_g:.1e} over 400 tets (200 slivers)")
    check(worst_p < -1e-3, f"plain: smallest eigenvalue / trace down to {worst_p:.2g} on the same tets")
    check(bool(blocks_ok), "gauged blocks = -w_ab (2 eta_ab + sum_k eta_kb eta_ak) / 4, diagonal unchanged (all 400)")


def part4(rng):
    print("4. flat transports: gauged = plain")
    rho = su2(rng, 4, 2.0)
    eta = [rho[b] @ rho[a].conj().T for a, b in combinations(range(4), 2)]
    S = stiffness(rng.normal(size=(4, 3)))
    tau = transports(eta)
    err = np.abs(gauged(S, tau) - plain(S, tau)).max()
    check(err < 1e-13 * abs(S).max(), f"eta_ab = rho_b rho_a^-1: max difference {err:.1e}")


def compare_with_code(rng):
    print("5. dhlb.conformal.tet_connection_laplacian")
    from dhlb import SimplicialComplex
    from dhlb.bundles import VectorBundle
    from dhlb.conformal import tet_connection_laplacian
    from dhlb.fem import connection_laplacian
    from dhlb.geometry import EuclideanComplex

    X = SimplicialComplex([(0, 1, 2, 3)])
    indefinite = False
    while not indefinite:
        P = rng.normal(size=(4, 3))
        P[:, 2] *= 1e-2
        eta = su2(rng, 6, 0.6)
        S = stiffness(P)
        Ap = plain(S, transports(eta))
        indefinite = bool(np.linalg.eigvalsh(Ap)[0] < -1e-3 * np.trace(Ap).real)
    geo = EuclideanComplex(X, points=P)
    E = VectorBundle(X, eta, "C", metric=True)
    A = tet_connection_laplacian(E, geo).toarray()
    err = np.abs(A - gauged(S, transports(eta))).max()
    check(err < 1e-12 * abs(S).max(), f"an indefinite plain tet energy: the code gauges it, error {err:.1e}")
    rho = su2(rng, 4, 2.0)
    flat = VectorBundle(X, np.array([rho[b] @ rho[a].conj().T for a, b in combinations(range(4), 2)]), "C",
                        metric=True)
    err = np.abs(tet_connection_laplacian(flat, geo) - connection_laplacian(flat, geo)).max()
    check(err < 1e-12 * abs(S).max(), f"a flat bundle: the plain connection Laplacian, error {err:.1e}")


if __name__ == "__main__":
    rng = np.random.default_rng(7)
    part1()
    part2()
    part3(rng)
    part4(rng)
    compare_with_code(rng)
    print("derive_conformal_tet_energy: all identities hold")
