"""The eigen-solver's result type and the steps shared by its methods (see :mod:`dhlb.linalg.eigen`).

:class:`EigenResult`; the Rayleigh–Ritz step with the backward errors of the wanted pairs; the
block subspace iteration on a factorized shift; the driver of iterative backends (LOBPCG in
chunks); and the errors raised when ``A`` turns out not to be PSD or nothing converged.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from dhlb.errors import ConvergenceError, InvalidOperatorError, NotSemidefiniteError
from dhlb.linalg._checks import eta as _eta
from dhlb.linalg._checks import fix_phase as _fix_phase
from dhlb.linalg._checks import norm1 as _norm1

__all__ = ["EigenResult", "m_orthonormalize"]


@dataclass(frozen=True)
class EigenResult:
    """Result of :func:`~dhlb.linalg.smallest_eigenpairs`.

    Every parameter is kept as the attribute of the same name.

    Parameters
    ----------
    eigenvalues : (k,) float array
        The eigenvalues, ascending.
    eigenvectors : (n, k) float or complex array
        The eigenvectors as columns, M-orthonormal (``Uᴴ M U = I``).
    iterations : int
        Applications of the shifted inverse (Lanczos), LOBPCG iterations, or 0 (dense).
    residuals : (k,) float array
        The normwise backward errors ``η`` of the pairs.
    converged : bool
        Whether every pair passed the backward-error test.
    backend : str
        The factorization backend actually used.
    shift : float
        The shift ``σ`` that was factorized (``A − σM``).
    block_size : int, optional
        The largest Lanczos basis or the LOBPCG block.
    method : str, optional
        ``"lanczos"``, ``"dense"``, ``"lobpcg"``, or ``"rayleigh-ritz"`` (the warm start passed as it was).
    factorizations : int, optional
        The number of sparse factorizations done.
    solves : int, optional
        The number of solves with the factorization (right-hand sides).
    note : str, optional
        Empty, or why the solver departed from the requested method (e.g. the factorization would
        not fit in memory and an iterative backend was used instead).
    factor : object or None, optional
        The factorization of ``A − shift·M`` that was used (``factor.solve(B)`` solves
        ``(A − shift·M) X = B``), so that callers can reuse it without refactorizing; ``None`` for
        iterative backends.  Not part of equality or ``repr``.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from dhlb.linalg import smallest_eigenpairs
    >>> A = sp.csr_matrix([[2.0, -1.0], [-1.0, 2.0]])                # eigenvalues 1 and 3
    >>> r = smallest_eigenpairs(A, sp.identity(2, format="csr"), 1)
    >>> r.converged, round(float(r.eigenvalues[0]), 6), r.eigenvectors.shape, r.method
    (True, 1.0, (2, 1), 'dense')
    """

    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    iterations: int
    residuals: np.ndarray
    converged: bool
    backend: str
    shift: float
    block_size: int = 0
    method: str = "lanczos"
    factorizations: int = 0
    solves: int = 0
    note: str = ""
    factor: object = field(default=None, compare=False, repr=False)


def m_orthonormalize(W: np.ndarray, M) -> tuple[np.ndarray, np.ndarray]:
    """An M-orthonormal basis ``Q`` of ``span W`` and ``M Q`` (eigen-decomposed Gram matrix).

    Cheaper than a Householder QR for tall, skinny blocks. A second pass restores the
    orthogonality lost to rounding when the Gram matrix is ill-conditioned; when the columns are
    numerically dependent (eigenvalue ratio below 1e-12) a Householder QR restores a full-rank
    basis first.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> Q, MQ = m_orthonormalize(np.array([[1.0, 1.0], [0.0, 1.0]]), sp.diags([1.0, 4.0]))
    >>> bool(np.allclose(Q.T @ MQ, np.eye(2)))
    True
    """
    Q, MQ = W, M @ W
    for _ in range(2):
        G = Q.T.conj() @ MQ
        s, V = np.linalg.eigh(0.5 * (G + G.conj().T))
        if s[0] <= 1e-12 * s[-1]:
            Q = np.linalg.qr(Q)[0]
            MQ = M @ Q
            G = Q.conj().T @ MQ
            s, V = np.linalg.eigh(0.5 * (G + G.conj().T))
        T = V / np.sqrt(s)
        Q, MQ = Q @ T, MQ @ T
        if s[0] > 1e-4 * s[-1]:  # well conditioned: orthogonal to ~eps·cond; no second pass needed
            break
    return Q, MQ


def _rayleigh_ritz(A, M, W, k, shift, normA, normM):
    """Ritz pairs of span ``W`` ordered by distance to ``shift``: ``(U, MU, λ_k, U_k, η_k)``."""
    W = W / np.linalg.norm(W, axis=0)
    Q, MQ = m_orthonormalize(W, M)
    AQ = A @ Q
    Qh = Q.conj().T
    Ap, Mp = Qh @ AQ, Qh @ MQ
    Ap, Mp = 0.5 * (Ap + Ap.conj().T), 0.5 * (Mp + Mp.conj().T)
    try:
        theta, C = sla.eigh(Ap, Mp)
    except np.linalg.LinAlgError as err:
        raise InvalidOperatorError(f"M is not positive definite (projected mass not PD: {err})") from err
    order = np.argsort(np.abs(theta - shift), kind="stable")
    theta, C = theta[order], C[:, order]
    U, MU = Q @ C, MQ @ C
    sel = np.argsort(theta[:k], kind="stable")
    lam, Uk = theta[:k][sel], U[:, :k][:, sel]
    R = AQ @ C[:, :k][:, sel] - MU[:, :k][:, sel] * lam[None, :]  # only the k wanted residuals
    return U, MU, lam, Uk, _eta(R, lam, Uk, normA, normM)


def _not_psd(lam0, shift):
    return NotSemidefiniteError(f"A is not positive semidefinite: found the eigenvalue {lam0:.6g} "
                                f"< -ε = {shift:.3g}; pass sigma= to search near a chosen value")


def _not_converged(res, maxiter, tol, p):
    return ConvergenceError(f"smallest_eigenpairs: not converged after {maxiter} iterations "
                            f"(largest backward error {res.residuals.max():.3g} > tol = {tol:.3g}); for a "
                            f"clustered spectrum raise block_size (now {p}) above the cluster size, else increase "
                            "maxiter, loosen tol, or pass a better v0", result=res)


def _iterate_lobpcg(be, A, M, U, k, eps_shift, tol, maxiter):
    """Iterative backend: its block method in chunks (25, 50, 100, ... iterations).

    Each chunk is followed by Rayleigh–Ritz and the backward-error test of the ``k`` wanted pairs
    (the extra block vectors need not converge), restarting from the current block.
    """
    normA, normM = _norm1(A), _norm1(M)
    p, its, chunk = U.shape[1], 0, 25
    while its < maxiter:
        X, used = be.eigensolve(A, M, U, shift=eps_shift, tol=tol, maxiter=min(chunk, maxiter - its))
        its, chunk = its + used, 2 * chunk
        if not np.all(np.isfinite(X)):
            raise InvalidOperatorError(f"{be.name} produced non-finite vectors (A or M numerically singular)")
        U, _, lam, Uk, eta = _rayleigh_ritz(A, M, X, k, -np.inf, normA, normM)
        if lam[0] < -eps_shift:
            raise _not_psd(lam[0], -eps_shift)
        if np.all(eta <= tol):
            return EigenResult(lam, _fix_phase(Uk), its, eta, True, be.name, -eps_shift, p,
                               getattr(be, "method", "lobpcg"))
    raise _not_converged(EigenResult(lam, _fix_phase(Uk), its, eta, False, be.name, -eps_shift, p,
                                     getattr(be, "method", "lobpcg")),
                         maxiter, tol, p)
