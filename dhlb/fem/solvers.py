"""Deprecated alias of :mod:`dhlb.linalg` (the solvers moved there); import from ``dhlb.linalg``."""

import warnings

from dhlb.linalg.eigen import EigenResult, backward_errors, default_shift, smallest_eigenpairs
from dhlb.linalg.linear import solve

__all__ = ["EigenResult", "backward_errors", "default_shift", "smallest_eigenpairs", "solve"]

warnings.warn("dhlb.fem.solvers is deprecated: the solvers live in dhlb.linalg (dhlb.fem re-exports "
              "smallest_eigenpairs, solve, EigenResult)", DeprecationWarning, stacklevel=2)
