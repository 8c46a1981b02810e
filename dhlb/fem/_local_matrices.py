"""Local mass and Dirichlet matrices of the piecewise-linear sections (seed Theorems 15 and 17).

See :mod:`dhlb.fem.integrals` for the conventions, the local gauge and the formulas.
"""

from __future__ import annotations

from functools import cache
from math import factorial, prod
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import ShapeError
from dhlb.fem._local_data import (
    check_closed,
    local_edges,
    parse_connection,
    parse_gram,
    parse_omega,
    parse_volume,
    tensor_last,
)
from dhlb.fem._moments import pair_moments

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["local_mass_matrices", "local_dirichlet_matrices", "local_matrices"]


@cache
def _xi_diagonal(n: int) -> np.ndarray:
    """``Ξ_aa(l, l') = n! Π p! / (n+4)!`` with ``p = 2e_a + e_l + e_l'`` (no curvature), ``[a, l, l']``."""
    out = np.empty((n + 1, n + 1, n + 1))
    for a in range(n + 1):
        for k in range(n + 1):
            for q in range(n + 1):
                p = np.zeros(n + 1, dtype=int)
                p[a] += 2
                p[k] += 1
                p[q] += 1
                out[a, k, q] = factorial(n) * prod(factorial(int(v)) for v in p) / factorial(n + 4)
    out.setflags(write=False)
    return out


def _unit(n: int, *idx: int) -> np.ndarray:
    p = np.zeros(n + 1, dtype=int)
    for v in idx:
        p[v] += 1
    return p


def _inputs(gram, volume, omega, connection, dim):
    """Parse and broadcast.

    Returns ``(G, vol, n, tensor, r, batched)`` with the simplex axis LAST: ``G (n+1, n+1, m)`` (or
    None), ``vol (m,)``, ``tensor (n+1, n+1, n+1, m)``, ``r (C(n+1,2), m)``.
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
        g = np.ascontiguousarray(np.moveaxis(np.broadcast_to(g, (m, n + 1, n + 1)), 0, -1))
    check_closed(arr, n)
    tensor = tensor_last(arr, n)
    e = local_edges(n)
    if connection is None:
        r = np.exp(1j * tensor[0, e[:, 0], e[:, 1]])
    else:
        r = np.ascontiguousarray(parse_connection(connection, m, n, arr).T)
    return g, vol, n, tensor, r, bool(given)


def _finish(out: np.ndarray, batched: bool) -> np.ndarray:
    out = np.moveaxis(out, -1, 0)
    return np.ascontiguousarray(out) if batched else out[0].copy()


def _mass(vol, n, tensor, r, th=None):
    """``M[b, a, :]`` with the simplex axis last."""
    m, nv = vol.shape[0], n + 1
    e = local_edges(n)
    out = np.zeros((nv, nv, m), dtype=complex)
    out[np.arange(nv), np.arange(nv)] = 2.0 / ((n + 1) * (n + 2)) * vol
    if len(e):
        if th is None:
            th = pair_moments(tensor, [(int(i), int(j), _unit(n, i, j)) for i, j in e])
        off = r * vol * th
        out[e[:, 1], e[:, 0]] = off
        out[e[:, 0], e[:, 1]] = np.conj(off)
    return out


def _dirichlet(g, vol, n, tensor, r):
    """``A[b, a, :]`` with the simplex axis last, and ``Θ_ab(a, b)`` per local edge (for the mass)."""
    m, nv = vol.shape[0], n + 1
    e = local_edges(n)
    ls = [(k, q) for k in range(nv) for q in range(k, nv)]
    sym = np.empty((nv, nv), dtype=int)          # position of Ξ(l, l') in the request list
    for t, (k, q) in enumerate(ls):
        sym[k, q] = sym[q, k] = t
    requests = []
    for i, j in e:
        i, j = int(i), int(j)
        requests.append((i, j, _unit(n)))
        requests += [(i, j, _unit(n, i, k)) for k in range(nv)]
        requests += [(i, j, _unit(n, j, k)) for k in range(nv)]
        requests += [(i, j, _unit(n, i, j, k, q)) for k, q in ls]
    out = np.zeros((nv, nv, m), dtype=complex)
    # diagonal: no curvature in the exponent and the Θ terms cancel
    xid = _xi_diagonal(n)
    for a in range(nv):
        quad = np.einsum("klm,kqm,qrm->lrm", tensor[a], g, tensor[a], optimize=True)
        out[a, a] = vol * (g[a, a] + np.einsum("lrm,lr->m", quad, xid[a]))
    if len(e) == 0:
        return out, None
    mom = pair_moments(tensor, requests).reshape(len(e), -1, m)
    th_ab = np.empty((len(e), m), dtype=complex)
    for p, (a, b) in enumerate(e):
        lam = mom[p, 0]
        th_a = mom[p, 1: 1 + nv]                       # Θ_ab(a, l)
        th_b = mom[p, 1 + nv: 1 + 2 * nv]              # Θ_ab(b, l)
        xi_ab = mom[p, 1 + 2 * nv:][sym]               # Ξ_ab(l, l'), (n+1, n+1, m)
        wa, wb = tensor[a], tensor[b]                  # W^a[k, l] = Ω_akl
        quad = np.einsum("klm,kqm,qrm->lrm", wa, g, wb, optimize=True)   # (W^aᵀ G W^b)_{l l'}
        pa = np.einsum("km,klm->lm", g[b], wa)                             # (G W^a)_{b l}
        pb = np.einsum("km,klm->lm", g[a], wb)                             # (G W^b)_{a l}
        val = (g[a, b] * lam + np.einsum("lrm,lrm->m", quad, xi_ab)
               + 1j * (np.einsum("lm,lm->m", pa, th_a) - np.einsum("lm,lm->m", pb, th_b)))
        off = r[p] * vol * val
        out[b, a] = off
        out[a, b] = np.conj(off)
        th_ab[p] = th_a[b]
    return out, th_ab


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
    _, vol, n, tensor, r, batched = _inputs(None, volume, omega, connection, dim)
    return _finish(_mass(vol, n, tensor, r), batched)


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
    g, vol, n, tensor, r, batched = _inputs(gram, volume, omega, connection, None)
    return _finish(_dirichlet(g, vol, n, tensor, r)[0], batched)


def local_matrices(
    gram: ArrayLike, volume: ArrayLike, omega: ArrayLike, connection: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Both local matrices ``(M, A)``; see :func:`local_mass_matrices` and :func:`local_dirichlet_matrices`.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[2., -1, -1], [-1, 1, 0], [-1, 0, 1]])
    >>> M, A = local_matrices(G, 0.5, [0.3])
    >>> M.shape, A.shape
    ((3, 3), (3, 3))
    """
    g, vol, n, tensor, r, batched = _inputs(gram, volume, omega, connection, None)
    dirichlet, th = _dirichlet(g, vol, n, tensor, r)
    mass = _mass(vol, n, tensor, r, th)
    return _finish(mass, batched), _finish(dirichlet, batched)
