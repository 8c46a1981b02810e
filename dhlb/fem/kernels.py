r"""The element-kernel interface of the finite elements: one kernel per simplex dimension.

An *element kernel* takes a batch of ``m`` simplices of one dimension n, simplex axis first::

    kernel(gram, volume, omega, connection=None, *, mass=True, dirichlet=True)
        gram        (m, n+1, n+1) Gram matrices <∇x_a, ∇x_b> (None when dirichlet is False)
        volume      (m,) volumes
        omega       (m, C(n+1, 3)) curvature on the local triangles (lexicographic), closed
        connection  (m, C(n+1, 2)) unit complex r_ab on the local edges, or None: the local gauge

and returns :class:`LocalEntries` ``(mass_off, mass_diag, dirichlet_off, dirichlet_diag)`` of the
local matrices of Theorems 15 and 17 (:mod:`dhlb.fem.integrals`), only those asked for (the others
are None), in a compact layout with the simplex axis last: ``off[p, s] = K_s[b, a]`` for the
local edge ``p = (a, b)`` (order of :func:`~dhlb.fem.integrals.local_edges`; ``K_s[a, b]`` is its
conjugate), shape ``(C(n+1, 2), m)`` complex, and ``diag[a, s] = K_s[a, a]``, shape ``(n+1, m)``
real.  Kernels trust their input: it is validated once at the public boundary
(``EuclideanComplex``, ``HermitianLineBundle``, :func:`~dhlb.fem.integrals.local_matrices`).

:func:`element_kernel` picks the kernel of a dimension from the registry :data:`KERNELS`:
the closed forms of :mod:`dhlb.fem.kernels_closed` for n = 2, 3 (proved against the generic
kernel in ``proofs/fast_local_closed_forms.py`` and ``tests/test_fem_kernels.py``), and
:func:`generic_kernel` (the Θ/Λ/Ξ moments as divided differences, any n) otherwise.
"""

from __future__ import annotations

from functools import cache
from math import factorial, prod
from typing import NamedTuple

import numpy as np

from dhlb.fem._local_data import local_edges, tensor_last
from dhlb.fem._moments import pair_moments
from dhlb.fem.kernels_closed import kernel_2d, kernel_3d

__all__ = ["LocalEntries", "KERNELS", "element_kernel", "generic_kernel", "dense"]


class LocalEntries(NamedTuple):
    """Compact local matrices (see the module docstring); None where not requested."""

    mass_off: np.ndarray | None
    mass_diag: np.ndarray | None
    dirichlet_off: np.ndarray | None
    dirichlet_diag: np.ndarray | None


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


def generic_kernel(gram, volume, omega, connection=None, *, mass=True, dirichlet=True) -> LocalEntries:
    """The element kernel of any dimension: Θ, Λ, Ξ by divided differences (:mod:`dhlb.fem._moments`).

    Parameters
    ----------
    gram, volume, omega, connection :
        One row per simplex, validated (see the module docstring); ``gram`` may be None if
        ``dirichlet`` is False.
    mass, dirichlet : bool
        Which local matrices to compute.

    Returns
    -------
    LocalEntries

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[[2., -1, -1], [-1, 1, 0], [-1, 0, 1]]])
    >>> Mo, Md, Ao, Ad = generic_kernel(G, np.array([0.5]), np.array([[0.0]]))
    >>> Ao.real.ravel().tolist(), Ad.ravel().tolist(), (Mo.real * 24).ravel().tolist()
    ([-0.5, -0.5, 0.0], [1.0, 0.5, 0.5], [1.0, 1.0, 1.0])
    """
    vol = np.asarray(volume, dtype=float)
    n = (np.shape(gram)[-1] - 1) if gram is not None else _dim(np.shape(omega)[1])
    tensor = tensor_last(np.asarray(omega, dtype=float).reshape(vol.size, -1), n)
    e = local_edges(n)
    r = np.exp(1j * tensor[0, e[:, 0], e[:, 1]]) if connection is None else np.ascontiguousarray(connection.T)
    th = out_a = None
    if dirichlet:
        out_a, th = _dirichlet(np.moveaxis(gram, 0, -1), vol, n, tensor, r)
    out_m = _mass(vol, n, tensor, r, th) if mass else None
    return LocalEntries(*_compact(out_m, e), *_compact(out_a, e))


def _dim(t: int) -> int:
    """N from the number ``C(n+1, 3)`` of local triangles (none: n = 1)."""
    n = 1
    while (n + 1) * n * (n - 1) // 6 < t:
        n += 1
    return n


def _compact(full, e):
    if full is None:
        return None, None
    k = full.shape[0]
    return np.ascontiguousarray(full[e[:, 1], e[:, 0]]), np.ascontiguousarray(full[np.arange(k), np.arange(k)].real)


KERNELS = {2: kernel_2d, 3: kernel_3d}


def element_kernel(n: int):
    """The element kernel for n-simplices: a closed form of :data:`KERNELS`, else :func:`generic_kernel`.

    Examples
    --------
    >>> element_kernel(3).__name__, element_kernel(4).__name__
    ('kernel_3d', 'generic_kernel')
    """
    return KERNELS.get(n, generic_kernel)


def dense(off: np.ndarray, diag: np.ndarray) -> np.ndarray:
    """The local matrices ``(m, n+1, n+1)`` (complex, Hermitian) from compact entries.

    Examples
    --------
    >>> import numpy as np
    >>> dense(np.array([[1j]]), np.array([[2.0], [3.0]]))[0].tolist()
    [[(2+0j), -1j], [1j, (3+0j)]]
    """
    k, m = diag.shape
    e = local_edges(k - 1)
    out = np.empty((k, k, m), dtype=complex)
    out[e[:, 1], e[:, 0]] = off
    out[e[:, 0], e[:, 1]] = off.conj()
    out[np.arange(k), np.arange(k)] = diag
    return np.ascontiguousarray(np.moveaxis(out, -1, 0))
