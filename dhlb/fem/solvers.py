"""Sparse generalized Hermitian eigenproblems ``A u = λ M u`` and shifted linear solves.

With a direct backend the eigensolver works on one factorization of ``K = A − σM`` (shift ``σ``):

1. **Lanczos** (default): thick-restart Lanczos on ``S = K⁻¹ M`` in the M-inner product
   (:mod:`dhlb.fem._krylov`), block size ``b = 1`` for ``k = 1`` and ``b = k`` otherwise (a block
   of ``k`` vectors sees every eigenvalue with its multiplicity up to ``k``, which is all the
   ``k`` smallest pairs can need), basis of ``max(20, 3k + b)`` vectors.  Each step is one solve
   with ``b`` right-hand sides; a cheap residual estimate decides when to do the explicit
   Rayleigh–Ritz step and the backward-error test below.  On the 69k-face bunny (n = 4 field,
   ``k = 1``) it needs 22 single solves where the subspace iteration needed 16 × 9.
2. **Subspace iteration** (fallback, or when ``block_size`` is given): iterate ``W = K⁻¹ M U``
   on a block of ``p`` vectors, orthonormalize ``W`` and solve the projected problem
   ``(QᴴAQ) c = θ (QᴴMQ) c``.  It is used when Lanczos has not met ``tol`` after half of
   ``maxiter`` steps (it then starts from Lanczos' Ritz vectors), and when the problem is too
   small for a Lanczos basis.

The Ritz vectors are M-orthonormal.  :attr:`EigenResult.iterations` counts applications of
``K⁻¹`` to a block (of :attr:`EigenResult.block_size` vectors), :attr:`EigenResult.method` says
which method converged.

Linear algebra goes through the backends of :mod:`dhlb.fem.backends` (``superlu`` always;
``cholmod``, ``cholespy``, ``amg-lobpcg`` when their packages are installed).  ``backend=None`` or
``"auto"`` chooses by problem size, sparsity (2-D vs 3-D-like) and availability
(:func:`~dhlb.fem.backends.select_backend`); the name of the method used is reported in
:attr:`EigenResult.backend`.  Iterative backends (``amg-lobpcg``) replace the shift-and-invert
methods by their own block method (LOBPCG); the final Rayleigh–Ritz step, the backward-error
test and the result are the same.  Everything runs under :func:`~dhlb.fem.backends.blas_guard`
(one BLAS thread).

Default shift
    For a PSD ``A`` the smallest eigenvalues are wanted and the kernel of ``A`` is typically
    non-trivial, so ``A`` itself cannot be factorized.  We use ``σ = -ε`` with
    ``ε = sqrt(eps) · ρ``, where ``ρ = max_i Σ_j |A_ij| / sqrt(M_ii M_jj)`` is the Gershgorin
    bound of the largest eigenvalue of the diagonally scaled ``D^{-1/2} A D^{-1/2}``
    (``D = diag M``) -- a scale of the top of the spectrum that is invariant under scaling
    ``A`` or ``M``.  Then ``A + εM`` is positive definite, its condition number is bounded by
    about ``κ(D^{-1/2} M D^{-1/2}) / sqrt(eps)`` independently of the mesh size, and ``ε`` is
    far below the low eigenvalues of interest, so convergence is not slowed down.  ``A + εM``
    is factorized as a Hermitian matrix and its pivots are checked: a non-positive pivot proves
    that ``A`` has an eigenvalue below ``−ε``, i.e. is not PSD (an error is raised).

Convergence test (for each of the ``k`` wanted pairs)
    * normwise backward error ``η = ‖A u − λ M u‖ / ((‖A‖₁ + |λ| ‖M‖₁) ‖u‖) <= tol``
      (Higham & Higham 1998; SLEPc's ``EPS_CONV_NORM``), computed from the explicit residual
      after a Rayleigh–Ritz step on ``(A, M)``.  Unlike ``‖r‖ / ‖Au‖`` it stays meaningful when
      ``λ ≈ 0``, where ``Au`` itself is at rounding-error level: ``η`` is the smallest relative
      perturbation of ``(A, M)`` for which ``(λ, u)`` is an exact eigenpair.  ``tol = 1e-10``
      (the default) on the bunny's n = 4 field leaves an eigenvalue error of ~1e-11 relative;
    * subspace iteration also requires that the eigenvalue changed by at most the same
      backward-error level since the last iteration:
      ``|λ_t − λ_{t−1}| ‖M‖₁ <= tol (‖A‖₁ + |λ_t| ‖M‖₁)``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from dhlb.errors import (
    InvalidOperatorError,
    InvalidParameterError,
    NonFiniteError,
    ShapeError,
)
from dhlb.fem._checks import as_sparse as _as_sparse  # noqa: F401  (re-exported for old imports)
from dhlb.fem._checks import eta as _eta
from dhlb.fem._checks import fix_phase as _fix_phase
from dhlb.fem._checks import norm1 as _norm1
from dhlb.fem._checks import validate_pair as _validate_pair
from dhlb.fem._eigen_steps import (
    EigenResult,
    _iterate_lobpcg,
    _not_converged,
    _not_psd,
    _rayleigh_ritz,
    _subspace_iteration,
)
from dhlb.fem._krylov import lanczos
from dhlb.fem.backends import SuperLUBackend, blas_guard, get_backend, pattern_dimension

__all__ = ["EigenResult", "SuperLUBackend", "backward_errors", "default_shift", "smallest_eigenpairs", "solve"]

_EPS = np.finfo(float).eps


def _get_backend(backend):
    """Backward-compatible alias: ``get_backend(backend)`` (``None`` → SuperLU)."""
    return get_backend(backend)


def default_shift(A: sp.csr_matrix, M: sp.csr_matrix) -> float:
    """``ε = sqrt(eps) ρ`` with ``ρ = max_i Σ_j |A_ij| / sqrt(M_ii M_jj)`` (see module docstring).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> bool(abs(default_shift(A, M) - 2 * np.sqrt(np.finfo(float).eps)) < 1e-20)
    True
    """
    s = 1.0 / np.sqrt(M.diagonal().real)
    rho = float(abs(sp.diags(s) @ A @ sp.diags(s)).sum(axis=1).max())
    return float(np.sqrt(_EPS) * (rho if rho > 0 else 1.0))


def backward_errors(A, M, eigenvalues, eigenvectors) -> np.ndarray:
    """Normwise backward errors ``η_i = ‖A u_i − λ_i M u_i‖ / ((‖A‖₁ + |λ_i| ‖M‖₁) ‖u_i‖)``.

    ``η_i`` is (up to the choice of norms) the smallest relative perturbation of ``(A, M)`` that
    makes ``(λ_i, u_i)`` an exact eigenpair; it is the residual used by :func:`smallest_eigenpairs`.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> backward_errors(A, M, [0.0, 2.0], np.array([[1.0, 1.0], [1.0, -1.0]])).tolist()
    [0.0, 0.0]
    >>> float(backward_errors(A, M, [0.0], np.array([[1.0], [0.0]]))[0])   # ‖(1,-1)‖ / (2·1)
    0.7071067811865476
    """
    A, M = _validate_pair(A, M)
    lam = np.atleast_1d(np.asarray(eigenvalues, dtype=float))
    U = np.asarray(eigenvectors)
    U = U.reshape(-1, 1) if U.ndim == 1 else U
    if U.shape != (A.shape[0], lam.size):
        raise ShapeError(f"eigenvectors must have shape ({A.shape[0]}, {lam.size}), got {U.shape}")
    return _eta(A @ U - (M @ U) * lam[None, :], lam, U, _norm1(A), _norm1(M))


def smallest_eigenpairs(A, M, k: int = 1, *, tol: float = 1e-10, maxiter: int = 500, sigma=None,
                        v0=None, backend=None, block_size: int | None = None,
                        factor_shift: str = "auto") -> EigenResult:
    """The ``k`` smallest eigenpairs of ``A u = λ M u`` (A Hermitian PSD, M Hermitian PD).

    Parameters
    ----------
    A, M : sparse or dense (n, n), real or complex Hermitian
    k : int, number of eigenpairs, ``1 <= k <= n``
    tol : float, tolerance of the backward-error and eigenvalue-change tests
    maxiter : int, maximal number of iterations (block solves; LOBPCG iterations)
    block_size : int, optional
        If given, the block subspace iteration is used (no Lanczos) with this many vectors
        (default of that method ``max(2k, k + 8)``; for ``amg-lobpcg`` ``k`` if ``k = 1``, else
        ``k + max(2, k // 2)``); its convergence goes like ``(λ_k / λ_{p+1})^iterations``, so
        use it with a block larger than the cluster for tightly clustered spectra (e.g. a
        Landau level of high multiplicity).
    sigma : float, optional
        Shift; if given, the ``k`` eigenvalues closest to ``sigma`` are returned (``A`` need not
        be PSD then).  Default ``-ε`` (see module docstring): the ``k`` smallest.
    v0 : (n,) or (n, j) array, optional, start vector(s); the rest of the subspace is random
        (seeded, so results are reproducible)
    backend : str or backend object, optional
        ``"superlu"``, ``"cholmod"``, ``"cholespy"``, ``"amg-lobpcg"`` (if installed), a backend
        object, or ``None``/``"auto"``: chosen by size, sparsity and availability
        (:func:`dhlb.fem.backends.select_backend`).  ``amg-lobpcg`` needs ``sigma=None``.
    factor_shift : {"auto", "floor"}
        Where the factorization is placed when ``sigma`` is not given: ``"auto"`` lets the solver
        choose (fastest); ``"floor"`` factorizes ``A + εM`` (``σ = −ε``, see module docstring), so
        that :attr:`EigenResult.factor` approximates ``A⁻¹`` — for callers that go on iterating
        with ``A⁻¹`` (e.g. the unit-modulus stripe section).

    Returns
    -------
    EigenResult

    Raises
    ------
    ShapeError, NonFiniteError, InvalidOperatorError
        Bad input: non-square/mismatched matrices, NaN/inf, not Hermitian, ``M`` not PD, or
        (default shift) ``A + εM`` not positive definite, i.e. ``A`` is not PSD.
    ConvergenceError
        Not converged within ``maxiter``; the partial result is attached as ``err.result``.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> n = 50                                        # path graph: λ_j = 2 - 2 cos(πj/n)
    >>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1])
    >>> res = smallest_eigenpairs(A, sp.identity(n), k=3)
    >>> np.allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(3) / n), atol=1e-12)
    True
    >>> res.converged, bool(res.residuals.max() <= 1e-10)
    (True, True)
    """
    A, M = _validate_pair(A, M)
    n = A.shape[0]
    if not (isinstance(k, (int, np.integer)) and 1 <= k <= n):
        raise InvalidParameterError(f"k must be an integer with 1 <= k <= n = {n}, got {k!r}")
    if not (np.isfinite(tol) and tol > 0):
        raise InvalidParameterError(f"tol must be a positive number, got {tol!r}")
    if not (isinstance(maxiter, (int, np.integer)) and maxiter >= 1):
        raise InvalidParameterError(f"maxiter must be a positive integer, got {maxiter!r}")
    default = sigma is None
    if factor_shift not in ("auto", "floor"):
        raise InvalidParameterError(f"factor_shift must be 'auto' or 'floor', got {factor_shift!r}")
    if not default and not (np.isscalar(sigma) and np.isreal(sigma) and np.isfinite(sigma)):
        raise InvalidParameterError(f"sigma must be a finite real number, got {sigma!r}")
    be = get_backend(backend, n=n, nnz=A.nnz, eigen=True, shifted=not default, dimension=lambda: pattern_dimension(A))
    iterative = hasattr(be, "eigensolve")
    if iterative and not default:
        raise InvalidParameterError(f"backend {be.name!r} computes the smallest eigenvalues only; sigma= needs a "
                                    "direct backend (e.g. backend='superlu' or 'cholmod')")
    complex_ = np.iscomplexobj(A.data) or np.iscomplexobj(M.data)
    dtype = np.complex128 if complex_ else np.float64
    eps_shift = default_shift(A, M)
    shift = -eps_shift if default else float(sigma)
    p = min(n, max(2 * k, k + 8) if not iterative else (k if k == 1 else k + max(2, k // 2)))
    if block_size is not None:
        if not isinstance(block_size, (int, np.integer)) or not k <= block_size:
            raise InvalidParameterError(f"block_size must be an integer >= k = {k}, got {block_size!r}")
        p = min(n, int(block_size))
    lanczos_first = block_size is None and not iterative
    U = _start_block(n, 1 if lanczos_first and k == 1 else p, complex_, dtype, v0)  # the rest if needed
    with blas_guard():
        if iterative:
            return _iterate_lobpcg(be, A, M, U, k, eps_shift, tol, maxiter)
        fac, shift = _factorize_shifted(be, A, M, shift, eps_shift, default)
        if block_size is None:
            res = _lanczos_then_subspace(fac, be, A, M, U, k, shift, default, tol, maxiter)
        else:
            res = _subspace_iteration(fac, be, A, M, U, k, shift, default, tol, maxiter)
        return replace(res, factor=fac)


def _lanczos_then_subspace(fac, be, A, M, U, k, shift, default, tol, maxiter):
    """Thick-restart Lanczos for up to half of ``maxiter`` steps, then subspace iteration from its Ritz vectors."""
    n, name = A.shape[0], getattr(fac, "name", be.name)
    b = 1 if k == 1 else k
    m = max(20, 3 * k + b)
    if m + b >= n:  # too small for a Lanczos basis (and every method takes microseconds)
        return _subspace_iteration(fac, be, A, M, U, k, shift, default, tol, maxiter)
    normA, normM = _norm1(A), _norm1(M)

    def accept(X, theta):
        _, _, lam, Uk, eta = _rayleigh_ritz(A, M, X, k, shift, normA, normM)
        if default and lam[0] < shift:
            raise _not_psd(lam[0], shift)
        return EigenResult(lam, _fix_phase(Uk), 0, eta, True, name, shift, b, "lanczos") if np.all(eta <= tol) else None

    X0 = U[:, :b] if U.shape[1] >= b else np.concatenate([U, _start_block(n, b, np.iscomplexobj(U), U.dtype,
                                                                            None)[:, U.shape[1]:]], axis=1)
    out = lanczos(fac.solve, A, M, X0, k, shift=shift, tol=tol, maxsteps=max(1, maxiter // 2), capacity=m,
                  accept=accept, norms=(normA, normM))
    if out.accepted is not None:
        return replace(out.accepted, iterations=out.steps)
    if maxiter - out.steps <= 0:
        _, _, lam, Uk, eta = _rayleigh_ritz(A, M, out.X, k, shift, normA, normM)
        part = EigenResult(lam, _fix_phase(Uk), out.steps, eta, False, name, shift, b, "lanczos")
        raise _not_converged(part, maxiter, tol, b)
    p = max(2 * k, k + 8)
    if U.shape[1] < p:
        U = np.concatenate([U, _start_block(n, p, np.iscomplexobj(U), U.dtype, None)[:, U.shape[1]:]], axis=1)
    q = min(out.X.shape[1], p)
    U = U.copy()
    U[:, :q] = out.X[:, :q]                     # warm start: Lanczos' best Ritz vectors, then the random block
    return _subspace_iteration(fac, be, A, M, U, k, shift, default, tol, maxiter - out.steps, its0=out.steps,
                               method="lanczos+subspace")


def _start_block(n, p, complex_, dtype, v0):
    rng = np.random.default_rng(0)
    U = rng.standard_normal((n, p))
    if complex_:
        U = U + 1j * rng.standard_normal((n, p))
    U = U.astype(dtype)
    if v0 is not None:
        V = np.asarray(v0)
        V = V.reshape(-1, 1) if V.ndim == 1 else V
        if V.ndim != 2 or V.shape[0] != n or V.shape[1] > n:
            raise ShapeError(f"v0 must have shape ({n},) or ({n}, j) with j <= {n}, got {np.shape(v0)}")
        if not np.all(np.isfinite(V)):
            raise NonFiniteError("v0 contains NaN or inf")
        if V.shape[1] > p:
            U = np.concatenate([U, np.zeros((n, V.shape[1] - p), dtype)], axis=1)
        U[:, : V.shape[1]] = V
    return U


def _factorize_shifted(be, A, M, shift, eps_shift, default):
    if default:
        try:
            return be.factorize((A + eps_shift * M).tocsc(), positive_definite=True), shift
        except InvalidOperatorError as err:
            raise InvalidOperatorError(f"A + εM (ε = {eps_shift:.3g}) is not positive definite, so A is not "
                                       f"positive semidefinite ({err}); pass sigma= to search near a chosen "
                                       "value") from err
    try:
        return be.factorize((A - shift * M).tocsc()), shift
    except InvalidOperatorError:  # σ is exactly an eigenvalue: step off it
        return be.factorize((A - (shift - eps_shift) * M).tocsc()), shift - eps_shift


def solve(A, M, lam, b, *, backend=None, positive_definite: bool = False) -> np.ndarray:
    """Solve ``(A − λ M) x = b`` by a sparse factorization (``b`` of shape (n,) or (n, r)).

    ``backend`` as in :func:`smallest_eigenpairs` (``auto``: a direct backend; Cholesky backends
    fall back to SuperLU when ``A − λM`` is indefinite).  With ``positive_definite=True`` the
    factorization asserts that ``A − λM`` is positive definite, i.e. that ``λ`` lies below the
    smallest eigenvalue of ``A u = λ M u``, and checks it (Cholesky, or the pivots of SuperLU's
    symmetric ``L D Lᴴ``) at no extra cost; an iterative backend (CG) can only check the
    necessary condition ``Re xᴴ b > 0``.

    Raises
    ------
    ShapeError, NonFiniteError, InvalidOperatorError
        Bad shapes, NaN/inf, non-Hermitian input, ``A − λM`` singular, or (``positive_definite``)
        not positive definite: the message names ``λ``.

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
    be = get_backend(backend, n=n, nnz=A.nnz, eigen=False)
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
