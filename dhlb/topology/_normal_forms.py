"""Dense exact integer linear algebra: Hermite and Smith normal forms, determinants, small kernels and solves.

The kernels behind :mod:`dhlb.topology.intlinalg` (which re-exports the public names and dispatches
large or sparse input to :mod:`dhlb.topology._sparse_elim`); the sparse elimination calls the dense
kernel and solve here on its small residual. Arithmetic is exact (Python integers in numpy object
arrays).

Examples
--------
>>> import numpy as np
>>> from dhlb.topology._normal_forms import hermite_normal_form
>>> H, U = hermite_normal_form(np.array([[2, 4]]))
>>> H.tolist()
[[0, 2]]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import ShapeError
from dhlb.topology._intmatrix import as_object_matrix, egcd, object_eye, to_int_array

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "hermite_normal_form",
    "smith_normal_form",
    "is_unimodular",
    "integer_determinant",
    "dense_kernel_basis",
    "dense_solve_integer",
]


# ----------------------------------------------------------------------------- Hermite normal form
def hermite_normal_form(A: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Column-style Hermite normal form ``H = A U`` with ``U`` unimodular.

    ``H = (0 | H')``: the first ``n - r`` columns are zero (so those columns of ``U`` are a
    Z-basis of ``ker A``, as in the proof of the seed's Lemma 1), and ``H'`` (``r = rank A``
    columns) is in echelon form read from the bottom: the pivot of column ``j`` is its lowest
    nonzero entry, pivots are positive, pivot rows strictly increase with ``j``, and every entry
    to the right of a pivot in its row lies in ``[0, pivot)``.

    Parameters
    ----------
    A : array_like or sparse matrix, shape (m, n)
        Integer matrix.

    Returns
    -------
    H : ndarray, shape (m, n)
    U : ndarray, shape (n, n)
        Unimodular (``det U = ±1``) with ``A @ U == H``.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[1, 1, 0], [0, 1, 1]])      # boundary of the path 0-1-2 closed by an edge
    >>> H, U = hermite_normal_form(A)
    >>> H.tolist()
    [[0, 1, 0], [0, 0, 1]]
    >>> bool((A @ U == H).all()), int(abs(integer_determinant(U)))
    (True, 1)
    """
    H = as_object_matrix(A).copy()
    m, n = H.shape
    U = object_eye(n)
    k = n  # columns k..n-1 hold pivots
    for i in range(m - 1, -1, -1):
        if k == 0:
            break
        p = k - 1
        for j in range(p):
            b = H[i, j]
            if b == 0:
                continue
            a = H[i, p]
            g, x, y = egcd(a, b)
            ag, bg = a // g, b // g
            cp, cj = H[:, p].copy(), H[:, j].copy()
            H[:, p] = x * cp + y * cj
            H[:, j] = ag * cj - bg * cp
            up, uj = U[:, p].copy(), U[:, j].copy()
            U[:, p] = x * up + y * uj
            U[:, j] = ag * uj - bg * up
        piv = H[i, p]
        if piv == 0:
            continue
        if piv < 0:
            H[:, p] = -H[:, p]
            U[:, p] = -U[:, p]
            piv = -piv
        for j in range(k, n):
            q = H[i, j] // piv
            if q:
                H[:, j] = H[:, j] - q * H[:, p]
                U[:, j] = U[:, j] - q * U[:, p]
        k -= 1
    return to_int_array(H), to_int_array(U)


# ----------------------------------------------------------------------------- Smith normal form
def _snf(A: np.ndarray):
    """Smith normal form of an object matrix; returns ``(U, D, V, Uinv, Vinv)`` (object arrays)."""
    M = A.copy()
    m, n = M.shape
    U, Ui, V, Vi = object_eye(m), object_eye(m), object_eye(n), object_eye(n)

    def swap_rows(i, j):
        M[[i, j]] = M[[j, i]]
        U[[i, j]] = U[[j, i]]
        Ui[:, [i, j]] = Ui[:, [j, i]]

    def swap_cols(i, j):
        M[:, [i, j]] = M[:, [j, i]]
        V[:, [i, j]] = V[:, [j, i]]
        Vi[[i, j]] = Vi[[j, i]]

    for t in range(min(m, n)):
        sub = M[t:, t:]
        nz = np.argwhere(sub != 0)
        if len(nz) == 0:
            break
        absvals = np.array([abs(sub[i, j]) for i, j in nz], dtype=object)
        i0, j0 = nz[int(np.argmin(absvals))]
        if i0:
            swap_rows(t, t + i0)
        if j0:
            swap_cols(t, t + j0)
        while True:
            # make the pivot the smallest nonzero entry of row t / column t, then clear both
            while True:
                col = M[t + 1:, t]
                row = M[t, t + 1:]
                cand = [(abs(x), 0, t + 1 + i) for i, x in enumerate(col) if x != 0]
                cand += [(abs(x), 1, t + 1 + j) for j, x in enumerate(row) if x != 0]
                if not cand:
                    break
                best = min(cand)
                if best[0] < abs(M[t, t]):
                    (swap_rows if best[1] == 0 else swap_cols)(t, best[2])
                p = M[t, t]
                q = M[t + 1:, t] // p
                if q.any():
                    M[t + 1:, :] -= q[:, None] * M[t, None, :]
                    U[t + 1:, :] -= q[:, None] * U[t, None, :]
                    Ui[:, t] += Ui[:, t + 1:].dot(q)
                q = M[t, t + 1:] // p
                if q.any():
                    M[:, t + 1:] -= M[:, t, None] * q[None, :]
                    V[:, t + 1:] -= V[:, t, None] * q[None, :]
                    Vi[t, :] += q.dot(Vi[t + 1:, :])
            p = M[t, t]
            rest = M[t + 1:, t + 1:]
            bad = np.argwhere(rest % p != 0) if rest.size else np.zeros((0, 2), int)
            if len(bad) == 0:
                break
            i = t + 1 + int(bad[0][0])  # row t += row i, then re-clear
            M[t, :] += M[i, :]
            U[t, :] += U[i, :]
            Ui[:, i] -= Ui[:, t]
        if M[t, t] < 0:
            M[t, :] = -M[t, :]
            U[t, :] = -U[t, :]
            Ui[:, t] = -Ui[:, t]
    return U, M, V, Ui, Vi


def smith_normal_form(A: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Smith normal form ``U A V = D`` with unimodular ``U``, ``V``.

    ``D`` has the shape of ``A``, is zero off the diagonal, and its diagonal is
    ``d_1 | d_2 | ... | d_r`` (positive, each dividing the next) followed by zeros, ``r = rank A``.

    Parameters
    ----------
    A : array_like or sparse matrix, shape (m, n)
        Integer matrix (exact arithmetic; meant for small matrices).

    Returns
    -------
    U : ndarray, shape (m, m)
    D : ndarray, shape (m, n)
    V : ndarray, shape (n, n)

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[0, 2, 2], [2, 0, 2]])   # not the boundary of anything, just a matrix
    >>> U, D, V = smith_normal_form(A)
    >>> D.tolist()
    [[2, 0, 0], [0, 2, 0]]
    >>> bool((U @ A @ V == D).all())
    True
    """
    M = as_object_matrix(A)
    U, D, V, _, _ = _snf(M)
    return to_int_array(U), to_int_array(D), to_int_array(V)


def integer_determinant(A) -> int:
    """Exact determinant of a square integer matrix (Bareiss fraction-free elimination).

    Examples
    --------
    >>> integer_determinant([[2, 1], [7, 4]])
    1
    """
    M = as_object_matrix(A).copy()
    n = M.shape[0]
    if M.shape != (n, n):
        raise ShapeError(f"integer_determinant needs a square matrix, got shape {M.shape}.")
    sign, prev = 1, 1
    for k in range(n):
        if M[k, k] == 0:
            nz = [i for i in range(k + 1, n) if M[i, k] != 0]
            if not nz:
                return 0
            M[[k, nz[0]]] = M[[nz[0], k]]
            sign = -sign
        for i in range(k + 1, n):
            M[i, k + 1:] = (M[i, k + 1:] * M[k, k] - M[i, k] * M[k, k + 1:]) // prev
        prev = M[k, k]
    return sign * int(M[n - 1, n - 1]) if n else 1


def is_unimodular(U: ArrayLike) -> bool:
    """True iff ``U`` is a square integer matrix with determinant ±1.

    Parameters
    ----------
    U : (m, n) int array_like or sparse matrix
        An integer matrix (floats with integer values are accepted).

    Returns
    -------
    bool
        Whether ``m == n`` and ``det U = ±1`` (computed exactly).

    Raises
    ------
    InvalidMatrixError
        ``U`` has a non-integer or non-finite entry, or is ragged.
    ShapeError
        ``U`` is not 2-dimensional.

    Examples
    --------
    >>> is_unimodular([[1, 5], [0, -1]]), is_unimodular([[2, 0], [0, 1]])
    (True, False)
    """
    M = as_object_matrix(U)
    return M.shape[0] == M.shape[1] and abs(integer_determinant(M)) == 1


def dense_kernel_basis(M: np.ndarray) -> np.ndarray:
    """Kernel basis of a (small) object matrix from its Hermite form (no sparse detour)."""
    H, U = hermite_normal_form(M)
    z = 0  # the zero columns of the Hermite form are exactly the leading ones
    while z < H.shape[1] and not H[:, z].any():
        z += 1
    return to_int_array(U[:, :z])


def dense_solve_integer(M: np.ndarray, B: np.ndarray):
    """Solve ``M X = B`` over Z for object arrays (via Smith form); ``None`` if unsolvable."""
    m, n = M.shape
    U, D, V, _, _ = _snf(M)
    c = U.dot(B) if m else np.zeros((0, B.shape[1]), dtype=object)
    diag = [D[i, i] for i in range(min(m, n)) if D[i, i] != 0]
    r = len(diag)
    if c[r:].any():
        return None
    y = np.zeros((n, B.shape[1]), dtype=object)
    for i, d in enumerate(diag):
        if any(x % d for x in c[i]):
            return None
        y[i] = c[i] // d
    return V.dot(y) if n else y
