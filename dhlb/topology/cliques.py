"""Clique enumeration on integer arrays: the generating simplices of a flag (clique) complex.

:func:`maximal_cliques` takes a graph as a vertex count and an ``(m, 2)`` edge array (no graph
library) and returns the cliques that generate its flag complex, vectorised level by level;
:meth:`SimplicialComplex.from_graph <dhlb.topology.complex.SimplicialComplex.from_graph>` builds
the complex from them. :func:`group_pairs` is the array kernel shared with the dual graph.

Examples
--------
>>> import numpy as np
>>> E = np.array([[0, 1], [1, 2], [0, 2], [2, 3]])   # a triangle with a tail
>>> [b.tolist() for b in maximal_cliques(4, E)]
[[[0, 1, 2]], [[2, 3]]]
"""

from __future__ import annotations

import numbers

import numpy as np

from dhlb._memory_errors import check_memory
from dhlb.errors import InvalidParameterError, InvalidSimplexError, InvalidTypeError

__all__ = ["maximal_cliques", "group_pairs"]


def maximal_cliques(n: int, edges, max_dim: int | None = None) -> list[np.ndarray]:
    """The maximal cliques of a graph, truncated at ``max_dim + 1`` vertices.

    These are the maximal simplices of the ``max_dim``-skeleton of the flag complex of the graph:
    every maximal clique with at most ``max_dim + 1`` vertices, and every clique with exactly
    ``max_dim + 1`` vertices (each lies in a larger clique or is maximal itself). Handed to
    :class:`~dhlb.topology.complex.SimplicialComplex`, which adds their faces, they give the
    flag complex.

    Parameters
    ----------
    n : int >= 0
        The number of vertices ``0 .. n-1``; vertices on no edge are cliques of one vertex.
    edges : (m, 2) int array_like
        The edges, as vertex pairs in any order and direction; repeats are allowed (the flag
        complex depends on the adjacency only).
    max_dim : int >= 0, optional
        The largest clique kept has ``max_dim + 1`` vertices. Default: no bound (every maximal
        clique).

    Returns
    -------
    list of (m_k, k+1) int64 arrays
        One array per clique size, largest first (sizes without a clique left out); each row a
        clique, its vertices sorted increasingly; the order of the rows is unspecified.

    Raises
    ------
    InvalidTypeError
        ``n`` or ``max_dim`` is not an integer, or ``edges`` is not an integer array of pairs.
    InvalidParameterError
        ``n`` or ``max_dim`` is negative.
    InvalidSimplexError
        An edge has a vertex outside ``0 .. n-1``, or joins a vertex to itself (a self-loop).
    ResourceLimitError
        The enumeration would need more memory than is available (a 30-clique has 2^30 cliques): checked
        before each level of cliques is built, from the number of candidate pairs; the message gives the
        estimate and the largest ``max_dim`` whose levels fit.

    Notes
    -----
    The cliques are enumerated level by level: vertices are ranked by degree, every edge points
    from the lower to the higher rank, and two k-cliques that agree but for their last
    (highest-rank) vertex make a (k+1)-clique when their last vertices are adjacent. Ranking by
    degree bounds the out-degrees by ``sqrt(2 m)`` (a star with a million leaves has no
    candidate triangle). The cliques that are faces of a clique one level up are then dropped,
    with one sorted look-up per face.

    Examples
    --------
    >>> import numpy as np
    >>> K4 = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
    >>> [b.tolist() for b in maximal_cliques(5, K4)]        # the tetrahedron and the lone vertex 4
    [[[0, 1, 2, 3]], [[4]]]
    >>> [b.shape for b in maximal_cliques(5, K4, max_dim=1)]  # the 1-skeleton: 6 edges, vertex 4
    [(6, 2), (1, 1)]
    >>> maximal_cliques(3, [[0, 0]])
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidSimplexError: edge 0 joins vertex 0 to itself (a self-loop); a clique has none
    """
    for name, value, or_none in (("n", n, ""), ("max_dim", max_dim, " or None")):
        if value is None and or_none:
            continue
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise InvalidTypeError(f"{name} must be a non-negative integer{or_none}, got {value!r}")
        if value < 0:
            raise InvalidParameterError(f"{name} must be a non-negative integer{or_none}, got {value}")
    n = int(n)
    E = np.asarray(edges)
    if E.size == 0:
        E = np.zeros((0, 2), np.int64)
    if E.ndim != 2 or E.shape[1] != 2 or not np.issubdtype(E.dtype, np.integer):
        raise InvalidTypeError(f"edges must be an (m, 2) integer array, got shape {E.shape} of {E.dtype}")
    E = E.astype(np.int64, copy=False)
    bad = np.flatnonzero(np.any((E < 0) | (E >= n), axis=1))
    if bad.size:
        raise InvalidSimplexError(f"edge {bad[0]} ({E[bad[0], 0]}, {E[bad[0], 1]}) has a vertex outside 0 .. {n - 1}")
    loops = np.flatnonzero(E[:, 0] == E[:, 1])
    if loops.size:
        raise InvalidSimplexError(f"edge {loops[0]} joins vertex {E[loops[0], 0]} to itself (a self-loop); "
                                  "a clique has none")
    top = max(n - 1, 0) if max_dim is None else int(max_dim)
    # rank the vertices by degree (ties by index) and write the edges as (lower rank, higher rank)
    order = np.argsort(np.bincount(E.ravel(), minlength=n), kind="stable")  # order[rank] = vertex
    rank = np.empty(n, np.int64)
    rank[order] = np.arange(n)
    levels, parents = _levels(n, rank[E], top, max_dim)
    return [np.sort(order[b], axis=1) for b in _maximal_blocks(n, levels, parents) if b.size]


def group_pairs(starts: np.ndarray, sizes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every pair ``a < b`` of positions within each contiguous group, ordered by ``(a, b)``.

    Parameters
    ----------
    starts : (g,) int array
        The first position of each group, increasing.
    sizes : (g,) int array
        The length of each group; group ``i`` is ``starts[i] .. starts[i] + sizes[i] - 1``, and
        the groups are back to back (``starts[i + 1] == starts[i] + sizes[i]``).

    Returns
    -------
    a : (p,) int array
        The first position of each pair; ``p = sum(sizes * (sizes - 1) / 2)``.
    b : (p,) int array
        The second position, ``b > a``, in the same group.

    Examples
    --------
    >>> import numpy as np
    >>> a, b = group_pairs(np.array([0, 3]), np.array([3, 2]))
    >>> a.tolist(), b.tolist()
    ([0, 0, 1, 3], [1, 2, 2, 4])
    """
    N = int(sizes.sum())
    local = np.arange(N) - np.repeat(starts, sizes)
    count = np.repeat(sizes, sizes) - 1 - local  # partners after each position in its group
    first = np.repeat(np.arange(N), count)
    offset = np.arange(first.size) - np.repeat(np.cumsum(count) - count, count)
    return first, first + 1 + offset


def _levels(n: int, E: np.ndarray, top: int, max_dim: int | None = None
            ) -> tuple[list[np.ndarray], list[np.ndarray | None]]:
    """All k-cliques (k <= top) of the graph on ``0 .. n-1`` with edges ``E`` (rows in any order, repeats allowed).

    Returns the levels (sorted rows in lexicographic order, level k of width k+1) and, for each
    level k >= 1, the row in level k-1 of every row without its last vertex. Before a level is built,
    its memory (the candidate pairs and the new rows, on top of the levels so far) is checked against
    the memory available (``max_dim`` is named in the refusal).
    """
    levels: list[np.ndarray] = [np.arange(n, dtype=np.int64).reshape(-1, 1)]
    parents: list[np.ndarray | None] = [None]
    if top < 1 or E.size == 0:
        return levels, parents
    E = np.unique(np.sort(E, axis=1), axis=0)
    levels.append(E)
    parents.append(E[:, 0])
    keys = E[:, 0] * n + E[:, 1]  # sorted
    while len(levels) <= top:
        C = levels[-1]
        k = C.shape[1]
        new_group = np.r_[True, np.any(C[1:, : k - 1] != C[:-1, : k - 1], axis=1)]
        starts = np.flatnonzero(new_group)
        sizes = np.diff(np.r_[starts, C.shape[0]])
        _check_level(levels, k, int(np.sum(sizes * (sizes - 1) // 2)), max_dim)
        a, b = group_pairs(starts, sizes)
        q = C[a, -1] * n + C[b, -1]  # are the two last vertices adjacent?
        pos = np.minimum(np.searchsorted(keys, q), keys.size - 1)
        hit = keys[pos] == q
        if not np.any(hit):
            break
        a, b = a[hit], b[hit]
        levels.append(np.column_stack([C[a], C[b, -1]]))
        parents.append(a)
    return levels, parents


def _check_level(levels: list[np.ndarray], k: int, pairs: int, max_dim: int | None) -> None:
    """Refuse the level of (k+1)-cliques from ``pairs`` candidate pairs if it would not fit in memory.

    The model: every clique kept so far costs its row, its parent and (later) its key (``8 (j + 3)``
    bytes for j+1 vertices); the level costs about ``56 + 16 (k + 1)`` bytes a candidate pair (the pairs,
    their keys and look-ups, the new rows; at most one new clique a pair).
    """
    held = sum(L.shape[0] * 8 * (L.shape[1] + 2) for L in levels)
    check_memory("max_dim", max_dim, held + pairs * (56 + 16 * (k + 1)),
                 largest=lambda room: k - 1,
                 advice=f"{sum(L.shape[0] for L in levels):,} cliques of up to {k} vertices found so far and "
                        f"{pairs:,} candidates for {k + 1} vertices (the estimate counts those levels only)")


def _maximal_blocks(n: int, levels: list[np.ndarray], parents: list) -> list[np.ndarray]:
    """The top level and the cliques of the lower levels that are faces of no clique one level up.

    The faces are found level by level (one look-up per face): the face of a row without its
    vertex ``i < k`` is the face of its parent without ``i``, extended by the row's last vertex.
    """
    top = len(levels) - 1
    blocks = [levels[top]]
    if top == 0:
        return blocks
    keys = [None] + [parents[j] * n + levels[j][:, -1] for j in range(1, top + 1)]  # each sorted
    faces = levels[1][:, ::-1]  # faces[r, i] = row in level j-1 of row r of level j without vertex i
    covered = []
    for j in range(1, top + 1):
        if j > 1:
            rows, parent = levels[j], parents[j]
            faces_j = np.empty((rows.shape[0], j + 1), np.int64)
            faces_j[:, j] = parent
            faces_j[:, :j] = np.searchsorted(keys[j - 1], faces[parent] * n + rows[:, -1:])
            faces = faces_j
        mask = np.zeros(levels[j - 1].shape[0], bool)
        mask[faces.ravel()] = True
        covered.append(mask)
    blocks += [levels[k][~covered[k]] for k in range(top - 1, -1, -1) if not covered[k].all()]
    return blocks
