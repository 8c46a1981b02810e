"""Simplex moments ``∫ x^p exp(-i Σ_m Ω_abm x_m)`` for pairs of vertices, batched by divided difference."""

from __future__ import annotations

from math import factorial, prod

import numpy as np

from dhlb.fem._expdd import divided_difference_columns

__all__ = ["pair_moments"]


def pair_moments(tensor: np.ndarray, requests) -> np.ndarray:
    """``(1/vol) ∫_σ x^p exp(-i Σ_m Ω_abm x_m)`` for each request ``(a, b, p)``; shape ``(R, m)``.

    ``tensor`` is the antisymmetric curvature tensor with the simplex axis last,
    ``(n+1, n+1, n+1, m)``.  The nodes of ``x_a`` and ``x_b`` are both 0 and are merged into one
    class, so requests that differ only in how the power is split between ``a`` and ``b`` share one
    divided difference; all requests with the same multiplicity pattern are evaluated in one batch.
    """
    n, m = tensor.shape[0] - 1, tensor.shape[-1]
    out = np.empty((len(requests), m), dtype=complex)
    jobs: dict[tuple, dict[tuple, list]] = {}
    for r, (a, b, p) in enumerate(requests):
        fac = factorial(n) * prod(factorial(int(k)) for k in p)
        if a == b:  # exponent vanishes: Dirichlet moment n! p! / (n + |p|)!
            out[r] = fac / factorial(n + int(sum(p)))
            continue
        others = [v for v in range(n + 1) if v not in (a, b)]
        mu = (int(p[a] + p[b] + 2),) + tuple(int(p[o] + 1) for o in others)
        jobs.setdefault(mu, {}).setdefault((a, b), []).append((r, fac))
    for mu, pairs in jobs.items():
        keys = list(pairs)
        ph = np.zeros((len(mu), len(keys) * m))
        for i, (a, b) in enumerate(keys):
            others = [v for v in range(n + 1) if v not in (a, b)]
            ph[1:, i * m:(i + 1) * m] = -tensor[a, b, others]
        dd = divided_difference_columns(ph, np.asarray(mu))
        for i, key in enumerate(keys):
            for r, fac in pairs[key]:
                out[r] = fac * dd[i * m:(i + 1) * m]
    return out
