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

_EXAMPLES = """\
examples:
  dhlb info                      # topology of the bundled example torus
  dhlb info mesh.off --json      # the same for your mesh, as JSON
  dhlb info --help               # options of one command
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``dhlb`` with one subparser per command module.

    Returns
    -------
    argparse.ArgumentParser
        ``dhlb`` and its commands (``build_parser().parse_args(argv)`` gives the namespace a
        command's ``run`` takes).
    """
    from dhlb import __version__
    from dhlb.cli._common import EXIT_CODES_HELP
    from dhlb.cli.commands import iter_commands

    parser = argparse.ArgumentParser(
        prog="dhlb",
        description="Discrete hermitian line bundles on simplicial complexes: command-line tools.",
        epilog=f"{_EXAMPLES}\n{EXIT_CODES_HELP}\nAdd --debug to a command to see tracebacks.",
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


def _check_spelling(parser: argparse.ArgumentParser, argv: list[str]) -> None:
    """Report a misspelt command or ``--option`` with a "did you mean" (argparse's usage error, exit 2).

    Runs before argparse, whose own message for a misspelt option can be another one (a required
    option missing). An unambiguous prefix of an option is accepted, as argparse accepts it.
    """
    from dhlb.cli._common import did_you_mean

    commands = next((a.choices for a in parser._actions if isinstance(a, argparse._SubParsersAction)), {})
    at = next((i for i, t in enumerate(argv) if not t.startswith("-")), None)
    if at is None:
        return
    if argv[at] not in commands:
        hint = did_you_mean(argv[at], commands)
        if hint:
            parser.error(f"unknown command {argv[at]!r}{hint}")
        return
    sub = commands[argv[at]]
    known = [s for a in sub._actions for s in a.option_strings if s.startswith("--")]
    for token in argv[at + 1:]:
        if token == "--":
            break
        if not token.startswith("--"):
            continue
        option = token.split("=", 1)[0]
        if not any(k.startswith(option) for k in known):
            sub.error(f"unrecognized arguments: {option}{did_you_mean(option, known)}")


_MPI_MAIN_RUNNING = False  # set by dhlb.cli.mpi.mpi_main, which calls main() on rank 0

_MPI_SIZE_VARIABLES = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS")
"""Environment variables in which mpirun / mpiexec (Open MPI, MPICH, PMIx) pass the number of ranks."""


def _under_mpirun() -> bool:
    """:func:`dhlb.cli.mpi.launched_by_mpirun`, without importing it (and PETSc) when no MPI variable is set."""
    import os

    if _MPI_MAIN_RUNNING or not any(k in os.environ for k in _MPI_SIZE_VARIABLES):
        return False
    from dhlb.cli.mpi import launched_by_mpirun

    return launched_by_mpirun()


def main(argv=None) -> int:
    """Run ``dhlb`` with ``argv`` (default ``sys.argv[1:]``); return the exit code.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after ``dhlb`` (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 success, 1 a computation that cannot be done, 2 a usage or value error.

    Examples
    --------
    >>> import contextlib, io
    >>> err = io.StringIO()
    >>> with contextlib.redirect_stderr(err):
    ...     main(["stripes", "mesh.obj", "--spacnig", "6"])
    2
    >>> err.getvalue().splitlines()[-1]
    'dhlb stripes: error: unrecognized arguments: --spacnig; did you mean --spacing?'
    """
    from dhlb.cli._common import EXIT_USAGE, run_command

    if _under_mpirun():  # mpirun -n P dhlb ...: every rank runs the command, rank 0 alone writes and prints
        from dhlb.cli.mpi import mpi_main

        return mpi_main(argv)
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else [str(a) for a in argv]
    try:
        _check_spelling(parser, argv)
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
