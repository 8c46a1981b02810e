"""Globally optimal n-direction fields (seed part 1, §5–§6): smoothest and aligned fields.

* **Smoothest field** (Eq. 6.5): the eigenvector of the smallest eigenvalue of ``A_s u = λ M u``
  (:func:`dhlb.fields.energy_matrices`, the engine's curvature-corrected matrices), computed by
  :func:`dhlb.fem.smallest_eigenpairs`; ``u`` is M-normalized and its energy is ``λ = uᴴ A_s u``.
* **Aligned field** (Eq. 6.6): ``(A_s − λ_t M) ũ = M q`` for a guidance field q, ``u = ũ/‖ũ‖_M``
  and ``t = (1 + ‖ũ‖_M)⁻¹`` for the guidance scaled to ``‖q‖_M = 1`` (Appendix A: t is the weight of
  the alignment term in ``E_{s,t} = (1 − t) E_s − t E_l``; it decreases strictly from 1 (λ_t → −∞,
  pure alignment) to 0 (λ_t → λ_1, the smoothest field); λ_t = 0 is the seed's default).
  Guidance: principal curvature through the discrete Hopf differential (``"curvature"``: q^{n/2};
  ``"min-curvature"``: (−q)^{n/2}), the boundary tangent (``"boundary"``, ``"boundary-normal"``),
  per-vertex 3D vectors, or per-vertex complex values in the frames of
  :class:`~dhlb.mesh.TangentBundle` (:mod:`dhlb.fields.guidance`).
  A flat mesh has no principal directions: curvature alignment then falls back to the smoothest
  field with a warning.
* **Several components.** The matrices are block diagonal; each component gets its own smallest
  eigenvector (or its own aligned solve), scaled so that ``‖u‖²_M`` on it is its share of the area.

The result carries the 3D directions, the per-face indices and singularities (mesh orientation)
and the Poincaré–Hopf check ``index_sum == poincare_hopf`` (``= nχ`` on closed meshes).

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.fields import direction_field
>>> res = direction_field(*read_surface(example_path("torus.obj")), n=4)
>>> res.index_sum, res.euler_characteristic, res.directions.shape[1:]
(0, 0, (4, 3))
"""

from __future__ import annotations

import numbers
import time
import warnings

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb._memory_errors import check_memory, translate_memory_errors
from dhlb.errors import DhlbWarning, InvalidParameterError, ShapeError
from dhlb.fields.directions import direction_vectors, field_indices
from dhlb.fields.energy import _tangent, check_s, energy_matrices
from dhlb.fields.guidance import Guidance, boundary_guidance, curvature_guidance, user_guidance
from dhlb.fields.options import FieldOptions
from dhlb.fields.result import DirectionField
from dhlb.linalg import SolverOptions, smallest_eigenpairs, solve, solver_options
from dhlb.linalg.backends import distributes, get_backend
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle

__all__ = ["direction_field", "guidance_for"]

_NAMED = ("curvature", "min-curvature", "boundary", "boundary-normal")


def guidance_for(tb: TangentBundle, align) -> Guidance:
    """The guidance field named by ``align`` (see :func:`direction_field`) on ``tb``.

    Parameters
    ----------
    tb : TangentBundle
        The tangent bundle (power n) of the mesh.
    align : {"curvature", "min-curvature", "boundary", "boundary-normal"}, Guidance or array
        A named guidance, a ready :class:`~dhlb.fields.Guidance`, or user vectors / values per vertex
        (:func:`~dhlb.fields.user_guidance`).

    Returns
    -------
    Guidance
        The guidance field on ``tb``.

    Raises
    ------
    ShapeError
        A :class:`~dhlb.fields.Guidance` with another number of values than ``tb`` has vertices.
    InvalidParameterError
        An unknown name.

    Examples
    --------
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.field import guidance_for
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], n=1)
    >>> guidance_for(tb, "boundary").kind
    'boundary'
    """
    if isinstance(align, Guidance):
        if np.shape(align.values) != (tb.mesh.n_vertices,):
            raise ShapeError(f"the guidance has {np.shape(align.values)} values for {tb.mesh.n_vertices} vertices")
        return align
    if isinstance(align, str):
        if align == "curvature":
            return curvature_guidance(tb, "max")
        if align == "min-curvature":
            return curvature_guidance(tb, "min")
        if align in ("boundary", "boundary-normal"):
            return boundary_guidance(tb, normal=align == "boundary-normal")
        raise InvalidParameterError(f"align must be one of {', '.join(_NAMED)}, an array of vectors/values or a "
                                    f"Guidance, got {align!r}")
    return user_guidance(tb, align)


def _check_lam(lam) -> float:
    if isinstance(lam, bool) or not isinstance(lam, numbers.Real) or not np.isfinite(lam):
        raise InvalidParameterError(f"lam must be a finite real number, got {lam!r}")
    return float(lam)


def _components(tb: TangentBundle) -> list[np.ndarray]:
    ncomp, label = tb.mesh.components
    if ncomp == 1:
        return [np.arange(tb.mesh.n_vertices)]
    return [np.nonzero(label == c)[0] for c in range(ncomp)]


def _sub(S, idx):
    return S[idx][:, idx]


DIRECTION_BYTES = 128
"""Peak bytes per vertex and direction of the n directions of a field (measured 106–112 B, rounded up)."""
LEAN_MIN_VERTICES = 250_000
"""From this many vertices on, :func:`direction_field` drops the mesh's cached arrays before the solve.

:meth:`dhlb.mesh.TangentBundle.release_caches`: at 655k vertices (the 1.31M-face icosphere) the peak
memory falls by 650 MiB, and recomputing what the indices need costs 2.5 s of 38 s.
"""
FIELD_BYTES_PER_FACE = 3_500
"""Peak bytes per face of :func:`direction_field` (measured 2.7–3.4 kB at 20k … 330k faces), for messages."""


def _vertex_rows(V) -> int:
    """The number of vertices of ``V`` (rows of an array, or of a mesh / tangent bundle), 0 if unknown."""
    mesh = getattr(V, "mesh", V)
    if hasattr(mesh, "n_vertices"):
        return int(mesh.n_vertices)
    try:
        return int(np.shape(V)[0])
    except (TypeError, ValueError, IndexError):
        return 0


def check_symmetry_memory(n: int, V) -> int:
    """Refuse a symmetry ``n`` whose ``n`` directions per vertex would not fit in memory; return the estimate.

    The work that grows with n is the ``(N, n, 3)`` array of directions (and its angles, sines and
    cosines on the way): about :data:`DIRECTION_BYTES` bytes a vertex and direction.

    Parameters
    ----------
    n : int
        The symmetry, already checked to be an integer >= 1.
    V : array or SurfaceMesh / TangentBundle
        The vertices (their number is what counts).

    Returns
    -------
    int
        The estimated bytes.

    Raises
    ------
    ResourceLimitError
        The estimate exceeds the memory available (free memory, the cgroup's and the address-space limit;
        :func:`dhlb.linalg.available_bytes`); the message gives the estimate and the largest n that fits.

    Examples
    --------
    >>> check_symmetry_memory(4, [[0, 0, 0]] * 1000)
    512000
    """
    rows = max(_vertex_rows(V), 1)
    per = DIRECTION_BYTES * rows
    return check_memory("n", n, per * int(n), largest=lambda room: (room // per) or None,
                        advice=f"the field has n directions at each of its {rows:,} vertices, about "
                               f"{DIRECTION_BYTES} bytes each")


def _field_estimate(V, F=None, n=None, *args, **kwargs):
    """``(bytes, what)`` for the message of a MemoryError: :data:`FIELD_BYTES_PER_FACE` a face, n directions."""
    faces = len(F) if F is not None else int(getattr(getattr(V, "mesh", V), "n_faces", 0))
    n = n if isinstance(n, numbers.Integral) else getattr(V, "n", 1)
    need = FIELD_BYTES_PER_FACE * faces + DIRECTION_BYTES * _vertex_rows(V) * int(n)
    return need, f"a field of {faces:,} faces ({FIELD_BYTES_PER_FACE / 1000:g} kB a face)"


def _under_mpi(V, F, n, s, align, lam, options, solver):
    """``direction_field`` with ``solver="petsc"`` under ``mpirun -n P`` (P > 1): the distributed form if there is one.

    The smoothest field goes to :func:`~dhlb.fields.distributed.distributed_direction_field` (collective) and
    rank 0 sends the field to the other ranks. An aligned field has no distributed form: rank 0 warns that every rank
    assembles the whole problem (PETSc distributes the factorization only) and None is returned.
    """
    from dhlb.fields.distributed import distributed_direction_field
    from dhlb.linalg.backends_petsc import comm_rank_size
    from dhlb.linalg.distributed import world

    if align is not None or lam != 0.0:
        if comm_rank_size()[0] == 0:
            warnings.warn("direction_field with align or lam is not distributed under mpirun: every rank assembles "
                          "the whole problem and the petsc backend distributes only its factorization (the smoothest "
                          "field, align=None, is distributed)", DhlbWarning, stacklevel=3)
        return None
    if isinstance(V, TangentBundle):
        n = V.n if n is None else n
        V = V.mesh
    if isinstance(V, SurfaceMesh):
        V, F = V.points, V.faces
    comm = world()
    res = distributed_direction_field(V, F, n=1 if n is None else n, s=s, solver=solver,
                                      options=options.replace(progress=False), comm=comm)
    return comm.bcast(res, root=0)   # the same script as on one process: every rank gets the field


@translate_memory_errors("direction_field", _field_estimate)
def direction_field(V, F=None, n: int | None = None, s: float = 0.0, align=None, lam: float = 0.0, *,
                    options: FieldOptions | None = None, solver: SolverOptions | str | None = None,
                    **deprecated) -> DirectionField:
    """The smoothest (or guidance-aligned) n-direction field of a triangle mesh.

    Parameters
    ----------
    V : (k, 3) float array, or SurfaceMesh / TangentBundle
        Vertex positions (or a mesh, then ``F`` is None).
    F : (m, 3) int array, optional
        Triangles (rows of ``V``).
    n : int >= 1, optional
        Symmetry: 1 vector field, 2 line field, 4 cross field (default: that of a TangentBundle
        ``V``, else 1).
    s : float in [−1, 1]
        Energy ``E_s = E_D − s(E_A − E_H)``; +1 holomorphic, −1 anti-holomorphic.
    align : None or str or array or Guidance
        None: smoothest field. ``"curvature"`` / ``"min-curvature"`` (even n), ``"boundary"`` /
        ``"boundary-normal"``, real ``(k, 3)`` vectors or complex ``(k,)`` values per vertex.
    lam : float
        λ_t of the aligned problem (must stay below the smallest eigenvalue).
    options : FieldOptions, optional
        Lumped mass, mesh repair (``repair``: the safe repairs by default, see :mod:`dhlb.mesh.repair`;
        ``reorient``, ``components``) and progress reporting (:class:`~dhlb.fields.FieldOptions`; default
        ``FieldOptions()``).
    solver : dhlb.linalg.SolverOptions or str, optional
        Backend and tolerance of the eigen solve or the aligned solve
        (:class:`~dhlb.linalg.SolverOptions`, or a backend name); the default tolerance
        :func:`dhlb.linalg.default_tol` scales with the mesh so that the singularities are those of a
        tol = 1e-14 solve.
    **deprecated
        The keywords ``lumped``, ``reorient``, ``components``, ``progress`` (→ ``options``), ``backend``
        and ``tol`` (→ ``solver``) of dhlb 0.1, with a :class:`DeprecationWarning`.

    Returns
    -------
    DirectionField
        Under ``mpirun -n P`` (P > 1) with ``solver="petsc"`` the smoothest field is computed by all ranks
        together (:func:`~dhlb.fields.distributed.distributed_direction_field`: no rank holds the global
        matrix; every rank must make the call, rank 0 with the mesh) and every rank gets it, so that a
        script written for one process runs unchanged (to keep it on rank 0 alone, call
        ``distributed_direction_field``). An aligned field is not distributed (every rank assembles it; a
        warning says so).

    Raises
    ------
    InvalidParameterError
        Bad n, s, lam or align (e.g. curvature alignment with odd n).
    ResourceLimitError
        The ``n`` directions per vertex would not fit in memory (:func:`check_symmetry_memory`): refused
        before any work, with the estimate and the largest n that fits.
    InsufficientMemoryError
        The computation ran out of memory all the same (a mesh too large for the memory available, e.g.
        under an address-space limit): the message says about how much it needs and how much is available.
    InvalidOperatorError
        ``A_s − λ_t M`` is singular or indefinite (aligned field with λ_t too large).
    TypeError
        An unknown keyword argument.

    Warns
    -----
    DhlbWarning
        Alignment requested but the guidance vanishes (flat mesh, no boundary): smoothest field. On a
        mesh of several components, the components where the guidance vanishes or where λ_t is not below
        the smallest eigenvalue (a flat triangle a repair cut off) get their smoothest field, with one
        warning for all of them.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.fields import FieldOptions, direction_field
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> res = direction_field(V, F, n=1)
    >>> res.index_sum, res.poincare_hopf          # Poincaré–Hopf on the octahedron: χ = 2
    (2, 2.0)
    >>> direction_field(V, F, n=1, options=FieldOptions(lumped=True), solver="superlu").index_sum
    2
    """
    from dhlb._progress import progress_bar

    options, solver = fold_deprecated_kwargs(
        "direction_field", deprecated, ("options", options, FieldOptions(), ("lumped", "reorient", "components",
                                                                            "progress")),
        ("solver", solver, SolverOptions(), ("backend", "tol")))
    solver = solver_options(solver)
    if distributes(solver.backend):
        out = _under_mpi(V, F, n, s, align, lam, options, solver)
        if out is not None:
            return out
    lumped, reorient, components, progress = options.lumped, options.reorient, options.components, options.progress
    backend = solver.backend

    t0 = time.perf_counter()
    s = check_s(s)
    lam = _check_lam(lam)
    faces = len(F) if F is not None else getattr(getattr(V, "mesh", V), "n_faces", 0)
    bar = progress_bar(3, "direction field", progress=progress, estimate_seconds=1.4e-5 * faces, unit="phase")
    if n is None:
        n = V.n if isinstance(V, TangentBundle) else 1
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InvalidParameterError(f"n must be an integer >= 1, got {n!r}")
    check_symmetry_memory(n, V)
    tb = _tangent(V, F, int(n), reorient, components, options.repair)
    guide = None
    if align is not None:
        guide = guidance_for(tb, align)
        if guide.empty:
            warnings.warn(f"no alignment: {guide.reason}; computing the smoothest field instead", DhlbWarning,
                          stacklevel=2)
            guide = None
    A, M = energy_matrices(tb, s=s, lumped=lumped)
    t1 = time.perf_counter()
    bar.update(1)

    N = tb.mesh.n_vertices
    u = np.zeros(N, np.complex128)
    area = np.asarray(tb.geometry.volumes(2)).sum()
    comps = _components(tb)
    eigs, ts, stats = [], [], []
    unaligned: list[tuple] = []   # components that get their smoothest field (one warning for all)
    if N >= LEAN_MIN_VERTICES:    # the assembly's cached arrays make room for the factor
        tb.release_caches()
    for ci, idx in enumerate(comps):
        Ac, Mc = (A, M) if len(comps) == 1 else (_sub(A, idx), _sub(M, idx))
        uc = None if guide is None else _aligned(Ac, Mc, guide.values[idx], lam, backend, stats, ts,
                                                 None if len(comps) == 1 else (ci, tb, idx, unaligned))
        if uc is None:
            res = smallest_eigenpairs(Ac, Mc, 1, solver=solver)
            uc = res.eigenvectors[:, 0]
            eigs.append(float(res.eigenvalues[0]))
            stats.append({"backend": res.backend, "iterations": int(res.iterations),
                          "residual": float(res.residuals[0]), "converged": bool(res.converged),
                          "factorizations": int(res.factorizations), "solves": int(res.solves),
                          "shift": float(res.shift), "note": res.note})
            del res  # its factor (L and U: 1.4 GB at 1.31M faces) is not needed for the directions and indices
        share = np.asarray(tb.geometry.volumes(2))[_faces_of(tb, idx)].sum() / area if len(comps) > 1 else 1.0
        u[idx] = uc * np.sqrt(share)
    if unaligned:
        faces = sum(k for _, k, _, _ in unaligned)
        ci, _, row, why = unaligned[0]
        warnings.warn(f"no alignment on {len(unaligned)} of {len(comps)} components ({faces} faces; first: "
                      f"component {ci}, with face {row} of F: {why}); they get their smoothest field", DhlbWarning,
                      stacklevel=2)
    t2 = time.perf_counter()
    bar.update(1)
    energy = float((u.conj() @ (A @ u)).real)
    dirs = direction_vectors(tb, u)
    indices = field_indices(tb, u)
    t3 = time.perf_counter()
    bar.update(1)
    bar.close()
    return DirectionField(
        n=int(n), s=s, lam=lam, tangent=tb, u=u, directions=dirs, indices=indices, energy=energy,
        eigenvalue=max(eigs) if eigs else None, t=(ts[0] if len(ts) == 1 else (max(ts) if ts else None)),
        guidance=guide, component_eigenvalues=tuple(eigs), solver=_merge(stats),
        timings={"setup": t1 - t0, "solve": t2 - t1, "indices": t3 - t2, "total": t3 - t0})


def _aligned(Ac, Mc, q, lam, backend, stats, ts, component):
    """The aligned field ``u`` on one component (Eq. 6.6), or None where it has none.

    ``component`` is None for a mesh of one component (a vanishing guidance or a λ_t that is not below
    the smallest eigenvalue is then an error), else ``(number, tangent bundle, vertices, unaligned)``:
    such a component (a flat triangle cut off by a repair, a flat part with no principal directions) is
    appended to ``unaligned`` (the caller warns once) and gets its smoothest field.
    """
    from dhlb.errors import InvalidOperatorError

    qn = float(np.sqrt(max((q.conj() @ (Mc @ q)).real, 0.0)))
    try:
        if qn == 0.0:
            raise InvalidParameterError("the guidance vanishes on a connected component; give guidance there")
        # Appendix A assumes ‖φ‖_M = 1; λ_t must lie below the smallest eigenvalue: A − λ_t M is PD
        ut = solve(Ac, Mc, lam, Mc @ (q / qn), backend=backend, positive_definite=True)
    except (InvalidParameterError, InvalidOperatorError):
        if component is None:
            raise
        ci, tb, idx, unaligned = component
        faces = np.flatnonzero(_faces_of(tb, idx))
        row = int(tb.mesh.face_rows[tb.mesh.face_of_triangle[faces[0]]])
        why = "the guidance vanishes there" if qn == 0.0 else f"λ_t = {lam:g} is not below its smallest eigenvalue"
        unaligned.append((ci, faces.size, row, why))
        return None
    norm = float(np.sqrt(max((ut.conj() @ (Mc @ ut)).real, 0.0)))
    ts.append(1.0 / (1.0 + norm))
    used = get_backend(backend, n=Ac.shape[0], nnz=Ac.nnz, eigen=False, shifted=False).name   # what solve() used
    stats.append({"backend": used, "iterations": 0, "residual": None, "converged": True,
                  "factorizations": 1, "solves": 1, "shift": float(lam), "note": ""})
    return ut / norm


def _faces_of(tb: TangentBundle, vertices: np.ndarray) -> np.ndarray:
    """Canonical triangles whose first vertex is in ``vertices`` (a component is closed under faces)."""
    tri = tb.mesh.complex.simplices(2)
    inside = np.zeros(tb.mesh.n_vertices, bool)
    inside[vertices] = True
    return inside[tri[:, 0]]


def _merge(stats: list[dict]) -> dict:
    if len(stats) == 1:
        return stats[0]
    out = dict(stats[0])
    for key in ("iterations", "factorizations", "solves"):
        out[key] = sum(int(st[key]) for st in stats)
    out["note"] = "; ".join(st["note"] for st in stats if st["note"])
    res = [st["residual"] for st in stats if st["residual"] is not None]
    out["residual"] = max(res) if res else None
    out["converged"] = all(st["converged"] for st in stats)
    out["components"] = len(stats)
    return out
