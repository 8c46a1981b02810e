"""What every ``dhlb`` subcommand shares: common options, the ``-o`` convention, messages, exit codes.

Exit codes (:data:`EXIT_CODES_HELP`): 0 success; 2 a usage or value error (bad or misspelt option, value
out of range, missing input file, unknown format or ``-o`` extension, missing optional package), found
before any work; 1 the input or the computation fails (the message says what to change). User mistakes
are reported in one line on stderr, without a traceback unless ``--debug`` is given; warnings once each,
in the words of the command line (:func:`cli_warning`).

``-o`` of the commands that write results: :mod:`dhlb.cli._outputs`.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import sys
import warnings

from dhlb._deprecation import did_you_mean as _did_you_mean
from dhlb.errors import DhlbError, MeshParseError, MeshRepairWarning, UnreferencedVertexWarning

__all__ = ["UsageError", "add_command", "common_options", "run_command", "write_output", "resolve_input",
           "finite_float", "int_in_range", "number_tuple", "nonempty_text", "PIXEL_SIZE", "check_outputs",
           "input_paths", "usage_from", "report_table", "did_you_mean", "cli_warning", "EXIT_CODES_HELP",
           "repair_choice", "add_repair_argument", "backend_choice", "check_output_file"]

EXIT_OK, EXIT_FAILURE, EXIT_USAGE = 0, 1, 2


class UsageError(Exception):
    """A mistake in how the command was called (reported with exit code 2)."""


# ------------------------------------------------------------------------------ value types
def finite_float(low: float | None = None, high: float | None = None, *, low_open: bool = False,
                 high_open: bool = False):
    """An argparse ``type`` for a finite float in ``[low, high]`` (``low_open``/``high_open``: exclusive).

    NaN, ±inf, ``1e400`` (overflows to inf) and non-numbers are usage errors (exit 2) naming the
    option, the value and the allowed range. Its attribute ``bounds`` is ``(low, high, low_open, high_open)``.

    Examples
    --------
    >>> positive = finite_float(0, low_open=True)
    >>> positive("2.5")
    2.5
    >>> positive("nan")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: 'nan' is not a finite number > 0
    >>> finite_float(-1, 1)("3")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: '3' is out of range: give a finite number in [-1, 1]
    """

    def describe() -> str:
        if low is not None and high is not None:
            return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
        if low is not None:
            return f"{'>' if low_open else '>='} {low:g}"
        if high is not None:
            return f"{'<' if high_open else '<='} {high:g}"
        return ""

    def convert(text: str) -> float:
        try:
            value = float(text)
        except (TypeError, ValueError):
            value = float("nan")
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{text!r} is not a finite number {describe()}".rstrip())
        if (low is not None and (value < low or (low_open and value == low))) or (
            high is not None and (value > high or (high_open and value == high))
        ):
            raise argparse.ArgumentTypeError(f"{text!r} is out of range: give a finite number {describe()}")
        return value

    convert.__name__ = "finite number"
    convert.bounds = (low, high, low_open, high_open)  # read by the tests that walk every option
    return convert


def int_in_range(low: int, high: int):
    """An argparse ``type`` for an integer in ``[low, high]`` (usage error otherwise, naming the range).

    Its attribute ``bounds`` is ``(low, high)``.

    Examples
    --------
    >>> size = int_in_range(16, 8192)
    >>> size("800")
    800
    >>> size("60000")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: 60000 is out of range: give an integer in [16, 8192]
    >>> size("0x10")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: '0x10' is not an integer; give an integer in [16, 8192]
    """

    def convert(text: str) -> int:
        try:
            value = int(text)
        except (TypeError, ValueError):
            raise argparse.ArgumentTypeError(
                f"{text!r} is not an integer; give an integer in [{low}, {high}]"
            ) from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"{value} is out of range: give an integer in [{low}, {high}]")
        return value

    convert.__name__ = "integer"
    convert.bounds = (low, high)  # read by the tests that walk every option
    return convert


PIXEL_SIZE = int_in_range(16, 8192)
"""The argparse ``type`` of every ``--size PX`` option (a square picture of PX pixels)."""


def number_tuple(names: str):
    """An argparse ``type`` for comma-separated finite numbers, one per name in ``names`` (``"X,Y,Z"``).

    Returns a tuple of floats; a wrong count, a non-number, NaN or infinity is a usage error (exit 2).
    Its attribute ``count`` is the number of values.

    Examples
    --------
    >>> point = number_tuple("X,Y,Z")
    >>> point("1, -1.6,1")
    (1.0, -1.6, 1.0)
    >>> point("1,nan,0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: '1,nan,0' is not three finite numbers X,Y,Z
    """
    count = len(names.split(","))
    spelled = {1: "one", 2: "two", 3: "three", 4: "four"}.get(count, str(count))

    def convert(text: str) -> tuple:
        try:
            values = tuple(float(t) for t in text.split(","))
        except ValueError:
            values = ()
        if len(values) != count or not all(math.isfinite(v) for v in values):
            raise argparse.ArgumentTypeError(f"{text!r} is not {spelled} finite numbers {names}")
        return values

    convert.__name__ = names
    convert.count = count
    return convert


def nonempty_text(text: str) -> str:
    """An argparse ``type`` refusing an empty or blank value.

    Examples
    --------
    >>> nonempty_text("fields")
    'fields'
    >>> nonempty_text(" ")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: an empty value is not allowed here
    """
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty value is not allowed here")
    return text


def _finite_floats(container):
    """Make ``type=float`` options added to ``container`` (a parser or group) accept finite numbers only.

    Every float option of every command thus rejects ``nan``, ``inf`` and ``1e400`` with a usage
    error (exit 2); commands that need a range pass :func:`finite_float` or :func:`int_in_range`.
    """
    plain_argument = container.add_argument

    def add_argument(*args, **kwargs):
        if kwargs.get("type") is float:
            kwargs["type"] = finite_float()
        return plain_argument(*args, **kwargs)

    container.add_argument = add_argument
    for name in ("add_argument_group", "add_mutually_exclusive_group"):
        plain_group = getattr(container, name, None)
        if plain_group is not None:
            def add_group(*args, _plain=plain_group, **kwargs):
                return _finite_floats(_plain(*args, **kwargs))

            setattr(container, name, add_group)
    return container


def repair_choice(text: str) -> str:
    """An argparse ``type`` for ``--repair``: the value if :meth:`dhlb.mesh.RepairOptions.parse` knows it.

    Examples
    --------
    >>> repair_choice("safe,merge-vertices")
    'safe,merge-vertices'
    >>> repair_choice("splitt")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: unknown repair 'splitt': give safe, none, all or ...; did you mean 'split'?
    """
    from dhlb.errors import InvalidParameterError
    from dhlb.mesh.repair import RepairOptions

    try:
        RepairOptions.parse(text)
    except InvalidParameterError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


def backend_choice(text: str) -> str:
    """An argparse ``type`` for ``--backend``: ``auto`` or an installed backend (``available_backends``).

    An unknown name, or one whose library is not installed, is a usage error (exit 2) naming the
    backends there are (and how to install the missing one), before any work.

    Examples
    --------
    >>> backend_choice("superlu"), backend_choice("auto")
    ('superlu', 'auto')
    >>> backend_choice("bogus")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: unknown backend 'bogus'; available: [...] (or 'auto')
    """
    from dhlb.linalg.backends import _INSTALL, _REGISTRY, available_backends

    if text == "auto":
        return text
    avail = available_backends()
    if text in avail:
        return text
    if text in _REGISTRY:
        hint = "; ".join(_INSTALL.get(r, f"pip install {r}") for r in _REGISTRY[text][1])
        raise argparse.ArgumentTypeError(f"backend {text!r} is not installed ({hint}); available: {avail}")
    raise argparse.ArgumentTypeError(f"unknown backend {text!r}; available: {avail} (or 'auto')"
                                     f"{did_you_mean(text, [*avail, 'auto'])}")


def add_repair_argument(parser) -> None:
    """The ``--repair`` option of the commands that read a surface mesh (``field``, ``stripes``)."""
    parser.add_argument("--repair", type=repair_choice, default="safe", metavar="WHAT",
                        help="repair the input mesh where it is safe (default 'safe': split non-manifold vertices "
                             "and edges, merge duplicate faces, remove doubled sheets, drop faces repeating a vertex, "
                             "reorient, mollify zero-area faces; each repair is one warning line); 'none' refuses "
                             "every defect; 'all'; or a comma-separated list, e.g. safe,merge-vertices "
                             "(docs/input-meshes.md)")


def common_options(output: bool | str = True) -> argparse.ArgumentParser:
    """Parent parser with the options every subcommand accepts.

    ``output``: True for ``-o FILE`` (the result to FILE instead of stdout), a string for its own
    help, False for a command that writes nothing (then it has no ``-o``).
    """
    parent = argparse.ArgumentParser(add_help=False)
    group = parent.add_argument_group("common options")
    if output:
        group.add_argument("-o", "--output", metavar="FILE",
                           help=output if isinstance(output, str) else "write the result to FILE instead of stdout")
    group.add_argument("--json", action="store_true", help="print machine-readable JSON instead of text")
    group.add_argument("-q", "--quiet", action="store_true", help="do not print warnings")
    group.add_argument("--debug", action="store_true", help="show full tracebacks on errors")
    return parent


def add_command(subparsers, name: str, summary: str, description: str, examples: str,
                outputs=None, output: bool | str = True) -> argparse.ArgumentParser:
    """Create the parser of a subcommand with the common options and an examples epilog.

    Its ``type=float`` options accept finite numbers only (NaN/inf are usage errors). With ``outputs``
    (a command that writes result files: its :class:`~dhlb.cli._outputs.OutputSpec`, which builds on
    this module, so it is not imported here) the help of ``-o`` and the epilog state the ``-o``
    convention; ``output`` is passed to :func:`common_options` (False: the command has no ``-o``).
    """
    epilog = "examples:\n" + examples.rstrip() + "\n\n"
    if outputs is not None:
        epilog += outputs.epilog() + "\n\n"
    p = _finite_floats(subparsers.add_parser(
        name,
        help=summary,
        description=description,
        epilog=epilog + EXIT_CODES_HELP,
        parents=[common_options(output)],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    ))
    if outputs is not None:
        action = next(a for a in p._actions if "--output" in a.option_strings)
        action.metavar, action.help = "OUT", outputs.help()
    return p


EXIT_CODES_HELP = (
    "exit codes: 0 success; 2 usage error, found before any work (a bad or misspelt option, a\n"
    "value out of range, a missing input file, an unknown format or -o extension, a missing optional\n"
    "package); 1 the input or the computation fails (the message says what to change)."
)
"""The exit-code paragraph of every ``--help`` (``dhlb --help`` too)."""


did_you_mean = functools.partial(_did_you_mean, quote=False)
"""``"; did you mean X?"`` for the choice closest to a word (:func:`dhlb._deprecation.did_you_mean`, unquoted)."""


# ------------------------------------------------------------------------------ inputs and outputs
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


#: argparse destinations that name input files, checked against every output path, and what they are called
INPUT_DESTS = {"file": "the input mesh", "mesh": "the input mesh", "velocity": "the input velocity",
               "field": "the input field", "align": "the input alignment", "u_file": "the input u file"}


def input_paths(args) -> list[str]:
    """The existing input files named on the command line (positional mesh, ``--velocity FILE.npy``...).

    Examples
    --------
    >>> import argparse
    >>> input_paths(argparse.Namespace(file=__file__, output="x.json"))  # doctest: +ELLIPSIS
    ['.../_common.py']
    """
    return [path for path, _ in _named_inputs(args)]


def _named_inputs(args) -> list[tuple[str, str]]:
    out = []
    for dest, role in INPUT_DESTS.items():
        value = getattr(args, dest, None)
        if isinstance(value, str) and value and os.path.isfile(value):
            out.append((value, f"{role} {value}"))
    return out


def check_outputs(outputs, args=None, inputs=()) -> None:
    """Refuse (usage error, exit 2) to write any of ``outputs`` over an input file.

    ``inputs`` are added to the input files named in ``args`` (see :func:`input_paths`). Call it
    with every path a command will write (derived names too, e.g. ``OUT.json`` next to
    ``OUT.ply``) before the computation starts.

    Examples
    --------
    >>> import argparse
    >>> check_outputs(["other.json"], argparse.Namespace(file=__file__))
    >>> check_outputs([__file__], argparse.Namespace(file=__file__))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dhlb.cli._common.UsageError: refusing to write .../_common.py: it is the input mesh ...
    """
    from dhlb._files import refuse_overwrite
    from dhlb.errors import OverwriteError

    named = (_named_inputs(args) if args is not None else []) + [(p, f"the input file {p}") for p in inputs if p]
    try:
        refuse_overwrite(list(outputs), [])  # two outputs that are one file
        for path, role in named:
            refuse_overwrite(list(outputs), [path], role=role)
    except OverwriteError as exc:
        raise UsageError(str(exc)) from None


def usage_from(exc: Exception) -> UsageError:
    """A :class:`UsageError` with the message of ``exc`` (for parameter checks run by a command)."""
    return UsageError(str(exc))


def report_table(rows, *, timings: dict | None = None, written=None, width: int = 14) -> str:
    """The human-readable report of a command: one ``label  value`` line per row, aligned.

    Parameters
    ----------
    rows : list of (str, object)
        The report's rows (often a result's ``summary_rows()`` and the command's own).
    timings : dict, optional
        Phase → seconds, appended as a ``timings`` row.
    written : list of str, optional
        Output paths, appended as a ``wrote`` row.
    width : int
        Width of the label column.

    Returns
    -------
    str
        The lines, joined by newlines (no trailing newline).

    Examples
    --------
    >>> print(report_table([("mesh", "ball.mesh")], timings={"total": 0.5}, written=["out.json"]))
    mesh           ball.mesh
    timings        total 0.5 s
    wrote          out.json
    """
    rows = list(rows)
    if timings:
        rows.append(("timings", ", ".join(f"{k} {v:.3g} s" for k, v in timings.items())))
    if written:
        rows.append(("wrote", ", ".join(written)))
    return "\n".join(f"{key:<{width}} {value}" for key, value in rows)


def check_output_file(args) -> None:
    """Refuse (usage error, exit 2) an ``-o FILE`` that cannot be written, before the work starts.

    Its folder must exist, it must not be a folder, and it must not be an input file.

    Examples
    --------
    >>> import argparse
    >>> check_output_file(argparse.Namespace(output="no/such/folder/x.txt"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dhlb.cli._common.UsageError: cannot write no/such/folder/x.txt: the folder .../no/such/folder does not exist
    """
    out = getattr(args, "output", None)
    if not out or out == "-":
        return
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise UsageError(f"cannot write {out}: the folder {folder} does not exist")
    if os.path.isdir(out):
        raise UsageError(f"cannot write {out}: it is a folder")
    check_outputs([out], args)


def write_output(args, text: str) -> None:
    """Write ``text`` to ``args.output`` (or stdout), ending with a newline.

    The file is written atomically (a temporary file renamed at the end) and never over an input
    file (usage error); disk-full and permission errors are one-line errors naming the path.
    """
    from dhlb._files import atomic_write

    if not text.endswith("\n"):
        text += "\n"
    if args.output and args.output != "-":
        check_output_file(args)
        with atomic_write(args.output, "w", encoding="utf-8") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)


def _one_line(message) -> str:
    return " ".join(str(message).split())


def cli_warning(message, args=None) -> str:
    """A library warning in the words of the command line: one line, file rows instead of API names.

    An :class:`~dhlb.errors.UnreferencedVertexWarning` speaks of ``V`` and ``vertex_labels``; here it
    names the input file and its first unused vertex row (from the warning's ``dropped`` and ``cell``).

    Examples
    --------
    >>> import argparse
    >>> from dhlb.errors import UnreferencedVertexWarning
    >>> args = argparse.Namespace(file="meshes/bunny.obj")
    >>> cli_warning(UnreferencedVertexWarning("3 vertices of V ... rows of V", dropped=[8, 16, 18], cell="face"),
    ...             args)
    '3 vertices of bunny.obj are used by no face and were dropped (first: row 8)'
    >>> cli_warning("something   odd")
    'something odd'
    """
    if isinstance(message, UnreferencedVertexWarning) and message.dropped:
        count, first = len(message.dropped), message.dropped[0]
        source = next((p for d in ("file", "mesh") if isinstance(p := getattr(args, d, None), str) and p), None)
        where = os.path.basename(source) if source else "the mesh"
        verb = "vertex of {} is used by no {} and was dropped" if count == 1 else \
            "vertices of {} are used by no {} and were dropped"
        return f"{count} {verb.format(where, message.cell)} (first: row {first})"
    if isinstance(message, MeshRepairWarning):   # rows of the file; --repair none refuses instead
        return f"repaired the mesh: {_one_line(message)}"
    return _one_line(message)


_COMMANDS_FOR = {"volume": "a tetrahedral mesh: dhlb vortex and dhlb conformal take it",
                 "surface": "a triangle mesh: dhlb field and dhlb stripes take it"}


def cli_error(exc) -> str:
    """A library error in the words of the command line: one line, commands instead of API names.

    A :class:`~dhlb.errors.MeshParseError` for a file that holds the other kind of mesh (its
    ``found``) names the readers of the Python API; here it names the commands that take the file.

    Examples
    --------
    >>> from dhlb.errors import MeshParseError
    >>> print(cli_error(MeshParseError("12 tetrahedra", "t.mesh", found="volume")))
    t.mesh: 12 tetrahedra; this is a tetrahedral mesh: dhlb vortex and dhlb conformal take it
    """
    if isinstance(exc, MeshParseError) and exc.found in _COMMANDS_FOR:
        where = "" if exc.path is None else f"{exc.path}: " if exc.line is None else f"{exc.path}, line {exc.line}: "
        return _one_line(f"{where}{exc.reason}; this is {_COMMANDS_FOR[exc.found]}")
    return _one_line(exc)


def run_command(args) -> int:
    """Run ``args.func(args)`` and turn exceptions into one-line messages and exit codes.

    Warnings are printed once each (:func:`cli_warning`), none with ``--quiet``.
    """
    prog = f"dhlb {args.command}"
    debug = getattr(args, "debug", False)
    shown: set[str] = set()

    def show_warning(message, category, filename, lineno, file=None, line=None):
        text = cli_warning(message, args)
        if text not in shown:  # the same warning from two layers (or two calls) is printed once
            shown.add(text)
            print(f"{prog}: warning: {text}", file=sys.stderr)

    try:
        output = getattr(args, "output", None)
        if isinstance(output, str) and output not in ("", "-"):
            check_outputs([output], args)  # never replace an input file (before any work)
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
        print(f"{prog}: error: {cli_error(exc)}", file=sys.stderr)
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
