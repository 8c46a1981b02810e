"""Thick-restart block Lanczos for shift-and-invert on a factorized ``K = A − σM``.

The operator is ``S = K⁻¹ M``, self-adjoint in the M-inner product ``⟨x, y⟩_M = xᴴ M y``; its
eigenpairs are ``(θ, u)`` with ``θ = 1 / (λ − σ)``, so the eigenvalues ``λ`` closest to ``σ`` are
the ``θ`` of largest modulus, which Krylov methods find first.  One *step* applies ``S`` to a
block of ``b`` vectors (one factor solve with ``b`` right-hand sides).

Basis
    ``V`` (``n × (m + b)``) is kept M-orthonormal by classical Gram–Schmidt with
    reorthogonalization, together with ``MV``: a first pass against the last two blocks (where
    the three-term recurrence puts almost all of ``S v_j``), then full passes, column by column,
    until a pass no longer shrinks the vector much (on the bunny one full pass per step instead
    of two; ``VᴴMV = I`` to ~1e-14 is tested through restarts).  After ``j`` basis vectors have been mapped,
    ``S V_j = V_j T + V_res H_res`` where ``T = V_jᴴ M S V_j`` (Hermitian, tridiagonal plus an
    arrow after restarts) and ``V_res`` (``b`` columns) is the new M-orthonormal block.  A
    rank-deficient new block (invariant subspace found) is completed with random vectors, so
    further eigenvectors, also of multiple eigenvalues, can still enter.
Residual estimate
    For a Ritz pair ``T y = θ y``, ``x = V_j y``, ``ν = σ + 1/θ``:
    ``S x − θ x = V_res f`` with ``f = H_res y``; multiplying by ``K`` gives
    ``(A − ν M) x = −(1/θ) K V_res f``, so the normwise backward error of ``(ν, x)`` costs one
    product with ``A`` per step, without forming residuals of the full basis.  When all ``k``
    wanted estimates pass, the caller's ``accept`` does the explicit Rayleigh–Ritz step and the
    true backward-error test; if that fails, the estimate threshold is tightened tenfold.
Restart (Wu & Simon 2000; Stewart's Krylov–Schur)
    When the basis is full, the ``keep`` Ritz vectors closest to ``σ`` are kept, ``T`` becomes
    ``diag(θ)`` and the residual block (with coupling ``H_res Y``) is carried over.

Examples
--------
>>> import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
>>> n = 200                                        # path graph: λ_j = 2 - 2 cos(πj/n)
>>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1], format="csc")
>>> M = sp.identity(n, format="csc"); sigma = -1e-3
>>> lu = spla.splu((A - sigma * M).tocsc())
>>> out = lanczos(lu.solve, A, M, np.ones((n, 1)) + np.arange(n)[:, None] % 3, 2, shift=sigma, tol=1e-12,
...               maxsteps=200, capacity=20, accept=lambda X, theta: 1 / theta + sigma)
>>> bool(np.allclose(out.accepted, 2 - 2 * np.cos(np.pi * np.arange(2) / n), atol=1e-12)), out.steps < 60
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from dhlb.errors import InvalidOperatorError

__all__ = ["KrylovOutcome", "lanczos", "m_orthonormalize"]


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


@dataclass
class KrylovOutcome:
    """What :func:`lanczos` returns.

    ``accepted``: the value returned by ``accept`` (``None`` if the step budget ran out);
    ``steps``: block applications of ``S``; ``X``, ``theta``: Ritz vectors and values, closest to
    ``σ`` first (the ``k`` accepted ones, or all of the basis when the budget ran out: a warm
    start for another method).
    """

    accepted: object
    steps: int
    X: np.ndarray
    theta: np.ndarray


def _gram_schmidt(Vb, MVb, w, local: int = 0):
    """Classical Gram–Schmidt of ``w`` against ``Vb`` in the M-inner product, with reorthogonalization.

    First against the last ``local`` columns only (in Lanczos the new vector ``S v_j`` is mostly
    along ``v_j``: the large cancellation happens there, at the cost of ``local`` columns), then
    full passes, repeated while a pass shrinks ``w`` below 0.7 of its size
    (Daniel–Gragg–Kaufman–Stewart; at most 5 passes): the result is orthogonal to working
    precision relative to its own size. Returns ``(w, h, ok)``, ``ok = False`` if ``w`` kept
    shrinking (it is rounding noise).
    """
    h = np.zeros(Vb.shape[1], dtype=w.dtype)
    if 0 < local < Vb.shape[1]:
        c = (w.conj() @ MVb[:, -local:]).conj()
        w = w - Vb[:, -local:] @ c
        h[-local:] += c
    old = np.linalg.norm(w)
    for _ in range(5):
        c = (w.conj() @ MVb).conj()              # = MVbᴴ w without conjugating the tall MVb
        w = w - Vb @ c
        h += c
        new = np.linalg.norm(w)
        if new > 0.7 * old:
            return w, h, True
        old = new
    return w, h, False


def _expand(V, MV, H, W, M, j, nv, rng):
    """Append the M-orthonormalized columns of ``W = S V[:, j:nv]`` to the basis, column by column.

    The coefficients go to ``H``; a column in the span of the basis (invariant subspace) is
    replaced by a random direction M-orthogonal to everything, with coupling 0.
    """
    b = W.shape[1]
    for i in range(b):
        q = nv + i
        w, h, ok = _gram_schmidt(V[:, :q], MV[:, :q], W[:, i], local=min(q, 2 * b + i))
        Mw = M @ w
        beta = float(np.sqrt(max((w.conj() @ Mw).real, 0.0)))
        H[:q, j + i] = h
        if ok and beta > 1e-12 * np.sqrt(np.sum(np.abs(h) ** 2) + beta**2):
            H[q, j + i] = beta
        else:
            H[q, j + i] = 0.0
            for _ in range(3):  # a random direction (two passes suffice: it starts large)
                w = rng.standard_normal(w.shape[0]).astype(w.dtype)
                w, _, ok = _gram_schmidt(V[:, :q], MV[:, :q], w)
                if ok:
                    break
            Mw = M @ w
            beta = float(np.sqrt((w.conj() @ Mw).real))
        V[:, q], MV[:, q] = w / beta, Mw / beta


def lanczos(solve, A, M, X0, k, *, shift, tol, maxsteps, capacity, accept, norms=None) -> KrylovOutcome:
    """Thick-restart block Lanczos on ``S = K⁻¹ M`` (see the module docstring).

    Parameters
    ----------
    solve : callable, ``solve(B)`` = ``K⁻¹ B`` for ``K = A − shift·M``
    A, M : sparse Hermitian (n, n)
    X0 : (n, b) start block (its column count is the block size ``b``)
    k : number of wanted eigenpairs (closest to ``shift``)
    tol : backward-error tolerance of the estimates
    maxsteps : maximal number of block applications of ``S``
    capacity : basis size ``m`` (columns, without the residual block); needs ``k + b <= m`` and
        ``m + b < n``
    accept : callable ``accept(X, theta)`` on the ``k`` wanted Ritz vectors (closest to σ first)
        and values; returns a result (stop) or ``None`` (continue with a tighter estimate)
    norms : ``(‖A‖₁, ‖M‖₁)``, optional
    """
    n, b = X0.shape
    m = int(capacity)
    if not (k + b <= m and m + b < n):
        raise ValueError(f"lanczos needs k + b <= capacity and capacity + b < n (k={k}, b={b}, m={m}, n={n})")
    normA, normM = norms if norms is not None else (float(abs(A).sum(axis=0).max()), float(abs(M).sum(axis=0).max()))
    dtype = np.result_type(X0.dtype, A.dtype, M.dtype)
    rng = np.random.default_rng(1)
    V = np.empty((n, m + b), dtype, order="F")  # column blocks are contiguous
    MV = np.empty((n, m + b), dtype, order="F")
    H = np.zeros((m + b, m), dtype)
    V[:, :b], MV[:, :b] = m_orthonormalize(X0.astype(dtype), M)
    j, steps, factor = 0, 0, 1.0
    X = theta = xnorm = None
    while steps < maxsteps:
        nv = j + b
        W = solve(MV[:, j:nv])
        steps += 1
        if not np.all(np.isfinite(W)):
            raise InvalidOperatorError("the shifted solve produced non-finite values; A - σM is numerically singular")
        _expand(V, MV, H, np.asarray(W, dtype=dtype).reshape(n, b), M, j, nv, rng)
        j = nv
        T = H[:j, :j]
        theta_all, Y = sla.eigh(0.5 * (T + T.conj().T))
        order = np.argsort(-np.abs(theta_all), kind="stable")
        theta_all, Y = theta_all[order], Y[:, order]
        X, theta = None, theta_all
        if j >= k and np.all(theta_all[:k] != 0):
            th = theta_all[:k]
            F = H[j:j + b, :j] @ Y[:, :k]
            KV = A @ V[:, j:j + b] - shift * MV[:, j:j + b]
            nu = shift + 1.0 / th
            num = np.linalg.norm(KV @ F, axis=0) / np.abs(th)
            if xnorm is None or np.all(num <= factor * tol * (normA + np.abs(nu) * normM) * 2.0 * xnorm):
                # ‖x‖ changes slowly: the norms of the last Ritz vectors screen the estimate, and are
                # recomputed only when it might pass (the accept step tests the true residual anyway)
                X = V[:, :j] @ Y[:, :k]
                xnorm = np.linalg.norm(X, axis=0)
            den = (normA + np.abs(nu) * normM) * xnorm
            est = num / np.where(den > 0, den, 1.0)
            if X is not None and np.all(est <= factor * tol):
                out = accept(X, th)
                if out is not None:
                    return KrylovOutcome(out, steps, X, th)
                factor *= 0.1
        if j + b > m:  # restart with the `keep` Ritz vectors closest to σ
            keep = min(m - b, max(k + b, (m + k) // 2))
            Yk = Y[:, :keep]
            Vk, MVk = V[:, :j] @ Yk, MV[:, :j] @ Yk
            Hres = H[j:j + b, :j] @ Yk
            V[:, keep:keep + b], MV[:, keep:keep + b] = V[:, j:j + b], MV[:, j:j + b]
            V[:, :keep], MV[:, :keep] = Vk, MVk
            H[:] = 0
            H[:keep, :keep] = np.diag(theta_all[:keep])
            H[keep:keep + b, :keep] = Hres
            j = keep
    restarted = j + b <= m and Y.shape[0] != j
    return KrylovOutcome(None, steps, V[:, :j].copy() if restarted else V[:, :j] @ Y, theta)
