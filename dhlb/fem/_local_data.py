"""Per-simplex input data of the local finite-element matrices: layout and validation.

Local vertices of an n-simplex are numbered ``0..n`` in the order of its sorted row
(``X.simplices(n)``), so local order agrees with global order and a local edge ``(a, b)`` or
triangle ``(a, b, c)`` with increasing local indices is canonically oriented globally too.
Per-simplex arrays list local edges / triangles in lexicographic order
(:func:`local_edges`, :func:`local_triangles`).
"""

from __future__ import annotations

from functools import cache
from itertools import combinations
from math import comb

import numpy as np

from dhlb._coerce import check_int
from dhlb.errors import (
    CurvatureMismatchError,
    DegenerateSimplexError,
    InvalidConnectionError,
    InvalidMetricError,
    NonFiniteError,
    NotClosedError,
    ShapeError,
    differing_digits,
)

__all__ = ["local_edges", "local_triangles", "curvature_tensor", "local_gauge_connection"]

CLOSED_ATOL = 1e-8      # |dΩ| allowed on a local tetrahedron, times (1 + max|Ω|)
HOLONOMY_ATOL = 1e-8    # |r_ab r_bc r_ca - exp(iΩ_abc)| allowed
UNIT_ATOL = 1e-9        # ||r| - 1| allowed


@cache
def _combos(n: int, k: int) -> np.ndarray:
    arr = np.array(list(combinations(range(n + 1), k)), dtype=np.int64).reshape(-1, k)
    arr.setflags(write=False)
    return arr


def local_edges(n: int) -> np.ndarray:
    """Local edges ``(a, b)``, ``a < b``, of an n-simplex in lexicographic order, shape ``(C(n+1, 2), 2)``.

    Examples
    --------
    >>> local_edges(2).tolist()
    [[0, 1], [0, 2], [1, 2]]
    """
    return _combos(_check_dim(n), 2)


def local_triangles(n: int) -> np.ndarray:
    """Local triangles ``(a, b, c)``, ``a < b < c``, in lexicographic order, shape ``(C(n+1, 3), 3)``.

    Examples
    --------
    >>> local_triangles(3).tolist()
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
    """
    return _combos(_check_dim(n), 3)


def _t(row) -> tuple:
    """A vertex tuple of plain ints (for messages)."""
    return tuple(int(v) for v in row)


def _check_dim(n) -> int:
    return check_int(n, "simplex dimension", 1)


def dim_from_triangles(t: int, dim=None) -> int:
    """The dimension n with ``C(n+1, 3) == t`` (``t == 0`` means n = 1 unless ``dim`` says otherwise)."""
    if dim is not None:
        n = _check_dim(dim)
        if comb(n + 1, 3) != t:
            raise ShapeError(f"curvature has {t} values per simplex but a {n}-simplex has "
                             f"{comb(n + 1, 3)} triangles; pass one value per local triangle")
        return n
    if t == 0:
        return 1
    n = 2
    while comb(n + 1, 3) < t:
        n += 1
    if comb(n + 1, 3) != t:
        raise ShapeError(f"curvature has {t} values per simplex, which is not C(n+1, 3) for any n; "
                         "pass one value per local triangle in lexicographic order")
    return n


def parse_omega(omega, dim=None):
    """Return ``(omega (m, T) float, n, batched)`` after checking shape, reality and finiteness."""
    arr = np.asarray(omega)
    if np.iscomplexobj(arr):
        if np.any(arr.imag != 0):
            raise CurvatureMismatchError("curvature must be real (angles per local triangle); got complex values")
        arr = arr.real
    try:
        arr = arr.astype(float)
    except (TypeError, ValueError) as exc:
        raise CurvatureMismatchError(f"curvature must be a real array: {exc}") from None
    if arr.ndim not in (1, 2):
        raise ShapeError(f"curvature must have shape (m, C(n+1,3)) or (C(n+1,3),), got {arr.shape}")
    batched = arr.ndim == 2
    if not batched:
        arr = arr[None, :]
    n = dim_from_triangles(arr.shape[1], dim)
    bad = ~np.isfinite(arr)
    if bad.any():
        s, t = np.argwhere(bad)[0]
        raise NonFiniteError(f"curvature of simplex {s} on local triangle {_t(local_triangles(n)[t])} "
                             f"is {arr[s, t]}; all curvature values must be finite")
    return arr, n, batched


def curvature_tensor(omega, dim=None) -> np.ndarray:
    """Antisymmetric tensor ``Ω[s, a, b, c]`` from values on the local triangles.

    Parameters
    ----------
    omega : array_like, shape (m, C(n+1, 3)) or (C(n+1, 3),)
        Curvature ``Ω_abc`` of each simplex on its canonically oriented local triangles
        ``a < b < c`` (order of :func:`local_triangles`).
    dim : int, optional
        The simplex dimension n, needed only for n = 1 (no triangles).

    Returns
    -------
    ndarray, shape (m, n+1, n+1, n+1) or (n+1, n+1, n+1)
        ``Ω[a, b, c]`` is antisymmetric in its indices and zero when two coincide.

    Examples
    --------
    >>> T = curvature_tensor([0.5])
    >>> float(T[0, 1, 2]), float(T[1, 0, 2]), float(T[2, 0, 1]), float(T[0, 0, 1])
    (0.5, -0.5, 0.5, 0.0)
    """
    arr, n, batched = parse_omega(omega, dim)
    out = np.moveaxis(tensor_last(arr, n), -1, 0)
    return out if batched else out[0]


def tensor_last(arr: np.ndarray, n: int) -> np.ndarray:
    """The antisymmetric tensor with the simplex axis last: ``(n+1, n+1, n+1, m)``."""
    out = np.zeros((n + 1, n + 1, n + 1, arr.shape[0]))
    for t, (a, b, c) in enumerate(local_triangles(n)):
        v = arr[:, t]
        out[a, b, c] = out[b, c, a] = out[c, a, b] = v
        out[b, a, c] = out[a, c, b] = out[c, b, a] = -v
    return out


def check_closed(arr: np.ndarray, n: int) -> None:
    """Raise :class:`NotClosedError` if Ω is not closed on some local tetrahedron."""
    if n < 3:
        return
    tri = {_t(t): i for i, t in enumerate(local_triangles(n))}
    scale = 1.0 + np.abs(arr).max(axis=1)
    for a, b, c, d in map(_t, _combos(n, 4)):
        dom = arr[:, tri[b, c, d]] - arr[:, tri[a, c, d]] + arr[:, tri[a, b, d]] - arr[:, tri[a, b, c]]
        bad = np.abs(dom) > CLOSED_ATOL * scale
        if bad.any():
            s = int(np.argmax(bad))
            raise NotClosedError(
                f"curvature is not closed on simplex {s}: on its local tetrahedron {(a, b, c, d)} "
                f"dΩ = {dom[s]:.6g} (a multiple of 2π means a vortex inside). The associated "
                "piecewise-smooth bundle needs a closed curvature 2-form (seed Lemma 4): choose a "
                "closed real lift of the holonomy angles")


def local_gauge_connection(omega, dim=None) -> np.ndarray:
    """Connection of the local gauge of each simplex: ``r_0a = 1``, ``r_ab = exp(iΩ_0ab)``.

    In this gauge the frame at local vertex ``a`` is the parallel transport of the frame at local
    vertex 0 along the edge ``0a``, i.e. the radially parallel local section of vertex 0 (seed,
    proof of Theorem 14) evaluated at the vertices.

    Returns
    -------
    ndarray, shape (m, C(n+1, 2)) or (C(n+1, 2),)
        Unit complex ``r_ab`` on the local edges in the order of :func:`local_edges`.

    Examples
    --------
    >>> import numpy as np
    >>> np.round(local_gauge_connection([np.pi / 2]), 12).tolist()
    [(1+0j), (1+0j), 1j]
    """
    arr, n, batched = parse_omega(omega, dim)
    t = tensor_last(arr, n)
    e = local_edges(n)
    out = np.exp(1j * t[0, e[:, 0], e[:, 1]]).T
    return out if batched else out[0]


def parse_connection(connection, m: int, n: int, arr: np.ndarray) -> np.ndarray:
    """Validate ``(m, C(n+1,2))`` unit complex connection values against the curvature."""
    r = np.asarray(connection)
    ne = comb(n + 1, 2)
    if r.ndim == 1:
        r = r[None, :]
    if r.ndim != 2 or r.shape[1] != ne or r.shape[0] not in (1, m):
        raise ShapeError(f"connection must have shape (m, {ne}) = one unit complex number per local "
                         f"edge in lexicographic order (m = {m}), got {np.shape(connection)}")
    r = np.broadcast_to(r.astype(complex), (m, ne))
    if not np.all(np.isfinite(r)):
        s, e = np.argwhere(~np.isfinite(r))[0]
        raise NonFiniteError(f"connection of simplex {s} on local edge {_t(local_edges(n)[e])} is not finite")
    off = np.abs(np.abs(r) - 1.0) > UNIT_ATOL
    if off.any():
        s, e = np.argwhere(off)[0]
        raise InvalidConnectionError(
            f"connection of simplex {s} on local edge {_t(local_edges(n)[e])} is {r[s, e]:.6g}, "
            "not a unit complex number; a hermitian connection is unitary (use exp(1j*angle))")
    idx = {_t(e): i for i, e in enumerate(local_edges(n))}
    for t, (a, b, c) in enumerate(map(_t, local_triangles(n))):
        hol = r[:, idx[a, b]] * r[:, idx[b, c]] * np.conj(r[:, idx[a, c]])
        bad = np.abs(hol - np.exp(1j * arr[:, t])) > HOLONOMY_ATOL
        if bad.any():
            s = int(np.argmax(bad))
            sh, so = differing_digits(np.angle(hol[s]), np.angle(np.exp(1j * arr[s, t])))
            raise CurvatureMismatchError(
                f"simplex {s}, local triangle {(a, b, c)}: the holonomy r_ab r_bc r_ca has angle {sh} "
                f"but Ω = {arr[s, t]!r} has angle {so} (mod 2π); the curvature must satisfy "
                "r_ij r_jk r_ki = exp(iΩ_ijk) (docs/conventions.md)")
    return r


def parse_volume(volume, m: int | None = None) -> tuple[np.ndarray, bool]:
    """Return ``(volume (m,) float, batched)``; volumes must be finite and positive."""
    try:
        v = np.asarray(volume, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"volume must be a real number or a 1-d array of them: {exc}") from None
    if v.ndim > 1:
        raise ShapeError(f"volume must be a scalar or have shape (m,), got {v.shape}")
    batched = v.ndim == 1
    v = v.reshape(-1)
    if m is not None and v.size not in (1, m):
        raise ShapeError(f"got {v.size} volumes for {m} simplices")
    if not np.all(np.isfinite(v)):
        raise NonFiniteError(f"volume of simplex {int(np.argmax(~np.isfinite(v)))} is not finite")
    if np.any(v <= 0):
        s = int(np.argmax(v <= 0))
        raise DegenerateSimplexError(f"simplex {s} has volume {v[s]:.6g}; volumes must be positive")
    return (np.broadcast_to(v, (m,)) if m is not None else v), batched


def parse_gram(gram) -> tuple[np.ndarray, int, bool]:
    """Return ``(G (m, n+1, n+1), n, batched)`` after checking the Gram matrix of barycentric gradients."""
    try:
        g = np.asarray(gram, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidMetricError(f"gram must be a real array: {exc}") from None
    if g.ndim not in (2, 3) or g.shape[-1] != g.shape[-2] or g.shape[-1] < 2:
        raise ShapeError(f"gram must have shape (m, n+1, n+1) with n >= 1, got {g.shape}")
    batched = g.ndim == 3
    g = g if batched else g[None]
    n = g.shape[-1] - 1
    if not np.all(np.isfinite(g)):
        raise NonFiniteError(f"gram of simplex {int(np.argmax(~np.isfinite(g).all(axis=(1, 2))))} is not finite")
    scale = np.abs(g).max(axis=(1, 2))
    asym = np.abs(g - g.transpose(0, 2, 1)).max(axis=(1, 2)) > 1e-10 * scale
    rows = np.abs(g.sum(axis=2)).max(axis=1) > 1e-8 * scale
    for bad, what in ((asym, "is not symmetric"), (rows, "has rows not summing to zero (Σ_j ∇λ_j = 0)")):
        if bad.any():
            s = int(np.argmax(bad))
            raise InvalidMetricError(f"Gram matrix <∇λ_i, ∇λ_j> of simplex {s} {what}")
    ev = np.linalg.eigvalsh(0.5 * (g + g.transpose(0, 2, 1)))
    bad = (ev[:, 0] < -1e-8 * ev[:, -1]) | (ev[:, 1] <= 100 * (n + 1) * np.finfo(float).eps * ev[:, -1])
    if bad.any():
        s = int(np.argmax(bad))
        raise InvalidMetricError(f"Gram matrix of simplex {s} is not positive semidefinite of rank n = {n} "
                                 f"(eigenvalues {ev[s]}); the simplex is degenerate or the metric invalid")
    return g, n, batched
