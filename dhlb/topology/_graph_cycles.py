"""Graph incidence matrices (internal): breadth-first spanning forests and fundamental cycles.

Used for ``∂_1`` of a complex: the kernel of an incidence matrix has the fundamental cycles of a
spanning forest as a Z-basis (each has exactly one non-tree edge), and the forest gives the unit
pivots of ``∂_1`` without any fill (see :meth:`ChainReduction._eliminate_graph`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph


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


def bfs_forest(head, tail, m):
    """Breadth-first spanning forest of the graph with edges ``tail -> head`` (``-1``: no edge).

    Returns ``order`` (vertices, parents first), ``pred`` (``m`` for component roots),
    ``tree_col`` (the column of the tree edge to the parent, -1 for roots), ``sign`` (+1 if that
    column points from the vertex to its parent) and ``root`` (the root of each vertex).
    """
    e = np.flatnonzero(head >= 0)
    h, t = head[e], tail[e]
    G = sp.coo_matrix((np.ones(len(e)), (h, t)), shape=(m, m)).tocsr()
    ncomp, lab = csgraph.connected_components(G, directed=False)
    roots = np.unique(lab, return_index=True)[1]
    ext = sp.coo_matrix((np.ones(len(e) + ncomp), (np.r_[h, np.full(ncomp, m)], np.r_[t, roots])),
                        shape=(m + 1, m + 1)).tocsr()
    order, pred = csgraph.breadth_first_order(ext, m, directed=False, return_predecessors=True)
    order = order[1:]
    pred = pred[:m]
    tree_col = np.full(m, -1, dtype=np.int64)
    sign = np.zeros(m, dtype=np.int64)
    verts = np.flatnonzero((pred >= 0) & (pred < m))
    if len(verts):
        key = np.minimum(h, t).astype(np.int64) * (m + 1) + np.maximum(h, t)
        srt = np.argsort(key, kind="stable")
        p = pred[verts]
        vk = np.minimum(verts, p).astype(np.int64) * (m + 1) + np.maximum(verts, p)
        pos = srt[np.searchsorted(key[srt], vk)]
        tree_col[verts] = e[pos]
        sign[verts] = np.where(h[pos] == p, 1, -1)
    root = roots[lab] if m else np.zeros(0, dtype=np.int64)
    return order, pred, tree_col, sign, root


def graph_kernel(A: sp.csc_matrix):
    """Fundamental cycles of a breadth-first spanning forest, or None if A is no incidence matrix."""
    m, n = A.shape
    inc = incidence(A)
    if inc is None or m == 0:
        return None
    head, tail = inc
    order, pred, tree_col, sign, _ = bfs_forest(head, tail, m)
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
