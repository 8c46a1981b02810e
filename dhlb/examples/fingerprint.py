"""A finger pad with the two singularities of a *loop* fingerprint (seed part 2, Fig. 5).

Fig. 5 of the seed's part 2 mimics a fingerprint by a stripe pattern that follows the smoothest
line field with prescribed singularities: a **core** of index +1/2, where the ridges turn around,
and a **delta** of index −1/2, the triradius where three ridge systems meet. :func:`fingerprint_pad`
gives the data of that figure — the surface and the prescription; the field and the stripes are
computed by the applications (this package sits below them, see ``docs/architecture.md``)::

    V, F, singularities = fingerprint_pad()
    field = dhlb.fields.prescribed_field(V, F, 2, singularities)   # a line field, n = 2
    pattern = dhlb.stripes.stripe_pattern(field, spacing=4.0)      # branch faces = the two faces
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int, check_real
from dhlb.errors import InvalidParameterError, ShapeError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["fingerprint_pad"]


def _disk(rings: int) -> tuple[np.ndarray, np.ndarray]:
    """The unit disk in concentric rings: ring ``k`` holds ``6k`` vertices, neighbouring rings zipped by angle.

    Vertex 0 is the centre, ring ``k`` starts at vertex ``1 + 3k(k − 1)`` at angle 0; the triangles
    are counter-clockwise in the plane (``6 rings²`` of them, nearly equilateral).
    """
    radius = np.concatenate([[0.0]] + [np.full(6 * k, k / rings) for k in range(1, rings + 1)])
    angle = np.concatenate([[0.0]] + [2.0 * np.pi * np.arange(6 * k) / (6 * k) for k in range(1, rings + 1)])
    tris = [(0, 1 + j, 1 + (j + 1) % 6) for j in range(6)]
    for k in range(1, rings):
        a, b, ni, no = 1 + 3 * k * (k - 1), 1 + 3 * k * (k + 1), 6 * k, 6 * (k + 1)
        i = j = 0
        while i < ni or j < no:  # advance on the ring whose next vertex comes first (exact: (i+1)/ni vs (j+1)/no)
            if j == no or (i < ni and (i + 1) * (k + 1) < (j + 1) * k):
                tris.append((a + i % ni, b + j % no, a + (i + 1) % ni))
                i += 1
            else:
                tris.append((a + i % ni, b + j % no, b + (j + 1) % no))
                j += 1
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1), np.array(tris, dtype=np.int64)


def _containing_face(P: np.ndarray, T: np.ndarray, point, name: str) -> int:
    """The triangle of the planar mesh ``(P, T)`` that contains ``point`` (largest smallest barycentric)."""
    p = np.asarray(point, dtype=np.float64)
    if p.shape != (2,):
        raise ShapeError(f"{name} must be a point (x, y) of the unit disk, got {point!r}")
    if not np.all(np.isfinite(p)) or p @ p >= 1.0:
        raise InvalidParameterError(f"{name} = {tuple(p.tolist())} must lie inside the unit disk (x² + y² < 1)")
    A, B, C = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    det = (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])
    l1 = ((p[0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (p[1] - A[:, 1]) * (C[:, 0] - A[:, 0])) / det
    l2 = ((B[:, 0] - A[:, 0]) * (p[1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (p[0] - A[:, 0])) / det
    return int(np.argmax(np.minimum(np.minimum(l1, l2), 1.0 - l1 - l2)))


def fingerprint_pad(
    rings: int = 30,
    core: ArrayLike = (-0.1, 0.1),
    delta: ArrayLike = (0.5, -0.35),
    *,
    aspect: float = 1.3,
    height: float = 0.5,
) -> tuple[np.ndarray, np.ndarray, dict[int, int]]:
    """A finger-tip surface and the core / delta singularities of a loop fingerprint (seed part 2, Fig. 5).

    The pad is the unit disk in ``rings`` concentric rings (ring ``k`` of ``6k`` vertices, nearly
    equilateral triangles), stretched to an ellipse and lifted to a dome:
    ``(x, y) ↦ (x, aspect·y, height·(1 − x² − y²))``. It is a topological disk (χ = 1, one boundary
    loop), oriented with the normals up (+z). The prescription is for a **line field** (``n = 2``):
    index ``k = +1`` (a +1/2 singularity, the core) on the face containing ``core`` and ``k = −1``
    (a −1/2 singularity, the delta) on the face containing ``delta``. On a surface with boundary
    any index sum is admissible (:func:`dhlb.fields.prescribed_field`); here it is 0, as for a
    real loop, whose ridges enter and leave on the same side.

    Parameters
    ----------
    rings : int, >= 2
        Number of rings: ``1 + 3 rings (rings + 1)`` vertices, ``6 rings²`` triangles.
    core, delta : (2,) float array
        Where the +1/2 and the −1/2 singularity go, in the unit disk before stretching (``y``
        along the finger, towards the tip). They must fall on different faces.
    aspect : float, > 0
        Length of the pad along the finger over its width.
    height : float, >= 0
        Height of the dome above its boundary.

    Returns
    -------
    V : (1 + 3 rings (rings + 1), 3) float64
        Vertex positions; vertex 0 is the top of the dome.
    F : (6 rings², 3) int64
        Triangles (counter-clockwise seen from above).
    singularities : dict
        ``{core face: 1, delta face: -1}`` (rows of ``F``), the argument ``singularities`` of
        :func:`dhlb.fields.prescribed_field` with ``n = 2``.

    Raises
    ------
    InvalidParameterError
        ``rings < 2``, ``aspect <= 0``, ``height < 0``, a point outside the unit disk, or ``core``
        and ``delta`` on the same face (their indices would cancel).
    ShapeError
        ``core`` or ``delta`` is not a pair ``(x, y)``.

    Examples
    --------
    >>> from dhlb.examples import fingerprint_pad
    >>> from dhlb.fields import prescribed_field
    >>> from dhlb.stripes import stripe_pattern
    >>> V, F, sing = fingerprint_pad()
    >>> V.shape, F.shape, sorted(sing.values())
    ((2791, 3), (5400, 3), [-1, 1])
    >>> field = prescribed_field(V, F, 2, sing)                    # core +1/2, delta −1/2
    >>> field.face_index[field.singularities.faces].tolist(), field.index_sum
    ([1, -1], 0)
    >>> pattern = stripe_pattern(field, spacing=4.0)
    >>> sorted(pattern.mesh.face_rows[pattern.branch_faces].tolist()) == sorted(sing)
    True
    """
    rings = check_int(rings, "rings", 2)
    aspect = check_real(aspect, "aspect", low=0.0)
    height = check_real(height, "height", low=0.0)
    if aspect == 0.0:
        raise InvalidParameterError("aspect must be > 0 (length over width of the pad), got 0.0")
    P, F = _disk(rings)
    f_core = _containing_face(P, F, core, "core")
    f_delta = _containing_face(P, F, delta, "delta")
    if f_core == f_delta:
        raise InvalidParameterError(f"core and delta fall on the same face {f_core}: their indices +1 and -1 would "
                                    f"cancel; move them apart (or use more rings than {rings})")
    V = np.column_stack([P[:, 0], aspect * P[:, 1], height * (1.0 - (P * P).sum(axis=1))])
    return V, F, {f_core: 1, f_delta: -1}
