"""Vertex fans of an oriented triangle mesh, vectorized (no loop over vertices or faces).

Corner ``c = 3 f + p`` is the corner of face ``f`` at vertex ``v = F[f, p]``; it spans the angle
from its *first edge* ``v → F[f, p+1]`` to its *second edge* ``v → F[f, p+2]``, counterclockwise
for the mesh orientation. The next corner counterclockwise around ``v`` is the one whose first
edge is this corner's second edge. Around an interior vertex the corners form a cycle, around a
boundary vertex a chain starting at the corner whose first edge is a boundary edge. Prefix sums
of the corner angles along each fan are computed by pointer jumping (``O(log degree)`` rounds).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dhlb.errors import NonManifoldError
from dhlb.topology._keys import argsort_keys

__all__ = ["AngleMap", "Fans", "halfedge_pairs", "vertex_fans"]

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class Fans:
    """Corner chains around the vertices (compact numbering, corners ``3 f + p``)."""

    vertex: np.ndarray  # (3m,) vertex of each corner
    first: np.ndarray  # (3m,) target of the first edge
    second: np.ndarray  # (3m,) target of the second edge
    succ: np.ndarray  # (3m,) next corner counterclockwise, -1 at the end of a chain
    twin: np.ndarray  # (3m,) corner whose first edge is the reverse of this first edge, -1 on the boundary
    start: np.ndarray  # (N,) first corner of each fan (the reference edge is its first edge)
    boundary: np.ndarray  # (N,) bool
    prefix: np.ndarray  # (3m,) Euclidean angle from the reference edge to the first edge of the corner
    rank: np.ndarray  # (3m,) position of the corner in its fan
    total: np.ndarray  # (N,) Θ_v, the sum of the corner angles at v
    count: np.ndarray  # (N,) number of corners at v
    last: np.ndarray  # (N,) last corner of each fan


def halfedge_pairs(F: np.ndarray, n_vertices: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Twins and edges of the half-edges ``h = 3 f + k`` (``F[f, k] → F[f, k+1]``) by one sort.

    Returns ``(twin, edge, n_edges)``: ``twin[h]`` the opposite half-edge (``-1`` on the
    boundary) and ``edge[h]`` the row of the undirected edge in lexicographic order (the order of
    ``SimplicialComplex.simplices(1)`` when the vertices are numbered ``0 .. n-1``). Raises
    :class:`~dhlb.errors.NonManifoldError` for an edge with three or more faces or two faces
    traversing it in the same direction.

    Examples
    --------
    >>> twin, edge, ne = halfedge_pairs(np.array([[0, 1, 2], [2, 1, 3]]), 4)
    >>> twin.tolist(), edge.tolist(), ne
    ([-1, 3, -1, 1, -1, -1], [0, 2, 1, 2, 3, 4], 5)
    """
    N = max(int(n_vertices), 1)
    a = F.ravel()
    b = np.roll(F, -1, axis=1).ravel()
    key = np.minimum(a, b) * N + np.maximum(a, b)
    order = argsort_keys(key, N * N)
    sk = key[order]
    same = sk[1:] == sk[:-1]
    if same.size > 1 and np.any(same[1:] & same[:-1]):
        i = int(np.argmax(same[1:] & same[:-1]))
        raise NonManifoldError(f"the edge ({int(a[order[i]])}, {int(b[order[i]])}) (compact numbers) lies in three "
                               "or more faces; validate the mesh with dhlb.mesh.validate_surface")
    new = np.r_[True, ~same]
    edge = np.empty(a.size, np.int64)
    edge[order] = np.cumsum(new) - 1
    twin = np.full(a.size, -1, np.int64)
    i = np.nonzero(same)[0]
    h0, h1 = order[i], order[i + 1]
    if np.any(a[h0] == a[h1]):
        j = int(np.argmax(a[h0] == a[h1]))
        raise NonManifoldError(f"two faces traverse the edge ({int(a[h0[j]])}, {int(b[h0[j]])}) (compact numbers) in "
                               "the same direction (inconsistent orientation); validate the mesh with "
                               "dhlb.mesh.validate_surface")
    twin[h0], twin[h1] = h1, h0
    return twin, edge, int(new.sum())


def vertex_fans(F: np.ndarray, n_vertices: int, alpha: np.ndarray, pairs=None) -> Fans:
    """Fans of the consistently oriented manifold mesh F with corner angles ``alpha`` (m, 3).

    ``pairs`` is the output of :func:`halfedge_pairs` if already computed.
    """
    N = int(n_vertices)
    v = F.ravel()
    a = np.roll(F, -1, axis=1).ravel()
    b = np.roll(F, -2, axis=1).ravel()
    twin = (pairs if pairs is not None else halfedge_pairs(F, N))[0]
    # corner c = half-edge c (its first edge); its second edge v → b reverses the half-edge b → v of the
    # same face, whose twin is the first edge of the next corner counterclockwise
    prev = np.arange(v.size).reshape(-1, 3)[:, [2, 0, 1]].ravel()
    succ = twin[prev]
    nc = v.size
    pred = np.full(nc, -1, np.int64)
    has = succ >= 0
    pred[succ[has]] = np.nonzero(has)[0]
    start = np.full(N, nc, np.int64)
    np.minimum.at(start, v, np.arange(nc, dtype=np.int64))
    heads = np.nonzero(pred < 0)[0]
    boundary = np.zeros(N, bool)
    boundary[v[heads]] = True
    start[v[heads]] = heads
    inner = np.nonzero(~boundary)[0]
    succ = succ.copy()
    succ[pred[start[inner]]] = -1  # cut each cycle before its start corner
    val = alpha.ravel().astype(np.float64).copy()
    cnt = np.ones(nc, np.int64)
    nxt = succ.copy()
    act = np.nonzero(nxt >= 0)[0]
    for _ in range(int(np.ceil(np.log2(nc + 1))) + 1):  # pointer jumping: suffix sums along each chain
        if act.size == 0:
            break
        j = nxt[act]
        val[act] = val[act] + val[j]
        cnt[act] = cnt[act] + cnt[j]
        j = nxt[j]
        nxt[act] = j
        act = act[j >= 0]  # the corners whose chain goes on
    total = val[start]
    count = cnt[start]
    per_vertex = np.bincount(v, minlength=N)
    if np.any(per_vertex != count) or np.any(nxt >= 0):  # a second fan (a cycle left uncut) at some vertex
        bad = int(np.argmax(per_vertex != count)) if np.any(per_vertex != count) else int(v[np.argmax(nxt >= 0)])
        raise NonManifoldError(f"the faces at vertex {bad} (compact number) do not form one fan; "
                               "validate the mesh with dhlb.mesh.validate_surface")
    last = np.full(N, -1, np.int64)
    ends = np.nonzero(succ < 0)[0]
    last[v[ends]] = ends
    return Fans(v, a, b, succ, twin, start, boundary, total[v] - val, count[v] - cnt, total, count, last)


class AngleMap:
    """Piecewise-linear map between rescaled angles θ at a vertex and polar angles ψ in its tangent plane.

    At vertex v the breakpoints are the edges of the fan: an edge with rescaled angle θ_e (see
    :mod:`dhlb.mesh.tangent`) maps to the polar angle ψ_e of its projection onto the plane
    orthogonal to the vertex normal, measured from the projected reference edge. Between two
    edges the map is linear; at a boundary vertex the gap from the last boundary edge to
    ``θ = 2π`` maps linearly onto the remaining polar angles. Edges map exactly, and the map is
    a bijection of the circle. Where the projected fan does not wind once around the normal
    (extreme saddles, edges parallel to the normal, boundary vertices with Θ ≥ 2π) the vertex
    falls back to ``ψ = θ``.
    """

    def __init__(self, vertex, theta, psi, n_vertices: int):
        N = int(n_vertices)
        if not (np.all(vertex[1:] >= vertex[:-1]) and np.all((theta[1:] >= theta[:-1]) | (vertex[1:] != vertex[:-1]))):
            order = np.lexsort((theta, vertex))
            vertex, theta, psi = vertex[order], theta[order], psi[order]
        nxt_same = np.r_[vertex[1:] == vertex[:-1], False]
        ok_step = (theta[1:] > theta[:-1]) & (psi[1:] > psi[:-1])
        bad = np.zeros(N, bool)
        bad[vertex[:-1][nxt_same[:-1] & ~ok_step]] = True
        starts = np.r_[True, ~nxt_same[:-1]]
        bad[vertex[starts & ((theta != 0) | (psi != 0))]] = True
        ends = ~nxt_same
        bad[vertex[ends & ((theta != TWO_PI) | (psi != TWO_PI))]] = True
        self.fallback = bad
        keep = ~bad[vertex]
        self._t, self._p = theta[keep], psi[keep]
        self._offsets = np.searchsorted(vertex[keep], np.arange(N + 1))

    @classmethod
    def from_offsets(cls, offsets: np.ndarray, theta: np.ndarray, psi: np.ndarray) -> AngleMap:
        """The map with the breakpoints of vertex v at ``offsets[v] : offsets[v + 1]`` (vertices in order).

        The same map as ``AngleMap(np.repeat(np.arange(N), np.diff(offsets)), theta, psi, N)``, without
        the vertex of each breakpoint when the angles of every vertex are already in increasing order.
        """
        N = offsets.size - 1
        if offsets[0] != 0 or np.any(offsets[1:] <= offsets[:-1]):
            return cls(np.repeat(np.arange(N), np.diff(offsets)), theta, psi, N)
        inner = np.ones(theta.size - 1, bool)  # breakpoint i and i + 1 belong to the same vertex
        inner[offsets[1:-1] - 1] = False
        up = theta[1:] >= theta[:-1]
        if not np.all(up | ~inner):
            return cls(np.repeat(np.arange(N), np.diff(offsets)), theta, psi, N)
        np.greater(theta[1:], theta[:-1], out=up)
        up &= psi[1:] > psi[:-1]
        bad_step = np.nonzero(inner & ~up)[0]
        first, last = offsets[:-1], offsets[1:] - 1
        bad = (theta[first] != 0) | (psi[first] != 0) | (theta[last] != TWO_PI) | (psi[last] != TWO_PI)
        bad[np.searchsorted(offsets, bad_step, side="right") - 1] = True
        self = cls.__new__(cls)
        self.fallback = bad
        if not np.any(bad):
            self._t, self._p, self._offsets = theta, psi, offsets
            return self
        size = np.where(bad, 0, np.diff(offsets))
        keep = np.repeat(~bad, np.diff(offsets))
        self._t, self._p = theta[keep], psi[keep]
        self._offsets = np.zeros(N + 1, np.int64)
        np.cumsum(size, out=self._offsets[1:])
        return self

    def _apply(self, vertex, x, src, dst) -> np.ndarray:
        vertex = np.asarray(vertex, np.int64)
        x = np.mod(np.asarray(x, np.float64), TWO_PI)
        x[x >= TWO_PI] = 0.0
        use = ~self.fallback[vertex]
        if not np.any(use) or self._t.size == 0:
            return x
        out = x
        qv, qx = (vertex, x) if use.all() else (vertex[use], x[use])
        lo, hi = self._offsets[qv], self._offsets[qv + 1] - 1  # src[lo] = 0 <= x < src[hi] = 2π
        # bisection inside each vertex's breakpoints (sorted, strictly increasing), all queries in step:
        # once hi = lo + 1, mid = lo and src[lo] <= x keep the bracket fixed
        mid, go, val = np.empty_like(lo), np.empty(lo.size, bool), np.empty(lo.size)
        for _ in range(int(np.max(hi - lo)).bit_length()):
            np.add(lo, hi, out=mid)
            mid >>= 1
            np.less_equal(np.take(src, mid, out=val), qx, out=go)
            np.copyto(lo, mid, where=go)
            np.logical_not(go, out=go)
            np.copyto(hi, mid, where=go)
        hi = lo + 1
        x0, x1, y0, y1 = src[lo], src[hi], dst[lo], dst[hi]
        out[use] = y0 + (qx - x0) * (y1 - y0) / (x1 - x0)
        return out

    def to_polar(self, vertex, theta) -> np.ndarray:
        """ψ for rescaled angles θ at the given vertices (values in [0, 2π))."""
        return self._apply(vertex, theta, self._t, self._p)

    def to_rescaled(self, vertex, psi) -> np.ndarray:
        """θ for polar angles ψ at the given vertices (values in [0, 2π))."""
        return self._apply(vertex, psi, self._p, self._t)
