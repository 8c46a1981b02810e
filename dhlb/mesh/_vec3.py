"""3-vectors stored by coordinate, ``(3, k)`` arrays: cross and dot products and normalization.

The arithmetic is that of ``np.cross``, ``np.linalg.norm(axis=-1)`` and ``np.einsum("ij,ij->i")`` on
``(k, 3)`` arrays, term by term and in the same order, so the results are the same to the last bit;
working on contiguous coordinate rows avoids the overhead of those functions on short rows.

Examples
--------
>>> import numpy as np
>>> a, b = np.array([[1.0], [0], [0]]), np.array([[0.0], [2], [0]])
>>> cross(a, b).ravel().tolist(), dot(a, b).tolist(), unit(b)[0].ravel().tolist()
([0.0, 0.0, 2.0], [0.0], [0.0, 1.0, 0.0])
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross", "dot", "norm", "unit"]


def cross(a: np.ndarray, b: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``a × b`` per column of ``(3, k)`` arrays (into ``out`` if given: no stacked copy)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape), np.result_type(a, b)) if out is None else out
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        np.subtract(a[j] * b[k], a[k] * b[j], out=out[i])
    return out


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a · b`` per column, summed as ``(a0 b0 + a2 b2) + a1 b1`` (the order of ``np.einsum`` over three terms)."""
    return (a[0] * b[0] + a[2] * b[2]) + a[1] * b[1]


def norm(x: np.ndarray) -> np.ndarray:
    """``|x|`` per column, unscaled (``np.linalg.norm(axis=-1)``)."""
    return np.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])


def unit(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(x / |x|, |x|)`` per column, scaled by the largest entry first: no overflow or underflow of ``|x|²``.

    Zero columns stay zero (with length 0).
    """
    a = np.abs(x)
    m = np.maximum(np.maximum(a[0], a[1]), a[2])
    y = x / np.where(m > 0, m, 1.0)
    r = np.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
    return y / np.where(r > 0, r, 1.0), r * m
