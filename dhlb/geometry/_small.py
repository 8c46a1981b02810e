"""Closed forms for stacks of 1- and 2-simplices (edges, triangles): the hot path of surface meshes.

:class:`~dhlb.geometry.simplex.SimplexStack` uses them instead of batched LAPACK calls, which
cost ~1 µs per tiny matrix, for ``n <= 2``:

* eigenvalues of a symmetric 2×2 metric ``g = [[a, b], [b, c]]``:
  ``λ_max = (a + c)/2 + hypot((a − c)/2, b)`` and ``λ_min = det g / λ_max`` (no cancellation in
  ``λ_min``: ``det g`` comes from the triangular factor, ``det g = (r_11 r_22)²``, when it is
  known, so degenerate triangles are measured to relative accuracy);
* the triangular factor ``R`` (``g = RᵀR``, positive diagonal) of the edge matrix
  ``E = [e_1 | e_2]``: ``r_11 = |e_1|``, ``r_12 = <e_1, e_2>/r_11``, ``r_22 = |e_1 ∧ e_2| / r_11``
  with ``|e_1 ∧ e_2|² = Σ_{i<j} (e_1i e_2j − e_1j e_2i)²`` (Lagrange's identity, any ambient
  dimension) -- the R of a QR factorization with the signs fixed to a positive diagonal;
* ``Y = R⁻ᵀ [−1 | I]`` from the explicit inverse of a 2×2 (or 1×1) lower-triangular matrix.

Each formula is checked against the LAPACK route in ``tests/test_geometry_small.py``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["eigvalsh_small", "factor_from_edges", "gradients_from_factor"]


def eigvalsh_small(g: np.ndarray, det: np.ndarray | None = None) -> np.ndarray:
    """Ascending eigenvalues ``(m, n)`` of symmetric ``(m, n, n)`` metrics, ``n <= 2``.

    Examples
    --------
    >>> eigvalsh_small(np.array([[[2.0, 1.0], [1.0, 2.0]]])).tolist()
    [[1.0, 3.0]]
    """
    if g.shape[1] == 1:
        return g[:, :, 0].copy()
    a, b, c = g[:, 0, 0], g[:, 0, 1], g[:, 1, 1]
    hi = 0.5 * (a + c) + np.hypot(0.5 * (a - c), b)
    d = a * c - b * b if det is None else det
    lo = np.divide(d, hi, out=np.zeros_like(hi), where=hi != 0)
    return np.stack([lo, hi], axis=1)


def factor_from_edges(E: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(R, g)`` for edge matrices ``E`` ``(m, d, n)``, ``n <= 2``: ``g = EᵀE = RᵀR``, ``R`` upper, diag >= 0.

    Examples
    --------
    >>> R, g = factor_from_edges(np.array([[[3.0, 1.0], [0.0, 2.0], [0.0, 0.0]]]))
    >>> R[0].tolist(), g[0].tolist()
    ([[3.0, 1.0], [0.0, 2.0]], [[9.0, 3.0], [3.0, 5.0]])
    """
    m, d, n = E.shape
    e1 = np.ascontiguousarray(E[:, :, 0])
    n11 = np.einsum("md,md->m", e1, e1)
    r11 = np.sqrt(n11)
    if n == 1:
        return r11.reshape(m, 1, 1), n11.reshape(m, 1, 1)
    e2 = np.ascontiguousarray(E[:, :, 1])
    n12 = np.einsum("md,md->m", e1, e2)
    n22 = np.einsum("md,md->m", e2, e2)
    if d == 3:
        c = np.cross(e1, e2)
        wedge2 = np.einsum("md,md->m", c, c)
    elif d == 2:
        wedge2 = (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) ** 2
    else:
        wedge2 = np.zeros(m)
        for i in range(d):
            for j in range(i + 1, d):
                wedge2 += (e1[:, i] * e2[:, j] - e1[:, j] * e2[:, i]) ** 2
    safe = np.where(r11 > 0, r11, 1.0)
    R = np.zeros((m, 2, 2))
    R[:, 0, 0] = r11
    R[:, 0, 1] = np.where(r11 > 0, n12 / safe, 0.0)
    R[:, 1, 1] = np.where(r11 > 0, np.sqrt(wedge2) / safe, np.sqrt(n22))
    g = np.empty((m, 2, 2))
    g[:, 0, 0], g[:, 0, 1], g[:, 1, 0], g[:, 1, 1] = n11, n12, n12, n22
    return R, g


def gradients_from_factor(R: np.ndarray) -> np.ndarray:
    """``Y = R⁻ᵀ [−1 | I]`` ``(m, n, n+1)`` for upper-triangular ``R`` ``(m, n, n)``, ``n <= 2`` (nonsingular).

    Examples
    --------
    >>> gradients_from_factor(np.array([[[1.0, 0.0], [0.0, 2.0]]])).tolist()
    [[[-1.0, 1.0, 0.0], [-0.5, 0.0, 0.5]]]
    """
    m, n = R.shape[0], R.shape[1]
    Z = np.zeros((m, n, n))  # Z = R⁻ᵀ (lower triangular)
    Z[:, 0, 0] = 1.0 / R[:, 0, 0]
    if n == 2:
        Z[:, 1, 1] = 1.0 / R[:, 1, 1]
        Z[:, 1, 0] = -R[:, 0, 1] * Z[:, 0, 0] * Z[:, 1, 1]
    return np.concatenate([-Z.sum(axis=2, keepdims=True), Z], axis=2)
