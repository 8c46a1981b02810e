"""Vortex filaments under MPI: each rank assembles, solves and extracts only its part of the tet mesh.

:func:`distributed_vortex_filaments` is :func:`~dhlb.vortex.vortex_filaments` for ``mpirun -n P``;
it is collective, and every rank calls it (rank 0 with the mesh, the others may pass None):

========== ===========================================================================================
phase      what each rank does
========== ===========================================================================================
mesh       rank 0 validates the whole mesh, partitions it (METIS) and sends each rank its owned vertices
           and one layer of halo tetrahedra (:func:`dhlb.mesh.distribute.distribute_tets`)
omega      :func:`~dhlb.vortex.velocity_bundle` on the local complex
assembly   :func:`dhlb.fem.bundle_matrices` on the local mesh, unchanged; the owned rows (bit for bit
           those of the serial assembly) go to PETSc
solve      :func:`dhlb.linalg.distributed_eigen.distributed_eigenpairs`: the owned rows of ψ
extraction the halo values of ψ by a scatter; the filament pieces through the owned tetrahedra,
           keyed by global triangle (:func:`~dhlb.vortex.filament_pieces`); rank 0 stitches them
           (:func:`~dhlb.vortex.stitch_pieces`) and computes the linking numbers
========== ===========================================================================================

Rank 0 returns a :class:`~dhlb.vortex.VortexResult` of the whole mesh (``psi`` gathered, in the
vertex numbering of the validated mesh); its ``bundle``, ``filament_set`` and ``matrices`` are None
(no rank holds them whole). The other ranks return None.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import box_tet_mesh
>>> from dhlb.linalg.backends_petsc import petsc_available
>>> from dhlb.vortex import FilamentField, vortex_ring
>>> v = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=48)], 2 * np.pi, core_radius=0.15)
>>> res = (distributed_vortex_filaments(box_tet_mesh(8, lower=-1.5, upper=1.5), None, v, 1.0)
...        if petsc_available() else None)
>>> res is None or (len(res.filaments), res.filaments[0].closed) == (1, True)
True
"""

from __future__ import annotations

import warnings

import numpy as np

from dhlb._phases import PhaseMeter, trim_heap
from dhlb.errors import ShapeError, UnresolvedFluxWarning
from dhlb.linalg import SolverOptions, solver_options
from dhlb.vortex.linking import filament_linking_numbers
from dhlb.vortex.options import DEFAULT_TOL, VortexOptions
from dhlb.vortex.result import VortexResult
from dhlb.vortex.velocity import _check_hbar, _per_vertex_velocity, velocity_bundle

__all__ = ["distributed_vortex_filaments"]


def distributed_vortex_filaments(V, T, velocity, hbar: float, *, options: VortexOptions | None = None,
                                 solver: SolverOptions | str | None = None, comm=None) -> VortexResult | None:
    """Vortex filaments of a velocity field on a tetrahedral mesh, computed by all MPI ranks together.

    Parameters
    ----------
    V : (n, 3) float array, TetMesh, LocalMesh or None
        Vertex positions or a validated :class:`~dhlb.mesh.TetMesh` (rank 0; None elsewhere); or, on every
        rank, its part of a mesh already distributed (:func:`dhlb.mesh.distribute.distribute_box`).
    T : (m, 4) int array or None
        Tetrahedra (rank 0, unless ``V`` is a TetMesh).
    velocity : callable or (n, 3) array
        ``v(x)`` (every rank needs it: pass the same callable everywhere), or one vector per row of
        ``V`` (rank 0; sent with the mesh).
    hbar : float > 0
        ħ: every filament carries the circulation ``2πħ``.
    options : VortexOptions, optional
        As :func:`~dhlb.vortex.vortex_filaments`.
    solver : SolverOptions or str, optional
        Only ``tol`` is used (default :data:`~dhlb.vortex.options.DEFAULT_TOL`).
    comm : mpi4py.MPI.Comm, optional
        Default ``MPI_COMM_WORLD``.

    Returns
    -------
    VortexResult or None
        On rank 0 (``bundle``, ``filament_set`` and ``matrices`` None); None on the other ranks.

    Raises
    ------
    DhlbError
        As :func:`~dhlb.vortex.vortex_filaments`, on every rank.

    Warns
    -----
    UnresolvedFluxWarning
        Some triangle has ``|Ω| > π`` (rank 0 names the worst one).
    """
    from dhlb._deprecation import check_option_group
    from dhlb.fem import bundle_matrices
    from dhlb.geometry import EuclideanComplex
    from dhlb.linalg.distributed import scatter_values
    from dhlb.linalg.distributed_eigen import distributed_eigenpairs
    from dhlb.mesh.distribute import LocalMesh, distribute_tets, gather_owned, parallel_report, world
    from dhlb.vortex.stitch import filament_pieces, stitch_pieces

    comm = world() if comm is None else comm
    if options is not None:
        check_option_group("distributed_vortex_filaments", "options", options, VortexOptions())
    options = VortexOptions() if options is None else options
    solver = solver_options(solver)
    tol = solver.tol if solver.tol is not None else DEFAULT_TOL
    h = _check_hbar(hbar)
    meter = PhaseMeter()
    array_velocity = not callable(velocity)
    per_vertex = None
    if array_velocity:
        def per_vertex(gm):
            rows = np.asarray(gm.complex.vertex_labels)
            n_rows = int(rows.max()) + 1 if V is gm else np.shape(V)[0]
            out = np.zeros((n_rows, 3))
            out[rows] = _per_vertex_velocity(velocity, n_rows, rows)
            return out
    if isinstance(V, LocalMesh):   # already distributed (e.g. dhlb.mesh.distribute.distribute_box)
        if T is not None or array_velocity:
            raise ShapeError("with a distributed mesh (LocalMesh) as V, T must be None and velocity a callable v(x)")
        loc = V
    else:
        loc = distribute_tets(V, T, orientation=options.orientation, vertex_values=per_vertex, comm=comm)
    part, N = loc.part, loc.n_vertices
    X, P = loc.mesh.complex, loc.mesh.points
    geo = EuclideanComplex(X, points=P)
    geo.barycentric_gradient_gram  # noqa: B018 -- geometry belongs to the mesh phase
    meter.mark("mesh")
    L = velocity_bundle(X, P, loc.vertex_values if array_velocity else velocity, h, order=options.order)
    Om = L.curvature
    tri = X.simplices(2)
    owned_tri = part.owns(tri)
    meter.mark("omega")
    A, M = bundle_matrices(L, geo)
    Ab, Mb = loc.row_block(A), loc.row_block(M)
    del A, M
    trim_heap()   # the assembly's temporaries, before the factorization
    meter.mark("assembly")
    eig = distributed_eigenpairs(Ab, Mb, 1, tol=tol)
    del Ab, Mb
    meter.mark("solve")
    psi_own = np.asarray(eig.vectors[:, 0], np.complex128)
    psi_loc = scatter_values(psi_own, loc.start, loc.stop, N, part.vertices)
    on_boundary = np.zeros(tri.shape[0], bool)
    if loc.boundary_faces.size:   # the whole mesh's boundary triangles with local vertices that are in the patch
        B = loc.boundary_faces[X.contains(2, loc.boundary_faces)]
        on_boundary[X.index(2, B)] = True
    owned_tets = loc.mesh.index[part.owned_cells]   # rows of X.simplices(3)
    pieces = filament_pieces(L, psi_loc, P, owned_tets, vertex_ids=part.vertices, boundary=on_boundary,
                             placement=options.placement)
    crossed = np.zeros(tri.shape[0], bool)   # the triangles the pieces cross: those of the owned tets with index != 0
    for piece in pieces:
        crossed[X.index(2, np.searchsorted(part.vertices, piece.faces))] = True
    by_crossed = np.bincount(np.count_nonzero(crossed[X.faces(3)[owned_tets]], axis=1), minlength=5)
    by_crossed = comm.allreduce(by_crossed)
    all_pieces = comm.gather(pieces, root=0)
    big = np.abs(Om) > np.pi
    flux = (float(np.abs(Om).max()) if Om.size else 0.0, int(np.count_nonzero(big & owned_tri)))
    worst = int(np.argmax(np.abs(Om))) if Om.size else -1
    worst_info = (flux[0], tuple(int(v) for v in part.vertices[tri[worst]]) if worst >= 0 else (),
                  P[tri[worst]].mean(axis=0).tolist() if worst >= 0 else [])
    fluxes = comm.gather(worst_info, root=0)
    n_unresolved = comm.allreduce(flux[1])
    n_edges = comm.allreduce(int(np.count_nonzero(part.owns(X.simplices(1)))))
    n_tri = comm.allreduce(int(np.count_nonzero(owned_tri)))
    psi_all = gather_owned(loc, psi_own, comm)
    meter.mark("extraction")
    parallel = parallel_report(loc, meter, comm)
    if comm.rank != 0:
        return None
    fs = stitch_pieces(all_pieces)
    n_crossed = np.unique(np.concatenate([f.faces for f in fs] + [np.zeros((0, 3), np.int64)]), axis=0).shape[0]
    Lk, lidx, defect = filament_linking_numbers(fs.pieces)
    meter.mark("extraction")
    t = dict(meter.seconds, total=meter.total)
    if n_unresolved:
        val, labels, c = max(fluxes, key=lambda f: f[0])
        rows = tuple(int(v) for v in loc.input_rows[loc.layout.order[list(labels)]])
        warnings.warn(
            f"{n_unresolved} triangles carry a flux |Ω| = |dω|/ħ > π; the largest, |Ω| = {val:.4g}, is on the "
            f"triangle {rows} (rows of V) near {np.round(c, 6).tolist()}: the mesh does not resolve the vortex core "
            "there, filaments may be misplaced or lost. Refine the mesh there, or increase ħ or the core radius.",
            UnresolvedFluxWarning, stacklevel=2)
    n_closed = sum(f.closed for f in fs)
    parallel["method"] = eig.method
    stats = {
        "n_vertices": int(N), "n_edges": int(n_edges), "n_triangles": int(n_tri), "n_tets": int(loc.n_cells),
        "hbar": h, "max_flux": max(f[0] for f in fluxes), "n_unresolved_faces": int(n_unresolved),
        "n_crossed_faces": int(n_crossed),
        "tets_by_crossed_faces": {str(k): int(c) for k, c in enumerate(by_crossed) if c},
        "n_filaments": len(fs), "n_closed": int(n_closed), "n_open": int(len(fs) - n_closed),
        "ambiguous_tets": len(fs.ambiguous_tets), "tie_edges": len(fs.tie_edges),
        "clamped_faces": len(fs.clamped_faces), "degenerate_faces": len(fs.degenerate_faces),
        "linking_defect": defect,
        "solver": {"backend": "petsc", "iterations": int(eig.iterations), "converged": bool(eig.converged),
                   "residual": float(eig.residuals[0]), "shift": float(eig.shift), "parallel": parallel,
                   "mumps": eig.stats},
    }
    return VortexResult(list(fs.pieces), psi_all, float(eig.eigenvalues[0]), Lk, lidx, stats, t, loc.global_mesh,
                        None, None, None)
