"""Vortex filaments of a velocity field on a tetrahedral mesh, end to end (seed part 3 §2.3).

The method of Weißmann, Pinkall and Schröder ("Smoke rings from smoke", 2014): the velocity
field ``v`` is the 1-form ``ω = ⟨v, ·⟩``; on the trivial line bundle with connection
``∇ψ = dψ − i ω ψ / ħ`` take the section ``ψ`` of unit L² norm with the least Dirichlet energy
``∫ |∇ψ|²`` (natural boundary conditions); its zero set is the filament configuration.  Where
``v`` is locally a gradient ``ħ ∇φ`` the section ``e^{iφ}`` is parallel, so the energy is spent
only near the vorticity, and every zero line of ψ carries the circulation ``2πħ``: a vortex
tube of circulation ``Γ`` is replaced by about ``Γ / 2πħ`` filaments.

:func:`vortex_filaments` runs the pipeline

========== =====================================================================================
phase      what
========== =====================================================================================
mesh       :func:`~dhlb.mesh.check_tet_mesh` (validate, orient) and the Euclidean geometry
omega      :func:`~dhlb.vortex.velocity_bundle`: ``ω_ij = ∫_ij v·dl`` (Gauss–Legendre),
           ``r = exp(iω/ħ)``, ``Ω = dω/ħ`` (real, not wrapped)
assembly   :func:`dhlb.fem.bundle_matrices`: mass and Dirichlet matrices of Theorems 15 and 17
           with their Ω-dependent terms (n = 3)
solve      :func:`dhlb.fem.smallest_eigenpairs`: ``A ψ = λ M ψ``, smallest λ, ``ψᴴ M ψ = 1``
extraction :func:`~dhlb.vortex.extract_filaments` (index form → crossed triangles → chains
           through tetrahedra → points at the zeros of the interpolant), then the Gauss linking
           numbers of the closed filaments (:func:`~dhlb.vortex.gauss_linking_integral`)
========== =====================================================================================

and returns a :class:`VortexResult` with the filaments, the section, statistics and the time of
each phase.  A triangle with ``|Ω| > π`` (the flux of ``curl v / ħ`` through it) means that the
mesh does not resolve the vortex core there; this is reported as an
:class:`~dhlb.errors.UnresolvedFluxWarning` naming the worst triangle.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import box_tet_mesh
>>> from dhlb.vortex import FilamentField, vortex_filaments, vortex_ring
>>> mesh = box_tet_mesh(8, lower=-1.5, upper=1.5)
>>> v = FilamentField([vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=48)], 2 * np.pi, core_radius=0.15)
>>> res = vortex_filaments(mesh.points, mesh.tets, v, hbar=1.0)
>>> len(res.filaments), res.filaments[0].closed
(1, True)
>>> bool(abs(np.vdot(res.psi, res.matrices[1] @ res.psi) - 1) < 1e-9)     # ψᴴ M ψ = 1
True
>>> sorted(res.timings)
['assembly', 'extraction', 'mesh', 'omega', 'solve', 'total']
"""

from __future__ import annotations

import time
import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb._memory_errors import translate_memory_errors
from dhlb.errors import (
    ShapeError,
    UnresolvedFluxWarning,
)
from dhlb.linalg import SolverOptions, solver_options
from dhlb.linalg.backends import distributes
from dhlb.mesh.tet import TetMesh, check_tet_mesh
from dhlb.vortex.filaments import extract_filaments
from dhlb.vortex.linking import filament_linking_numbers
from dhlb.vortex.options import DEFAULT_TOL, VortexOptions
from dhlb.vortex.velocity import _check_hbar, _per_vertex_velocity, velocity_bundle

if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

    from numpy.typing import ArrayLike

from dhlb.vortex.result import VortexResult

__all__ = ["VortexResult", "filament_linking_numbers", "vortex_filaments"]

def _warn_flux(X, points, Om) -> int:
    big = np.abs(Om) > np.pi
    nbig = int(big.sum())
    if nbig:
        t = int(np.argmax(np.abs(Om)))
        tri = X.simplices(2)[t]
        labels = tuple(int(v) for v in X.vertex_labels[tri])
        c = points[tri].mean(axis=0)
        warnings.warn(
            f"{nbig} triangles carry a flux |Ω| = |dω|/ħ > π; the largest, Ω = {Om[t]:.4g}, is on the triangle "
            f"{labels} (rows of V) near {np.round(c, 6).tolist()}: the mesh does not resolve the vortex core "
            "there, filaments may be misplaced or lost. Refine the mesh there, or increase ħ or the core radius.",
            UnresolvedFluxWarning, stacklevel=3)
    return nbig


_BYTES_PER_TET = 2_000  # VORTEX_BYTES_PER_CELL of dhlb.mesh.tet over the 6 tetrahedra of a cell, for messages


def _estimate(V, T=None, *args, **kwargs):
    tets = len(T) if T is not None else int(np.shape(getattr(V, "tets", ()))[0])
    return _BYTES_PER_TET * tets, f"a mesh of {tets:,} tetrahedra ({_BYTES_PER_TET / 1000:g} kB a tetrahedron)"


@translate_memory_errors("vortex_filaments", _estimate)
def vortex_filaments(
    V: ArrayLike | TetMesh,
    T: ArrayLike | None,
    velocity: Callable[[np.ndarray], np.ndarray] | ArrayLike,
    hbar: float,
    *,
    options: VortexOptions | None = None,
    solver: SolverOptions | str | None = None,
    progress: bool = False,
    **deprecated: Any,
) -> VortexResult:
    """Vortex filaments of a velocity field on a tetrahedral mesh (see the module docstring).

    Parameters
    ----------
    V : (n, 3) float array, or TetMesh
        Vertex positions; or an already validated :class:`~dhlb.mesh.TetMesh` (then ``T`` must
        be None).
    T : (m, 4) int array or None
        Tetrahedra (0-based rows of ``V``), any orientation (fixed per tetrahedron, see
        :func:`~dhlb.mesh.check_tet_mesh`).
    velocity : callable, (n, 3) array, or FilamentField
        ``v(x)`` mapping ``(k, 3)`` points to ``(k, 3)`` vectors (integrated along every edge by
        Gauss–Legendre with ``order`` nodes), or one vector per row of ``V`` (``mesh.points`` for a
        TetMesh), meaning the piecewise-linear field (integrated exactly).
    hbar : float > 0
        ħ: every filament carries the circulation ``2πħ``.
    options : VortexOptions, optional
        Quadrature ``order``, zero ``placement`` and tet ``orientation`` handling
        (:class:`~dhlb.vortex.VortexOptions`).
    solver : dhlb.linalg.SolverOptions or str, optional
        Backend and tolerance (default :data:`DEFAULT_TOL`) of :func:`dhlb.fem.smallest_eigenpairs`
        (:class:`~dhlb.linalg.SolverOptions`, or a backend name).
    progress : bool
        Show a progress bar over the five phases on stderr (needs tqdm, ``pip install
        'dhlb[progress]'``) when the run is expected to take more than about two seconds.
    **deprecated
        The keywords ``order``, ``placement``, ``orientation`` (→ ``options``), ``backend`` and ``tol``
        (→ ``solver``) of dhlb 0.1, with a :class:`DeprecationWarning`.

    Returns
    -------
    VortexResult
        Under ``mpirun -n P`` (P > 1) with ``solver="petsc"``, the filaments are computed by all ranks
        together (:func:`~dhlb.vortex.distributed.distributed_vortex_filaments`: no rank holds the global
        matrix; every rank must make the call, rank 0 with the mesh) and every rank gets the result (its
        ``bundle``, ``filament_set`` and ``matrices`` None); to keep it on rank 0 alone, call
        ``distributed_vortex_filaments``.

    Raises
    ------
    InvalidParameterError
        ``hbar`` not a finite number > 0 (options are checked when they are built); an old keyword
        together with ``options`` or ``solver``.
    InvalidTypeError
        ``hbar`` is not a real number (a string, a complex number).
    TypeError
        An unknown keyword argument.
    ShapeError, NonFiniteError
        ``V``/``T`` malformed; a velocity array not of shape (n, 3), not real, or NaN/inf (the
        vertex is named); a callable returning the wrong shape or NaN/inf (the edge and point are
        named).
    DegenerateSimplexError, InconsistentOrientationError, NonManifoldError
        Flat tetrahedra, folded (inverted) tetrahedra, a non-manifold mesh: the element is named
        (:func:`~dhlb.mesh.check_tet_mesh`).
    SectionZeroError
        The computed ψ vanishes exactly at a vertex (perturb the mesh).
    InsufficientMemoryError
        The computation ran out of memory (a mesh too large for the memory available, e.g. under an
        address-space limit): the message says about how much it needs and how much is available.

    Warns
    -----
    UnresolvedFluxWarning
        Some triangle has ``|Ω| > π`` (the worst one is named).
    DhlbWarning
        Tetrahedra crossed by more than one filament; touching filaments (linking number guessed).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.linalg import SolverOptions
    >>> from dhlb.vortex import FilamentField, VortexOptions, vortex_filaments, vortex_ring
    >>> ring = vortex_ring(0.8, center=(0.01, 0.02, 0.03), n=32)
    >>> v = FilamentField([ring], 2 * np.pi, core_radius=0.2)    # circulation 2πħ: one filament
    >>> res = vortex_filaments(box_tet_mesh(6, lower=-1.5, upper=1.5), None, v, hbar=1.0)
    >>> len(res.filaments), res.filaments[0].closed
    (1, True)
    >>> res = vortex_filaments(box_tet_mesh(6, lower=-1.5, upper=1.5), None, v, hbar=1.0,
    ...                        options=VortexOptions(order=6), solver=SolverOptions(backend="superlu", tol=1e-10))
    >>> len(res.filaments)
    1
    """
    options, solver = fold_deprecated_kwargs(
        "vortex_filaments", deprecated, ("options", options, VortexOptions(), ("order", "placement", "orientation")),
        ("solver", solver, SolverOptions(), ("backend", "tol")))
    solver = solver_options(solver)
    if distributes(solver.backend):   # petsc under mpirun -n P > 1: all ranks together, no global matrix
        from dhlb.linalg.distributed import world
        from dhlb.vortex.distributed import distributed_vortex_filaments

        comm = world()
        res = distributed_vortex_filaments(V, T, velocity, hbar, options=options, solver=solver, comm=comm)
        return comm.bcast(res, root=0)   # the same script as on one process: every rank gets the result
    solver = solver if solver.tol is not None else solver.replace(tol=DEFAULT_TOL)
    order, placement, orientation, backend = options.order, options.placement, options.orientation, solver.backend
    h = _check_hbar(hbar)
    from dhlb._progress import progress_bar
    from dhlb.fem import bundle_matrices, smallest_eigenpairs
    from dhlb.geometry import EuclideanComplex

    timings = {}
    t0 = t = time.perf_counter()
    n_tets = V.tets.shape[0] if isinstance(V, TetMesh) else len(T) if T is not None else 0
    bar = progress_bar(5, "vortex filaments", progress=progress, estimate_seconds=4e-5 * n_tets, unit="phase")
    if isinstance(V, TetMesh):
        if T is not None:
            raise ShapeError("pass either a TetMesh as V (and T=None) or the arrays V and T")
        mesh, n_rows, rows = V, V.points.shape[0], np.arange(V.points.shape[0])
    else:
        mesh = check_tet_mesh(V, T, orientation=orientation)
        n_rows, rows = np.shape(V)[0], np.asarray(mesh.complex.vertex_labels)
    X, P = mesh.complex, mesh.points
    if not callable(velocity):
        velocity = _per_vertex_velocity(velocity, n_rows, rows)
    geo = EuclideanComplex(X, points=P)
    geo.barycentric_gradient_gram  # noqa: B018 -- geometry belongs to the mesh phase
    timings["mesh"] = (t1 := time.perf_counter()) - t
    with bar:
        bar.update(1)
        L = velocity_bundle(X, P, velocity, h, order=order)
        n_unresolved = _warn_flux(X, P, L.curvature)
        timings["omega"] = (t2 := time.perf_counter()) - t1
        bar.update(1)
        A, M = bundle_matrices(L, geo)
        timings["assembly"] = (t3 := time.perf_counter()) - t2
        bar.update(1)
        eig = smallest_eigenpairs(A, M, k=1, solver=solver)
        psi = np.asarray(eig.eigenvectors[:, 0])
        timings["solve"] = (t4 := time.perf_counter()) - t3
        bar.update(1)
        fs = extract_filaments(L, psi, P, placement=placement)
        Lk, lidx, defect = filament_linking_numbers(fs.filaments)
        timings["extraction"] = (t5 := time.perf_counter()) - t4
        bar.update(1)
    timings["total"] = t5 - t0

    crossed = np.count_nonzero(fs.index[X.faces(3)], axis=1)
    hist = np.bincount(crossed, minlength=5)
    n_closed = sum(f.closed for f in fs.filaments)
    stats = {
        "n_vertices": int(X.n_vertices), "n_edges": int(X.n_simplices(1)), "n_triangles": int(X.n_simplices(2)),
        "n_tets": int(X.n_simplices(3)), "hbar": h,
        "max_flux": float(np.abs(L.curvature).max()) if L.curvature.size else 0.0,
        "n_unresolved_faces": n_unresolved,
        "n_crossed_faces": int(np.count_nonzero(fs.index)),
        "tets_by_crossed_faces": {str(k): int(c) for k, c in enumerate(hist) if c},
        "n_filaments": len(fs), "n_closed": int(n_closed), "n_open": int(len(fs) - n_closed),
        "ambiguous_tets": int(fs.ambiguous_tets.size), "tie_edges": int(fs.tie_edges.size),
        "clamped_faces": int(fs.clamped_faces.size), "degenerate_faces": int(fs.degenerate_faces.size),
        "linking_defect": defect,
        "solver": {"backend": str(getattr(eig, "backend", backend)), "iterations": int(getattr(eig, "iterations", -1)),
                   "converged": bool(getattr(eig, "converged", True)),
                   "residual": float(np.max(getattr(eig, "residuals", [np.nan]))),
                   "shift": float(getattr(eig, "shift", np.nan))},
    }
    return VortexResult(list(fs.filaments), psi, float(eig.eigenvalues[0]), Lk, lidx, stats, timings, mesh, L, fs,
                        (A, M))
