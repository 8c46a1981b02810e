"""Array kernels for sections of a hermitian line bundle: the rotation form and the index form.

Plain arrays in, plain arrays out (seed part 3, §8): :meth:`HermitianLineBundle.rotation_form`,
:meth:`HermitianLineBundle.index_form` and the functions of :mod:`dhlb.bundles.index` call them.
Tie rule (Remark 8, ``docs/conventions.md``): when ``η_ij(ψ_i) = −ψ_j`` the canonical edge gets ``+π``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import CurvatureMismatchError, NonFiniteError, SectionZeroError
from dhlb.topology._incidence import coboundary_values
from dhlb.topology._names import simplex_name

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology._protocol import ComplexLike

__all__ = ["checked_section", "rotation_angles", "index_values"]


def checked_section(X: ComplexLike, section: ArrayLike) -> np.ndarray:
    """A nowhere-vanishing section as complex128, one value per vertex of X.

    Raises
    ------
    SectionZeroError
        if the length is wrong or the section vanishes at a vertex (named in input labels).
    NonFiniteError
        if a value is NaN or infinite.
    """
    z = np.asarray(section)
    try:
        z = z.astype(np.complex128).reshape(-1)
    except (TypeError, ValueError):
        raise SectionZeroError(f"a section is one complex number per vertex ({X.n_vertices})") from None
    if z.size != X.n_vertices:
        raise SectionZeroError(f"a section has one complex number per vertex: length {X.n_vertices}, got {z.size}")
    if not np.all(np.isfinite(z)):
        v = int(np.argmin(np.isfinite(z)))
        raise NonFiniteError(f"the section is NaN or infinite at vertex {int(X.vertex_labels[v])}")
    zero = z == 0
    if np.any(zero):
        v = int(np.argmax(zero))
        raise SectionZeroError(
            f"the section vanishes at vertex {int(X.vertex_labels[v])}; rotation and index forms need a "
            "nowhere-vanishing section (perturb it there)"
        )
    return z


def rotation_angles(E: np.ndarray, z: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``ξ_ij = arg(z_j / (r_ij z_i)) ∈ (−π, π]`` per edge ``(i, j)`` of ``E`` (``r``: unit transports).

    Examples
    --------
    >>> E = np.array([[0, 1], [1, 2]])
    >>> rotation_angles(E, np.array([1, 1j, -1]), np.array([1, -1])).round(6).tolist()
    [1.570796, -1.570796]
    """
    xi = np.angle(z[E[:, 1]] * np.conj(r * z[E[:, 0]]))
    return np.where(xi <= -np.pi, np.pi, xi)


def index_values(X: ComplexLike, xi: np.ndarray, curvature: np.ndarray) -> np.ndarray:
    """``(dξ + Ω) / 2π`` per triangle as int64, checked to be integers (Theorem 11).

    Raises
    ------
    CurvatureMismatchError
        if a value is not an integer (the curvature does not match the connection there).
    """
    val = (coboundary_values(X, 1, xi)[0] + curvature) / (2 * np.pi)
    n = np.round(val)
    off = np.abs(val - n)
    tol = 1e-6 * np.maximum(1.0, np.abs(curvature) / (2 * np.pi))
    if np.any(off > tol):
        t = int(np.argmax(off > tol))
        raise CurvatureMismatchError(
            f"the index on triangle {simplex_name(X, 2, t)} is {val[t]:.9g}, not an integer: the curvature "
            "does not match the connection there"
        )
    return n.astype(np.int64)
