"""The layering of the package, written once and enforced: imports point down only, applications are independent.

Each top-level package of ``dhlb`` has a rank; a module may import (at any place in the file, also
inside functions) only packages of a lower rank, or its own. Applications share a rank and must not
import each other. Results reach the io and render layers above them through the entry-point group
``dhlb.plugins`` (:mod:`dhlb._result`), and deprecated import paths resolve by name
(:mod:`dhlb._deprecation`): neither is an import edge. ``KNOWN`` lists imports that break the rule, each
with its reason; it is empty, and a listed import that is gone fails too, so the list cannot go stale.
The same rule is written as import-linter contracts in ``pyproject.toml`` (run by :func:`test_import_linter_contracts`
and in CI).
"""

from __future__ import annotations

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1] / "dhlb"

RANK = {
    # layer 0, leaves: exceptions, progress bars, result base, deprecation shims, atomic files, argument coercion
    "errors": 0,
    "_progress": 0.5, "_display": 0.5, "_result": 0.5, "_deprecation": 0.5, "_files": 0.5, "_coerce": 0.5,
    "_phases": 0.5,
    "_memory_errors": 0.5, "_caches": 0.5, "_install": 0.5,
    "topology": 1,
    "forms": 2, "examples": 2,                    # examples: named complexes, built on topology only
    "bundles": 3,
    "geometry": 4,                                # Euclidean complexes
    "linalg": 5,                                  # sparse eigen/linear solvers and their backends
    "fem": 6,                                     # Θ/Λ/Ξ elements, connection Laplacians
    "mesh": 7,                                    # the one place that validates and describes meshes
    "strategies": 7.5,                            # hypothesis strategies (test support)
    "fields": 8, "stripes": 8, "vortex": 8, "conformal": 8,   # applications, mutually independent
    "io": 9,                                      # every reader and writer
    "render": 10,                                 # pictures, the viewer
    "cli": 11, "__main__": 12,
    "surface": 13, "volume": 13, "commands": 13,  # deprecated alias packages (no static imports)
}
APPLICATIONS = {"fields", "stripes", "vortex", "conformal"}

KNOWN = {
}



def imports_of(path: pathlib.Path) -> set[str]:
    """Top-level ``dhlb`` packages imported anywhere in the file (absolute imports)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names = ([node.module] if isinstance(node, ast.ImportFrom) and node.module and node.level == 0
                 else [a.name for a in node.names] if isinstance(node, ast.Import) else [])
        for name in names:
            parts = name.split(".")
            if parts[0] == "dhlb" and len(parts) > 1:
                out.add(parts[1])
            if isinstance(node, ast.ImportFrom) and node.module == "dhlb":
                out.update(a.name for a in node.names)
    return out


def violations(edges) -> set[tuple[str, str]]:
    """The (importer, imported) pairs that point up or across applications."""
    bad = set()
    for src, dst in edges:
        if src == dst or dst not in RANK or src not in RANK:
            continue
        if RANK[dst] > RANK[src] or (RANK[dst] == RANK[src] and (src in APPLICATIONS or dst in APPLICATIONS
                                                                  or RANK[src] in (0.5, 2))):
            bad.add((src, dst))
    return bad


def package_edges() -> set[tuple[str, str]]:
    edges = set()
    for path in ROOT.rglob("*.py"):
        rel = path.relative_to(ROOT).parts
        src = rel[0].removesuffix(".py")
        if src == "__init__":
            continue
        edges |= {(src, dst) for dst in imports_of(path)}
    return edges


def test_every_package_has_a_rank():
    packages = {p.name.removesuffix(".py") for p in ROOT.iterdir()
                if (p.is_dir() and (p / "__init__.py").exists()) or (p.suffix == ".py" and p.name != "__init__.py")}
    assert packages <= set(RANK), f"give these a layer in RANK: {sorted(packages - set(RANK))}"


def test_imports_point_down_and_applications_are_independent():
    bad = violations(package_edges())
    new = {e: "?" for e in bad if e not in KNOWN}
    assert not new, f"imports against the layering (import from a lower layer only): {sorted(new)}"
    fixed = sorted(set(KNOWN) - bad)
    assert not fixed, f"these known exceptions are gone: remove them from KNOWN: {fixed}"


@pytest.mark.parametrize(("src", "code"), [("topology", "from dhlb.fem import mass_matrix"),
                                           ("fields", "import dhlb.vortex.pipeline"),
                                           ("geometry", "def f():\n    from dhlb.linalg import solve")])
def test_an_upward_import_is_caught(tmp_path, src, code):
    """The check can fail: a deliberately added upward (or sideways) import is reported."""
    path = tmp_path / "mod.py"
    path.write_text(code, encoding="utf-8")
    assert violations({(src, dst) for dst in imports_of(path)})


def test_import_linter_contracts():
    """The import-linter contracts of pyproject.toml (layers, independent applications, no circles) are kept."""
    pytest.importorskip("importlinter")
    import subprocess
    import sys

    root = ROOT.parent
    proc = subprocess.run([sys.executable, "-c", "from importlinter.cli import lint_imports_command; "
                           "lint_imports_command()", "--no-cache"], cwd=root, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-2000:]
    assert "Contracts: 3 kept, 0 broken." in proc.stdout
