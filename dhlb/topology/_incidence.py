"""Incidence data derived from the stored rows of a :class:`~dhlb.topology.complex.SimplicialComplex`.

Face tables, the boundary matrices ∂_k, the maximal simplices, the CSR pattern of the vertex
adjacency and the data positions of the local entries of each top simplex in it. These are the
implementations behind the (cached) attributes of the class, which keep the documentation and
examples; they take plain arrays, or the complex itself, and this module does not import
:mod:`dhlb.topology.complex` (which imports it).
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidSimplexError, SimplexNotFoundError
from dhlb.topology import _keys

if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    from dhlb.topology._protocol import ComplexLike

__all__ = ["VertexAdjacency", "face_tables", "boundary_matrices", "maximal_rows", "vertex_adjacency",
           "top_entry_positions", "subfaces", "coboundary_values"]


class VertexAdjacency(NamedTuple):
    """CSR pattern of vertex adjacency; see :attr:`SimplicialComplex.vertex_adjacency`."""

    indptr: np.ndarray
    indices: np.ndarray
    diagonal: np.ndarray
    upper: np.ndarray
    lower: np.ndarray


def face_tables(rows: Sequence[np.ndarray], keys: Sequence[np.ndarray], n: int,
                row_index: Callable[[int, np.ndarray], np.ndarray]) -> dict[int, np.ndarray]:
    """Per k >= 1, shape ``(n_k, k+1)``: row in the (k−1)-simplices of the face omitting vertex ``i``.

    ``rows[k]`` are the sorted k-rows, ``keys[k]`` their keys (prefix row * n + last vertex),
    ``n`` the number of vertices and ``row_index(k, rows)`` the row look-up of the complex.
    """
    out = {}
    for k in range(1, len(rows)):
        rk = rows[k]
        f = np.empty(rk.shape, np.int64)
        for i in range(k + 1):
            if i == k:
                f[:, i] = keys[k] // n if k > 1 else rk[:, 0]
            else:
                f[:, i] = row_index(k - 1, np.delete(rk, i, axis=1))
        f.setflags(write=False)
        out[k] = f
    return out


def boundary_matrices(faces: dict[int, np.ndarray], counts: Sequence[int]) -> list[sp.csr_matrix]:
    """∂_0 .. ∂_{dim+1} from the face tables, ``counts = (n_0, ..., n_dim)``; entries ``(−1)^i``."""
    dim = len(counts) - 1
    mats = [sp.csr_matrix((0, counts[0]), dtype=np.int64)]
    for k in range(1, dim + 1):
        f = faces[k]
        n_k = f.shape[0]
        signs = np.tile((-1) ** np.arange(k + 1, dtype=np.int64), n_k)
        cols = np.repeat(np.arange(n_k, dtype=np.int64), k + 1)
        mats.append(sp.csc_matrix((signs, (f.ravel(), cols)), shape=(counts[k - 1], n_k)).tocsr())
    mats.append(sp.csr_matrix((counts[dim], 0), dtype=np.int64))
    return mats


def maximal_rows(rows: Sequence[np.ndarray], faces: dict[int, np.ndarray]) -> list[np.ndarray]:
    """For each k, the rows of ``rows[k]`` that are faces of no (k+1)-simplex."""
    out = []
    dim = len(rows) - 1
    for k in range(dim + 1):
        if k == dim:
            out.append(rows[k])
        else:
            used = np.zeros(rows[k].shape[0], bool)
            used[faces[k + 1].ravel()] = True
            out.append(rows[k][~used])
    return out


def vertex_adjacency(N: int, E: np.ndarray) -> VertexAdjacency:
    """CSR pattern (read-only arrays) of N vertices and the canonical edges ``E`` (rows ``i < j``, sorted).

    Row ``v`` holds, by increasing column, the edges ``(u, v)`` with ``u < v``, the diagonal and the edges
    ``(v, w)`` with ``w > v``. The latter are consecutive rows of the sorted ``E``; the former are found by
    one sort of the edges by their second vertex.
    """
    n1 = E.shape[0]
    a, b = E[:, 0], E[:, 1]
    up, down = np.bincount(a, minlength=N), np.bincount(b, minlength=N)
    indptr = np.zeros(N + 1, np.int64)
    np.cumsum(up + down + 1, out=indptr[1:])
    diagonal = indptr[:-1] + down
    e = np.arange(n1, dtype=np.int64)
    first_up = np.cumsum(up) - up  # first edge (v, ·) in E
    upper = diagonal[a] + 1 + (e - first_up[a])
    by_b = np.argsort(b * N + a)  # distinct keys: no stable sort needed
    first_down = np.cumsum(down) - down
    bb = b[by_b]
    lower = np.empty(n1, np.int64)
    lower[by_b] = indptr[bb] + (e - first_down[bb])
    indices = np.empty(int(indptr[-1]), np.int64)
    indices[diagonal] = np.arange(N)
    indices[upper] = b
    indices[lower] = a
    out = VertexAdjacency(indptr, indices, diagonal, upper, lower)
    for arr in out:
        arr.setflags(write=False)
    return out


def top_entry_positions(X: ComplexLike, adj: VertexAdjacency) -> np.ndarray:
    """Positions in ``adj`` of the entries ``(v_b, v_a)`` of each top simplex, shape ``(n_top, k, k)``."""
    n = X.dim
    rows = X.simplices(n)
    pos = np.empty((rows.shape[0], n + 1, n + 1), np.int64)
    for a in range(n + 1):
        pos[:, a, a] = adj.diagonal[rows[:, a]]
    if n >= 1:
        edges = subfaces(X, n, 1)
        for p, (a, b) in enumerate(_keys.combination_columns(n + 1, 2).tolist()):
            pos[:, b, a] = adj.lower[edges[:, p]]  # v_a < v_b: (v_b, v_a) is below the diagonal
            pos[:, a, b] = adj.upper[edges[:, p]]
    pos.setflags(write=False)
    return pos

def _check_k(X: ComplexLike, k, lowest: int = 0) -> int:
    if isinstance(k, (bool, np.bool_)) or not isinstance(k, numbers.Integral):
        raise InvalidSimplexError(f"the dimension k must be an integer, got {k!r}")
    k = int(k)
    if k < lowest or k > X.dim:
        raise SimplexNotFoundError(f"the complex has dimension {X.dim}; it has no {k}-simplices "
                                   f"(use {lowest} <= k <= {X.dim})")
    return k


def subfaces(X: ComplexLike, j: int, k: int) -> np.ndarray:
    """Shape ``(n_j, C(j+1, k+1))``: rows of the k-faces of each j-simplex (lexicographic column order).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> subfaces(SimplicialComplex([(0, 1, 2)]), 2, 1).tolist()
    [[0, 1, 2]]
    """
    j, k = _check_k(X, j), _check_k(X, k)
    if k > j:
        raise InvalidSimplexError(f"subfaces(j={j}, k={k}) needs k <= j")
    rows = X.simplices(j)
    if k == j:
        return np.arange(rows.shape[0], dtype=np.int64).reshape(-1, 1)
    if k == 0:
        return rows.astype(np.int64)
    if k == j - 1:
        return np.asarray(X.faces(j))[:, ::-1]  # face omitting i is the i-th from the end in lex order
    # recursion over facets: the k-face S of a j-simplex is a k-face of the facet omitting the
    # largest local vertex not in S (pure index arithmetic, no look-ups)
    facets = np.asarray(X.faces(j))
    sub = subfaces(X, j - 1, k)
    inner = {tuple(c): p for p, c in enumerate(_keys.combination_columns(j, k + 1).tolist())}
    combos = _keys.combination_columns(j + 1, k + 1).tolist()
    out = np.empty((rows.shape[0], len(combos)), dtype=np.int64)
    for c, S in enumerate(combos):
        omit = max(set(range(j + 1)) - set(S))
        rel = tuple(v if v < omit else v - 1 for v in S)
        out[:, c] = sub[facets[:, omit], inner[rel]]
    return out


def coboundary_values(X: ComplexLike, k: int, values) -> tuple[np.ndarray, np.ndarray]:
    """``d_k`` applied to a k-cochain via ``X.faces(k+1)`` (no sparse matrix is built).

    Returns ``(d values, scale)`` where ``scale = |d| |values|`` bounds the rounding error.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> coboundary_values(X, 1, np.array([1.0, 2.0, 4.0]))[0].tolist()      # ω_12 − ω_02 + ω_01
    [3.0]
    """
    v = np.asarray(values)
    if X.n_simplices(k + 1) == 0:
        return np.zeros(0, v.dtype), np.zeros(0)
    f = X.faces(k + 1)
    signs = np.where(np.arange(k + 2) % 2 == 0, 1.0, -1.0)
    g = v[f]
    return g @ signs, np.abs(g).sum(axis=1)
