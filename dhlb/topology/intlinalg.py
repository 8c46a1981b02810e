"""Exact integer linear algebra: Hermite and Smith normal forms, integer kernels, integer solving.

All arithmetic is exact (Python integers in numpy object arrays).  Results are returned as
``int64`` arrays when every entry fits, otherwise as ``object`` arrays of Python ints.

Dense algorithms are meant for small matrices (up to a few hundred rows/columns).  Large sparse
matrices (boundary matrices of big complexes) go through the sparse unit-pivot elimination of
:mod:`dhlb.topology._sparse_elim` first, so only a small residual is treated densely:
:func:`integer_kernel_basis` and :func:`solve_integer` do that automatically for
``scipy.sparse`` input.

Examples
--------
>>> import numpy as np
>>> from dhlb.topology.intlinalg import smith_normal_form
>>> U, D, V = smith_normal_form(np.array([[2, 4], [6, 8]]))
>>> np.diag(D).tolist()
[2, 4]
>>> bool((U @ np.array([[2, 4], [6, 8]]) @ V == D).all())
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidMatrixError, ShapeError
from dhlb.topology._intmatrix import as_object_matrix, to_int_array
from dhlb.topology._normal_forms import (
    dense_kernel_basis,
    dense_solve_integer,
    hermite_normal_form,
    integer_determinant,
    is_unimodular,
    smith_normal_form,
)
from dhlb.topology._sparse_elim import sparse_kernel_basis, sparse_solve_integer

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "hermite_normal_form",
    "smith_normal_form",
    "integer_kernel_basis",
    "solve_integer",
    "is_unimodular",
    "integer_determinant",
]

# ----------------------------------------------------------------------------- kernels and solving
_DENSE_LIMIT = 2_500  # entries; larger dense input goes through sparse elimination too


def integer_kernel_basis(A: ArrayLike | sp.spmatrix) -> np.ndarray | sp.csc_matrix:
    """Z-basis of ``ker A ∩ Z^n`` as the columns of an integer matrix.

    Small dense input uses the Hermite form ``A U = (0 | H)`` (seed, Lemma 1): the first
    ``n - r`` columns of ``U``.  Sparse (or large) input is first reduced by unit-pivot elimination
    (:class:`~dhlb.topology._sparse_elim.ChainReduction`); the kernel of the small residual is
    lifted back by back-substitution.  For graph incidence matrices (every column one ``+1`` and
    one ``-1``) the basis is the fundamental cycles of a breadth-first spanning forest.

    Parameters
    ----------
    A : array_like or sparse matrix, shape (m, n)

    Returns
    -------
    K : ndarray (dense input) or scipy.sparse.csc_matrix (sparse input), shape (n, n - rank A)

    Examples
    --------
    >>> import numpy as np
    >>> d1 = np.array([[-1, -1, 0], [1, 0, -1], [0, 1, 1]])   # boundary of a triangle's edges
    >>> K = integer_kernel_basis(d1)
    >>> K.shape, bool((d1 @ K == 0).all())
    ((3, 1), True)
    >>> abs(K[:, 0]).tolist()
    [1, 1, 1]
    """
    A_sparse = _sparse_if_large(A)
    if A_sparse is not None:
        K = sparse_kernel_basis(A_sparse)
        return K if sp.issparse(A) else K.toarray()
    return dense_kernel_basis(as_object_matrix(A))



def solve_integer(A: ArrayLike | sp.spmatrix, b: ArrayLike) -> np.ndarray | None:
    """Integer solution ``x`` of ``A x = b``, or ``None`` if there is none.

    Parameters
    ----------
    A : array_like or sparse matrix, shape (m, n)
        Integer matrix.
    b : array_like, shape (m,) or (m, p)
        Integer right-hand side(s).

    Returns
    -------
    x : (n,) or (n, p) int array, or None
        One integer solution (for 2-D ``b``, all columns must be solvable); ``None`` when there
        is none. An object array of Python ints when an entry does not fit int64.

    Raises
    ------
    ShapeError
        ``b`` is neither 1- nor 2-dimensional, its number of rows is not ``m``, or ``A`` is not
        2-dimensional.
    InvalidMatrixError
        ``A`` or ``b`` has a non-integer or non-finite entry (or a non-numeric dtype).

    Examples
    --------
    >>> import numpy as np
    >>> d0 = np.array([[-1, 1, 0], [0, -1, 1]])   # coboundary of the path 0-1-2
    >>> f = solve_integer(d0, [2, 3])
    >>> (d0 @ f).tolist(), int(f[1] - f[0])
    ([2, 3], 2)
    >>> print(solve_integer([[2, 0], [0, 2]], [1, 0]))
    None
    """
    if np.ndim(b) not in (1, 2):
        raise ShapeError(f"b must be a vector or a matrix of right-hand sides, got shape {np.shape(b)}.")
    one_d = np.ndim(b) == 1
    B = as_object_matrix(b, "b", ndim=np.ndim(b))
    if one_d:
        B = B[:, None]
    A_sparse = _sparse_if_large(A)
    m = A.shape[0] if A_sparse is not None else as_object_matrix(A).shape[0]
    if B.shape[0] != m:
        raise ShapeError(f"b has {B.shape[0]} rows but A has {m}; they must match.")
    if A_sparse is not None:
        x = sparse_solve_integer(A_sparse, B)
    else:
        x = dense_solve_integer(as_object_matrix(A), B)
    if x is None:
        return None
    x = to_int_array(x)
    return x[:, 0] if one_d else x


def _sparse_if_large(A):
    """``A`` as int64 CSR if it is sparse or large (sparse elimination pays off), else None."""
    if sp.issparse(A):
        if A.dtype.kind == "f":
            as_object_matrix(A.data[None, :], "A")  # typed error for non-integer entries
        elif A.dtype.kind not in "iub":
            raise InvalidMatrixError(f"A has dtype {A.dtype}, expected integers.")
        return sp.csr_matrix(A).astype(np.int64)
    if np.size(A) <= _DENSE_LIMIT:
        return None
    M = to_int_array(as_object_matrix(A))
    return sp.csr_matrix(M) if M.dtype == np.int64 else None
