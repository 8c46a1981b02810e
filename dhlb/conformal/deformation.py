r"""Close-to-conformal deformations of tetrahedral meshes (seed part 3 §2.4; Chern, Pinkall, Schröder 2015).

Given a tet mesh of a domain ``M ⊂ R³ = Im H`` and a target log conformal factor ``u``, find
``f: M → R³`` with ``|df(X)| ≈ e^u |X|``.  Exact solutions (Möbius maps) have
``df(X) = e^u φ̄ X φ`` with a unit quaternion field ``φ`` that is *parallel* for the metric
connection ``∇_X ψ = dψ(X) + ½ (grad u × X) ψ`` on ``M × H`` (derived, with the curvature of ∇,
in ``proofs/derive_conformal_quaternion.py``).  :func:`conformal_deformation` runs

========== =====================================================================================
phase      what
========== =====================================================================================
mesh       :func:`dhlb.mesh.check_tet_mesh` (validate, orient), connectedness, charges outside
factor     ``u`` at the vertices and ``g_ij`` = grad u on every edge (at its midpoint for a
           :class:`~dhlb.conformal.ConformalFactor`, central differences of a plain callable,
           recovered from vertex values for an array: see :func:`edge_gradients`)
bundle     :func:`quaternion_bundle`: the complex rank-2 hermitian :class:`dhlb.bundles.VectorBundle`
           with ``η_ij = exp(−½ g_ij × e_ij)`` ∈ SU(2) (H ≅ C², right complex structure)
solve      :func:`tet_connection_laplacian` (the connection energy tet by tet, in a gauge per tet:
           positive semidefinite on every mesh) + :func:`dhlb.fem.connection_mass` (lumped),
           :func:`dhlb.fem.smallest_eigenpairs`; ``φ = ψ/|ψ|``
map        ``E_ij = e^{(u_i+u_j)/2} φ̄_ij e_ij φ_ij`` (φ_ij: φ_i and φ_j transported to the edge
           midpoint and averaged), ``G_T`` the least-squares linear map of the edges of each tet
           to their ``E``, then ``min Σ_T vol_T |∇f − G_T|²``: one Poisson solve ``L f = b``
           (``b_i = Σ_T vol_T G_T ∇λ_i``) with three right-hand sides, vertex 0 pinned
           (:func:`dhlb.fem.solve`); ``f`` is translated so that its centroid is that of the input
quality    per tet: deformation gradient ``F``, ``distortion = σ_max/σ_min``,
           ``scale_error = log(mean σ) − u``
========== =====================================================================================

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import ball_tet_mesh
>>> from dhlb.conformal import conformal_deformation, mobius_factor
>>> mesh = ball_tet_mesh(4)
>>> res = conformal_deformation(mesh, None, mobius_factor((2.5, 0.0, 0.0), 2.0))
>>> res.points.shape, res.phi.shape, bool(abs(res.eigenvalue) < 1e-5)
((321, 3), (321, 4), True)
>>> bool(res.statistics["distortion_mean"] < 1.25), res.statistics["inverted_tets"]   # = the exact map's P1 interpolant
(True, 0)
"""

from __future__ import annotations

import time
import warnings
from typing import TYPE_CHECKING

import numpy as np

from dhlb._memory_errors import translate_memory_errors
from dhlb.conformal.factors import ConformalFactor
from dhlb.conformal.quaternion import from_c2, imag, qconj, qexp, qmul, su2_matrix
from dhlb.errors import (
    DhlbWarning,
    InvalidParameterError,
    NonFiniteError,
    NonManifoldError,
    SectionZeroError,
    ShapeError,
)
from dhlb.fem.connection import TET_PSD_TOL, tet_connection_laplacian  # the engine's per-tet energy
from dhlb.mesh.coerce import as_tet_mesh
from dhlb.mesh.tet import TetMesh, signed_volumes

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

    from dhlb.bundles import VectorBundle
from dhlb.conformal.result import ConformalResult

__all__ = ["MAX_EDGE_ANGLE", "RESOLVED_EDGE_ANGLE", "TET_PSD_TOL", "ConformalResult", "conformal_deformation",
           "default_charge", "edge_gradients", "quaternion_bundle", "tet_connection_laplacian", "tet_distortion"]

DEFAULT_TOL = 1e-10
"""Default backward-error tolerance of the eigen solve."""

RESOLVED_EDGE_ANGLE = 0.5 * np.pi
"""Phase changes per edge from this one on are not resolved: :func:`conformal_deformation` refuses them.

At ``θ = π/2`` the chord of a section turning by ``θ`` has lost 29 % of its length at its midpoint
(``cos(θ/2)``); at ``θ = π`` its two ends are opposite and the section cannot be told from one
turning the other way (or vanishing in between).
"""


MAX_EDGE_ANGLE = 0.5
r"""The largest phase change per edge, ``θ_e = ½ |g_e × e|`` (radians), that :func:`default_charge` allows.

``θ_e`` is the angle of the transport ``η_e = exp(−½ g_e × e)`` and the angle in ``R⁴`` between
the values of a parallel section at the two ends of the edge; their chord (what P1 elements see)
has length ``2 sin(θ/2)`` and its midpoint the norm ``cos(θ/2)``, so at ``θ = ½`` a P1 section
loses at most 3 % of its length between vertices and the edge energy misses ``θ²/12`` ≈ 2 % of
the rotation (``proofs/derive_conformal_tet_energy.py``).  Sections that turn by ``π`` along an
edge cannot be resolved at all (:func:`conformal_deformation` then raises
:class:`~dhlb.errors.SectionZeroError`).
"""


def _smallest_pair(A, M, tol, backend):
    """The smallest eigenpair of ``A ψ = λ M ψ``, A positive semidefinite up to :data:`TET_PSD_TOL`.

    The engine's default backend is tried first (AMG-LOBPCG on large meshes when pyamg is
    installed).  Should ``A`` have an eigenvalue below ``−ε`` (tets whose plain energy is negative
    by less than :data:`TET_PSD_TOL`, or rounding), or should an automatically chosen iterative
    backend stall, the engine's ``psd=False`` mode finds the smallest pair certified by the
    inertia of ``A − σM`` (SuperLU).
    """
    from dhlb.errors import ConvergenceError, NotSemidefiniteError
    from dhlb.fem import SolverOptions, smallest_eigenpairs

    auto = backend is None or backend == "auto"
    try:
        return smallest_eigenpairs(A, M, k=1, solver=SolverOptions(tol=tol, backend=backend))
    except NotSemidefiniteError:
        pass
    except ConvergenceError:
        if not auto:
            raise
    return smallest_eigenpairs(A, M, k=1, psd=False, solver=SolverOptions(tol=tol, backend=backend))


# ---------------------------------------------------------------------------- checks
def _check_connected(mesh: TetMesh) -> None:
    n, labels = mesh.complex.connected_components()
    if n <= 1:
        return
    counts = np.bincount(labels, minlength=n)
    tet_comp = labels[mesh.tets[:, 0]]
    tcounts = np.bincount(tet_comp, minlength=n)
    parts = "; ".join(f"component {c}: {int(counts[c])} vertices, {int(tcounts[c])} tets (first tet #"
                      f"{int(np.argmax(tet_comp == c))})" for c in range(min(n, 6)))
    raise NonManifoldError(
        f"the tet mesh has {n} connected components ({parts}{'; ...' if n > 6 else ''}). The least-energy "
        "section would live on one component only and the map is defined per component up to its own rigid "
        "motion: deform each component separately (split with mesh.complex.connected_components())."
    )


def _inside(mesh: TetMesh, x: np.ndarray, rtol: float = 1e-12) -> np.ndarray:
    """Whether each point of ``x`` lies in a (closed) tetrahedron of ``mesh``."""
    P, T = mesh.points, mesh.tets
    p0 = P[T[:, 0]]
    B = np.stack([P[T[:, 1]] - p0, P[T[:, 2]] - p0, P[T[:, 3]] - p0], axis=2)  # (m, 3, 3) columns
    Binv = np.linalg.inv(B)
    out = np.zeros(x.shape[0], bool)
    for k, a in enumerate(x):
        lam = np.einsum("mij,mj->mi", Binv, a - p0)
        bary = np.concatenate([1 - lam.sum(1, keepdims=True), lam], axis=1)
        out[k] = bool(np.any(bary.min(axis=1) >= -rtol))
    return out


def _check_singularities(mesh: TetMesh, factor: ConformalFactor, rows: np.ndarray) -> None:
    S = factor.singularities
    if S.shape[0] == 0:
        return
    inside = _inside(mesh, S)
    if not np.any(inside):
        return
    k = int(np.argmax(inside))
    d = np.linalg.norm(mesh.points - S[k], axis=1)
    v = int(np.argmin(d))
    raise InvalidParameterError(
        f"{factor.labels[k]} lies inside the mesh, where u is singular (nearest vertex: row {int(rows[v])} at "
        f"{np.round(mesh.points[v], 6).tolist()}, distance {d[v]:.3g}); {int(inside.sum())} of "
        f"{S.shape[0]} singular points are inside. Move the charges outside the solid."
    )


# ---------------------------------------------------------------------------- u and its gradient
def _vertex_values(u, mesh: TetMesh, n_rows: int, rows: np.ndarray) -> np.ndarray:
    P = mesh.points
    N = P.shape[0]
    if isinstance(u, (bool, np.bool_)):
        raise InvalidParameterError("u must be a number, an array of one value per vertex or a callable, got a bool")
    if callable(u):
        try:
            val = np.asarray(u(P.copy()))
        except (TypeError, ValueError, IndexError) as exc:
            raise ShapeError(f"the callable u failed on an ({N}, 3) array of points: {exc}") from exc
        if val.shape not in ((N,), (N, 1)):
            raise ShapeError(f"the callable u must map ({N}, 3) points to ({N},) values, returned shape {val.shape}")
        if np.iscomplexobj(val):
            raise ShapeError("the callable u must return real values, got complex ones")
        val = val.reshape(N).astype(np.float64)
        bad = ~np.isfinite(val)
        if np.any(bad):
            v = int(np.argmax(bad))
            raise NonFiniteError(f"u({np.round(P[v], 6).tolist()}) = {val[v]} at vertex row {int(rows[v])} is not "
                                 f"finite ({int(bad.sum())} vertices); is a singularity of u inside the mesh?")
        return val
    try:
        arr = np.asarray(u)
    except (TypeError, ValueError):
        raise ShapeError("u must be a number, an array of one value per vertex or a callable") from None
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number)) or np.iscomplexobj(arr):
        raise ShapeError(f"u must be real numbers, got dtype {arr.dtype}")
    arr = arr.astype(np.float64)
    if arr.ndim == 0:
        if not np.isfinite(arr):
            raise NonFiniteError(f"the constant u = {float(arr)} is not finite")
        return np.full(N, float(arr))
    if arr.shape != (n_rows,):
        raise ShapeError(f"u must have one value per vertex row of the mesh, shape ({n_rows},), got {arr.shape}")
    bad = ~np.isfinite(arr)
    if np.any(bad):
        v = int(np.argmax(bad))
        raise NonFiniteError(f"u[{v}] = {arr[v]} is not finite ({int(bad.sum())} entries); give finite values")
    return arr[rows]


def edge_gradients(mesh: TetMesh, u: Any, values: np.ndarray | None = None) -> np.ndarray:
    """The value of ``grad u`` on every canonical edge ``i < j`` of ``mesh.complex`` (shape ``(n_1, 3)``).

    * a :class:`~dhlb.conformal.ConformalFactor`: its exact gradient at the edge midpoint;
    * another callable: central differences of ``u`` at the midpoint, step ``δ = ε^{1/3}·diam``
      (error ``O(δ²)``);
    * vertex values (``values``; ``u`` is then ignored): the volume-weighted average of the P1
      tet gradients at each vertex (gradient recovery), averaged over the two ends.  This is
      second-order accurate at vertices whose star is point-symmetric (Kuhn/Freudenthal grids)
      and first-order in general, so the holonomy of the discrete connection then matches the
      curvature only to first order on irregular meshes; prefer a callable when you have one.

    Only the component of ``g`` orthogonal to the edge enters the transport ``exp(−½ g × e)``.

    Parameters
    ----------
    mesh : TetMesh
        The validated mesh (:func:`~dhlb.mesh.check_tet_mesh`).
    u : ConformalFactor or callable or None
        The log conformal factor: a :class:`~dhlb.conformal.ConformalFactor`, or a callable mapping
        ``(m, 3)`` points to ``(m,)`` values; ignored when ``values`` is given.
    values : (N,) float array, optional
        Values of ``u`` at the vertices of ``mesh`` (compact order); not checked here, a
        non-finite value shows as a non-finite gradient.

    Returns
    -------
    (n_1, 3) float array
        ``grad u`` on every edge of ``mesh.complex.simplices(1)``.

    Raises
    ------
    ShapeError
        The callable ``u`` does not map ``(m, 3)`` points to ``(m,)`` values, or the gradient of a
        :class:`~dhlb.conformal.ConformalFactor` is not ``(n_1, 3)``.
    NonFiniteError
        ``grad u`` is not finite on some edge (the edge and its midpoint are named; e.g. a
        singularity of ``u`` inside the mesh).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(2)
    >>> g = edge_gradients(mesh, None, values=mesh.points @ [1.0, 2.0, 3.0])    # linear u: exact
    >>> bool(np.allclose(g, [1.0, 2.0, 3.0]))
    True
    """
    X, P = mesh.complex, mesh.points
    E = X.simplices(1)
    mid = 0.5 * (P[E[:, 0]] + P[E[:, 1]])
    if values is None and isinstance(u, ConformalFactor):
        g = u.gradient(mid)
    elif values is None:
        diam = float(np.linalg.norm(P.max(0) - P.min(0)))
        d = np.finfo(float).eps ** (1 / 3) * max(diam, 1e-300)
        g = np.empty_like(mid)
        for c in range(3):
            step = np.zeros(3)
            step[c] = d
            up, dn = (np.asarray(u(mid + step), dtype=np.float64), np.asarray(u(mid - step), dtype=np.float64))
            if up.shape != (mid.shape[0],) or dn.shape != (mid.shape[0],):
                raise ShapeError(f"the callable u must map (m, 3) points to (m,) values, returned shape {up.shape}")
            g[:, c] = (up - dn) / (2 * d)
    else:
        T = mesh.tets
        p0 = P[T[:, 0]]
        B = np.stack([P[T[:, 1]] - p0, P[T[:, 2]] - p0, P[T[:, 3]] - p0], axis=1)  # rows e_k
        du = values[T[:, 1:]] - values[T[:, :1]]
        Gt = np.linalg.solve(B, du[:, :, None])[:, :, 0]                           # B G = du
        vol = np.abs(signed_volumes(P, T))
        N = P.shape[0]
        acc = np.zeros((N, 3))
        wsum = np.bincount(T.ravel(), weights=np.repeat(vol, 4), minlength=N)
        for c in range(3):
            acc[:, c] = np.bincount(T.ravel(), weights=np.repeat(vol * Gt[:, c], 4), minlength=N)
        gv = acc / wsum[:, None]
        g = 0.5 * (gv[E[:, 0]] + gv[E[:, 1]])
    g = np.asarray(g, dtype=np.float64)
    if g.shape != mid.shape:
        raise ShapeError(f"the gradient of u must have shape {mid.shape}, got {g.shape}")
    bad = ~np.isfinite(g).all(axis=1)
    if np.any(bad):
        e = int(np.argmax(bad))
        raise NonFiniteError(f"grad u at the midpoint {np.round(mid[e], 6).tolist()} of edge {E[e].tolist()} is "
                             "not finite; is a singularity of u inside the mesh?")
    return g


def quaternion_bundle(mesh: TetMesh, edge_gradient: np.ndarray) -> VectorBundle:
    """The hermitian rank-2 bundle ``M × H ≅ M × C²`` with ``η_ij = exp(−½ g_ij × e_ij)`` (left multiplication).

    ``e_ij = x_j − x_i`` on the canonical edge ``i < j``; a parallel section satisfies
    ``ψ_j = η_ij ψ_i`` (the exact transport of ``∇ψ = dψ + ½ (g × dx) ψ`` for ``g`` constant on the
    edge).  Left multiplication by quaternions is C-linear for the right complex structure
    ``J q = q i``, so in the coordinates of :func:`~dhlb.conformal.quaternion.to_c2` each
    transport is the SU(2) matrix of :func:`~dhlb.conformal.quaternion.su2_matrix`.

    Parameters
    ----------
    mesh : TetMesh
        The mesh; the bundle lives on ``mesh.complex``.
    edge_gradient : (n_1, 3) float array
        ``g_ij``, the gradient of ``u`` on each canonical edge (:func:`edge_gradients`).

    Returns
    -------
    VectorBundle
        Complex rank 2, metric (SU(2) transports), over ``mesh.complex``.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(1)
    >>> E = quaternion_bundle(mesh, np.tile([0.0, 0.0, 1.0], (mesh.complex.n_simplices(1), 1)))
    >>> E.rank, E.field, E.metric, E.is_flat()     # constant grad u = g: curvature ½ g (g·(X × Y)) ≠ 0
    (2, 'C', True, False)
    """
    from dhlb.bundles import VectorBundle

    X, P = mesh.complex, mesh.points
    E = X.simplices(1)
    e = P[E[:, 1]] - P[E[:, 0]]
    eta = qexp(imag(-0.5 * np.cross(edge_gradient, e)))
    return VectorBundle(X, su2_matrix(eta), "C", metric=True)


def _edge_angles(mesh: TetMesh, g: np.ndarray) -> np.ndarray:
    """``θ_e = ½ |g_e × e|``: the angle of each edge transport (the phase change of a parallel section)."""
    E = mesh.complex.simplices(1)
    return 0.5 * np.linalg.norm(np.cross(g, mesh.points[E[:, 1]] - mesh.points[E[:, 0]]), axis=1)


def default_charge(P: ArrayLike | TetMesh, T: ArrayLike | None = None, *, max_edge_angle: float = MAX_EDGE_ANGLE
                   ) -> np.ndarray:
    r"""The default point charge of ``dhlb conformal``: one row ``(x, y, z, q)`` scaled to the mesh.

    The charge sits at the distance ``0.3 d`` above the top centre of the bounding box (``d`` its
    diagonal); its strength is ``q = 0.5 d`` (scale-invariant: ``u = q/r`` is then the same on a
    mesh and its scaled copy) unless the mesh is too coarse for it: since ``u`` is linear in ``q``,
    so is the phase change per edge ``θ_e = ½ |grad u × e| ≤ q |e| / (2 r²)``, and ``q`` is reduced
    until ``max_e θ_e = max_edge_angle`` (:data:`MAX_EDGE_ANGLE`).

    Parameters
    ----------
    P : (n, 3) float array, or TetMesh
        Vertex positions, or a validated :class:`~dhlb.mesh.TetMesh` (then ``T`` must be None).
    T : (m, 4) int array or None
        Tetrahedra (rows of ``P``).
    max_edge_angle : float, optional
        The largest phase change per edge allowed, in radians (> 0).

    Returns
    -------
    (1, 4) float array
        The charge, ready for :func:`~dhlb.conformal.point_charge_factor`.

    Raises
    ------
    InvalidParameterError
        ``max_edge_angle`` is not a finite number > 0 (and the errors of :func:`dhlb.mesh.check_tet_mesh`).

    Examples
    --------
    >>> from dhlb.mesh import ball_tet_mesh
    >>> C = default_charge(ball_tet_mesh(6))             # fine enough: q = 0.5 d
    >>> C.round(4).tolist()
    [[0.0, 0.0, 2.0392, 1.7321]]
    >>> float(default_charge(ball_tet_mesh(1))[0, 3]) < 1.7       # coarse: a weaker charge
    True
    """
    from dhlb.conformal.factors import point_charge_factor

    if not (np.isscalar(max_edge_angle) and np.isfinite(max_edge_angle) and max_edge_angle > 0):
        raise InvalidParameterError(f"max_edge_angle must be a finite number > 0, got {max_edge_angle!r}")
    mesh = as_tet_mesh(P, T, caller="default_charge")
    Pm = mesh.points
    lo, hi = Pm.min(0), Pm.max(0)
    d = float(np.linalg.norm(hi - lo))
    C = np.array([[0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), hi[2] + 0.3 * d, 0.5 * d]])
    theta = _edge_angles(mesh, edge_gradients(mesh, point_charge_factor(C))).max(initial=0.0)
    if theta > max_edge_angle:
        C[0, 3] *= max_edge_angle / theta
    return C


def _working_scale(u: Any, theta: float) -> str:
    """What to do when u varies too fast: a scale of ``u`` (and its charges) with ``θ <= MAX_EDGE_ANGLE``."""
    s = MAX_EDGE_ANGLE / theta if theta > MAX_EDGE_ANGLE else 0.5
    hint = (f"u varies too fast for this mesh (up to {theta:.3g} rad per edge): scale u by {s:.3g} (at most "
            f"{MAX_EDGE_ANGLE:g} rad per edge) or refine the mesh")
    C = getattr(u, "charges", None)
    if C is not None:
        q = " ".join(f"--charge {x:g},{y:g},{z:g},{s * qq:.3g}" for x, y, z, qq in np.asarray(C))
        hint += f"; for these charges: {q}"
    return hint


def tet_distortion(P: ArrayLike, T: ArrayLike, F: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Singular values of the affine map of every tet ``P[T] → F[T]``: ``(σ (m, 3) descending, det (m,), J (m, 3, 3))``.

    Parameters
    ----------
    P : (n, 3) float array
        Vertex positions before the map.
    T : (m, 4) int array
        Tetrahedra as rows of ``P`` (not checked; a flat tetrahedron of ``P`` makes numpy raise
        ``LinAlgError``).
    F : (n, 3) float array
        Vertex positions after the map.

    Returns
    -------
    sigma : (m, 3) float array
        The singular values of each deformation gradient, descending.
    det : (m,) float array
        Its determinant (negative for an inverted tetrahedron).
    J : (m, 3, 3) float array
        The deformation gradient ``J`` with ``F[T[:, k]] − F[T[:, 0]] = J (P[T[:, k]] − P[T[:, 0]])``.

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> s, det, _ = tet_distortion(P, [[0, 1, 2, 3]], P * [2.0, 1.0, 1.0])
    >>> s.tolist(), det.tolist()
    ([[2.0, 1.0, 1.0]], [2.0])
    """
    P, F = np.asarray(P, dtype=np.float64), np.asarray(F, dtype=np.float64)
    T = np.asarray(T, dtype=np.int64)
    D = np.stack([P[T[:, k]] - P[T[:, 0]] for k in (1, 2, 3)], axis=2)
    Df = np.stack([F[T[:, k]] - F[T[:, 0]] for k in (1, 2, 3)], axis=2)
    J = Df @ np.linalg.inv(D)
    return np.linalg.svd(J, compute_uv=False), np.linalg.det(J), J


# ---------------------------------------------------------------------------- the pipeline
def _mid_phi(phi: np.ndarray, E: np.ndarray, e: np.ndarray, g: np.ndarray) -> np.ndarray:
    """``φ`` at the edge midpoints: φ_i transported forward and φ_j backward by half the edge, averaged."""
    half = qexp(imag(-0.25 * np.cross(g, e)))
    s = qmul(half, phi[E[:, 0]]) + qmul(qconj(half), phi[E[:, 1]])
    n = np.linalg.norm(s, axis=1)
    bad = n < 1e-8
    if np.any(bad):
        k = int(np.argmax(bad))
        raise SectionZeroError(f"φ turns by about π along edge {E[k].tolist()}: the section is not resolved there "
                               "(refine the mesh where grad u is large)")
    return s / n[:, None]


def _tet_gradient_rhs(X, P: np.ndarray, e: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``b_i = Σ_T vol_T G_T ∇λ_i``: the right-hand side of ``min Σ_T vol_T |∇f − G_T|²`` (``L f = b``).

    ``G_T`` is the least-squares linear map of the six edges of ``T`` to their targets,
    ``G_T = (Σ E_ab e_abᵀ)(Σ e_ab e_abᵀ)⁻¹``; it is exact (``G_T = J``) when the targets are
    ``E_ab = J e_ab``.  Every tet term is a positive multiple of a square, whatever the signs of
    the cotan weights (the edge form ``Σ w_ab |f_b − f_a − E_ab|²`` agrees with it only for
    integrable targets and pumps their non-integrable part into the negative weights of slivers).
    """
    from dhlb.topology.structure import subfaces

    S = X.simplices(3)
    edges = subfaces(X, 3, 1)                                       # canonical edges of each tet, e = x_b − x_a
    ee, EE = e[edges], target[edges]                                # (m, 6, 3)
    G = np.einsum("mpi,mpj->mij", EE, ee) @ np.linalg.inv(np.einsum("mpi,mpj->mij", ee, ee))
    B = P[S[:, 1:]] - P[S[:, :1]]                                   # rows x_k − x_0
    Binv = np.linalg.inv(B)                                         # columns ∇λ_1..3
    grads = np.concatenate([-Binv.sum(axis=2, keepdims=True), Binv], axis=2)   # (m, 3, 4): ∇λ_a as columns
    vol = np.abs(np.linalg.det(B)) / 6.0
    contrib = vol[:, None, None] * (G @ grads)                      # (m, 3, 4): vol G ∇λ_a
    b = np.zeros((P.shape[0], 3))
    for a in range(4):
        np.add.at(b, S[:, a], contrib[:, :, a])
    return b


_BYTES_PER_TET = 4_000  # peak of conformal_deformation (measured 3.6 kB a tetrahedron at 98k), for messages


def _estimate(P, T=None, *args, **kwargs):
    tets = len(T) if T is not None else int(np.shape(getattr(P, "tets", ()))[0])
    return _BYTES_PER_TET * tets, f"a mesh of {tets:,} tetrahedra ({_BYTES_PER_TET / 1000:g} kB a tetrahedron)"


@translate_memory_errors("conformal_deformation", _estimate)
def conformal_deformation(
    P: ArrayLike | TetMesh,
    T: ArrayLike | None,
    u: Any,
    *,
    backend: Any = None,
    tol: float = DEFAULT_TOL,
    orientation: str = "fix",
) -> ConformalResult:
    """Close-to-conformal deformation of a tet mesh with target log conformal factor ``u`` (module docstring).

    Parameters
    ----------
    P : (n, 3) float array, or TetMesh
        Vertex positions, or a validated :class:`~dhlb.mesh.TetMesh` (then ``T`` must be None).
    T : (m, 4) int array or None
        Tetrahedra (rows of ``P``), any orientation.
    u : number, (n,) array, callable or ConformalFactor
        The target ``log`` of the conformal factor: a constant, one value per row of ``P``, a
        callable ``(k, 3) → (k,)``, or a :class:`~dhlb.conformal.ConformalFactor` (e.g.
        :func:`~dhlb.conformal.point_charge_factor`, :func:`~dhlb.conformal.mobius_factor`),
        whose exact gradient is used and whose singular points must lie outside the mesh.
    backend : str or backend object, optional
        Linear-algebra backend of :func:`dhlb.fem.smallest_eigenpairs` and :func:`dhlb.fem.solve`.
    tol : float
        Backward-error tolerance of the eigen solve.
    orientation : {"fix", "require"}
        :func:`~dhlb.mesh.check_tet_mesh`: re-orient negatively oriented tets, or raise.

    Returns
    -------
    ConformalResult

    Raises
    ------
    ShapeError, NonFiniteError
        ``u`` of the wrong length or shape, NaN/inf values, a callable returning the wrong shape
        or non-finite values (the vertex is named); malformed ``P``/``T``.
    DegenerateSimplexError, InconsistentOrientationError, NonManifoldError
        Flat tets, folded (inverted) tets, a non-manifold mesh (the element is named), or a
        disconnected mesh (the components are listed).
    InvalidParameterError
        A TetMesh together with ``T``, or arrays without ``T``; a singular point of ``u``
        (a charge) inside the mesh: the charge and the nearest vertex
        are named; bad ``tol``.
    SectionZeroError
        ``u`` varies too fast for the mesh: a parallel section would turn by
        :data:`RESOLVED_EDGE_ANGLE` or more along an edge (checked before any solve), or the
        least-energy section vanishes at a vertex or turns by π along an edge; the message names a
        scale of ``u`` (for point charges: the charges) whose phase change per edge is at most
        :data:`MAX_EDGE_ANGLE`.
    InsufficientMemoryError
        The computation ran out of memory (a mesh too large for the memory available, e.g. under an
        address-space limit): the message says about how much it needs and how much is available.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import ball_tet_mesh
    >>> from dhlb.conformal import point_charge_factor
    >>> res = conformal_deformation(ball_tet_mesh(2), None, point_charge_factor([[0, 0, 1.6, 0.8]]))
    >>> bool(res.eigenvalue > 0), bool(res.distortion.mean() > 1), res.statistics["inverted_tets"]
    (True, True, 0)
    """
    from dhlb.fem import connection_mass, solve
    from dhlb.geometry import EuclideanComplex

    if not (np.isscalar(tol) and np.isfinite(tol) and tol > 0):
        raise InvalidParameterError(f"tol must be a finite number > 0, got {tol!r}")
    timings: dict[str, float] = {}
    t0 = t = time.perf_counter()

    def lap(name):
        nonlocal t
        now = time.perf_counter()
        timings[name] = now - t
        t = now

    mesh = as_tet_mesh(P, T, orientation=orientation, caller="conformal_deformation")
    if mesh is P:
        n_rows, rows = P.points.shape[0], np.arange(P.points.shape[0])
    else:
        n_rows, rows = np.shape(P)[0], np.asarray(mesh.complex.vertex_labels)
    _check_connected(mesh)
    if isinstance(u, ConformalFactor):
        _check_singularities(mesh, u, rows)
    X, Pm = mesh.complex, mesh.points
    lap("mesh")

    uv = _vertex_values(u, mesh, n_rows, rows)
    if callable(u):
        g = edge_gradients(mesh, u)
    else:
        g = edge_gradients(mesh, None, values=uv)
    lap("factor")

    theta = _edge_angles(mesh, g)
    if theta.size and theta.max() >= RESOLVED_EDGE_ANGLE:
        k = int(np.argmax(theta))
        raise SectionZeroError(f"a parallel section would turn by {theta[k]:.3g} rad along the edge between vertex "
                               f"rows {rows[X.simplices(1)[k]].tolist()}, more than P1 elements resolve "
                               f"({RESOLVED_EDGE_ANGLE:.3g} rad): {_working_scale(u, float(theta[k]))}")
    bundle = quaternion_bundle(mesh, g)
    geo = EuclideanComplex(X, points=Pm)
    E = X.simplices(1)
    e = Pm[E[:, 1]] - Pm[E[:, 0]]
    lap("bundle")

    A = tet_connection_laplacian(bundle, geo)
    M = connection_mass(geo, 2)
    res = _smallest_pair(A, M, tol, backend)
    psi = res.eigenvectors[:, 0]
    lam = float(np.real(np.vdot(psi, A @ psi)) / np.real(np.vdot(psi, M @ psi)))
    q = from_c2(psi.reshape(-1, 2))
    nq = np.linalg.norm(q, axis=1)
    small = nq <= 1e-12 * nq.max()
    if np.any(small):
        v = int(np.argmax(small))
        raise SectionZeroError(f"the least-energy section vanishes at vertex row {int(rows[v])} "
                               f"({np.round(Pm[v], 6).tolist()}); {_working_scale(u, _edge_angles(mesh, g).max())}")
    phi = q / nq[:, None]
    lap("solve")

    try:
        pm = _mid_phi(phi, E, e, g)
    except SectionZeroError as err:
        raise SectionZeroError(f"{err}; {_working_scale(u, _edge_angles(mesh, g).max())}") from None
    target = np.exp(0.5 * (uv[E[:, 0]] + uv[E[:, 1]]))[:, None] * qmul(qconj(pm), qmul(imag(e), pm))[:, 1:]
    N = Pm.shape[0]
    b = _tet_gradient_rhs(X, Pm, e, target)           # Σ_T vol_T G_T ∇λ_i: the normal equations' right-hand side
    L = geo.stiffness_matrix().tocsr()                 # Σ_T vol_T ∇λ_i · ∇λ_j
    Ml = geo.mass_matrix(lumped=True).tocsr()
    f = np.zeros((N, 3))
    if N > 1:
        # translation fixed by pinning vertex 0 (f_0 = 0): L restricted to the other vertices is PD
        f[1:] = solve(L[1:, 1:], Ml[1:, 1:], 0.0, b[1:], backend=backend, positive_definite=True)
    mass = Ml.diagonal()
    f += (mass @ Pm - mass @ f) / mass.sum()
    lap("map")

    sig, det, _ = tet_distortion(Pm, mesh.tets, f)
    with np.errstate(divide="ignore"):
        distortion = np.where(sig[:, 2] > 0, sig[:, 0] / np.where(sig[:, 2] > 0, sig[:, 2], 1.0), np.inf)
        scale_error = np.log(sig.mean(axis=1)) - uv[mesh.tets].mean(axis=1)
    lap("quality")
    timings["total"] = time.perf_counter() - t0
    stats = {
        "n_vertices": int(N), "n_edges": int(E.shape[0]), "n_tets": int(mesh.tets.shape[0]),
        "u": (getattr(u, "name", "callable") if callable(u) else "array" if np.ndim(u) else
              f"constant {float(np.asarray(u)):g}"),
        "inverted_tets": int(np.sum(det <= 0)),
        "distortion_mean": float(np.mean(distortion)), "distortion_max": float(np.max(distortion)),
        "scale_error_rms": float(np.sqrt(np.mean(scale_error**2))),
        "scale_error_max": float(np.max(np.abs(scale_error))),
        "max_edge_angle": float(_edge_angles(mesh, g).max()) if E.size else 0.0,
        "solver": {"backend": res.backend, "iterations": int(res.iterations), "converged": bool(res.converged),
                   "residual": float(np.max(res.residuals)), "shift": float(res.shift), "method": res.method},
    }
    _warn_if_poor(det, distortion)
    return ConformalResult(f, phi, lam, distortion, scale_error, uv, stats, timings, mesh, bundle, g)


POOR_DISTORTION = 100.0
"""A largest distortion ``σ_max/σ_min`` above this is reported as a poor result (a warning), like any inverted tet.

A close-to-conformal map has distortions near 1 (the ball, the hand: means 1.0–1.1, largest below 5);
100 is far outside that and far below what a collapsed sliver gives (4.2e4 on bunny-tet.mesh).
"""


def _warn_if_poor(det: np.ndarray, distortion: np.ndarray) -> None:
    """Warn (:class:`~dhlb.errors.DhlbWarning`) of inverted tetrahedra or a distortion above :data:`POOR_DISTORTION`."""
    inverted = np.flatnonzero(det <= 0)
    worst = float(np.max(distortion)) if distortion.size else 1.0
    if not inverted.size and worst <= POOR_DISTORTION:
        return
    what = (f"{inverted.size:,} of {det.size:,} tetrahedra are inverted by the deformation (det F <= 0; first: "
            f"tet row {int(inverted[0])})" if inverted.size else f"tet row {int(np.argmax(distortion))} is distorted")
    warnings.warn(f"a poor deformation: {what}; the largest distortion σ_max/σ_min is {worst:.3g} (median "
                  f"{float(np.median(distortion)):.3g}, 1 is conformal). Flat or needle-like tetrahedra (slivers, "
                  "often on the hull) do this: remove or repair them, or ask for a gentler conformal factor u",
                  DhlbWarning, stacklevel=3)
