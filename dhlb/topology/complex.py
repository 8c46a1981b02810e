"""Abstract simplicial complexes of any dimension: storage, look-up, boundary maps.

The structural operations (star, link, skeleta, components, subdivision) live in
:mod:`dhlb.topology.structure`, the manifold checks in :mod:`dhlb.topology.manifold`,
orientations in :mod:`dhlb.topology.orientation`, integer homology in :mod:`dhlb.topology.homology`;
:class:`SimplicialComplex` exposes them as methods. Face tables, boundary matrices and the
vertex-adjacency pattern are computed in the private module ``dhlb.topology._incidence``.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidParameterError, InvalidSimplexError, SimplexNotFoundError
from dhlb.topology import _graphs, _incidence, _keys
from dhlb.topology._incidence import VertexAdjacency
from dhlb.topology._input import parse_rows, parse_simplices
from dhlb.topology.cliques import maximal_cliques

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

    from numpy.typing import ArrayLike

__all__ = ["SimplicialComplex", "VertexAdjacency"]


def _compact_labels(blocks: dict) -> tuple[np.ndarray, dict]:
    """The sorted vertex labels in use and the blocks renumbered ``0 .. n-1`` (a table look-up when dense)."""
    flat = np.concatenate([b.ravel() for b in blocks.values()])
    lo, hi = int(flat.min()), int(flat.max())
    if lo >= 0 and hi < 4 * flat.size + 1024:  # dense labels: counting instead of sorting
        used = np.bincount(flat, minlength=hi + 1) > 0
        labels = np.nonzero(used)[0].astype(flat.dtype)
        lut = np.cumsum(used) - 1
        return labels, {k: lut[b].astype(np.int64) for k, b in blocks.items()}
    labels = np.unique(flat)
    return labels, {k: np.searchsorted(labels, b).astype(np.int64) for k, b in blocks.items()}


class SimplicialComplex:
    """A finite abstract simplicial complex, closed under taking faces.

    Parameters
    ----------
    simplices : iterable of vertex tuples, int array of shape (m, k+1), or list of such arrays
        The generating simplices (mixed dimensions allowed; a list of 2-d arrays is the fast
        way to pass several dimensions at once). All their faces are added.
        Vertex labels are non-negative integers; they are compacted to ``0 .. N-1`` in
        increasing order and the input labels are kept in :attr:`vertex_labels`.

    Notes
    -----
    The k-simplices are stored as sorted rows in lexicographic order (see
    ``docs/conventions.md``); the row number is the simplex's index everywhere.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (2, 3)])
    >>> X.counts
    (4, 4, 1)
    >>> X.simplices(1)
    array([[0, 1],
           [0, 2],
           [1, 2],
           [2, 3]])
    >>> X.boundary(2).toarray().ravel().tolist()
    [1, -1, 1, 0]
    >>> X.euler_characteristic
    1
    """

    def __init__(self, simplices: Iterable[Sequence[int]] | ArrayLike):
        blocks = parse_simplices(simplices)
        labels, blocks = _compact_labels(blocks)
        self._labels = labels
        self._labels.setflags(write=False)
        n = labels.size
        self._n = n
        self._dim = max(blocks)
        self._rows: list[np.ndarray] = [np.arange(n, dtype=np.int64).reshape(-1, 1)]
        self._key_list: list[np.ndarray] = [np.arange(n, dtype=np.int64)]
        for k in range(1, self._dim + 1):
            cands = []
            for m, block in blocks.items():
                if m < k:
                    continue
                if m == k:
                    cands.append(block)
                    continue
                for cols in _keys.combination_columns(m + 1, k + 1):
                    cands.append(block[:, cols])
            cand = np.concatenate(cands) if len(cands) > 1 else cands[0]
            ukeys = np.sort(self._key_of(k, cand))  # (np.unique hashes, which is slower here)
            self._append_keys(ukeys[np.r_[True, ukeys[1:] != ukeys[:-1]]])
        self._rows[0].setflags(write=False)

    def _append_keys(self, ukeys: np.ndarray) -> None:
        """Add the next dimension k from its sorted, distinct keys ``prefix row * n + last vertex``."""
        k, n = len(self._rows), self._n
        rows = np.empty((ukeys.size, k + 1), np.int64)  # decode the keys
        prefix, rows[:, k] = np.divmod(ukeys, n)
        rows[:, :k] = prefix[:, None] if k == 1 else self._rows[k - 1][prefix]
        rows.setflags(write=False)
        self._rows.append(rows)
        self._key_list.append(ukeys)

    @classmethod
    def _from_keys(cls, labels: np.ndarray, keys: list[np.ndarray], top_faces: np.ndarray | None = None
                   ) -> SimplicialComplex:
        """The complex on the sorted vertex ``labels`` whose k-simplices have the keys ``keys[k - 1]``.

        For callers that already sorted the simplices (:func:`dhlb.mesh.validate_surface` gets the edges
        and triangles of a surface from its half-edges): the keys of each dimension must be sorted and
        distinct, ``prefix row * n + last vertex`` as in the constructor (:meth:`_key_of`), and the
        complex closed under faces; nothing is checked. ``top_faces``, if given, is :meth:`faces` of the
        top dimension (at least 2; the lower ones are computed when asked for).
        """
        X = cls.__new__(cls)
        X._labels = np.asarray(labels)
        X._labels.setflags(write=False)
        X._n = int(labels.size)
        X._dim = len(keys)
        X._rows = [np.arange(X._n, dtype=np.int64).reshape(-1, 1)]
        X._key_list = [np.arange(X._n, dtype=np.int64)]
        for ukeys in keys:
            X._append_keys(ukeys)
        X._rows[0].setflags(write=False)
        if top_faces is not None:
            faces = _incidence.face_tables(X._rows[:-1], X._key_list[:-1], X._n, X._row_index)
            top_faces.setflags(write=False)
            X.__dict__["_faces"] = {**faces, X._dim: top_faces}
        return X

    # ------------------------------------------------------------------ keys and look-up
    def _key_of(self, k: int, rows: np.ndarray) -> np.ndarray:
        """Keys of sorted k-rows whose (k-1)-prefix faces are in the complex."""
        if k <= 1:
            return _keys.row_keys(rows, None, self._n)
        prefix = self._row_index(k - 1, rows[:, :k])
        return prefix * self._n + rows[:, k]

    def _row_index(self, k: int, rows: np.ndarray, missing: str = "raise") -> np.ndarray:
        """Row indices of sorted k-rows (compact labels); -1 for missing if ``missing='mark'``."""
        if k == 0:
            return rows[:, 0].astype(np.int64)
        if k == 1:
            keys = rows[:, 0] * self._n + rows[:, 1]
        else:
            prefix = self._row_index(k - 1, rows[:, :k], missing="mark")
            keys = np.where(prefix >= 0, prefix * self._n + rows[:, k], -1)
        pos, found = _keys.lookup(self._key_list[k], keys)
        if missing == "mark":
            return np.where(found, pos, -1)
        if not np.all(found):
            bad = rows[np.argmin(found)]
            shown = tuple(int(v) for v in self._labels[bad])
            raise SimplexNotFoundError(f"the {k}-simplex {shown} (input labels) is not in the complex")
        return pos

    def _compact_rows(self, rows, k: int | None) -> tuple[np.ndarray, np.ndarray]:
        """Validated rows in compact labels (sorted) and the original row parity."""
        arr = parse_rows(rows, k)
        if arr.shape[0] == 0:
            return arr.reshape(0, arr.shape[1] if arr.ndim == 2 else 0), np.zeros(0, np.int64)
        srt = np.sort(arr, axis=1)
        if srt.shape[1] > 1 and np.any(srt[:, 1:] == srt[:, :-1]):
            bad = arr[np.nonzero(np.any(srt[:, 1:] == srt[:, :-1], axis=1))[0][0]]
            raise InvalidSimplexError(f"the simplex {tuple(int(v) for v in bad)} repeats a vertex")
        return srt, _keys.permutation_parity(arr)

    def _labels_to_compact(self, srt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        pos, found = _keys.lookup(self._labels, srt.ravel())
        return pos.reshape(srt.shape), found.reshape(srt.shape).all(axis=1)

    def index(self, k: int, rows: ArrayLike) -> np.ndarray:
        """Row indices in :meth:`simplices` of k-simplices given by input vertex labels.

        The vertices of each row may be in any order.

        Examples
        --------
        >>> X = SimplicialComplex([(0, 1, 2)])
        >>> X.index(1, [(2, 1), (0, 1)]).tolist()
        [2, 0]
        """
        srt, _ = self._compact_rows(rows, k)
        if srt.shape[0] == 0:
            return np.zeros(0, np.int64)
        if k > self._dim:
            raise SimplexNotFoundError(f"the complex has dimension {self._dim}; it has no {k}-simplices")
        comp, ok = self._labels_to_compact(srt)
        if not np.all(ok):
            bad = srt[np.argmin(ok)]
            raise SimplexNotFoundError(
                f"the {k}-simplex {tuple(int(v) for v in bad)} is not in the complex (unknown vertex)"
            )
        return self._row_index(k, comp)

    def contains(self, k: int, rows: ArrayLike) -> np.ndarray:
        """Boolean mask: which of the given k-simplices (input labels) belong to the complex."""
        srt, _ = self._compact_rows(rows, k)
        if srt.shape[0] == 0 or k > self._dim:
            return np.zeros(srt.shape[0], bool)
        comp, ok = self._labels_to_compact(srt)
        out = np.zeros(srt.shape[0], bool)
        if np.any(ok):
            out[ok] = self._row_index(k, comp[ok], missing="mark") >= 0
        return out

    @staticmethod
    def orientation_of(rows: ArrayLike) -> np.ndarray:
        """+1/-1 per row: the orientation of the vertex order relative to the canonical (sorted) one.

        Examples
        --------
        >>> SimplicialComplex.orientation_of([(0, 1, 2), (1, 0, 2), (2, 0, 1)]).tolist()
        [1, -1, 1]
        """
        arr = parse_rows(rows)
        return _keys.permutation_parity(arr)

    # ------------------------------------------------------------------ basic data
    @property
    def dim(self) -> int:
        """Dimension: the largest k with a k-simplex."""
        return self._dim

    @property
    def n_vertices(self) -> int:
        """Number of vertices N (they are labelled ``0 .. N-1`` internally)."""
        return self._n

    @property
    def vertex_labels(self) -> np.ndarray:
        """Input label of each compact vertex, increasing (read-only)."""
        return self._labels

    def simplices(self, k: int) -> np.ndarray:
        """The k-simplices as sorted rows in lexicographic order, shape ``(n_k, k+1)`` (read-only)."""
        if k < 0:
            raise ValueError(f"k must be non-negative, got {k}")
        if k > self._dim:
            return np.zeros((0, k + 1), np.int64)
        return self._rows[k]

    def n_simplices(self, k: int) -> int:
        """Number of k-simplices (0 above the dimension)."""
        return 0 if k > self._dim or k < 0 else self._rows[k].shape[0]

    @property
    def counts(self) -> tuple[int, ...]:
        """``(n_0, ..., n_dim)``."""
        return tuple(r.shape[0] for r in self._rows)

    @cached_property
    def euler_characteristic(self) -> int:
        """χ = Σ_k (−1)^k n_k."""
        return int(sum((-1) ** k * c for k, c in enumerate(self.counts)))

    # ------------------------------------------------------------------ incidence
    def faces(self, k: int) -> np.ndarray:
        """Shape ``(n_k, k+1)``: row in ``simplices(k-1)`` of the face omitting vertex ``i``."""
        if k < 1 or k > self._dim:
            raise ValueError(f"faces(k) needs 1 <= k <= dim = {self._dim}, got {k}")
        return self._faces[k]

    @cached_property
    def _faces(self) -> dict[int, np.ndarray]:
        return _incidence.face_tables(self._rows, self._key_list, self._n, self._row_index)

    def boundary(self, k: int) -> sp.csr_matrix:
        """∂_k as an integer sparse matrix of shape ``(n_{k-1}, n_k)``, entries ``(−1)^i``.

        Examples
        --------
        >>> X = SimplicialComplex([(0, 1, 2, 3)])
        >>> d2, d3 = X.boundary(2), X.boundary(3)
        >>> int(abs(d2 @ d3).sum())
        0
        """
        if k < 0 or k > self._dim + 1:
            raise ValueError(f"boundary(k) needs 0 <= k <= dim + 1 = {self._dim + 1}, got {k}")
        return self._boundaries[k]

    def coboundary(self, k: int) -> sp.csr_matrix:
        """d_k = ∂_{k+1}ᵀ, shape ``(n_{k+1}, n_k)``."""
        return self.boundary(k + 1).T.tocsr()

    @cached_property
    def _boundaries(self) -> list[sp.csr_matrix]:
        return _incidence.boundary_matrices(self._faces, self.counts)

    @cached_property
    def vertex_adjacency(self) -> VertexAdjacency:
        """CSR pattern of the vertex adjacency (diagonal + both directions of every edge).

        Operators on vertex functions (mass, Laplacians) share this pattern; ``upper[e]`` and
        ``lower[e]`` are the data positions of the entries ``(i, j)`` and ``(j, i)`` of the
        canonical edge ``e = (i < j)``, ``diagonal[v]`` that of ``(v, v)``.

        Examples
        --------
        >>> adj = SimplicialComplex([(0, 1, 2)]).vertex_adjacency
        >>> adj.indptr.tolist(), adj.indices.tolist(), adj.upper.tolist()
        ([0, 3, 6, 9], [0, 1, 2, 0, 1, 2, 0, 1, 2], [1, 2, 5])
        """
        E = self._rows[1] if self._dim >= 1 else np.zeros((0, 2), np.int64)
        return _incidence.vertex_adjacency(self._n, E)

    @cached_property
    def top_entry_positions(self) -> np.ndarray:
        """Data positions in :attr:`vertex_adjacency` of the local entries of each top simplex.

        Shape ``(n_top, k, k)``, ``k = dim + 1``: the position of the entry ``(v_b, v_a)`` for the
        local vertices ``a, b`` of each top simplex ``v = simplices(dim)[s]``.

        Summing per-simplex local matrices into a global vertex operator is one ``bincount``.
        """
        return _incidence.top_entry_positions(self, self.vertex_adjacency)

    def maximal_simplices(self) -> list[np.ndarray]:
        """For each k, the k-simplices that are faces of no (k+1)-simplex."""
        return _incidence.maximal_rows(self._rows, self._faces)

    @property
    def is_pure(self) -> bool:
        """True if every maximal simplex has dimension :attr:`dim`."""
        return all(m.shape[0] == 0 for m in self.maximal_simplices()[:-1])

    # ------------------------------------------------------------------ delegated operations
    # Implemented in sibling modules (one room per concern); these are thin entry points.
    def skeleton(self, k: int) -> SimplicialComplex:
        """The k-skeleton: all simplices of dimension <= k (see :func:`dhlb.topology.structure.skeleton`)."""
        from dhlb.topology.structure import skeleton

        return skeleton(self, k)

    def star(self, k: int, index: int) -> list[np.ndarray]:
        """Star of the k-simplex with row ``index`` (see :func:`dhlb.topology.structure.star`)."""
        from dhlb.topology.structure import star

        return star(self, k, index)

    def link(self, k: int, index: int) -> SimplicialComplex | None:
        """Link of the k-simplex with row ``index`` (see :func:`dhlb.topology.structure.link`)."""
        from dhlb.topology.structure import link

        return link(self, k, index)

    def connected_components(self) -> tuple[int, np.ndarray]:
        """Component label per vertex (see :func:`dhlb.topology.structure.connected_components`)."""
        from dhlb.topology.structure import connected_components

        return connected_components(self)

    def boundary_complex(self) -> SimplicialComplex | None:
        """The boundary subcomplex (see :func:`dhlb.topology.structure.boundary_complex`)."""
        from dhlb.topology.structure import boundary_complex

        return boundary_complex(self)

    def barycentric_subdivision(self) -> tuple[SimplicialComplex, np.ndarray]:
        """Barycentric subdivision (see :func:`dhlb.topology.subdivision.barycentric_subdivision`)."""
        from dhlb.topology.subdivision import barycentric_subdivision

        return barycentric_subdivision(self)

    def is_pseudomanifold(self) -> bool:
        """See :func:`dhlb.topology.manifold.is_pseudomanifold`."""
        from dhlb.topology.manifold import is_pseudomanifold

        return is_pseudomanifold(self)

    def is_manifold(self) -> bool:
        """See :func:`dhlb.topology.manifold.is_manifold`."""
        from dhlb.topology.manifold import is_manifold

        return is_manifold(self)

    def is_orientable(self) -> bool:
        """See :func:`dhlb.topology.orientation.is_orientable`."""
        from dhlb.topology.orientation import is_orientable

        return is_orientable(self)

    def orientation(self) -> np.ndarray:
        """±1 per top simplex, a consistent orientation (see :func:`dhlb.topology.orientation.orientation`)."""
        from dhlb.topology.orientation import orientation

        cached = self.__dict__.get("_orientation")
        if cached is None:
            cached = orientation(self)
            cached.setflags(write=False)
            self.__dict__["_orientation"] = cached
        return cached

    def homology(self) -> list:
        """Integer homology H_0..H_dim with torsion (see :func:`dhlb.topology.homology.homology`)."""
        from dhlb.topology.homology import homology

        return homology(self)

    def cohomology(self, coefficients: str | int = "Z") -> list:
        """Cohomology with coefficients Z, R, ("Z", m) or S1 (see :func:`dhlb.topology.homology.cohomology`)."""
        from dhlb.topology.homology import cohomology

        return cohomology(self, coefficients)

    # ------------------------------------------------------------------ dunder
    def __repr__(self) -> str:
        return f"SimplicialComplex(dim={self._dim}, counts={self.counts})"

    def __eq__(self, other) -> bool:
        if not isinstance(other, SimplicialComplex):
            return NotImplemented
        if self.counts != other.counts or not np.array_equal(self._labels, other._labels):
            return False
        return all(np.array_equal(a, b) for a, b in zip(self._rows, other._rows))

    __hash__ = None  # mutable-free but array-valued: compare, don't hash
    _exact_boundaries = True  # ∂_{k-1} ∂_k = 0 by construction: homology() does not check it again

    # ------------------------------------------------------------------ graphs (networkx, optional)
    @classmethod
    def from_graph(cls, G, kind: str = "clique", max_dim: int | None = None) -> SimplicialComplex:
        """The complex of a graph: its clique (flag) complex.

        Vertex ``i`` is the node ``list(G.nodes)[i]``;
        :func:`~dhlb.topology.networkx_bridge.flag_complex` also returns that list, and says how
        directed graphs and multigraphs are read. The graph is read through ``G.nodes`` and
        ``G.edges()`` only, so networkx itself is not needed; the cliques are enumerated by
        :func:`~dhlb.topology.cliques.maximal_cliques`.

        Parameters
        ----------
        G : networkx.Graph (or DiGraph, MultiGraph, MultiDiGraph, or an object with .nodes and .edges)
            The graph; any hashable nodes, no self-loops.
        kind : {"clique"}
            ``"clique"``: the k-simplices are the (k+1)-cliques of ``G``.
        max_dim : int >= 0, optional
            The largest simplex dimension kept; default every clique (clique number − 1).

        Returns
        -------
        SimplicialComplex
            The flag complex; ``X.vertex_labels`` is ``0 .. n-1``.

        Raises
        ------
        InvalidParameterError
            ``kind`` is not ``"clique"``, or ``max_dim`` is negative.
        InvalidTypeError
            ``G`` has no ``.nodes`` or no ``.edges``, or ``max_dim`` is not an integer.
        InvalidSimplexError
            ``G`` has a self-loop (the message names the node), or an edge end that is not a node.
        EmptyComplexError
            ``G`` has no nodes.
        ResourceLimitError
            The cliques, or the complex built from them, would need more memory than is available (a
            30-clique has 2^30 simplices): refused before the work (the cliques level by level, see
            :func:`~dhlb.topology.cliques.maximal_cliques`; then the complex), with the estimate and the
            largest ``max_dim`` that fits.

        Examples
        --------
        >>> import networkx as nx
        >>> SimplicialComplex.from_graph(nx.complete_graph(4)).counts
        (4, 6, 4, 1)
        """
        if kind != "clique":
            raise InvalidParameterError(f"kind must be one of ('clique',), got {kind!r}")
        from dhlb._memory_errors import check_memory
        from dhlb.topology.subdivision import complex_bytes

        nodes, edges = _graphs.read_graph(G)
        blocks = maximal_cliques(len(nodes), edges, max_dim)
        shapes = [(b.shape[0], b.shape[1] - 1) for b in blocks]

        def skeleton_bytes(d: int) -> int:  # max_dim = d: a larger clique gives C(m+1, d+1) d-cliques (not monotone)
            return complex_bytes([(r, m) if m <= d else (r * math.comb(m + 1, d + 1), d) for r, m in shapes])

        top = max(m for _, m in shapes)
        check_memory("max_dim", max_dim, complex_bytes(shapes),
                     largest=lambda room: max((d for d in range(top + 1) if skeleton_bytes(d) <= room), default=None),
                     advice=f"the complex of the {sum(r for r, _ in shapes):,} maximal cliques (up to {top + 1} "
                            "vertices) is built with all their faces")
        return cls(blocks)

    def to_networkx(self, kind: str = "skeleton"):
        """The complex as a networkx graph: its 1-skeleton or its dual graph.

        Parameters
        ----------
        kind : {"skeleton", "dual"}
            ``"skeleton"``: :func:`~dhlb.topology.networkx_bridge.skeleton_graph` (vertex indices,
            edge attribute ``'index'``); ``"dual"``: :func:`~dhlb.topology.networkx_bridge.dual_graph`
            (top-simplex indices, edge attribute ``'face'``).

        Returns
        -------
        networkx.Graph
            A new graph (changing it does not change the complex).

        Raises
        ------
        InvalidParameterError
            ``kind`` is not one of ``"skeleton"``, ``"dual"``.
        ImportError
            networkx is not installed (the message names ``pip install "dhlb[graph]"``).

        Examples
        --------
        >>> from dhlb import examples
        >>> T = examples.torus()
        >>> T.to_networkx().number_of_edges(), T.to_networkx("dual").number_of_edges()
        (21, 21)
        """
        graphs = {"skeleton": _graphs.skeleton_graph, "dual": _graphs.dual_graph}
        if kind not in graphs:
            raise InvalidParameterError(f"kind must be one of {tuple(graphs)}, got {kind!r}")
        return graphs[kind](self)
