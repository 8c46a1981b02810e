"""Discrete vector bundles with connection (seed part 3, §3–§4).

A rank-K bundle over a complex X stores one invertible K×K matrix per canonically oriented
edge ``i < j``: ``η_ij`` maps fibre coordinates at ``i`` to those at ``j`` (``v_j = η_ij v_i``);
``η_ji = η_ij⁻¹`` is implied.  A section is an array ``(n_0, K)``; it is parallel iff
``ψ_j = η_ij ψ_i`` on every edge.  Paths are sequences of compact vertex indices.

Examples
--------
>>> import numpy as np
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import VectorBundle
>>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])      # a circle
>>> R = np.array([[0., -1.], [1., 0.]])                  # quarter turn on edge (1, 2)
>>> E = VectorBundle(X, [np.eye(2), np.eye(2), R], metric=True)
>>> E.monodromy([0, 1, 2, 0]).round(12).tolist()          # η_20 η_12 η_01
[[0.0, -1.0], [1.0, 0.0]]
>>> E.parallel_sections().shape, E.is_trivial()
((3, 2, 0), False)
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles import paths
from dhlb.bundles._vector_bundle_checks import checked_transports
from dhlb.bundles.fields import field_ops
from dhlb.errors import InvalidConnectionError, NotAPathError
from dhlb.topology import graph
from dhlb.topology._names import simplex_name

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

    from dhlb.bundles.fields import ComplexOps, PrimeFieldOps, RealOps
    from dhlb.topology.complex import SimplicialComplex

__all__ = ["VectorBundle"]


class VectorBundle:
    """A discrete F-vector bundle of rank K with connection over a simplicial complex.

    Parameters
    ----------
    X : SimplicialComplex
    transports : array_like, shape (n_1, K, K) (or (n_1,) for rank 1)
        ``transports[e]`` is ``η_ij`` for the canonical edge ``e = (i < j)`` of ``X.simplices(1)``.
    field : ``"R"``, ``"C"`` or ``("GF", p)``
    metric : bool
        Euclidean / hermitian fibres: transports must be orthogonal / unitary (R or C only).
    atol : float
        Tolerance of the floating-point checks (unitarity, comparisons, numerical kernels).

    Raises
    ------
    InvalidConnectionError
        wrong shape, a singular transport, or (``metric=True``) a non-unitary one; the
        message names the edge.

    Examples
    --------
    >>> from dhlb.examples import torus
    >>> E = VectorBundle.trivial(torus(), 2)
    >>> E.rank, E.is_flat(), E.is_trivial(), E.parallel_sections().shape
    (2, True, True, (7, 2, 2))
    """

    def __init__(
        self,
        X: SimplicialComplex,
        transports: ArrayLike,
        field: str | tuple[str, int] = "R",
        *,
        metric: bool = False,
        atol: float = 1e-9,
    ):
        self._X = X
        self._ops = field_ops(field, atol)
        self._atol = float(atol)
        arr, inv = checked_transports(X, transports, self._ops, metric, atol)
        arr.setflags(write=False)
        inv.setflags(write=False)
        self._eta = arr
        self._eta_inv = inv
        self._metric = bool(metric)

    # ------------------------------------------------------------------ basic data
    @property
    def X(self) -> SimplicialComplex:
        """The base complex."""
        return self._X

    @property
    def rank(self) -> int:
        """The fibre dimension K."""
        return int(self._eta.shape[1])

    @property
    def field(self) -> str | tuple[str, int]:
        """The field specification: ``"R"``, ``"C"`` or ``("GF", p)``."""
        return self._ops.spec

    @property
    def ops(self) -> RealOps | ComplexOps | PrimeFieldOps:
        """The field operations object (see :mod:`dhlb.bundles.fields`)."""
        return self._ops

    @property
    def metric(self) -> bool:
        """True for Euclidean / hermitian bundles (orthogonal / unitary transports)."""
        return self._metric

    @property
    def atol(self) -> float:
        """The absolute tolerance of the floating-point comparisons (unused over GF(p))."""
        return self._atol

    @property
    def transports(self) -> np.ndarray:
        """``(n_1, K, K)`` read-only: ``η_ij`` per canonical edge ``i < j``."""
        return self._eta

    @property
    def inverse_transports(self) -> np.ndarray:
        """``(n_1, K, K)`` read-only: ``η_ji = η_ij⁻¹`` per canonical edge."""
        return self._eta_inv

    def _like(self, transports, metric=None) -> VectorBundle:
        metric = self._metric if metric is None else metric
        return VectorBundle(self._X, transports, self._ops.spec, metric=metric, atol=self._atol)

    def __repr__(self) -> str:
        return f"VectorBundle(rank={self.rank}, field={self.field!r}, metric={self._metric}, X={self._X!r})"

    @classmethod
    def trivial(
        cls,
        X: SimplicialComplex,
        rank: int,
        field: str | tuple[str, int] = "R",
        *,
        metric: bool = False,
        atol: float = 1e-9,
    ) -> VectorBundle:
        """The product bundle ``V × F^K`` with identity transports.

        Examples
        --------
        >>> from dhlb import SimplicialComplex
        >>> VectorBundle.trivial(SimplicialComplex([(0, 1, 2)]), 2).is_trivial()
        True
        """
        ops = field_ops(field, atol)
        eta = np.broadcast_to(ops.eye(rank), (X.n_simplices(1), rank, rank)).copy()
        return cls(X, eta, field, metric=metric, atol=atol)

    @classmethod
    def from_monodromy(
        cls,
        X: SimplicialComplex,
        matrices: ArrayLike,
        field: str | tuple[str, int] = "R",
        *,
        base: int | None = None,
        metric: bool = False,
        atol: float = 1e-9,
    ) -> VectorBundle:
        """The bundle of Theorem 2 (surjectivity) with monodromy representation ``matrices``.

        Its transports are the identity on a spanning forest and ``matrices[g]`` on the g-th
        non-tree edge, so its monodromy representation is exactly ``matrices``.

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb import SimplicialComplex
        >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
        >>> E = VectorBundle.from_monodromy(X, [[[2.0]]])
        >>> E.monodromy_representation().ravel().tolist()
        [2.0]
        """
        forest = graph.spanning_forest(X, base)
        ops = field_ops(field, atol)
        M = ops.asarray(np.asarray(matrices), "monodromy matrices")
        m = forest.nontree.size
        if M.ndim != 3 or M.shape[0] != m or M.shape[1] != M.shape[2]:
            raise InvalidConnectionError(f"need one K×K matrix per loop generator: shape ({m}, K, K), got {M.shape}")
        eta = np.broadcast_to(ops.eye(M.shape[1]), (X.n_simplices(1),) + M.shape[1:]).copy()
        eta[forest.nontree] = M
        return cls(X, eta, field, metric=metric, atol=atol)

    # ------------------------------------------------------------------ transport
    def _oriented(self, edges, forward) -> np.ndarray:
        return np.where(np.asarray(forward)[:, None, None], self._eta[edges], self._eta_inv[edges])

    def edge_transport(self, i: int, j: int) -> np.ndarray:
        """The matrix of ``η_ij`` for the oriented edge ``i → j`` (compact vertex indices)."""
        e, fwd = graph.path_edges(self._X, [i, j])
        return self._oriented(e, fwd)[0].copy()

    def transport(self, path: Sequence[int] | np.ndarray, v: ArrayLike) -> np.ndarray:
        """Parallel transport of ``v`` (shape (K,) or (K, m)) along a vertex path.

        Raises
        ------
        NotAPathError
            naming the first step that is not an edge.
        """
        e, fwd = graph.path_edges(self._X, path)
        ops = self._ops
        out = ops.asarray(np.asarray(v), "the vector")
        vec = out.ndim == 1
        if vec:
            out = out[:, None]
        if out.shape[0] != self.rank:
            raise InvalidConnectionError(f"the vector has {out.shape[0]} rows; the fibre has dimension {self.rank}")
        for M in self._oriented(e, fwd):
            out = ops.matmul(M, out)
        return out[:, 0] if vec else out

    def monodromy(self, loop: Sequence[int] | np.ndarray) -> np.ndarray:
        """``P_γ = η_{e_ℓ} ⋯ η_{e_1}`` around a closed path ``γ`` (first vertex = last vertex)."""
        loop = np.asarray(loop)
        if loop.ndim != 1 or loop.size < 1 or loop[0] != loop[-1]:
            raise NotAPathError(f"a loop must start and end at the same vertex, got {np.asarray(loop).tolist()!r}")
        return self.transport(loop, self._ops.eye(self.rank))

    # ------------------------------------------------------------------ monodromy
    @cached_property
    def forest(self) -> graph.SpanningForest:
        """The BFS spanning forest used for generators (roots: smallest vertex per component)."""
        return graph.spanning_forest(self._X)

    @cached_property
    def tree_transports(self) -> np.ndarray:
        """``(n_0, K, K)``: transport from the component root to each vertex along the forest."""
        return self._tree_transports(self.forest)

    def _tree_transports(self, T: graph.SpanningForest) -> np.ndarray:
        ops = self._ops
        K = self.rank
        n0 = self._X.n_vertices
        step = np.broadcast_to(ops.eye(K), (n0, K, K)).copy()
        child = np.nonzero(T.parent >= 0)[0]
        step[child] = self._oriented(T.parent_edge[child], T.parent[child] < child)
        return graph.tree_accumulate(T, step, ops.matmul, ops.eye(K))

    def loop_generators(self) -> np.ndarray:
        """Edge rows of the non-tree edges; edge ``(u, v)`` is the loop ``root → u → v → root``."""
        return self.forest.nontree

    def monodromy_representation(self, base: int | None = None) -> np.ndarray:
        """``(m, K, K)``: the monodromy ``T_v⁻¹ η_uv T_u`` of each loop generator (Prop. 5).

        ``base`` (a vertex) re-roots its component's spanning tree there; the generators are
        then the non-tree edges of ``spanning_forest(X, base)``.
        """
        T = self.forest if base is None else graph.spanning_forest(self._X, base)
        Tt = self.tree_transports if base is None else self._tree_transports(T)
        E = self._X.simplices(1)[T.nontree]
        Tinv, _ = self._ops.inv(Tt[E[:, 1]]) if T.nontree.size else (Tt[:0], None)
        return self._ops.matmul(Tinv, self._ops.matmul(self._eta[T.nontree], Tt[E[:, 0]]))

    def fundamental_group(self) -> paths.LoopGroupPresentation:
        """Presentation of π₁(X) at the forest roots: generators and triangle relators."""
        return paths.loop_group_presentation(self._X, self.forest)

    def triangle_monodromy(self) -> np.ndarray:
        """``(n_2, K, K)``: ``η_ca η_bc η_ab`` around each triangle ``a < b < c``, based at ``a``."""
        if self._X.dim < 2:
            return np.zeros((0, self.rank, self.rank), self._ops.dtype)
        f = self._X.faces(2)
        ops = self._ops
        return ops.matmul(self._eta_inv[f[:, 1]], ops.matmul(self._eta[f[:, 0]], self._eta[f[:, 2]]))

    def is_flat(self) -> bool:
        """True if the monodromy around every triangle is the identity."""
        H = self.triangle_monodromy()
        return bool(np.all(self._ops.close(H, self._ops.eye(self.rank))))

    def fundamental_group_representation(self) -> tuple[paths.LoopGroupPresentation, np.ndarray]:
        """The presentation of π₁ and the monodromy matrices of its generators (flat bundles only).

        Raises
        ------
        InvalidConnectionError
            if the connection is not flat (names a triangle with non-trivial monodromy):
            only then does the monodromy factor through π₁.
        """
        H = self.triangle_monodromy()
        ok = self._ops.close(H, self._ops.eye(self.rank))
        if not np.all(ok):
            t = int(np.argmin(ok))
            raise InvalidConnectionError(
                f"the connection is not flat: the monodromy around triangle {simplex_name(self._X, 2, t)} "
                "is not the identity, so it does not factor through π₁"
            )
        return self.fundamental_group(), self.monodromy_representation()

    # ------------------------------------------------------------------ parallel sections
    def _component_generators(self):
        T = self.forest
        E = self._X.simplices(1)
        comp = T.component[E[T.nontree, 0]] if T.nontree.size else np.zeros(0, np.int64)
        return comp

    def parallel_sections(self) -> np.ndarray:
        """A basis of the parallel sections as an array ``(n_0, K, d)`` (columns = sections).

        Each basis section is supported on one connected component: propagated along the
        spanning tree from a kernel vector of ``M_g − I`` over the generators g.
        """
        ops = self._ops
        K = self.rank
        T = self.forest
        M = self.monodromy_representation()
        comp_g = self._component_generators()
        Tt = self.tree_transports
        cols = []
        for c in range(T.n_components):
            Mc = M[comp_g == c]
            A = (Mc - ops.eye(K)).reshape(-1, K)
            if ops.exact:
                A = A % ops.p
            N = ops.nullspace(A)
            if N.shape[1] == 0:
                continue
            sec = np.zeros((self._X.n_vertices, K, N.shape[1]), ops.dtype)
            mask = T.component == c
            sec[mask] = ops.matmul(Tt[mask], N)
            cols.append(sec)
        if not cols:
            return np.zeros((self._X.n_vertices, K, 0), ops.dtype)
        return np.concatenate(cols, axis=2)

    def is_parallel(self, section: ArrayLike) -> bool:
        """True if ``section`` (shape (n_0, K)) satisfies ``ψ_j = η_ij ψ_i`` on every edge."""
        s = self._ops.asarray(np.asarray(section), "the section").reshape(self._X.n_vertices, self.rank, 1)
        E = self._X.simplices(1)
        moved = self._ops.matmul(self._eta, s[E[:, 0]])
        return bool(np.all(self._ops.close(moved, s[E[:, 1]])))

    def is_trivial(self) -> bool:
        """Proposition 1: trivial iff K linearly independent parallel sections (per component)."""
        T = self.forest
        P = self.parallel_sections()
        if P.shape[2] == 0:
            return False
        support = np.array([T.component[np.nonzero(np.any(P[:, :, j] != 0, axis=1))[0][0]] for j in range(P.shape[2])])
        counts = np.bincount(support, minlength=T.n_components)
        return bool(np.all(counts == self.rank))

    # ------------------------------------------------------------------ algebra (functions in morphisms.py)
    def gauge(self, g: ArrayLike) -> VectorBundle:
        """The bundle ``η'_ij = g_j η_ij g_i⁻¹`` (``g`` is an isomorphism onto it).

        See :func:`dhlb.bundles.morphisms.gauge`.
        """
        ops = self.ops
        G = _vertex_matrices(self, g, "the gauge transformation")
        Ginv, bad = ops.inv(G)
        if np.any(bad):
            v = int(np.argmax(bad))
            raise InvalidConnectionError(
                f"the gauge transformation is singular at vertex {int(self.X.vertex_labels[v])}"
            )
        Ed = self.X.simplices(1)
        eta = ops.matmul(G[Ed[:, 1]], ops.matmul(self.transports, Ginv[Ed[:, 0]]))
        metric = self.metric and bool(np.all(ops.unitary_defect(G) <= 10 * self.atol))
        return VectorBundle(self.X, eta, self.field, metric=metric, atol=self.atol)

    def direct_sum(self, other: VectorBundle) -> VectorBundle:
        """The direct sum ``E ⊕ F``; see :func:`dhlb.bundles.morphisms.direct_sum`."""
        _check_pair(self, other)
        n1, a, b = self.X.n_simplices(1), self.rank, other.rank
        eta = np.zeros((n1, a + b, a + b), self.ops.dtype)
        eta[:, :a, :a] = self.transports
        eta[:, a:, a:] = other.transports
        return VectorBundle(self.X, eta, self.field, metric=self.metric and other.metric, atol=self.atol)

    def tensor(self, other: VectorBundle) -> VectorBundle:
        """The tensor product ``E ⊗ F``; see :func:`dhlb.bundles.morphisms.tensor`."""
        _check_pair(self, other)
        eta = _kron(self.transports, other.transports)
        if self.ops.exact:
            eta = eta % self.ops.p
        return VectorBundle(self.X, eta, self.field, metric=self.metric and other.metric, atol=self.atol)

    def dual(self) -> VectorBundle:
        """The dual bundle ``E*``; see :func:`dhlb.bundles.morphisms.dual`."""
        eta = np.swapaxes(self.inverse_transports, 1, 2)
        return VectorBundle(self.X, eta, self.field, metric=self.metric, atol=self.atol)


def _vertex_matrices(E: VectorBundle, g, what: str) -> np.ndarray:
    n0, K = E.X.n_vertices, E.rank
    arr = np.asarray(g)
    if arr.ndim == 1 and arr.shape[0] == n0 and K == 1:
        arr = arr.reshape(n0, 1, 1)
    if arr.shape != (n0, K, K):
        raise InvalidConnectionError(f"{what} must have shape (n_0, K, K) = ({n0}, {K}, {K}), got {np.shape(g)}")
    return E.ops.asarray(arr, what)


def _check_pair(E: VectorBundle, F: VectorBundle, same_rank: bool = False) -> None:
    if not (isinstance(E, VectorBundle) and isinstance(F, VectorBundle)):
        raise InvalidConnectionError(
            "expected two VectorBundle objects (for hermitian line bundles use "
            "HermitianLineBundle.find_isomorphism or .vector_bundle())"
        )
    if E.X is not F.X and E.X != F.X:
        raise InvalidConnectionError("the two bundles live over different complexes")
    if E.ops.name != F.ops.name:
        raise InvalidConnectionError(f"the two bundles have different fields: {E.field!r} and {F.field!r}")
    if same_rank and E.rank != F.rank:
        raise InvalidConnectionError(f"the two bundles have different ranks: {E.rank} and {F.rank}")


def _kron(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    n, a, _ = A.shape
    b = B.shape[1]
    return np.einsum("eij,ekl->eikjl", A, B).reshape(n, a * b, a * b)
