"""Sparse generalized Hermitian eigenproblems ``A u = λ M u``: the ``k`` smallest pairs.

Method
    With a direct backend, one factorization of ``K = A − σM`` and shift-and-invert Lanczos
    (:mod:`dhlb.linalg._lanczos`): Lanczos on ``K⁻¹ M`` in the M-inner product, whose largest
    eigenvalues ``θ = 1/(λ − σ)`` belong to the ``λ`` closest to ``σ``.  The factorization is
    applied through its ``solve``, so every backend of :mod:`dhlb.linalg.backends` serves, and
    :attr:`EigenResult.solves` counts its applications.  Lanczos stops at the first step where
    a Rayleigh–Ritz step on ``(A, M)`` in its basis gives pairs that pass the backward-error test
    below (explicit residuals); ARPACK, which tests only when its basis is full, needed a quarter
    more solves (see :mod:`dhlb.linalg._lanczos`).
    Problems with at most :data:`DENSE_MAX` unknowns (unless a backend is named) and problems
    too small for a Lanczos basis are solved densely (:func:`scipy.linalg.eigh`), so any valid
    small problem converges.  Iterative backends
    (``amg-lobpcg``) run their own block method (LOBPCG) with the same final test.

Default shift
    For a PSD ``A`` the smallest eigenvalues are wanted and the kernel of ``A`` is typically
    non-trivial, so ``A`` itself cannot be factorized.  We use ``σ = -ε`` with
    ``ε = sqrt(eps) · ρ``, where ``ρ = max_i Σ_j |A_ij| / sqrt(M_ii M_jj)`` is the Gershgorin
    bound of the largest eigenvalue of the diagonally scaled ``D^{-1/2} A D^{-1/2}``
    (``D = diag M``) -- a scale of the top of the spectrum that is invariant under scaling
    ``A`` or ``M``.  Then ``A + εM`` is positive definite, its condition number is bounded by
    about ``κ(D^{-1/2} M D^{-1/2}) / sqrt(eps)`` independently of the mesh size, and ``ε`` is
    far below the low eigenvalues of interest.  ``A + εM`` is factorized as a Hermitian matrix
    and its pivots are checked: a non-positive pivot proves that ``A`` has an eigenvalue below
    ``−ε``, i.e. is not PSD (an error is raised).

Convergence test (for each of the ``k`` wanted pairs)
    normwise backward error ``η = ‖A u − λ M u‖ / ((‖A‖₁ + |λ| ‖M‖₁) ‖u‖) <= tol``
    (Higham & Higham 1998; SLEPc's ``EPS_CONV_NORM``), computed from the explicit residual
    after a Rayleigh–Ritz step on ``(A, M)``.  Unlike ``‖r‖ / ‖Au‖`` it stays meaningful when
    ``λ ≈ 0``: ``η`` is the smallest relative perturbation of ``(A, M)`` for which ``(λ, u)`` is
    an exact eigenpair.

Default tolerance (:func:`default_tol`)
    ``tol = min(1e-10, 3e-6 / n)``.  The error of a computed eigenvector is about
    ``η (‖A‖ + |λ| ‖M‖) / gap``; on a fixed shape refined to ``n`` vertices ``‖A‖₁ ∝ n`` while the
    spectral gap stays put, so a fixed ``η`` lets the vector's error grow like ``n``.  Measured
    on a 1.1M-face n = 4 field: ``η = 1e-10`` moved 1 of 48 singularities relative to a
    ``1e-14`` solve, ``1e-12`` none; the scaled default gives ``5e-12`` there and ``1e-10`` up to
    30k unknowns.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from dhlb._deprecation import fold_deprecated_kwargs
from dhlb.errors import (
    ConvergenceError,
    InvalidOperatorError,
    InvalidParameterError,
    NonFiniteError,
    NotSemidefiniteError,
    ShapeError,
)
from dhlb.linalg._checks import eta as _eta
from dhlb.linalg._checks import fix_phase as _fix_phase
from dhlb.linalg._checks import norm1 as _norm1
from dhlb.linalg._checks import validate_pair as _validate_pair
from dhlb.linalg._eigen_steps import EigenResult, _iterate_lobpcg, _not_converged, _not_psd, _rayleigh_ritz
from dhlb.linalg._lanczos import lanczos
from dhlb.linalg.backends import available_backends, blas_guard, get_backend, pattern_dimension
from dhlb.linalg.memory import InsufficientMemoryError
from dhlb.linalg.options import SolverOptions, solver_options

__all__ = ["DENSE_MAX", "EigenResult", "backward_errors", "default_shift", "default_tol", "smallest_eigenpairs"]

_EPS = np.finfo(float).eps

_SOLVER = ("tol", "maxiter", "backend", "block_size", "factor_shift", "seed")  # the keywords of dhlb 0.1

DENSE_MAX = 400
"""Problems with at most this many unknowns are solved densely (:func:`scipy.linalg.eigh`)."""


def default_shift(A: sp.csr_matrix, M: sp.csr_matrix) -> float:
    """``ε = sqrt(eps) ρ`` with ``ρ = max_i Σ_j |A_ij| / sqrt(M_ii M_jj)`` (see module docstring).

    Parameters
    ----------
    A : (n, n) scipy.sparse matrix
        The Hermitian operator (not checked).
    M : (n, n) scipy.sparse matrix
        The Hermitian mass matrix, with a positive diagonal (not checked).

    Returns
    -------
    float
        The shift ``ε`` (with ``ρ = 1`` when ``A`` is zero).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.csr_matrix([[1.0, -1.0], [-1.0, 1.0]]); M = sp.identity(2, format="csr")
    >>> bool(abs(default_shift(A, M) - 2 * np.sqrt(np.finfo(float).eps)) < 1e-20)
    True
    """
    s = 1.0 / np.sqrt(M.diagonal().real)
    rho = float(np.max(s * (abs(A) @ s)))       # row sums of |D^-1/2 A D^-1/2| = D^-1/2 |A| D^-1/2 1
    return float(np.sqrt(_EPS) * (rho if rho > 0 else 1.0))


def backward_errors(A, M, eigenvalues, eigenvectors) -> np.ndarray:
    """Normwise backward errors ``η_i = ‖A u_i − λ_i M u_i‖ / ((‖A‖₁ + |λ_i| ‖M‖₁) ‖u_i‖)``.

    ``η_i`` is (up to the choice of norms) the smallest relative perturbation of ``(A, M)`` that
    makes ``(λ_i, u_i)`` an exact eigenpair; it is the residual used by :func:`smallest_eigenpairs`.

    Parameters
    ----------
    A : (n, n) scipy.sparse matrix or array
        The Hermitian operator.
    M : (n, n) scipy.sparse matrix or array
        The Hermitian mass matrix, with a positive diagonal.
    eigenvalues : (k,) float array
        The approximate eigenvalues ``λ_i`` (a scalar counts as ``k = 1``).
    eigenvectors : (n, k) float or complex array
        The approximate eigenvectors ``u_i`` as columns (an ``(n,)`` array counts as one column).

    Returns
    -------
    eta : (k,) float array
        The backward error of each pair (0 where the denominator vanishes and the residual is 0).

    Raises
    ------
    ShapeError
        When ``A`` or ``M`` is not a non-empty square numeric matrix, their shapes differ, or
        ``eigenvectors`` does not have shape ``(n, k)``.
    NonFiniteError
        When ``A`` or ``M`` has a NaN or infinite entry.
    InvalidOperatorError
        When ``A`` or ``M`` is not Hermitian, or ``M`` has a non-positive diagonal entry.

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


def default_tol(n: int) -> float:
    """The default backward-error tolerance for ``n`` unknowns, ``min(1e-10, 3e-6 / n)`` (module docstring).

    Parameters
    ----------
    n : int
        The number of unknowns (values below 1 count as 1).

    Returns
    -------
    float
        The tolerance.

    Examples
    --------
    >>> default_tol(1000), default_tol(300_000)
    (1e-10, 1e-11)
    """
    return float(min(1e-10, 3e-6 / max(int(n), 1)))


def smallest_eigenpairs(A, M, k: int = 1, *, sigma=None, v0=None, psd: bool = True,
                        solver: SolverOptions | str | None = None, **deprecated) -> EigenResult:
    """The ``k`` smallest eigenpairs of ``A u = λ M u`` (A Hermitian PSD, M Hermitian PD).

    Parameters
    ----------
    A, M : (n, n) sparse or dense matrix, real or complex Hermitian
    k : int
        Number of eigenpairs, ``1 <= k <= n``.
    sigma : float, optional
        Shift; if given, the ``k`` eigenvalues closest to ``sigma`` are returned (``A`` need not
        be PSD then).  Default ``-ε`` (see module docstring): the ``k`` smallest.
    v0 : (n,) or (n, j) array, optional
        Start vector(s) (summed into one for Lanczos); default a seeded random vector, so results
        are reproducible.
    psd : bool
        ``True`` (default): ``A`` must be positive semidefinite, and an eigenvalue below ``−ε``
        is an error.  ``False``: ``A`` may be indefinite; the ``k`` algebraically smallest pairs
        are returned, certified by inertia: SuperLU's ``L D Lᴴ`` pivots count the eigenvalues
        below the shift, and the shift is lowered (refactorizing) until Lanczos has found all of
        them.  Direct backends only (SuperLU is used for the inertia).
    solver : dhlb.linalg.SolverOptions or str, optional
        Backend, tolerance (default :func:`default_tol` ``(n)``), ``maxiter``, ``block_size``,
        ``factor_shift`` and ``seed`` (:class:`~dhlb.linalg.SolverOptions`); a string names the
        backend.  With one BLAS thread every backend is bitwise reproducible run to run for a given
        ``seed``: the direct backends (SuperLU, CHOLMOD) and Lanczos are deterministic given the start
        vector, and so are pyamg's aggregation and LOBPCG (``amg-lobpcg``).  A different ``seed``
        gives the same eigenvalues to the tolerance and, for a simple eigenvalue, the same
        eigenvector up to its phase, which :attr:`EigenResult.eigenvectors` fixes (largest entry
        real positive).
    **deprecated
        The keywords ``tol``, ``maxiter``, ``backend``, ``block_size``, ``factor_shift`` and ``seed``
        of dhlb 0.1, each folded into ``solver`` with a :class:`DeprecationWarning`.

    Returns
    -------
    EigenResult

    Raises
    ------
    ShapeError, NonFiniteError, InvalidOperatorError
        Bad input: non-square/mismatched matrices, NaN/inf, not Hermitian, ``M`` not PD, or
        (default shift) ``A + εM`` not positive definite, i.e. ``A`` is not PSD.
    InvalidParameterError
        ``k``, ``sigma`` or ``block_size`` (below ``k``) out of range; an old keyword together with ``solver``.
    TypeError
        An unknown keyword argument.
    ResourceLimitError
        The ``k`` eigenvectors (and the Krylov basis) would not fit in the available memory; checked
        before any work.
    InsufficientMemoryError
        The factorization would not fit in the available memory and no iterative backend is
        installed (the message says what would fit).  With ``backend=None``/``"auto"`` and pyamg
        installed the solver falls back to ``amg-lobpcg`` instead and says so in
        :attr:`EigenResult.note`.
    ConvergenceError
        Not converged within ``maxiter``.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> n = 500                                       # path graph: λ_j = 2 - 2 cos(πj/n)
    >>> A = sp.diags([-np.ones(n - 1), np.r_[1, 2 * np.ones(n - 2), 1], -np.ones(n - 1)], [-1, 0, 1])
    >>> res = smallest_eigenpairs(A, sp.identity(n), k=3)
    >>> np.allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * np.arange(3) / n), atol=1e-12)
    True
    >>> res.converged, res.method, res.factorizations, bool(res.residuals.max() <= 1e-10)
    (True, 'lanczos', 1, True)
    >>> smallest_eigenpairs(A, sp.identity(n), solver=SolverOptions(backend="superlu", tol=1e-12)).converged
    True
    """
    (solver,) = fold_deprecated_kwargs("smallest_eigenpairs", deprecated, ("solver", solver, SolverOptions(), _SOLVER))
    solver = solver_options(solver)
    A, M = _validate_pair(A, M)
    n = A.shape[0]
    if not (isinstance(k, (int, np.integer)) and not isinstance(k, bool) and 1 <= k <= n):
        raise InvalidParameterError(f"k must be an integer with 1 <= k <= n = {n}, got {k!r}")
    tol = default_tol(n) if solver.tol is None else solver.tol
    maxiter, backend, block_size = solver.maxiter, solver.backend, solver.block_size
    factor_shift, seed = solver.factor_shift, solver.seed
    if not isinstance(psd, (bool, np.bool_)):
        raise InvalidParameterError(f"psd must be True or False, got {psd!r}")
    default = sigma is None
    if not default and not (np.isscalar(sigma) and np.isreal(sigma) and np.isfinite(sigma)):
        raise InvalidParameterError(f"sigma must be a finite real number, got {sigma!r}")
    if block_size is not None and not (isinstance(block_size, (int, np.integer)) and k <= block_size):
        raise InvalidParameterError(f"block_size must be an integer >= k = {k}, got {block_size!r}")
    _check_basis_memory(n, k, block_size, np.iscomplexobj(A.data) or np.iscomplexobj(M.data))
    sA, sM = _pencil_scales(A, M)
    if sA == 1.0 and sM == 1.0:
        return _solve(A, M, k, tol, maxiter, sigma, v0, backend, block_size, factor_shift, psd, seed)
    res = _solve(A * sA, M * sM, k, tol, maxiter, None if sigma is None else float(sigma) * sA / sM, v0, backend,
                 block_size, factor_shift, psd, seed)
    return _unscale(res, sA, sM)


def _check_basis_memory(n: int, k: int, block_size, complex_: bool) -> None:
    """Refuse, before any work, a number of eigenpairs whose vectors would not fit in memory."""
    from dhlb.errors import ResourceLimitError
    from dhlb.linalg.memory import available_bytes

    if n <= DENSE_MAX:
        return
    vectors = max(2 * k + 1, k + 24, int(block_size or 0)) + 1 + 2 * k + 3   # basis, Ritz vectors, A X, work
    need = vectors * n * (16 if complex_ else 8)
    have = available_bytes()
    if need > have:
        fit = max(1, int(have / (5 * n * (16 if complex_ else 8))))
        raise ResourceLimitError("k", k, need, have, f"at most about k = {fit} eigenpairs of this {n:,}-unknown "
                                 "problem fit in memory")


def _pencil_scales(A, M) -> tuple[float, float]:
    """Powers of two ``(s_A, s_M)`` that bring ``‖A‖₁`` and ``max M_ii`` near 1, or ``(1, 1)`` if they are.

    The eigenproblem is scale-covariant: ``(s_A A) u = (s_A λ / s_M)(s_M M) u``.  A mesh measured in
    units of 1e-150 has a mass matrix near 1e-300 and the M-norms of Lanczos underflow; scaling by powers
    of two (``s_M`` a power of four, so that ``√s_M`` is one too) is exact, so results in the
    caller's units do not depend on the unit.  Only far-out scales (beyond 2^±64) are touched.
    """
    nA = _norm1(A)
    dM = float(M.diagonal().real.max())
    eA = int(np.round(np.log2(nA))) if nA > 0 and np.isfinite(nA) else 0
    eM = int(np.round(np.log2(dM) / 2)) if dM > 0 and np.isfinite(dM) else 0
    if abs(eA) <= 64 and abs(eM) <= 32:
        return 1.0, 1.0
    return float(np.ldexp(1.0, -eA)), float(np.ldexp(1.0, -2 * eM))


def _unscale(res: EigenResult, sA: float, sM: float) -> EigenResult:
    """The result of the scaled pencil ``(s_A A, s_M M)`` in the caller's units."""
    c = sM / sA
    fac = None if res.factor is None else _ScaledFactor(res.factor, sA)
    return replace(res, eigenvalues=res.eigenvalues * c, eigenvectors=res.eigenvectors * np.sqrt(sM),
                   shift=res.shift * c, factor=fac)


class _ScaledFactor:
    """``solve`` for ``A − σM`` from a factor of ``s_A (A − σM)``."""

    def __init__(self, fac, sA: float):
        self.fac, self.sA = fac, sA
        self.name = getattr(fac, "name", "")

    @property
    def negative_pivots(self):
        return getattr(self.fac, "negative_pivots", None)

    def solve(self, B):
        return self.fac.solve(B) * self.sA


def _solve(A, M, k, tol, maxiter, sigma, v0, backend, block_size, factor_shift, psd, seed) -> EigenResult:
    """:func:`smallest_eigenpairs` after the checks, on a pencil of ordinary scale."""
    n = A.shape[0]
    default = sigma is None
    complex_ = np.iscomplexobj(A.data) or np.iscomplexobj(M.data)
    eps_shift = default_shift(A, M)
    shift = -eps_shift if default else float(sigma)
    ncv = int(block_size) if block_size is not None else max(2 * k + 1, k + 24)
    v = _start_vector(n, complex_, v0, seed)
    auto = backend is None or (isinstance(backend, str) and backend == "auto")
    if not auto:
        get_backend(backend)  # an unknown or uninstalled name is an error even when the dense path answers
    if (auto and n <= DENSE_MAX) or k >= n - 2 or (block_size is not None and ncv >= n - 1):
        return _dense(A, M, k, shift, default, psd, tol, eps_shift)
    ncv = min(ncv, n - 1)
    if default and not psd:
        with blas_guard():
            return _lowest_of_indefinite(A, M, k, eps_shift, tol, maxiter, v, ncv)
    # a warm start may already pass (not when the caller asked for the factor of A + εM: it must be made)
    if v0 is not None and factor_shift != "floor" and (k == 1 or (np.ndim(v0) == 2 and np.shape(v0)[1] >= k)):
        W = np.asarray(v0) if np.ndim(v0) == 2 and np.shape(v0)[1] >= k else v[:, None]
        _, _, lam, U, eta = _rayleigh_ritz(A, M, W, k, shift, _norm1(A), _norm1(M))
        if np.all(eta <= tol) and not (default and lam[0] < shift):
            return EigenResult(lam, _fix_phase(U), 0, eta, True, "warm start", shift, k, "rayleigh-ritz")
    be = get_backend(backend, n=n, nnz=A.nnz, eigen=True, shifted=not default, dimension=lambda: pattern_dimension(A))
    with blas_guard():  # once per eigen solve: every factorization and solve below runs inside
        if hasattr(be, "eigensolve"):
            return _iterative(be, A, M, k, v, block_size, eps_shift, tol, maxiter, default, complex_, seed)
        try:
            fac, shift = _factorize_shifted(be, A, M, shift, eps_shift, default)
        except InsufficientMemoryError as err:
            if not (auto and default and "amg-lobpcg" in available_backends()):
                raise
            res = _iterative(get_backend("amg-lobpcg"), A, M, k, v, block_size, eps_shift, tol, maxiter, default,
                             complex_, seed)
            return replace(res, note=f"{be.name} would not fit in memory ({err}); solved by amg-lobpcg instead")
        res = _shift_invert(fac, A, M, k, shift, tol, maxiter, v, ncv, default, getattr(fac, "name", be.name))
    return replace(res, factor=fac, factorizations=1)


def _lowest_of_indefinite(A, M, k, eps_shift, tol, maxiter, v, ncv, tries=12):
    """The ``k`` smallest pairs of an indefinite pencil, certified by the inertia of ``A − σM``.

    ``ν`` negative pivots of the ``L D Lᴴ`` factorization of ``A − σM`` (Sylvester) mean exactly
    ``ν`` eigenvalues below ``σ``.  Lanczos asks for the ``ν + k`` nearest to ``σ``; when ``ν`` of
    them lie below ``σ`` every eigenvalue below ``σ`` has been found, and the ``k`` smallest of
    what was found are the ``k`` smallest of the pencil.  Otherwise ``σ`` is lowered below the
    lowest eigenvalue found, by ten times its distance to ``σ`` and then a hundred, ... (never
    below a Gershgorin bound of the spectrum), and the pencil refactorized.
    """
    from dhlb.linalg.backends import SuperLUBackend

    n = A.shape[0]
    shift, solves = -eps_shift, 0
    d = M.diagonal().real                              # Gershgorin: every eigenvalue is >= floor
    floor = -1.01 * float(np.max(abs(A).sum(axis=1).A1 / d)) / float(min(1.0, np.min(d) / np.max(d))) - eps_shift
    for attempt in range(1, tries + 1):
        try:
            fac = SuperLUBackend().factorize((A - shift * M).tocsc(), inertia=True)
        except InvalidOperatorError:  # σ is (numerically) an eigenvalue: step off it
            shift -= eps_shift
            continue
        nu = fac.negative_pivots
        if nu == 0:
            res = _shift_invert(fac, A, M, k, shift, tol, maxiter, v, ncv, False, fac.name)
            return replace(res, factor=fac, factorizations=attempt, solves=solves + res.solves)
        nev = min(n - 2, nu + k)
        op = _CountingInverse(fac)
        out = lanczos(op, A, M, nev, v, shift=shift,
                      solver=SolverOptions(tol=tol, maxiter=maxiter, block_size=max(ncv, min(n - 1, 2 * nev + 1))))
        solves += op.count
        lam_all = out.eigenvalues
        if out.converged and int(np.sum(lam_all < shift)) == nu:
            sel = np.argsort(lam_all, kind="stable")[:k]
            return EigenResult(lam_all[sel], _fix_phase(out.vectors[:, sel]), solves, out.residuals[sel], True,
                               fac.name, shift, ncv, "lanczos", factorizations=attempt, solves=solves, factor=fac)
        low = min(float(lam_all.min()), shift)
        shift = max(low - max(abs(shift - low), eps_shift) * 10.0**attempt, floor)
    raise ConvergenceError(f"smallest_eigenpairs(psd=False): the {k} smallest eigenvalues were not certified "
                           f"after {tries} shifts (last shift {shift:.6g}); is A far from semidefinite?")


def _iterative(be, A, M, k, v, block_size, eps_shift, tol, maxiter, default, complex_, seed=0):
    """An iterative backend's block method (LOBPCG) from ``v`` and random vectors."""
    if not default:
        raise InvalidParameterError(f"backend {be.name!r} computes the smallest eigenvalues only; sigma= needs a "
                                    "direct backend (e.g. backend='superlu' or 'cholmod')")
    n = A.shape[0]
    p = min(n, int(block_size) if block_size is not None else (k if k == 1 else k + max(2, k // 2)))
    U = np.concatenate([v[:, None], _random_block(n, p - 1, complex_, seed + 1)], axis=1)
    return _iterate_lobpcg(be, A, M, U, k, eps_shift, tol, maxiter)


class _CountingInverse:
    """``x ↦ K⁻¹ x`` through a factor, counting the solves."""

    def __init__(self, fac):
        self.fac, self.count = fac, 0

    def __call__(self, x):
        self.count += 1
        return self.fac.solve(x)


def _shift_invert(fac, A, M, k, shift, tol, maxiter, v, ncv, default, name):
    """Shift-and-invert Lanczos (:mod:`dhlb.linalg._lanczos`) on the factorized shift.

    Lanczos stops at the first step where the backward errors of the ``k`` wanted pairs meet
    ``tol``.  For ``k > 1`` the result is checked for a missed copy of a multiple eigenvalue (a
    single-vector Krylov method sees the second copy only through rounding): Lanczos runs once
    more on the M-orthogonal complement of the pairs found, and whatever it finds below ``λ_k``
    joins them (Rayleigh–Ritz on the union); this repeats until a pass finds nothing new below ``λ_k``.
    """
    n = A.shape[0]
    op = _CountingInverse(fac)
    out = lanczos(op, A, M, k, v, shift=shift, solver=SolverOptions(tol=tol, maxiter=maxiter, block_size=ncv))
    lam, U, eta = out.eigenvalues, out.vectors, out.residuals
    found, passes = U, 0
    while out.converged and k > 1:   # a pass finds one copy of each eigenvalue: repeat until none is missed
        passes += 1
        defl = _Deflated(op, M, found)
        start = defl.project(_random_block(n, 1, np.iscomplexobj(U), seed=7 + passes)[:, 0])  # not the first start
        extra = lanczos(defl, A, M, max(1, k // 4), start, shift=shift,
                        solver=SolverOptions(tol=tol, maxiter=max(1, maxiter - op.count), block_size=ncv))
        if not (extra.converged and np.any(extra.eigenvalues < lam[-1])):
            break
        union, _, lam2, U2, eta2 = _rayleigh_ritz(A, M, np.concatenate([found, extra.vectors], axis=1), k, shift,
                                                  _norm1(A), _norm1(M))
        if not np.sum(lam2) < np.sum(lam) - 1e-8 * (abs(lam[-1]) + abs(shift)):   # nothing missed: a copy again
            break
        found, lam, U, eta = union, lam2, U2, eta2
    if default and lam[0] < shift:
        raise _not_psd(lam[0], shift)
    if out.converged and np.all(eta <= tol):
        return EigenResult(lam, _fix_phase(U), op.count, eta, True, name, shift, ncv, "lanczos", solves=op.count)
    part = EigenResult(lam, _fix_phase(U), op.count, eta, False, name, shift, ncv, "lanczos", factorizations=1,
                       solves=op.count, factor=fac)
    raise _not_converged(part, op.count, tol, ncv)


class _Deflated:
    """``y ↦ P K⁻¹ y`` with ``P = I − X Xᴴ M`` the M-orthogonal projector onto the complement of ``X``.

    ``X`` is M-orthonormal (Lanczos' Ritz vectors).
    """

    def __init__(self, op, M, X):
        self.op, self.X, self.MX = op, X, M @ X

    def project(self, x):
        return x - self.X @ (self.MX.conj().T @ x)

    def __call__(self, y):   # twice: K⁻¹ amplifies what one projection leaves of X by up to 1/|λ − σ|
        return self.project(self.project(self.op(y)))


def _dense(A, M, k, shift, smallest, psd, tol, eps_shift):
    """Dense generalized eigensolver for small problems (always converges).

    ``smallest``: the ``k`` algebraically smallest pairs (``sigma`` not given), else the ``k``
    closest to ``shift``; ``psd``: an eigenvalue below the shift is an error.  Like the sparse path,
    the returned factor steps off ``shift`` by ``ε`` when ``shift`` is exactly an eigenvalue.
    """
    Ad, Md = A.toarray(), M.toarray()
    n = Ad.shape[0]
    try:
        if smallest:
            lam, U = sla.eigh(Ad, Md, subset_by_index=[0, k - 1])
        else:
            lam, U = sla.eigh(Ad, Md)
            sel = np.sort(np.argsort(np.abs(lam - shift), kind="stable")[:k])
            lam, U = lam[sel], U[:, sel]
    except np.linalg.LinAlgError as err:
        raise InvalidOperatorError(f"M is not positive definite ({err})") from err
    if smallest and psd and lam[0] < shift:
        raise _not_psd(lam[0], shift)
    eta = _eta(A @ U - (M @ U) * lam[None, :], lam, U, _norm1(A), _norm1(M))
    fac = _DenseFactor(Ad - shift * Md)
    if not fac.regular:  # σ is exactly an eigenvalue: step off it
        shift -= eps_shift
        fac = _DenseFactor(Ad - shift * Md)
    return EigenResult(lam, _fix_phase(U), 0, eta, bool(np.all(eta <= max(tol, 1e3 * _EPS))), "dense", shift, n,
                       "dense", factor=fac)


class _DenseFactor:
    """LU factorization of a small dense ``K`` with the ``solve(B)`` of the sparse backends."""

    name = "dense"

    def __init__(self, K):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sla.LinAlgWarning)  # an exactly singular K: reported by `regular`
            self.lu = sla.lu_factor(K, check_finite=False)
        self.regular = bool(np.all(np.diagonal(self.lu[0]) != 0))

    def solve(self, B):
        return sla.lu_solve(self.lu, np.asarray(B), check_finite=False)


def _random_block(n, p, complex_, seed=0):
    rng = np.random.default_rng(seed)
    U = rng.standard_normal((n, p))
    return U + 1j * rng.standard_normal((n, p)) if complex_ else U


def _start_vector(n, complex_, v0, seed=0):
    if v0 is None:
        return _random_block(n, 1, complex_, seed)[:, 0]
    V = np.asarray(v0)
    V = V.reshape(-1, 1) if V.ndim == 1 else V
    if V.ndim != 2 or V.shape[0] != n or V.shape[1] > n:
        raise ShapeError(f"v0 must have shape ({n},) or ({n}, j) with j <= {n}, got {np.shape(v0)}")
    if not np.all(np.isfinite(V)):
        raise NonFiniteError("v0 contains NaN or inf")
    v = V.sum(axis=1)
    if not np.any(v):
        return _random_block(n, 1, complex_, seed)[:, 0]
    return v.astype(np.complex128) if complex_ else np.real(v).astype(np.float64)


def _factorize_shifted(be, A, M, shift, eps_shift, default):
    if default:
        try:
            return be.factorize((A + eps_shift * M).tocsc(), positive_definite=True), shift
        except InvalidOperatorError as err:
            raise NotSemidefiniteError(f"A + εM (ε = {eps_shift:.3g}) is not positive definite, so A is not "
                                       f"positive semidefinite ({err}); pass psd=False for the smallest pairs of "
                                       "an indefinite A, or sigma= to search near a chosen value") from err
    try:
        return be.factorize((A - shift * M).tocsc()), shift
    except InvalidOperatorError:  # σ is exactly an eigenvalue: step off it
        return be.factorize((A - (shift - eps_shift) * M).tocsc()), shift - eps_shift
