"""Simplex moments ``∫ x^p exp(-i Σ_m Ω_abm x_m)`` for pairs of vertices, batched by divided difference."""

from __future__ import annotations

from math import factorial, prod

import numpy as np

from dhlb.fem._expdd import expi_divided_difference as _dd

__all__ = ["pair_moments"]


def pair_moments(tensor: np.ndarray, requests) -> np.ndarray:
    """``(1/vol) ∫_σ x^p exp(-i Σ_m Ω_abm x_m)`` for each request ``(a, b, p)``; shape ``(m, R)``.

    ``tensor`` is the antisymmetric curvature tensor ``(m, n+1, n+1, n+1)``.  The nodes of
    ``x_a`` and ``x_b`` are both 0 and are merged into one class, so requests that differ only in
    how the power is split between ``a`` and ``b`` share one divided difference.
    """
    m, n = tensor.shape[0], tensor.shape[1] - 1
    out = np.empty((m, len(requests)), dtype=complex)
    jobs: dict[tuple, dict[tuple, list]] = {}
    for r, (a, b, p) in enumerate(requests):
        fac = factorial(n) * prod(factorial(int(k)) for k in p)
        if a == b:  # exponent vanishes: Dirichlet moment n! p! / (n + |p|)!
            out[:, r] = fac / factorial(n + int(sum(p)))
            continue
        others = [v for v in range(n + 1) if v not in (a, b)]
        mu = (int(p[a] + p[b] + 2),) + tuple(int(p[o] + 1) for o in others)
        jobs.setdefault(mu, {}).setdefault((a, b), []).append((r, fac))
    for mu, pairs in jobs.items():
        keys = list(pairs)
        ph = np.zeros((len(keys), m, len(mu)))
        for i, (a, b) in enumerate(keys):
            others = [v for v in range(n + 1) if v not in (a, b)]
            ph[i, :, 1:] = -tensor[:, a, b, others]
        dd = _dd(ph, np.asarray(mu))
        for i, key in enumerate(keys):
            for r, fac in pairs[key]:
                out[:, r] = fac * dd[i]
    return out
