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

from dhlb._deprecation import check_choice, check_integer, check_number, did_you_mean
from dhlb.errors import InvalidParameterError, InvalidTypeError

__all__ = ["SolverOptions", "solver_options"]

FACTOR_SHIFTS = ("auto", "floor")
"""The values of :attr:`SolverOptions.factor_shift`."""


def _check_backend(backend: Any) -> None:
    """Refuse a backend that is neither None, a registered name (or ``"auto"``) nor a backend object."""
    if backend is None or (hasattr(backend, "factorize") and hasattr(backend, "name")):
        return
    from dhlb.linalg.backends import _REGISTRY, available_backends

    names = [*_REGISTRY, "auto"]
    if not isinstance(backend, str):
        raise InvalidTypeError(
            f"SolverOptions.backend must be a backend name ({', '.join(map(repr, names))}), None, or a backend "
            f"object with a `name` and a `factorize(K, positive_definite=False)` method returning an object with "
            f"`solve(B)`; got {backend!r} ({type(backend).__name__})")
    if backend not in names:
        avail = available_backends()
        missing = [n for n in _REGISTRY if n not in avail]
        also = f"; registered but not installed: {', '.join(map(repr, missing))}" if missing else ""
        raise InvalidParameterError(f"SolverOptions.backend: unknown backend {backend!r}; available: {avail} "
                                    f"(or 'auto'){also}{did_you_mean(backend, names)}")


@dataclass(frozen=True)
class SolverOptions:
    """How the sparse eigen and linear solvers run (see :func:`dhlb.linalg.smallest_eigenpairs`).

    Parameters
    ----------
    backend : str or backend object, optional
        ``"superlu"``, ``"cholmod"``, ``"cholespy"``, ``"amg-lobpcg"`` (if installed), a backend
        object, or ``None``/``"auto"``: chosen by size, sparsity and availability
        (:func:`dhlb.linalg.select_backend`).  ``amg-lobpcg`` needs ``sigma=None``.  A name must be
        registered (:func:`dhlb.linalg.register_backend`; checked here); whether it is installed is
        checked when the solve resolves it (:func:`dhlb.linalg.get_backend`).  A backend object has a
        ``name`` and a ``factorize(K, positive_definite=False)`` method.
    tol : float in (0, 1), optional
        Bound on the normwise backward error of each eigenpair; default (``None``)
        :func:`dhlb.linalg.default_tol` ``(n)``, or the application's own default.  Finite, > 0, and
        < 1: the backward error of any vector is at most about 1, so ``tol >= 1`` would accept anything.
    maxiter : int >= 1
        Maximal number of applications of the shifted inverse (direct backends) or of LOBPCG
        iterations (``amg-lobpcg``).
    block_size : int >= 1, optional
        Largest Lanczos basis before a thick restart (default ``max(2k + 1, k + 24)``),
        or the LOBPCG block for ``amg-lobpcg``; raise it above the size of a cluster of nearly
        equal eigenvalues.  Must be at least the number ``k`` of wanted pairs (checked by the solve).
    factor_shift : {"auto", "floor"}
        Where the factorization is placed when ``sigma`` is not given: ``"auto"`` lets the solver
        choose; ``"floor"`` factorizes ``A + εM`` (``σ = −ε``), so that ``EigenResult.factor``
        approximates ``A⁻¹`` — for callers that go on iterating with ``A⁻¹``.
    seed : int >= 0
        Seed of the random start vectors (when ``v0`` does not give them all); with one BLAS thread
        every backend is then bitwise reproducible run to run.  Passed to
        :func:`numpy.random.default_rng`, which refuses negative seeds.

    Raises
    ------
    InvalidParameterError
        ``tol``, ``maxiter``, ``block_size``, ``factor_shift`` or ``seed`` of the wrong type or out of
        range (integers are Python or numpy integers, not bools); a ``backend`` name that is not
        registered.  Checked at construction, and again by :meth:`replace`.
    InvalidTypeError
        A ``backend`` that is neither None, a string nor a backend object (also a :class:`TypeError`,
        as the solve raised before).

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
    dhlb.errors.InvalidParameterError: SolverOptions.maxiter must be an integer >= 1, got 0
    """

    backend: Any = None
    tol: float | None = None
    maxiter: int = 1000
    block_size: int | None = None
    factor_shift: str = "auto"
    seed: int = 0

    _SHORTHAND = ((str,), "a backend name such as 'superlu'")   # solver="superlu" (solver_options)
    _EXAMPLE = "tol=1e-10"   # the example of a right call (dhlb._deprecation.check_option_group)

    def __post_init__(self) -> None:
        _check_backend(self.backend)
        if self.tol is not None:
            check_number(self.tol, "SolverOptions.tol", "a positive number below 1 (a relative backward error), "
                         "or None", lambda x: 0 < x < 1)
        check_integer(self.maxiter, "SolverOptions.maxiter", 1)
        if self.block_size is not None:
            check_integer(self.block_size, "SolverOptions.block_size", 1)
        check_choice(self.factor_shift, "SolverOptions.factor_shift", FACTOR_SHIFTS)
        check_integer(self.seed, "SolverOptions.seed", 0, why="numpy refuses negative seeds")

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
        ``solver`` is neither None, a string nor a :class:`SolverOptions`, or names an unknown backend.

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
        hint = f": write solver=SolverOptions(**{solver!r})" if isinstance(solver, dict) else ""
        raise InvalidParameterError(f"solver must be a SolverOptions, a backend name or None, got {solver!r}{hint}")
    return solver
