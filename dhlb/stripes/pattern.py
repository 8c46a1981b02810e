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
(vertex v = input row ``mesh.vertex_labels[v]`` of V, face f = input row ``mesh.face_rows[f]`` of
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

from dhlb.errors import DhlbWarning, InvalidParameterError, NotSemidefiniteError
from dhlb.fem import select_backend, smallest_eigenpairs
from dhlb.mesh.surface import SurfaceMesh, validate_surface
from dhlb.mesh.tangent import TangentBundle
from dhlb.stripes.energy import ENERGIES, stripe_matrices
from dhlb.stripes.oneform import stripe_form
from dhlb.stripes.section import (
    MAX_UNIT_ITERATIONS,
    POWER_ITERATIONS,
    UNIT_RTOL,
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

__all__ = ["SECTIONS", "StripePattern", "stripe_pattern"]

SECTIONS = ("unit", "eigenvector", "power")


def _is_field(obj) -> bool:
    return all(hasattr(obj, a) for a in ("mesh", "n", "directions")) and isinstance(obj.mesh, SurfaceMesh)


def _surface(V, F, reorient, components):
    if isinstance(V, TangentBundle):
        V = V.mesh
    if isinstance(V, SurfaceMesh):
        if F is not None:
            raise InvalidParameterError("pass either a SurfaceMesh (or TangentBundle) as V with F=None, or arrays V, F")
        return V
    if F is None:
        raise InvalidParameterError("stripe_pattern needs the face array F (or a SurfaceMesh / direction field as V)")
    return validate_surface(V, F, reorient=reorient, components=components)


def _field_directions(fld, mesh, n):
    """The first direction per vertex of a direction-field result, and the n to use."""
    fn = int(fld.n)
    if fn not in (1, 2):
        raise InvalidParameterError(f"stripes need a vector field (n = 1) or a line field (n = 2); the direction "
                                    f"field has n = {fn}")
    if n is None:
        n = fn
    elif n < fn:
        raise InvalidParameterError("the direction field is a line field (n = 2): its directions have no consistent "
                                    "orientation, so it cannot drive an oriented (n = 1) pattern; use n=2")
    if mesh is fld.mesh:
        return np.asarray(fld.directions)[:, 0, :], n
    if hasattr(fld, "input_directions"):
        return np.asarray(fld.input_directions())[:, 0, :], n
    return np.asarray(fld.directions)[:, 0, :], n


def _indefinite(A, M, tol, backend, block_size):
    """Smallest eigenpair of an indefinite A (negative cotan weights): shift below a Gershgorin bound."""
    d = np.asarray(M.diagonal()).real
    absA = abs(A)
    radius = np.asarray(absA.sum(axis=1)).ravel() - np.abs(A.diagonal())
    low = float(np.min((A.diagonal().real - radius) / d))
    sigma = low - 1e-3 * abs(low)
    warnings.warn("the cotan stripe energy is indefinite on this mesh (negative cotangent weights of obtuse "
                  f"triangles; the smallest eigenvalue is below 0): searching below the Gershgorin bound {low:.3g}. "
                  "The curvature-corrected energy='fem' is always positive semidefinite", DhlbWarning, stacklevel=4)
    return smallest_eigenpairs(A, M, 1, tol=tol, backend=backend, block_size=block_size, sigma=sigma,
                               maxiter=2000)


def _factor_solve(res, A, M, tol):
    """``K⁻¹`` for ``K = A − shift·M`` positive definite.

    The eigensolver's factor, or (iterative backends, no factor) one direct factorization of the floor
    shift, warm-started from the eigenvector.
    """
    if res.factor is not None:
        return res.factor.solve
    direct = select_backend(A.shape[0], A.nnz, eigen=True, shifted=True)
    again = smallest_eigenpairs(A, M, 1, tol=tol, backend=direct, v0=res.eigenvectors[:, 0], factor_shift="floor")
    return again.factor.solve


def _section(section, A, M, x, res, cplx, tol, iterations, seed, unit_tol):
    if section == "eigenvector":
        return x, None
    solve = _factor_solve(res, A, M, tol)
    if section == "power":
        it = power_section(A, M, solve, POWER_ITERATIONS if iterations is None else iterations, seed=seed,
                           complex_form=cplx)
    else:
        it = unit_section(A, M, solve, x, complex_form=cplx,
                          maxiter=MAX_UNIT_ITERATIONS if iterations is None else iterations, rtol=unit_tol,
                          seed=0 if seed is None else seed)
    return it.x, it


def _solve(form, energy, lumped, branch_weight, backend, tol, block_size, section, iterations, seed, unit_tol):
    t0 = time.perf_counter()
    A, M, cplx = stripe_matrices(form, energy, lumped=lumped, branch_weight=branch_weight)
    t1 = time.perf_counter()
    shift = "auto" if section == "eigenvector" else "floor"   # unit / power iterate with K ≈ A⁻¹ (not K ≈ (A − λ₁M)⁻¹)
    try:
        res = smallest_eigenpairs(A, M, 1, tol=tol, backend=backend, block_size=block_size, factor_shift=shift)
        indefinite = False
    except NotSemidefiniteError:
        res, indefinite = _indefinite(A, M, tol, backend, block_size), True
    t2 = time.perf_counter()
    x, it = _section(section, A, M, res.eigenvectors[:, 0], res, cplx, tol, iterations, seed, unit_tol)
    t3 = time.perf_counter()
    rho = it.unit_energy if it is not None else unit_energy(A, M, normalize_per_vertex(x, cplx))
    psi = x if cplx else x[0::2] + 1j * x[1::2]
    solver = {"backend": res.backend, "iterations": int(res.iterations), "residual": float(res.residuals[0]),
              "converged": bool(res.converged), "shift": float(res.shift), "block_size": int(res.block_size),
              "unknowns": int(A.shape[0]), "complex": cplx, "indefinite": indefinite}
    return (np.ascontiguousarray(psi, np.complex128), float(res.eigenvalues[0]), solver, t1 - t0, t3 - t1,
            t3 - t2, it, rho)


def _one(tb, X, n, frequency, spacing, method, energy, lumped, branch_weight, backend, tol, block_size,
         warn_aliasing, section, iterations, seed, unit_tol, t_mesh):
    t0 = time.perf_counter()
    form = stripe_form(tb, X, n, frequency=frequency, spacing=spacing, method=method, warn_aliasing=warn_aliasing)
    t1 = time.perf_counter()
    psi, lam, solver, t_mat, t_solve, t_sec, it, rho = _solve(form, energy, lumped, branch_weight, backend, tol,
                                                                block_size, section, iterations, seed, unit_tol)
    t2 = time.perf_counter()
    tex = texture_coordinates(form, psi)
    t3 = time.perf_counter()
    setup = t_mesh + (t1 - t0) + t_mat
    timings = {"setup": setup, "solve": t_solve, "section": t_sec, "texture": t3 - t2,
               "total": setup + t_solve + (t3 - t2)}
    return StripePattern(form, psi, tex, lam, energy, solver, timings, section=section, unit_energy=rho,
                         iteration=it)


def _check_section(section, iterations, seed, unit_tol):
    if section not in SECTIONS:
        raise InvalidParameterError(f"section must be one of {SECTIONS}, got {section!r}")
    if iterations is not None:
        if isinstance(iterations, (bool, np.bool_)) or not isinstance(iterations, numbers.Integral):
            raise InvalidParameterError(f"iterations must be an integer, got {iterations!r}")
        low = 1 if section == "power" else 0
        if not low <= int(iterations) <= 100_000:
            raise InvalidParameterError(f"iterations must be between {low} and 100000 (one back-solve each), "
                                        f"got {iterations!r}")
    try:
        ok = bool(np.isfinite(unit_tol) and unit_tol > 0)
    except TypeError:
        ok = False
    if not ok:
        raise InvalidParameterError(f"unit_tol must be a positive number, got {unit_tol!r}")
    if seed is not None and not isinstance(seed, (numbers.Integral, np.random.Generator)):
        raise InvalidParameterError(f"seed must be an integer or a numpy Generator, got {seed!r}")


def stripe_pattern(
    V: Any,
    F: ArrayLike | None = None,
    directions: Any = None,
    frequency: ArrayLike | None = None,
    *,
    spacing: ArrayLike | None = None,
    n: int | None = None,
    energy: str = "cotan",
    backend: Any = None,
    orthogonal: bool = False,
    method: str = "intrinsic",
    lumped: bool | None = None,
    branch_weight: float = 0.0,
    tol: float = 1e-10,
    block_size: int | None = None,
    reorient: bool = False,
    components: str = "all",
    warn_aliasing: bool = True,
    section: str = "unit",
    iterations: int | None = None,
    seed: Any = None,
    unit_tol: float = UNIT_RTOL,
    progress: bool = False,
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
    frequency : float or per-vertex array, > 0
        Stripes per unit length.
    spacing : float or per-vertex array, > 0
        Alternatively, the period in mean edge lengths.
    n : {1, 2}, optional
        1: oriented directions, 2: line field; default the field's n, else 1.
    energy : {"cotan", "fem"}
        The seed's cotangent energy (default) or the curvature-corrected FEM energy (see
        :mod:`dhlb.stripes.energy`).
    backend : str or backend object, optional
        Factorization backend of :func:`dhlb.fem.smallest_eigenpairs`.
    orthogonal : bool
        Also compute the pattern of the directions turned by 90° (``N × X``), as ``result.orthogonal``.
    method : {"intrinsic", "extrinsic"}
        How ω̂ is computed (:func:`dhlb.stripes.stripe_form`).
    lumped, branch_weight :
        See :func:`dhlb.stripes.energy.stripe_matrices`.
    tol : float
        Backward-error tolerance of the eigenpair.
    block_size : int, optional
        Subspace size of the eigensolver.
    reorient, components :
        Passed to :func:`dhlb.mesh.validate_surface`.
    warn_aliasing : bool
        Warn when stripes are narrower than two edges (the result stays correct, §4.3).
    section : {"unit", "eigenvector", "power"}
        Which section ψ gives the pattern:

        * ``"unit"`` (default): the smallest eigenvector, then the unit-modulus iteration
          ``x ← normalize_per_vertex(M K⁻¹ M x)`` with the eigensolver's factorization of
          ``K = A + εM`` (:func:`dhlb.stripes.section.unit_section`): it returns the iterate of lowest
          *unit* energy (the seed's energy of a unit function, part 2 §2.1, before the relaxation
          Eq. 2.3), so each level of a surface with varying girth keeps its own number of stripes,
          joined by dislocations. Never higher unit energy than ``"eigenvector"``.
        * ``"eigenvector"``: the smallest eigenvector of the relaxed problem (the seed's §2.1 / §4.2).
        * ``"power"``: the seed's Algorithm 9, ``iterations`` inverse power steps (default 20) from a
          uniformly random start (``seed``), for reproducing published figures.
    iterations : int, optional
        ``"unit"``: the maximum number of steps (default 100; 0 = the normalized eigenvector);
        ``"power"``: the number of steps (default 20).
    seed : int or numpy Generator, optional
        Random start of ``"power"``; for ``"unit"`` the seed of the small phase perturbation of the
        start (default 0, deterministic; see :func:`dhlb.stripes.section.unit_section`).
    unit_tol : float
        ``"unit"`` stops when the unit energy changed by less than this (relative) in one step.
    progress : bool
        Report the patterns computed (one, or two with ``orthogonal``) on stderr with tqdm when the
        run is expected to take more than about two seconds; the CLI passes ``not --quiet``.

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

    Warns
    -----
    DhlbWarning
        Stripes narrower than the mesh resolves (the frequency adjustment keeps α correct).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.stripes import stripe_pattern
    >>> V, F = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)    # stripes across x
    >>> alpha = res.texture.evaluate(0, [[1, 0, 0], [0, 1, 0]])    # from x = 0 to x = 1: Δα = 2π/4
    >>> round(float(alpha[1] - alpha[0]) / np.pi, 6)
    0.5
    """
    t0 = time.perf_counter()
    if energy not in ENERGIES:
        raise InvalidParameterError(f"energy must be one of {ENERGIES}, got {energy!r}")
    _check_section(section, iterations, seed, unit_tol)
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
    mesh = _surface(V, F, reorient, components)
    if fld is not None:
        X, n = _field_directions(fld, mesh, n)
    else:
        X, n = directions, 1 if n is None else int(n)
    tb = V if isinstance(V, TangentBundle) and V.n == 1 else TangentBundle(mesh, 1)
    t_mesh = time.perf_counter() - t0
    args = (frequency, spacing, method, energy, lumped, branch_weight, backend, tol, block_size, warn_aliasing,
            section, iterations, seed, unit_tol)
    from dhlb._progress import progress_bar

    with progress_bar(2 if orthogonal else 1, "stripe pattern", progress=progress, unit="pattern",
                      estimate_seconds=(2 if orthogonal else 1) * 1.5e-5 * n * mesh.n_faces) as bar:
        res = _one(tb, X, n, *args, t_mesh)
        bar.update(1)
        if orthogonal:
            t1 = time.perf_counter()
            Y = np.cross(tb.normals, res.form.directions)
            res.orthogonal = _one(tb, Y, n, *args, time.perf_counter() - t1)
            bar.update(1)
    return res

