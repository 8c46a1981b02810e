"""Small shared helpers: naming simplices in error messages, wrapping angles."""

from __future__ import annotations

import numpy as np

__all__ = ["simplex_name", "wrap_angle"]


def simplex_name(X, k: int, index: int) -> str:
    """``"(a, b, ...)"`` in input vertex labels for the k-simplex with row ``index``.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> simplex_name(SimplicialComplex([(3, 7, 9)]), 1, 2)
    '(7, 9)'
    """
    row = X.vertex_labels[X.simplices(k)[int(index)]]
    return "(" + ", ".join(str(int(v)) for v in row) + ")"


def wrap_angle(a) -> np.ndarray:
    """Canonical representative in (−π, π] of angles mod 2π.

    Examples
    --------
    >>> wrap_angle([np.pi, -np.pi, 3 * np.pi / 2]).round(4).tolist()
    [3.1416, 3.1416, -1.5708]
    """
    a = np.asarray(a, dtype=np.float64)
    w = np.mod(a + np.pi, 2 * np.pi) - np.pi
    return np.where(w <= -np.pi, w + 2 * np.pi, w)
