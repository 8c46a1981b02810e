"""Local mass and Dirichlet matrices of the piecewise-linear sections (seed Theorems 15 and 17).

See :mod:`dhlb.fem.integrals` for the conventions, the local gauge and the formulas.
"""

from __future__ import annotations

from functools import lru_cache
from math import factorial, prod

import numpy as np

from dhlb.errors import ShapeError
from dhlb.fem._local_data import (
    _tensor,
    check_closed,
    local_edges,
    parse_connection,
    parse_gram,
    parse_omega,
    parse_volume,
)
from dhlb.fem._moments import pair_moments

__all__ = ["local_mass_matrices", "local_dirichlet_matrices", "local_matrices"]


@lru_cache(maxsize=None)
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
    """Parse and broadcast; returns ``(G or None, vol, omega, n, tensor, r, batched)``."""
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
    bad = {k: v for k, v in given.items() if v != m}
    if bad:
        raise ShapeError(f"inconsistent numbers of simplices: {given}")
    batched = bool(given)
    arr = np.broadcast_to(arr, (m, arr.shape[1]))
    vol = np.broadcast_to(vol, (m,))
    if g is not None:
        g = np.broadcast_to(g, (m, n + 1, n + 1))
    check_closed(arr, n)
    tensor = _tensor(arr, n)
    e = local_edges(n)
    if connection is None:
        r = np.exp(1j * tensor[:, 0, e[:, 0], e[:, 1]])
    else:
        r = parse_connection(connection, m, n, arr, tensor)
    return g, vol, n, tensor, r, batched


def _mass(vol, n, tensor, r, th=None):
    m = vol.shape[0]
    e = local_edges(n)
    a, b = e[:, 0], e[:, 1]
    out = np.zeros((m, n + 1, n + 1), dtype=complex)
    diag = 2.0 / ((n + 1) * (n + 2))
    out[:, np.arange(n + 1), np.arange(n + 1)] = diag * vol[:, None]
    if len(e):
        if th is None:
            th = pair_moments(tensor, [(int(i), int(j), _unit(n, i, j)) for i, j in e])
        off = r * vol[:, None] * th
        out[:, b, a] = off
        out[:, a, b] = np.conj(off)
    return out


def _dirichlet(g, vol, n, tensor, r):
    m = vol.shape[0]
    e = local_edges(n)
    a, b = e[:, 0], e[:, 1]
    npair, nv = len(e), n + 1
    ls = [(k, q) for k in range(nv) for q in range(k, nv)]
    requests = []
    for i, j in e:
        i, j = int(i), int(j)
        requests.append((i, j, _unit(n)))
        requests += [(i, j, _unit(n, i, k)) for k in range(nv)]
        requests += [(i, j, _unit(n, j, k)) for k in range(nv)]
        requests += [(i, j, _unit(n, i, j, k, q)) for k, q in ls]
    out = np.zeros((m, nv, nv), dtype=complex)
    # diagonal: no curvature in the exponent, Θ terms cancel
    qd = np.swapaxes(tensor, -1, -2) @ (g[:, None] @ tensor)       # (W^aᵀ G W^a), (m, n+1, n+1, n+1)
    diag = g[:, np.arange(nv), np.arange(nv)] + np.einsum("malr,alr->ma", qd, _xi_diagonal(n))
    out[:, np.arange(nv), np.arange(nv)] = vol[:, None] * diag
    if npair == 0:
        return out, None
    mom = pair_moments(tensor, requests).reshape(m, npair, -1)
    lam = mom[:, :, 0]
    th_a = mom[:, :, 1: 1 + nv]
    th_b = mom[:, :, 1 + nv: 1 + 2 * nv]
    xi_u = mom[:, :, 1 + 2 * nv:]
    xi_full = np.empty((m, npair, nv, nv), dtype=complex)
    for t, (k, q) in enumerate(ls):
        xi_full[:, :, k, q] = xi_u[:, :, t]
        xi_full[:, :, q, k] = xi_u[:, :, t]
    wa, wb = tensor[:, a], tensor[:, b]                      # W^a[k, l] = Ω_akl, (m, P, n+1, n+1)
    quad = np.swapaxes(wa, -1, -2) @ (g[:, None] @ wb)     # (W^aᵀ G W^b)_{l l'}
    pa = (g[:, b, None, :] @ wa)[:, :, 0, :]                 # (G W^a)_{b l}
    pb = (g[:, a, None, :] @ wb)[:, :, 0, :]                 # (G W^b)_{a l}
    val = (g[:, a, b] * lam + np.einsum("mplr,mplr->mp", quad, xi_full)
           + 1j * (np.einsum("mpl,mpl->mp", pa, th_a) - np.einsum("mpl,mpl->mp", pb, th_b)))
    off = r * vol[:, None] * val
    out[:, b, a] = off
    out[:, a, b] = np.conj(off)
    return out, th_a[:, np.arange(npair), b]


def local_mass_matrices(volume, omega, connection=None, *, dim=None) -> np.ndarray:
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
    out = _mass(vol, n, tensor, r)
    return out if batched else out[0]


def local_dirichlet_matrices(gram, volume, omega, connection=None) -> np.ndarray:
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
    out = _dirichlet(g, vol, n, tensor, r)[0]
    return out if batched else out[0]


def local_matrices(gram, volume, omega, connection=None) -> tuple[np.ndarray, np.ndarray]:
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
    return (mass, dirichlet) if batched else (mass[0], dirichlet[0])
