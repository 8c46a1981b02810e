"""The documentation works without a network (issue 42, point 8): its mathematics comes from the build.

``docs/_check_views.py`` opens the built pages in headless Chromium with host-name resolution off and
requires every formula typeset (run by ``.ci/run`` after the docs build); here, without a browser, the
configuration: MathJax is a local file of the build, not a CDN's script.
"""

from __future__ import annotations

import ast
import pathlib

REPO = pathlib.Path(__file__).resolve().parents[1]


def _assignments() -> dict:
    tree = ast.parse((REPO / "docs" / "conf.py").read_text(encoding="utf-8"))
    return {t.id: node.value for node in tree.body if isinstance(node, ast.Assign)
            for t in node.targets if isinstance(t, ast.Name)}


def test_mathjax_is_a_file_of_the_build_not_a_cdn():
    conf = _assignments()
    assert "mathjax_path" in conf, "docs/conf.py leaves MathJax to Sphinx's default, a CDN"
    path = ast.literal_eval(conf["mathjax_path"])
    assert "://" not in path and not path.startswith("//")
    static = ast.literal_eval(conf["html_static_path"])
    found = [REPO / "docs" / d / path for d in static if (REPO / "docs" / d / path).is_file()]
    assert found, f"{path} is in none of html_static_path {static}"
    text = found[0].read_text(encoding="utf-8", errors="replace")
    assert len(text) > 1_000_000 and "cdn.jsdelivr" not in text[:2000]    # the whole MathJax, self-contained
    assert (found[0].parent / "LICENSE").is_file()


def test_the_view_check_runs_with_the_network_off():
    source = (REPO / "docs" / "_check_views.py").read_text(encoding="utf-8")
    assert "--host-resolver-rules=MAP * ~NOTFOUND" in source and "def check_math" in source


def test_the_index_takes_its_layer_table_from_the_readme():
    """Issue 42, point 8: docs/index.md listed 6 layers without conformal; now it includes the README's table."""
    index = (REPO / "docs" / "index.md").read_text(encoding="utf-8")
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    start, end = "Imports point down this list only.", "The rule is enforced twice"
    assert f"```{{include}} ../README.md\n:start-after: \"{start}\"\n:end-before: \"{end}\"\n```" in index
    assert readme.count(start) == 1 and readme.count(end) == 1
    table = readme.split(start)[1].split(end)[0]
    rows = [line for line in table.splitlines() if line.startswith("| ") and "---" not in line][1:]
    assert len(rows) >= 8 and any("dhlb.conformal" in r for r in rows)
    assert "| layer | package | what |" not in index.split("```{include}")[0]     # no second, hand-kept table
    assert "shared/seed" not in index                                              # no path outside the repository
