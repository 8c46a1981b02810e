"""Deprecated alias of :mod:`dhlb.io.stripes` (moved in dhlb 0.2; removed in 0.3)."""

from dhlb._deprecation import moved_module

__getattr__, __dir__ = moved_module(__name__, "dhlb.io.stripes")
