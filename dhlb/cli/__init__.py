"""The ``dhlb`` command line: a thin dispatcher over its subcommands (:mod:`dhlb.cli.commands`).

Examples
--------
>>> from dhlb.cli import main
>>> main(["--version"])  # doctest: +ELLIPSIS
dhlb ...
0
"""

from __future__ import annotations

import argparse
import sys

__all__ = ["build_parser", "main"]

_EPILOG = """\
examples:
  dhlb info                      # topology of the bundled example torus
  dhlb info mesh.off --json      # the same for your mesh, as JSON
  dhlb info --help               # options of one command

exit codes: 0 ok, 1 failure (e.g. unparsable or invalid input), 2 usage error
(bad option, missing input file, unknown format). Add --debug to a command to see tracebacks."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``dhlb`` with one subparser per command module."""
    from dhlb import __version__
    from dhlb.cli.commands import iter_commands

    parser = argparse.ArgumentParser(
        prog="dhlb",
        description="Discrete hermitian line bundles on simplicial complexes: command-line tools.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"dhlb {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")
    for module in iter_commands():
        module.register(subparsers)
    return parser


def _subparser(parser: argparse.ArgumentParser, name: str | None) -> argparse.ArgumentParser:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction) and name in action.choices:
            return action.choices[name]
    return parser


def main(argv=None) -> int:
    """Run ``dhlb`` with ``argv`` (default ``sys.argv[1:]``); return the exit code."""
    from dhlb.cli._common import EXIT_USAGE, run_command

    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
        if extra:  # report unknown options with the usage line of the subcommand they were given to
            sub = _subparser(parser, getattr(args, "command", None))
            sub.error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # --help / --version (0) or a usage error (2), already printed
        return exc.code if isinstance(exc.code, int) else EXIT_USAGE
    if args.command is None:
        parser.print_usage(sys.stderr)
        print("dhlb: error: a command is required (try 'dhlb info' or 'dhlb --help')", file=sys.stderr)
        return EXIT_USAGE
    return run_command(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
