"""What every ``dhlb`` subcommand shares: common options, output, error reporting, exit codes.

Exit codes: 0 success; 1 the command failed (unparsable or invalid input, failed computation);
2 usage error (bad option, missing input file, unknown file format). User mistakes are reported
in one line on stderr, without a traceback unless ``--debug`` is given.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

from dhlb.errors import DhlbError, MeshParseError

__all__ = ["UsageError", "add_command", "common_options", "run_command", "write_output", "resolve_input"]

EXIT_OK, EXIT_FAILURE, EXIT_USAGE = 0, 1, 2


class UsageError(Exception):
    """A mistake in how the command was called (reported with exit code 2)."""


def common_options() -> argparse.ArgumentParser:
    """Parent parser with the options every subcommand accepts."""
    parent = argparse.ArgumentParser(add_help=False)
    group = parent.add_argument_group("common options")
    group.add_argument("-o", "--output", metavar="FILE", help="write the result to FILE instead of stdout")
    group.add_argument("--json", action="store_true", help="print machine-readable JSON instead of text")
    group.add_argument("-q", "--quiet", action="store_true", help="do not print warnings")
    group.add_argument("--debug", action="store_true", help="show full tracebacks on errors")
    return parent


def add_command(subparsers, name: str, summary: str, description: str, examples: str) -> argparse.ArgumentParser:
    """Create the parser of a subcommand with the common options and an examples epilog."""
    return subparsers.add_parser(
        name,
        help=summary,
        description=description,
        epilog="examples:\n" + examples.rstrip() + "\n\n" + EXIT_CODES_HELP,
        parents=[common_options()],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )


EXIT_CODES_HELP = (
    "exit codes: 0 ok, 1 failure (e.g. unparsable or invalid input), 2 usage error\n"
    "(bad option, missing input file, unknown format)."
)


def resolve_input(path: str, fmt: str | None = None) -> str:
    """Check that ``path`` is a readable file of a known format; return the format name.

    Raises :class:`UsageError` otherwise.
    """
    from dhlb.io.formats import format_of

    if not os.path.exists(path):
        raise UsageError(f"{path}: no such file")
    if os.path.isdir(path):
        raise UsageError(f"{path}: is a directory, not a mesh file")
    try:
        return format_of(path, fmt, hint="(or use --format FMT)")
    except MeshParseError as exc:
        raise UsageError(str(exc)) from None


def write_output(args, text: str) -> None:
    """Write ``text`` to ``args.output`` (or stdout), ending with a newline."""
    if not text.endswith("\n"):
        text += "\n"
    if args.output and args.output != "-":
        try:
            with open(args.output, "w", encoding="utf-8") as fh:
                fh.write(text)
        except OSError as exc:
            raise UsageError(f"cannot write {args.output}: {exc.strerror}") from None
    else:
        sys.stdout.write(text)


def _one_line(message) -> str:
    return " ".join(str(message).split())


def run_command(args) -> int:
    """Run ``args.func(args)`` and turn exceptions into one-line messages and exit codes."""
    prog = f"dhlb {args.command}"
    debug = getattr(args, "debug", False)

    def show_warning(message, category, filename, lineno, file=None, line=None):
        print(f"{prog}: warning: {_one_line(message)}", file=sys.stderr)

    try:
        with warnings.catch_warnings():
            if getattr(args, "quiet", False):
                warnings.simplefilter("ignore")
            else:
                warnings.simplefilter("default")
                warnings.showwarning = show_warning
            return int(args.func(args))
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except UsageError as exc:
        if debug:
            raise
        print(f"{prog}: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        if debug:
            raise
        what = exc.filename if exc.filename else ""
        print(f"{prog}: error: cannot open {what}: {exc.strerror or _one_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except DhlbError as exc:
        if debug:
            raise
        print(f"{prog}: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_FAILURE
    except Exception as exc:  # a bug: still one line, but say so
        if debug:
            raise
        print(
            f"{prog}: internal error: {type(exc).__name__}: {_one_line(exc)} "
            "(this is a bug in dhlb; rerun with --debug for the traceback)",
            file=sys.stderr,
        )
        return EXIT_FAILURE
