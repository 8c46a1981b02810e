"""Rotation form, index form and the discrete Poincaré–Hopf theorem (seed part 3, §8).

For a nowhere-vanishing section ``ψ_i = z_i X_i`` of a hermitian line bundle with curvature:

* rotation form ``ξ_ij = arg(z_j / (r_ij z_i)) ∈ (−π, π]`` on each canonical edge ``i < j``
  (``ξ_ji = −ξ_ij``); tie rule (Remark 8, ``docs/conventions.md``): when
  ``η_ij(ψ_i) = −ψ_j`` the canonical edge gets ``+π``;
* index form ``ind = (dξ + Ω) / 2π``, an integer per triangle (Theorem 11);
* Poincaré–Hopf (Theorem 12): on a closed oriented surface ``Σ_t o_t ind_t = deg L``; more
  generally ``Σ_t C_t ind_t = (1/2π) ∫_C Ω`` for every integer 2-cycle ``C`` (``∫_C dξ = 0``).

Examples
--------
>>> import numpy as np
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import HermitianLineBundle
>>> from dhlb.bundles.index import index_form, index_sum
>>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
>>> L = HermitianLineBundle(X, np.ones(6), np.zeros(4))
>>> z = np.exp(1j * np.array([0.0, 2.0, 4.0, 0.0]))       # winds once around triangle 012
>>> index_form(L, z).tolist(), index_sum(L, z)
([1, 0, 0, 1], 0)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles._util import coboundary, simplex_name
from dhlb.errors import CurvatureMismatchError, NonFiniteError, SectionZeroError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle

__all__ = ["rotation_form", "index_form", "index_sum"]


def _section(L, section) -> np.ndarray:
    X = L.X
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


def rotation_form(L: HermitianLineBundle, section: ArrayLike) -> np.ndarray:
    """``ξ_ij = arg(z_j / (r_ij z_i)) ∈ (−π, π]`` per canonical edge (float64, length n_1).

    Raises
    ------
    SectionZeroError
        if the section vanishes at some vertex (named).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.bundles import HermitianLineBundle
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> z = np.exp(1j * np.array([0.0, 2.0, 4.0, 0.0]))
    >>> rotation_form(HermitianLineBundle.trivial(X), z).round(6).tolist()
    [2.0, -2.283185, 0.0, 2.0, -2.0, 2.283185]
    """
    z = _section(L, section)
    E = L.X.simplices(1)
    xi = np.angle(z[E[:, 1]] * np.conj(L.connection * z[E[:, 0]]))
    return np.where(xi <= -np.pi, np.pi, xi)


def index_form(L: HermitianLineBundle, section: ArrayLike) -> np.ndarray:
    """``ind = (dξ + Ω) / 2π`` as int64, one per triangle in the order of ``X.simplices(2)``.

    The values are integers by Theorem 11; they are checked to tolerance (a failure would
    mean that the bundle's curvature and connection disagree).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.bundles import HermitianLineBundle
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
    >>> index_form(L, np.ones(4)).tolist()
    [0, 0, 0, 1]
    """
    xi = rotation_form(L, section)
    val = (coboundary(L.X, 1, xi)[0] + L.curvature) / (2 * np.pi)
    n = np.round(val)
    off = np.abs(val - n)
    tol = 1e-6 * np.maximum(1.0, np.abs(L.curvature) / (2 * np.pi))
    if np.any(off > tol):
        t = int(np.argmax(off > tol))
        raise CurvatureMismatchError(
            f"the index on triangle {simplex_name(L.X, 2, t)} is {val[t]:.9g}, not an integer: the curvature "
            "does not match the connection there"
        )
    return n.astype(np.int64)


def index_sum(L: HermitianLineBundle, section: ArrayLike, cycle: ArrayLike | None = None) -> int:
    """The index sum ``Σ_t C_t ind_t`` over an integer 2-cycle ``C``.

    ``C`` defaults to the fundamental cycle ``X.orientation()`` of a closed oriented surface.
    Poincaré–Hopf: this equals ``(1/2π) ∫_C Ω`` (the degree, for the fundamental cycle).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.bundles import HermitianLineBundle
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
    >>> index_sum(L, np.ones(4)), L.degree(), index_sum(L, np.ones(4), [-1, 1, -1, 1])
    (-1, -1, 1)
    """
    ind = index_form(L, section)
    if cycle is None:
        cycle = L.fundamental_cycle()
    else:
        cycle = L._chain(cycle, 2)
    return int(np.asarray(cycle, dtype=np.int64) @ ind)
