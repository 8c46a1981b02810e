"""Stripe patterns end to end (seed part 2, Alg. 4): directions + frequency → ψ → texture coordinates.

:func:`stripe_pattern` validates the mesh, builds the stripe form ω̂ and the double-cover bundle
(:func:`~dhlb.stripes.stripe_form`), the energy (:func:`~dhlb.stripes.energy.stripe_matrices`:
the cotangent connection Laplacian of the O(2) bundle without branch triangles and the lumped
mass, or the curvature-corrected FEM matrices), solves for the smallest eigenpair with
:func:`dhlb.fem.smallest_eigenpairs` (to a backward error ``tol``, not a fixed number of
iterations) and computes the texture coordinates (:func:`~dhlb.stripes.texture_coordinates`).

**Units.** ``frequency`` is in stripes per unit length (period ``1/frequency``, ``ν = 2π·frequency``);
``spacing`` is the period in mean edge lengths (scale independent).

**Numbering.** Inside the result everything is in the compact numbering of ``result.mesh``
(vertex v = input row ``mesh.vertex_rows[v]`` of V, face f = input row ``mesh.face_rows[f]`` of
F); :meth:`StripePattern.to_json` reports faces as input rows of F.

Examples
--------
>>> import numpy as np
>>> from dhlb.stripes import stripe_pattern
>>> x, y = np.meshgrid(np.arange(5.0), np.arange(4.0), indexing="ij")
>>> V = np.stack([x.ravel(), y.ravel(), 0 * x.ravel()], 1)
>>> a = (np.arange(4)[:, None] * 4 + np.arange(3)).ravel()
>>> F = np.concatenate([np.stack([a, a + 4, a + 5], 1), np.stack([a, a + 5, a + 1], 1)])
>>> res = stripe_pattern(V, F, np.tile([1.0, 0.0, 0.0], (len(V), 1)), frequency=0.25)
>>> res.zero_faces.size, res.branch_faces.size, abs(res.eigenvalue) < 1e-9
(0, 0, True)
>>> alpha = res.texture.evaluate([0, 0], [[1, 0, 0], [0, 1, 0]])   # from x = 0 to x = 1: Δα = 2π/4
>>> round(float(alpha[1] - alpha[0]) / np.pi, 10)
0.5
>>> sorted(res.to_json())[:4]
['branch_faces', 'eigenvalue', 'energy', 'frequency']
"""

from __future__ import annotations

import numbers
import time
import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb._memory_errors import translate_memory_errors
from dhlb.errors import DhlbWarning, InvalidParameterError, NotSemidefiniteError
from dhlb.fem import SolverOptions, select_backend, smallest_eigenpairs
from dhlb.linalg import solver_options
from dhlb.linalg.backends import get_backend
from dhlb.mesh.repair import repair_surface
from dhlb.mesh.surface import SurfaceMesh
from dhlb.mesh.tangent import TangentBundle
from dhlb.stripes.energy import stripe_matrices
from dhlb.stripes.oneform import stripe_form
from dhlb.stripes.options import SECTIONS, SectionOptions, StripeOptions
from dhlb.stripes.section import (
    MAX_UNIT_ITERATIONS,
    POWER_ITERATIONS,
    normalize_per_vertex,
    power_section,
    unit_energy,
    unit_section,
)
from dhlb.stripes.texture import texture_coordinates

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike
from dhlb.stripes.result import StripePattern

__all__ = ["SECTIONS", "StripePattern", "stripe_pattern"]   # SECTIONS: re-exported from dhlb.stripes.options

DEFAULT_TOL = 1e-10
"""Default backward-error tolerance of the eigenpair (``SolverOptions.tol`` when it is None)."""


def _is_field(obj) -> bool:
    return all(hasattr(obj, a) for a in ("mesh", "n", "directions")) and isinstance(obj.mesh, SurfaceMesh)


def _surface(V, F, reorient, components, fld=None, repair="none"):
    if isinstance(V, TangentBundle):
        V = V.mesh
    if isinstance(V, SurfaceMesh):
        if F is not None:
            raise InvalidParameterError("pass either a SurfaceMesh (or TangentBundle) as V with F=None, or arrays V, F")
        return V
    if F is None:
        raise InvalidParameterError("stripe_pattern needs the face array F (or a SurfaceMesh / direction field as V)")
    if fld is not None and fld.mesh.is_validation_of(V, F, components):
        return fld.mesh
    return repair_surface(V, F, repair, reorient=reorient, components=components)   # "none": validate_surface


def _field_n(fld, n):
    """The directions (the field itself, which stripe_form reads) and the n to use with a direction field."""
    fn = int(fld.n)
    if fn not in (1, 2):
        raise InvalidParameterError(f"stripes need a vector field (n = 1) or a line field (n = 2); the direction "
                                    f"field has n = {fn}")
    if n is None:
        n = fn
    elif n < fn:
        raise InvalidParameterError("the direction field is a line field (n = 2): its directions have no consistent "
                                    "orientation, so it cannot drive an oriented (n = 1) pattern; use n=2")
    return fld, n


def _indefinite(A, M, solver):
    """Smallest eigenpair of an indefinite A (negative cotan weights): shift-invert just below it.

    A Gershgorin bound ``low`` is below every eigenvalue, but often far below (-3e5 on the ogre, whose
    smallest eigenvalue is -6.2): shift-invert there sees a cluster and does not converge. So the shift
    is the first of ``low · 10⁻ᵏ`` (k = 6 … 0) at which ``A − σM`` is positive definite (a factorization
    with a pivot check: Sylvester's law of inertia), at most ten times below the smallest eigenvalue.
    """
    from dhlb.errors import InvalidOperatorError

    d = np.asarray(M.diagonal()).real
    absA = abs(A)
    radius = np.asarray(absA.sum(axis=1)).ravel() - np.abs(A.diagonal())
    low = float(np.min((A.diagonal().real - radius) / d))
    sigma = low - 1e-3 * abs(low)
    direct = get_backend(select_backend(A.shape[0], A.nnz, eigen=True, shifted=True))
    for k in range(6, 0, -1):
        trial = sigma * 10.0**-k
        try:
            direct.factorize((A - trial * M).tocsc(), positive_definite=True)
        except InvalidOperatorError:
            continue
        sigma = trial
        break
    warnings.warn("the cotan stripe energy is indefinite on this mesh (negative cotangent weights of obtuse "
                  f"triangles; the smallest eigenvalue is below 0): shift-invert at {sigma:.3g}, where A − σM is "
                  f"positive definite (Gershgorin bound {low:.3g}). The curvature-corrected energy='fem' is always "
                  "positive semidefinite", DhlbWarning, stacklevel=4)
    return smallest_eigenpairs(A, M, 1, sigma=sigma, solver=SolverOptions(backend=solver.backend, tol=solver.tol,
                                                                          block_size=solver.block_size, maxiter=2000))


def _factor_solve(res, A, M):
    """``(K⁻¹, factorizations)`` for ``K = A − shift·M`` positive definite.

    The eigensolver's factor (no new factorization), or (iterative and external backends, no factor)
    one direct factorization of ``A − shift·M`` by the backend :func:`~dhlb.linalg.select_backend` picks.
    (Not an eigen solve warm-started from the eigenvector: that one stops at the warm start, factorizing
    nothing.)
    """
    if res.factor is not None:
        return res.factor.solve, 0
    direct = get_backend(select_backend(A.shape[0], A.nnz, eigen=True, shifted=True))
    return direct.factorize((A - res.shift * M).tocsc(), positive_definite=True).solve, 1


def _counted(solve):
    """``solve`` and a list whose length is the number of right-hand sides it was called with."""
    calls = []

    def counted(b):
        calls.append(1 if np.ndim(b) == 1 else np.shape(b)[1])
        return solve(b)
    return counted, calls


def _section(sec: SectionOptions, A, M, x, res, cplx, tol):
    """``(x, iteration, solves, factorizations)`` of the section after the eigenvector."""
    if sec.kind == "eigenvector":
        return x, None, 0, 0
    solve, factorizations = _factor_solve(res, A, M)
    solve, calls = _counted(solve)
    if sec.kind == "power":
        it = power_section(A, M, solve, POWER_ITERATIONS if sec.iterations is None else sec.iterations, seed=sec.seed,
                           complex_form=cplx)
    else:
        it = unit_section(A, M, solve, x, complex_form=cplx,
                          options=sec.replace(iterations=MAX_UNIT_ITERATIONS if sec.iterations is None
                                              else sec.iterations, seed=0 if sec.seed is None else sec.seed))
    return it.x, it, sum(calls), factorizations


def _solve(form, opts: StripeOptions, solver: SolverOptions):
    t0 = time.perf_counter()
    A, M, cplx = stripe_matrices(form, opts.energy, lumped=opts.lumped, branch_weight=opts.branch_weight)
    t1 = time.perf_counter()
    # unit / power iterate with K ≈ A⁻¹ (not K ≈ (A − λ₁M)⁻¹)
    shift = "auto" if opts.section.kind == "eigenvector" else "floor"
    try:
        res = smallest_eigenpairs(A, M, 1, solver=SolverOptions(backend=solver.backend, tol=solver.tol,
                                                                block_size=solver.block_size, factor_shift=shift))
        indefinite = False
    except NotSemidefiniteError:
        res, indefinite = _indefinite(A, M, solver), True
    t2 = time.perf_counter()
    x, it, sec_solves, sec_factors = _section(opts.section, A, M, res.eigenvectors[:, 0], res, cplx, solver.tol)
    t3 = time.perf_counter()
    rho = it.unit_energy if it is not None else unit_energy(A, M, normalize_per_vertex(x, cplx))
    psi = x if cplx else x[0::2] + 1j * x[1::2]
    stats = {"backend": res.backend, "iterations": int(res.iterations), "residual": float(res.residuals[0]),
             "converged": bool(res.converged), "shift": float(res.shift), "block_size": int(res.block_size),
             "unknowns": int(A.shape[0]), "complex": cplx, "indefinite": indefinite,
             "factorizations": int(res.factorizations), "solves": int(res.solves),
             "section_solves": sec_solves, "section_factorizations": sec_factors}
    return (np.ascontiguousarray(psi, np.complex128), float(res.eigenvalues[0]), stats, t1 - t0, t3 - t1,
            t3 - t2, it, rho)


def _one(tb, X, n, frequency, spacing, opts: StripeOptions, solver: SolverOptions, t_mesh):
    t0 = time.perf_counter()
    form = stripe_form(tb, X, n, frequency=frequency, spacing=spacing, method=opts.method,
                       warn_aliasing=opts.warn_aliasing)
    t1 = time.perf_counter()
    psi, lam, stats, t_mat, t_solve, t_sec, it, rho = _solve(form, opts, solver)
    t2 = time.perf_counter()
    tex = texture_coordinates(form, psi)
    t3 = time.perf_counter()
    setup = t_mesh + (t1 - t0) + t_mat
    timings = {"setup": setup, "solve": t_solve, "section": t_sec, "texture": t3 - t2,
               "total": setup + t_solve + (t3 - t2)}
    return StripePattern(form, psi, tex, lam, opts.energy, stats, timings, section=opts.section.kind, unit_energy=rho,
                         iteration=it)


_OPTIONS = {**{k: k for k in ("energy", "orthogonal", "method", "lumped", "branch_weight", "reorient", "components",
                              "warn_aliasing", "progress")},
            "section": "section.kind", "iterations": "section.iterations", "seed": "section.seed",
            "unit_tol": "section.unit_tol"}   # the keywords of dhlb 0.1 → fields of StripeOptions


_BYTES_PER_FACE = 3_600  # peak of stripe_pattern (measured 3.5 kB a face at 20k and 82k faces), for messages


def _estimate(V, F=None, *args, **kwargs):
    faces = len(F) if F is not None else int(getattr(getattr(V, "mesh", V), "n_faces", 0))
    return _BYTES_PER_FACE * faces, f"a stripe pattern on {faces:,} faces ({_BYTES_PER_FACE / 1000:g} kB a face)"


@translate_memory_errors("stripe_pattern", _estimate)
def stripe_pattern(
    V: Any,
    F: ArrayLike | None = None,
    directions: Any = None,
    frequency: ArrayLike | None = None,
    *,
    spacing: ArrayLike | None = None,
    n: int | None = None,
    options: StripeOptions | None = None,
    solver: SolverOptions | str | None = None,
    **deprecated: Any,
) -> StripePattern:
    """A stripe pattern following ``directions`` with the given frequency (seed part 2).

    Parameters
    ----------
    V : (k, 3) array, or a SurfaceMesh / TangentBundle (then F = None), or a direction-field result
        (:func:`dhlb.fields.direction_field`; then F = None and ``directions`` = None).
    F : (m, 3) int array
    directions : (k, 3) or (N, 3) array, (…, j, 3) array (first direction used), or a direction-field
        result with ``n`` = 1 or 2 (its first direction per vertex)
        One tangent direction per vertex (rows of V or compact vertices); its tangential part is used.
        A field computed on these very arrays V, F lends its validated mesh and tangent bundle (the
        mesh is validated once, by the field; its warnings are not repeated) and the angles of its section.
    frequency : float or per-vertex array, > 0
        Stripes per unit length.
    spacing : float or per-vertex array, > 0
        Alternatively, the period in mean edge lengths.
    n : {1, 2}, optional
        1: oriented directions, 2: line field; default the field's n, else 1.
    options : StripeOptions, optional
        Energy, orthogonal pattern, ω̂ method, mass, mesh repair, aliasing warning, progress and the
        section ψ (:class:`~dhlb.stripes.StripeOptions`, :class:`~dhlb.stripes.SectionOptions`).
    solver : dhlb.linalg.SolverOptions or str, optional
        Backend, tolerance (default 1e-10, the backward error of the eigenpair) and block size of
        :func:`dhlb.fem.smallest_eigenpairs` (:class:`~dhlb.linalg.SolverOptions`, or a backend name).
    **deprecated
        The keywords of dhlb 0.1, with a :class:`DeprecationWarning`: ``energy``, ``orthogonal``,
        ``method``, ``lumped``, ``branch_weight``, ``reorient``, ``components``, ``warn_aliasing``,
        ``progress`` (→ ``options``), ``section``, ``iterations``, ``seed``, ``unit_tol``
        (→ ``options.section``: ``kind``, ``iterations``, ``seed``, ``unit_tol``), ``backend``, ``tol``,
        ``block_size`` (→ ``solver``).

    Returns
    -------
    StripePattern

    Raises
    ------
    ShapeError, NonFiniteError, SectionZeroError, InvalidParameterError
        Bad directions (NaN, zero or normal to the surface: the vertex is named), non-positive or
        missing frequency, bad n / energy / method; the mesh errors of
        :func:`dhlb.mesh.validate_surface` (naming the face or vertex).
    ConvergenceError
        The eigensolver did not reach ``tol``.
    InsufficientMemoryError
        The computation ran out of memory (a mesh too large for the memory available, e.g. under an
        address-space limit): the message says about how much it needs and how much is available.
    TypeError
        An unknown keyword argument.

    Warns
    -----
    DhlbWarning
        Stripes narrower than the mesh resolves (the frequency adjustment keeps α correct).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes import SectionOptions, StripeOptions, stripe_pattern
    >>> V, F = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)    # stripes across x
    >>> alpha = res.texture.evaluate(0, [[1, 0, 0], [0, 1, 0]])    # from x = 0 to x = 1: Δα = 2π/4
    >>> round(float(alpha[1] - alpha[0]) / np.pi, 6)
    0.5
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25, solver="superlu",
    ...                      options=StripeOptions(section=SectionOptions(kind="eigenvector")))
    >>> res.section
    'eigenvector'
    """
    t0 = time.perf_counter()
    opts, solver = fold_deprecated_kwargs("stripe_pattern", deprecated, ("options", options, StripeOptions(), _OPTIONS),
                                          ("solver", solver, SolverOptions(), ("backend", "tol", "block_size")))
    solver = solver_options(solver)
    solver = solver if solver.tol is not None else solver.replace(tol=DEFAULT_TOL)
    fld = None
    if _is_field(V) and F is None and directions is None:
        fld, V = V, V.mesh
    elif _is_field(directions):
        fld = directions
    if directions is None and fld is None:
        raise InvalidParameterError("stripe_pattern needs directions (per-vertex vectors or a direction field)")
    if n is not None and (isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral) or n not in (1, 2)):
        raise InvalidParameterError(f"n must be 1 (vector field) or 2 (line field), got {n!r}")
    if fld is not None and F is None and not isinstance(V, (SurfaceMesh, TangentBundle)):
        V = fld.mesh
    mesh = _surface(V, F, opts.reorient, opts.components, fld, opts.repair)
    if fld is not None:
        X, n = _field_n(fld, n)
    else:
        X, n = directions, 1 if n is None else int(n)
    tb = next((t for t in (V, getattr(fld, "tangent", None)) if isinstance(t, TangentBundle) and t.n == 1
               and t.mesh is mesh), None) or TangentBundle(mesh, 1)
    t_mesh = time.perf_counter() - t0
    from dhlb._progress import progress_bar

    count = 2 if opts.orthogonal else 1
    with progress_bar(count, "stripe pattern", progress=opts.progress, unit="pattern",
                      estimate_seconds=count * 1.5e-5 * n * mesh.n_faces) as bar:
        res = _one(tb, X, n, frequency, spacing, opts, solver, t_mesh)
        bar.update(1)
        if opts.orthogonal:
            t1 = time.perf_counter()
            Y = np.cross(tb.normals, res.form.directions)
            res.orthogonal = _one(tb, Y, n, frequency, spacing, opts, solver, time.perf_counter() - t1)
            bar.update(1)
    return res

