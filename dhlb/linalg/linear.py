"""Shifted sparse linear solves ``(A − λM) x = b`` through the backends of :mod:`dhlb.linalg.backends`."""

from __future__ import annotations

import numpy as np

from dhlb.errors import InvalidOperatorError, InvalidParameterError, NonFiniteError, ShapeError
from dhlb.linalg._checks import validate_pair as _validate_pair
from dhlb.linalg.backends import blas_guard, get_backend

__all__ = ["solve"]


def solve(A, M, lam, b, *, backend=None, positive_definite: bool = False) -> np.ndarray:
    """Solve ``(A − λ M) x = b`` by a sparse factorization (``b`` of shape (n,) or (n, r)).

    ``backend`` as in :func:`smallest_eigenpairs` (``auto``: a direct backend; Cholesky backends
    fall back to SuperLU when ``A − λM`` is indefinite).  With ``positive_definite=True`` the
    factorization asserts that ``A − λM`` is positive definite, i.e. that ``λ`` lies below the
    smallest eigenvalue of ``A u = λ M u``, and checks it (Cholesky, or the pivots of SuperLU's
    symmetric ``L D Lᴴ``) at no extra cost; an iterative backend (CG) can only check the
    necessary condition ``Re xᴴ b > 0``.

    Parameters
    ----------
    A : (n, n) scipy.sparse matrix or array
        The Hermitian operator.
    M : (n, n) scipy.sparse matrix or array
        The Hermitian mass matrix, with a positive diagonal.
    lam : float
        The shift ``λ``.
    b : (n,) or (n, r) float or complex array
        The right-hand side(s).
    backend : str or backend object, optional
        ``None``/``"auto"``, a name from :func:`available_backends`, or an object with ``name`` and
        ``factorize(K, positive_definite=False)``.
    positive_definite : bool, optional
        Assert, and check, that ``A − λM`` is positive definite.

    Returns
    -------
    x : (n,) or (n, r) float or complex array
        The solution, of the shape of ``b``; complex when ``A``, ``M`` or ``b`` is.

    Raises
    ------
    ShapeError, NonFiniteError, InvalidOperatorError
        Bad shapes, NaN/inf, non-Hermitian input, ``A − λM`` singular, or (``positive_definite``)
        not positive definite: the message names ``λ``.
    InvalidParameterError
        When ``lam`` is not a finite scalar, or ``backend`` names an unknown or uninstalled backend.
    InsufficientMemoryError
        When the factorization would not fit in the available memory.
    TypeError
        When ``backend`` is an object without ``name`` and ``factorize``.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> A = sp.csr_matrix([[2.0, -1.0], [-1.0, 2.0]]); M = sp.identity(2, format="csr")
    >>> solve(A, M, 0.5, np.array([1.0, 0.0]))
    array([1.2, 0.8])
    >>> solve(A, M, 1.5, np.array([1.0, 0.0]), positive_definite=True)     # eigenvalues 1 and 3
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidOperatorError: A − λM is not positive definite for λ = 1.5 ...
    """
    A, M = _validate_pair(A, M)
    n = A.shape[0]
    if not (np.isscalar(lam) and np.isfinite(lam)):
        raise InvalidParameterError(f"lam must be a finite scalar, got {lam!r}")
    B = np.asarray(b)
    if B.ndim not in (1, 2) or B.shape[0] != n:
        raise ShapeError(f"b must have shape ({n},) or ({n}, r), got {B.shape}")
    if not np.all(np.isfinite(B)):
        raise NonFiniteError("b contains NaN or inf")
    K = (A - lam * M).tocsc()
    be = get_backend(backend, n=n, nnz=A.nnz, eigen=False, shifted=not positive_definite)
    not_pd = (f"A − λM is not positive definite for λ = {lam:.10g} (...): λ must lie below the smallest "
              "eigenvalue of A u = λ M u; lower λ (or pass positive_definite=False for an indefinite solve)")
    with blas_guard():
        try:
            fac = be.factorize(K, positive_definite=bool(positive_definite))
        except InvalidOperatorError as err:
            if positive_definite:
                raise InvalidOperatorError(not_pd.replace("(...)", f"({err})")) from err
            raise
        if np.iscomplexobj(B) and not np.iscomplexobj(K.data):
            x = (fac.solve(np.ascontiguousarray(B.real, dtype=float))
                 + 1j * fac.solve(np.ascontiguousarray(B.imag, dtype=float)))
        else:
            x = fac.solve(B.astype(K.dtype))
    if not np.all(np.isfinite(x)):
        raise InvalidOperatorError(f"A - {lam}·M is numerically singular (the solution is not finite)")
    x2, B2 = x.reshape(n, -1), B.reshape(n, -1)
    if positive_definite and np.any((np.sum(np.conj(x2) * B2, axis=0).real <= 0) & np.any(B2 != 0, axis=0)):
        raise InvalidOperatorError(not_pd.replace("(...)", "(xᴴ (A − λM) x <= 0 for the solution x)"))
    return x
