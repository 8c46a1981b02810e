"""Legacy VTK ASCII unstructured grids (``.vtk``, file versions up to 5.1): points and simplices.

Vertex, line, triangle and tetrahedron cells are read (quadratic simplices by their corners);
other cell types are refused. Point and cell data sections are ignored.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import MeshParseError
from dhlb.io._text import (
    check_cells,
    check_finite,
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

__all__ = ["read_vtk", "write_vtk"]

# VTK cell type -> (dimension, number of points, number of corners)
_TYPES = {1: (0, 1, 1), 3: (1, 2, 2), 5: (2, 3, 3), 10: (3, 4, 4), 21: (1, 3, 2), 22: (2, 6, 3), 24: (3, 10, 4)}
_VTK_TYPE_OF_DIM = {0: 1, 1: 3, 2: 5, 3: 10}
_NAMES = {2: "poly-vertex", 4: "poly-line", 6: "triangle strip", 7: "polygon", 8: "pixel", 9: "quad",
          11: "voxel", 12: "hexahedron", 13: "wedge", 14: "pyramid"}  # fmt: skip
_STOP = {"POINT_DATA", "CELL_DATA", "FIELD"}
_KEYWORDS = {"POINTS", "CELLS", "CELL_TYPES"} | _STOP


class _Stream:
    """Whitespace tokens of the file body with the line of each token."""

    def __init__(self, lines, first_line: int, path: str):
        self.tokens, self.lines = [], []
        for number, text in enumerate(lines, first_line):
            t = text.split()
            self.tokens.extend(t)
            self.lines.extend([number] * len(t))
        self.i, self.path = 0, path

    def line(self, offset: int = 0) -> int | None:
        j = min(self.i + offset, len(self.lines) - 1)
        return self.lines[j] if self.lines else None

    def peek(self):
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def word(self, what: str) -> str:
        if self.i >= len(self.tokens):
            raise MeshParseError(f"the file ends where {what} was expected", self.path)
        self.i += 1
        return self.tokens[self.i - 1]

    def numbers(self, n: int, dtype, what: str) -> tuple[np.ndarray, np.ndarray]:
        """The next ``n`` tokens as numbers, and their lines."""
        if n < 0:
            raise MeshParseError(f"negative count for the {what}", self.path, self.line(-1))
        if self.i + n > len(self.tokens):
            raise MeshParseError(f"the file ends inside the {what} ({n} values expected)", self.path)
        toks = self.tokens[self.i : self.i + n]
        lines = np.asarray(self.lines[self.i : self.i + n], dtype=np.int64)
        self.i += n
        try:
            return np.array(toks, dtype=dtype), lines
        except (ValueError, OverflowError):
            to_array([[t] for t in toks], lines, dtype, self.path, what)
            raise  # pragma: no cover - the scan above raises


def _legacy_offsets(data: np.ndarray, lines: np.ndarray, n_cells: int, path: str):
    """``n p0 p1 .. n p0 ..`` -> (connectivity, offsets (n_cells+1,), line of each cell)."""
    if n_cells and data.size % n_cells == 0 and data.size >= 2 * n_cells:  # fast path: all cells of one size
        width = data.size // n_cells
        table = data.reshape(n_cells, width)
        if np.all(table[:, 0] == width - 1):
            return table[:, 1:].ravel(), np.arange(n_cells + 1) * (width - 1), lines[::width]
    starts, pos = [], 0
    for _ in range(n_cells):
        if pos >= data.size:
            at = int(lines[-1]) if lines.size else None
            raise MeshParseError(f"the CELLS data ends after {len(starts)} of {n_cells} cells", path, at)
        k = int(data[pos])
        if k < 1 or pos + 1 + k > data.size:
            raise MeshParseError(
                f"cell {len(starts)} declares {k} points, which does not fit the CELLS size", path, int(lines[pos])
            )
        starts.append(pos)
        pos += 1 + k
    if pos != data.size:
        raise MeshParseError("the CELLS size is larger than the cells it lists", path, int(lines[pos]))
    starts = np.asarray(starts, dtype=np.int64)
    keep = np.ones(data.size, bool)
    keep[starts] = False
    sizes = data[starts]
    return data[keep], np.concatenate([[0], np.cumsum(sizes)]), lines[starts]


@no_gc
def read_vtk(path: str | os.PathLike[str]) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Read a legacy ASCII VTK ``UNSTRUCTURED_GRID`` file.

    Parameters
    ----------
    path : str or path-like
        The file to read.

    Returns
    -------
    V : (n, 3) float64
    cells : dict {k: (m_k, k+1) int64}
        0-based simplices by dimension, in file order.

    Raises
    ------
    MeshParseError
        Binary file, other dataset type, unreadable value, wrong counts, non-simplicial cell
        type, index out of range; the message names the line.
    NonFiniteError
        A point has a NaN or infinite coordinate.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_vtk, write_vtk
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_vtk(os.path.join(d, "t.vtk"), V, {3: [[0, 1, 2, 3]], 2: [[0, 1, 2]]})
    ...     V2, cells = read_vtk(os.path.join(d, "t.vtk"))
    >>> sorted(cells), cells[3].tolist()
    ([2, 3], [[0, 1, 2, 3]])
    """
    path = os.fspath(path)
    raw = read_text(path).splitlines()
    if not any(t.strip() for t in raw):
        raise MeshParseError("the file is empty", path)
    if not raw[0].lower().startswith("# vtk datafile version"):
        raise MeshParseError("expected '# vtk DataFile Version x.x'; is this a legacy VTK file?", path, 1)
    if len(raw) < 4:
        raise MeshParseError("the file ends inside the VTK header", path, len(raw))
    if raw[2].strip().upper() != "ASCII":
        raise MeshParseError(f"only ASCII VTK files are supported, found {raw[2].strip()!r}", path, 3)
    s = _Stream(raw[3:], 4, path)
    if s.word("DATASET").upper() != "DATASET":
        raise MeshParseError("expected 'DATASET UNSTRUCTURED_GRID'", path, s.line(-1))
    kind = s.word("the dataset type")
    if kind.upper() != "UNSTRUCTURED_GRID":
        raise MeshParseError(f"only UNSTRUCTURED_GRID datasets are supported, found {kind}", path, s.line(-1))
    V = vlines = cells = cell_lines = types = type_lines = None
    while s.peek() is not None:
        key = s.word("a keyword").upper()
        at = s.line(-1)
        if key in _STOP:
            break
        if key == "METADATA":
            while s.peek() is not None and s.peek().upper() not in _KEYWORDS:
                s.i += 1
            continue
        if key == "POINTS":
            (n,), _ = s.numbers(1, np.int64, "number of points")
            s.word("the point data type")
            flat, lines = s.numbers(3 * int(n), np.float64, "point coordinate")
            V, vlines = flat.reshape(-1, 3), lines[::3]
        elif key == "CELLS":
            (a, b), _ = s.numbers(2, np.int64, "CELLS size")
            if a < 0 or b < 0:
                raise MeshParseError("negative CELLS size", path, at)
            if s.peek() is not None and s.peek().upper() == "OFFSETS":
                s.word("OFFSETS"), s.word("the offsets type")
                offsets, _ = s.numbers(int(a), np.int64, "cell offset")
                if s.word("CONNECTIVITY").upper() != "CONNECTIVITY":
                    raise MeshParseError("expected 'CONNECTIVITY' after the offsets", path, s.line(-1))
                s.word("the connectivity type")
                conn, lines = s.numbers(int(b), np.int64, "cell point index")
                if offsets.size == 0 or offsets[0] != 0 or offsets[-1] != b or np.any(np.diff(offsets) < 1):
                    raise MeshParseError("the cell OFFSETS must increase from 0 to the connectivity size", path, at)
                cells = (conn, offsets, lines[offsets[:-1]] if conn.size else np.zeros(0, np.int64))
            else:
                data, lines = s.numbers(int(b), np.int64, "cell value")
                cells = _legacy_offsets(data, lines, int(a), path)
        elif key == "CELL_TYPES":
            (n,), _ = s.numbers(1, np.int64, "number of cell types")
            types, type_lines = s.numbers(int(n), np.int64, "cell type")
        else:
            raise MeshParseError(f"unexpected keyword {key!r}", path, at)
    if V is None:
        raise MeshParseError("the file has no POINTS section", path)
    if cells is None or types is None:
        raise MeshParseError("the file needs CELLS and CELL_TYPES sections", path)
    conn, offsets, cell_lines = cells
    if len(types) != len(offsets) - 1:
        raise MeshParseError(
            f"{len(offsets) - 1} CELLS but {len(types)} CELL_TYPES", path, int(type_lines[0]) if len(types) else None
        )
    check_finite(V, path, vlines)
    known = np.isin(types, list(_TYPES))
    if not known.all():
        i = int(np.flatnonzero(~known)[0])
        t = int(types[i])
        raise MeshParseError(
            f"cell type {t} ({_NAMES.get(t, 'unknown')}) is not a simplex; dhlb reads vertex, line, triangle "
            "and tetrahedron cells (types 1, 3, 5, 10 and quadratic 21, 22, 24)",
            path,
            int(type_lines[i]),
        )
    table = np.zeros((max(_TYPES) + 1, 3), dtype=np.int64)
    for t, row in _TYPES.items():
        table[t] = row
    dims, n_points, _n_corners = table[types].T
    wrong = np.flatnonzero(np.diff(offsets) != n_points)
    if wrong.size:
        i = int(wrong[0])
        raise MeshParseError(
            f"a cell of type {types[i]} needs {n_points[i]} points, got {offsets[i + 1] - offsets[i]}",
            path,
            int(cell_lines[i]),
        )
    out = {}
    for dim in np.unique(dims).tolist():
        rows = np.flatnonzero(dims == dim)
        out[dim] = conn[offsets[rows][:, None] + np.arange(dim + 1)[None, :]]
        check_cells(out[dim], len(V), path, cell_lines[rows], what="cell")
    return V, out


def write_vtk(path: str | os.PathLike[str], V: ArrayLike, cells: ArrayLike | Mapping[int, ArrayLike]) -> None:
    """Write points and simplices as a legacy ASCII VTK (version 3.0) unstructured grid.

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float
    cells : (m, k+1) int array (k = 0..3) or dict {k: array}

    Raises
    ------
    InvalidSimplexError
        A wrong shape, a non-integer cell array, or a cell index out of range.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.
    OutputError
        The file cannot be written (missing folder, no permission, disk full); nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import write_vtk
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_vtk(os.path.join(d, "t.vtk"), np.eye(3), [[0, 1, 2]])
    ...     print(open(os.path.join(d, "t.vtk")).read().split("CELLS")[1].split())
    ['1', '4', '3', '0', '1', '2', 'CELL_TYPES', '1', '5']
    """
    V, blocks = normalize_cells(V, cells, dims=(0, 1, 2, 3))
    m = sum(len(T) for T in blocks.values())
    size = sum(len(T) * (k + 2) for k, T in blocks.items())
    out = ["# vtk DataFile Version 3.0\nwritten by dhlb\nASCII\nDATASET UNSTRUCTURED_GRID\n"]
    out.append(f"POINTS {len(V)} double\n")
    out.append(format_number_rows(V, "%r"))
    out.append(f"CELLS {m} {size}\n")
    for k, T in sorted(blocks.items()):
        out.append(format_number_rows(np.column_stack([np.full(len(T), k + 1), T]), "%d"))
    out.append(f"CELL_TYPES {m}\n")
    for k, T in sorted(blocks.items()):
        out.append(f"{_VTK_TYPE_OF_DIM[k]}\n" * len(T))
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write("".join(out))
