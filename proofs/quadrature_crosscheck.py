"""Numerical cross-check of every closed form used by dhlb.fem.integrals, by Gauss quadrature.

A collapsed (Duffy) tensor Gauss–Legendre rule on the n-simplex (proofs/_common.simplex_rule) is
exact for polynomials of high degree and converges exponentially for exp(i θ·x) with moderate θ.

  1. expi_moment (Hermite–Genocchi route) for n = 1..4, random monomials of degree <= 4.
  2. theta, lambda_, xi (Definitions 18–19) for n = 2, 3, all index combinations.
  3. local_mass_matrices / local_dirichlet_matrices (Theorems 15, 17) for n = 1, 2, 3 against the
     integrals ∫|ψ̃|², ∫|∇ψ̃|² of the piecewise-linear section written in the single frame φ_0:
     ψ̃ = F φ_0, F = Σ_a z_a x_a r_a0 exp(-i Σ_m Ω_a0m x_m), ∇ψ̃ = (dF + i F ω_0) φ_0 — a route
     that uses neither Θ, Λ, Ξ nor the frames φ_a of the other vertices.
"""

from itertools import product

import numpy as np
from _common import check, closed_curvature, random_simplex, simplex_rule


def main() -> None:
    from dhlb.fem.integrals import (
        curvature_tensor,
        expi_moment,
        lambda_,
        local_edges,
        local_matrices,
        theta,
        xi,
    )
    print("Quadrature cross-check")
    rng = np.random.default_rng(11)
    worst = 0.0
    for n in (1, 2, 3, 4):
        x, wts = simplex_rule(n, {1: 40, 2: 40, 3: 24, 4: 14}[n])
        for _ in range(6):
            th = rng.uniform(-6, 6, n + 1)
            p = rng.integers(0, 3, n + 1)
            if p.sum() > 4:
                p[: p.sum() - 4] = 0
            ref = np.sum(wts * np.prod(x ** p, axis=1) * np.exp(1j * x @ th))
            worst = max(worst, abs(expi_moment(th, p) - ref) / abs(ref))
    check(worst < 1e-11, f"expi_moment, n = 1..4 (max rel. error {worst:.1e})")

    worst = 0.0
    for n in (2, 3):
        x, wts = simplex_rule(n, 40 if n == 2 else 24)
        om, _ = closed_curvature(rng, n, 1.5)
        T = curvature_tensor(om)
        for i, j in product(range(n + 1), repeat=2):
            ex = np.exp(-1j * x @ T[i, j])
            ref = np.sum(wts * ex)
            worst = max(worst, abs(lambda_(om, i, j) - ref) / abs(ref))
            for k, l in product(range(n + 1), repeat=2):
                for f, mono in ((theta, x[:, k] * x[:, l]), (xi, x[:, i] * x[:, j] * x[:, k] * x[:, l])):
                    ref = np.sum(wts * mono * ex)
                    worst = max(worst, abs(f(om, i, j, k, l) - ref) / abs(ref))
    check(worst < 1e-11, f"theta, lambda_, xi for n = 2, 3, all indices (max rel. error {worst:.1e})")

    worst = 0.0
    for n in (1, 2, 3):
        x, wts = simplex_rule(n, {1: 40, 2: 40, 3: 26}[n])
        for scale in (0.3, 2.0):
            _, gram, vol = random_simplex(rng, n)
            om, r = closed_curvature(rng, n, scale)
            T = curvature_tensor(om, dim=n)
            e = {tuple(v): q for q, v in enumerate(local_edges(n))}
            rr = lambda a, b: 1.0 if a == b else (r[e[a, b]] if a < b else np.conj(r[e[b, a]]))
            vals, grads = [], []
            for a in range(n + 1):
                ph = np.exp(-1j * x @ T[a, 0])
                f = x[:, a] * rr(a, 0) * ph
                df = np.outer(f, -1j * T[a, 0])
                df[:, a] += rr(a, 0) * ph
                grads.append(df + 1j * f[:, None] * (x @ T[0].T))     # dF + i F ω_0, ω_0[k] = Σ_l Ω_0kl x_l
                vals.append(f)
            mass_q = np.array([[vol * np.sum(wts * np.conj(vals[b]) * vals[a]) for a in range(n + 1)]
                               for b in range(n + 1)])
            dir_q = np.array([[vol * np.sum(wts * np.einsum("pk,kl,pl->p", np.conj(grads[b]), gram, grads[a]))
                               for a in range(n + 1)] for b in range(n + 1)])
            mass, dirichlet = local_matrices(gram, vol, om, r)
            worst = max(worst, np.abs(mass - mass_q).max() / np.abs(mass_q).max(),
                        np.abs(dirichlet - dir_q).max() / np.abs(dir_q).max())
    check(worst < 1e-11,
          f"local mass and Dirichlet matrices, n = 1, 2, 3, single-frame route (max rel. error {worst:.1e})")


if __name__ == "__main__":
    main()
