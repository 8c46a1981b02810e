"""Deprecated alias package: the subcommands moved to :mod:`dhlb.cli` (dhlb 0.2; removed in 0.3)."""

from dhlb._deprecation import moved_module

__getattr__, __dir__ = moved_module(__name__, "dhlb.cli.commands")
