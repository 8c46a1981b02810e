"""The knobs of the sparse eigen and linear solvers, as one frozen value: :class:`SolverOptions`.

Every function that solves (:func:`dhlb.linalg.smallest_eigenpairs` and the applications built on it)
takes ``solver: SolverOptions | str | None``; a string is shorthand for the backend,
``solver="cholmod"`` ≡ ``solver=SolverOptions(backend="cholmod")`` (:func:`solver_options`).

Examples
--------
>>> from dhlb.linalg import SolverOptions
>>> opts = SolverOptions(backend="superlu", tol=1e-12)
>>> opts.replace(maxiter=50).maxiter, opts.maxiter
(50, 1000)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from dhlb.errors import InvalidParameterError

__all__ = ["SolverOptions", "solver_options"]


@dataclass(frozen=True)
class SolverOptions:
    """How the sparse eigen and linear solvers run (see :func:`dhlb.linalg.smallest_eigenpairs`).

    Parameters
    ----------
    backend : str or backend object, optional
        ``"superlu"``, ``"cholmod"``, ``"cholespy"``, ``"amg-lobpcg"`` (if installed), a backend
        object, or ``None``/``"auto"``: chosen by size, sparsity and availability
        (:func:`dhlb.linalg.select_backend`).  ``amg-lobpcg`` needs ``sigma=None``.
    tol : float, optional
        Bound on the normwise backward error of each eigenpair; default (``None``)
        :func:`dhlb.linalg.default_tol` ``(n)``, or the application's own default.
    maxiter : int
        Maximal number of applications of the shifted inverse (direct backends) or of LOBPCG
        iterations (``amg-lobpcg``).
    block_size : int, optional
        Largest Lanczos basis before a thick restart (default ``max(2k + 1, k + 24)``),
        or the LOBPCG block for ``amg-lobpcg``; raise it above the size of a cluster of nearly
        equal eigenvalues.  Must be at least the number ``k`` of wanted pairs (checked by the solve).
    factor_shift : {"auto", "floor"}
        Where the factorization is placed when ``sigma`` is not given: ``"auto"`` lets the solver
        choose; ``"floor"`` factorizes ``A + εM`` (``σ = −ε``), so that ``EigenResult.factor``
        approximates ``A⁻¹`` — for callers that go on iterating with ``A⁻¹``.
    seed : int
        Seed of the random start vectors (when ``v0`` does not give them all); with one BLAS thread
        every backend is then bitwise reproducible run to run.

    Raises
    ------
    InvalidParameterError
        ``tol``, ``maxiter``, ``block_size``, ``factor_shift`` or ``seed`` out of range.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from dhlb.linalg import SolverOptions, smallest_eigenpairs
    >>> res = smallest_eigenpairs(sp.diags([2.0, 3.0, 5.0]), sp.identity(3), 2, solver=SolverOptions(tol=1e-12))
    >>> res.eigenvalues.tolist()
    [2.0, 3.0]
    >>> SolverOptions(maxiter=0)
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidParameterError: maxiter must be a positive integer, got 0
    """

    backend: Any = None
    tol: float | None = None
    maxiter: int = 1000
    block_size: int | None = None
    factor_shift: str = "auto"
    seed: int = 0

    def __post_init__(self) -> None:
        tol = self.tol
        if tol is not None and not (isinstance(tol, (int, float, np.floating)) and not isinstance(tol, bool)
                                    and np.isfinite(tol) and tol > 0):
            raise InvalidParameterError(f"tol must be a positive number, got {tol!r}")
        if not (isinstance(self.maxiter, (int, np.integer)) and not isinstance(self.maxiter, bool)
                and self.maxiter >= 1):
            raise InvalidParameterError(f"maxiter must be a positive integer, got {self.maxiter!r}")
        if not (isinstance(self.seed, (int, np.integer)) and not isinstance(self.seed, bool) and self.seed >= 0):
            raise InvalidParameterError(f"seed must be a non-negative integer, got {self.seed!r}")
        if self.factor_shift not in ("auto", "floor"):
            raise InvalidParameterError(f"factor_shift must be 'auto' or 'floor', got {self.factor_shift!r}")
        bs = self.block_size
        if bs is not None and not (isinstance(bs, (int, np.integer)) and not isinstance(bs, bool) and bs >= 1):
            raise InvalidParameterError(f"block_size must be a positive integer, got {bs!r}")

    def replace(self, **changes: Any) -> SolverOptions:
        """A copy with some fields changed (:func:`dataclasses.replace`; validated again).

        Parameters
        ----------
        **changes
            Field names and their new values.

        Returns
        -------
        SolverOptions

        Examples
        --------
        >>> SolverOptions().replace(backend="superlu").backend
        'superlu'
        """
        return dataclasses.replace(self, **changes)


def solver_options(solver: SolverOptions | str | None, default: SolverOptions | None = None) -> SolverOptions:
    """``solver`` as a :class:`SolverOptions`: ``None`` → ``default``, a string → that backend.

    Parameters
    ----------
    solver : SolverOptions, str or None
        What the caller passed as ``solver=``.
    default : SolverOptions, optional
        Used when ``solver`` is None (default ``SolverOptions()``); a string replaces its backend.

    Returns
    -------
    SolverOptions

    Raises
    ------
    InvalidParameterError
        ``solver`` is neither None, a string nor a :class:`SolverOptions`.

    Examples
    --------
    >>> solver_options("superlu", SolverOptions(tol=1e-9))
    SolverOptions(backend='superlu', tol=1e-09, maxiter=1000, block_size=None, factor_shift='auto', seed=0)
    """
    default = SolverOptions() if default is None else default
    if solver is None:
        return default
    if isinstance(solver, str):
        return default.replace(backend=solver)
    if not isinstance(solver, SolverOptions):
        raise InvalidParameterError(f"solver must be a SolverOptions, a backend name or None, got {solver!r}")
    return solver
