"""Gmsh ``.msh`` files, ASCII versions 2.2 and 4.1: nodes and simplicial elements.

Points, lines, triangles and tetrahedra are read (second-order simplices by their corner nodes);
other element types are refused. Node tags may be arbitrary positive integers: they are mapped
to 0-based rows in the order of the ``$Nodes`` section.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import MeshParseError
from dhlb.io._text import (
    check_cells,
    check_finite,
    content_lines,
    format_number_rows,
    no_gc,
    normalize_cells,
    read_text,
    to_array,
)
from dhlb.io.atomic import atomic_write

if TYPE_CHECKING:
    from collections.abc import Mapping

    from numpy.typing import ArrayLike

__all__ = ["read_gmsh", "write_gmsh"]

# element type -> (dimension, number of nodes, number of corner nodes)
_TYPES = {15: (0, 1, 1), 1: (1, 2, 2), 2: (2, 3, 3), 4: (3, 4, 4), 8: (1, 3, 2), 9: (2, 6, 3), 11: (3, 10, 4)}
_GMSH_TYPE_OF_DIM = {0: 15, 1: 1, 2: 2, 3: 4}
_NAMES = {3: "4-node quadrangle", 5: "hexahedron", 6: "prism", 7: "pyramid", 10: "9-node quadrangle",
          12: "27-node hexahedron", 13: "18-node prism", 14: "14-node pyramid", 16: "8-node quadrangle",
          17: "20-node hexahedron", 18: "15-node prism", 19: "13-node pyramid"}  # fmt: skip


def _sections(lines, path):
    """Split the file into {name: (header line, [(line, tokens), ...])}."""
    out = {}
    i = 0
    while i < len(lines):
        line, toks = lines[i]
        if not toks[0].startswith("$") or toks[0].startswith("$End"):
            raise MeshParseError(f"expected a section header such as '$Nodes', found {toks[0]!r}", path, line)
        name = toks[0][1:]
        j = i + 1
        while j < len(lines) and lines[j][1][0] != "$End" + name:
            j += 1
        if j == len(lines):
            raise MeshParseError(f"section ${name} is not closed by $End{name}", path, line)
        if name in out and name in ("MeshFormat", "Nodes", "Elements"):
            raise MeshParseError(f"section ${name} appears twice", path, line)
        out.setdefault(name, (line, lines[i + 1 : j]))
        i = j + 1
    return out


class _Body:
    """Cursor over the (line, tokens) rows of one section."""

    def __init__(self, rows, header_line, name, path):
        self.rows, self.i, self.header, self.name, self.path = rows, 0, header_line, name, path

    def take(self, n: int | None = None):
        """Next row (or next ``n`` rows); error if the section ends early."""
        k = 1 if n is None else n
        if k < 0:
            raise MeshParseError(f"negative count in section ${self.name}", self.path, self.rows[self.i - 1][0])
        if self.i + k > len(self.rows):
            raise MeshParseError(f"section ${self.name} ends too early", self.path, self.header)
        got = self.rows[self.i : self.i + k]
        self.i += k
        return got[0] if n is None else got

    def ints(self, count: int, what: str):
        line, toks = self.take()
        if len(toks) != count:
            raise MeshParseError(f"expected {count} integers ({what}), got {len(toks)} values", self.path, line)
        return line, [int(v) for v in to_array([toks], [line], np.int64, self.path, what)[0]]

    def done(self):
        if self.i != len(self.rows):
            line = self.rows[self.i][0]
            raise MeshParseError(f"unexpected data at the end of section ${self.name}", self.path, line)


def _coords(rows, path, skip_tag: bool):
    numbers = [r[0] for r in rows]
    width = 4 if skip_tag else 3
    bad = [i for i, (_, t) in enumerate(rows) if (len(t) != 4 if skip_tag else len(t) < 3)]
    if bad:
        need = "a tag and 3 coordinates" if skip_tag else "3 coordinates"
        raise MeshParseError(f"a node line needs {need}", path, numbers[bad[0]])
    toks = [t[:width] for _, t in rows]
    if skip_tag:
        tags = to_array([t[:1] for t in toks], numbers, np.int64, path, "node tag").ravel()
        return tags, to_array([t[1:] for t in toks], numbers, np.float64, path, "coordinate").reshape(-1, 3), numbers
    return None, to_array(toks, numbers, np.float64, path, "coordinate").reshape(-1, 3), numbers


def _element_type(etype: int, line: int, path: str):
    if etype not in _TYPES:
        what = _NAMES.get(etype, f"type {etype}")
        raise MeshParseError(
            f"element type {etype} ({what}) is not a simplex; dhlb reads points, lines, triangles and "
            "tetrahedra (types 15, 1, 2, 4 and their second-order versions 8, 9, 11)",
            path,
            line,
        )
    return _TYPES[etype]


def _add(by_dim: dict, dim: int, corners: np.ndarray, lines, order=None) -> None:
    """Collect a block of elements of one dimension; ``order`` keys restore file order later."""
    parts = by_dim.setdefault(dim, [])
    start = sum(len(c) for _, c, _ in parts) if order is None else 0
    key = np.arange(start, start + len(corners)) if order is None else np.asarray(order)
    parts.append((key, corners, np.asarray(lines, dtype=np.int64)))


def _elements_v2(rows, by_dim: dict, path: str) -> None:
    """``tag type n_tags tag.. node..`` lines, converted by groups of equal length."""
    lengths = np.fromiter((len(t) for _, t in rows), dtype=np.int64, count=len(rows))
    lines = np.fromiter((ln for ln, _ in rows), dtype=np.int64, count=len(rows))
    for length in np.unique(lengths).tolist():
        idx = np.flatnonzero(lengths == length)
        if length < 3:
            raise MeshParseError("an element line needs 'tag type n_tags ...'", path, int(lines[idx[0]]))
        vals = to_array([rows[i][1] for i in idx], lines[idx], np.int64, path, "element value")
        for etype, ntags in np.unique(vals[:, 1:3], axis=0).tolist():
            sel = np.flatnonzero((vals[:, 1] == etype) & (vals[:, 2] == ntags))
            at = int(lines[idx[sel[0]]])
            dim, n_nodes, n_corners = _element_type(etype, at, path)
            first = 3 + ntags
            if ntags < 0 or length != first + n_nodes:
                raise MeshParseError(f"element of type {etype} needs {n_nodes} nodes, got {length - first}", path, at)
            _add(by_dim, dim, vals[sel, first : first + n_corners], lines[idx[sel]], order=idx[sel])


def _nodes_and_elements(sec, version: str, path: str):
    if "Nodes" not in sec or "Elements" not in sec:
        raise MeshParseError("the file needs a $Nodes and an $Elements section", path)
    nodes = _Body(sec["Nodes"][1], sec["Nodes"][0], "Nodes", path)
    elems = _Body(sec["Elements"][1], sec["Elements"][0], "Elements", path)
    by_dim: dict[int, list] = {}
    if version.startswith("2"):
        _, (n,) = nodes.ints(1, "number of nodes")
        tags, V, vlines = _coords(nodes.take(n), path, skip_tag=True)
        nodes.done()
        _, (m,) = elems.ints(1, "number of elements")
        _elements_v2(elems.take(m), by_dim, path)
        elems.done()
    else:
        _, (blocks, _n, _lo, _hi) = nodes.ints(4, "numEntityBlocks numNodes minNodeTag maxNodeTag")
        tag_parts, coord_parts, vlines = [], [], []
        for _ in range(blocks):
            line, (_edim, _etag, _parametric, k) = nodes.ints(4, "entityDim entityTag parametric numNodesInBlock")
            tag_rows = nodes.take(k)
            bad = [ln for ln, t in tag_rows if len(t) != 1]
            if bad:
                raise MeshParseError("expected one node tag per line", path, bad[0])
            tags_k = to_array([t for _, t in tag_rows], [ln for ln, _ in tag_rows], np.int64, path, "node tag")
            tag_parts.append(tags_k.ravel())
            _, X, numbers = _coords(nodes.take(k), path, skip_tag=False)
            coord_parts.append(X)
            vlines += numbers
        nodes.done()
        tags = np.concatenate(tag_parts) if tag_parts else np.zeros(0, np.int64)
        V = np.concatenate(coord_parts) if coord_parts else np.zeros((0, 3))
        _, (blocks, _m, _lo, _hi) = elems.ints(4, "numEntityBlocks numElements minElementTag maxElementTag")
        for _ in range(blocks):
            line, (_edim, _etag, etype, k) = elems.ints(4, "entityDim entityTag elementType numElementsInBlock")
            dim, n_nodes, n_corners = _element_type(etype, line, path)
            rows = elems.take(k)
            numbers = [ln for ln, _ in rows]
            bad = [ln for ln, t in rows if len(t) != n_nodes + 1]
            if bad:
                raise MeshParseError(f"an element of type {etype} needs a tag and {n_nodes} nodes", path, bad[0])
            vals = to_array([t for _, t in rows], numbers, np.int64, path, "node tag").reshape(-1, n_nodes + 1)
            _add(by_dim, dim, vals[:, 1 : 1 + n_corners], numbers)
        elems.done()
    return tags, V, vlines, by_dim


@no_gc
def read_gmsh(path: str | os.PathLike[str]) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Read an ASCII Gmsh ``.msh`` file (format 2.2 or 4.1).

    Parameters
    ----------
    path : str or path-like
        The file to read.

    Returns
    -------
    V : (n, 3) float64
        Node coordinates, in ``$Nodes`` order.
    cells : dict {k: (m_k, k+1) int64}
        0-based simplices by dimension (points k=0, lines, triangles, tetrahedra), in file order.

    Raises
    ------
    MeshParseError
        Binary or unsupported version, bad section layout, unreadable value, non-simplicial
        element, unknown or duplicate node tag; the message names the line.
    NonFiniteError
        A node has a NaN or infinite coordinate.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_gmsh
    >>> text = '''$MeshFormat
    ... 4.1 0 8
    ... $EndMeshFormat
    ... $Nodes
    ... 1 3 1 3
    ... 2 1 0 3
    ... 1
    ... 2
    ... 3
    ... 0 0 0
    ... 1 0 0
    ... 0 1 0
    ... $EndNodes
    ... $Elements
    ... 1 1 1 1
    ... 2 1 2 1
    ... 1 1 2 3
    ... $EndElements
    ... '''
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "t.msh"); _ = open(p, "w").write(text)
    ...     V, cells = read_gmsh(p)
    >>> cells[2].tolist()
    [[0, 1, 2]]
    """
    path = os.fspath(path)
    text = read_text(path)
    lines = list(content_lines(text, comment=None))
    if not lines:
        raise MeshParseError("the file is empty", path)
    if lines[0][1][0] != "$MeshFormat":
        found = lines[0][1][0]
        raise MeshParseError(f"expected '$MeshFormat', found {found!r}; is this a Gmsh file?", path, lines[0][0])
    sec = _sections(lines, path)
    fline, frows = sec["MeshFormat"]
    if not frows or len(frows[0][1]) != 3:
        raise MeshParseError("expected 'version file-type data-size' after $MeshFormat", path, fline)
    version, ftype, _ = frows[0][1]
    if ftype != "0":
        raise MeshParseError("binary .msh files are not supported; save the mesh as ASCII", path, frows[0][0])
    if not (version.startswith("2") or version == "4.1"):
        raise MeshParseError(f"MSH version {version} is not supported; save as version 4.1 or 2.2", path, frows[0][0])
    tags, V, vlines, by_dim = _nodes_and_elements(sec, version, path)
    check_finite(V, path, vlines)
    order = np.argsort(tags, kind="stable")
    sorted_tags = tags[order]
    dup = np.flatnonzero(sorted_tags[1:] == sorted_tags[:-1])
    if dup.size:
        raise MeshParseError(f"node tag {sorted_tags[dup[0]]} appears twice", path, vlines[order[dup[0] + 1]])
    cells = {}
    for dim, parts in sorted(by_dim.items()):
        key = np.concatenate([k for k, _, _ in parts])
        first = np.argsort(key, kind="stable")  # file order
        refs = np.concatenate([c for _, c, _ in parts]).reshape(-1, dim + 1)[first]
        numbers = np.concatenate([ln for _, _, ln in parts])[first]
        pos = np.minimum(np.searchsorted(sorted_tags, refs), max(len(tags) - 1, 0))
        found = sorted_tags[pos] == refs if len(tags) else np.zeros(refs.shape, bool)
        if not found.all():
            i = int(np.flatnonzero(~found.all(axis=1))[0])
            tag = int(refs[i][~found[i]][0])
            raise MeshParseError(f"element refers to node tag {tag}, which is not in $Nodes", path, int(numbers[i]))
        cells[dim] = order[pos]
        check_cells(cells[dim], len(V), path, numbers, what="element")
    return V, cells


def write_gmsh(
    path: str | os.PathLike[str], V: ArrayLike, cells: ArrayLike | Mapping[int, ArrayLike], version: str = "2.2"
) -> None:
    """Write nodes and simplices as an ASCII Gmsh file, format ``"2.2"`` (default) or ``"4.1"``.

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float
    cells : (m, k+1) int array (k = 0..3) or dict {k: array}
    version : {"2.2", "4.1"}

    Raises
    ------
    ValueError
        ``version`` is neither ``"2.2"`` nor ``"4.1"``.
    InvalidSimplexError
        A wrong shape, a non-integer cell array, or a cell index out of range.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.
    OutputError
        The file cannot be written (missing folder, no permission, disk full); nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_gmsh, write_gmsh
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]); T = np.array([[0, 1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_gmsh(os.path.join(d, "t.msh"), V, T, version="4.1")
    ...     print(read_gmsh(os.path.join(d, "t.msh"))[1][3])
    [[0 1 2 3]]
    """
    if version not in ("2.2", "4.1"):
        raise ValueError(f"version must be '2.2' or '4.1', got {version!r}")
    V, blocks = normalize_cells(V, cells, dims=(0, 1, 2, 3))
    n = len(V)
    out = [f"$MeshFormat\n{version} 0 8\n$EndMeshFormat\n$Nodes\n"]
    if version == "2.2":
        out.append(f"{n}\n")
        out.append("".join(f"{i} {x!r} {y!r} {z!r}\n" for i, (x, y, z) in enumerate(V.tolist(), 1)))
        out.append("$EndNodes\n$Elements\n")
        out.append(f"{sum(len(T) for T in blocks.values())}\n")
        tag = 1
        for k, T in sorted(blocks.items()):
            # tag, type, 2 tags (physical 0, elementary 1)
            head = np.column_stack(
                [np.arange(tag, tag + len(T)), np.full((len(T), 4), [_GMSH_TYPE_OF_DIM[k], 2, 0, 1])]
            )
            out.append(format_number_rows(np.column_stack([head, T + 1]), "%d"))
            tag += len(T)
    else:
        out.append(f"1 {n} 1 {n}\n3 1 0 {n}\n" if n else "0 0 0 0\n")
        out.append("".join(f"{i}\n" for i in range(1, n + 1)))
        out.append(format_number_rows(V, "%r"))
        m = sum(len(T) for T in blocks.values())
        out.append(f"$EndNodes\n$Elements\n{len(blocks)} {m} {min(m, 1)} {m}\n")
        tag = 1
        for k, T in sorted(blocks.items()):
            out.append(f"{k} 1 {_GMSH_TYPE_OF_DIM[k]} {len(T)}\n")
            out.append(format_number_rows(np.column_stack([np.arange(tag, tag + len(T)), T + 1]), "%d"))
            tag += len(T)
    out.append("$EndElements\n")
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write("".join(out))
