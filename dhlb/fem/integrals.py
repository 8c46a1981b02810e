r"""Integrals of the associated piecewise-smooth line bundle: Θ, Λ, Ξ and the local FEM matrices.

Seed part 3, §10–§12 (Definitions 18–19, Theorems 15–17).  Proofs of every formula used here are
in ``proofs/`` (sympy); the seed's misprints are listed in ``proofs/README.md``.

Setting and conventions
-----------------------
An n-simplex σ has local vertices ``0..n`` in the order of its sorted row, barycentric coordinates
``x_0..x_n`` and per-simplex data

* ``gram[a, b] = <∇x_a, ∇x_b>`` — the Gram matrix of barycentric gradients, shape ``(n+1, n+1)``;
  ``vol(σ) gram`` is the P1 stiffness (seed Theorem 16, the cotangent formula);
* ``volume`` — ``vol(σ)``;
* ``omega`` — the curvature ``Ω_abc`` on the local triangles ``a < b < c`` in lexicographic order
  (:func:`local_triangles`), shape ``(C(n+1, 3),)``; ``Ω_abc`` is extended antisymmetrically and by 0
  on repeated indices;
* ``connection`` (optional) — ``r_ab`` on the local edges ``a < b`` (:func:`local_edges`), meaning
  ``η_ab(X_a) = r_ab X_b``, with ``r_ab r_bc r_ca = exp(iΩ_abc)`` (``docs/conventions.md``).

All functions take stacks of ``m`` simplices (a leading axis of length ``m`` on every array) or a
single simplex (no leading axis).

The radially parallel frames.  Let ``φ_a`` be the section on the star of vertex ``a`` obtained
by parallel transport of ``X_a`` along rays from ``a`` (seed, proof of Theorem 14).  Transporting
``φ_a(p)`` around the triangle ``(p, a, b)`` (back to ``a`` along the ray, along the edge ``ab``,
out along the ray of ``b``) gives ``r_ab φ_b(p)``, and the holonomy of the triangle is
``exp(i ∫ Ω̃)`` with ``∫_{(a,b,p)} Ω̃ = Σ_m Ω_abm x_m(p)`` (Ω̃ is the constant 2-form with the
given integrals over the faces; the integral is affine in ``p``).  Hence

    φ_a = r_ab exp(-i Σ_m Ω_abm x_m) φ_b,     ∇φ_a = i ω_a φ_a,   ω_a = Σ_{k,l} Ω_akl x_l dx_k,

(the seed's Eq. 11.3 and 11.4; ``ω_a`` vanishes on rays from ``a`` and satisfies
``ω_a - ω_b = -Σ_m Ω_abm dx_m`` by ``dΩ = 0``, which fixes it uniquely).

Local matrices.  A discrete section ``Σ_a z_a X_a`` becomes ``ψ̃ = Σ_a z_a x_a φ_a``; the local
matrices ``M``, ``A`` satisfy ``∫_σ |ψ̃|² = zᴴ M z`` and ``∫_σ |∇ψ̃|² = zᴴ A z`` (antilinear in the
first slot).  With ``Θ_ab``, ``Λ_ab``, ``Ξ_ab`` of Definitions 18–19 (:func:`theta`,
:func:`lambda_`, :func:`xi`), ``G = gram`` and ``W^a[k, l] = Ω_akl``::

    M[b, a] = r_ab vol Θ_ab(a, b)                                                   (Theorem 15)
    A[b, a] = r_ab vol ( G_ab Λ_ab + Σ_{l,l'} (W^aᵀ G W^b)_{l l'} Ξ_ab(l, l')
                         + i Σ_l [ (G W^a)_{b l} Θ_ab(a, l) - (G W^b)_{a l} Θ_ab(b, l) ] )   (Theorem 17)

with ``r_aa = 1``.  Both are Hermitian; ``M[b, a] -> r_ab vol/((n+1)(n+2)) (1 + δ_ab)`` and
``A -> vol G`` (times ``r``) as Ω -> 0, and for a parallel pair the off-diagonal term of
``|z_b - r_ab z_a|²`` has the sign of the convention (``A[b, a] = -w r_ab``).

The local gauge.  When ``connection`` is omitted, the frame at local vertex ``a`` is the transport
of the frame at vertex 0 along the edge ``0a`` — the radially parallel section ``φ_0`` at the
vertices, the seed's local system of the first vertex.  There ``r_0a = 1`` and ``r_ab = exp(iΩ_0ab)``
(:func:`local_gauge_connection`), so the matrices depend on ``(gram, volume, omega)`` only.  For
global frames ``X_i`` with connection ``r``, put ``g_a = r_{v_0 v_a}`` (``g_0 = 1``); then
``M_global[b, a] = g_b M_local[b, a] conj(g_a)`` (same for ``A``), which is what passing
``connection`` computes directly.

Evaluation.  By the Hermite–Genocchi formula, for a monomial ``x^p = Π x_m^{p_m}``,

    (1/vol) ∫_σ x^p exp(i Σ θ_m x_m) = n! Π p_m! · exp[iθ_0^(p_0+1), ..., iθ_n^(p_n+1)],

a confluent divided difference of ``exp`` (:func:`expi_moment`), evaluated by the clustered
Taylor / partial-fraction / scaling-and-squaring scheme of :mod:`dhlb.fem._expdd` to about 1e-15
relative accuracy for all real curvatures, tiny or much larger than π.
"""

from __future__ import annotations

from math import factorial, prod
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.fem._expdd import expi_divided_difference as _dd
from dhlb.fem._local_data import (
    curvature_tensor,
    local_edges,
    local_gauge_connection,
    local_triangles,
    parse_omega,
    tensor_last,
)
from dhlb.fem._local_matrices import local_dirichlet_matrices, local_mass_matrices, local_matrices
from dhlb.fem._moments import pair_moments

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "expi_divided_difference",
    "expi_moment",
    "theta",
    "lambda_",
    "xi",
    "local_edges",
    "local_triangles",
    "curvature_tensor",
    "local_gauge_connection",
    "local_mass_matrices",
    "local_dirichlet_matrices",
    "local_matrices",
]


def expi_divided_difference(phases: ArrayLike, multiplicities: ArrayLike) -> np.ndarray:
    """Confluent divided difference ``exp[iθ_1^(μ_1), ..., iθ_C^(μ_C)]`` of the exponential.

    Parameters
    ----------
    phases : array_like, shape (..., C)
        Real phases ``θ_c``; node ``iθ_c`` is repeated ``μ_c`` times.
    multiplicities : array_like of int, shape (C,)
        Multiplicities ``μ_c >= 1``.

    Returns
    -------
    ndarray, shape (...)
        Complex values, relative accuracy about 1e-15 (see :mod:`dhlb.fem._expdd`).

    Raises
    ------
    ShapeError
        When ``phases`` is complex or a scalar.
    InvalidParameterError
        When ``multiplicities`` are not ``C`` integers >= 1.
    NonFiniteError
        When a phase is NaN or infinite.

    Examples
    --------
    >>> import numpy as np
    >>> t = 3.0   # exp[0, 0, it] = (e^{it} - 1 - it) / (it)^2
    >>> v = expi_divided_difference([0.0, t], [2, 1])
    >>> bool(np.isclose(v, (np.exp(1j * t) - 1 - 1j * t) / (1j * t) ** 2, rtol=1e-14))
    True
    """
    th = np.asarray(phases)
    if np.iscomplexobj(th) or th.ndim < 1:
        raise ShapeError("phases must be a real array of shape (..., C)")
    th = th.astype(float)
    mu = np.asarray(multiplicities)
    if mu.shape != (th.shape[-1],) or not np.issubdtype(mu.dtype, np.integer) or np.any(mu < 1):
        raise InvalidParameterError(f"multiplicities must be {th.shape[-1]} integers >= 1, got {multiplicities!r}")
    if not np.all(np.isfinite(th)):
        raise NonFiniteError("phases must be finite")
    return _dd(th, mu)


def expi_moment(phases: ArrayLike, powers: ArrayLike) -> np.ndarray:
    """Normalized moment ``(1/vol) ∫_σ Π x_m^{p_m} exp(i Σ_m θ_m x_m)`` over an n-simplex.

    Parameters
    ----------
    phases : array_like, shape (..., n+1)
        Real ``θ_m``, one per vertex.
    powers : array_like of int, shape (n+1,)
        Exponents ``p_m >= 0`` of the barycentric monomial.

    Returns
    -------
    ndarray, shape (...)
        ``n! Π p_m! exp[iθ_0^(p_0+1), ..., iθ_n^(p_n+1)]`` (Hermite–Genocchi).

    Raises
    ------
    InvalidParameterError
        When ``powers`` are not ``n+1`` integers >= 0 (or ``phases`` is a scalar).
    ShapeError, NonFiniteError
        When ``phases`` is complex, or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> float(expi_moment([0.0, 0.0, 0.0], [1, 1, 0]).real)   # P1 mass: 1/12
    0.08333333333333333
    """
    th = np.asarray(phases)
    p = np.asarray(powers)
    if th.ndim < 1 or p.shape != (th.shape[-1],) or not np.issubdtype(p.dtype, np.integer) or np.any(p < 0):
        raise InvalidParameterError(f"powers must be {np.shape(phases)[-1:]} non-negative integers, got {powers!r}")
    n = th.shape[-1] - 1
    fac = factorial(n) * prod(factorial(int(k)) for k in p)
    return fac * expi_divided_difference(th, p + 1)


def _pair_integral(omega, idx, extra, dim):
    arr, n, batched = parse_omega(omega, dim)
    for v in idx:
        try:
            check_int(v, "a local vertex index", 0, n)
        except InvalidParameterError:
            raise InvalidParameterError(f"local vertex index {v!r} is out of range 0..{n} for an {n}-simplex") from None
    p = np.zeros(n + 1, dtype=int)
    for v in extra:
        p[v] += 1
    val = pair_moments(tensor_last(arr, n), [(int(idx[0]), int(idx[1]), p)])[0]
    return val if batched else val[0]


def theta(omega: ArrayLike, i: int, j: int, k: int, l: int, *, dim: int | None = None) -> np.ndarray | complex:
    """Θ of Definition 18: ``(1/vol) ∫_σ x_k x_l exp(-i Σ_m Ω_ijm x_m)``.

    Parameters
    ----------
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature on the local triangles (order of :func:`local_triangles`).
    i, j, k, l : int
        Local vertex indices ``0..n``.
    dim : int, optional
        Simplex dimension; needed only for n = 1.

    Returns
    -------
    ndarray of shape (m,), or a complex scalar for a single simplex.

    Raises
    ------
    InvalidParameterError
        When a local vertex index is not an integer in ``0..n``, or ``dim`` is not an integer >= 1.
    ShapeError
        When ``omega`` has the wrong shape (not one value per local triangle).
    CurvatureMismatchError, NonFiniteError
        When ``omega`` is not real, or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> complex(theta([0.0], 0, 1, 0, 1))                # flat: 1/12
    (0.08333333333333333+0j)
    >>> w = 0.7                                          # seed Eq. 12.1 corrected
    >>> ref = 2 * (np.exp(-1j * w) - 1 + 1j * w + w**2 / 2 - 1j * w**3 / 6) / w**4
    >>> bool(np.isclose(theta([w], 0, 1, 0, 1), ref, rtol=1e-13))
    True
    """
    return _pair_integral(omega, (i, j, k, l), (k, l), dim)


def lambda_(omega: ArrayLike, i: int, j: int, *, dim: int | None = None) -> np.ndarray | complex:
    """Λ of Definition 19: ``(1/vol) ∫_σ exp(-i Σ_m Ω_ijm x_m)``.

    Parameters
    ----------
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature on the local triangles (order of :func:`local_triangles`).
    i, j : int
        Local vertex indices ``0..n``.
    dim : int, optional
        Simplex dimension; needed only for n = 1.

    Returns
    -------
    (m,) complex array, or a complex scalar for a single simplex
        The value of ``Λ_ij`` on each simplex.

    Raises
    ------
    InvalidParameterError
        When a local vertex index is not an integer in ``0..n``, or ``dim`` is not an integer >= 1.
    ShapeError
        When ``omega`` has the wrong shape (not one value per local triangle).
    CurvatureMismatchError, NonFiniteError
        When ``omega`` is not real, or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> w = 2.0   # n = 2: Λ_ij = 2 (e^{-iw} - 1 + iw) / (-iw)^2
    >>> bool(np.isclose(lambda_([w], 0, 1), 2 * (np.exp(-1j * w) - 1 + 1j * w) / (-1j * w) ** 2))
    True
    """
    return _pair_integral(omega, (i, j), (), dim)


def xi(omega: ArrayLike, i: int, j: int, k: int, l: int, *, dim: int | None = None) -> np.ndarray | complex:
    """Ξ of Definition 19: ``(1/vol) ∫_σ x_i x_j x_k x_l exp(-i Σ_m Ω_ijm x_m)``.

    Parameters
    ----------
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature on the local triangles (order of :func:`local_triangles`).
    i, j : int
        Local vertex indices ``0..n`` of the pair whose phase ``Ω_ijm`` is integrated.
    k, l : int
        Two more local vertex indices ``0..n`` of the monomial ``x_i x_j x_k x_l``.
    dim : int, optional
        Simplex dimension; needed only for n = 1.

    Returns
    -------
    (m,) complex array, or a complex scalar for a single simplex
        The value of ``Ξ_ij(k, l)`` on each simplex.

    Raises
    ------
    InvalidParameterError
        When a local vertex index is not an integer in ``0..n``, or ``dim`` is not an integer >= 1.
    ShapeError
        When ``omega`` has the wrong shape (not one value per local triangle).
    CurvatureMismatchError, NonFiniteError
        When ``omega`` is not real, or not finite.

    Examples
    --------
    >>> complex(xi([0.0], 0, 0, 1, 1))                    # 2! 2! 2! / 6! = 1/90
    (0.011111111111111112+0j)
    """
    return _pair_integral(omega, (i, j, k, l), (i, j, k, l), dim)


