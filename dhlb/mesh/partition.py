"""Vertex partitions of a mesh for distributed assembly: METIS parts, a part-by-part numbering, local meshes.

Rank 0 of a distributed run validates the global mesh, partitions its vertices
(:func:`partition_vertices`), renumbers them part by part (:func:`vertex_layout`: rank ``r`` owns
the contiguous new ids ``offsets[r]:offsets[r+1]``) and hands every rank a :class:`MeshPart`: its
owned vertices plus the halo its owned matrix rows depend on (:func:`surface_part`,
:func:`tet_part`). Each rank runs the ordinary assembly on its local mesh and keeps its owned rows
(:func:`owned_rows`); these are **bitwise equal** to the owned rows of the serial assembly on the
renumbered mesh. Nothing here uses MPI: a "rank" is just an index.

Why bitwise: a local mesh numbers its vertices in increasing new global id and keeps its cells in
their global order, so every canonical simplex order, every CSR row and every ``bincount`` sum the
assembly forms for an owned row sees the same terms in the same order as in the serial run.

Halos:

* **surfaces** (the tangent bundle of :mod:`dhlb.mesh.tangent`): an owned row ``i`` sums over the
  faces at ``i`` (ring 1), whose connection and curvature use the rescaled angles, angle sums
  and reference edges of all their vertices (the *needed* vertices), which depend on the complete
  fans of these vertices. The local faces are all faces touching a needed vertex (two rings). The
  other vertices of these faces (the *fringe*) may be touched in several disconnected fans (a
  bowtie), which :func:`~dhlb.mesh.validate_surface` refuses; their own data never enters an
  owned row, so each such fringe vertex is split into one copy per fan (the copies are appended at
  the end of :attr:`MeshPart.vertices`, with the global id repeated). Faces keep their global order,
  which keeps the reference edge (the corner of smallest index ``3f + p``) of every needed vertex.
* **tetrahedral meshes** (:mod:`dhlb.vortex`: the connection and curvature are per edge and per
  triangle, the element matrices per tetrahedron): one layer, the tetrahedra at an owned vertex.
  Such a patch of a valid mesh need not be a manifold at its fringe (a vertex or edge whose star in
  the patch is disconnected), so :func:`~dhlb.mesh.check_tet_mesh` may refuse it; build the local
  mesh with :meth:`~dhlb.mesh.TetMesh.from_validated` (no checks: the global check validated the
  cells) or straight as ``SimplicialComplex(local_cells)``.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import box_tet_mesh
>>> mesh = box_tet_mesh(4)
>>> part = partition_vertices(len(mesh.points), mesh.tets, 2)
>>> layout = vertex_layout(part, 2)
>>> T = layout.inverse[mesh.tets]                       # the mesh in the new numbering
>>> p0, p1 = tet_part(T, layout, 0), tet_part(T, layout, 1)
>>> p0.n_owned + p1.n_owned == len(mesh.points), int(p0.owned_cells.sum() + p1.owned_cells.sum()) == len(T)
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError, InvalidSimplexError, ShapeError, UnreferencedVertexError

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = ["METIS_PARTITION_OPTIONS", "MeshPart", "VertexLayout", "box_tet_part", "owned_rows", "partition_vertices",
           "surface_part", "tet_part", "vertex_layout"]

METIS_PARTITION_OPTIONS = {"seed": 0}
"""METIS's options for :func:`partition_vertices`: a fixed random seed, so that repeated calls agree."""


def _cells(cells: ArrayLike, n_vertices: int, what: str = "cells") -> np.ndarray:
    """``cells`` as an ``(m, 3)`` or ``(m, 4)`` int64 array of vertex ids in ``0 .. n_vertices-1``."""
    C = np.asarray(cells)
    if C.ndim != 2 or C.shape[1] not in (3, 4) or C.shape[0] == 0:
        raise ShapeError(f"{what} must have shape (m, 3) (triangles) or (m, 4) (tetrahedra), m > 0, got {C.shape}")
    if C.dtype.kind not in "iu":
        raise InvalidSimplexError(f"{what} must hold integer vertex ids, got dtype {C.dtype}")
    C = C.astype(np.int64, copy=False)
    lo, hi = int(C.min()), int(C.max())
    if lo < 0 or hi >= n_vertices:
        bad = lo if lo < 0 else hi
        raise InvalidSimplexError(f"{what} refer to vertex {bad}, outside 0 .. {n_vertices - 1}")
    return C


def _vertex_graph(n: int, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CSR ``(xadj, adjncy)`` of the vertex adjacency graph of the cells (no self loops, sorted, int32)."""
    k = C.shape[1]
    a, b = np.nonzero(~np.eye(k, dtype=bool))  # every ordered pair of distinct corners
    rows, cols = C[:, a].ravel(), C[:, b].ravel()
    G = sp.csr_matrix((np.ones(rows.size, np.int8), (rows, cols)), shape=(n, n))
    G.sum_duplicates()  # canonical: sorted columns, one entry per edge
    return G.indptr.astype(np.int32), G.indices.astype(np.int32)


def partition_vertices(n_vertices: int, cells: ArrayLike, parts: int) -> np.ndarray:
    """The part of every vertex: METIS's k-way partition of the vertex adjacency graph of ``cells``.

    Parameters
    ----------
    n_vertices : int
        Number of vertices ``n``; ``cells`` refer to ``0 .. n-1``.
    cells : (m, 3) or (m, 4) int array
        Triangles or tetrahedra (any numbering; only the edges they span are used).
    parts : int
        Number of parts ``P``, ``1 <= P <= n``.

    Returns
    -------
    part : (n,) int64 array
        Part id in ``0 .. P-1`` of each vertex. Deterministic (:data:`METIS_PARTITION_OPTIONS`);
        ``P = 1`` gives zeros without calling METIS.

    Raises
    ------
    InvalidParameterError
        ``parts`` is not an integer in ``1 .. n_vertices``.
    ShapeError, InvalidSimplexError
        ``cells`` is not an ``(m, 3)`` or ``(m, 4)`` integer array of ids below ``n_vertices``.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(4)
    >>> part = partition_vertices(len(mesh.points), mesh.tets, 3)
    >>> sizes = np.bincount(part)                    # 125 vertices in three parts of about 42
    >>> int(sizes.sum()), bool(sizes.max() - sizes.min() <= 3)
    (125, True)
    >>> bool((part == partition_vertices(len(mesh.points), mesh.tets, 3)).all())     # deterministic
    True
    """
    n = check_int(n_vertices, "n_vertices", 1)
    if isinstance(parts, bool) or not isinstance(parts, (int, np.integer)) or not 1 <= parts <= n:
        raise InvalidParameterError(f"parts must be an integer in 1 .. n_vertices = {n}, got {parts!r}")
    C = _cells(cells, n)
    if parts == 1:
        return np.zeros(n, np.int64)
    import pymetis

    xadj, adjncy = _vertex_graph(n, C)
    _, part = pymetis.part_graph(int(parts), pymetis.CSRAdjacency(xadj, adjncy),
                                 options=pymetis.Options(**METIS_PARTITION_OPTIONS))
    return np.asarray(part, dtype=np.int64)


@dataclass(frozen=True)
class VertexLayout:
    """A numbering of the vertices part by part: rank ``r`` owns the new ids ``offsets[r]:offsets[r+1]``.

    Made by :func:`vertex_layout`.

    Parameters
    ----------
    order : (n,) int64 array
        ``order[new]`` is the old id of the vertex with new id ``new`` (part by part, the old order
        kept inside each part).
    inverse : (n,) int64 array
        ``inverse[old]`` is the new id of vertex ``old``: a cell array ``C`` becomes ``inverse[C]``,
        per-vertex data ``x`` becomes ``x[order]``.
    offsets : (P + 1,) int64 array
        Rank ``r`` owns the new ids ``offsets[r]:offsets[r+1]``.

    Examples
    --------
    >>> layout = vertex_layout(np.array([1, 0, 1, 0, 2]), 3)
    >>> layout.order.tolist(), layout.offsets.tolist(), layout.owner([0, 1, 2, 4]).tolist()
    ([1, 3, 0, 2, 4], [0, 2, 4, 5], [0, 0, 1, 2])
    """

    order: np.ndarray
    inverse: np.ndarray
    offsets: np.ndarray

    @property
    def parts(self) -> int:
        """The number of parts ``P``."""
        return self.offsets.size - 1

    def owner(self, new_ids: ArrayLike) -> np.ndarray:
        """The rank owning each new vertex id.

        Parameters
        ----------
        new_ids : int array
            New vertex ids, any shape.

        Returns
        -------
        int64 array
            Same shape: ``r`` with ``offsets[r] <= id < offsets[r+1]``.
        """
        return np.searchsorted(self.offsets, np.asarray(new_ids, np.int64), side="right") - 1


def vertex_layout(part: ArrayLike, parts: int) -> VertexLayout:
    """Renumber the vertices part by part (the old order kept inside each part).

    Parameters
    ----------
    part : (n,) int array
        Part id in ``0 .. parts-1`` of each vertex (:func:`partition_vertices`); parts may be empty.
    parts : int >= 1
        Number of parts ``P``.

    Returns
    -------
    VertexLayout
        ``order`` (new → old), ``inverse`` (old → new), ``offsets`` (P + 1).

    Raises
    ------
    InvalidParameterError
        ``parts`` is not an integer >= 1 or a part id is outside ``0 .. parts-1``.
    ShapeError
        ``part`` is not one-dimensional.

    Examples
    --------
    >>> layout = vertex_layout([1, 1, 0, 1, 0], 2)
    >>> layout.order.tolist(), layout.inverse.tolist(), layout.offsets.tolist()
    ([2, 4, 0, 1, 3], [2, 3, 0, 4, 1], [0, 2, 5])
    """
    P = check_int(parts, "parts", 1)
    p = np.asarray(part)
    if p.ndim != 1:
        raise ShapeError(f"part must be one-dimensional (one part id per vertex), got shape {p.shape}")
    if p.size and (p.dtype.kind not in "iu" or int(p.min()) < 0 or int(p.max()) >= P):
        raise InvalidParameterError(f"part ids must be integers in 0 .. {P - 1}, got values in "
                                    f"{p.min()} .. {p.max()} (dtype {p.dtype})")
    p = p.astype(np.int64, copy=False)
    order = np.argsort(p, kind="stable")
    inverse = np.empty_like(order)
    inverse[order] = np.arange(order.size)
    offsets = np.zeros(P + 1, np.int64)
    np.cumsum(np.bincount(p, minlength=P), out=offsets[1:])
    for a in (order, inverse, offsets):
        a.setflags(write=False)
    return VertexLayout(order, inverse, offsets)


@dataclass(frozen=True)
class MeshPart:
    """The local mesh of one rank: its owned vertices, the halo its owned rows need, and its cells.

    Made by :func:`surface_part` and :func:`tet_part`. The local mesh is ``(V_new[vertices],
    local_cells)`` for the renumbered points ``V_new = V[layout.order]``.

    Parameters
    ----------
    rank : int
        The rank ``r``.
    parts : int
        The number of ranks ``P``.
    vertices : (nl,) int64 array
        New global id of each local vertex: increasing, then the extra copies of split fringe
        vertices (their global id repeated), see :attr:`n_copies`.
    owned : slice
        Local positions of the owned vertices, a contiguous block of ``vertices``.
    owned_range : (int, int)
        ``(start, stop)``: the new global ids owned, ``layout.offsets[rank:rank + 2]``.
    cells : (ml,) int64 array
        Row of each local cell in the global (renumbered) cell array, increasing.
    local_cells : (ml, k) int64 array
        The cells in local vertex numbers (rows of ``vertices``), in the order of ``cells``.
    owned_cells : (ml,) bool array
        The cells this rank owns: those whose smallest new vertex id it owns (every cell is owned
        by exactly one rank).

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(2)
    >>> layout = vertex_layout(np.arange(27) // 14, 2)      # ranks own 14 and 13 vertices
    >>> p = tet_part(layout.inverse[mesh.tets], layout, 1)
    >>> p.owned, p.owned_range, p.n_owned, p.halo.size, p.n_copies
    (slice(13, 26, None), (14, 27), 13, 13, 0)
    """

    rank: int
    parts: int
    vertices: np.ndarray
    owned: slice
    owned_range: tuple[int, int]
    cells: np.ndarray
    local_cells: np.ndarray
    owned_cells: np.ndarray

    @property
    def n_owned(self) -> int:
        """The number of owned vertices."""
        return self.owned.stop - self.owned.start

    @property
    def n_copies(self) -> int:
        """The number of extra copies of split fringe vertices (the last entries of :attr:`vertices`)."""
        return self.vertices.size - self._n_distinct

    @property
    def _n_distinct(self) -> int:
        v = self.vertices
        down = np.flatnonzero(v[1:] <= v[:-1])
        return v.size if down.size == 0 else int(down[0]) + 1

    def owns(self, simplices: ArrayLike) -> np.ndarray:
        """Which simplices (rows of local vertex ids: edges, triangles, cells) this rank owns.

        The rule of :attr:`owned_cells`, for simplices of any dimension: a simplex belongs to the
        owner of its smallest (new, global) vertex id, so every simplex of the whole mesh is owned by
        exactly one rank.

        Parameters
        ----------
        simplices : (s, k) int array
            Rows of local vertex ids (positions in :attr:`vertices`).

        Returns
        -------
        (s,) bool array

        Examples
        --------
        >>> import numpy as np
        >>> from dhlb.mesh import box_tet_mesh
        >>> box = box_tet_mesh(2)
        >>> layout = vertex_layout(partition_vertices(27, box.tets, 2), 2)
        >>> p = tet_part(layout.inverse[box.tets], layout, 0)
        >>> bool(np.array_equal(p.owns(p.local_cells), p.owned_cells))
        True
        """
        return _owned_by(self.vertices[np.asarray(simplices)], *self.owned_range)

    @property
    def halo(self) -> np.ndarray:
        """Local positions of the vertices this rank does not own (copies included)."""
        return np.r_[np.arange(self.owned.start), np.arange(self.owned.stop, self.vertices.size)].astype(np.int64)


def _owned_range(layout: VertexLayout, rank: int) -> tuple[int, int]:
    if not isinstance(layout, VertexLayout):
        raise InvalidParameterError(f"layout must be a VertexLayout (see vertex_layout), got {type(layout).__name__}")
    r = check_int(rank, "rank", 0)
    if r >= layout.parts:
        raise InvalidParameterError(f"rank must be in 0 .. {layout.parts - 1}, got {rank!r}")
    return int(layout.offsets[r]), int(layout.offsets[r + 1])


def _make_part(C: np.ndarray, rows: np.ndarray, layout: VertexLayout, rank: int, lo: int, hi: int,
               split: bool) -> MeshPart:
    """The :class:`MeshPart` with the cells ``C[rows]`` (fringe vertices split into fans when ``split``)."""
    n = layout.inverse.size
    cells = C[rows]
    used = np.zeros(n, bool)
    used[cells.ravel()] = True
    nowned = int(np.count_nonzero(used[lo:hi]))
    if nowned != hi - lo:
        v = lo + int(np.argmin(used[lo:hi]))
        raise UnreferencedVertexError(f"vertex {v} (new number) of rank {rank} lies in no cell; partition a "
                                      "compact mesh (dhlb.mesh.compact_mesh)")
    vertices = np.flatnonzero(used)
    local = np.full(n, -1, np.int64)
    local[vertices] = np.arange(vertices.size)
    lc = local[cells]
    n_distinct = vertices.size
    if split:
        fringe = np.ones(vertices.size, bool)
        fringe[lc[_touches(cells, lo, hi)].ravel()] = False  # the needed vertices: those of ring 1
        lc, copies = _split_fans(lc, fringe)
        vertices = np.concatenate([vertices, vertices[copies]])
    start = int(np.searchsorted(vertices[:n_distinct], lo))
    owned_cells = _owned_by(vertices[lc], lo, hi)
    for a in (vertices, rows, lc, owned_cells):
        a.setflags(write=False)
    return MeshPart(rank, layout.parts, vertices, slice(start, start + nowned), (lo, hi), rows, lc, owned_cells)


def _owned_by(G: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Rows of global vertex ids whose smallest id is in ``[lo, hi)``: the simplices the owner of that range owns."""
    gmin = np.minimum.reduce([G[:, j] for j in range(G.shape[1])]) if G.shape[1] else np.zeros(len(G), np.int64)
    return (gmin >= lo) & (gmin < hi)


def _any_column(B: np.ndarray) -> np.ndarray:
    """``B.any(axis=1)`` for a bool array with few columns (one pass per column, faster than the reduction)."""
    out = B[:, 0].copy()
    for j in range(1, B.shape[1]):
        out |= B[:, j]
    return out


def _touches(C: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Bool per row of ``C``: a vertex in ``lo .. hi-1``."""
    return _any_column((C - lo).view(np.uint64) < np.uint64(hi - lo))  # one comparison: negatives wrap around


def _split_fans(F: np.ndarray, fringe: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split every fringe vertex of the triangles ``F`` whose faces form k > 1 fans into k vertices.

    The corners at a fringe vertex are linked across the edges ``(w, x)`` they share; each
    connected set of corners is a fan. The fan holding the vertex's first corner keeps the vertex,
    the others get new vertices ``N, N + 1, ...`` (by vertex, then first corner). Returns the new
    faces and, per new vertex, the vertex it copies.
    """
    N = fringe.size
    flat = F.ravel()
    corner = np.flatnonzero(fringe[flat])
    if corner.size == 0:
        return F, np.zeros(0, np.int64)
    w = flat[corner]
    f, p = np.divmod(corner, 3)
    ends = np.stack([F[f, (p + 1) % 3], F[f, (p + 2) % 3]], axis=1)  # the two edges (w, x) of each corner
    key = (w[:, None] * N + ends).ravel()
    idx = np.repeat(np.arange(corner.size), 2)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    pair = np.flatnonzero(sk[1:] == sk[:-1])  # a manifold mesh has at most two corners per (w, x)
    a, b = idx[order[pair]], idx[order[pair + 1]]
    k = corner.size
    G = sp.csr_matrix((np.ones(a.size, np.int8), (a, b)), shape=(k, k))
    ncomp, label = connected_components(G, directed=False)
    seen = np.zeros(N, bool)
    seen[w] = True
    if ncomp == np.count_nonzero(seen):  # one fan per fringe vertex
        return F, np.zeros(0, np.int64)
    first = np.full(ncomp, k, np.int64)
    np.minimum.at(first, label, np.arange(k))  # corners are increasing: the first corner of each fan
    cw = w[first]
    order = np.lexsort((first, cw))  # fans by vertex, then first corner
    keep = np.r_[True, cw[order][1:] != cw[order][:-1]]
    target = np.empty(ncomp, np.int64)
    extra = order[~keep]
    target[order[keep]] = cw[order[keep]]
    target[extra] = N + np.arange(extra.size)
    out = F.copy().ravel()
    out[corner] = target[label]
    return out.reshape(F.shape), cw[extra]


def surface_part(F: ArrayLike, layout: VertexLayout, rank: int) -> MeshPart:
    """The local triangle mesh of ``rank``: the two rings of faces its owned rows depend on.

    Ring 1 are the faces touching an owned vertex; the *needed* vertices are those of ring 1; the
    local faces are all faces touching a needed vertex, so every needed vertex has its complete
    fan (angle sum, reference edge, rescaled angles). The remaining (fringe) vertices whose local
    faces form several fans are split, one copy per fan, so that the local mesh is a 2-manifold
    that :func:`~dhlb.mesh.validate_surface` accepts.

    Parameters
    ----------
    F : (m, 3) int array
        The validated (oriented, manifold) faces in the **new** vertex numbers
        (``layout.inverse[F_old]``), in their original order: the face order fixes the reference
        edges of the tangent bundle and must not change.
    layout : VertexLayout
        The numbering (:func:`vertex_layout`).
    rank : int
        The rank, ``0 <= rank < layout.parts``.

    Returns
    -------
    MeshPart
        ``local_cells`` are faces of the local mesh ``(V_new[vertices], local_cells)``.

    Raises
    ------
    InvalidParameterError
        ``rank`` is out of range or ``layout`` is not a :class:`VertexLayout`.
    ShapeError, InvalidSimplexError
        ``F`` is not an ``(m, 3)`` integer array of vertex ids of the layout.
    UnreferencedVertexError
        An owned vertex lies in no face (partition a compact mesh).

    Examples
    --------
    >>> from dhlb.io import example_path, read_surface
    >>> from dhlb.mesh import validate_surface
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> layout = vertex_layout(partition_vertices(len(V), F, 2), 2)
    >>> p = surface_part(layout.inverse[F], layout, 0)
    >>> local = validate_surface(V[layout.order][p.vertices], p.local_cells)   # a valid mesh
    >>> local.n_faces == p.cells.size, p.n_owned == int(layout.offsets[1])
    (True, True)
    """
    lo, hi = _owned_range(layout, rank)
    C = _cells(F, layout.inverse.size, "F")
    if C.shape[1] != 3:
        raise ShapeError(f"F must have shape (m, 3), got {C.shape}")
    ring1 = _touches(C, lo, hi)
    needed = np.zeros(layout.inverse.size, bool)
    needed[C[ring1].ravel()] = True
    rows = np.flatnonzero(_any_column(needed[C]))
    return _make_part(C, rows, layout, rank, lo, hi, split=True)


def tet_part(T: ArrayLike, layout: VertexLayout, rank: int) -> MeshPart:
    """The local tetrahedral mesh of ``rank``: the tetrahedra touching an owned vertex (one layer).

    Enough for matrices whose element data are per tetrahedron, per triangle and per edge
    (:func:`dhlb.vortex.velocity_bundle` and :func:`dhlb.fem.bundle_matrices`): every term of an
    owned row comes from a tetrahedron at its vertex. The patch need not be a manifold at its
    fringe; build its mesh with :meth:`~dhlb.mesh.TetMesh.from_validated`.

    Parameters
    ----------
    T : (m, 4) int array
        The validated tetrahedra in the **new** vertex numbers (``layout.inverse[T_old]``).
    layout : VertexLayout
        The numbering (:func:`vertex_layout`).
    rank : int
        The rank, ``0 <= rank < layout.parts``.

    Returns
    -------
    MeshPart
        No fringe vertex is split (``n_copies == 0``).

    Raises
    ------
    InvalidParameterError
        ``rank`` is out of range or ``layout`` is not a :class:`VertexLayout`.
    ShapeError, InvalidSimplexError
        ``T`` is not an ``(m, 4)`` integer array of vertex ids of the layout.
    UnreferencedVertexError
        An owned vertex lies in no tetrahedron.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(3)
    >>> layout = vertex_layout(partition_vertices(len(mesh.points), mesh.tets, 2), 2)
    >>> p = tet_part(layout.inverse[mesh.tets], layout, 1)
    >>> bool(np.all(np.diff(p.cells) > 0)), p.n_copies
    (True, 0)
    """
    lo, hi = _owned_range(layout, rank)
    C = _cells(T, layout.inverse.size, "T")
    if C.shape[1] != 4:
        raise ShapeError(f"T must have shape (m, 4), got {C.shape}")
    return _make_part(C, np.flatnonzero(_touches(C, lo, hi)), layout, rank, lo, hi, split=False)


def owned_rows(S, part: MeshPart) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The owned rows of a local matrix, in CSR with new global column ids (sorted in each row).

    Parameters
    ----------
    S : (nl, nl) scipy.sparse matrix
        A matrix on the local vertices of ``part`` (e.g. assembled on its local mesh).
    part : MeshPart
        The part (:func:`surface_part`, :func:`tet_part`).

    Returns
    -------
    indptr : (n_owned + 1,) int64 array
    indices : (nnz,) int64 array
        New global column ids, increasing in each row.
    data : (nnz,) array
        The entries, dtype of ``S``. Together the local rows ``owned_range`` of the global matrix,
        e.g. for PETSc's ``Mat.createAIJ(..., csr=(indptr, indices, data))``.

    Raises
    ------
    ShapeError
        ``S`` is not ``(nl, nl)``, or an owned row has an entry in the column of a split fringe
        copy (its rows then depend on data the part does not hold correctly).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> layout = vertex_layout([0, 1, 0, 1], 2)             # new ids: old 0, 2 → 0, 1; old 1, 3 → 2, 3
    >>> F = layout.inverse[[[0, 1, 2], [1, 3, 2]]]          # two triangles, new numbers
    >>> p = surface_part(F, layout, 1)
    >>> p.vertices.tolist(), p.owned
    ([0, 1, 2, 3], slice(2, 4, None))
    >>> S = sp.csr_matrix(np.arange(16.0).reshape(4, 4))     # a local matrix
    >>> [a.tolist() for a in owned_rows(S, p)]
    [[0, 4, 8], [0, 1, 2, 3, 0, 1, 2, 3], [8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0]]
    """
    nl = part.vertices.size
    S = sp.csr_matrix(S)
    if S.shape != (nl, nl):
        raise ShapeError(f"S must be ({nl}, {nl}) (one row and column per local vertex), got {S.shape}")
    R = S[part.owned]
    if not R.has_sorted_indices:
        R = R.sorted_indices()
    cols = R.indices.astype(np.int64)
    nd = part._n_distinct
    if cols.size and int(cols.max()) >= nd:
        raise ShapeError(f"an owned row has an entry in column {int(cols.max())}, a copy of a split fringe vertex; "
                         "the part does not hold that row")
    return R.indptr.astype(np.int64), part.vertices[cols], R.data.copy()


def box_tet_part(m: int | Sequence[int], lower: ArrayLike, upper: ArrayLike, rank: int,
                 parts: int) -> tuple[MeshPart, np.ndarray, np.ndarray]:
    """The part of ``rank`` of :func:`~dhlb.mesh.box_tet_mesh` cut in slabs of x, built without the whole box.

    The vertices are partitioned by their grid plane ``i`` along x (the slowest axis of the box
    numbering): rank ``r`` owns the planes ``i0 = r (m_0+1) // P`` to ``i1 = (r+1)(m_0+1) // P``
    (excluded), i.e. the box vertex ids ``i0 S .. i1 S - 1`` with ``S = (m_1+1)(m_2+1)``. These
    are contiguous, so the layout is the identity (``vertex_layout`` of the slab part ids keeps every
    id) and the part equals ``tet_part(box.tets, vertex_layout(slab_ids, P), rank)`` field by field
    — ``cells`` are rows of ``box_tet_mesh(m, lower, upper).tets`` and ``local_cells`` those rows,
    same vertex order, in local ids — while only the tetrahedra of the grid cells of x-layers
    ``i0 - 1 .. i1 - 1`` (one layer of halo) are made: time and memory are those of the part.

    Parameters
    ----------
    m : int >= 1, or 3 ints
        Cells per axis, as :func:`~dhlb.mesh.box_tet_mesh`.
    lower, upper : 3 floats (or one number for all axes)
        Opposite corners, ``lower < upper`` on every axis.
    rank : int
        The rank ``r``, ``0 <= r < parts``.
    parts : int
        The number of ranks ``P``, ``1 <= P <= m_0 + 1`` (every rank owns at least one plane).

    Returns
    -------
    part : MeshPart
        As :func:`tet_part` gives it for the whole box and the slab partition (``n_copies == 0``).
    points : (nl, 3) float array
        ``box.points[part.vertices]``, bit for bit.
    boundary_faces : (b, 3) int64 array
        The boundary triangles of the whole box (``box.boundary_faces``: outward normals) whose three
        vertices are local, in local vertex ids, in the order of ``box.boundary_faces``.

    Raises
    ------
    InvalidParameterError
        ``m`` is not a positive integer (or three), ``lower < upper`` fails on an axis, ``parts`` is
        not an integer in ``1 .. m_0 + 1`` or ``rank`` not in ``0 .. parts - 1``.
    ResourceLimitError
        The part's estimated memory (:func:`~dhlb.mesh.check_box_memory` for its layers) exceeds what is available.
    ShapeError, NonFiniteError
        ``lower`` or ``upper`` is neither a number nor 3 numbers, or is not finite.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> box = box_tet_mesh(3, lower=-1.0, upper=1.0)
    >>> ids = np.arange(64) // 16 // 2                        # planes 0, 1 -> rank 0; 2, 3 -> rank 1
    >>> whole = tet_part(box.tets, vertex_layout(ids, 2), 1)
    >>> part, points, bf = box_tet_part(3, -1.0, 1.0, rank=1, parts=2)
    >>> part.owned_range, part.vertices.size, part.cells.size, bf.shape
    ((32, 64), 48, 108, (66, 3))
    >>> bool(np.array_equal(part.local_cells, whole.local_cells) and np.array_equal(points, box.points[16:]))
    True
    """
    from dhlb.examples._util import kuhn_paths
    from dhlb.examples.grids import _cells_per_axis, _strides
    from dhlb.mesh.tet import box_corners, check_box_memory

    cells = _cells_per_axis(3, m, 1)
    lo_pt, hi_pt = box_corners(lower, upper)
    planes = cells[0] + 1
    if isinstance(parts, bool) or not isinstance(parts, (int, np.integer)) or not 1 <= parts <= planes:
        raise InvalidParameterError(f"parts must be an integer in 1 .. m_0 + 1 = {planes} (every rank owns a plane "
                                    f"of the x slabs), got {parts!r}")
    P = int(parts)
    if isinstance(rank, bool) or not isinstance(rank, (int, np.integer)) or not 0 <= rank < P:
        raise InvalidParameterError(f"rank must be an integer in 0 .. {P - 1}, got {rank!r}")
    r = int(rank)
    i0, i1 = r * planes // P, (r + 1) * planes // P        # owned planes
    c0, c1 = max(i0 - 1, 0), min(i1, cells[0])              # cell layers with a tet at an owned vertex
    check_box_memory((c1 - c0, cells[1], cells[2]))
    shape = (planes, cells[1] + 1, cells[2] + 1)
    strides = _strides(shape)
    S = int(strides[0])
    v0 = c0 * S                                             # first local vertex: plane c0 .. plane c1
    # the tets of the cells, as cube_nd makes them, in the order of SimplicialComplex.simplices
    # (lexicographic: by the cell's lowest corner, then the sorted Kuhn offsets); check_tet_mesh then
    # swaps the last two vertices of the negatively oriented ones (odd paths: lower < upper)
    paths = kuhn_paths(3)
    offsets = paths @ strides
    order = np.lexsort(offsets.T[::-1])
    offsets, paths = offsets[order], paths[order]
    negative = np.linalg.det((paths[:, 1:] - paths[:, :1]).astype(np.float64)) < 0
    offsets[negative] = offsets[negative][:, [0, 1, 3, 2]]
    base = np.zeros(1, np.int64)
    for a, (start, stop) in enumerate(((c0, c1), (0, cells[1]), (0, cells[2]))):
        base = np.add.outer(base, np.arange(start, stop, dtype=np.int64) * strides[a]).ravel()
    local_cells = ((base - v0)[:, None, None] + offsets[None]).reshape(-1, 4)
    per_layer = 6 * cells[1] * cells[2]
    rows = np.arange(c0 * per_layer, c1 * per_layer, dtype=np.int64)
    nl = (c1 + 1 - c0) * S
    vertices = np.arange(v0, v0 + nl, dtype=np.int64)
    owned_cells = np.repeat(np.arange(c0, c1) >= i0, per_layer)  # the lowest vertex is the cell's corner
    idx = np.indices((c1 + 1 - c0,) + shape[1:], dtype=np.int64).reshape(3, -1).T
    idx[:, 0] += c0
    points = lo_pt + idx / np.asarray(cells, dtype=np.float64) * (hi_pt - lo_pt)
    # boundary faces: the faces of the local tets (in the order of TetMesh.boundary_faces) on a side of the box;
    # every one whose vertices are local is a face of a local tet, and a face lies on a side iff its vertices do
    sides = np.zeros(nl, np.uint8)                          # bit 2a: on the side i_a = 0; bit 2a + 1: i_a = m_a
    for a in range(3):
        sides |= (idx[:, a] == 0).astype(np.uint8) << np.uint8(2 * a)
        sides |= (idx[:, a] == cells[a]).astype(np.uint8) << np.uint8(2 * a + 1)
    corners = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    C = sides[local_cells]
    on_side = np.stack([C[:, f[0]] & C[:, f[1]] & C[:, f[2]] for f in corners], axis=1) != 0
    t, f = np.nonzero(on_side)                              # by tet, then face: the order of boundary_faces
    boundary = local_cells[t[:, None], corners[f]]
    for a in (vertices, rows, local_cells, owned_cells):
        a.setflags(write=False)
    part = MeshPart(r, P, vertices, slice((i0 - c0) * S, (i1 - c0) * S), (i0 * S, i1 * S), rows, local_cells,
                    owned_cells)
    return part, points, boundary
