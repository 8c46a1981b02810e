"""References and random builders for the tests of dhlb.fem.integrals (``test_integrals*.py``).

60-digit mpmath divided differences (exp of the Opitz matrix) and Hermite–Genocchi moments; random
well-conditioned simplices; closed curvature with a consistent connection; Gauss quadrature of the
piecewise-linear section written in a single radially parallel frame.
"""

from math import factorial

import mpmath as mp
import numpy as np

from dhlb.fem.integrals import curvature_tensor, local_edges, local_triangles


def mp_divided_difference(nodes, dps=60):
    """exp[nodes] as the (0, N) entry of exp of the Opitz matrix, in mpmath."""
    with mp.workdps(dps):
        k = len(nodes)
        t = mp.matrix(k, k)
        for i, z in enumerate(nodes):
            t[i, i] = mp.mpc(z.real, z.imag)
            if i + 1 < k:
                t[i, i + 1] = 1
        return complex(mp.expm(t)[0, k - 1])


def mp_pair_moment(omega_tensor, a, b, p):
    """(1/vol) ∫ x^p exp(-i Σ_m Ω_abm x_m) by Hermite-Genocchi in mpmath (one simplex)."""
    n = len(p) - 1
    nodes = []
    for m in range(n + 1):
        nodes += [-1j * omega_tensor[a, b, m]] * (p[m] + 1)
    return factorial(n) * np.prod([factorial(k) for k in p]) * mp_divided_difference(nodes)


def simplex(rng, n, cond=1e3):
    """Random n-simplex in R^n: (points, gram of barycentric gradients, volume)."""
    while True:
        p = rng.normal(size=(n + 1, n))
        e = p[1:] - p[0]
        g = e @ e.T
        if np.linalg.cond(g) < cond:
            d = np.hstack([-np.ones((n, 1)), np.eye(n)])
            return p, d.T @ np.linalg.solve(g, d), np.sqrt(np.linalg.det(g)) / factorial(n)


def closed_data(rng, n, scale):
    """Exact (closed) curvature Ω = dα on the local triangles and the consistent connection exp(iα)."""
    edges = [tuple(e) for e in local_edges(n)]
    alpha = dict(zip(edges, rng.normal(size=len(edges)) * scale))
    om = np.array([alpha[b, c] - alpha[a, c] + alpha[a, b] for a, b, c in local_triangles(n)])
    return om, np.exp(1j * np.array([alpha[e] for e in edges]))


def simplex_rule(n, order):
    g, w = np.polynomial.legendre.leggauss(order)
    g, w = 0.5 * (g + 1), 0.5 * w
    u = np.stack([a.ravel() for a in np.meshgrid(*([g] * n), indexing="ij")], axis=1)
    wt = np.prod(np.stack([a.ravel() for a in np.meshgrid(*([w] * n), indexing="ij")], axis=1), axis=1)
    x = np.zeros((u.shape[0], n + 1))
    rem = np.ones(u.shape[0])
    for k in range(n):
        x[:, k + 1] = rem * u[:, k]
        wt = wt * (1 - u[:, k]) ** (n - 1 - k)
        rem = rem * (1 - u[:, k])
    x[:, 0] = rem
    return x, wt * factorial(n)


def quadrature_matrices(gram, vol, om, r, order):
    """∫|ψ̃|², ∫|∇ψ̃|² with ψ̃ = F φ_0 (single frame), by Gauss quadrature."""
    n = gram.shape[0] - 1
    x, wt = simplex_rule(n, order)
    t = curvature_tensor(om, dim=n)
    e = {tuple(v): q for q, v in enumerate(local_edges(n))}
    rr = lambda a, b: 1.0 if a == b else (r[e[a, b]] if a < b else np.conj(r[e[b, a]]))  # noqa: E731
    vals, grads = [], []
    for a in range(n + 1):
        ph = np.exp(-1j * x @ t[a, 0])
        f = x[:, a] * rr(a, 0) * ph
        df = np.outer(f, -1j * t[a, 0])
        df[:, a] += rr(a, 0) * ph
        grads.append(df + 1j * f[:, None] * (x @ t[0].T))
        vals.append(f)
    mass = np.array([[vol * np.sum(wt * np.conj(vals[b]) * vals[a]) for a in range(n + 1)] for b in range(n + 1)])
    dirichlet = np.array([[vol * np.sum(wt * np.einsum("pk,kl,pl->p", np.conj(grads[b]), gram, grads[a]))
                           for a in range(n + 1)] for b in range(n + 1)])
    return mass, dirichlet
