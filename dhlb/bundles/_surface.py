"""Fast ker ∂₂ for 2-complexes in which every edge has at most two triangles.

For such a complex an integer 2-cycle is constant up to sign on each dual-connected
component (triangles glued along edges with two cofaces), vanishes on components touching an
edge with a single triangle, and exists exactly on the closed *orientable* components, where
it is the orientation ``Σ o_t t`` (``o = +1`` on the component's first triangle, as in
``docs/conventions.md``).  Everything is vectorized: one BFS on the dual graph and pointer
jumping for the orientation signs, ``O(n log n)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from dhlb.topology.graph import bfs_forest, tree_accumulate

__all__ = ["SurfaceCycles", "surface_cycles"]

_SIGNS = np.array([1, -1, 1], dtype=np.int64)


@dataclass(frozen=True)
class SurfaceCycles:
    """Dual components of a (pseudo)surface and the integer basis of ker ∂₂.

    Attributes
    ----------
    component : (n_2,) int64, dual component of each triangle
    signs : (n_2,) int64, ±1 orientation propagated from the component's first triangle
    closed : (c,) bool, component has no edge with a single triangle
    orientable : (c,) bool, the propagated signs are consistent on every interior edge
    cycle_components : (ℓ,) int64, the closed orientable components (one basis cycle each)
    """

    component: np.ndarray
    signs: np.ndarray
    closed: np.ndarray
    orientable: np.ndarray
    cycle_components: np.ndarray

    def basis(self) -> sp.csc_matrix:
        """``(n_2, ℓ)`` integer basis of ker ∂₂ (column a: the fundamental cycle of component a)."""
        n2 = self.component.size
        rank = np.full(self.closed.size, -1, np.int64)
        rank[self.cycle_components] = np.arange(self.cycle_components.size)
        col = rank[self.component]
        keep = col >= 0
        return sp.csc_matrix(
            (self.signs[keep], (np.nonzero(keep)[0], col[keep])), shape=(n2, self.cycle_components.size), dtype=np.int64
        )


def surface_cycles(X) -> SurfaceCycles | None:
    """:class:`SurfaceCycles` of X, or None if some edge has three or more triangles (or dim != 2).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> S = surface_cycles(SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]))
    >>> S.basis().toarray().ravel().tolist()
    [1, -1, 1, -1]
    """
    if X.dim != 2:
        return None
    f = X.faces(2)
    n1, n2 = X.n_simplices(1), f.shape[0]
    flat = f.ravel()
    cnt = np.bincount(flat, minlength=n1)
    if np.any(cnt > 2):
        return None
    # the two incidences of each interior edge, without sorting: the last writer and the rest
    slots = np.arange(flat.size, dtype=np.int64)
    last = np.zeros(n1, np.int64)
    last[flat] = slots
    total = np.bincount(flat, weights=slots.astype(np.float64), minlength=n1).astype(np.int64)
    inner = np.nonzero(cnt == 2)[0]
    i2 = last[inner]
    i1 = total[inner] - i2
    t1, t2 = i1 // 3, i2 // 3
    rho = -_SIGNS[i1 % 3] * _SIGNS[i2 % 3]  # o_t2 = rho * o_t1 for a consistent orientation
    labels, roots, parent, order = bfs_forest(n2, t1, t2)
    ncomp = roots.size
    # sign of the link child -> parent: the edge of the child whose other triangle is the parent
    other = np.full(n1, -1, np.int64)
    other[inner] = t1 + t2  # other triangle = other[e] - this triangle
    rho_e = np.zeros(n1, np.int64)
    rho_e[inner] = rho
    child = np.nonzero(parent >= 0)[0]
    fc = f[child]
    col = np.argmax(other[fc] - child[:, None] == parent[child][:, None], axis=1)
    step = np.ones(n2, np.int64)
    step[child] = rho_e[fc[np.arange(child.size), col]]
    signs = tree_accumulate(parent, step, np.multiply, 1, order=order)
    bad_edge = signs[t2] != rho * signs[t1]
    orientable = np.ones(ncomp, bool)
    orientable[labels[t1[bad_edge]]] = False
    closed = np.ones(ncomp, bool)
    boundary_tris = np.nonzero((cnt == 1)[f].any(axis=1))[0]
    closed[labels[boundary_tris]] = False
    return SurfaceCycles(
        component=labels,
        signs=signs,
        closed=closed,
        orientable=orientable,
        cycle_components=np.nonzero(closed & orientable)[0].astype(np.int64),
    )
