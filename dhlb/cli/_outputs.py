"""``-o`` of the commands that write results: one convention, checked before any work.

A base name OUT writes the command's default set (:class:`OutputSpec`), a name with an extension writes
that one format; unknown extensions, missing optional packages and outputs over inputs are usage errors
(exit 2) found by :func:`output_plan` before any work; the files are written under temporary names and
appear together at the end (:meth:`OutputPlan.writing`).
"""

from __future__ import annotations

import contextlib
import importlib
import os
import re

from dhlb._install import install_hint
from dhlb.cli._common import UsageError, check_outputs

__all__ = ["EXTRAS", "OutputPlan", "OutputSpec", "output_plan", "require_extra"]

EXTRAS = {
    "meshio": install_hint("meshio", "meshio"),
    "matplotlib": "pip install matplotlib",
    "polyscope": install_hint("polyscope", "view"),
}
"""Optional packages the commands need for some outputs, and how to install them."""


def require_extra(module: str, purpose: str, hint: str = "") -> None:
    """Raise :class:`UsageError` (exit 2, before any work) when the optional package ``module`` is missing.

    Parameters
    ----------
    module : str
        A key of :data:`EXTRAS` (``meshio``, ``matplotlib``, ``polyscope``).
    purpose : str
        What needs it (``"writing out.vtu"``), the start of the message.
    hint : str
        Appended to the install command (e.g. ``" or add --no-png"``).

    Raises
    ------
    UsageError
        ``module`` cannot be imported; the message names the install command.

    Examples
    --------
    >>> require_extra("matplotlib", "writing out.png")
    >>> require_extra("no_such_module_dhlb", "writing out.x")
    Traceback (most recent call last):
    ...
    KeyError: 'no_such_module_dhlb'
    """
    install = EXTRAS[module]
    try:
        importlib.import_module(module)
    except ImportError:
        raise UsageError(f"{purpose} needs {module}, which is not installed: {install}{hint}") from None


_EXTENSION = re.compile(r"\.[A-Za-z][A-Za-z0-9]{0,7}")


def _extension(name: str) -> str:
    """The extension of a file name (``.vtu``), or ``""`` for a base name (``spot-s0.5`` has none)."""
    ext = os.path.splitext(name)[1]
    return ext if _EXTENSION.fullmatch(ext) else ""


class OutputSpec:
    """What ``-o`` of one command writes: its default set and the formats a name with an extension asks for.

    Parameters
    ----------
    command : str
        The command's name (for messages).
    default : sequence of str
        The suffixes written for a base name OUT, in order (``".ply"``, ``"-isolines.obj"``, ...).
    formats : dict
        Extension → what the file holds; the extensions ``-o`` accepts (each writes that file only).
    companions : dict, optional
        Suffix → suffixes always written with it (a stripe OBJ's ``.json`` sidecar).
    switches : dict, optional
        Suffix → the flag's ``dest`` that turns it off (``{".png": "no_png"}``).
    extras : dict, optional
        Extension → the optional package (key of :data:`EXTRAS`) its writer needs.

    Examples
    --------
    >>> spec = OutputSpec("field", (".ply", ".json"), {".ply": "mesh", ".json": "summary", ".vtu": "ParaView"})
    >>> spec.help()
    'a base name OUT writes OUT.ply, OUT.json; a name ending in .ply, .json or .vtu writes that file only'
    """

    def __init__(self, command: str, default, formats: dict, *, companions: dict | None = None,
                 switches: dict | None = None, extras: dict | None = None):
        self.command = command
        self.default = tuple(default)
        self.formats = dict(formats)
        self.companions = dict(companions or {})
        self.switches = dict(switches or {})
        self.extras = {".vtu": "meshio", ".png": "matplotlib"} if extras is None else dict(extras)

    def _exts(self) -> str:
        exts = list(self.formats)
        return ", ".join(exts[:-1]) + f" or {exts[-1]}" if len(exts) > 1 else exts[0]

    def help(self) -> str:
        """The help line of ``-o``."""
        with_ = "".join(f" ({e} with {', '.join(self.companions[e])})" for e in self.formats if e in self.companions)
        return (f"a base name OUT writes {', '.join('OUT' + s for s in self.default)}; "
                f"a name ending in {self._exts()} writes that file only{with_}")

    def epilog(self) -> str:
        """The paragraph of ``--help`` that states the ``-o`` convention."""
        width = max(len(e) for e in self.formats)
        lines = [f"output (-o): a base name OUT writes {', '.join('OUT' + s for s in self.default)};",
                 "a name with an extension writes that format only:"]
        for ext, what in self.formats.items():
            need = self.extras.get(ext)
            notes = [f"with OUT{c}" for c in self.companions.get(ext, ())]
            notes += [f"needs {need}"] if need and need != "matplotlib" else []
            lines.append(f"  OUT{ext:<{width}}  {what}" + (f" ({'; '.join(notes)})" if notes else ""))
        lines += ["any other extension is a usage error (exit 2) found before any work, like a missing",
                  "optional package. The files are written under temporary names and appear together",
                  "at the end: after a failure none of them is left."]
        return "\n".join(lines)


class OutputPlan:
    """The files one run writes (from :func:`output_plan`), written together by :meth:`writing`.

    Attributes
    ----------
    base : str or None
        The output path without extension; None when nothing is written.
    suffixes : tuple of str
        What is written: ``base + suffix`` for each.
    explicit : str or None
        The extension ``-o`` named, or None for a base name (the default set).
    written : list of str
        The files in place after :meth:`writing` ended.
    """

    def __init__(self, base: str | None, suffixes=(), explicit: str | None = None):
        self.base, self.suffixes, self.explicit = base, tuple(suffixes), explicit
        self.written: list[str] = []

    def __bool__(self) -> bool:
        return bool(self.suffixes)

    def wants(self, suffix: str) -> bool:
        """Whether ``base + suffix`` is written."""
        return suffix in self.suffixes

    def path(self, suffix: str) -> str:
        """The final path ``base + suffix``."""
        return f"{self.base}{suffix}"

    @property
    def paths(self) -> list[str]:
        """The final paths of every file of the plan."""
        return [self.path(s) for s in self.suffixes]

    @contextlib.contextmanager
    def writing(self):
        """Write the files into a hidden folder beside the targets; move them into place at the end.

        Yields a function ``stage(suffix) -> path`` giving the temporary path to write ``base + suffix``
        to. When the block ends normally the planned files are renamed onto their targets (others a
        writer left are dropped) and listed in :attr:`written`; after an error or an interrupt the
        folder is removed and no target is touched.

        Examples
        --------
        >>> import os, tempfile
        >>> with tempfile.TemporaryDirectory() as d:
        ...     plan = OutputPlan(os.path.join(d, "out"), (".txt", ".json"))
        ...     try:
        ...         with plan.writing() as stage:
        ...             _ = open(stage(".txt"), "w").write("half")
        ...             raise KeyboardInterrupt
        ...     except KeyboardInterrupt:
        ...         pass
        ...     before = os.listdir(d)
        ...     with plan.writing() as stage:
        ...         for s in (".txt", ".json"):
        ...             _ = open(stage(s), "w").write("x")
        ...     print(before, sorted(os.listdir(d)), len(plan.written))
        [] ['out.json', 'out.txt'] 2
        """
        import shutil
        import tempfile

        from dhlb._files import output_error

        folder, name = os.path.split(os.path.abspath(self.path("")))
        try:
            tmp = tempfile.mkdtemp(prefix=f".{name}.", suffix=".dhlb-tmp", dir=folder)
        except OSError as exc:
            raise output_error(self.path(self.suffixes[0] if self.suffixes else ""), exc) from None
        moved: list[str] = []
        try:
            yield lambda suffix: os.path.join(tmp, name + suffix)
            for suffix in self.suffixes:
                src = os.path.join(tmp, name + suffix)
                if os.path.isfile(src):
                    try:
                        os.replace(src, self.path(suffix))
                    except OSError as exc:
                        raise output_error(self.path(suffix), exc) from None
                    moved.append(self.path(suffix))
        except BaseException:
            for path in moved:  # all or nothing
                with contextlib.suppress(OSError):
                    os.unlink(path)
            raise
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        self.written = moved


def output_plan(spec: OutputSpec, args, *, default_base: str | None = None, also: dict | None = None,
                inputs=()) -> OutputPlan:
    """The files ``-o`` asks for, checked before any work; see :class:`OutputSpec`.

    Parameters
    ----------
    spec : OutputSpec
        What the command writes.
    args : argparse.Namespace
        The parsed command line (``output``, the ``switches`` flags, the input files).
    default_base : str, optional
        The base name used without ``-o`` (None: nothing is written).
    also : dict, optional
        Suffix → suffixes written with it in this run (``--orthogonal``: the second pattern).
    inputs : sequence of str, optional
        Input files beyond those :func:`input_paths` finds (never overwritten).

    Returns
    -------
    OutputPlan

    Raises
    ------
    UsageError
        An unknown extension, a format a flag turns off, a missing folder, an output that is an input
        file or a folder, or a missing optional package its writer needs (all exit 2).

    Examples
    --------
    >>> import argparse
    >>> spec = OutputSpec("field", (".ply", ".json", ".png"), {".ply": "mesh", ".json": "summary", ".png": "picture"},
    ...                   switches={".png": "no_png"})
    >>> output_plan(spec, argparse.Namespace(output="out", no_png=True)).paths
    ['out.ply', 'out.json']
    >>> output_plan(spec, argparse.Namespace(output="out.png", no_png=False)).paths
    ['out.png']
    >>> output_plan(spec, argparse.Namespace(output="out.txt", no_png=False))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dhlb.cli._common.UsageError: -o out.txt: dhlb field does not write .txt files; give a base name OUT ...
    """
    out = getattr(args, "output", None)
    if not out or out == "-":
        if default_base is None:
            return OutputPlan(None)
        out = default_base
    name = os.path.basename(out)
    if not name or name in (".", ".."):
        raise UsageError(f"-o {out}: give a base name such as {os.path.join(out, 'result')}, not a folder")
    ext = _extension(name)
    if ext:
        if ext.lower() not in spec.formats:
            raise UsageError(f"-o {out}: dhlb {spec.command} does not write {ext} files; give a base name OUT "
                             f"(writes {', '.join('OUT' + s for s in spec.default)}) or a name ending in "
                             f"{spec._exts()}")
        ext = ext.lower()
        flag = spec.switches.get(ext)
        if flag and getattr(args, flag, False):
            raise UsageError(f"-o {out} asks for the {ext} file that --{flag.replace('_', '-')} turns off")
        base, wanted = out[: -len(ext)], [ext]
    else:
        base = out
        wanted = [s for s in spec.default if not getattr(args, spec.switches.get(s, ""), False)]
    suffixes: list[str] = []
    for s in wanted:
        for t in (s, *spec.companions.get(s, ()), *(also or {}).get(s, ())):
            if t not in suffixes:
                suffixes.append(t)
    plan = OutputPlan(base, suffixes, ext or None)
    folder = os.path.dirname(os.path.abspath(base))
    if not os.path.isdir(folder):
        raise UsageError(f"cannot write {out}: the folder {folder} does not exist")
    for path in plan.paths:
        if os.path.isdir(path):
            raise UsageError(f"cannot write {path}: it is a folder")
    check_outputs(plan.paths, args, inputs=[p for p in inputs if p])
    for s in suffixes:
        module = spec.extras.get(_extension("x" + s).lower())
        if module:
            flag = spec.switches.get(s)
            hint = f", or add --{flag.replace('_', '-')}" if flag and not ext else ""
            require_extra(module, f"writing {plan.path(s)}", hint)
    return plan
