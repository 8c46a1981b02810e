"""Euclidean simplicial complexes: a pure simplicial complex with a discrete metric.

A discrete metric (seed, Definition 16) is one length per edge such that the metric form of
every top simplex is positive definite; it comes either from vertex positions in some R^d
(``d >= n``) or directly from edge lengths.  The real P1 finite-element matrices built here
(stiffness = cotangent Laplacian, mass) are what the bundle Laplacians reduce to at zero
curvature, and serve as references.
"""

from __future__ import annotations

from functools import cached_property
from itertools import combinations
from math import factorial
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMetricError, InvalidParameterError, NonFiniteError, NonManifoldError, ShapeError
from dhlb.geometry._small import soa_empty
from dhlb.geometry.simplex import SimplexStack
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.structure import subfaces

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["EuclideanComplex"]


class EuclideanComplex:
    """A pure n-dimensional simplicial complex with a Euclidean metric on every simplex.

    Parameters
    ----------
    complex : SimplicialComplex
        A pure complex of dimension ``n >= 0``.
    points : array (N, d), optional
        Vertex positions, ``d >= n``.  Row ``v`` belongs to the compact vertex ``v`` (the vertex
        with input label ``complex.vertex_labels[v]``); alternatively an array with one row per
        input label ``0 .. max label`` is accepted (rows of unused labels are ignored).
    edge_lengths : array (n_1,), optional
        One positive length per edge, in the row order of ``complex.simplices(1)``.
    rtol : float, optional
        A top simplex whose metric has ``λ_min/λ_max <= rtol`` counts as degenerate
        (default ``100 n eps``, see :func:`dhlb.geometry.simplex.default_rtol`).

    Raises
    ------
    NonFiniteError, ShapeError
        NaN/inf coordinates or lengths (the vertex or edge is named), wrong array shapes.
    InvalidMetricError
        Non-positive lengths, lengths violating a triangle inequality or not realizable on some
        top simplex (the simplices are listed by input labels), or not exactly one of
        ``points`` / ``edge_lengths`` given.
    DegenerateSimplexError
        Some top simplex has zero volume.
    NonManifoldError
        The complex is not pure.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.geometry import EuclideanComplex
    >>> X = SimplicialComplex([(0, 1, 2), (1, 2, 3)])
    >>> E = EuclideanComplex(X, points=[[0, 0], [1, 0], [0, 1], [1, 1]])
    >>> E.volumes(2).tolist(), float(E.volumes(1).sum().round(6))
    ([0.5, 0.5], 5.414214)
    >>> K = E.stiffness_matrix()
    >>> K.toarray().round(3)
    array([[ 1. , -0.5, -0.5,  0. ],
           [-0.5,  1. ,  0. , -0.5],
           [-0.5,  0. ,  1. , -0.5],
           [ 0. , -0.5, -0.5,  1. ]])
    >>> float(E.mass_matrix().sum())
    1.0
    """

    def __init__(
        self,
        complex: SimplicialComplex,
        points: ArrayLike | None = None,
        edge_lengths: ArrayLike | None = None,
        *,
        rtol: float | None = None,
    ):
        if not isinstance(complex, SimplicialComplex):
            raise TypeError(f"complex must be a dhlb.SimplicialComplex, got {type(complex).__name__}")
        if (points is None) == (edge_lengths is None):
            raise InvalidMetricError("give exactly one of points= (vertex positions) or edge_lengths= "
                                     "(one length per row of complex.simplices(1))")
        X = complex
        if not X.is_pure:
            k = next(k for k, s in enumerate(X.maximal_simplices()) if s.shape[0] and k < X.dim)
            bad = tuple(int(v) for v in X.vertex_labels[X.maximal_simplices()[k][0]])
            raise NonManifoldError(f"a Euclidean complex must be pure, but the {k}-simplex {bad} (input labels) "
                                   f"is a face of no {X.dim}-simplex; remove it or add the missing top simplices")
        self.complex = X
        self.dim = X.dim
        self._rtol = rtol
        self._points = None
        self._lengths = None
        if points is not None:
            self._points = self._parse_points(points)
        else:
            self._lengths = self._parse_lengths(edge_lengths)
        self._volumes: dict[int, np.ndarray] = {}
        self._faces: dict[int, np.ndarray] = {}
        self._top.check(labels=X.vertex_labels[X.simplices(self.dim)], what=f"{self.dim}-simplex")

    # ------------------------------------------------------------------ input
    def _parse_points(self, points) -> np.ndarray:
        X = self.complex
        P = np.asarray(points, dtype=float) if not isinstance(points, np.ndarray) else points.astype(float)
        labels = X.vertex_labels
        if P.ndim != 2:
            raise ShapeError(f"points must be a 2-D array (N, d), got shape {P.shape}")
        if P.shape[0] == X.n_vertices:
            rows_label = labels
        elif P.shape[0] == int(labels[-1]) + 1:
            P = P[labels]
            rows_label = labels
        else:
            raise ShapeError(f"points has {P.shape[0]} rows; expected one per vertex ({X.n_vertices}) "
                             f"or one per input label 0..{int(labels[-1])} ({int(labels[-1]) + 1})")
        if P.shape[1] < self.dim:
            raise ShapeError(f"a {self.dim}-dimensional complex needs points in R^d with d >= {self.dim}, "
                             f"got d = {P.shape[1]}")
        bad = ~np.all(np.isfinite(P), axis=1)
        if np.any(bad):
            v = np.nonzero(bad)[0]
            raise NonFiniteError(f"the position of vertex {int(rows_label[v[0]])} (input label) is not finite: "
                                 f"{P[v[0]].tolist()}" + (f" ({v.size} vertices affected)" if v.size > 1 else "")
                                 + "; give finite coordinates")
        P = np.ascontiguousarray(P)
        P.setflags(write=False)
        return P

    def _parse_lengths(self, edge_lengths) -> np.ndarray:
        X = self.complex
        L = np.asarray(edge_lengths, dtype=float).copy()
        n1 = X.n_simplices(1)
        if L.shape != (n1,):
            raise ShapeError(f"edge_lengths must have shape ({n1},) (one per row of complex.simplices(1)), "
                             f"got {L.shape}")
        edges = X.vertex_labels[X.simplices(1)]
        bad = ~np.isfinite(L)
        if np.any(bad):
            e = np.nonzero(bad)[0][0]
            raise NonFiniteError(f"the length of edge {tuple(int(v) for v in edges[e])} (input labels) is "
                                 f"{L[e]}; give finite lengths")
        if np.any(L <= 0):
            e = np.nonzero(L <= 0)[0][0]
            raise InvalidMetricError(f"the length of edge {tuple(int(v) for v in edges[e])} (input labels) is "
                                     f"{L[e]}; edge lengths must be > 0")
        L.setflags(write=False)
        return L

    # ------------------------------------------------------------------ per-simplex stacks
    def top_faces(self, k: int) -> np.ndarray:
        """Rows in ``complex.simplices(k)`` of the local k-faces of each top simplex, ``(m, C(n+1, k+1))``.

        Lexicographic local order (``dhlb.topology.structure.subfaces``), computed once per geometry.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> E = EuclideanComplex(SimplicialComplex([(0, 1, 2)]), points=[[0, 0], [1, 0], [0, 1]])
        >>> E.top_faces(1).tolist()
        [[0, 1, 2]]
        """
        if k not in self._faces:
            f = subfaces(self.complex, self.dim, k)
            f.setflags(write=False)
            self._faces[k] = f
        return self._faces[k]

    def _stack(self, k: int) -> SimplexStack:
        S = self.complex.simplices(k)
        if self._points is not None:
            return SimplexStack.from_points(self._points[S], rtol=self._rtol)
        L2 = soa_empty(S.shape[0], k + 1, k + 1)
        for a in range(k + 1):
            L2[:, a, a] = 0.0
        if k >= 1:
            ids = self.top_faces(1) if k == self.dim else subfaces(self.complex, k, 1)
            sq = self._lengths[ids] ** 2
            for p, (a, b) in enumerate(combinations(range(k + 1), 2)):
                L2[:, a, b] = L2[:, b, a] = sq[:, p]
        return SimplexStack._from_checked_lengths(L2, rtol=self._rtol)

    @cached_property
    def _top(self) -> SimplexStack:
        return self._stack(self.dim)

    # ------------------------------------------------------------------ public quantities
    @property
    def points(self) -> np.ndarray | None:
        """Vertex positions ``(N, d)`` in compact vertex order, or ``None`` if built from lengths."""
        return self._points

    @cached_property
    def edge_lengths(self) -> np.ndarray:
        """Length of each edge, in the row order of ``complex.simplices(1)``."""
        if self._lengths is not None:
            return self._lengths
        E = self.complex.simplices(1)
        L = np.linalg.norm(self._points[E[:, 1]] - self._points[E[:, 0]], axis=1)
        L.setflags(write=False)
        return L

    def volumes(self, k: int | None = None) -> np.ndarray:
        """k-volume of every k-simplex (default ``k = dim``); vertices have volume 1."""
        k = self.dim if k is None else int(k)
        if not 0 <= k <= self.dim:
            raise InvalidParameterError(f"volumes(k) needs 0 <= k <= dim = {self.dim}, got {k}")
        if k not in self._volumes:
            v = self._top.volumes if k == self.dim else self._stack(k).volumes
            v = np.array(v)
            v.setflags(write=False)
            self._volumes[k] = v
        return self._volumes[k]

    @cached_property
    def metric(self) -> np.ndarray:
        """Metric form of each top simplex in its edge basis ``p_a - p_0`` (sorted vertices), ``(m, n, n)``."""
        return self._top.metric

    @cached_property
    def metric_condition(self) -> np.ndarray:
        """Condition number ``λ_max/λ_min`` of the metric of each top simplex (a shape-quality measure)."""
        return self._top.condition_numbers

    @cached_property
    def barycentric_gradient_gram(self) -> np.ndarray:
        """``<∇λ_i, ∇λ_j>`` on each top simplex, ``(m, n+1, n+1)``, local order = sorted vertices."""
        return self._top.barycentric_gradient_gram

    @cached_property
    def cotan_weights(self) -> np.ndarray:
        """Local P1 stiffness ``c_ij = vol · <∇λ_i, ∇λ_j>`` per top simplex (Theorem 16), ``(m, n+1, n+1)``."""
        return self._top.cotan_weights

    @cached_property
    def dihedral_angles(self) -> np.ndarray:
        """Angle between the facets opposite local vertices ``i`` and ``j`` per top simplex, ``(m, n+1, n+1)``."""
        return self._top.dihedral_angles

    # ------------------------------------------------------------------ global matrices
    def _assemble(self, local: np.ndarray) -> sp.csr_matrix:
        S = self.complex.simplices(self.dim)
        N = self.complex.n_vertices
        n1 = self.dim + 1
        rows = np.broadcast_to(S[:, :, None], (S.shape[0], n1, n1)).ravel()
        cols = np.broadcast_to(S[:, None, :], (S.shape[0], n1, n1)).ravel()
        return sp.coo_matrix((local.ravel(), (rows, cols)), shape=(N, N)).tocsr()

    def stiffness_matrix(self) -> sp.csr_matrix:
        """Real P1 stiffness ``K_ij = ∫ <∇φ_i, ∇φ_j>`` (the cotangent Laplacian in weak form), csr, PSD.

        ``K @ 1 = 0``; the Dirichlet energy of a piecewise-linear function ``u`` is ``u @ K @ u``.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> E = EuclideanComplex(SimplicialComplex([(0, 1), (1, 2)]), points=[[0.0], [1.0], [3.0]])
        >>> E.stiffness_matrix().toarray()
        array([[ 1. , -1. ,  0. ],
               [-1. ,  1.5, -0.5],
               [ 0. , -0.5,  0.5]])
        """
        return self._assemble(self.cotan_weights)

    def mass_matrix(self, lumped: bool = False) -> sp.csr_matrix:
        """Real P1 mass ``M_ij = ∫ φ_i φ_j`` (csr, symmetric positive definite).

        Per top simplex ``∫ λ_i λ_j = vol (1 + δ_ij) / ((n+1)(n+2))``; ``lumped=True`` gives the
        diagonal matrix of row sums (``vol/(n+1)`` from each simplex at each of its vertices).

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> E = EuclideanComplex(SimplicialComplex([(0, 1)]), edge_lengths=[6.0])
        >>> E.mass_matrix().toarray()
        array([[2., 1.],
               [1., 2.]])
        >>> E.mass_matrix(lumped=True).diagonal()
        array([3., 3.])
        """
        n = self.dim
        vol = self.volumes(n)
        N = self.complex.n_vertices
        if lumped:
            S = self.complex.simplices(n)
            d = np.bincount(S.ravel(), weights=np.repeat(vol / (n + 1), n + 1), minlength=N)
            return sp.csr_matrix(sp.diags(d, format="csr"))
        ref = (np.ones((n + 1, n + 1)) + np.eye(n + 1)) * (factorial(n) / factorial(n + 2))
        return self._assemble(vol[:, None, None] * ref)

    def __repr__(self) -> str:
        src = "points" if self._points is not None else "edge_lengths"
        return f"EuclideanComplex(dim={self.dim}, counts={self.complex.counts}, from {src})"
