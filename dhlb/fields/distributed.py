"""The smoothest n-direction field under MPI: each rank assembles and solves only its part of the mesh.

:func:`distributed_direction_field` is :func:`~dhlb.fields.direction_field` (smoothest field) for
``mpirun -n P``; it is collective, and every rank calls it (rank 0 with the mesh, the others may
pass None):

========== ===========================================================================================
phase      what each rank does
========== ===========================================================================================
distribute rank 0 validates the whole mesh, partitions it (METIS) and sends each rank its owned vertices
           and two rings of halo faces (:func:`dhlb.mesh.distribute.distribute_surface`)
assembly   the tangent bundle and :func:`~dhlb.fields.energy_matrices` of the *local* mesh, unchanged;
           the owned rows (bit for bit those of the serial assembly) go to PETSc
solve      :func:`dhlb.linalg.distributed_eigen.distributed_eigenpairs` (SLEPc, MUMPS): the owned rows of the
           eigenvector
indices    the halo values of ``u`` by a scatter; directions of the owned vertices and indices of the
           owned faces (:func:`~dhlb.fields.field_indices` with ``faces=``) on the local mesh;
           Poincaré–Hopf terms summed over the ranks
gather     rank 0 collects ``u``, directions, frames and the singularities and returns the
           :class:`~dhlb.fields.DirectionField` of the whole mesh (the other ranks return None)
========== ===========================================================================================

No rank ever holds a global matrix; rank 0 alone holds the whole mesh (it read it) and the
gathered per-vertex results. The result's ``solver`` dict has a ``"parallel"`` entry: the ranks,
each rank's owned and local vertex counts, the rows it handed to PETSc and its peak memory per
phase.

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.linalg.backends_petsc import petsc_available
>>> V, F = read_surface(example_path("torus.obj"))
>>> res = distributed_direction_field(V, F, n=4) if petsc_available() else None   # one process here
>>> res is None or (res.index_sum, res.solver["parallel"]["ranks"]) == (0, 1)
True
"""

from __future__ import annotations

import numbers

import numpy as np

from dhlb._phases import PhaseMeter, trim_heap
from dhlb.errors import InvalidParameterError
from dhlb.fields.directions import FieldIndices, Singularities, direction_vectors, field_indices
from dhlb.fields.energy import check_s, energy_matrices
from dhlb.fields.options import FieldOptions
from dhlb.fields.result import DirectionField
from dhlb.linalg import SolverOptions, default_tol, solver_options
from dhlb.linalg._checks import phase_factors
from dhlb.mesh.tangent import TangentBundle

__all__ = ["distributed_direction_field"]


def distributed_direction_field(V, F=None, n: int = 1, s: float = 0.0, *, options: FieldOptions | None = None,
                                solver: SolverOptions | str | None = None, comm=None) -> DirectionField | None:
    """The smoothest n-direction field of a triangle mesh, computed by all MPI ranks together.

    Parameters
    ----------
    V : (k, 3) float array or None
        Vertex positions (rank 0; the other ranks may pass None).
    F : (m, 3) int array or None
        Triangles (rank 0; None elsewhere).
    n : int >= 1
        Symmetry: 1 vector, 2 line, 4 cross field.
    s : float in [−1, 1]
        Energy ``E_s = E_D − s(E_A − E_H)``.
    options : FieldOptions, optional
        ``lumped``, ``reorient`` and ``components`` as for :func:`~dhlb.fields.direction_field`
        (``progress`` is ignored).
    solver : SolverOptions or str, optional
        Only ``tol`` is used (default :func:`dhlb.linalg.default_tol` of the global vertex count); the
        solver is SLEPc's (:func:`dhlb.linalg.distributed_eigen.distributed_eigenpairs`).
    comm : mpi4py.MPI.Comm, optional
        Default ``MPI_COMM_WORLD``.

    Returns
    -------
    DirectionField or None
        The field of the whole mesh on rank 0 (vertex numbering of ``validate_surface(V, F)``, as
        :func:`~dhlb.fields.direction_field`); None on the other ranks.

    Raises
    ------
    InvalidParameterError
        Bad ``n`` or ``s``; a mesh of several connected components (compute the components one by one,
        or pass ``FieldOptions(components="largest")``).
    DhlbError
        Invalid meshes as :func:`~dhlb.mesh.validate_surface`, raised on every rank.
    InvalidOperatorError
        The eigensolver failed (PETSc's message and code).

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> from dhlb.linalg.backends_petsc import petsc_available
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> if petsc_available():
    ...     res = distributed_direction_field(V, F, n=4)
    ...     ok = res.index_sum == direction_field(V, F, n=4).index_sum
    ... else:
    ...     ok = True
    >>> ok
    True
    """
    from dhlb._deprecation import check_option_group
    from dhlb.linalg.distributed import scatter_values
    from dhlb.linalg.distributed_eigen import distributed_eigenpairs
    from dhlb.mesh.distribute import distribute_surface, gather_cells, gather_owned, parallel_report, world

    comm = world() if comm is None else comm
    if options is not None:
        check_option_group("distributed_direction_field", "options", options, FieldOptions())
    options = FieldOptions() if options is None else options
    solver = solver_options(solver)
    s = check_s(s)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InvalidParameterError(f"n must be an integer >= 1, got {n!r}")
    n = int(n)
    meter = PhaseMeter()
    loc = distribute_surface(V, F, reorient=options.reorient, components=options.components, connected=True,
                             comm=comm)
    meter.mark("distribute")
    part, N = loc.part, loc.n_vertices
    tb = TangentBundle(loc.mesh, n)
    A, M = energy_matrices(tb, s=s, lumped=options.lumped)
    Ab, Mb = loc.row_block(A), loc.row_block(M)
    A_own = A[part.owned]   # the owned rows in local columns, for the energy
    del A, M
    trim_heap()   # the assembly's temporaries, before the factorization
    meter.mark("assembly")
    tol = solver.tol if solver.tol is not None else default_tol(N)
    eig = distributed_eigenpairs(Ab, Mb, 1, tol=tol)
    del Ab, Mb
    meter.mark("solve")
    u_own = np.asarray(eig.vectors[:, 0], np.complex128)
    # the phase of one process (dhlb.linalg.eigen: the largest-modulus entry, first in the vertex numbering,
    # real positive), so that the directions are those of direction_field, not turned by a global angle
    u_all = gather_owned(loc, u_own, comm)
    turn = comm.bcast(phase_factors(u_all[:, None])[0] if comm.rank == 0 else None, root=0)
    u_own = u_own * turn
    if u_all is not None:
        u_all = u_all * turn
    u_loc = scatter_values(u_own, loc.start, loc.stop, N, part.vertices)
    fi = field_indices(tb, u_loc, faces=part.owned_cells)
    dirs = direction_vectors(tb, u_loc)[part.owned]
    energy = comm.allreduce(float(np.vdot(u_own, A_own @ u_loc).real))
    total_curv = comm.allreduce(fi.total_curvature)
    rot = comm.allreduce(fi.boundary_rotation)
    sing = fi.singularities
    mine = np.zeros(loc.mesh.n_faces, bool)
    mine[sing.faces] = True   # the owned singular faces (only owned faces have a nonzero index), increasing
    meter.mark("indices")
    d_all = gather_owned(loc, dirs, comm)
    fr_all = gather_owned(loc, tb.frames[part.owned], comm)
    ids, vals = gather_cells(loc, mine, np.column_stack([sing.index, sing.barycentric, sing.points]), comm)
    meter.mark("gather")
    parallel = parallel_report(loc, meter, comm)
    if comm.rank != 0:
        return None
    t = meter.seconds
    gm = loc.global_mesh
    tb_g = TangentBundle(gm, n)
    tb_g.__dict__["frames"] = fr_all      # the owners' frames (bit for bit those of the whole mesh)
    face_index = np.zeros(gm.n_faces, np.int64)
    face_index[ids] = vals[:, 0].astype(np.int64)
    sing_g = Singularities(ids, gm.face_rows[ids], vals[:, 0].astype(np.int64), vals[:, 1:4], vals[:, 4:7])
    indices = FieldIndices(face_index, int(face_index.sum()), total_curv, rot, (total_curv + rot) / (2 * np.pi),
                           sing_g)
    parallel["method"] = eig.method
    stats = {"backend": "petsc", "iterations": int(eig.iterations), "residual": float(eig.residuals[0]),
             "converged": bool(eig.converged), "factorizations": int(eig.factorizations), "solves": int(eig.solves),
             "shift": float(eig.shift), "note": eig.note, "parallel": parallel, **{"mumps": eig.stats}}
    lam = float(eig.eigenvalues[0])
    return DirectionField(n=n, s=s, lam=0.0, tangent=tb_g, u=u_all, directions=d_all, indices=indices, energy=energy,
                          eigenvalue=lam, t=None, guidance=None, component_eigenvalues=(lam,), solver=stats,
                          timings={"setup": t["distribute"] + t["assembly"], "indices": t["indices"] + t["gather"],
                                   **t, "total": meter.total})
