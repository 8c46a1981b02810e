"""Layer 4: sparse linear algebra — eigenpairs and shifted solves of Hermitian pencils, their backends.

* :func:`smallest_eigenpairs` — ``A u = λ M u``: shift-and-invert Lanczos on one sparse
  factorization (:mod:`dhlb.linalg.eigen`), dense for small problems, LOBPCG for iterative
  backends; every pair passes a normwise backward-error test.
* :func:`solve` — ``(A − λM) x = b``.
* :class:`SolverOptions` — the solver knobs (backend, tolerance, ...) as one frozen value, taken by
  every solving function as ``solver=`` (a backend name is shorthand, :func:`solver_options`).
* backends (:mod:`dhlb.linalg.backends`): CHOLMOD (cvxopt's wheel) and SuperLU in a
  nested-dissection order (always), cholespy and AMG-LOBPCG when their packages are installed;
  :func:`select_backend`
  chooses by size, sparsity and the memory a factorization would need
  (:mod:`dhlb.linalg.memory`, :mod:`dhlb.linalg.ordering`).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from dhlb.linalg import smallest_eigenpairs
>>> A = sp.diags([2.0, 3.0, 5.0]); M = sp.identity(3)
>>> smallest_eigenpairs(A, M, 2).eigenvalues.tolist()
[2.0, 3.0]
"""

from dhlb.linalg import backends_cholesky  # noqa: F401  (the default direct backend: cvxopt loads with the layer)
from dhlb.linalg.backends import available_backends, select_backend
from dhlb.linalg.eigen import EigenResult, backward_errors, default_shift, default_tol, smallest_eigenpairs
from dhlb.linalg.linear import solve
from dhlb.linalg.memory import InsufficientMemoryError, available_bytes, set_memory_limit
from dhlb.linalg.options import SolverOptions, solver_options

__all__ = [
    "EigenResult",
    "backward_errors",
    "default_shift",
    "default_tol",
    "smallest_eigenpairs",
    "SolverOptions",
    "solver_options",
    "solve",
    "available_backends",
    "select_backend",
    "InsufficientMemoryError",
    "available_bytes",
    "set_memory_limit",
]
