"""Barycentric subdivision and relabeling of simplicial complexes (vectorized)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from dhlb._memory_errors import check_memory
from dhlb.errors import InvalidSimplexError
from dhlb.topology.structure import _from_blocks, maximal_mask

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology._protocol import ComplexLike

__all__ = ["barycentric_subdivision", "relabeled"]


def barycentric_subdivision(X: ComplexLike) -> tuple[ComplexLike, np.ndarray]:
    """The barycentric subdivision Sd X and the map from its vertices to the simplices of X.

    The vertices of Sd X are the simplices of X, numbered by dimension then row: the k-simplex
    with row r is vertex ``sum(counts[:k]) + r``. A j-simplex of Sd X is a flag
    σ_0 ⊂ σ_1 ⊂ … ⊂ σ_j of simplices of X.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.

    Returns
    -------
    Sd : SimplicialComplex
        The subdivision, of the type of ``X`` and of the same dimension; its vertex labels are
        ``0 .. sum(X.counts) - 1``.
    vertex_map : (n_vertices(Sd), 2) int64 array
        ``vertex_map[w] = (k, row)`` of the simplex of X that vertex w stands for.

    Raises
    ------
    ResourceLimitError
        The subdivision would need more memory than is available (a maximal m-simplex becomes
        ``(m+1)!`` top simplices, with ``2^(m+1) (m+1)!`` faces to sort: a 12-simplex needs terabytes):
        refused before any work, with the estimate and the largest skeleton of ``X`` whose subdivision
        fits.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> Sd, vmap = barycentric_subdivision(SimplicialComplex([(0, 1, 2)]))
    >>> Sd.counts, Sd.euler_characteristic
    ((7, 12, 6), 1)
    >>> vmap[-1].tolist()
    [2, 0]
    """
    masks = [maximal_mask(X, m) for m in range(X.dim + 1)]
    tops = [int(np.count_nonzero(mask)) for mask in masks]
    check_memory("X.dim", X.dim, _subdivision_bytes(tops),
                 largest=lambda room: max((d for d in range(X.dim + 1)
                                           if _subdivision_bytes(_skeleton_tops(X, tops, d)) <= room), default=None),
                 advice=f"a maximal m-simplex becomes (m+1)! simplices ({math.factorial(X.dim + 1):,} for a "
                        f"{X.dim}-simplex); subdivide X.skeleton(k) for a k that fits")
    counts = np.asarray(X.counts, np.int64)
    offset = np.concatenate([[0], np.cumsum(counts)[:-1]])
    blocks = []
    for m in range(X.dim + 1):
        top = np.nonzero(masks[m])[0]
        if top.size == 0:
            continue
        flags = []
        for perm in _permutations(m + 1):
            cols = np.empty((top.size, m + 1), np.int64)
            cur = top
            cols[:, m] = offset[m] + cur
            for i in range(m, 0, -1):  # drop vertex perm[i] (its rank among perm[:i+1]) from sigma_i
                pos = int(np.sum(perm[:i] < perm[i]))
                cur = np.asarray(X.faces(i))[cur, pos]
                cols[:, i - 1] = offset[i - 1] + cur
            flags.append(cols)
        blocks.append(np.concatenate(flags))
    vertex_map = np.column_stack([np.repeat(np.arange(counts.size), counts),
                                  np.concatenate([np.arange(c) for c in counts])]).astype(np.int64)
    return _from_blocks(X, blocks), vertex_map


def complex_bytes(shapes) -> int:
    """Estimated peak bytes of building a complex from generating blocks of the given ``(rows, dimension)`` shapes.

    A model of the constructor of :class:`~dhlb.topology.complex.SimplicialComplex`: dimension by
    dimension it copies the ``C(m+1, k+1)`` column choices of every block of m-simplices (one array
    each), concatenates, keys and sorts them and keeps the distinct rows and keys; the input is copied
    (parsed, compacted). Measured peaks (tracemalloc) are 0.65–1.1 times the model for single
    simplices and flag complexes, 0.6–0.7 times for meshes and subdivisions. Used by the guards of
    :func:`barycentric_subdivision` and :meth:`SimplicialComplex.from_graph
    <dhlb.topology.complex.SimplicialComplex.from_graph>` (this module does not import the class).

    Parameters
    ----------
    shapes : iterable of (int, int)
        ``(rows, m)`` of each block of generating m-simplices.

    Returns
    -------
    int
        The estimated peak bytes.

    Examples
    --------
    >>> complex_bytes([(1, 12)]) < 10**7 < complex_bytes([(1, 20)])     # 2^13 vs 2^21 simplices
    True
    """
    by_m: dict[int, int] = {}
    for rows, m in shapes:
        if rows:
            by_m[int(m)] = by_m.get(int(m), 0) + int(rows)
    if not by_m:
        return 0
    kept = peak = 0
    for k in range(1, max(by_m) + 1):
        cands = sum(r * math.comb(m + 1, k + 1) for m, r in by_m.items() if m >= k)
        arrays = sum(math.comb(m + 1, k + 1) for m in by_m if m > k)
        peak = max(peak, kept + cands * (16 * (k + 1) + 64) + arrays * (16 * (k + 1) + 400))
        kept += cands * (k + 2) * 8
    return 3 * sum(r * (m + 1) * 8 for m, r in by_m.items()) + max(peak, kept)


def _subdivision_bytes(tops) -> int:
    """Estimated peak bytes of :func:`barycentric_subdivision` with ``tops[m]`` maximal m-simplices."""
    shapes, extra = [], 0
    for m, top in enumerate(tops):
        if top:
            f = math.factorial(m + 1)
            shapes.append((top * f, m))
            extra += f * (176 + 16 * (m + 1)) + 2 * top * f * (m + 1) * 8   # permutations, flags twice
    return extra + complex_bytes(shapes)


def _skeleton_tops(X, tops, d: int) -> list[int]:
    """The maximal simplices per dimension of the d-skeleton of X (all its d-simplices are maximal)."""
    return [*tops[:d], X.n_simplices(d)] if d < len(tops) - 1 else list(tops)


def _permutations(n: int) -> np.ndarray:
    from itertools import permutations

    return np.array(list(permutations(range(n))), np.int64)


def relabeled(X: ComplexLike, permutation: ArrayLike) -> ComplexLike:
    """The same complex with compact vertex v renamed ``permutation[v]``.

    ``permutation`` holds one distinct non-negative integer label per vertex of X.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex.
    permutation : (X.n_vertices,) int array_like
        The new label of every compact vertex: distinct, non-negative (any injective labelling,
        not only a permutation of ``0 .. n-1``).

    Returns
    -------
    SimplicialComplex
        The complex (of the type of ``X``) with the new labels, compacted again: its rows are
        sorted in the new labels' order and ``vertex_labels`` are the sorted new labels.

    Raises
    ------
    InvalidSimplexError
        ``permutation`` does not have one entry per vertex, is not integer, has a negative entry,
        or gives two vertices the same label (the message names them).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (2, 3)])
    >>> relabeled(X, [3, 2, 1, 0]).simplices(2).tolist()
    [[1, 2, 3]]
    """
    perm = np.asarray(permutation)
    if perm.ndim != 1 or perm.shape[0] != X.n_vertices:
        raise InvalidSimplexError(f"a relabeling needs one label per vertex ({X.n_vertices}), "
                                  f"got shape {perm.shape}")
    if perm.dtype == bool or not np.issubdtype(perm.dtype, np.integer):
        raise InvalidSimplexError(f"new vertex labels must be integers, got dtype {perm.dtype}")
    perm = perm.astype(np.int64)
    if np.any(perm < 0):
        v = int(np.argmax(perm < 0))
        raise InvalidSimplexError(f"new label {int(perm[v])} of vertex {v} is negative")
    uniq, _first, cnt = np.unique(perm, return_index=True, return_counts=True)
    if np.any(cnt > 1):
        lab = uniq[cnt > 1][0]
        a, b = np.nonzero(perm == lab)[0][:2]
        raise InvalidSimplexError(f"vertices {a} and {b} both get the new label {int(lab)}; "
                                  f"a relabeling must be injective")
    return _from_blocks(X, [perm[X.simplices(j)[maximal_mask(X, j)]] for j in range(X.dim + 1)])
