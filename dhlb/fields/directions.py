"""From the power representation of an n-direction field to 3D directions, indices and singularities.

A section ``u`` (one complex number per compact vertex, in the frames of a
:class:`~dhlb.mesh.TangentBundle`) represents at vertex i the n directions of rescaled angles
``(arg u_i + 2πk)/n``, ``k = 0 .. n−1`` (seed part 1, §2). Its index form (Eq. 6.9, seed part 3
Definition 9, :func:`dhlb.bundles.index_form`) gives one integer per face; we report it in the
**mesh orientation** (index of the oriented face, ``o_t`` times the canonical one). Poincaré–Hopf:
``Σ_f index_f = (Σ_f n σ_f + R)/2π`` where ``R = Σ_{e ⊂ ∂M} ξ_e`` is the rotation of the field
relative to parallel transport along the positively oriented boundary; ``R = 0`` and the sum is
``n χ`` on a closed mesh.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import tangent_bundle
>>> from dhlb.fields.directions import field_indices
>>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
>>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
>>> tb = tangent_bundle(V, F, n=1)
>>> fi = field_indices(tb, np.exp(0.3j * np.arange(6)))
>>> fi.total, int(fi.face_index.sum()), len(fi.singularities.faces) > 0
(2, 2, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles.index import index_form, rotation_form
from dhlb.errors import NonFiniteError, ShapeError
from dhlb.mesh.tangent import TangentBundle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Singularities", "FieldIndices", "section_values", "direction_vectors", "field_indices"]


@dataclass(frozen=True)
class Singularities:
    """Faces with nonzero index.

    Made by :func:`field_indices`; every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    faces : (k,) int array
        Rows of ``mesh.faces`` (``mesh.face_rows[faces]`` are the input rows of F).
    input_faces : (k,) int array
        Rows of the input F.
    index : (k,) int array
        Index in the mesh orientation (+1: red, −1: blue).
    barycentric : (k, 3) float array
        Position in the face, w.r.t. ``mesh.faces[faces]``.
    points : (k, 3) float array
        Position in space.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields import field_indices
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> sing = field_indices(tangent_bundle(V, F), np.exp(0.3j * np.arange(6))).singularities
    >>> sing.faces.tolist(), sing.index.tolist(), sing.points.shape
    ([0, 7], [1, 1], (2, 3))
    """

    faces: np.ndarray
    input_faces: np.ndarray
    index: np.ndarray
    barycentric: np.ndarray
    points: np.ndarray


@dataclass(frozen=True)
class FieldIndices:
    """Indices of a section: per face (mesh orientation), their sum and the Poincaré–Hopf terms.

    ``poincare_hopf = (total_curvature + boundary_rotation) / 2π`` equals ``total`` (up to rounding);
    on a closed mesh ``boundary_rotation = 0`` and ``total = n χ``. Made by :func:`field_indices`;
    every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    face_index : (m,) int array
        The index of each face of ``mesh.faces``, in the mesh orientation.
    total : int
        ``face_index.sum()``.
    total_curvature : float
        ``Σ_f n σ_f`` (:attr:`TangentBundle.total_curvature`).
    boundary_rotation : float
        ``R``, the rotation of the field relative to parallel transport along the positively
        oriented boundary (0 on a closed mesh).
    poincare_hopf : float
        ``(total_curvature + boundary_rotation) / 2π``.
    singularities : Singularities
        The faces with nonzero index.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields import field_indices
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> fi = field_indices(tangent_bundle(V, F, n=1), np.exp(0.3j * np.arange(6)))
    >>> fi.total, round(fi.poincare_hopf, 6), round(fi.boundary_rotation, 6)    # χ(S²) = 2
    (2, 2.0, 0.0)
    """

    face_index: np.ndarray
    total: int
    total_curvature: float
    boundary_rotation: float
    poincare_hopf: float
    singularities: Singularities


def section_values(tb: TangentBundle, u: ArrayLike) -> np.ndarray:
    """Validate a section: one finite complex value per compact vertex (or per row of the input V).

    Parameters
    ----------
    tb : TangentBundle
        The bundle the section lives in.
    u : (N,) or (n,) complex array
        One value per compact vertex of ``tb.mesh``, or per row of the input V (rows no face uses
        are dropped).

    Returns
    -------
    (N,) complex array
        The section in compact vertex order, as ``complex128``.

    Raises
    ------
    ShapeError
        ``u`` is not one-dimensional, or its length is neither ``N`` nor the number of input rows.
    NonFiniteError
        A value is NaN or infinite (the vertex is named by its input row).

    Examples
    --------
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields import section_values
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> section_values(tb, [1, 1j, -1]).tolist()
    [(1+0j), 1j, (-1+0j)]
    """
    arr = np.asarray(u)
    if arr.ndim != 1:
        raise ShapeError(f"a section has one complex value per vertex, got shape {arr.shape}")
    z = tb.mesh.per_vertex(arr, "the section").astype(np.complex128)
    if not np.all(np.isfinite(z)):
        v = int(np.argmax(~np.isfinite(z)))
        raise NonFiniteError(f"the section is not finite at vertex {int(tb.mesh.vertex_rows[v])}")
    return z


def direction_vectors(tb: TangentBundle, u: ArrayLike) -> np.ndarray:
    """All n unit directions per vertex in 3D, ``(N, n, 3)``; zero vectors where ``u_i = 0``.

    Direction k at vertex i has rescaled angle ``(arg u_i + 2πk)/n`` and is mapped into the tangent
    plane by :meth:`TangentBundle.angles_to_vectors`.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle the section lives in.
    u : (N,) complex array
        The section, as accepted by :func:`section_values`.

    Returns
    -------
    (N, n, 3) float array
        Unit tangent vectors, direction ``k`` of vertex ``i`` at ``[i, k]``; zero rows where ``u_i = 0``.

    Raises
    ------
    ShapeError, NonFiniteError
        As :func:`section_values`.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields.directions import direction_vectors
    >>> tb = tangent_bundle([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], n=2)
    >>> direction_vectors(tb, [1, 0, 1])[0].round(12).tolist()
    [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    z = section_values(tb, u)
    n = tb.n
    theta = (np.angle(z)[:, None] + 2 * np.pi * np.arange(n)[None, :]) / n
    vec = tb.angles_to_vectors(np.arange(z.size)[:, None], theta)
    vec[z == 0] = 0.0
    return vec


def _zeros_from_base(tb: TangentBundle, z, Fc) -> np.ndarray:
    """Barycentric zero of the linear interpolation of z with the frames transported to ``Fc[:, 0]``."""
    a, b, c = Fc[:, 0], Fc[:, 1], Fc[:, 2]
    ua = z[a]
    ub = np.conj(tb.half_edge_transport(a, b)) * z[b]
    uc = np.conj(tb.half_edge_transport(a, c)) * z[c]
    p, q = ub - ua, uc - ua
    det = p.real * q.imag - p.imag * q.real
    ok = np.abs(det) > 1e-14 * (np.abs(p) * np.abs(q) + 1e-300)
    sd = np.where(ok, det, 1.0)
    x = (-ua.real * q.imag + ua.imag * q.real) / sd
    y = (-p.real * ua.imag + p.imag * ua.real) / sd
    bary = np.clip(np.stack([1 - x - y, x, y], axis=1), 0.0, None)
    s = bary.sum(axis=1, keepdims=True)
    return np.where(ok[:, None] & (s > 0), bary / np.where(s > 0, s, 1.0), 1.0 / 3.0)


def _zeros_in_faces(tb: TangentBundle, z, faces) -> np.ndarray:
    """Barycentric position of the zero of a section in each face, independent of the corner order.

    With the frames transported to one corner, the zero of the linear interpolation
    ``u_a + x (u_b' − u_a) + y (u_c' − u_a) = 0`` (``u_b' = conj(r_ab) u_b``) depends on the corner,
    because transport around the face has holonomy; we average the three choices (each clipped
    into the face, the centroid where the system is singular).
    """
    Fc = tb.mesh.faces[faces]
    out = np.zeros((len(Fc), 3))
    for k in range(3):
        out += np.roll(_zeros_from_base(tb, z, np.roll(Fc, -k, axis=1)), k, axis=1)
    return out / 3.0


def field_indices(tb: TangentBundle, u: ArrayLike, *, faces: ArrayLike | None = None) -> FieldIndices:
    """Per-face indices, their sum, the Poincaré–Hopf terms and the singular faces of a section.

    Parameters
    ----------
    tb : TangentBundle
        The n-th tangent power bundle the section lives in.
    u : (N,) complex array
        The section, as accepted by :func:`section_values`.
    faces : (m,) bool array, optional
        Count only these faces (rows of ``mesh.faces``): the others get index 0, and the sum, the
        total curvature and the boundary rotation are those of these faces and their boundary
        edges. The counts over the parts of a partition of the faces add up to the whole mesh's
        (a rank of an MPI run counts its own faces, :mod:`dhlb.fields.distributed`).

    Returns
    -------
    FieldIndices
        The per-face indices (mesh orientation), their sum, the Poincaré–Hopf terms and the
        :class:`Singularities`.

    Raises
    ------
    ShapeError, NonFiniteError
        As :func:`section_values`.
    SectionZeroError
        ``u`` vanishes at a vertex (the index is defined for nowhere-vanishing sections).

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb.mesh import tangent_bundle
    >>> from dhlb.fields import field_indices
    >>> V = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]]
    >>> F = [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]
    >>> fi = field_indices(tangent_bundle(V, F, n=1), np.exp(0.3j * np.arange(6)))
    >>> fi.total, fi.face_index.tolist()                  # Poincaré–Hopf on the octahedron: χ = 2
    (2, [1, 0, 0, 0, 0, 0, 0, 1])
    """
    z = section_values(tb, u)
    m = tb.mesh
    L = tb.bundle
    ind = index_form(L, z)
    face_index = (m.face_sign * ind[m.triangle_of_face]).astype(np.int64)
    boundary = m.halfedge_twin < 0  # boundary half-edges h = 3f + k, faces[f, k] → faces[f, k+1]
    total_curv = tb.total_curvature
    if faces is not None:
        counted = np.asarray(faces, bool)
        if counted.shape != (m.n_faces,):
            raise ShapeError(f"faces must be a bool mask of shape ({m.n_faces},), got {counted.shape}")
        face_index[~counted] = 0
        boundary &= np.repeat(counted, 3)
        total_curv = float(tb.n * tb.face_curvature[counted].sum())
    h = np.nonzero(boundary)[0]
    rot = 0.0
    if h.size:
        xi = rotation_form(L, z)
        a, b = m.faces.ravel()[h], np.roll(m.faces, -1, axis=1).ravel()[h]
        rot = float(np.sum(np.where(a < b, 1.0, -1.0) * xi[m.halfedge_edge[h]]))
    singular = np.nonzero(face_index)[0]
    bary = _zeros_in_faces(tb, z, singular)
    pts = np.einsum("kp,kpd->kd", bary, m.points[m.faces[singular]])
    sing = Singularities(singular, m.face_rows[singular], face_index[singular], bary, pts)
    return FieldIndices(face_index, int(face_index.sum()), total_curv, rot,
                        (total_curv + rot) / (2 * np.pi), sing)
