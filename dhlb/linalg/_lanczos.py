"""Shift-and-invert Lanczos with thick restarts, stopped by the backward error of ``(A, M)``.

The eigenpairs of ``A u = λ M u`` nearest a shift ``σ`` are the dominant ones of ``W = K⁻¹M``
(``K = A − σM``), which is self-adjoint in the M inner product: ``W u = θ u`` with
``θ = 1 / (λ − σ)``.  Lanczos builds an M-orthonormal basis ``Q`` of the Krylov space of ``W``
(every new vector is M-orthogonalized against all previous ones twice -- full
reorthogonalization, so no spurious copies appear) and the projection ``H = Qᴴ M W Q``.  After
``m`` steps ``W Q = Q H + β q_{m+1} e_mᵀ`` holds, so the Ritz pair ``(θ, u = Q s)`` of ``H``
satisfies ``W u − θ u = β s_m q_{m+1}``; multiplying by ``K`` and dividing by ``−θ``,
``A u − (σ + 1/θ) M u = −(β s_m / θ) K q_{m+1}``: the residual of the pencil is known from one
product ``K q_{m+1}`` without forming ``u`` (``A q_{m+1}`` also updates ``Qᴴ A Q``).  Once the
estimate is within four orders of the tolerance, every step also does a Rayleigh–Ritz step on
``(A, M)`` in the whole basis (the newest vector included) and computes the explicit residuals
and Rayleigh quotients of the wanted pairs.  The iteration stops at the first step where the normwise backward error
(:func:`dhlb.linalg.backward_errors`) of every wanted pair meets the tolerance.

Why not ARPACK (:func:`scipy.sparse.linalg.eigsh`, which dhlb used until 0.3): ARPACK tests
convergence only when its basis is full, so the number of solves moves in steps of
``ncv − nev`` (measured on the Stanford bunny's cross field: 25 solves at every ``ncv`` from 10
to 24, against 19 here), its stopping test is relative to ``θ`` rather than the pencil's backward
error, and it spends as much time in its own bookkeeping and M-products as in four solves.
PRIMME's GD+k (``primme.eigsh`` with the factorization as preconditioner) needed 18 solves, but
it ships no wheels (it is compiled against a system LAPACK), and its own stopping test is not
the backward error (its ``convtest`` hook crashed on complex problems in 3.2.3).

When the basis reaches ``ncv`` vectors the ``keep`` dominant Ritz vectors and ``q_{m+1}`` are
kept (thick restart, Wu & Simon 2000): ``H`` becomes ``diag(θ)``, bordered by ``β s_m`` once the
next column is orthogonalized, and the relation above continues to hold.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> n = 300                                        # path graph: λ_j = 2 − 2 cos(πj/n)
>>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1]).tocsc()
>>> M = sp.identity(n, format="csc")
>>> import scipy.sparse.linalg as spla
>>> lu = spla.splu((A + 1e-3 * M).tocsc())
>>> from dhlb.linalg import SolverOptions
>>> out = lanczos(lu.solve, A, M, 2, np.ones(n), shift=-1e-3, solver=SolverOptions(tol=1e-12))
>>> bool(np.allclose(out.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(2) / n), atol=1e-12))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from dhlb.linalg._checks import eta as _eta
from dhlb.linalg._checks import norm1
from dhlb.linalg.options import SolverOptions

__all__ = ["LanczosResult", "lanczos"]


@dataclass(frozen=True)
class LanczosResult:
    """Outcome of :func:`lanczos`.

    Parameters
    ----------
    eigenvalues : (nev,) float array
        The Rayleigh quotients of the Ritz vectors nearest the shift, ascending.
    vectors : (n, nev) array
        The Ritz vectors, M-orthonormal.
    solves : int
        Applications of ``K⁻¹``.
    residuals : (nev,) float array
        Their normwise backward errors (explicit residuals).
    converged : bool
        Whether every backward error met the tolerance.
    restarts : int
        Thick restarts done.

    Examples
    --------
    >>> LanczosResult(np.zeros(1), np.zeros((2, 1)), 3, np.zeros(1), True, 0).solves
    3
    """

    eigenvalues: np.ndarray
    vectors: np.ndarray
    solves: int
    residuals: np.ndarray
    converged: bool
    restarts: int


def lanczos(solve, A, M, nev: int, v, *, shift: float, solver: SolverOptions) -> LanczosResult:
    """The ``nev`` eigenpairs of ``A u = λ M u`` nearest ``shift``, by shift-and-invert Lanczos.

    Parameters
    ----------
    solve : callable
        ``x ↦ K⁻¹ x`` with ``K = A − shift·M`` (a factorization's solve).
    A : (n, n) sparse matrix
        The Hermitian operator.
    M : (n, n) sparse matrix
        The Hermitian positive definite mass matrix.
    nev : int
        The number of wanted pairs, ``1 <= nev < n``.
    v : (n,) array
        The start vector (nonzero).
    shift : float
        ``σ``.
    solver : dhlb.linalg.SolverOptions
        ``tol``: the backward-error tolerance of every wanted pair (not None); ``maxiter``: the
        largest number of solves; ``block_size``: the largest basis (default
        ``max(2 nev + 1, nev + 24)``, at most ``n − 1``).

    Returns
    -------
    LanczosResult
        ``converged`` is False when ``maxiter`` solves did not suffice (the current Ritz pairs
        are returned).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> d = np.array([1.0, 2.0, 4.0, 8.0]); A = sp.diags(d, format="csr"); M = sp.identity(4, format="csr")
    >>> out = lanczos(lambda x: x / d, A, M, 1, np.ones(4), shift=0.0, solver=SolverOptions(tol=1e-14))
    >>> round(float(out.eigenvalues[0]), 12), out.converged
    (1.0, True)
    """
    n = M.shape[0]
    tol, maxiter, ncv = solver.tol, solver.maxiter, solver.block_size
    ncv = max(1, min(n - 1, max(2 * nev + 1, nev + 24) if ncv is None else int(ncv)))
    dtype = np.result_type(np.asarray(v).dtype, A.dtype, M.dtype, np.float64)
    A, M = A.astype(dtype, copy=False), M.astype(dtype, copy=False)   # a real M times complex x: cast once
    Q = np.empty((n, ncv + 1), dtype=dtype, order="F")
    H = np.zeros((ncv + 1, ncv + 1), dtype=dtype)       # Qᴴ M K⁻¹ M Q: the Lanczos matrix of W = K⁻¹M
    normA, normM = norm1(A), norm1(M)
    rng = np.random.default_rng(1)
    q = np.asarray(v, dtype=dtype)
    Mq = M @ q
    beta = np.sqrt(max(float(np.vdot(q, Mq).real), 0.0))
    if not (beta > 0 and np.isfinite(beta)):
        raise ValueError("the start vector is zero or not finite")
    Q[:, 0], Mq = q / beta, Mq / beta
    qnorm = np.empty(ncv + 1)                           # Euclidean norms of the basis vectors
    qnorm[0] = np.linalg.norm(Q[:, 0])
    P = np.zeros((ncv + 1, ncv + 1), dtype=dtype)       # Qᴴ A Q, for Rayleigh–Ritz on the pencil
    P[0, 0] = np.vdot(Q[:, 0], A @ Q[:, 0]).real
    m, solves, restarts = 0, 0, 0       # m + 1 vectors in the basis, the images of the first m taken
    while True:
        x = solve(Mq)
        solves += 1
        x, h, beta, Mx = _orthogonalize(Q[:, :m + 1], x, M)
        H[:m + 1, m] = h
        H[m, :m + 1] = h.conj()
        theta, S = _dominant(H[:m + 1, :m + 1])
        if not beta > 1e-13 * abs(theta[0]):   # an invariant subspace: go on in a fresh direction
            x, Mx = _fresh(Q[:, :m + 1], M, rng, dtype)
            beta = 0.0
        else:
            x, Mx = x / beta, Mx / beta
        m += 1
        Q[:, m], Mq = x, Mx
        qnorm[m] = np.linalg.norm(x)
        Aq = A @ x
        p = Q[:, :m + 1].T @ Aq.conj()                    # conj(Qᴴ A q) without conjugating Q
        P[:m + 1, m] = p.conj()
        P[m, :m + 1] = p
        # W u − θ u = β s_m q_{m+1} for the Ritz pairs of H: their pencil residual, without forming u
        if m >= nev:
            lam_w = shift + 1.0 / theta[:nev]
            coeff = beta * np.abs(S[m - 1, :nev]) / np.abs(theta[:nev]) * float(np.linalg.norm(Aq - shift * Mq))
            if np.all(coeff <= 1e4 * tol * (normA + np.abs(lam_w) * normM) * qnorm[:m].min()):
                lam, X, eta = _pencil_ritz(A, M, Q[:, :m + 1], P[:m + 1, :m + 1], nev, shift, normA, normM)
                if np.all(eta <= tol):
                    return LanczosResult(lam, X, solves, eta, True, restarts)
        if solves >= maxiter:
            lam, X, eta = _pencil_ritz(A, M, Q[:, :m + 1], P[:m + 1, :m + 1], min(nev, m + 1), shift, normA, normM)
            return LanczosResult(lam, X, solves, eta, False, restarts)
        if m == ncv:   # thick restart: keep the dominant Ritz vectors of W and the newest direction
            theta, S = _dominant(H[:m, :m])
            keep = min(m - 1, max(nev + (ncv - nev) // 2, nev + 1))
            Sk = S[:, :keep]
            Q[:, :keep] = Q[:, :m] @ Sk
            Q[:, keep] = Q[:, m]
            Pk = np.zeros_like(P)                               # Qᴴ A Q of the new basis [Q Sk, q]
            Pk[:keep, :keep] = Sk.conj().T @ P[:m, :m] @ Sk
            Pk[:keep, keep] = Sk.conj().T @ P[:m, m]
            Pk[keep, :keep] = Pk[:keep, keep].conj()
            Pk[keep, keep] = P[m, m]
            P = Pk
            qnorm[:keep + 1] = np.r_[np.linalg.norm(Q[:, :keep], axis=0), qnorm[m]]
            H[:] = 0
            H[np.arange(keep), np.arange(keep)] = theta[:keep]  # the border β s comes with the next column
            m, restarts = keep, restarts + 1


def _dominant(H):
    """Eigenpairs of the Hermitian ``H``, largest ``|θ|`` first."""
    theta, S = sla.eigh(0.5 * (H + H.conj().T))
    order = np.argsort(-np.abs(theta), kind="stable")
    return theta[order], S[:, order]


def _pencil_ritz(A, M, Q, P, nev, shift, normA, normM):
    """Rayleigh–Ritz on ``(A, M)`` in the M-orthonormal ``span Q`` (``P = Qᴴ A Q``): ``nev`` pairs nearest ``shift``.

    Returns their Ritz vectors (M-orthonormal), their Rayleigh quotients computed from explicit
    products (the accumulated ``P`` carries rounding of order ``eps ‖A‖``), ascending, and their
    backward errors from explicit residuals.
    """
    lam, C = sla.eigh(0.5 * (P + P.conj().T))
    pick = np.sort(np.argsort(np.abs(lam - shift), kind="stable")[:nev])
    X = Q @ C[:, pick]
    AX, MX = A @ X, M @ X
    lam = np.sum(X.conj() * AX, axis=0).real / np.sum(X.conj() * MX, axis=0).real   # explicit Rayleigh quotients
    order = np.argsort(lam, kind="stable")
    lam, X = lam[order], X[:, order]
    return lam, X, _eta(AX[:, order] - MX[:, order] * lam[None, :], lam, X, normA, normM)


def _orthogonalize(Q, x, M):
    """``x`` M-orthogonalized against the columns of ``Q`` by classical Gram–Schmidt.

    A second pass is made when the first removed more than half of ``‖x‖²_M`` (Daniel, Gragg,
    Kaufman & Stewart 1976: then rounding may have left components along ``Q``).  Returns the new
    vector, the coefficients ``Qᴴ M x`` (passes summed), its M-norm and ``M x``.
    """
    Mx = M @ x
    h = (Q.T @ Mx.conj()).conj()
    before = float(np.vdot(x, Mx).real)
    x = x - Q @ h
    Mx = M @ x
    if before - float(np.vdot(h, h).real) < 0.5 * before:
        h2 = (Q.T @ Mx.conj()).conj()
        x = x - Q @ h2                # M x changes by M Q h2, of the order of rounding: not recomputed
        h = h + h2
    return x, h, np.sqrt(max(float(np.vdot(x, Mx).real), 0.0)), Mx


def _fresh(Q, M, rng, dtype):
    """A random M-unit vector M-orthogonal to ``Q`` and its image under ``M`` (after a breakdown)."""
    n = Q.shape[0]
    x = rng.standard_normal(n)
    if np.dtype(dtype).kind == "c":
        x = x + 1j * rng.standard_normal(n)
    x, _, b, Mx = _orthogonalize(Q, x.astype(dtype), M)
    return x / b, Mx / b
