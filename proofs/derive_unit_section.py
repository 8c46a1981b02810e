"""Part 2, §2.1 (Eq. 2.3) undone: what the unit-modulus iteration of ``section="unit"`` minimizes.

The seed defines the energy of a *unit* function φ (|φ| = 1 pointwise) and relaxes the constraint
(Eq. 2.3): the minimum of ρ(ψ) = ψᴴAψ / ψᴴMψ over all ψ is the smallest eigenvector. dhlb's
``section="unit"`` (dhlb/stripes/section.py) goes back to the constraint and iterates

    x_{t+1} = normalize_per_vertex(C x_t),   C = M K⁻¹ M,   K = A − σM positive definite (σ < λ₁).

Derived here:

1. (generalized power method) g(x) = xᴴ C x is convex, so g(y) = g(x) + 2 Re((Cx)ᴴ(y − x)) + (y − x)ᴴC(y − x)
   (identity, symbolic) >= g(x) + 2 Re((Cx)ᴴ(y − x)); per vertex, Re(conj(c_i) y_i) <= |c_i| on |y_i| = 1 with
   equality at y_i = c_i/|c_i| (symbolic), so the step maximizes the linearization and g(x_{t+1}) >= g(x_t).
   For the real 2N form the same holds with 2-vectors per vertex (Cauchy–Schwarz in R²).
2. A lumped (diagonal, positive) M, equal on both real components of a vertex, does not change a phase:
   normalize(M K⁻¹ M x) = normalize(K⁻¹ M x), the iteration measured in issue 18.
3. (what g has to do with the unit energy) In the M-orthonormal eigenbasis, x = Σ c_k u_k, p_k = |c_k|²,
   μ_k = λ_k − σ > 0:  xᴴMx = Σ p_k,  xᴴKx = Σ p_k μ_k,  g(x) = Σ p_k / μ_k, and
   (Σ p_k/μ_k)(Σ p_k μ_k) − (Σ p_k)² = Σ_{k<l} p_k p_l (μ_k − μ_l)² / (μ_k μ_l) >= 0   (symbolic, 3 terms),
   hence ρ(x) >= σ + xᴴMx / g(x), with equality iff x lies in one eigenspace. On the torus xᴴMx is fixed
   (lumped M), so raising g lowers a lower bound of ρ — but not ρ itself:
4. a numerical counterexample where ρ increases in one step while g increases, on a small random
   connection Laplacian; hence dhlb's guard (return the iterate of lowest ρ), checked against an independent
   transcription of the iteration on random instances: g monotone at every step, dhlb's result = the minimum
   of the independent energies, never above the normalized eigenvector's.
"""

import numpy as np
import scipy.sparse as sps
import sympy as sp
from _common import check

from dhlb.stripes import SectionOptions
from dhlb.stripes.section import unit_section

print("1. generalized power method: g(y) >= g(x) + 2 Re((Cx)^H (y - x)), and the step maximizes the linear part")
a, b, c = sp.symbols("a b c", real=True)
d1, d2 = sp.symbols("d1 d2", real=True)
C = sp.Matrix([[d1, a + sp.I * b], [a - sp.I * b, d2]])        # generic Hermitian 2 x 2
xs = sp.symbols("x1r x1i x2r x2i y1r y1i y2r y2i", real=True)
x = sp.Matrix([xs[0] + sp.I * xs[1], xs[2] + sp.I * xs[3]])
y = sp.Matrix([xs[4] + sp.I * xs[5], xs[6] + sp.I * xs[7]])


def herm(u, Hm, v):
    return (u.H * Hm * v)[0, 0]


lhs = herm(y, C, y) - herm(x, C, x) - 2 * sp.re(sp.expand(herm(C * x, sp.eye(2), y - x))) - herm(y - x, C, y - x)
check(sp.simplify(sp.expand(lhs)) == 0, "g(y) - g(x) - 2 Re((Cx)^H (y-x)) = (y-x)^H C (y-x)  (>= 0 for C PSD)")
amp, phi, th = sp.symbols("a phi theta", real=True)
lin = sp.re(sp.conjugate(amp * sp.exp(sp.I * phi)) * sp.exp(sp.I * th))
check(sp.simplify(sp.expand_complex(lin) - amp * sp.cos(th - phi)) == 0,
      "Re(conj(c_i) e^{i theta}) = |c_i| cos(theta - arg c_i): maximal at theta = arg c_i (y_i = c_i/|c_i|)")
u1, u2, v1, v2 = sp.symbols("u1 u2 v1 v2", real=True)
check(sp.expand((u1 ** 2 + u2 ** 2) * (v1 ** 2 + v2 ** 2) - (u1 * v1 + u2 * v2) ** 2 - (u1 * v2 - u2 * v1) ** 2) == 0,
      "real 2N form: <c_i, y_i> <= |c_i| |y_i| per vertex (Lagrange identity), equality at y_i = c_i/|c_i|")

print("2. a lumped mass does not change the phases")
m, s = sp.symbols("m s", positive=True)
zr, zi = sp.symbols("zr zi", real=True)
z = zr + sp.I * zi
check(sp.simplify(m * s * z / sp.Abs(m * s * z) - z / sp.Abs(z)) == 0,
      "normalize(m_i (K^-1 M x)_i) = normalize((K^-1 M x)_i) for m_i > 0")

print("3. the bound rho(x) >= sigma + x^H M x / g(x)")
p = sp.symbols("p1:4", nonnegative=True)
mu = sp.symbols("mu1:4", positive=True)
gap = sp.Add(*[pk / mk for pk, mk in zip(p, mu)]) * sp.Add(*[pk * mk for pk, mk in zip(p, mu)]) - sp.Add(*p) ** 2
sos = sp.Add(*[p[k] * p[l] * (mu[k] - mu[l]) ** 2 / (mu[k] * mu[l]) for k in range(3) for l in range(k + 1, 3)])
check(sp.simplify(gap - sos) == 0, "(sum p/mu)(sum p mu) - (sum p)^2 = sum_{k<l} p_k p_l (mu_k - mu_l)^2/(mu_k mu_l)")


print("4. numbers: g is monotone, rho is not (hence the guard), dhlb keeps the best iterate")


def connection_laplacian(n, rng, extra=2.0):
    """A random graph (ring + chords) with random unit connection: sum_e w |z_j - r z_i|^2, lumped mass."""
    i = np.arange(n)
    E = np.r_[np.c_[i, (i + 1) % n], rng.integers(0, n, (int(extra * n), 2))]
    E = E[E[:, 0] != E[:, 1]]
    w = rng.uniform(0.5, 2.0, len(E))
    r = np.exp(1j * rng.uniform(-np.pi, np.pi, len(E)))
    rows = np.r_[np.arange(len(E)), np.arange(len(E))]
    D = sps.csr_matrix((np.r_[-r, np.ones(len(E))], (rows, np.r_[E[:, 0], E[:, 1]])), shape=(len(E), n))
    A = (D.conj().T @ sps.diags(w) @ D).tocsr()
    M = sps.diags(rng.uniform(0.5, 1.5, n)).astype(complex).tocsr()
    return A, M


def normalize(v):
    return v / np.abs(v)


increase_seen = 0
for seed in range(40):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(8, 40))
    A, M = connection_laplacian(n, rng)
    Ad, Md = A.toarray(), M.toarray()
    lam, U = np.linalg.eigh(np.linalg.solve(np.sqrt(Md), np.linalg.solve(np.sqrt(Md), Ad).T).T)
    sigma = -1e-8 * np.abs(Ad).sum(1).max()
    Kinv = np.linalg.inv(Ad - sigma * Md)
    Cm = Md @ Kinv @ Md
    x0 = np.linalg.solve(np.sqrt(Md), U[:, 0])               # the smallest eigenvector
    xt = normalize(x0)
    gs, rhos = [np.real(xt.conj() @ Cm @ xt)], [np.real(xt.conj() @ Ad @ xt) / np.real(xt.conj() @ Md @ xt)]
    for _ in range(60):
        xt = normalize(Cm @ xt)
        gs.append(np.real(xt.conj() @ Cm @ xt))
        rhos.append(np.real(xt.conj() @ Ad @ xt) / np.real(xt.conj() @ Md @ xt))
    gs, rhos = np.array(gs), np.array(rhos)
    assert np.all(np.diff(gs) >= -1e-9 * gs[1:]), (seed, np.diff(gs).min())
    assert np.all(rhos >= sigma + np.real(np.sum(Md)) / gs - 1e-9 * np.abs(rhos)), seed
    increase_seen += int(np.any(np.diff(rhos) > 1e-9 * np.abs(rhos[1:])))
    lu = sps.linalg.splu((A - sigma * M).tocsc())
    it = unit_section(A, M, lu.solve, x0, kick=0.0,   # 60 steps: neither stopping rule (fixed point, flat energy)
                      options=SectionOptions(iterations=60, unit_tol=1e-300, energy_tol=0.0))
    assert np.allclose(it.energies, rhos, rtol=1e-7, atol=1e-10), seed
    assert it.unit_energy == min(it.energies) <= it.energies[0] and np.isclose(it.unit_energy, rhos.min()), seed
check(True, "g(x_t) non-decreasing on 40 random connection Laplacians (n = 8..39), 60 steps each")
check(True, "rho(x_t) >= sigma + x^H M x / g(x_t) at every step")
check(increase_seen > 0, f"rho increases in some step on {increase_seen} of the 40 instances: not monotone")
check(True, "dhlb's unit_section: the same energies as the independent transcription, returns the lowest")
print("done")
