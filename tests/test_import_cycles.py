"""No import circles inside the lower-layer packages (topology, forms, bundles, io).

Every import counts: module level, inside functions, and under ``TYPE_CHECKING`` (grimp reads
them all from the source). A circle between two modules of one package means neither is the
lower one; the fix is to move the shared piece down or to build through ``type(X)``.
"""

from __future__ import annotations

import itertools

import pytest

grimp = pytest.importorskip("grimp")

PACKAGES = ["dhlb.topology", "dhlb.forms", "dhlb.bundles", "dhlb.io"]


def find_cycle(modules, imports_of) -> list[str] | None:
    """One import cycle among ``modules`` (as a closed path ``[a, b, ..., a]``), or None.

    ``imports_of(m)`` gives the modules that ``m`` imports directly; edges leaving ``modules``
    are ignored. Iterative depth-first search with white/grey/black colouring.
    """
    modules = sorted(modules)
    inside = set(modules)
    colour = dict.fromkeys(modules, 0)  # 0 unseen, 1 on the current path, 2 done
    for root in modules:
        if colour[root]:
            continue
        path = [root]
        stack = [iter(sorted(set(imports_of(root)) & inside))]
        colour[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                colour[path.pop()] = 2
                stack.pop()
            elif colour[nxt] == 1:
                return path[path.index(nxt):] + [nxt]
            elif colour[nxt] == 0:
                colour[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(set(imports_of(nxt)) & inside)))
    return None


@pytest.fixture(scope="module")
def graph():
    return grimp.build_graph("dhlb", include_external_packages=False, cache_dir=None)


@pytest.mark.parametrize("package", PACKAGES)
def test_no_import_cycle_inside(graph, package):
    inside = {m for m in graph.modules if m == package or m.startswith(package + ".")}  # the facade counts too
    assert len(inside) > 1, f"no modules found under {package}"
    cycle = find_cycle(inside, graph.find_modules_directly_imported_by)
    if cycle:
        lines = []
        for a, b in itertools.pairwise(cycle):
            at = [d["line_number"] for d in graph.get_import_details(importer=a, imported=b)]
            lines.append(f"{a} -> {b} (line {', '.join(map(str, at))})")
        pytest.fail(f"import cycle in {package}:\n" + "\n".join(lines))


def test_find_cycle_sees_a_cycle_in_a_synthetic_graph():
    package = {"p.a", "p.b", "p.c"}
    edges = {"p.a": {"p.b"}, "p.b": {"p.c", "q.x"}, "p.c": {"p.a"}, "q.x": {"p.a"}}
    assert find_cycle(package, lambda m: edges.get(m, ())) == ["p.a", "p.b", "p.c", "p.a"]
    edges["p.c"] = set()  # cut the circle: the way back through q.x leaves the package and is ignored
    assert find_cycle(package, lambda m: edges.get(m, ())) is None
    edges["p.c"] = {"p.b"}  # a two-module circle further down
    assert find_cycle(package, lambda m: edges.get(m, ())) == ["p.b", "p.c", "p.b"]


def test_find_cycle_sees_an_added_edge_in_the_real_graph(graph):
    inside = {m for m in graph.modules if m.startswith("dhlb.topology.")}
    extra = {("dhlb.topology._keys", "dhlb.topology.complex")}  # complex imports _keys; add the way back

    def imports_of(m):
        return set(graph.find_modules_directly_imported_by(m)) | {b for a, b in extra if a == m}

    cycle = find_cycle(inside, imports_of)
    assert cycle is not None and cycle[0] == cycle[-1]
    assert {"dhlb.topology._keys", "dhlb.topology.complex"} <= set(cycle)
