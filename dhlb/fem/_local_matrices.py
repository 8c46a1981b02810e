"""Local mass and Dirichlet matrices of the piecewise-linear sections (seed Theorems 15 and 17).

The public boundary of the element kernels: inputs are validated here (typed errors naming the
simplex) and passed to the kernel of their dimension (:func:`dhlb.fem.kernels.element_kernel`).
See :mod:`dhlb.fem.integrals` for the conventions, the local gauge and the formulas.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import ShapeError
from dhlb.fem._local_data import check_closed, parse_connection, parse_gram, parse_omega, parse_volume
from dhlb.fem.kernels import dense, element_kernel

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["local_mass_matrices", "local_dirichlet_matrices", "local_matrices"]


def _inputs(gram, volume, omega, connection, dim):
    """Validate and broadcast: the public boundary of the local matrices.

    Returns ``(G, vol, omega, r, kernel, batched)`` in the layout of :mod:`dhlb.fem.kernels`:
    ``G (m, n+1, n+1)`` (or None), ``vol (m,)``, ``omega (m, C(n+1, 3))``, ``r (m, C(n+1, 2))`` or
    None (local gauge), and the element kernel of the dimension.
    """
    g, sizes = None, {}
    if gram is not None:
        g, dim, b_g = parse_gram(gram)
        sizes["gram"] = g.shape[0] if b_g else None
    arr, n, b_om = parse_omega(omega, dim)
    sizes["curvature"] = arr.shape[0] if b_om else None
    vol, b_v = parse_volume(volume)
    sizes["volume"] = vol.size if b_v else None
    if connection is not None and np.ndim(connection) == 2:
        sizes["connection"] = np.shape(connection)[0]
    given = {k: v for k, v in sizes.items() if v is not None}
    m = max(given.values(), default=1)
    if any(v != m for v in given.values()):
        raise ShapeError(f"inconsistent numbers of simplices: {given}")
    arr = np.broadcast_to(arr, (m, arr.shape[1]))
    vol = np.ascontiguousarray(np.broadcast_to(vol, (m,)))
    if g is not None:
        g = np.ascontiguousarray(np.broadcast_to(g, (m, n + 1, n + 1)))
    check_closed(arr, n)
    arr = np.ascontiguousarray(arr)
    r = None if connection is None else np.ascontiguousarray(parse_connection(connection, m, n, arr))
    return g, vol, arr, r, element_kernel(n), bool(given)


def _finish(off, diag, batched: bool) -> np.ndarray:
    out = dense(off, diag)
    return out if batched else out[0]


def local_mass_matrices(
    volume: ArrayLike, omega: ArrayLike, connection: ArrayLike | None = None, *, dim: int | None = None
) -> np.ndarray:
    """Local mass matrices ``M[b, a] = r_ab vol Θ_ab(a, b)`` of the piecewise-linear sections (Theorem 15).

    Parameters
    ----------
    volume : float or array_like, shape (m,)
        Simplex volumes.
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature on the local triangles in lexicographic order (must be closed per simplex).
    connection : array_like, shape (m, C(n+1, 2)), optional
        Unit complex ``r_ab`` on the local edges (lexicographic), consistent with ``omega``.
        Omitted: the local gauge (``r_0a = 1``, ``r_ab = exp(iΩ_0ab)``), see :mod:`dhlb.fem.integrals`.
    dim : int, optional
        Simplex dimension; needed only for n = 1.

    Returns
    -------
    ndarray, shape (m, n+1, n+1) or (n+1, n+1), complex
        Hermitian positive definite; ``∫_σ |ψ̃|² = zᴴ M z``.

    Examples
    --------
    >>> import numpy as np
    >>> M = local_mass_matrices(0.5, [0.0])           # flat triangle of area 1/2: P1 mass
    >>> np.allclose(M * 24, [[2, 1, 1], [1, 2, 1], [1, 1, 2]])
    True
    """
    _, vol, arr, r, kernel, batched = _inputs(None, volume, omega, connection, dim)
    return _finish(*kernel(None, vol, arr, r, dirichlet=False)[:2], batched)


def local_dirichlet_matrices(
    gram: ArrayLike, volume: ArrayLike, omega: ArrayLike, connection: ArrayLike | None = None
) -> np.ndarray:
    """Local Dirichlet matrices ``∫_σ |∇ψ̃|² = zᴴ A z`` of the piecewise-linear sections (Theorem 17).

    Parameters
    ----------
    gram : array_like, shape (m, n+1, n+1) or (n+1, n+1)
        ``<∇x_a, ∇x_b>`` of the barycentric coordinates of each simplex.
    volume, omega, connection :
        As in :func:`local_mass_matrices`.

    Returns
    -------
    ndarray, shape (m, n+1, n+1) or (n+1, n+1), complex
        Hermitian positive semidefinite; ``vol · gram`` (times ``r``) when Ω = 0.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[2., -1, -1], [-1, 1, 0], [-1, 0, 1]])   # right triangle (0,0),(1,0),(0,1)
    >>> A = local_dirichlet_matrices(G, 0.5, [0.0])
    >>> np.allclose(A, 0.5 * G)
    True
    >>> A = local_dirichlet_matrices(G, 0.5, [1.0])
    >>> np.allclose(A, A.conj().T), bool(np.linalg.eigvalsh(A).min() > 0)
    (True, True)
    """
    g, vol, arr, r, kernel, batched = _inputs(gram, volume, omega, connection, None)
    return _finish(*kernel(g, vol, arr, r, mass=False)[2:], batched)


def local_matrices(
    gram: ArrayLike, volume: ArrayLike, omega: ArrayLike, connection: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Both local matrices ``(M, A)``; see :func:`local_mass_matrices` and :func:`local_dirichlet_matrices`.

    Parameters
    ----------
    gram : array_like, shape (m, n+1, n+1) or (n+1, n+1)
        ``<∇x_a, ∇x_b>`` of the barycentric coordinates of each simplex.
    volume : float or array_like, shape (m,)
        Simplex volumes.
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature on the local triangles in lexicographic order (must be closed per simplex).
    connection : array_like, shape (m, C(n+1, 2)), optional
        Unit complex ``r_ab`` on the local edges, as in :func:`local_mass_matrices`.

    Returns
    -------
    M : ndarray, shape (m, n+1, n+1) or (n+1, n+1), complex
        The local mass matrices, as :func:`local_mass_matrices`.
    A : ndarray, shape (m, n+1, n+1) or (n+1, n+1), complex
        The local Dirichlet matrices, as :func:`local_dirichlet_matrices`.

    Raises
    ------
    ShapeError
        When a shape is wrong or the inputs give different numbers of simplices.
    NonFiniteError
        When an input has a NaN or infinite value.
    InvalidMetricError, DegenerateSimplexError
        When ``gram`` is not a valid Gram matrix, or a volume is not positive.
    CurvatureMismatchError, NotClosedError, InvalidConnectionError
        When ``omega`` is not real or not closed, or ``connection`` is not unit or does not fit ``omega``.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[2., -1, -1], [-1, 1, 0], [-1, 0, 1]])
    >>> M, A = local_matrices(G, 0.5, [0.3])
    >>> M.shape, A.shape
    ((3, 3), (3, 3))
    """
    g, vol, arr, r, kernel, batched = _inputs(gram, volume, omega, connection, None)
    mo, md, ao, ad = kernel(g, vol, arr, r)
    return _finish(mo, md, batched), _finish(ao, ad, batched)
