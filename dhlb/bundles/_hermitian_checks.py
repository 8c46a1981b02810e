"""Input checks of :class:`dhlb.bundles.HermitianLineBundle`: connection, curvature and their match.

Private helpers of :mod:`dhlb.bundles.hermitian`: :func:`from_cochain` unwraps
:class:`dhlb.forms.Cochain` input, :func:`checked_connection` validates the unit complex
``r_ij`` per canonical edge, :func:`checked_curvature` validates the real Ω per canonical
triangle against ``exp(iΩ_ijk) = r_ij r_jk r_ki`` and ``dΩ = 0`` (``docs/conventions.md``);
errors name the offending edge, triangle or tetrahedron in input labels.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import CurvatureMismatchError, InvalidConnectionError, NonFiniteError, NotClosedError, differing_digits
from dhlb.forms.groups import wrap_angle
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology._names import simplex_name

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = ["real_vector", "from_cochain", "checked_connection", "checked_curvature"]


def real_vector(values, n: int, what: str) -> np.ndarray:
    """``(n,)`` float64 from real (or complex with zero imaginary part) finite input; ``what`` names it in errors."""
    arr = np.asarray(values)
    if np.iscomplexobj(arr):
        if np.any(arr.imag != 0):
            raise InvalidConnectionError(f"{what} must be real")
        arr = arr.real
    try:
        arr = arr.astype(np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidConnectionError(f"{what} must be a real array of length {n}") from None
    if arr.size != n:
        raise InvalidConnectionError(f"{what} must have length {n}, got {arr.size}")
    if not np.all(np.isfinite(arr)):
        raise NonFiniteError(f"{what} contains NaN or infinity (entry {int(np.argmin(np.isfinite(arr)))})")
    return arr


def from_cochain(value, k: int):
    """Accept a :class:`dhlb.forms.Cochain` (S¹ angles become unit complex numbers)."""
    if hasattr(value, "values") and hasattr(value, "group") and hasattr(value, "k"):
        if value.k != k:
            raise InvalidConnectionError(f"expected a {k}-form, got a {value.k}-form")
        vals = np.asarray(value.values)
        return np.exp(1j * vals) if (k == 1 and value.group == "S1") else vals
    return value


def checked_connection(X: SimplicialComplex, connection: ArrayLike, atol: float) -> np.ndarray:
    """``(n_1,)`` complex128 ``r`` of modulus exactly 1 from input within ``atol`` of unit modulus.

    Raises
    ------
    InvalidConnectionError
        wrong length or a non-unit ``r`` (names the edge).
    NonFiniteError
        a NaN or infinite entry (names the edge).
    """
    n1 = X.n_simplices(1)
    r = np.asarray(connection)
    try:
        r = r.astype(np.complex128, copy=False).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidConnectionError(f"the connection must be a complex array of length n_1 = {n1}") from None
    if r.size != n1:
        raise InvalidConnectionError(
            f"the connection needs one unit complex number per edge: length n_1 = {n1}, got {r.size}"
        )
    modulus = np.abs(r)
    dev = np.abs(modulus - 1.0)
    finite = np.all(np.isfinite(modulus))    # |r| is NaN or infinite where r is (or overflows)
    if not finite or np.any(dev > atol):
        if not np.all(np.isfinite(r)):
            bad_edge = simplex_name(X, 1, int(np.argmin(np.isfinite(r))))
            raise NonFiniteError(f"the connection contains NaN or infinity (edge {bad_edge})")
        e = int(np.argmax(dev))
        raise InvalidConnectionError(
            f"the connection on edge {simplex_name(X, 1, e)} is not unitary: |r| = {abs(r[e]):.6g}; "
            "a hermitian connection needs |r_ij| = 1"
        )
    return r / modulus


def checked_curvature(X: SimplicialComplex, r: np.ndarray, curvature: ArrayLike, atol: float) -> np.ndarray:
    """``(n_2,)`` float64 Ω, checked against the holonomy of the unit connection ``r`` and for ``dΩ = 0``.

    Raises
    ------
    CurvatureMismatchError
        ``exp(iΩ_t) ≠ r_ij r_jk r_ki`` (names the triangle and the mismatch).
    NotClosedError
        ``dΩ ≠ 0`` on a tetrahedron (names it).
    """
    n2 = X.n_simplices(2)
    Om = real_vector(curvature, n2, "the curvature")
    if n2:
        f = X.faces(2)
        hol = np.angle(r[f[:, 2]] * r[f[:, 0]] * np.conj(r[f[:, 1]]))
        mis = wrap_angle(Om - hol)
        badc = np.abs(mis) > atol * np.maximum(1.0, np.abs(Om))
        if np.any(badc):
            t = int(np.argmax(badc))
            so, sh = differing_digits(Om[t], hol[t])
            raise CurvatureMismatchError(
                f"triangle {simplex_name(X, 2, t)}: exp(iΩ) does not match the holonomy r_ij r_jk r_ki of "
                f"the connection: Ω = {so}, holonomy angle = {sh}, mismatch = {mis[t]:.3g} (mod 2π)"
            )
    if X.dim >= 3 and X.n_simplices(3):
        dOm, scale = coboundary(X, 2, Om)
        badd = np.abs(dOm) > atol * np.maximum(1.0, scale)
        if np.any(badd):
            s = int(np.argmax(badd))
            raise NotClosedError(
                f"the curvature is not closed: dΩ = {dOm[s]:.6g} on the tetrahedron {simplex_name(X, 3, s)}"
            )
    return Om
