"""Exact linear algebra over the prime field GF(p) with int64 arithmetic.

Elements are stored as int64 in ``0 .. p-1``.  Every product is reduced before the next
addition, so all intermediate values stay below ``p**2 + p``; primes up to ``2**31`` are
therefore safe.  Batched routines act on the last two axes (``(..., m, n)``).

Examples
--------
>>> import numpy as np
>>> from dhlb.bundles.finite_field import inv_mod, matmul_mod
>>> A = np.array([[1, 2], [3, 4]])
>>> Ainv, singular = inv_mod(A, 5)
>>> matmul_mod(A, Ainv, 5).tolist(), bool(singular)
([[1, 0], [0, 1]], False)
"""

from __future__ import annotations

import math

import numpy as np

from dhlb.errors import InvalidConnectionError

__all__ = [
    "check_prime",
    "pow_mod",
    "matmul_mod",
    "inv_mod",
    "rref_mod",
    "rank_mod",
    "nullspace_mod",
]

MAX_PRIME = 2**31


def check_prime(p) -> int:
    """Validate ``p`` as a prime below ``2**31`` and return it as ``int``.

    Examples
    --------
    >>> check_prime(7)
    7
    """
    try:
        q = int(p)
    except (TypeError, ValueError):
        raise InvalidConnectionError(f"the field ('GF', {p!r}) needs an integer prime p") from None
    if q != p or not _is_prime(q):
        raise InvalidConnectionError(f"the field ('GF', {p!r}) needs a prime p; {p!r} is not prime")
    if q >= MAX_PRIME:
        raise InvalidConnectionError(f"GF(p) arithmetic is exact in int64 only for p < 2**31, got p = {q}")
    return q


def _is_prime(q: int) -> bool:
    """Exact primality for ``q < 2**31`` (or a little more): trial division by 2 and the odd numbers up to √q."""
    if q < 2:
        return q == 2
    if q % 2 == 0:
        return q == 2
    odd = np.arange(3, math.isqrt(q) + 1, 2, dtype=np.int64)
    return not bool(np.any(q % odd == 0))


def pow_mod(x, e: int, p: int) -> np.ndarray:
    """Elementwise ``x**e mod p`` (``e >= 0``) by repeated squaring.

    Examples
    --------
    >>> pow_mod([2, 3, 4], 5, 7).tolist()   # Fermat: x**(p-2) is the inverse
    [4, 5, 2]
    """
    base = np.asarray(x, dtype=np.int64) % p
    out = np.ones_like(base)
    while e:
        if e & 1:
            out = out * base % p
        base = base * base % p
        e >>= 1
    return out


def matmul_mod(A, B, p: int) -> np.ndarray:
    """Batched matrix product mod p (broadcasting over leading axes).

    Examples
    --------
    >>> matmul_mod([[2, 3]], [[4], [5]], 7).tolist()
    [[2]]
    """
    A = np.asarray(A, dtype=np.int64)
    B = np.asarray(B, dtype=np.int64)
    k = A.shape[-1]
    if B.shape[-2] != k:
        raise ValueError(f"matmul_mod: shapes {A.shape} and {B.shape} do not match")
    shape = np.broadcast_shapes(A.shape[:-2], B.shape[:-2]) + (A.shape[-2], B.shape[-1])
    out = np.zeros(shape, np.int64)
    for t in range(k):
        out = (out + A[..., :, t, None] * B[..., None, t, :]) % p
    return out


def inv_mod(A, p: int) -> tuple[np.ndarray, np.ndarray]:
    """Batched inverse mod p by Gauss–Jordan elimination.

    Returns ``(inverse, singular)``; ``singular`` is a bool array over the batch (the
    inverse entries of singular matrices are meaningless).
    """
    A = np.asarray(A, dtype=np.int64) % p
    batch = A.shape[:-2]
    K = A.shape[-1]
    eye = np.broadcast_to(np.eye(K, dtype=np.int64), (int(np.prod(batch, dtype=np.int64)), K, K))
    M = np.concatenate([A.reshape(-1, K, K), eye], axis=2)
    N = M.shape[0]
    singular = np.zeros(N, bool)
    idx = np.arange(N)
    for col in range(K):
        nz = M[:, col:, col] != 0
        has = nz.any(axis=1)
        singular |= ~has
        piv = col + np.argmax(nz, axis=1)
        row_c = M[idx, col].copy()
        M[idx, col] = M[idx, piv]
        M[idx, piv] = row_c
        scale = pow_mod(M[:, col, col], p - 2, p)
        M[:, col, :] = M[:, col, :] * scale[:, None] % p
        f = M[:, :, col].copy()
        f[:, col] = 0
        M = (M - f[:, :, None] * M[:, None, col, :]) % p
    return M[:, :, K:].reshape(batch + (K, K)), singular.reshape(batch)


def rref_mod(A, p: int) -> tuple[np.ndarray, list[int]]:
    """Reduced row echelon form of one matrix mod p and its pivot columns.

    Examples
    --------
    >>> R, piv = rref_mod([[2, 4], [1, 2]], 5)
    >>> R.tolist(), piv
    ([[1, 2], [0, 0]], [0])
    """
    R = np.array(A, dtype=np.int64, ndmin=2) % p
    m, n = R.shape
    pivots: list[int] = []
    row = 0
    for col in range(n):
        if row >= m:
            break
        nz = np.nonzero(R[row:, col])[0]
        if nz.size == 0:
            continue
        r = row + int(nz[0])
        R[[row, r]] = R[[r, row]]
        R[row] = R[row] * pow(int(R[row, col]), p - 2, p) % p
        f = R[:, col].copy()
        f[row] = 0
        R = (R - f[:, None] * R[row][None, :]) % p
        pivots.append(col)
        row += 1
    return R, pivots


def rank_mod(A, p: int) -> int:
    """Rank of a matrix over GF(p).

    Examples
    --------
    >>> rank_mod([[1, 1], [1, 1]], 2)
    1
    """
    return len(rref_mod(A, p)[1])


def nullspace_mod(A, p: int) -> np.ndarray:
    """A basis of ``{x : A x = 0 mod p}`` as the columns of an ``(n, k)`` int64 array.

    Examples
    --------
    >>> nullspace_mod([[1, 1]], 3).T.tolist()
    [[2, 1]]
    """
    A = np.array(A, dtype=np.int64, ndmin=2)
    n = A.shape[1]
    R, pivots = rref_mod(A, p)
    free = [c for c in range(n) if c not in set(pivots)]
    basis = np.zeros((n, len(free)), np.int64)
    for j, c in enumerate(free):
        basis[c, j] = 1
        for i, pc in enumerate(pivots):
            basis[pc, j] = (-R[i, c]) % p
    return basis
