"""Sphinx configuration for the dhlb documentation."""
import os

import dhlb

# the teaching notebooks are executed at build time (myst-nb); their kernels inherit this environment:
# interactive views without plotly's script (every page loads it once, below), figures drawn as in Jupyter
os.environ["DHLB_WEB_SCRIPT"] = "page"
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"

project = "dhlb"
author = "dhlb developers"
release = dhlb.__version__
extensions = [
    "myst_nb",  # MyST markdown (it includes myst-parser) and the executed notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]
source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb", ".rst": "restructuredtext"}
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
napoleon_numpy_docstring = True
napoleon_google_docstring = False
autodoc_member_order = "bysource"
autodoc_typehints = "description"
exclude_patterns = ["_build", "_generated"]  # _generated: includes written at build time
html_theme = "alabaster"
# the notebooks (copied from ../notebooks by _copy_notebooks) run on every build, so the docs show what the
# code does now (jupyter-cache keys on the notebook's text only, not on dhlb); a failing cell fails the build.
# DHLB_DOCS_EXECUTE=cache (or off) for quicker local rebuilds
nb_execution_mode = os.environ.get("DHLB_DOCS_EXECUTE", "force")
nb_execution_timeout = 900
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_ipywidgets_js = {}  # no require.js (an AMD loader would swallow plotly's script); the notebooks use no widgets
# plotly's script, once per page before any view (copied from the installed plotly by _write_plotlyjs)
html_static_path = ["_generated/static", "_mathjax"]
# the mathematics renders without a network (issue 42): MathJax 3.2.2's self-contained SVG build (every TeX
# extension and the font's glyphs in one file, Apache-2.0, docs/_mathjax/LICENSE), not a CDN's script
mathjax_path = "tex-svg-full.js"
html_js_files = [(None, {"body": "window.PlotlyConfig = {MathJaxConfig: 'local'};"}), "plotly.min.js"]
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


# --- the teaching notebooks (../notebooks) and plotly's script, put in place before Sphinx reads -------
def _copy_notebooks(app, config):
    """Copy ``../notebooks/*.ipynb`` into ``docs/notebooks/`` (Sphinx reads documents under docs/ only).

    A copy is rewritten only when its text changes (Sphinx re-reads by modification time); copies of
    notebooks that no longer exist are removed. Links into the documentation (``../docs/x.md``) are
    made relative to the copy (``../x.md``).
    """
    import glob
    import json

    source = os.path.join(app.confdir, os.pardir, "notebooks")
    target = os.path.join(app.confdir, "notebooks")
    os.makedirs(target, exist_ok=True)
    names = set()
    for path in sorted(glob.glob(os.path.join(source, "*.ipynb"))):
        name = os.path.basename(path)
        names.add(name)
        with open(path, encoding="utf-8") as fh:
            nb = json.load(fh)
        for cell in nb["cells"]:
            if cell["cell_type"] == "markdown":
                text = "".join(cell["source"]).replace("](../docs/", "](../")
                cell["source"] = text.splitlines(keepends=True)
        text = json.dumps(nb, indent=1, ensure_ascii=False) + "\n"
        out = os.path.join(target, name)
        if os.path.isfile(out):
            with open(out, encoding="utf-8") as fh:
                if fh.read() == text:
                    continue
        with open(out, "w", encoding="utf-8") as fh:
            fh.write(text)
    for stale in set(os.listdir(target)) - names:
        if stale.endswith(".ipynb"):
            os.remove(os.path.join(target, stale))


def _write_plotlyjs(app, config):
    """Copy plotly's script from the installed plotly into ``docs/_generated/static/`` (``html_static_path``)."""
    from dhlb.render.web import write_plotlyjs

    folder = os.path.join(app.confdir, "_generated", "static")
    os.makedirs(folder, exist_ok=True)
    write_plotlyjs(folder)


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
    # before the html builder checks html_static_path (config-inited, priority 500) and before Sphinx reads
    app.connect("config-inited", _copy_notebooks, priority=100)
    app.connect("config-inited", _write_plotlyjs, priority=100)
    return {"parallel_read_safe": True}
