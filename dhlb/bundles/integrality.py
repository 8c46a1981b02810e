"""Weil's integrality condition (seed part 3, §7, Theorem 7): ``∫_C Ω ∈ 2πZ`` on integer 2-cycles.

:func:`integer_cycle_basis` gives the integer 2-cycles to test and :func:`check_integrality`
tests a curvature on them (re-exported by :mod:`dhlb.bundles.weil`, which constructs bundles
from curvatures, and used by :meth:`HermitianLineBundle.check_integrality`).

Integer basis of ker ∂₂: for 2-complexes in which every edge has at most two triangles it is
read off the dual graph in ``O(n log n)`` (one fundamental cycle per closed orientable
component); other 2-complexes use :func:`dhlb.topology.intlinalg.integer_kernel_basis`; with
3-simplices, ``ker ∂₂ = im ∂₃ + ⟨H₂ generators⟩``, so the tetrahedron boundaries (``dΩ`` mod 2π)
and the generators of :func:`dhlb.topology.homology.homology` are checked.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.bundles._hermitian_checks import real_vector as _real_vector
from dhlb.bundles._surface import surface_cycles
from dhlb.errors import IntegralityError, NotClosedError
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology._names import simplex_name
from dhlb.topology.homology import homology
from dhlb.topology.intlinalg import integer_kernel_basis

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology._protocol import ComplexLike

__all__ = ["integer_cycle_basis", "check_integrality"]


def integer_cycle_basis(X: ComplexLike) -> sp.csc_matrix:
    """An integer basis of the 2-cycles to test, ``(n_2, ℓ)`` sparse int64.

    For complexes without 3-simplices this is a Z-basis of ker ∂₂.  With 3-simplices it is
    the list of H₂ generators (free and torsion); together with the tetrahedron boundaries
    they generate ker ∂₂.

    Parameters
    ----------
    X : SimplicialComplex
        A complex (of dimension < 2 it has no 2-cycles: the result is ``(0, 0)``).

    Returns
    -------
    (n_2, ℓ) scipy.sparse int64 csc matrix
        One integer 2-cycle over ``X.simplices(2)`` per column (``ℓ = 0`` when there is none).

    Examples
    --------
    >>> from dhlb.examples import projective_plane, torus
    >>> from dhlb.topology import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> integer_cycle_basis(X).toarray().ravel().tolist()
    [1, -1, 1, -1]
    >>> integer_cycle_basis(torus()).shape, integer_cycle_basis(projective_plane()).shape
    ((14, 1), (10, 0))
    """
    if X.dim < 2:
        return sp.csc_matrix((0, 0), dtype=np.int64)       # no triangles: no 2-cycles
    S = surface_cycles(X)
    if S is not None:
        return S.basis()
    if X.dim == 2:
        return sp.csc_matrix(integer_kernel_basis(X.boundary(2).tocsc()), dtype=np.int64)
    return sp.csc_matrix(np.asarray(homology(X)[2].generators, dtype=np.int64))


def _raise_defect(X, cycle, period, defect, what):
    raise IntegralityError(
        f"Ω is not integral: its integral over {what} is {period:.9g}, which is {defect:+.3g} away from "
        "2πZ (Weil's condition ∫_C Ω ∈ 2πZ fails); the attributes .cycle and .defect hold the cycle and the defect",
        cycle=cycle,
        defect=float(defect),
    )


def check_integrality(X: ComplexLike, Omega: ArrayLike, atol: float = 1e-8) -> np.ndarray:
    """Check ``∫_C Ω ∈ 2πZ`` for an integer basis of 2-cycles; return the periods ``∫_C Ω / 2π``.

    With 3-simplices, the boundary of every tetrahedron is tested first (``dΩ ∈ 2πZ``).

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension >= 2.
    Omega : (n_2,) float array_like
        The curvature 2-form, one real value per row of ``X.simplices(2)``.
    atol : float, default 1e-8
        Tolerance of ``∫_C Ω ∈ 2πZ``, scaled by ``max(1, ∫_C |Ω|)``.

    Returns
    -------
    (ℓ,) int64 array
        One period per cycle of :func:`integer_cycle_basis` (for a closed connected
        orientable surface: ``[deg]``, for the fundamental cycle with ``o = +1`` on triangle 0).

    Raises
    ------
    IntegralityError
        for the first violating cycle, with ``.cycle`` (int64 2-chain, length n_2) and
        ``.defect`` (``∫_C Ω − 2πn``, the distance to the nearest multiple of 2π).
    InvalidConnectionError
        ``Omega`` is not real or does not have length ``n_2``.
    NonFiniteError
        ``Omega`` contains NaN or infinity.

    Examples
    --------
    >>> import numpy as np
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)])
    >>> check_integrality(X, [np.pi, -np.pi, np.pi, -np.pi]).tolist()
    [2]
    >>> try:
    ...     check_integrality(X, [0.5, 0, 0, 0])
    ... except IntegralityError as err:
    ...     print(err.cycle.tolist(), round(err.defect, 3))
    [1, -1, 1, -1] 0.5
    """
    Om = _real_vector(Omega, X.n_simplices(2), "Ω")
    if Om.size == 0:
        return np.zeros(0, np.int64)
    if X.dim >= 3 and X.n_simplices(3):
        per, scale = coboundary(X, 2, Om)
        dfc = per - 2 * np.pi * np.round(per / (2 * np.pi))
        bad = np.abs(dfc) > atol * np.maximum(1.0, scale)
        if np.any(bad):
            s = int(np.argmax(bad))
            cyc = np.asarray(X.boundary(3)[:, [s]].toarray()).ravel().astype(np.int64)
            _raise_defect(X, cyc, per[s], dfc[s], f"the boundary of the tetrahedron {simplex_name(X, 3, s)}")
    C = integer_cycle_basis(X)
    per = C.T @ Om
    n = np.round(per / (2 * np.pi))
    dfc = per - 2 * np.pi * n
    bad = np.abs(dfc) > atol * np.maximum(1.0, abs(C).T @ np.abs(Om))
    if np.any(bad):
        a = int(np.argmax(bad))
        cyc = np.asarray(C[:, [a]].toarray()).ravel().astype(np.int64)
        _raise_defect(X, cyc, per[a], dfc[a], f"the integer 2-cycle number {a} of the basis (attribute .cycle)")
    return n.astype(np.int64)


def _check_closed(X, Om: np.ndarray, atol: float) -> None:
    if X.dim >= 3 and X.n_simplices(3):
        dOm, scale = coboundary(X, 2, Om)
        bad = np.abs(dOm) > atol * np.maximum(1.0, scale)
        if np.any(bad):
            s = int(np.argmax(bad))
            raise NotClosedError(f"Ω is not closed: dΩ = {dOm[s]:.6g} on the tetrahedron {simplex_name(X, 3, s)}")
