"""Zeros of a section on the triangles of a tetrahedral mesh: which faces are crossed and where.

Split out of :mod:`dhlb.vortex.filaments` (which chains these crossings into filaments); see the
module notes there for the conventions (index form, local gauge, placement of the zero).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import as_points
from dhlb.bundles._sections import rotation_angles
from dhlb.errors import (
    InvalidParameterError,
    NonFiniteError,
    NonManifoldError,
    SectionZeroError,
    ShapeError,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle

__all__ = ["face_zeros"]

_CLAMP_TOL = 1e-9  # barycentric coordinates below -tol count as "outside the face"


def _check_inputs(bundle, section, points):
    X = getattr(bundle, "X", None)
    if X is None or not hasattr(bundle, "connection"):
        raise InvalidParameterError(f"bundle must be a dhlb HermitianLineBundle, got {type(bundle).__name__}")
    if X.dim != 3:
        raise NonManifoldError("filaments are traced in tetrahedral meshes; the bundle's complex has "
                               f"dimension {X.dim}")
    P = as_points(points, "points (one per vertex of the complex)", n=X.n_vertices, finite=False)
    if not np.isfinite(P).all():  # named by vertex label, not by row
        v = int(np.argmax(~np.isfinite(P).all(axis=1)))
        raise NonFiniteError(f"the position of vertex {int(X.vertex_labels[v])} is not finite")
    z = np.asarray(section)
    if z.ndim != 1 or z.size != X.n_vertices or not (np.issubdtype(z.dtype, np.number)):
        raise ShapeError(f"the section must be one complex number per vertex, shape ({X.n_vertices},), got "
                         f"{z.dtype} array of shape {z.shape}")
    z = z.astype(np.complex128)
    if not np.isfinite(z).all():
        v = int(np.argmax(~np.isfinite(z)))
        raise NonFiniteError(f"the section is NaN or infinite at vertex {int(X.vertex_labels[v])}")
    if np.any(z == 0):
        v = np.nonzero(z == 0)[0]
        raise SectionZeroError(
            f"the section vanishes at vertex {int(X.vertex_labels[v[0]])} (position {P[v[0]].tolist()})"
            + (f" and at {v.size - 1} more vertices" if v.size > 1 else "")
            + ": the filament passes through a vertex, where its crossing faces are undefined; "
            "perturb the section (or the mesh) there"
        )
    return X, P, z


def face_zeros(
    bundle: HermitianLineBundle,
    section: ArrayLike,
    points: ArrayLike,
    faces: ArrayLike | None = None,
    *,
    placement: str = "balanced",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Zero of the linear interpolant of the section on triangles, in a local gauge of each triangle.

    The inputs are not checked (:func:`~dhlb.vortex.extract_filaments` checks them before it calls
    this function).

    Parameters
    ----------
    bundle : HermitianLineBundle
        The bundle over the complex ``X = bundle.X``.
    section : (N,) complex array
        One value per vertex of ``X`` (in the frames of the bundle), nowhere zero.
    points : (N, 3) float array
        Vertex positions (compact vertex order of ``X``).
    faces : (c,) int array, optional
        Rows of ``X.simplices(2)`` (default: all triangles).
    placement : {"balanced", "vertex"}, optional
        The local gauge of a triangle ``(i < j < k)``:

        * ``"vertex"``: transport to vertex ``i``, ``w = (z_i, conj(r_ij) z_j, conj(r_ik) z_k)``;
        * ``"balanced"`` (default): spread the curvature evenly over the three edges,
          ``w = (|z_i|, |z_j| e^{iξ'_ij}, |z_k| e^{i(ξ'_ij + ξ'_jk)})`` with ``ξ' = ξ + Ω/3`` (ξ the
          rotation form, traversed ``i → j → k → i``). Then ``ξ'_ij + ξ'_jk + ξ'_ki = 2π ind``, so
          whenever all ``|ξ'| < π`` the triangle ``w`` winds ``ind`` times around 0 and the zero
          lies inside the face exactly when the index is ±1.

        For a flat connection (``Ω = 0``) both give the same point (they differ by a constant phase).

    Returns
    -------
    positions : (c, 3) float array
        The zero of each triangle in space.
    barycentric : (c, 3) float array
        Barycentric coordinates (in the sorted vertex order of each triangle), clamped to the triangle.
    clamped : (c,) bool array
        The unclamped zero lay outside the triangle (by more than 1e-9).
    degenerate : (c,) bool array
        The values ``w`` are collinear in C; the centroid is returned.

    Raises
    ------
    InvalidParameterError
        ``placement`` is neither ``"balanced"`` nor ``"vertex"``.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import extract_filaments, face_zeros, uniform_flow, velocity_bundle
    >>> mesh = box_tet_mesh(4, lower=-1, upper=1)
    >>> L = velocity_bundle(mesh.complex, mesh.points, uniform_flow([0.0, 0.0, 0.0]), 1.0)   # trivial bundle
    >>> x, y, _ = mesh.points.T
    >>> psi = (x - 0.1) + 1j * (y - 0.2)                  # zero set: the vertical line (0.1, 0.2, t)
    >>> crossed = np.nonzero(extract_filaments(L, psi, mesh.points).index)[0]
    >>> pos, bary, clamped, degenerate = face_zeros(L, psi, mesh.points, crossed)
    >>> bool(np.allclose(pos[:, :2], [0.1, 0.2])), bool(clamped.any()), bool(degenerate.any())
    (True, False, False)
    """
    if placement not in ("balanced", "vertex"):
        raise InvalidParameterError(f"placement must be 'balanced' or 'vertex', got {placement!r}")
    X = bundle.X
    P = np.asarray(points, dtype=np.float64)
    z = np.asarray(section).astype(np.complex128)
    rows = np.arange(X.n_simplices(2)) if faces is None else np.asarray(faces, dtype=np.int64)
    tri, fe = X.simplices(2)[rows], X.faces(2)[rows]
    r = bundle.connection
    zi, zj, zk = z[tri[:, 0]], z[tri[:, 1]], z[tri[:, 2]]
    if placement == "vertex":
        w = np.stack([zi, np.conj(r[fe[:, 2]]) * zj, np.conj(r[fe[:, 1]]) * zk], axis=1)
    else:
        E1 = X.simplices(1)
        third = bundle.curvature[rows] / 3  # rotation form on the edges ij, jk (canonical, tie rule +π)
        t_ij = rotation_angles(E1[fe[:, 2]], z, r[fe[:, 2]]) + third
        t_jk = rotation_angles(E1[fe[:, 0]], z, r[fe[:, 0]]) + third
        w = np.stack([np.abs(zi), np.abs(zj) * np.exp(1j * t_ij), np.abs(zk) * np.exp(1j * (t_ij + t_jk))], axis=1)
    w = w / np.abs(w).max(axis=1, keepdims=True)
    lam = np.stack([np.imag(np.conj(w[:, 1]) * w[:, 2]), np.imag(np.conj(w[:, 2]) * w[:, 0]),
                    np.imag(np.conj(w[:, 0]) * w[:, 1])], axis=1)
    S = lam.sum(axis=1)
    degenerate = ~(np.abs(S) > 1e-14 * np.abs(lam).sum(axis=1))
    S = np.where(degenerate, 1.0, S)
    lam = np.where(degenerate[:, None], 1.0 / 3.0, lam / S[:, None])
    clamped = lam.min(axis=1) < -_CLAMP_TOL
    lam = np.maximum(lam, 0.0)
    lam = lam / lam.sum(axis=1, keepdims=True)
    return np.einsum("ca,cak->ck", lam, P[tri]), lam, clamped, degenerate


# ---------------------------------------------------------------------------- graph
