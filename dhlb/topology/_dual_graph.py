"""The dual graph of the top simplices, shared by the manifold checks and the orientation code.

:func:`interior_pairs` (re-exported by :mod:`dhlb.topology.manifold`, where it is documented)
and the strongly connected components of the dual graph (the messages of both modules name
simplices with :mod:`dhlb.topology._names`). Neither :mod:`dhlb.topology.manifold` nor
:mod:`dhlb.topology.orientation` is imported here, so both can import this module.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order
from scipy.sparse.csgraph import connected_components as _cc

if TYPE_CHECKING:
    from dhlb.topology._protocol import ComplexLike

__all__ = ["interior_pairs", "propagate_signs", "strong_components"]


def interior_pairs(X: ComplexLike):
    """The dual graph: pairs of top simplices sharing an (n−1)-face that has exactly two cofaces.

    Returns
    -------
    pairs : (E, 2) rows of the two n-simplices
    positions : (E, 2) position (in each) of the vertex not on the shared face
    faces : (E,) row of the shared (n−1)-face
    counts : (n_{n-1},) number of cofaces of every (n−1)-simplex

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3)])
    >>> pairs, pos, faces, counts = interior_pairs(X)
    >>> pairs.tolist(), pos.tolist(), X.simplices(1)[faces].tolist()
    ([[0, 1]], [[0, 2]], [[1, 2]])
    """
    n = X.dim
    f = np.asarray(X.faces(n)).ravel()  # flat position = top * (n+1) + local position
    counts = np.bincount(f, minlength=X.n_simplices(n - 1))
    flat = np.arange(f.size, dtype=np.int64)
    lo = np.full(counts.size, f.size, np.int64)
    hi = np.full(counts.size, -1, np.int64)
    np.minimum.at(lo, f, flat)  # O(n) first/last occurrence per face, no sort
    np.maximum.at(hi, f, flat)
    faces = np.nonzero(counts == 2)[0]
    (ta, pa), (tb, pb) = np.divmod(lo[faces], n + 1), np.divmod(hi[faces], n + 1)
    return np.stack([ta, tb], axis=1), np.stack([pa, pb], axis=1), faces, counts


def strong_components(X: ComplexLike, pairs: np.ndarray) -> tuple[int, np.ndarray]:
    """Number and labels (per top simplex) of the connected components of the dual graph ``pairs``."""
    m = X.n_simplices(X.dim)
    g = sp.csr_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
    return _cc(g, directed=False)


def propagate_signs(m: int, pairs: np.ndarray, flip: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signs ±1 on the ``m`` nodes of a graph with ``o[b] = o[a] (−1)^flip`` along every edge ``(a, b)``.

    The first node of each connected component gets +1; signs are propagated over a BFS tree by
    pointer jumping (vectorized, O(m log depth)), then every edge is checked.

    Parameters
    ----------
    m : int
        Number of nodes (top simplices, faces).
    pairs : (E, 2) int array
        The edges of the graph (pairs of nodes).
    flip : (E,) int array of 0 / 1
        1 where the two ends of an edge must get opposite signs.

    Returns
    -------
    o : (m,) int64 array of ±1
    labels : (m,) int array
        Connected component of each node (:func:`scipy.sparse.csgraph.connected_components`).
    clash : (E,) bool array
        The edges whose condition fails (none on an orientable graph).

    Examples
    --------
    >>> o, lab, clash = propagate_signs(3, np.array([[0, 1], [1, 2], [2, 0]]), np.array([1, 1, 0]))
    >>> o.tolist(), clash.tolist()
    ([1, -1, 1], [False, False, False])
    >>> propagate_signs(3, np.array([[0, 1], [1, 2], [2, 0]]), np.array([1, 1, 1]))[2].any()   # odd cycle
    np.True_
    """
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    flip = np.asarray(flip, np.int64)
    g = sp.csr_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
    _, lab = _cc(g, directed=False)
    _, roots = np.unique(lab, return_index=True)
    # BFS from a super-root m joined to the first node of every component; the symmetric
    # adjacency stores flip + 1 so that tree edges can be looked up.
    u = np.concatenate([pairs[:, 0], pairs[:, 1], np.full(roots.size, m), roots])
    v = np.concatenate([pairs[:, 1], pairs[:, 0], roots, np.full(roots.size, m)])
    w = np.concatenate([flip, flip, np.zeros(2 * roots.size, np.int64)]).astype(np.int8) + 1
    g = sp.csr_matrix((w, (u, v)), shape=(m + 1, m + 1))
    _, pred = breadth_first_order(g, m, directed=True, return_predecessors=True)
    parent = pred.astype(np.int64)
    parent[m] = m
    parity = np.zeros(m + 1, np.int64)
    parity[:m] = np.asarray(g[np.arange(m), parent[:m]]).ravel() - 1
    while np.any(parent != m):  # pointer jumping: parity relative to the super-root
        parity = (parity + parity[parent]) % 2
        parent = parent[parent]
    o = np.where(parity[:m] == 0, 1, -1).astype(np.int64)
    clash = o[pairs[:, 1]] != o[pairs[:, 0]] * (1 - 2 * flip)
    return o, lab, clash
