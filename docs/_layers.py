"""The layer diagram of ``dhlb``, read from the import graph (``docs/architecture.md``).

The docs build runs this (``docs/conf.py``, at ``builder-inited``); by hand, from the repository root::

    python docs/_layers.py                 # writes docs/_generated/architecture.svg and layers.md

Nothing here knows a package name: the packages, their imports and their layers are read from the code.

* **Packages.** The nodes are the top-level subpackages and modules ``dhlb.X`` of the package; every module
  of a subpackage counts for it. The root ``dhlb/__init__.py`` is no node: it only imports lazily.
* **Imports.** Every ``import``/``from … import`` of a module is read with :mod:`ast`, module level and
  inside functions alike; relative imports are resolved; the bodies of ``if TYPE_CHECKING:`` are skipped
  (they do not run). ``from dhlb import X`` counts as an import of ``X`` when ``X`` is a package; other names
  imported from the root (``__version__``, lazy re-exports) count for no package.
* **Deprecated aliases.** A package is a deprecated alias when the first line of the docstring of its
  ``__init__.py`` says "deprecated" (``"Deprecated alias package (dhlb 0.2; …)"``), or when it is in the
  set passed as ``deprecated``. Its own imports do not count for the layering (an alias imports the new
  homes, wherever they are); it is drawn in a row of its own on top. An import *of* an alias from a
  package that is not one is a violation.
* **Layers.** The layer of a package is the length of the longest import path below it: layer 0 imports
  no other package. An import cycle has no such layering; it is broken by setting aside, in each cycle, the
  weakest import (fewest imports at module level, then fewest imports, then by name) until none is left —
  and putting back each set-aside import that closes no cycle. A set-aside import points up: it is a
  violation, drawn in red and listed with the cycle it closes.
"""

from __future__ import annotations

import ast
import dataclasses
import os
import sys
from xml.sax.saxutils import escape

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(os.path.dirname(HERE), "dhlb")
OUT = os.path.join(HERE, "_generated")


@dataclasses.dataclass
class Edge:
    """The imports of one package by another.

    Attributes
    ----------
    imports : int
        Number of import statements (one per imported name of a ``from … import``).
    module_level : int
        How many of them run when the importing module is loaded (the others are inside functions).
    first : str
        Where the first one is, ``"dhlb/pkg/mod.py:12"``.
    """

    imports: int = 0
    module_level: int = 0
    first: str = ""


@dataclasses.dataclass
class Layers:
    """The package graph of a Python package and its layering (see the module docstring for the rules).

    Attributes
    ----------
    name : str
        The name of the package (``"dhlb"``).
    modules, lines : dict of str to int
        Per package: number of modules (``.py`` files) and of lines.
    deprecated : set of str
        The deprecated alias packages.
    edges : dict of (str, str) to Edge
        ``(importer, imported)`` → the imports; no self-imports.
    layer : dict of str to int
        Per package its layer; the aliases are one above the top layer.
    violations : dict of (str, str) to str
        The imports that point up or into an alias (a subset of ``edges``) → why, in words.
    cycles : list of list of str
        The import cycles between packages: the packages of each (a strongly connected component), sorted.
    """

    name: str
    modules: dict
    lines: dict
    deprecated: set
    edges: dict
    layer: dict
    violations: dict
    cycles: list

    @property
    def packages(self) -> list:
        """The packages, top layer first, by name within a layer."""
        return sorted(self.modules, key=lambda p: (-self.layer[p], p))

    @property
    def top(self) -> int:
        """The highest layer of a package that is not an alias (``-1`` if there is none)."""
        return max((v for p, v in self.layer.items() if p not in self.deprecated), default=-1)

    def imports(self, package: str) -> list:
        """The packages that ``package`` imports, by name."""
        return sorted(dst for src, dst in self.edges if src == package)


# --- reading the code ------------------------------------------------------------------------------------------

def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _import_nodes(tree: ast.AST):
    """``(node, module_level)`` for every import statement, ``if TYPE_CHECKING:`` bodies skipped."""
    stack = [(tree, True)]
    while stack:
        node, top = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node, top
            continue
        inner = top and not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            children = node.orelse
        else:
            children = list(ast.iter_child_nodes(node))
        stack.extend((child, inner) for child in reversed(children))


def import_targets(source: str, module: str, package: str, *, is_init: bool = False) -> list:
    """The top-level packages of ``package`` that a module imports.

    Parameters
    ----------
    source : str
        The text of the module.
    module : str
        Its dotted name, ``"dhlb.fem.mass"`` (``"dhlb.fem"`` for ``dhlb/fem/__init__.py``).
    package : str
        The name of the root package, ``"dhlb"``.
    is_init : bool
        Whether the module is an ``__init__.py`` (relative imports then start from ``module`` itself).

    Returns
    -------
    list of (str, bool, int)
        ``(X, module_level, line)`` for each imported name under ``package.X``, in the order of the file;
        imports of other packages are left out. ``X`` may be a name of the root that is no subpackage
        (``from dhlb import __version__``): :func:`scan` keeps only the packages.

    Examples
    --------
    >>> src = '''
    ... import numpy
    ... from dhlb.fem import mass
    ... def f():
    ...     from ..topology import X
    ... '''
    >>> import_targets(src, "dhlb.fields.energy", "dhlb")
    [('fem', True, 3), ('topology', False, 5)]
    """
    here = module.split(".") if is_init else module.split(".")[:-1]
    out = []
    for node, top in _import_nodes(ast.parse(source)):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif node.level:
            base = here[:len(here) - node.level + 1] if node.level <= len(here) else []
            stem = ".".join(base + ([node.module] if node.module else []))
            names = [f"{stem}.{a.name}" if not node.module or stem == package else stem for a in node.names]
        elif node.module == package:
            names = [f"{package}.{a.name}" for a in node.names]
        else:
            names = [node.module] * len(node.names)
        for name in names:
            parts = name.split(".")
            if parts[0] == package and len(parts) > 1:
                out.append((parts[1], top, node.lineno))
    return out


def _docstring_says_deprecated(path: str) -> bool:
    with open(path, encoding="utf-8") as f:
        doc = ast.get_docstring(ast.parse(f.read())) or ""
    return "deprecated" in (doc.strip().splitlines() or [""])[0].lower()


def scan(root: str = ROOT, deprecated=None) -> Layers:
    """Read the package graph of the package in ``root`` and layer it.

    Parameters
    ----------
    root : str
        The directory of the package (``…/dhlb``); its name is the package name.
    deprecated : set of str, optional
        The deprecated alias packages. Default: those whose ``__init__.py`` docstring says "deprecated" in
        its first line.

    Returns
    -------
    Layers
        Packages, imports, layers, violations and cycles.

    Raises
    ------
    FileNotFoundError
        If ``root`` is not a directory.
    SyntaxError
        If a module does not parse.

    Examples
    --------
    >>> g = scan()
    >>> g.layer["errors"], g.layer["cli"] > g.layer["fem"] > g.layer["topology"]
    (0, True)
    """
    root = os.path.abspath(root)
    name = os.path.basename(root)
    modules, lines, files = {}, {}, []
    for entry in sorted(os.listdir(root)):
        path = os.path.join(root, entry)
        if os.path.isdir(path) and os.path.isfile(os.path.join(path, "__init__.py")):
            found = sorted(os.path.join(d, f) for d, _, fs in os.walk(path) for f in fs if f.endswith(".py"))
        elif entry.endswith(".py") and entry != "__init__.py":
            found, entry = [path], entry[:-3]
        else:
            continue
        modules[entry], lines[entry] = len(found), 0
        for f in found:
            with open(f, encoding="utf-8") as fh:
                text = fh.read()
            lines[entry] += text.count("\n") + (not text.endswith("\n") and bool(text))
            files.append((entry, f, text))
    if deprecated is None:
        deprecated = {p for p in modules if os.path.isfile(init := os.path.join(root, p, "__init__.py"))
                      and _docstring_says_deprecated(init)}
    deprecated = set(deprecated) & set(modules)
    edges = {}
    for src, path, text in files:
        rel = os.path.relpath(path, os.path.dirname(root))
        dotted = rel[:-3].replace(os.sep, ".")
        is_init = dotted.endswith(".__init__")
        dotted = dotted.removesuffix(".__init__")
        for dst, top, line in import_targets(text, dotted, name, is_init=is_init):
            if dst == src or dst not in modules:
                continue
            e = edges.setdefault((src, dst), Edge(first=f"{rel.replace(os.sep, '/')}:{line}"))
            e.imports += 1
            e.module_level += top
    return _layer(Layers(name, modules, lines, deprecated, edges, {}, {}, []))


# --- the layering ----------------------------------------------------------------------------------------------

def strongly_connected(nodes, edges) -> list:
    """The strongly connected components of a directed graph (Tarjan, iterative), each sorted.

    Parameters
    ----------
    nodes : iterable of str
    edges : iterable of (str, str)

    Returns
    -------
    list of list of str
        Every node in exactly one component.

    Examples
    --------
    >>> strongly_connected("abcd", [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")])
    [['a', 'b', 'c'], ['d']]
    """
    succ = {n: [] for n in nodes}
    for u, v in edges:
        succ[u].append(v)
    index, low, on, stack, out = {}, {}, set(), [], []
    for start in sorted(succ):
        if start in index:
            continue
        work = [(start, iter(sorted(succ[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is None:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        x = stack.pop()
                        on.discard(x)
                        comp.append(x)
                        if x == v:
                            break
                    out.append(sorted(comp))
            elif w not in index:
                index[w] = low[w] = len(index)
                stack.append(w)
                on.add(w)
                work.append((w, iter(sorted(succ[w]))))
            elif w in on:
                low[v] = min(low[v], index[w])
    return sorted(out)


def _path(succ, a, b) -> list:
    """A shortest path ``a → … → b`` in the graph ``succ`` (breadth first), or ``[]``."""
    prev, todo = {a: None}, [a]
    for u in todo:
        if u == b:
            path = []
            while u is not None:
                path.append(u)
                u = prev[u]
            return path[::-1]
        for v in sorted(succ.get(u, ())):
            if v not in prev:
                prev[v] = u
                todo.append(v)
    return []


def _layer(g: Layers) -> Layers:
    """Fill in ``g.layer``, ``g.violations`` and ``g.cycles`` (the rules are in the module docstring)."""
    live = {(u, v): e for (u, v), e in g.edges.items() if u not in g.deprecated and v not in g.deprecated}
    g.cycles = [c for c in strongly_connected(g.modules, live) if len(c) > 1]

    def weak(uv):  # the order of setting aside: weakest first
        return (live[uv].module_level, live[uv].imports, uv)

    kept, aside = dict(live), []
    while True:
        comp = {n: i for i, c in enumerate(strongly_connected(g.modules, kept)) for n in c}
        inside = [uv for uv in kept if comp[uv[0]] == comp[uv[1]]]
        if not inside:
            break
        uv = min(inside, key=weak)
        aside.append(uv)
        del kept[uv]
    succ = {}
    for u, v in kept:
        succ.setdefault(u, set()).add(v)
    for uv in sorted(aside, key=weak, reverse=True):  # put back the strongest first
        if not _path(succ, uv[1], uv[0]):
            kept[uv] = live[uv]
            succ.setdefault(uv[0], set()).add(uv[1])
    order, seen = [], set()

    def visit(n):  # depth first, dependencies first (no recursion limit worries: a few dozen packages)
        if n in seen:
            return
        seen.add(n)
        for m in sorted(succ.get(n, ())):
            visit(m)
        order.append(n)

    for n in sorted(g.modules):
        visit(n)
    for n in order:
        g.layer[n] = 1 + max((g.layer[m] for m in succ.get(n, ())), default=-1)
    for p in g.deprecated:
        g.layer[p] = g.top + 1
    for u, v in sorted(set(live) - set(kept)):
        g.violations[(u, v)] = (f"points up (layer {g.layer[u]} → {g.layer[v]}): closes the import cycle "
                                + " → ".join([u, *_path(succ, v, u)]))
    for u, v in sorted(g.edges):
        if v in g.deprecated and u not in g.deprecated:
            g.violations[(u, v)] = "imports a deprecated alias"
    return g


# --- the picture -----------------------------------------------------------------------------------------------

BOX_W, BOX_H, GAP_X, ROW_H, LEFT, PAD = 124, 52, 14, 86, 62, 14
INK, FAINT, RED, ALIAS = "#222", "#8a8f98", "#c62828", "#9e9e9e"
FILL = ["#e8f0fb", "#eaf5ea", "#fdf3e1", "#f3eafa"]  # cycled per layer, to tell the rows apart


def _rows(g: Layers) -> dict:
    """``{layer: [packages]}`` ordered within each row to keep arrows short (barycentre sweeps)."""
    rows = {}
    for p in sorted(g.modules):
        rows.setdefault(g.layer[p], []).append(p)
    down = {p: [v for (u, v) in g.edges if u == p] for p in g.modules}
    up = {p: [u for (u, v) in g.edges if v == p] for p in g.modules}

    def sweep(levels, nbrs):
        pos = {p: i - (len(rows[lv]) - 1) / 2 for lv in rows for i, p in enumerate(rows[lv])}
        for lv in levels:
            def key(p, pos=pos, lv=lv):
                xs = [pos[q] for q in nbrs[p] if q in pos and g.layer[q] != lv]
                return (sum(xs) / len(xs) if xs else pos[p], p)
            rows[lv].sort(key=key)
            pos.update({p: i - (len(rows[lv]) - 1) / 2 for i, p in enumerate(rows[lv])})

    levels = sorted(rows)
    for _ in range(2):
        sweep(levels[1:], down)
        sweep(levels[-2::-1], up)
    sweep(levels[1:], down)
    return rows


def to_svg(g: Layers) -> str:
    """The layer diagram as a self-contained SVG document.

    One row per layer, the highest on top (the deprecated aliases above it, dashed); a box per package with
    its name, modules and lines; an arrow per importing package pair, from the importer down to the imported.
    Violations (see :class:`Layers`) are red; the imports of an alias are dashed grey.

    Parameters
    ----------
    g : Layers

    Returns
    -------
    str
        The SVG text (UTF-8, no external references).

    Examples
    --------
    >>> svg = to_svg(scan())
    >>> svg.startswith("<svg") and "topology" in svg
    True
    """
    rows = _rows(g)
    levels = sorted(rows, reverse=True)
    box_w = max([BOX_W] + [round(9 * len(p) + 16) for p in g.modules])  # 15 px bold: about 9 px a letter
    widest = max(len(r) for r in rows.values())
    width = LEFT + widest * (box_w + GAP_X) - GAP_X + PAD
    height = PAD * 2 + len(levels) * ROW_H - (ROW_H - BOX_H) + 26 + 40
    xy = {}
    for i, lv in enumerate(levels):
        row = rows[lv]
        x0 = LEFT + (widest - len(row)) * (box_w + GAP_X) / 2
        for j, p in enumerate(row):
            xy[p] = (x0 + j * (box_w + GAP_X), PAD + 26 + i * ROW_H)
    # ports: spread the arrows leaving/entering a box along its edge, ordered by the other end's x
    outs = {p: sorted((e for e in g.edges if e[0] == p), key=lambda e: (xy[e[1]][0], e[1])) for p in g.modules}
    ins = {p: sorted((e for e in g.edges if e[1] == p), key=lambda e: (xy[e[0]][0], e[0])) for p in g.modules}

    def port(p, e, side):
        lst = outs[p] if side == "out" else ins[p]
        k = lst.index(e)
        return xy[p][0] + box_w * (k + 1) / (len(lst) + 1)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
           f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">',
           f"<title>{escape(g.name)}: packages by layer, arrows point to the imported package</title>",
           "<defs>"]
    for key, colour in (("ink", FAINT), ("red", RED), ("alias", ALIAS)):
        out.append(f'<marker id="arrow-{key}" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
                   f'markerHeight="7" orient="auto-start-reverse"><path d="M0,1 L10,5 L0,9 z" fill="{colour}"/>'
                   "</marker>")
    out.append("</defs>")
    out.append(f'<text x="{PAD}" y="{PAD + 8}" font-size="12" fill="{INK}">layer</text>')
    for i, lv in enumerate(levels):
        y = PAD + 26 + i * ROW_H + BOX_H / 2 + 5
        label = "aliases" if lv > g.top else str(lv)
        out.append(f'<text x="{PAD}" y="{y:.0f}" font-size="14" font-weight="bold" fill="{FAINT}">{label}</text>')
        if i:
            yl = PAD + 26 + i * ROW_H - (ROW_H - BOX_H) / 2
            out.append(f'<line x1="{PAD}" y1="{yl:.0f}" x2="{width - PAD:.0f}" y2="{yl:.0f}" stroke="#e3e5e8" '
                       'stroke-width="1"/>')
    # arrows under the boxes: a long import disappears behind the boxes it passes and shows where it lands;
    # an import that a longer downward path also gives is drawn faint, so that the chain of layers stands out
    succ = {}
    for (u, v) in g.edges:
        if (u, v) not in g.violations and u not in g.deprecated:
            succ.setdefault(u, set()).add(v)
    implied = {(u, v) for u in succ for v in succ[u]
               if any(_path({**succ, u: succ[u] - {v}}, w, v) for w in succ[u] - {v})}
    for (u, v), e in sorted(g.edges.items(), key=lambda kv: (kv[0] in g.violations, kv[0] not in implied, kv[0])):
        bad = (u, v) in g.violations
        x1, x2 = port(u, (u, v), "out"), port(v, (u, v), "in")
        if g.layer[v] < g.layer[u] or u in g.deprecated:  # down: bottom of u to top of v
            y1, y2 = xy[u][1] + BOX_H, xy[v][1]
        else:  # up (a violation): top of u to bottom of v
            y1, y2 = xy[u][1], xy[v][1] + BOX_H
        bend = max(18.0, abs(y2 - y1) * 0.4) * (1 if y2 > y1 else -1)
        key = "red" if bad else "alias" if u in g.deprecated else "ink"
        colour = {"red": RED, "alias": ALIAS, "ink": FAINT}[key]
        dash = ' stroke-dasharray="5 3"' if u in g.deprecated and not bad else ""
        stroke = 2.0 if bad else 0.8 if (u, v) in implied else 1.4
        if (u, v) in implied:
            dash += ' stroke-opacity="0.45"'
        tip = f"{u} → {v}: {e.imports} import{'s' * (e.imports != 1)}, first at {e.first}"
        out.append(f'<path d="M{x1:.1f},{y1:.1f} C{x1:.1f},{y1 + bend:.1f} {x2:.1f},{y2 - bend:.1f} {x2:.1f},'
                   f'{y2:.1f}" fill="none" stroke="{colour}" stroke-width="{stroke}"{dash} '
                   f'marker-end="url(#arrow-{key})"><title>{escape(tip)}</title></path>')
    for p, (x, y) in sorted(xy.items()):
        alias = p in g.deprecated
        fill = "#f5f5f5" if alias else FILL[g.layer[p] % len(FILL)]
        border = RED if any(p in c for c in g.cycles) else ALIAS if alias else "#5f6b7a"
        dash = ' stroke-dasharray="5 3"' if alias else ""
        stats = (f"{g.modules[p]} module{'s' * (g.modules[p] != 1)}", f"{g.lines[p]:,} lines")
        out.append(f'<g><title>{escape(f"{g.name}.{p}: {stats[0]}, {stats[1]}")}</title>'
                   f'<rect x="{x:.1f}" y="{y:.1f}" width="{box_w}" height="{BOX_H}" rx="5" fill="{fill}" '
                   f'stroke="{border}" stroke-width="1.3"{dash}/>'
                   f'<text x="{x + box_w / 2:.1f}" y="{y + 19:.1f}" text-anchor="middle" font-size="15" '
                   f'font-weight="bold" fill="{ALIAS if alias else INK}"'
                   f'{" font-style=" + chr(34) + "italic" + chr(34) if alias else ""}>{escape(p)}</text>'
                   f'<text x="{x + box_w / 2:.1f}" y="{y + 34:.1f}" text-anchor="middle" font-size="11" '
                   f'fill="#555">{escape(stats[0])}</text>'
                   f'<text x="{x + box_w / 2:.1f}" y="{y + 47:.1f}" text-anchor="middle" font-size="11" '
                   f'fill="#555">{escape(stats[1])}</text></g>')
    legend = ("an arrow points from a package to one it imports; faint: also imported through a longer path;",
              "red: points up (a layering violation) or closes an import cycle")
    for k, text in enumerate(legend):
        out.append(f'<text x="{PAD}" y="{height - PAD - 16 + 15 * k:.0f}" font-size="11" fill="#555">'
                   f"{escape(text)}</text>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


# --- the table -------------------------------------------------------------------------------------------------

def to_markdown(g: Layers, *, svg: str | None = None) -> str:
    """The violations and cycles (a list) and the table package | layer | modules | lines | imports, as MyST.

    Parameters
    ----------
    g : Layers
    svg : str, optional
        A path to the diagram, relative to the including page; given, the figure comes first.

    Returns
    -------
    str
        Markdown; violations in red (inline HTML), marked ↑ in the table.

    Examples
    --------
    >>> "| package | layer | modules | lines | imports |" in to_markdown(scan()).splitlines()
    True
    """
    out = []
    if svg:
        out += [f"![The packages of {g.name} by layer; an arrow points from a package to one it imports]({svg})",
                ""]
    if g.violations or g.cycles:
        for c in g.cycles:
            out.append(f'* <span style="color:{RED}">import cycle</span> between '
                       + ", ".join(f"`{p}`" for p in c))
        for (u, v), why in sorted(g.violations.items()):
            e = g.edges[(u, v)]
            out.append(f'* <span style="color:{RED}">`{u}` → `{v}`</span> {why} '
                       f"({e.imports} import{'s' * (e.imports != 1)}, first at `{e.first}`)")
        out.append("")
    out += ["| package | layer | modules | lines | imports |", "|---|---|---:|---:|---|"]
    for p in g.packages:
        layer = "alias" if p in g.deprecated else str(g.layer[p])
        imports = ", ".join(f"`{q}`" + (" ↑" if (p, q) in g.violations else "") for q in g.imports(p))
        out.append(f"| `{g.name}.{p}` | {layer} | {g.modules[p]} | {g.lines[p]:,} | {imports or '—'} |")
    return "\n".join(out) + "\n"


def _write(path: str, text: str) -> bool:
    """Write ``text`` to ``path`` unless it is there already (Sphinx then need not re-read the page)."""
    try:
        with open(path, encoding="utf-8") as f:
            if f.read() == text:
                return False
    except FileNotFoundError:
        pass
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return True


def generate(root: str = ROOT, out: str = OUT, deprecated=None) -> Layers:
    """Write ``out/architecture.svg`` (the diagram) and ``out/layers.md`` (violations and table).

    Parameters
    ----------
    root : str
        The package directory.
    out : str
        The output directory (created).
    deprecated : set of str, optional
        Passed to :func:`scan`.

    Returns
    -------
    Layers
        What was drawn.
    """
    g = scan(root, deprecated)
    os.makedirs(out, exist_ok=True)
    _write(os.path.join(out, "architecture.svg"), to_svg(g))
    _write(os.path.join(out, "layers.md"), to_markdown(g))
    return g


if __name__ == "__main__":
    g = generate(*sys.argv[1:2])
    print(f"{len(g.modules)} packages in {g.top + 1} layers, {len(g.violations)} violations, "
          f"{len(g.cycles)} cycles → {OUT}")
    for (u, v), why in sorted(g.violations.items()):
        print(f"  {u} → {v}: {why}")
