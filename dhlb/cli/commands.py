"""The subcommands of the ``dhlb`` command line, in the order ``dhlb --help`` lists them.

Each subcommand lives in its own module of :mod:`dhlb.cli` and defines

* ``NAME`` (the word typed after ``dhlb``) and ``SUMMARY`` (one line for ``dhlb --help``);
* ``register(subparsers)``: add its parser, built with :func:`dhlb.cli._common.add_command`
  so that it shares the common options ``-o/--output``, ``--json``, ``--quiet``, ``--debug``
  (a command that writes result files passes ``outputs=OutputSpec(...)``, the ``-o`` convention);
* ``run(args) -> int``: check every usage (``output_plan`` for ``-o``) before the work, then do it,
  raising :class:`dhlb.cli._common.UsageError` (exit 2) on user mistakes and
  :class:`dhlb.errors.DhlbError` (exit 1) when the input or the computation fails.

To add a command, write the module and append its name to :data:`COMMAND_MODULES`.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Iterator
    from types import ModuleType

__all__ = ["COMMAND_MODULES", "iter_commands"]

#: module names under dhlb.cli, in the order ``dhlb --help`` lists them
COMMAND_MODULES = ("info", "field", "stripes", "vortex", "conformal", "view", "demo")


def iter_commands() -> Iterator[ModuleType]:
    """Yield the command modules listed in :data:`COMMAND_MODULES`.

    Yields
    ------
    module
        ``dhlb.cli.<name>`` for each name, imported on demand.
    """
    for name in COMMAND_MODULES:
        yield importlib.import_module(f"dhlb.cli.{name}")
