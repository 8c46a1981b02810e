"""Deprecated alias of :mod:`dhlb.linalg` (the solvers moved there); import from ``dhlb.linalg``."""

from dhlb.linalg.eigen import EigenResult, backward_errors, default_shift, smallest_eigenpairs
from dhlb.linalg.linear import solve

__all__ = ["EigenResult", "backward_errors", "default_shift", "smallest_eigenpairs", "solve"]
