"""Integer matrices as numpy object arrays of Python ints: validation, conversion, small helpers.

Private helpers of :mod:`dhlb.topology.intlinalg` (which re-exports :func:`as_object_matrix` and
:func:`to_int_array`): exact arithmetic works on ``object`` arrays, results go back to ``int64``
when every entry fits. Non-integer, ragged or non-finite input raises typed errors that name the
offending entry.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMatrixError, ShapeError

__all__ = ["as_object_matrix", "to_int_array", "object_eye", "egcd"]


def as_object_matrix(A, name: str = "A", ndim: int = 2) -> np.ndarray:
    """Validate an integer matrix (dense or sparse) and return it as an object array of Python ints."""
    if sp.issparse(A):
        A = A.toarray()
    try:
        arr = np.asarray(A)
    except Exception as exc:  # ragged input
        raise InvalidMatrixError(f"{name} is not a rectangular integer array ({exc}); pass a 2-D array.") from None
    if ndim == 2 and arr.ndim == 1 and arr.size == 0:
        arr = arr.reshape(0, 0)
    if arr.ndim != ndim:
        raise ShapeError(f"{name} must be {ndim}-dimensional, got shape {arr.shape}.")
    if arr.dtype == object:
        flat = arr.ravel()
        for i, x in enumerate(flat):
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
                if isinstance(x, (float, np.floating)) and np.isfinite(x) and float(x).is_integer():
                    continue
                idx = np.unravel_index(i, arr.shape)
                raise InvalidMatrixError(f"{name}{list(map(int, idx))} = {x!r} is not an integer; pass integers.")
        return np.array([int(x) for x in flat], dtype=object).reshape(arr.shape)
    if np.issubdtype(arr.dtype, np.integer) or arr.dtype == bool:
        return arr.astype(np.int64).astype(object) if arr.dtype != np.uint64 else np.array(
            [int(x) for x in arr.ravel()], dtype=object).reshape(arr.shape)
    if np.issubdtype(arr.dtype, np.floating):
        bad = ~np.isfinite(arr) | (arr != np.round(arr)) if arr.size else np.zeros(arr.shape, bool)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InvalidMatrixError(f"{name}{list(idx)} = {arr[idx]!r} is not an integer; pass integers.")
        return np.array([int(x) for x in arr.ravel()], dtype=object).reshape(arr.shape)
    raise InvalidMatrixError(f"{name} has dtype {arr.dtype}, expected integers.")


def to_int_array(M: np.ndarray) -> np.ndarray:
    """Return ``M`` as int64 if every entry fits, else as an object array of Python ints."""
    M = np.asarray(M, dtype=object)
    if M.size == 0:
        return np.zeros(M.shape, dtype=np.int64)
    try:
        return M.astype(np.int64)
    except OverflowError:
        return M


def object_eye(n: int) -> np.ndarray:
    """The ``n × n`` identity as an object array of Python ints."""
    E = np.zeros((n, n), dtype=object)
    E[np.arange(n), np.arange(n)] = 1
    return E


def egcd(a: int, b: int) -> tuple[int, int, int]:
    """Return ``(g, x, y)`` with ``x a + y b = g = gcd(a, b) >= 0``."""
    x0, y0, x1, y1 = 1, 0, 0, 1
    while b:
        q, a, b = a // b, b, a % b
        x0, x1 = x1, x0 - q * x1
        y0, y1 = y1, y0 - q * y1
    if a < 0:
        return -a, -x0, -y0
    return a, x0, y0
