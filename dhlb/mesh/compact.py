"""Dropping vertices that no cell uses, keeping the map back to the input indices."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidSimplexError, UnreferencedVertexWarning

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["compact_mesh"]


def _renumber(n: int, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(kept, new)``: the rows of ``0 .. n - 1`` that some cell uses (increasing), and the renumbering.

    ``new[i]`` is the position of row ``i`` in ``kept`` (``-1`` for a row no cell uses), so that
    ``kept[new[cells]] == cells``.
    """
    used = np.zeros(n, dtype=bool)
    used[np.asarray(cells, dtype=np.int64).ravel()] = True
    kept = np.flatnonzero(used).astype(np.int64)
    new = np.full(n, -1, dtype=np.int64)
    new[kept] = np.arange(kept.size, dtype=np.int64)
    return kept, new


def compact_mesh(V: ArrayLike, F: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Remove the vertices that no cell references and renumber the cells.

    Parameters
    ----------
    V : (n, d) array
        Vertex coordinates (any number of columns).
    F : (m, k) int array
        Cells (triangles, tetrahedra, ...) as 0-based rows of ``V``.

    Returns
    -------
    V2 : (n2, d) array
        ``V[kept]``.
    F2 : (m, k) int64
        The cells renumbered into ``V2``; ``kept[F2] == F``.
    kept : (n2,) int64
        Increasing original indices of the kept vertices.

    Warns
    -----
    UnreferencedVertexWarning
        When at least one vertex is dropped (the message gives the count and the first ones).

    Raises
    ------
    InvalidSimplexError
        ``F`` is not a 2-d integer array or refers to rows outside ``V``.

    Examples
    --------
    >>> import warnings, numpy as np
    >>> from dhlb.io import compact_mesh
    >>> V = np.arange(15.0).reshape(5, 3); F = np.array([[0, 2, 4]])
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     V2, F2, kept = compact_mesh(V, F)
    >>> F2.tolist(), kept.tolist(), type(w[0].message).__name__
    ([[0, 1, 2]], [0, 2, 4], 'UnreferencedVertexWarning')
    """
    V = np.asarray(V)
    F = np.asarray(F)
    if V.ndim != 2:
        raise InvalidSimplexError(f"V must be a 2-d array (one vertex per row), got shape {V.shape}")
    if F.ndim != 2 or (F.size and not np.issubdtype(F.dtype, np.integer)):
        raise InvalidSimplexError(
            f"F must be a 2-d integer array (one cell per row), got shape {F.shape}, dtype {F.dtype}"
        )
    F = F.astype(np.int64)
    n = V.shape[0]
    if F.size and (F.min() < 0 or F.max() >= n):
        bad = int(np.flatnonzero(((F < 0) | (F >= n)).any(axis=1))[0])
        raise InvalidSimplexError(f"cell {bad} {tuple(F[bad].tolist())} refers to a vertex outside 0 .. {n - 1}")
    kept, new = _renumber(n, F)
    if kept.size < n:
        dropped = np.flatnonzero(new < 0)
        first = ", ".join(str(int(i)) for i in dropped[:5]) + (", ..." if dropped.size > 5 else "")
        warnings.warn(UnreferencedVertexWarning(
            f"{dropped.size} of {n} vertices are used by no cell and were dropped (indices {first}); "
            "the returned `kept` maps new vertex indices to the input ones", dropped=dropped, cell="cell"),
            stacklevel=2)
    return V[kept], new[F], kept
