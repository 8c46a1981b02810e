"""Guidance fields for aligned n-direction fields (seed part 1, §5, §6.1.2, App. D.5).

A guidance field is one complex number per vertex in the power representation of the
tangent bundle's vertex frames (:mod:`dhlb.mesh.tangent`): ``u_i = |w_i| e^{i n θ_i}`` for a
tangent vector of rescaled angle θ_i and weight ``|w_i|``. Zero means "no guidance here"
(smoothness takes over). Every function returns a :class:`Guidance`; when the field vanishes
everywhere (curvature guidance on a flat mesh, boundary guidance on a closed mesh, all-zero user
vectors) ``empty`` is True and the caller should fall back to the smoothest field with a
warning; no NaN is produced.

Principal curvature (D.5): the discrete shape operator is concentrated on the edges; its
trace-free part, the Hopf differential, pairs with the basis section Ψ_i to
``q̃_i = −¼ Σ_{e ∋ i} β_e |e| e^{2iθ_i(e)}`` (β_e the signed dihedral angle, positive at convex
edges of an outward-oriented surface). Then ``q = M⁻¹ q̃`` (lumped mass by default), a 2-vector
of modulus ``|κ₁ − κ₂| / 2`` pointing along the direction of **maximal** curvature (the
eigenvalue ``+(κ₁ − κ₂)/2`` of the trace-free shape operator); ``−q`` points along the minimal
one. For ``n = 2m`` the guidance is ``(±q)^m`` (the seed: ``q`` for n = 2, ``q²`` for n = 4;
``magnitude="linear"`` keeps the modulus ``|q|`` instead of ``|q|^m``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.mesh.tangent import TangentBundle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Guidance", "dihedral_angles", "hopf_differential", "curvature_guidance", "boundary_guidance",
           "user_guidance"]


@dataclass(frozen=True)
class Guidance:
    """A guidance field.

    ``values`` (N,) complex in the power representation, ``kind``, and ``empty`` (True if it
    vanishes everywhere; ``reason`` says why). Made by the functions of this module; every
    parameter is kept as the attribute of the same name.

    Parameters
    ----------
    values : (N,) complex array
        One value per compact vertex in the power representation of the vertex frames (read-only).
    kind : str
        Where it comes from: ``"curvature-max"``, ``"curvature-min"``, ``"boundary"``,
        ``"boundary-normal"`` or ``"user"``.
    empty : bool
        True if ``values`` vanishes everywhere.
    reason : str, optional
        Why the field is empty (``""`` when it is not).

    Examples
    --------
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import boundary_guidance
    >>> g = boundary_guidance(tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))
    >>> g.kind, g.empty, g.values.shape
    ('boundary', False, (3,))
    """

    values: np.ndarray
    kind: str
    empty: bool
    reason: str = ""


def _guidance(values, kind, why) -> Guidance:
    values = np.asarray(values, np.complex128)
    values.setflags(write=False)
    empty = not np.any(values != 0)
    return Guidance(values, kind, empty, why if empty else "")


def dihedral_angles(tb: TangentBundle) -> np.ndarray:
    """``(n_1,)`` signed dihedral angle β_e per canonical edge (0 on boundary edges).

    β_e is the angle from the normal of one face to the normal of the other, positive where the
    surface bends away from its normals (convex edges of an outward-oriented closed surface).

    Parameters
    ----------
    tb : TangentBundle
        The tangent bundle of the mesh (any n).

    Returns
    -------
    beta : (n_1,) float array
        The signed dihedral angle in ``(−π, π]`` of each edge of ``tb.mesh.complex.simplices(1)``.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import dihedral_angles
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> beta = dihedral_angles(tangent_bundle(V, F))    # every edge convex: π − arccos(−1/3)
    >>> beta.shape, bool(np.allclose(beta, np.pi - np.arccos(-1 / 3)))
    ((12,), True)
    """
    fa, P = tb._fans, tb.mesh.points
    c = tb._edge_corner
    tw = fa.twin[c]
    inner = tw >= 0
    N1 = tb.face_normals[c // 3]
    N2 = tb.face_normals[np.where(inner, tw, c) // 3]
    e = P[fa.first[c]] - P[fa.vertex[c]]
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    beta = np.arctan2(np.sum(e * np.cross(N1, N2), axis=1), np.sum(N1 * N2, axis=1))
    return np.where(inner, beta, 0.0)


def hopf_differential(tb: TangentBundle, *, mass: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The discrete Hopf differential as 2-vectors in the vertex frames.

    Parameters
    ----------
    tb : TangentBundle
        The tangent bundle of the mesh (any n; the frames are the same for every n).
    mass : (N, N) sparse Hermitian matrix, optional
        Mass matrix of the 2nd tangent power (``dhlb.fem.mass_matrix``); default: the lumped
        (barycentric area) mass, i.e. ``q_i = q̃_i / A_i``.

    Returns
    -------
    q : (N,) complex
        Per-vertex Hopf differential, ``|q| ≈ |κ₁ − κ₂| / 2``, along the maximal curvature.
    q_dual : (N,) complex
        The pairings ``q̃_i = ⟨⟨q, Ψ_i⟩⟩`` (right-hand side ``M q`` of the aligned problem, Eq. 6.6).

    Raises
    ------
    ShapeError
        ``mass`` is not ``(N, N)``.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import hopf_differential
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]], n=2)
    >>> q, q_dual = hopf_differential(tb)
    >>> float(np.abs(q).max())
    0.0
    """
    E = tb.mesh.complex.simplices(1)
    w = -0.25 * dihedral_angles(tb) * tb.geometry.edge_lengths
    th = tb.edge_angles
    N = tb.mesh.n_vertices
    z = w[:, None] * np.exp(2j * th)
    qd = np.bincount(E[:, 0], z[:, 0].real, N) + np.bincount(E[:, 1], z[:, 1].real, N)
    qd = qd + 1j * (np.bincount(E[:, 0], z[:, 0].imag, N) + np.bincount(E[:, 1], z[:, 1].imag, N))
    if mass is None:
        q = qd / tb.geometry.mass_matrix(lumped=True).diagonal()
    else:
        M = sp.csc_matrix(mass)
        if M.shape != (N, N):
            raise ShapeError(f"the mass matrix must be ({N}, {N}), got {M.shape}")
        q = spla.spsolve(M.astype(np.complex128), qd)
    return q, qd


def curvature_guidance(
    tb: TangentBundle,
    direction: str = "max",
    *,
    mass: ArrayLike | None = None,
    magnitude: str = "power",
    flat_tol: float = 1e-10,
) -> Guidance:
    """Principal-curvature guidance for even n: ``(q)^{n/2}`` ("max") or ``(−q)^{n/2}`` ("min").

    A mesh whose dihedral angles are all below ``flat_tol`` is flat: the result is all zeros
    with ``empty=True``.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle of the mesh, ``n`` even.
    direction : {"max", "min"}, optional
        Align with the direction of maximal or of minimal principal curvature.
    mass : (N, N) sparse Hermitian matrix, optional
        Passed to :func:`hopf_differential` (default: the lumped mass).
    magnitude : {"power", "linear"}, optional
        ``"power"``: the modulus is ``|q|^{n/2}``; ``"linear"``: it is ``|q|``.
    flat_tol : float, optional
        Dihedral angles (radians) up to this size count as flat.

    Returns
    -------
    Guidance
        Of kind ``"curvature-max"`` or ``"curvature-min"``.

    Raises
    ------
    InvalidParameterError
        ``direction`` or ``magnitude`` is not one of the values above, or ``n`` is odd.
    ShapeError
        ``mass`` is not ``(N, N)``.

    Examples
    --------
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import curvature_guidance
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]], n=4)
    >>> g = curvature_guidance(tb)
    >>> g.empty, g.reason
    (True, 'the mesh is flat: no principal curvature directions')
    """
    if direction not in ("max", "min"):
        raise InvalidParameterError(f"direction must be 'max' or 'min', got {direction!r}")
    if magnitude not in ("power", "linear"):
        raise InvalidParameterError(f"magnitude must be 'power' or 'linear', got {magnitude!r}")
    if tb.n % 2:
        raise InvalidParameterError(f"principal curvature directions are unoriented lines: they guide n-direction "
                                    f"fields with even n only, got n = {tb.n}")
    why = "the mesh is flat: no principal curvature directions"
    if not np.any(np.abs(dihedral_angles(tb)) > flat_tol):
        return _guidance(np.zeros(tb.mesh.n_vertices), f"curvature-{direction}", why)
    q = hopf_differential(tb, mass=mass)[0]
    if direction == "min":
        q = -q
    m = tb.n // 2
    vals = q**m if magnitude == "power" else np.abs(q) * np.exp(1j * m * np.angle(q))
    return _guidance(vals, f"curvature-{direction}", why)


def boundary_guidance(tb: TangentBundle, *, normal: bool = False) -> Guidance:
    """Alignment with the boundary: the boundary tangent at boundary vertices, 0 inside.

    At a boundary vertex the fan spans the rescaled angles ``[0, Θ_i]`` from the outgoing to the
    incoming boundary edge (surface on the left), so the positively oriented boundary leaves along
    the angle 0 and arrives along ``Θ_i − π``. The guidance is the normalized mean of the two edge
    directions in the power representation, ``(1 + e^{in(Θ_i − π)}) / |1 + e^{in(Θ_i − π)}|``
    (0 where they cancel): for n = 1 the bisector ``e^{i(Θ_i − π)/2}``; for a cross field at a
    right-angle corner it is 1, the cross aligned with *both* edges (the bisector would point
    diagonally and force spurious singularities). With ``normal=True`` every direction is turned
    by ``+π/2`` (the inward normal): the value is multiplied by ``e^{inπ/2}``.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle of the mesh.
    normal : bool, optional
        Align with the inward normal of the boundary instead of its tangent.

    Returns
    -------
    Guidance
        Of kind ``"boundary"`` or ``"boundary-normal"``; empty on a closed mesh.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import boundary_guidance
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]], n=1)
    >>> g = boundary_guidance(tb)
    >>> tb.angles_to_vectors(np.arange(4), np.angle(g.values)).round(6).tolist()[0]
    [0.707107, -0.707107, 0.0]
    >>> tb4 = tangent_bundle(tb.mesh, n=4)
    >>> boundary_guidance(tb4).values.round(12).tolist()[0]     # right-angle corner: aligned with both edges
    (1+0j)
    """
    n = tb.n
    mean = 1.0 + np.exp(1j * n * (tb.angle_sums - np.pi))
    mod = np.abs(mean)
    vals = np.where(tb.is_boundary_vertex & (mod > 1e-12), mean / np.where(mod > 0, mod, 1.0), 0.0)
    if normal:
        vals = vals * np.exp(0.5j * n * np.pi)
    return _guidance(vals, "boundary-normal" if normal else "boundary", "the mesh has no boundary")


def user_guidance(tb: TangentBundle, values: ArrayLike) -> Guidance:
    """Guidance from user data, one row per compact vertex or per row of the input V.

    * real ``(k, 3)``: 3D vectors, projected onto the vertex tangent planes; value
      ``|w_t| e^{i n θ}`` with ``w_t`` the tangential part and θ its rescaled angle;
    * complex ``(k,)``: values already in the power representation of the vertex frames.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle of the mesh.
    values : (k, 3) float array or (k,) complex array
        3D vectors or power-representation values, ``k`` the number of compact vertices or of
        rows of the input V.

    Returns
    -------
    Guidance
        Of kind ``"user"``; empty if every value is zero (or every vector normal to the surface).

    Raises
    ------
    ShapeError
        ``values`` is neither real ``(k, 3)`` nor complex ``(k,)``, or ``k`` matches neither vertex count.
    NonFiniteError
        A value is NaN or infinite.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.guidance import user_guidance
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], n=2)
    >>> user_guidance(tb, [[0, 2, 5], [0, 0, 0], [1, 0, 0]]).values.round(6).tolist()
    [(-2+0j), 0j, (-1+0j)]
    """
    arr = np.asarray(values)
    if np.iscomplexobj(arr):
        if arr.ndim != 1:
            raise ShapeError(f"complex guidance must have one value per vertex, got shape {arr.shape}")
        vals = tb.mesh.per_vertex(arr, "guidance values").astype(np.complex128)
        if not np.all(np.isfinite(vals)):
            v = int(np.argmax(~np.isfinite(vals)))
            raise NonFiniteError(f"the guidance value at vertex {int(tb.mesh.vertex_rows[v])} is not finite")
        return _guidance(vals, "user", "all guidance values are zero")
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ShapeError(f"guidance vectors must be real (k, 3) or complex (k,), got shape {arr.shape}")
    theta, length = tb.vectors_to_angles(arr)
    return _guidance(length * np.exp(1j * tb.n * theta), "user", "all guidance vectors are zero or normal")
