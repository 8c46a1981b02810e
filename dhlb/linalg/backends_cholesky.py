"""Cholesky backends: CHOLMOD through cvxopt, and cholespy on the real 2N embedding.

Both factorize positive definite Hermitian matrices only.  Asked to factorize a matrix that
turns out indefinite without ``positive_definite=True`` (``sigma`` inside the spectrum, or
:func:`dhlb.fem.solve` at an interior ``λ``), they fall back to SuperLU; the returned factor's
``name`` says which method was used.

The real 2N embedding of a complex Hermitian ``K = R + iI`` (``R`` symmetric, ``I``
antisymmetric) is the real symmetric ``[[R, −I], [I, R]]``: ``K (x + iy) = b + ic`` iff
``[[R, −I], [I, R]] [x; y] = [b; c]``, and it is positive definite iff ``K`` is (its
eigenvalues are those of ``K``, each twice).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> K = sp.csc_matrix(np.array([[2.0, -1j], [1j, 2.0]]))
>>> E = real_embedding(K).toarray()
>>> bool(np.allclose(E, E.T)), E.shape
(True, (4, 4))
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from cvxopt import cholmod, matrix, spmatrix

from dhlb.errors import InvalidOperatorError
from dhlb.linalg.backends import (
    SuperLUBackend,
    _fitting_alternatives,
    blas_guard,
    cached_symbolic,
    canonical_csc,
    pattern_dimension,
    pattern_key,
)
from dhlb.linalg.memory import (
    TRIM_MIN,
    InsufficientMemoryError,
    available_bytes,
    check_factorization_memory,
    release_free_memory,
)
from dhlb.linalg.ordering import nested_dissection

__all__ = ["CholespyBackend", "CholmodBackend", "real_embedding"]


def real_embedding(K) -> sp.csc_matrix:
    """The real symmetric ``[[Re K, −Im K], [Im K, Re K]]`` of a complex Hermitian ``K`` (see module docstring)."""
    K = sp.csc_matrix(K)
    R, I = K.real, K.imag
    return canonical_csc(sp.bmat([[R, -I], [I, R]], format="csc"))


def _fallback(K, positive_definite, err, name, why=None):
    """SuperLU's factor of ``K``, which ``name`` found not positive definite (or the error, if it was asserted)."""
    if positive_definite:
        raise InvalidOperatorError(f"the matrix is not positive definite ({name}: {why or err})") from err
    return SuperLUBackend().factorize(K)


class _CholmodFactor:
    """``K X = B`` through CHOLMOD's ``P K Pᵀ = L Lᴴ`` (cvxopt); ``B`` is copied, never overwritten."""

    name = "cholmod"

    def __init__(self, factor, n, complex_):
        self.factor, self.n, self.complex_ = factor, n, complex_

    def solve(self, B):
        B = np.asarray(B)
        cols = B.reshape(self.n, -1)
        if not self.complex_ and np.iscomplexobj(cols):   # a real factor: the real and imaginary parts together
            X = self._solve(np.hstack([cols.real, cols.imag]), np.float64)
            k = cols.shape[1]
            return (X[:, :k] + 1j * X[:, k:]).reshape(B.shape)
        return self._solve(cols, np.complex128 if self.complex_ else np.float64).reshape(B.shape)

    def _solve(self, cols, dtype):
        X = matrix(np.asfortranarray(cols, dtype=dtype))
        with blas_guard():
            cholmod.solve(self.factor, X)
        return np.asarray(X)      # a view of X's column-major buffer


class CholmodBackend:
    """CHOLMOD (SuiteSparse) supernodal Cholesky ``P K Pᵀ = L Lᴴ`` through cvxopt's bundled CHOLMOD.

    Complex Hermitian matrices are factorized directly, only their lower triangle is passed, and
    the factor ``L`` is all that is stored (half of SuperLU's ``L`` and ``U``).  ``P`` is CHOLMOD's
    own AMD ordering, or from :data:`METIS_MIN` unknowns on the nested-dissection order of
    :func:`dhlb.linalg.ordering.nested_dissection` (METIS, computed once per sparsity pattern and
    cached).  The factorization succeeds iff ``K`` is positive definite, which is therefore proved
    at every size; a matrix that is not falls back to SuperLU (or raises
    :class:`~dhlb.errors.InvalidOperatorError` under ``positive_definite=True``).
    """

    name = "cholmod"

    def factorize(self, K, *, positive_definite: bool = False):
        """Factorize ``K``; raises :class:`InvalidOperatorError` if asserted PD and it is not."""
        K = canonical_csc(K)
        complex_ = K.dtype.kind == "c" and bool(np.any(K.data.imag))
        n = K.shape[0]
        need = check_factorization_memory(n, K.nnz, complex_=complex_, triangles=1, backend=self.name,
                                          dimension=lambda: pattern_dimension(K), alternatives=_fitting_alternatives())
        q = cached_symbolic(pattern_key(self.name, K), lambda: nested_dissection(K)) if n >= METIS_MIN else None
        cols = np.repeat(np.arange(n, dtype=np.intp), np.diff(K.indptr))
        lower = K.indices >= cols
        data = K.data[lower] if complex_ else K.data.real[lower]
        A = spmatrix(matrix(np.ascontiguousarray(data, np.complex128 if complex_ else np.float64)),
                     matrix(K.indices[lower].astype(np.intp)), matrix(cols[lower]), (n, n))
        del cols, lower, data
        saved = dict(cholmod.options)     # cvxopt's options are global: set ours, then give the caller's back
        cholmod.options["supernodal"] = 2
        try:
            with blas_guard():
                order = {} if q is None else {"p": matrix(q.astype(np.intp))}   # cvxopt refuses p=None
                factor = cholmod.symbolic(A, uplo="L", **order)
                if n >= TRIM_MIN:     # the ordering's and the conversion's garbage, then the factorization's
                    release_free_memory()
                cholmod.numeric(A, factor)
                if n >= TRIM_MIN:
                    release_free_memory()
        except ArithmeticError as err:   # the leading minor of order err.args[0] is not positive
            return _fallback(K, positive_definite, err, "CHOLMOD",
                             f"the leading minor of order {err} of the reordered matrix is not positive")
        except MemoryError as err:
            raise InsufficientMemoryError(
                f"CHOLMOD ran out of memory factorizing this {n:,}-unknown matrix (estimated {need / 2**30:.2f} "
                f"GiB, {available_bytes() / 2**30:.2f} GiB available now); use backend='amg-lobpcg' "
                "(pip install pyamg) or a machine with more memory", needed=need, available=available_bytes()) \
                from err
        finally:
            cholmod.options.clear()
            cholmod.options.update(saved)
        return _CholmodFactor(factor, n, complex_)


METIS_MIN = 40_000
"""From this many unknowns on, CHOLMOD factorizes in METIS' nested-dissection order instead of its AMD.

Measured (cross-field matrices, factorization and 15 solves; the ordering counted): the bunny
(34,834 unknowns) 0.44 s with AMD against 0.25 + 0.35 s with METIS; the icosphere in its
subdivision order, 40,962 unknowns: 0.98 s against 0.31 + 0.59 s; 655,362 unknowns: numeric
factorization 31 s and 1.35 GiB with AMD against 6.9 + 8.8 s and 790 MiB.  AMD, unlike SuperLU's
minimum degree, does not blow up on a bad vertex numbering (the icosphere above; SuperLU's minimum
degree took 4.3 s there).
"""


class _CholespyFactor:
    name = "cholespy"

    def __init__(self, solver, n, complex_):
        self.solver, self.n, self.complex_ = solver, n, complex_

    def solve(self, B):
        B = np.asarray(B)
        n = self.n
        with blas_guard():
            if self.complex_:
                B = B.astype(np.complex128)
                X = self._solve(np.concatenate([B.real, B.imag], axis=0))
                return X[:n] + 1j * X[n:]
            if np.iscomplexobj(B):
                return self._solve(B.real) + 1j * self._solve(B.imag)
            return self._solve(B)

    def _solve(self, b):
        b = np.ascontiguousarray(b, dtype=np.float64)
        x = np.zeros_like(b)
        self.solver.solve(b, x)
        return x


class CholespyBackend:
    """cholespy's CPU Cholesky (CHOLMOD inside; real matrices only).

    A complex Hermitian ``K`` is factorized through its real 2N embedding (module docstring),
    which doubles the unknowns: measured about 3× slower than CHOLMOD on the complex matrix.
    cholespy offers no separate symbolic analysis, so nothing is reused across calls.
    """

    name = "cholespy"

    def factorize(self, K, *, positive_definite: bool = False):
        """Factorize ``K`` (its real embedding if complex).

        Raises :class:`InvalidOperatorError` if asserted positive definite and it is not.
        """
        import cholespy

        K = canonical_csc(K)
        complex_ = K.dtype.kind == "c" and bool(np.any(K.data.imag))
        Kr = real_embedding(K) if complex_ else canonical_csc(K.real)
        with blas_guard():
            try:
                solver = cholespy.CholeskySolverD(Kr.shape[0], Kr.indptr.astype(np.int32), Kr.indices.astype(np.int32),
                                                  np.ascontiguousarray(Kr.data, dtype=np.float64),
                                                  cholespy.MatrixType.CSC)
            except ValueError as err:  # "Matrix is not positive definite!"
                return _fallback(K, positive_definite, err, "cholespy")
        return _CholespyFactor(solver, K.shape[0], complex_)
