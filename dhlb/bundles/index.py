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

from dhlb.bundles._sections import checked_section, index_values, rotation_angles

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.hermitian import HermitianLineBundle

__all__ = ["rotation_form", "index_form", "index_sum"]



def rotation_form(L: HermitianLineBundle, section: ArrayLike) -> np.ndarray:
    """``ξ_ij = arg(z_j / (r_ij z_i)) ∈ (−π, π]`` per canonical edge (float64, length n_1).

    Parameters
    ----------
    L : HermitianLineBundle
        The bundle; ``r_ij`` are its unit transports (``L.connection``).
    section : (n_0,) complex array_like
        The coefficients ``z_i`` of the section in the frames of ``L``, nowhere zero.

    Returns
    -------
    (n_1,) float64 array
        ``ξ`` per row of ``X.simplices(1)``, in (−π, π] (``+π`` at a tie).

    Raises
    ------
    SectionZeroError
        if the section vanishes at some vertex (named), or does not have one value per vertex.
    NonFiniteError
        if a value of the section is NaN or infinite.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.bundles import HermitianLineBundle
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> z = np.exp(1j * np.array([0.0, 2.0, 4.0, 0.0]))
    >>> rotation_form(HermitianLineBundle.trivial(X), z).round(6).tolist()
    [2.0, -2.283185, 0.0, 2.0, -2.0, 2.283185]
    """
    return rotation_angles(L.X.simplices(1), checked_section(L.X, section), L.connection)


def index_form(L: HermitianLineBundle, section: ArrayLike) -> np.ndarray:
    """``ind = (dξ + Ω) / 2π`` as int64, one per triangle in the order of ``X.simplices(2)``.

    The values are integers by Theorem 11; they are checked to tolerance (a failure would
    mean that the bundle's curvature and connection disagree).

    Parameters
    ----------
    L : HermitianLineBundle
        The bundle, with its curvature Ω.
    section : (n_0,) complex array_like
        The coefficients ``z_i`` of the section in the frames of ``L``, nowhere zero.

    Returns
    -------
    (n_2,) int64 array
        The index of the section in every triangle.

    Raises
    ------
    SectionZeroError
        if the section vanishes at some vertex (named), or does not have one value per vertex.
    NonFiniteError
        if a value of the section is NaN or infinite.
    CurvatureMismatchError
        if a value is not an integer (the curvature does not match the connection there).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> from dhlb.bundles import HermitianLineBundle
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> L = HermitianLineBundle(X, np.ones(6), [0, 0, 0, 2 * np.pi])
    >>> index_form(L, np.ones(4)).tolist()
    [0, 0, 0, 1]
    """
    return index_values(L.X, rotation_form(L, section), L.curvature)


def index_sum(L: HermitianLineBundle, section: ArrayLike, cycle: ArrayLike | None = None) -> int:
    """The index sum ``Σ_t C_t ind_t`` over an integer 2-cycle ``C``.

    ``C`` defaults to the fundamental cycle ``X.orientation()`` of a closed oriented surface.
    Poincaré–Hopf: this equals ``(1/2π) ∫_C Ω`` (the degree, for the fundamental cycle).

    Parameters
    ----------
    L : HermitianLineBundle
        The bundle.
    section : (n_0,) complex array_like
        The coefficients ``z_i`` of the section in the frames of ``L``, nowhere zero.
    cycle : (n_2,) int array_like or Chain, optional
        An integer 2-cycle ``C`` (``∂C = 0``). Default: ``L.fundamental_cycle()``.

    Returns
    -------
    int
        ``Σ_t C_t ind_t``.

    Raises
    ------
    SectionZeroError
        if the section vanishes at some vertex, or does not have one value per vertex.
    CurvatureMismatchError
        if the curvature does not match the connection on some triangle.
    NotClosedError
        ``cycle`` is not an integer vector of length n_2, or not a cycle.
    NonManifoldError
        ``cycle`` is omitted and X is not a closed surface.
    NonOrientableError
        ``cycle`` is omitted and X is not orientable.

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
