"""Input validation and small helpers of :mod:`dhlb.linalg.eigen` (Hermitian pencils, norms, phases)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from dhlb.errors import InvalidOperatorError, NonFiniteError, ShapeError

__all__ = ["as_sparse", "eta", "fix_phase", "norm1", "validate_pair"]


def as_sparse(A, name: str) -> sp.csr_matrix:
    if sp.issparse(A):
        S = sp.csr_matrix(A)
    else:
        arr = np.asarray(A)
        if arr.ndim != 2:
            raise ShapeError(f"{name} must be a 2-D matrix, got an array of shape {arr.shape}")
        S = sp.csr_matrix(arr)
    if S.shape[0] != S.shape[1]:
        raise ShapeError(f"{name} must be square, got shape {S.shape}")
    if S.shape[0] == 0:
        raise ShapeError(f"{name} is empty (shape {S.shape})")
    if not (np.issubdtype(S.dtype, np.number) and not np.issubdtype(S.dtype, np.bool_)):
        raise ShapeError(f"{name} must have a numeric dtype, got {S.dtype}")
    S = S.astype(np.complex128 if np.iscomplexobj(S.data) else np.float64, copy=False)  # no copy of a large pencil
    if not S.has_canonical_format:  # summing duplicates works in place: never on the caller's arrays
        S = S.copy()
        S.sum_duplicates()
    if not np.all(np.isfinite(S.data)):
        coo = S.tocoo()
        i = np.nonzero(~np.isfinite(coo.data))[0][0]
        raise NonFiniteError(f"{name}[{int(coo.row[i])}, {int(coo.col[i])}] = {coo.data[i]} is not finite")
    return S


def _check_hermitian(S: sp.csr_matrix, name: str) -> None:
    D = (S - S.conj().T).tocoo()
    scale = np.abs(S.data).max() if S.nnz else 0.0
    bad = np.abs(D.data) > 1e-10 * scale
    if np.any(bad):
        i = np.nonzero(bad)[0][0]
        r, c = int(D.row[i]), int(D.col[i])
        raise InvalidOperatorError(f"{name} is not Hermitian: {name}[{r}, {c}] = {S[r, c]} but "
                                   f"conj({name}[{c}, {r}]) = {np.conj(S[c, r])}")


def validate_pair(A, M) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    A = as_sparse(A, "A")
    M = as_sparse(M, "M")
    if A.shape != M.shape:
        raise ShapeError(f"A has shape {A.shape} but M has shape {M.shape}; they must agree")
    _check_hermitian(A, "A")
    _check_hermitian(M, "M")
    d = M.diagonal()
    if np.any(d.real <= 0):
        i = int(np.nonzero(d.real <= 0)[0][0])
        raise InvalidOperatorError(f"M is not positive definite: M[{i}, {i}] = {d[i]}")
    return A, M


def norm1(S: sp.csr_matrix) -> float:
    return float(abs(S).sum(axis=0).max())


def phase_factors(U: np.ndarray) -> np.ndarray:
    """The unit factor per column that makes its largest-modulus entry (the first of equal ones) real positive."""
    j = np.argmax(np.abs(U), axis=0)
    piv = U[j, np.arange(U.shape[1])]
    mod = np.abs(piv)
    return np.where(mod > 0, mod / np.where(mod > 0, piv, 1), 1)


def fix_phase(U: np.ndarray) -> np.ndarray:
    """Make the largest-modulus entry of each column real positive (deterministic output)."""
    if U.size == 0:
        return U
    return U * phase_factors(U)[None, :]


def eta(R, lam, U, normA, normM) -> np.ndarray:
    den = (normA + np.abs(lam) * normM) * np.linalg.norm(U, axis=0)
    return np.linalg.norm(R, axis=0) / np.where(den > 0, den, 1.0)
