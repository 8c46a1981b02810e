"""Small shared helpers: naming simplices in error messages, cheap coboundaries (wrap_angle comes from dhlb.forms)."""

from __future__ import annotations

import numpy as np

from dhlb.forms.groups import wrap_angle  # the one canonical (−π, π] representative

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


def coboundary(X, k: int, values) -> np.ndarray:
    """``d_k`` applied to a k-cochain via ``X.faces(k+1)`` (no sparse matrix is built).

    Returns ``(d values, scale)`` where ``scale = |d| |values|`` bounds the rounding error.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> coboundary(X, 1, np.array([1.0, 2.0, 4.0]))[0].tolist()      # ω_12 − ω_02 + ω_01
    [3.0]
    """
    v = np.asarray(values)
    if X.n_simplices(k + 1) == 0:
        return np.zeros(0, v.dtype), np.zeros(0)
    f = X.faces(k + 1)
    signs = np.where(np.arange(k + 2) % 2 == 0, 1.0, -1.0)
    g = v[f]
    return g @ signs, np.abs(g).sum(axis=1)
