"""Closed forms for stacks of 1-, 2- and 3-simplices: the hot path of surface and tet meshes.

:class:`~dhlb.geometry.simplex.SimplexStack` uses them instead of batched LAPACK calls, which
cost ~1 µs per tiny matrix, for ``n <= 3``:

* eigenvalues of a symmetric 2×2 metric ``g = [[a, b], [b, c]]``:
  ``λ_max = (a + c)/2 + hypot((a − c)/2, b)`` and ``λ_min = det g / λ_max`` (no cancellation in
  ``λ_min``: ``det g`` comes from the triangular factor, ``det g = (r_11 r_22)²``, when it is
  known, so degenerate triangles are measured to relative accuracy);
* the triangular factor ``R`` (``g = RᵀR``, positive diagonal) of the edge matrix
  ``E = [e_1 | e_2]``: ``r_11 = |e_1|``, ``r_12 = <e_1, e_2>/r_11``, ``r_22 = |e_1 ∧ e_2| / r_11``
  with ``|e_1 ∧ e_2|² = Σ_{i<j} (e_1i e_2j − e_1j e_2i)²`` (Lagrange's identity, any ambient
  dimension) -- the R of a QR factorization with the signs fixed to a positive diagonal;
* the Cholesky factor of a 3×3 metric written out (``r_11 = sqrt(g_11)``, ``r_1j = g_1j / r_11``,
  ``r_22 = sqrt(g_22 − r_12²)``, ``r_23 = (g_23 − r_12 r_13)/r_22``, ``r_33 = sqrt(g_33 − r_13² − r_23²)``);
  ``nan`` where a pivot is not positive;
* a certificate of definiteness for 3×3 metrics: positive pivots and ``det g / tr(g)³ > t`` imply
  ``λ_min/λ_max >= det g/λ_max³ >= det g / tr(g)³ > t`` (``λ_min = det g/(λ_mid λ_max)``), so only
  the simplices it cannot certify need eigenvalues;
* ``Y = R⁻ᵀ [−1 | I]`` from the explicit inverse of a lower-triangular matrix of order <= 3
  (forward substitution written out), and for triangles its Gram matrix ``YᵀY`` straight from
  ``R`` (the same operations, without the ``(m, 2, 3)`` stack ``Y``).

Each formula is checked against the LAPACK route in ``tests/test_geometry_small.py``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["soa_empty", "eigvalsh_small", "factor_from_edges", "cholesky_3", "surely_definite_3",
           "gradients_from_factor", "gram_of_columns", "gradient_gram_2"]


def soa_empty(m: int, *shape: int) -> np.ndarray:
    """An uninitialised ``(m, *shape)`` array stored simplex axis last, so ``A[:, i, j]`` is contiguous.

    Examples
    --------
    >>> soa_empty(5, 3, 3)[:, 0, 1].flags["C_CONTIGUOUS"]
    True
    """
    return np.moveaxis(np.empty((*shape, m)), -1, 0)


def eigvalsh_small(g: np.ndarray, det: np.ndarray | None = None, sqrt_det: np.ndarray | None = None) -> np.ndarray:
    """Ascending eigenvalues ``(m, n)`` of symmetric ``(m, n, n)`` metrics, ``n <= 2``.

    ``det`` (or, better, ``sqrt_det``, which cannot overflow where ``det = sqrt_det²`` would: edges
    of length 1e150) gives the determinant accurately; ``λ_min = det / λ_max``.

    Examples
    --------
    >>> eigvalsh_small(np.array([[[2.0, 1.0], [1.0, 2.0]]])).tolist()
    [[1.0, 3.0]]
    """
    if g.shape[1] == 1:
        return g[:, :, 0].copy()
    a, b, c = g[:, 0, 0], g[:, 0, 1], g[:, 1, 1]
    hi = 0.5 * (a + c) + np.hypot(0.5 * (a - c), b)
    if sqrt_det is not None:  # λ_min = √det · (√det / λ_max): no intermediate det (1e600 for 1e150 edges)
        lo = sqrt_det * np.divide(sqrt_det, hi, out=np.zeros_like(hi), where=hi != 0)
        return np.stack([lo, hi], axis=1)
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
    wedge = np.sqrt(_wedge2(e1, e2, m, d))
    # |e1 ∧ e2|² is a 4th power of the lengths: it under/overflows for edges of 1e∓100, where the
    # metric itself is still fine; there, recompute it from edges scaled by a power of two (exact)
    far = (n11 > 1e200) | (n11 < 1e-200) | (n22 > 1e200) | (n22 < 1e-200)
    if np.any(far):
        big = np.maximum(np.abs(e1[far]).max(axis=1), np.abs(e2[far]).max(axis=1))
        sc = np.exp2(np.round(np.log2(np.where(big > 0, big, 1.0))))
        wedge[far] = np.sqrt(_wedge2(e1[far] / sc[:, None], e2[far] / sc[:, None], int(far.sum()), d)) * sc**2
    safe = np.where(r11 > 0, r11, 1.0)
    R = np.zeros((m, 2, 2))
    R[:, 0, 0] = r11
    R[:, 0, 1] = np.where(r11 > 0, n12 / safe, 0.0)
    R[:, 1, 1] = np.where(r11 > 0, wedge / safe, np.sqrt(n22))
    g = np.empty((m, 2, 2))
    g[:, 0, 0], g[:, 0, 1], g[:, 1, 0], g[:, 1, 1] = n11, n12, n12, n22
    return R, g


def _wedge2(e1: np.ndarray, e2: np.ndarray, m: int, d: int) -> np.ndarray:
    """``|e1 ∧ e2|²`` per row for edge vectors ``(m, d)``."""
    if d == 3:
        c = np.cross(e1, e2)
        return np.einsum("md,md->m", c, c)
    if d == 2:
        return (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) ** 2
    out = np.zeros(m)
    for i in range(d):
        for j in range(i + 1, d):
            out += (e1[:, i] * e2[:, j] - e1[:, j] * e2[:, i]) ** 2
    return out


def cholesky_3(g: np.ndarray) -> np.ndarray:
    """Upper-triangular ``R`` ``(m, 3, 3)`` with ``g = RᵀR`` for symmetric ``(m, 3, 3)``; ``nan`` where not definite.

    Examples
    --------
    >>> cholesky_3(np.array([[[4.0, 2.0, 0.0], [2.0, 5.0, 0.0], [0.0, 0.0, 9.0]]]))[0].tolist()
    [[2.0, 1.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]
    """
    R = soa_empty(g.shape[0], 3, 3)
    R[:, 1, 0] = R[:, 2, 0] = R[:, 2, 1] = 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        r11 = np.sqrt(g[:, 0, 0])
        r12, r13 = g[:, 0, 1] / r11, g[:, 0, 2] / r11
        r22 = np.sqrt(g[:, 1, 1] - r12 * r12)
        r23 = (g[:, 1, 2] - r12 * r13) / r22
        r33 = np.sqrt(g[:, 2, 2] - r13 * r13 - r23 * r23)
    R[:, 0, 0], R[:, 0, 1], R[:, 0, 2], R[:, 1, 1], R[:, 1, 2], R[:, 2, 2] = r11, r12, r13, r22, r23, r33
    return R


def surely_definite_3(g: np.ndarray, R: np.ndarray, rtol: float) -> np.ndarray:
    """Simplices whose metric certainly has ``λ_min/λ_max > rtol`` (``R`` from :func:`cholesky_3`).

    ``det g = (r_11 r_22 r_33)²``; the margin ``1e-12`` covers the rounding of the pivots.

    Examples
    --------
    >>> g = np.array([np.eye(3), np.diag([1.0, 1.0, 1e-20])])
    >>> surely_definite_3(g, cholesky_3(g), 1e-13).tolist()
    [True, False]
    """
    with np.errstate(invalid="ignore"):
        det = (R[:, 0, 0] * R[:, 1, 1] * R[:, 2, 2]) ** 2
        tr = g[:, 0, 0] + g[:, 1, 1] + g[:, 2, 2]
        return det > max(2.0 * rtol, 1e-12) * tr * tr * tr    # nan (a failed pivot) compares False


def gradients_from_factor(R: np.ndarray) -> np.ndarray:
    """``Y = R⁻ᵀ [−1 | I]`` ``(m, n, n+1)`` for upper-triangular ``R`` ``(m, n, n)``, ``n <= 3`` (nonsingular).

    Examples
    --------
    >>> gradients_from_factor(np.array([[[1.0, 0.0], [0.0, 2.0]]])).tolist()
    [[[-1.0, 1.0, 0.0], [-0.5, 0.0, 0.5]]]
    """
    m, n = R.shape[0], R.shape[1]
    Z = soa_empty(m, n, n)  # Z = R⁻ᵀ (lower triangular)
    Z[:, 0, 0] = 1.0 / R[:, 0, 0]
    if n >= 2:
        Z[:, 1, 1] = 1.0 / R[:, 1, 1]
        Z[:, 1, 0] = -R[:, 0, 1] * Z[:, 0, 0] * Z[:, 1, 1]
    if n == 3:
        Z[:, 2, 2] = 1.0 / R[:, 2, 2]
        Z[:, 2, 1] = -R[:, 1, 2] * Z[:, 1, 1] * Z[:, 2, 2]
        Z[:, 2, 0] = -(R[:, 0, 2] * Z[:, 0, 0] + R[:, 1, 2] * Z[:, 1, 0]) * Z[:, 2, 2]
    Y = soa_empty(m, n, n + 1)
    for k in range(n):
        Y[:, k, k + 2:] = 0.0
        Y[:, k, 1:k + 2] = Z[:, k, :k + 1]
        Y[:, k, 0] = -Z[:, k, 0]
        for j in range(1, k + 1):
            Y[:, k, 0] -= Z[:, k, j]
    return Y


def gram_of_columns(Y: np.ndarray) -> np.ndarray:
    """``YᵀY`` ``(m, k, k)`` for ``(m, n, k)``, entry by entry (symmetric by construction, simplex axis last).

    Examples
    --------
    >>> gram_of_columns(np.array([[[1.0, 2.0], [0.0, 1.0]]]))[0].tolist()
    [[1.0, 2.0], [2.0, 5.0]]
    """
    m, n, k = Y.shape
    G = soa_empty(m, k, k)
    for a in range(k):
        for b in range(a, k):
            acc = Y[:, 0, a] * Y[:, 0, b]
            for q in range(1, n):
                acc += Y[:, q, a] * Y[:, q, b]
            G[:, a, b] = acc
            G[:, b, a] = acc
    return G


def gradient_gram_2(R: np.ndarray) -> np.ndarray:
    """``YᵀY`` ``(m, 3, 3)`` of ``Y = R⁻ᵀ [−1 | I]`` for upper-triangular ``R`` ``(m, 2, 2)`` (nonsingular).

    Bit for bit ``gram_of_columns(gradients_from_factor(R))``, with ``(m,)`` temporaries only.

    Examples
    --------
    >>> R = np.array([[[1.0, 0.5], [0.0, 2.0]]])
    >>> bool(np.array_equal(gradient_gram_2(R), gram_of_columns(gradients_from_factor(R))))
    True
    """
    z00 = 1.0 / R[:, 0, 0]
    z11 = 1.0 / R[:, 1, 1]
    z10 = -R[:, 0, 1] * z00 * z11
    y = ((-z00, z00, 0.0), (-z10 - z11, z10, z11))        # the rows of Y
    G = soa_empty(R.shape[0], 3, 3)
    for a in range(3):
        for b in range(a, 3):
            acc = y[0][a] * y[0][b] + y[1][a] * y[1][b]
            G[:, a, b] = acc
            G[:, b, a] = acc
    return G
