"""Meshes under MPI: rank 0 reads, validates and partitions; every rank gets its part and a halo.

The pattern of FEniCSx and Firedrake on the tools dhlb has (:mod:`dhlb.mesh.partition`, mpi4py):

1. **Rank 0** validates the whole mesh (orientation, manifoldness, components, geometry: the checks of
   :func:`~dhlb.mesh.validate_surface` and :func:`~dhlb.mesh.check_tet_mesh`), partitions its vertices
   with METIS (:func:`~dhlb.mesh.partition.partition_vertices`) and renumbers them part by part
   (:func:`~dhlb.mesh.partition.vertex_layout`); rank ``r`` owns the new vertex ids
   ``offsets[r]:offsets[r + 1]``. Cells keep their order.
2. **Every rank** receives its :class:`~dhlb.mesh.partition.MeshPart` — owned vertices plus the halo
   whose data enter the owned rows (surfaces: two rings of faces; tets: one layer) — and builds the
   local mesh from it with the same mesh layer as on one process; the assembly kernels then run
   unchanged on the local mesh, and the owned rows are those of the serial assembly, bit for bit.

Bad input is found on rank 0 and raised on *every* rank as the same typed error
(:func:`root_first`), so no rank is left waiting in a collective call.

All functions here are collective over ``comm`` (default ``MPI_COMM_WORLD``); on one process (no
mpi4py, or one rank) they do the same work without communication.

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> loc = distribute_surface(*read_surface(example_path("torus.obj")))   # one process: the whole mesh
>>> loc.n_owned == loc.n_vertices, loc.rank, loc.size
(True, 0, 1)
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb._phases import trim_heap
from dhlb.errors import DhlbError, InvalidParameterError
from dhlb.linalg.distributed import RowBlock, gather_to_root, world

if TYPE_CHECKING:
    from collections.abc import Callable

    from dhlb.mesh.partition import MeshPart, VertexLayout

__all__ = ["LocalMesh", "distribute_box", "distribute_surface", "distribute_tets", "gather_cells", "gather_owned",
           "parallel_report", "root_first", "world"]


def _rebuild(kind: type, message: str) -> BaseException:
    """An exception of class ``kind`` with ``message`` (its own constructor if it takes one string)."""
    try:
        err = kind(message)
    except Exception:
        return DhlbError(f"{kind.__name__}: {message}")
    return err if str(err) == message else DhlbError(f"{kind.__name__}: {message}")


def root_first(fn: Callable[[], Any], comm=None, *, what: str = "") -> Any:
    """Run ``fn()`` on rank 0 only; if it raises, raise the same kind of error on every rank.

    The value of ``fn()`` is returned on rank 0 and None elsewhere. On failure rank 0 re-raises its
    own exception and every other rank raises one of the same class and message (prefixed with
    ``what``, and the rank that failed), so that ``except`` clauses and exit codes agree everywhere.

    Parameters
    ----------
    fn : callable
        The work (no arguments) rank 0 does.
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.
    what : str, optional
        Says what was being done, for the other ranks' message.

    Returns
    -------
    object or None
        ``fn()`` on rank 0, None on the other ranks.

    Raises
    ------
    Exception
        Of the class ``fn`` raised (a :class:`~dhlb.errors.DhlbError` if that class cannot be rebuilt
        from a message), on every rank.

    Examples
    --------
    >>> root_first(lambda: 42)
    42
    """
    comm = world() if comm is None else comm
    value, status = None, None
    if comm.rank == 0:
        try:
            value = fn()
        except Exception as err:
            status = (type(err), str(err))
            if comm.size > 1:
                comm.bcast(status, root=0)
            raise
    if comm.size == 1:
        return value
    status = comm.bcast(status, root=0)
    if status is not None:
        kind, message = status
        raise _rebuild(kind, f"{what + ': ' if what else ''}{message} (found on MPI rank 0)")
    return value


@dataclass(eq=False)
class LocalMesh:
    """The part of a distributed mesh held by one rank (made by :func:`distribute_surface` / :func:`distribute_tets`).

    Parameters
    ----------
    mesh : SurfaceMesh or TetMesh
        The local mesh: the owned vertices and the halo, validated locally by the mesh layer (local
        vertex ``i`` is the new global vertex ``part.vertices[i]``; local cell ``c`` the global cell
        ``part.cells[c]``).
    part : MeshPart
        Owned vertices, halo and cell ownership (:mod:`dhlb.mesh.partition`).
    offsets : (P + 1,) int array
        Rank ``r`` owns the new global vertex ids ``offsets[r]:offsets[r + 1]``.
    n_vertices, n_cells : int
        Global counts.
    rank, size : int
        This rank and the number of ranks.
    whole : SurfaceMesh or TetMesh or callable or None
        Rank 0 only: the validated whole mesh, or a function that rebuilds it (see :attr:`global_mesh`);
        None elsewhere.
    layout : VertexLayout or None
        Rank 0 only: old ↔ new vertex numbers; None elsewhere.
    vertex_values : (n_local, ...) array or None
        The local rows of per-vertex data sent with the mesh (:func:`distribute_tets`).
    boundary_faces : (b, 3) int array or None
        Tets: the boundary triangles of the whole mesh with all three vertices local (local vertex ids),
        so that a face of the patch's boundary can be told from a cut between ranks.
    input_rows : (n_vertices,) int array or None
        Rank 0 only: the input row of ``V`` of each vertex of the whole mesh (old numbering).
    """

    mesh: Any
    part: MeshPart
    offsets: np.ndarray
    n_vertices: int
    n_cells: int
    rank: int
    size: int
    whole: Any = None
    layout: VertexLayout | None = None
    vertex_values: np.ndarray | None = None
    boundary_faces: np.ndarray | None = None
    input_rows: np.ndarray | None = None

    @property
    def global_mesh(self):
        """Rank 0: the validated whole mesh (old numbering); None on the other ranks.

        With more than one rank, rank 0 does not keep the whole mesh's structures while the ranks
        assemble and solve (they would be most of its memory, ~0.75 KB per face of a surface): it is
        validated again on first use, after the solve (deterministic: the same mesh).
        """
        if callable(self.whole):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # the first validation warned already
                self.whole = self.whole()
        return self.whole

    @property
    def start(self) -> int:
        """The first owned new global vertex id."""
        return int(self.offsets[self.rank])

    @property
    def stop(self) -> int:
        """One past the last owned new global vertex id."""
        return int(self.offsets[self.rank + 1])

    def row_block(self, S) -> RowBlock:
        """The owned rows of a matrix assembled on the local mesh, as the distributed linear algebra takes them.

        Parameters
        ----------
        S : (n_local, n_local) scipy.sparse matrix
            Assembled on :attr:`mesh` (rows and columns are local vertices).

        Returns
        -------
        RowBlock
            Rows ``start:stop`` of the global matrix, global column ids (:func:`~dhlb.mesh.partition.owned_rows`).
        """
        from dhlb.mesh.partition import owned_rows

        return RowBlock(*owned_rows(S, self.part), self.start, self.stop, self.n_vertices)

    @property
    def n_owned(self) -> int:
        """The number of owned vertices."""
        return self.stop - self.start


def _scatter_parts(comm, make_parts: Callable[[], tuple[Any, list]], what: str):
    """Rank 0 computes ``(header, [payload per rank])``; every rank gets ``(header, its payload)``."""
    out = root_first(make_parts, comm, what=what)
    if comm.size == 1:
        header, payloads = out
        return header, payloads[0]
    header, payloads = out if comm.rank == 0 else (None, None)
    header = comm.bcast(header, root=0)
    mine = comm.scatter(payloads, root=0)
    return header, mine


def distribute_surface(V, F, *, reorient: bool = False, components: str = "all", connected: bool = False,
                       comm=None) -> LocalMesh:
    """Validate a triangle mesh on rank 0 and give every rank its part with two rings of halo faces.

    Parameters
    ----------
    V : (n, 3) float array or None
        Vertex positions (read on rank 0 only; the other ranks may pass None).
    F : (m, 3) int array or None
        Triangles (rank 0; None elsewhere).
    reorient : bool, optional
        Flip inconsistently oriented faces (as :func:`~dhlb.mesh.validate_surface`).
    components : {"all", "largest"}, optional
        Keep all connected components, or only the largest (as :func:`~dhlb.mesh.validate_surface`).
    connected : bool, optional
        Refuse a mesh of several connected components (:class:`~dhlb.errors.InvalidParameterError`).
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    LocalMesh
        With ``mesh`` the local :class:`~dhlb.mesh.SurfaceMesh` (owned vertices and halo).

    Raises
    ------
    DhlbError
        Whatever :func:`~dhlb.mesh.validate_surface` raises for the whole mesh, on every rank.

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> loc = distribute_surface(*read_surface(example_path("torus.obj")))
    >>> loc.mesh.n_faces == loc.n_cells
    True
    """
    from dhlb.mesh import partition
    from dhlb.mesh.surface import validate_surface

    comm = world() if comm is None else comm

    def root():
        gm = validate_surface(V, F, reorient=reorient, components=components)
        if connected and gm.components[0] > 1:
            raise InvalidParameterError(
                f"the mesh has {gm.components[0]} connected components; the distributed field solves one "
                "eigenproblem: keep the largest (components='largest'), or compute the components one by one")
        lay = partition.vertex_layout(partition.partition_vertices(gm.n_vertices, gm.faces, comm.size), comm.size)
        Fn = lay.inverse[gm.faces]
        Pn = gm.points[lay.order]
        parts = [partition.surface_part(Fn, lay, r) for r in range(comm.size)]
        rebuild = gm if comm.size == 1 else (lambda: validate_surface(V, F, reorient=reorient, components=components))
        root.kept = (rebuild, lay, np.asarray(gm.vertex_labels))
        return (lay.offsets, gm.n_vertices, gm.n_faces), [(p, np.ascontiguousarray(Pn[p.vertices])) for p in parts]

    (offsets, nv, nf), (part, P) = _scatter_parts(comm, root, "distributing the surface")
    whole, lay, rows = root.kept if comm.rank == 0 else (None, None, None)
    root.kept = None
    # the local patch (one rank: the whole mesh, validated once); rank 0 validated the whole mesh
    local = whole if comm.size == 1 else validate_surface(P, part.local_cells)
    trim_heap()   # the validation's temporaries: give them back before the assembly
    return LocalMesh(local, part, np.asarray(offsets), int(nv), int(nf), comm.rank, comm.size, whole, lay,
                     input_rows=rows)


def distribute_tets(V, T, *, orientation: str = "fix", vertex_values=None, comm=None) -> LocalMesh:
    """Validate a tetrahedral mesh on rank 0 and give every rank its part with one layer of halo tets.

    Parameters
    ----------
    V : (n, 3) float array or TetMesh or None
        Vertex positions, or an already validated :class:`~dhlb.mesh.TetMesh` (rank 0; None elsewhere).
    T : (m, 4) int array or None
        Tetrahedra (rank 0, unless ``V`` is a TetMesh).
    orientation : {"fix", "require"}, optional
        As :func:`~dhlb.mesh.check_tet_mesh`.
    vertex_values : (n, ...) array or callable, optional
        Per-vertex data given with the input rows of ``V`` (rank 0): each rank receives the rows of its
        local vertices as ``LocalMesh.vertex_values``. A callable is called on rank 0 with the validated
        :class:`~dhlb.mesh.TetMesh` and must return such an array (it may raise; every rank then raises).
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    LocalMesh
        With ``mesh`` the local :class:`~dhlb.mesh.TetMesh` (:meth:`~dhlb.mesh.TetMesh.from_validated`: a
        patch may have a vertex or edge whose star is disconnected at its edge) and ``boundary_faces``.

    Raises
    ------
    DhlbError
        Whatever :func:`~dhlb.mesh.check_tet_mesh` raises for the whole mesh, on every rank.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> loc = distribute_tets(box_tet_mesh(3), None)
    >>> loc.mesh.tets.shape[0] == loc.n_cells == 162
    True
    """
    from dhlb.mesh import partition
    from dhlb.mesh.tet import TetMesh, check_tet_mesh

    comm = world() if comm is None else comm

    def root():
        gm = V if isinstance(V, TetMesh) else check_tet_mesh(V, T, orientation=orientation)
        values = vertex_values(gm) if callable(vertex_values) else vertex_values
        rows = np.asarray(gm.complex.vertex_labels)
        if values is not None:  # input rows -> compact -> new numbering
            values = np.asarray(values)[rows]
        lay = partition.vertex_layout(partition.partition_vertices(gm.points.shape[0], gm.tets, comm.size),
                                      comm.size)
        if values is not None:
            values = values[lay.order]
        Tn = lay.inverse[gm.tets]
        Pn = gm.points[lay.order]
        Bn = lay.inverse[gm.boundary_faces]   # the whole mesh's boundary triangles, new ids
        parts = [partition.tet_part(Tn, lay, r) for r in range(comm.size)]
        keep = gm if comm.size == 1 or isinstance(V, TetMesh) else (
            lambda: check_tet_mesh(V, T, orientation=orientation))
        root.kept = (keep, lay, rows)
        payloads = []
        for p in parts:
            local_of = np.full(Pn.shape[0], -1, np.int64)
            local_of[p.vertices] = np.arange(p.vertices.size)
            B = local_of[Bn]
            payloads.append((p, np.ascontiguousarray(Pn[p.vertices]), None if values is None else values[p.vertices],
                             B[np.all(B >= 0, axis=1)]))
        return (lay.offsets, gm.points.shape[0], gm.tets.shape[0]), payloads

    (offsets, nv, nt), (part, P, vals, B) = _scatter_parts(comm, root, "distributing the tetrahedral mesh")
    whole, lay, rows = root.kept if comm.rank == 0 else (None, None, None)
    root.kept = None
    # a patch of the mesh rank 0 validated and oriented (one rank: the whole mesh itself)
    local = whole if comm.size == 1 else TetMesh.from_validated(P, part.local_cells)
    trim_heap()   # the validation's temporaries: give them back before the assembly
    return LocalMesh(local, part, np.asarray(offsets), int(nv), int(nt), comm.rank, comm.size, whole, lay, vals, B,
                     rows)


def distribute_box(m, lower=(0.0, 0.0, 0.0), upper=(1.0, 1.0, 1.0), *, comm=None) -> LocalMesh:
    """Every rank builds its own slab of :func:`~dhlb.mesh.box_tet_mesh`; no rank builds the whole box.

    The parts are slabs of x-planes (:func:`dhlb.mesh.partition.box_tet_part`), so the vertex numbering
    is the box's own (the layout is the identity) and nothing is sent between the ranks.

    Parameters
    ----------
    m : int or 3 ints
        Cells per axis.
    lower, upper : 3 floats (or one number for all axes)
        Opposite corners of the box.
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    LocalMesh
        As :func:`distribute_tets`; on rank 0 :attr:`LocalMesh.global_mesh` builds the whole box on first
        use (after the solve).

    Raises
    ------
    InvalidParameterError, ResourceLimitError
        As :func:`~dhlb.mesh.box_tet_mesh`, or more ranks than x-planes; on every rank (each checks).

    Examples
    --------
    >>> loc = distribute_box(3, -1.0, 1.0)
    >>> loc.n_vertices, loc.n_cells, loc.mesh.tets.shape[0]
    (64, 162, 162)
    """
    from dhlb.mesh import partition
    from dhlb.mesh.tet import TetMesh

    comm = world() if comm is None else comm
    part, P, B = partition.box_tet_part(m, lower, upper, comm.rank, comm.size)
    cells = np.broadcast_to(np.asarray(m, np.int64), 3)
    nv, nt = int(np.prod(cells + 1)), int(6 * np.prod(cells))
    starts = comm.allgather(part.owned_range[0])
    offsets = np.array(list(starts) + [nv], np.int64)
    lay = whole = rows = None
    if comm.rank == 0:
        ident = np.arange(nv, dtype=np.int64)
        lay = partition.VertexLayout(ident, ident, offsets)
        rows = ident

        def whole():
            p, points, _ = partition.box_tet_part(m, lower, upper, 0, 1)
            return TetMesh.from_validated(points, p.local_cells)
    local = TetMesh.from_validated(P, part.local_cells)
    return LocalMesh(local, part, offsets, nv, nt, comm.rank, comm.size, whole, lay, None, B, rows)


def gather_owned(loc: LocalMesh, values, comm=None):
    """The owned rows of per-vertex ``values`` of every rank, on rank 0 in the OLD (input) vertex numbering.

    Parameters
    ----------
    loc : LocalMesh
        This rank's part.
    values : (n_owned, ...) array
        One row per owned vertex, in the order of the owned new ids.
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    (n_vertices, ...) array or None
        On rank 0 the rows in the numbering of ``loc.global_mesh``; None elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> loc = distribute_tets(box_tet_mesh(2), None)
    >>> x = gather_owned(loc, loc.mesh.points[loc.part.owned])
    >>> bool(np.array_equal(x, box_tet_mesh(2).points))
    True
    """
    comm = world() if comm is None else comm
    values = np.asarray(values)
    if values.shape[0] != loc.n_owned:
        from dhlb.errors import ShapeError

        raise ShapeError(f"gather_owned: {values.shape[0]} rows for {loc.n_owned} owned vertices")
    new = gather_to_root(values)   # rank order = new id order
    return None if new is None else new[loc.layout.inverse]


def parallel_report(loc: LocalMesh, meter, comm=None) -> dict | None:
    """What each rank held and used, on rank 0: the ``"parallel"`` entry of a distributed result (collective).

    Parameters
    ----------
    loc : LocalMesh
        This rank's part.
    meter : dhlb._phases.PhaseMeter
        The run's phases: their peak memory and the memory each began with.
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    dict or None
        On rank 0: ``ranks``; per rank ``owned_vertices`` (also the rows handed to PETSc, ``petsc_rows``),
        ``local_vertices``, ``owned_cells``, ``local_cells``, ``peak_mb`` and ``start_mb`` (per phase).
        None elsewhere.

    Examples
    --------
    >>> from dhlb._phases import PhaseMeter
    >>> from dhlb.mesh import box_tet_mesh
    >>> meter = PhaseMeter()
    >>> loc = distribute_tets(box_tet_mesh(2), None)
    >>> meter.mark("mesh")
    >>> r = parallel_report(loc, meter)
    >>> r["ranks"], r["owned_vertices"], r["owned_cells"], sorted(r["peak_mb"][0])
    (1, [27], [48], ['mesh'])
    """
    comm = world() if comm is None else comm
    mine = (loc.n_owned, int(loc.part.vertices.size), int(loc.part.owned_cells.sum()), int(loc.part.cells.size),
            dict(meter.peak_mb), dict(meter.start_mb))
    got = comm.gather(mine, root=0)
    if comm.rank != 0:
        return None
    owned, local, owned_cells, local_cells, peaks, starts = (list(c) for c in zip(*got))
    return {"ranks": comm.size, "owned_vertices": owned, "local_vertices": local, "owned_cells": owned_cells,
            "local_cells": local_cells, "petsc_rows": list(owned), "peak_mb": peaks, "start_mb": starts}


def gather_cells(loc: LocalMesh, mask, values, comm=None):
    """Per-cell ``values`` of the cells ``mask`` of every rank, on rank 0 by global cell id.

    Parameters
    ----------
    loc : LocalMesh
        This rank's part.
    mask : (n_local_cells,) bool array
        The local cells to send (e.g. owned cells with a nonzero index).
    values : (mask.sum(), ...) array
        Their values, in local cell order.
    comm : mpi4py.MPI.Comm, optional
        Default :func:`world`.

    Returns
    -------
    ids : (k,) int array or None
        On rank 0 the global cell ids (rows of the whole mesh's cells), increasing; None elsewhere.
    values : (k, ...) array or None
        Their values; None elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> loc = distribute_tets(box_tet_mesh(2), None)
    >>> ids, vals = gather_cells(loc, loc.part.owned_cells, np.ones(int(loc.part.owned_cells.sum())))
    >>> ids.size, float(vals.sum())
    (48, 48.0)
    """
    comm = world() if comm is None else comm
    ids = loc.part.cells[mask]
    got = comm.gather((ids, np.asarray(values)), root=0)
    if comm.rank != 0:
        return None, None
    all_ids = np.concatenate([g[0] for g in got])
    all_vals = np.concatenate([g[1] for g in got])
    order = np.argsort(all_ids, kind="stable")
    return all_ids[order], all_vals[order]

