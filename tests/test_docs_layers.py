"""The layer diagram of docs/architecture.md (docs/_layers.py): layers, violations, cycles, the SVG and the table."""

from __future__ import annotations

import doctest
import importlib.util
import pathlib
import sys
import xml.etree.ElementTree as ET

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def layers():
    spec = importlib.util.spec_from_file_location("_dhlb_docs_layers", REPO / "docs" / "_layers.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    yield module
    del sys.modules[spec.name]


def write_package(root: pathlib.Path, files: dict) -> pathlib.Path:
    """A package ``root/pkg`` with ``files`` (relative path → source); every folder gets an ``__init__.py``."""
    pkg = root / "pkg"
    for rel, text in {"__init__.py": '"""The root."""\n', **files}.items():
        path = pkg / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        for parent in path.relative_to(pkg).parents:
            (pkg / parent / "__init__.py").touch()
        path.write_text(text, encoding="utf-8")
    return pkg


def svg_texts(svg: str) -> set:
    ns = "{http://www.w3.org/2000/svg}"
    return {t.text for t in ET.fromstring(svg).iter(f"{ns}text")}


def test_a_chain_with_an_upward_import(layers, tmp_path):
    pkg = write_package(tmp_path, {
        "a/__init__.py": "from pkg.b import f\n",
        "a/more.py": "import numpy\nimport pkg.b.g\n",
        "b/__init__.py": "from ..c import h as f\n",
        "c/__init__.py": "def h():\n    from pkg.a import more  # the upward import\n    return more\n",
    })
    g = layers.scan(pkg)
    assert g.layer == {"a": 2, "b": 1, "c": 0}
    assert set(g.edges) == {("a", "b"), ("b", "c"), ("c", "a")}
    assert g.edges[("a", "b")].imports == 2 and g.edges[("c", "a")].module_level == 0
    assert g.edges[("c", "a")].first == "pkg/c/__init__.py:2"
    assert list(g.violations) == [("c", "a")]
    assert "closes the import cycle c → a → b → c" in g.violations[("c", "a")]
    assert g.cycles == [["a", "b", "c"]]
    assert (g.modules, g.lines) == ({"a": 2, "b": 1, "c": 1}, {"a": 3, "b": 1, "c": 3})
    svg = layers.to_svg(g)
    assert {"a", "b", "c"} <= svg_texts(svg)
    assert svg.count(f'stroke="{layers.RED}"') == 1 + 3  # the upward arrow, the three boxes of the cycle
    table = layers.to_markdown(g)
    assert "| `pkg.c` | 0 | 1 | 3 | `a` ↑ |" in table
    assert "| `pkg.a` | 2 | 2 | 3 | `b` |" in table


def test_without_the_upward_import_there_is_no_violation(layers, tmp_path):
    pkg = write_package(tmp_path, {"a.py": "import pkg.b\n", "b/__init__.py": "from pkg import c\n",
                                   "c/__init__.py": "from pkg import __version__\n"})
    g = layers.scan(pkg)
    assert g.layer == {"a": 2, "b": 1, "c": 0}
    assert not g.violations and not g.cycles
    assert f'stroke="{layers.RED}"' not in layers.to_svg(g)


def test_type_checking_imports_do_not_count(layers, tmp_path):
    pkg = write_package(tmp_path, {
        "a/__init__.py": "",
        "b/__init__.py": ("import typing\nfrom typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                          "    from pkg.a import X\nif typing.TYPE_CHECKING:\n    import pkg.a\n"
                          "else:\n    import pkg.c\n"),
        "c/__init__.py": "",
    })
    g = layers.scan(pkg)
    assert set(g.edges) == {("b", "c")}


def test_deprecated_aliases(layers, tmp_path):
    pkg = write_package(tmp_path, {
        "old/__init__.py": '"""Deprecated alias package (pkg 0.2; removed in 0.3).\n\nMoved to pkg.new."""\n'
                           "from pkg.new import f\n",
        "new/__init__.py": '"""The new home.\n\nIts docstring may say deprecated on a later line."""\n'
                           "import pkg.base\n",
        "base/__init__.py": "",
        "user.py": "from pkg.old import f\n",
    })
    g = layers.scan(pkg)
    assert g.deprecated == {"old"}
    assert g.layer["base"] == 0 and g.layer["new"] == 1 and g.layer["old"] == 2 == g.top + 1
    assert g.violations == {("user", "old"): "imports a deprecated alias"}
    assert layers.scan(pkg, deprecated={"old", "new", "nothing"}).deprecated == {"old", "new"}
    assert "| `pkg.old` | alias |" in layers.to_markdown(g)


def test_strongly_connected_components(layers):
    assert layers.strongly_connected("abcde", [("a", "b"), ("b", "a"), ("b", "c"), ("c", "d"), ("d", "c")]) == [
        ["a", "b"], ["c", "d"], ["e"]]


def test_the_real_tree(layers, tmp_path):
    root = REPO / "dhlb"
    packages = {p.name.removesuffix(".py") for p in root.iterdir()
                if (p.is_dir() and (p / "__init__.py").exists()) or (p.suffix == ".py" and p.name != "__init__.py")}
    g = layers.generate(str(root), str(tmp_path))
    assert set(g.modules) == set(g.layer) == packages
    assert sum(g.modules.values()) == sum(1 for p in root.rglob("*.py")) - 1  # all but dhlb/__init__.py
    assert g.layer["errors"] == 0 and not g.imports("errors")
    for (u, v) in set(g.edges) - set(g.violations):
        assert g.layer[u] > g.layer[v] or u in g.deprecated
    svg = (tmp_path / "architecture.svg").read_text(encoding="utf-8")
    assert packages <= svg_texts(svg)
    table = (tmp_path / "layers.md").read_text(encoding="utf-8")
    assert all(f"| `dhlb.{p}` |" in table for p in packages)


def test_the_examples_in_the_docstrings(layers):
    result = doctest.testmod(layers, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 4 and not result.failed
