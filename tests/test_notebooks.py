"""Every teaching notebook in notebooks/ runs in the environment its first cell names, shows a picture (a PNG or
an interactive 3-D view), prints no warning and writes nothing beside itself.

The environment is the line ``pip install .`` or ``pip install ".[extra,...]"`` (what works in a clone of the
repository, issue 42) of the first (markdown) cell, plus the Jupyter kernel. The notebook runs with every
other installed distribution hidden from it
(``sys.modules[name] = None``: ``import`` raises ModuleNotFoundError and ``importlib.util.find_spec`` returns
None, as if it were not installed) and its entry points unlisted (``importlib.metadata.entry_points(group=...)``:
a plugin such as trio's hook for hypothesis is not loaded), so a notebook that needs an extra it does not name
fails here.
"""
import re
import shutil
import sys
from importlib import metadata
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

try:
    import tomllib
except ImportError:  # Python 3.10: pytest's own dependency
    import tomli as tomllib

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
ENVIRONMENT = re.compile(r"""pip install (?:\.|"\.\[([\w,-]+)\]")(?=[\s`]|$)""")
KERNEL = ["ipykernel"]  # what runs the cells (with its dependencies: IPython, matplotlib-inline, ...)


def _environment(nb):
    """The extras named by the first cell's ``pip install`` line."""
    first = nb.cells[0]
    assert first.cell_type == "markdown", "the first cell must be markdown naming the environment"
    named = ENVIRONMENT.findall(first.source)
    assert len(named) == 1, 'the first cell must name its environment once: pip install . / ".[extra]"'
    return [e for e in named[0].split(",") if e]


def _requirements(extras):
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    optional = project["optional-dependencies"]
    unknown = [e for e in extras if e not in optional]
    assert not unknown, f"the first cell names extras that pyproject.toml does not define: {unknown}"
    return [Requirement(r) for r in project["dependencies"] + [r for e in extras for r in optional[e]]]


def _closure(names):
    """Canonical names of the installed distributions ``names`` and everything they require."""
    seen, todo = set(), [canonicalize_name(n) for n in names]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        try:
            requires = metadata.requires(name) or []
        except metadata.PackageNotFoundError:
            continue
        for text in requires:
            req = Requirement(text)
            if req.marker is None or req.marker.evaluate({"extra": ""}):
                todo.append(canonicalize_name(req.name))
    return seen


def _hidden(extras):
    """Top-level modules and canonical names of the installed distributions outside the environment and the kernel."""
    requirements = _requirements(extras)
    missing = [r.name for r in requirements if not _installed(r.name)]
    if missing:
        pytest.skip(f"the notebook's environment dhlb[{','.join(extras)}] is not installed here (missing {missing})")
    allowed = _closure([r.name for r in requirements] + KERNEL)
    modules = sorted(
        module
        for module, dists in metadata.packages_distributions().items()
        if module.isidentifier() and module != "dhlb" and module not in sys.stdlib_module_names
        and not any(canonicalize_name(d) in allowed for d in dists)
    )
    dists = sorted({canonicalize_name(d.metadata["Name"]) for d in metadata.distributions()} - allowed - {"dhlb"})
    return modules, dists


# the first cell of the run: hide the modules and the entry points of the distributions outside the environment
HIDE = """\
import importlib.metadata
import re
import sys

sys.modules.update(dict.fromkeys(m for m in {modules!r} if m not in sys.modules))
_entry_points = importlib.metadata.entry_points


def _visible_entry_points(**params):
    found = _entry_points(**params)
    if not params:
        return found
    return importlib.metadata.EntryPoints(
        e for e in found if e.dist is None or re.sub(r"[-_.]+", "-", e.dist.name).lower() not in {dists!r})


importlib.metadata.entry_points = _visible_entry_points
"""


def _installed(name):
    try:
        metadata.distribution(name)
    except metadata.PackageNotFoundError:
        return False
    return True


WEB_VIEW = "dhlb-web-view"  # the class of the div of an interactive view (dhlb.render.web.notebook_view)
FIRST_3D = "06_direction_fields"  # the first notebook with a 3-D result: it must show it interactively


def _displayed(nb):
    return [o.get("data", {}) for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
            if o.get("output_type") in ("display_data", "execute_result")]


def _web_views(nb):
    return [d for d in _displayed(nb) if WEB_VIEW in d.get("text/html", "")]


def _pictures(nb):
    """PNG pictures and interactive views."""
    return [d for d in _displayed(nb) if "image/png" in d or WEB_VIEW in d.get("text/html", "")]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_in_its_environment_shows_a_picture_and_writes_nothing_beside_itself(path, tmp_path, monkeypatch):
    # the kernel draws as Jupyter does (inline PNGs), not into the suite's Agg backend
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    monkeypatch.delenv("DHLB_WEB_SCRIPT", raising=False)  # interactive views carry plotly's script, as in Jupyter
    nb = nbformat.read(path, as_version=4)
    hidden, dists = _hidden(_environment(nb))
    assert "pytest" in hidden  # the test can fail: the suite's own tools are not the notebook's environment
    here = tmp_path / "notebooks"  # a fresh copy, run where it lies, as a reader does
    here.mkdir()
    shutil.copy(path, here / path.name)
    hide = nbformat.v4.new_code_cell(HIDE.format(modules=hidden, dists=set(dists)))
    nb.cells.insert(0, hide)
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(here)}}).execute()
    nb.cells.remove(hide)
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors
    warned = [o.text for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.output_type == "stream" and o.name == "stderr" and "Warning" in o.text]
    assert not warned, f"the notebook printed warnings (a deprecated call? catch and explain an intended one): {warned}"
    assert _pictures(nb), "the notebook shows no picture (no image/png output, no interactive view)"
    if path.stem == FIRST_3D:
        assert _web_views(nb), "the first notebook with a 3-D result shows no interactive view (backend='web')"
    written = sorted(p.name for p in here.iterdir() if p.name != path.name)
    assert not written, f"the notebook wrote {written} beside itself; write into a temporary or output folder"
