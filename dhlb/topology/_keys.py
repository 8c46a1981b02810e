"""Integer keys for simplices, ordered lexicographically.

A k-simplex ``(v_0 < ... < v_k)`` is keyed by ``row_{k-1}(v_0..v_{k-1}) * N + v_k`` where
``row_{k-1}`` is the row of its prefix face among the (k-1)-simplices (which are in
lexicographic order).  Keys therefore sort exactly like the rows, fit into int64 for any
realistic complex, and make look-up a ``searchsorted``.
"""

from __future__ import annotations

import numpy as np


def combination_columns(k_plus_1: int, j_plus_1: int) -> np.ndarray:
    """All increasing column selections of size ``j_plus_1`` from ``k_plus_1`` columns (lex order)."""
    from itertools import combinations

    return np.array(list(combinations(range(k_plus_1), j_plus_1)), dtype=np.int64).reshape(-1, j_plus_1)


def row_keys(rows: np.ndarray, prefix_rows: np.ndarray | None, n_vertices: int) -> np.ndarray:
    """Keys of sorted ``rows`` given the row indices of their prefixes (``None`` for vertices/edges)."""
    if rows.shape[1] == 1:
        return rows[:, 0].astype(np.int64)
    if rows.shape[1] == 2:
        return rows[:, 0].astype(np.int64) * n_vertices + rows[:, 1]
    return prefix_rows.astype(np.int64) * n_vertices + rows[:, -1]


def lookup(sorted_keys: np.ndarray, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions of ``keys`` in ``sorted_keys`` and a mask of which were found."""
    if sorted_keys.size == 0:
        return np.zeros(keys.shape, np.int64), np.zeros(keys.shape, bool)
    pos = np.searchsorted(sorted_keys, keys)
    pos_c = np.minimum(pos, sorted_keys.size - 1)
    found = (pos < sorted_keys.size) & (sorted_keys[pos_c] == keys)
    return pos_c.astype(np.int64), found


def permutation_parity(rows: np.ndarray) -> np.ndarray:
    """+1/-1 per row: parity of the permutation that sorts the row (rows of distinct entries)."""
    m, n = rows.shape
    inversions = np.zeros(m, dtype=np.int64)
    for a in range(n):
        for b in range(a + 1, n):
            inversions += rows[:, a] > rows[:, b]
    return np.where(inversions % 2 == 0, 1, -1).astype(np.int64)


def argsort_keys(key: np.ndarray, bound: int) -> np.ndarray:
    """``np.argsort(key)`` for int64 keys in ``[0, bound)``, equal keys by position (a stable order).

    Sorts the values ``key * size + position`` when they fit into int64 (a value sort is several
    times faster than an index sort), else ``np.argsort(key, kind="stable")``.

    Examples
    --------
    >>> argsort_keys(np.array([5, 1, 5, 0]), 6).tolist()
    [3, 1, 0, 2]
    """
    size = key.size
    if size == 0 or int(bound) * size >= np.iinfo(np.int64).max:
        return np.argsort(key, kind="stable")
    comb = key * size
    comb += np.arange(size)
    comb.sort()
    return np.remainder(comb, size, out=comb)
