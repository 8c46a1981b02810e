"""Graph primitives on the 1-skeleton: spanning forests, edge look-up, tree sweeps, fundamental cycles.

One home for what topology, forms and bundles do with graphs:

* :func:`bfs_forest` — a breadth-first spanning forest of any graph (one C-level BFS from a
  virtual super-root); :func:`spanning_forest` — that of a complex's 1-skeleton as a
  :class:`SpanningForest` (parent edges, non-tree edges);
* :func:`edge_lookup` and :func:`path_edges` — edge rows of vertex pairs and paths;
* :func:`tree_accumulate` — values accumulated from the roots along the tree (level sweep or
  pointer jumping, ``O(n log depth)`` vectorized work);
* :func:`tree_path_chains`, :func:`fundamental_cycles` — the tree paths and the fundamental
  1-cycles (a Z-basis of ker ∂₁), :func:`cycle_vertices` — one fundamental cycle as a vertex loop;
* :func:`incidence`, :func:`incidence_forest`, :func:`graph_kernel` — the same for a graph given
  as an incidence matrix (``∂_1``): the kernel basis of fundamental cycles used by the sparse
  elimination (:mod:`dhlb.topology._sparse_elim`).

A spanning forest of the 1-skeleton has one root per connected component; every non-tree
edge ``e = (u, v)``, ``u < v``, closes one fundamental cycle ``chain(u) + e − chain(v)``.

Examples
--------
>>> from dhlb import SimplicialComplex
>>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2), (2, 3)])
>>> T = spanning_forest(X)
>>> T.roots.tolist(), T.nontree.tolist()
([0], [2])
>>> fundamental_cycles(X, T).toarray().tolist()     # the triangle loop 0 -> 1 -> 2 -> 0
[[1, -1, 1, 0]]
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components

from dhlb.errors import NotAPathError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology._protocol import ComplexLike

__all__ = [
    "SpanningForest",
    "spanning_forest",
    "bfs_forest",
    "tree_accumulate",
    "edge_lookup",
    "path_edges",
    "tree_path_chains",
    "fundamental_cycles",
    "cycle_vertices",
    "incidence",
    "incidence_forest",
    "graph_kernel",
]


@dataclass(frozen=True)
class SpanningForest:
    """A BFS spanning forest of the 1-skeleton (made by :func:`spanning_forest`).

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    roots : (c,) int64 array
        The root (base vertex) of each component.
    component : (n_0,) int64 array
        Component label of each vertex (index into ``roots``).
    parent : (n_0,) int64 array
        Parent vertex, ``-1`` at roots.
    parent_edge : (n_0,) int64 array
        Row in ``X.simplices(1)`` of the edge to the parent, ``-1`` at roots.
    order : (n_0,) int64 array
        Vertices in BFS order (parents before children).
    tree_mask : (n_1,) bool array
        Which edges are tree edges.
    nontree : (m,) int64 array
        The non-tree edges (one loop-group generator each), increasing.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> T = spanning_forest(SimplicialComplex([(0, 1), (1, 2), (3, 4)]))
    >>> T.n_components, T.roots.tolist(), T.parent.tolist(), T.nontree.tolist()
    (2, [0, 3], [-1, 0, 1, -1, 3], [])
    """

    roots: np.ndarray
    component: np.ndarray
    parent: np.ndarray
    parent_edge: np.ndarray
    order: np.ndarray
    tree_mask: np.ndarray
    nontree: np.ndarray

    @property
    def n_components(self) -> int:
        """Number of trees (connected components)."""
        return int(self.roots.size)

    def step_forward(self, X: ComplexLike) -> np.ndarray:
        """Bool per vertex: the edge from the parent is canonically oriented parent → vertex."""
        return self.parent < np.arange(self.parent.size)


def _edge_keys(X) -> np.ndarray:
    E = X.simplices(1)
    return E[:, 0] * X.n_vertices + E[:, 1]


def edge_lookup(X, a, b) -> tuple[np.ndarray, np.ndarray]:
    """Edge rows of the vertex pairs ``(a, b)`` (compact indices, any order) and a found mask.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> idx, ok = edge_lookup(X, [2, 0], [1, 2])
    >>> idx.tolist(), ok.tolist()
    ([2, 1], [True, True])
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    keys = _edge_keys(X)
    q = np.minimum(a, b) * X.n_vertices + np.maximum(a, b)
    if keys.size == 0:
        return np.zeros(q.shape, np.int64), np.zeros(q.shape, bool)
    pos = np.minimum(np.searchsorted(keys, q), keys.size - 1)
    found = (keys[pos] == q) & (a != b)
    return pos.astype(np.int64), found


def bfs_forest(n: int, a, b, roots=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """BFS forest of the undirected graph on ``n`` nodes with links ``(a[k], b[k])``.

    Returns ``(labels, roots, parent, order)``: component label per node, root per component
    (the smallest node, or the node given in ``roots`` for its component), parent node
    (``-1`` at roots) and the nodes in BFS order.  One C-level BFS from a virtual super-root.
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    g = sp.csr_matrix((np.ones(a.size), (a, b)), shape=(n, n))
    ncomp, labels = connected_components(g, directed=False)
    root = np.full(ncomp, n, np.int64)
    np.minimum.at(root, labels, np.arange(n, dtype=np.int64))
    for r in [] if roots is None else np.atleast_1d(roots):
        root[labels[int(r)]] = int(r)
    rows = np.concatenate([a, np.full(ncomp, n)])
    cols = np.concatenate([b, root])
    aug = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n + 1, n + 1))
    order, pred = breadth_first_order(aug, n, directed=False, return_predecessors=True)
    parent = pred[:n].astype(np.int64)
    parent[parent == n] = -1
    return labels.astype(np.int64), root, parent, order[1:].astype(np.int64)


def spanning_forest(X: ComplexLike, base: int | None = None, edges: ArrayLike | None = None) -> SpanningForest:
    """BFS spanning forest; the root of each component is its smallest vertex, or ``base``.

    ``edges`` (optional edge rows) restricts the graph to a subset of the 1-skeleton; then
    ``nontree`` lists only the subset's non-tree edges.

    Parameters
    ----------
    X : SimplicialComplex
        Any complex; its 1-skeleton is the graph.
    base : int, optional
        A compact vertex index: the root of its component (the other components keep their
        smallest vertex).
    edges : (m,) int array_like, optional
        Rows of ``X.simplices(1)``: the graph is restricted to these edges (every vertex kept).
        Default: every edge.

    Returns
    -------
    SpanningForest
        The BFS forest, its ``tree_mask`` over all ``X.n_simplices(1)`` edges.

    Raises
    ------
    NotAPathError
        ``base`` is not a vertex index ``0 .. X.n_vertices - 1``.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> T = spanning_forest(SimplicialComplex([(0, 1, 2), (3, 4)]), base=2)
    >>> T.roots.tolist(), T.parent.tolist()
    ([2, 3], [2, 2, -1, -1, 3])
    """
    n = X.n_vertices
    n1 = X.n_simplices(1)
    sel = np.arange(n1, dtype=np.int64) if edges is None else np.asarray(edges, dtype=np.int64)
    E = X.simplices(1)[sel]
    if base is not None and not (0 <= int(base) < n):
        raise NotAPathError(f"base vertex {base} is not a vertex of the complex (0 .. {n - 1})")
    labels, roots, parent, order = bfs_forest(n, E[:, 0], E[:, 1], None if base is None else [base])
    child = np.nonzero(parent >= 0)[0]
    pe = np.full(n, -1, np.int64)
    pe[child] = edge_lookup(X, parent[child], child)[0]
    tree_mask = np.zeros(n1, bool)
    tree_mask[pe[child]] = True
    return SpanningForest(
        roots=roots,
        component=labels,
        parent=parent,
        parent_edge=pe,
        order=order,
        tree_mask=tree_mask,
        nontree=sel[~tree_mask[sel]] if edges is not None else np.nonzero(~tree_mask)[0].astype(np.int64),
    )


def tree_accumulate(forest, step, compose, identity, order=None):
    """Accumulate edge values from the roots: ``acc[v] = step[v] ∘ acc[parent[v]]``.

    ``step[v]`` is the value on the tree edge parent → v (ignored at roots, where the
    result is ``identity``); ``compose(a, b)`` must be associative and vectorized over the
    first axis.  ``forest`` is a :class:`SpanningForest` or a parent array (``-1`` at roots).

    With a BFS order (``forest.order`` or ``order``) the tree is swept level by level in BFS
    order (cache friendly, one vectorized step per level); for deep trees (many levels) or
    without an order, pointer jumping is used (``O(log depth)`` rounds of random gathers).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> T = spanning_forest(SimplicialComplex([(0, 1), (1, 2), (2, 3)]))
    >>> tree_accumulate(T, np.ones(4, int), np.add, 0).tolist()   # depths
    [0, 1, 2, 3]
    """
    parent = getattr(forest, "parent", forest)
    order = getattr(forest, "order", None) if order is None else order
    n = parent.size
    if order is not None and n > 4096:
        out = _sweep_levels(parent, np.asarray(order), step, compose, identity, max_levels=256 + n // 512)
        if out is not None:
            return out
    roots_mask = parent < 0
    val = np.array(step, copy=True)
    val[roots_mask] = identity
    ptr = np.where(roots_mask, np.arange(n), parent)
    while True:
        pending = ~roots_mask[ptr]
        if not np.any(pending):
            return val
        idx = np.nonzero(pending)[0]
        val[idx] = compose(val[idx], val[ptr[idx]])
        ptr[idx] = ptr[ptr[idx]]


def _sweep_levels(parent, order, step, compose, identity, max_levels: int):
    """Level-by-level accumulation in BFS order; None if there are more than ``max_levels`` levels."""
    n = parent.size
    pos = np.empty(n, np.int64)
    pos[order] = np.arange(n)
    par = parent[order]
    ppos = np.where(par >= 0, pos[np.maximum(par, 0)], -1)  # non-decreasing in BFS order
    if np.any(ppos[1:] < ppos[:-1]):
        return None
    starts = [0]
    s = int(np.searchsorted(ppos, 0, side="left"))  # the roots come first
    while s < n:
        if len(starts) > max_levels:
            return None
        starts.append(s)
        s = int(np.searchsorted(ppos, s, side="left"))
    starts.append(n)
    val = np.array(step, copy=True)[order]
    val[: starts[1]] = identity
    for a, b in pairwise(starts[1:]):
        val[a:b] = compose(val[a:b], val[ppos[a:b]])
    out = np.empty_like(val)
    out[order] = val
    return out


def path_edges(X, path) -> tuple[np.ndarray, np.ndarray]:
    """Edge rows of the steps of a vertex path and whether each step is canonically oriented.

    Raises
    ------
    NotAPathError
        naming the first step that is not an edge of the complex.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2)])
    >>> e, fwd = path_edges(X, [0, 2, 1])
    >>> e.tolist(), fwd.tolist()
    ([1, 2], [True, False])
    """
    p = np.asarray(path)
    if p.ndim != 1 or p.size == 0:
        raise NotAPathError(f"a path is a non-empty 1-d sequence of vertices, got shape {p.shape}")
    if not np.issubdtype(p.dtype, np.integer):
        if not (np.issubdtype(p.dtype, np.floating) and np.all(np.isfinite(p)) and np.all(p == np.round(p))):
            raise NotAPathError(f"path vertices must be integers, got {p.tolist()!r}")
    p = p.astype(np.int64)
    bad = (p < 0) | (p >= X.n_vertices)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise NotAPathError(
            f"path position {i}: vertex {int(p[i])} is not a vertex of the complex (0 .. {X.n_vertices - 1})"
        )
    u, v = p[:-1], p[1:]
    idx, ok = edge_lookup(X, u, v)
    if not np.all(ok):
        i = int(np.argmin(ok))
        raise NotAPathError(
            f"path step {i}: ({int(u[i])}, {int(v[i])}) is not an edge of the complex; "
            "consecutive path vertices must span an edge"
        )
    return idx, u < v


def tree_path_chains(X, forest: SpanningForest, vertices) -> sp.csr_matrix:
    """Integer 1-chains of the tree paths root → v, one row per vertex in ``vertices``."""
    vertices = np.asarray(vertices, dtype=np.int64)
    rows, cols, vals = [], [], []
    ids = np.arange(vertices.size)
    cur = vertices.copy()
    active = forest.parent[cur] >= 0
    while np.any(active):
        c = cur[active]
        par = forest.parent[c]
        rows.append(ids[active])
        cols.append(forest.parent_edge[c])
        vals.append(np.where(par < c, 1, -1))
        cur[active] = par
        active = forest.parent[cur] >= 0

    def cat(xs):
        return np.concatenate(xs) if xs else np.zeros(0, np.int64)

    return sp.csr_matrix((cat(vals), (cat(rows), cat(cols))), shape=(vertices.size, X.n_simplices(1)), dtype=np.int64)


def fundamental_cycles(X: ComplexLike, forest: SpanningForest, edges: ArrayLike | None = None) -> sp.csr_matrix:
    """The fundamental 1-cycles ``chain(u) + e − chain(v)`` of non-tree edges (rows).

    Together (``edges=None``: all non-tree edges) they form a Z-basis of ker ∂₁.  Cost
    ``O(m · depth)`` nonzeros; meant for small complexes and few edges.

    Parameters
    ----------
    X : SimplicialComplex
        The complex whose 1-skeleton ``forest`` spans.
    forest : SpanningForest
        A spanning forest of ``X`` (:func:`spanning_forest`); ``chain(v)`` is its path root → v.
    edges : (m,) int array_like, optional
        The edges ``e = (u, v)``, ``u < v`` (rows of ``X.simplices(1)``) closing the cycles.
        Default: ``forest.nontree``.

    Returns
    -------
    (m, n_1) scipy.sparse int64 csr matrix
        Row ``i``: the 1-chain ``chain(u) + e − chain(v)`` of ``edges[i]``, a cycle over
        ``X.simplices(1)`` (zero for a tree edge).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> C = fundamental_cycles(X, spanning_forest(X))
    >>> C.shape, bool(abs(X.boundary(1) @ C.T).sum() == 0)
    ((3, 6), True)
    """
    edges = forest.nontree if edges is None else np.asarray(edges, dtype=np.int64)
    E = X.simplices(1)[edges]
    m = edges.size
    own = sp.csr_matrix((np.ones(m, np.int64), (np.arange(m), edges)), shape=(m, X.n_simplices(1)))
    out = tree_path_chains(X, forest, E[:, 0]) + own - tree_path_chains(X, forest, E[:, 1])
    out.eliminate_zeros()
    return out.tocsr()


def cycle_vertices(parent: np.ndarray, i: int, j: int) -> list[int]:
    """The fundamental cycle of the non-tree edge ``(i, j)`` as a closed vertex list.

    ``i → j → … → lca → … → i`` along the tree given by ``parent`` (``-1`` at roots), in the
    forest's (compact) vertex numbering.

    Examples
    --------
    >>> cycle_vertices(np.array([-1, 0, 1, 0]), 2, 3)    # the tree 0-1-2, 0-3 and the edge (2, 3)
    [2, 3, 0, 1, 2]
    """

    def to_root(v: int) -> list[int]:
        out = [v]
        while parent[out[-1]] >= 0:
            out.append(int(parent[out[-1]]))
        return out

    pi, pj = to_root(int(i)), to_root(int(j))
    on_i = {v: t for t, v in enumerate(pi)}
    a = next(t for t, v in enumerate(pj) if v in on_i)
    return [int(i)] + pj[: a + 1] + pi[: on_i[pj[a]]][::-1]


# ---------------------------------------------------------------------------- incidence matrices
def incidence(A: sp.csc_matrix):
    """``(head, tail)`` per column of an incidence matrix, else None.

    Every column must be ``e_head - e_tail`` (``head != tail``) or zero (then head = tail = -1).
    ``A``: canonical int64 CSC.
    """
    nnz = np.diff(A.indptr)
    if np.any((nnz != 2) & (nnz != 0)):
        return None
    head = np.full(A.shape[1], -1, dtype=np.int64)
    tail = np.full(A.shape[1], -1, dtype=np.int64)
    two = np.flatnonzero(nnz == 2)
    start = A.indptr[two]
    d0, d1 = A.data[start], A.data[start + 1]
    if not np.all(d0 + d1 == 0) or not np.all(np.abs(d0) == 1):
        return None
    r0, r1 = A.indices[start], A.indices[start + 1]
    head[two] = np.where(d0 == 1, r0, r1)
    tail[two] = np.where(d0 == 1, r1, r0)
    return head, tail


def incidence_forest(head, tail, m):
    """The BFS spanning forest of :func:`bfs_forest` on the columns of an incidence matrix.

    ``head``/``tail`` per column as from :func:`incidence` (``-1``: zero column). Returns
    ``order`` (vertices, parents first), ``pred`` (``m`` for component roots), ``tree_col``
    (the column of the tree edge to the parent, -1 for roots), ``sign`` (+1 if that column
    points from the vertex to its parent) and ``root`` (the root of each vertex).
    """
    e = np.flatnonzero(head >= 0)
    h, t = head[e], tail[e]
    labels, roots, parent, order = bfs_forest(m, h, t)
    tree_col = np.full(m, -1, dtype=np.int64)
    sign = np.zeros(m, dtype=np.int64)
    verts = np.flatnonzero(parent >= 0)
    if len(verts):
        key = np.minimum(h, t).astype(np.int64) * (m + 1) + np.maximum(h, t)
        srt = np.argsort(key, kind="stable")
        p = parent[verts]
        vk = np.minimum(verts, p).astype(np.int64) * (m + 1) + np.maximum(verts, p)
        pos = srt[np.searchsorted(key[srt], vk)]
        tree_col[verts] = e[pos]
        sign[verts] = np.where(h[pos] == p, 1, -1)
    pred = np.where(parent < 0, m, parent)
    return order, pred, tree_col, sign, roots[labels] if m else np.zeros(0, dtype=np.int64)


def graph_kernel(A: sp.csc_matrix):
    """Fundamental cycles of a breadth-first spanning forest, or None if A is no incidence matrix."""
    m, n = A.shape
    inc = incidence(A)
    if inc is None or m == 0:
        return None
    head, tail = inc
    order, pred, tree_col, sign, _ = incidence_forest(head, tail, m)
    depth = np.zeros(m + 1, dtype=np.int64)
    pred = np.r_[pred, m]
    for v in order.tolist():  # parents come first
        depth[v] = depth[pred[v]] + 1
    is_tree = np.zeros(n, dtype=bool)
    is_tree[tree_col[tree_col >= 0]] = True
    nt = np.flatnonzero((head >= 0) & ~is_tree)
    zero_cols = np.flatnonzero(head < 0)
    K = len(nt) + len(zero_cols)
    rows = [nt, zero_cols]
    cols = [np.arange(len(nt)), len(nt) + np.arange(len(zero_cols))]
    vals = [np.ones(len(nt), dtype=np.int64), np.ones(len(zero_cols), dtype=np.int64)]
    gid = np.arange(len(nt))
    ch, ct = head[nt], tail[nt]
    while len(gid):
        done = ch == ct
        gid, ch, ct = gid[~done], ch[~done], ct[~done]
        if not len(gid):
            break
        dh, dt = depth[ch], depth[ct]
        uh, ut = dh >= dt, dt >= dh
        rows += [tree_col[ch[uh]], tree_col[ct[ut]]]
        cols += [gid[uh], gid[ut]]
        vals += [sign[ch[uh]], -sign[ct[ut]]]
        ch = np.where(uh, pred[ch], ch)
        ct = np.where(ut, pred[ct], ct)
    rows, cols, vals = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    order_cols = np.argsort(np.r_[nt, zero_cols], kind="stable")  # basis in column order
    inv = np.empty(K, dtype=np.int64)
    inv[order_cols] = np.arange(K)
    return sp.csc_matrix((vals, (rows, inv[cols])), shape=(n, K), dtype=np.int64)
