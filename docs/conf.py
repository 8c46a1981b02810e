"""Sphinx configuration for the dhlb documentation."""
import dhlb

project = "dhlb"
author = "dhlb developers"
release = dhlb.__version__
extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
napoleon_numpy_docstring = True
napoleon_google_docstring = False
autodoc_member_order = "bysource"
autodoc_typehints = "description"
exclude_patterns = ["_build", "_generated"]  # _generated: includes written at build time
html_theme = "alabaster"
# ref.python: "more than one target found" for words of numpydoc type lines that Sphinx turns into
# cross-references, e.g. the ``n`` of ``(n, 3) float array`` against every attribute named n
suppress_warnings = ["myst.xref_missing", "ref.python"]


# --- `dhlb --help` in the docs (docs/api/cli.md), generated from the parser at build time ---------
def _dhlb_parsers():
    """``[("dhlb", parser), ("dhlb info", subparser), ...]`` in the order of ``dhlb --help``."""
    import argparse

    from dhlb.cli import build_parser

    parser = build_parser()
    out = [("dhlb", parser)]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            out += [(f"dhlb {name}", sub) for name, sub in action.choices.items()]
    return out


def _help_text(parser) -> str:
    import os

    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"  # argparse wraps to the terminal width; fix it for reproducible docs
    try:
        return parser.format_help()
    finally:
        if old is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = old


# --- the layer diagram of docs/architecture.md, generated from the import graph at build time -------
def _generate_layers(app):
    """Write ``docs/_generated/architecture.svg`` and ``layers.md`` (``docs/_layers.py``) from the code."""
    import importlib.util
    import os
    import sys

    path = os.path.join(app.confdir, "_layers.py")
    spec = importlib.util.spec_from_file_location("_dhlb_docs_layers", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    module.generate()  # the source tree next to docs/ (dhlb/), into docs/_generated/


def setup(app):
    from docutils import nodes
    from docutils.parsers.rst import Directive

    class DhlbHelp(Directive):
        """``dhlb-help``: the ``--help`` text of ``dhlb`` or of its commands.

        No argument: ``dhlb`` itself; a command name: that command; ``*``: every command, each
        under a rubric.
        """

        optional_arguments = 1

        def run(self):
            which = self.arguments[0] if self.arguments else None
            parsers = _dhlb_parsers()
            if which is None:
                parsers = parsers[:1]
            elif which != "*":
                parsers = [p for p in parsers if p[0] == f"dhlb {which}"]
                if not parsers:
                    raise self.error(f"dhlb has no command {which!r}")
            else:
                parsers = parsers[1:]
            result = []
            for name, parser in parsers:
                text = _help_text(parser)
                if which == "*":
                    result.append(nodes.rubric(text=name))
                result.append(nodes.literal_block(text, text))
            return result

    app.add_directive("dhlb-help", DhlbHelp)
    app.connect("builder-inited", _generate_layers)
    return {"parallel_read_safe": True}
