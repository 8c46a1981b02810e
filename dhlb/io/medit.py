"""Medit / INRIA ``.mesh`` files (ASCII): vertices, edges, triangles, tetrahedra.

Indices in the file are 1-based and every row ends with a reference number, which is read
and dropped. Sections dhlb does not use (corners, ridges, normals, ...) are skipped; quads,
hexahedra, prisms and pyramids are refused (dhlb handles simplicial meshes only).
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

__all__ = ["read_medit", "write_medit"]

_SIMPLICES = {"Edges": 1, "Triangles": 2, "Tetrahedra": 3}
_SECTION_OF_DIM = {k: name for name, k in _SIMPLICES.items()}
_SINGULAR = {1: "edge", 2: "triangle", 3: "tetrahedron"}
_NON_SIMPLICIAL = ("Quadrilaterals", "Hexahedra", "Prisms", "Pyramids")


def _value_after(lines, toks, line, path, what):
    """The value following a keyword, on the same line or the next one."""
    if len(toks) > 2:
        raise MeshParseError(f"unexpected values after {toks[0]}: {' '.join(toks[2:])!r}", path, line)
    if len(toks) == 2:
        return line, toks[1]
    nxt = next(lines, None)
    if nxt is None:
        raise MeshParseError(f"the file ends after '{toks[0]}', expected {what}", path, line)
    if len(nxt[1]) != 1:
        raise MeshParseError(f"expected {what} after '{toks[0]}', got {' '.join(nxt[1])!r}", path, nxt[0])
    return nxt[0], nxt[1][0]


@no_gc
def read_medit(path: str | os.PathLike[str]) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Read a Medit ``.mesh`` file.

    Parameters
    ----------
    path : str or path-like
        The file to read.

    Returns
    -------
    V : (n, 3) float64
        Vertex coordinates (2-d meshes get z = 0).
    cells : dict {k: (m_k, k+1) int64}
        0-based ``Edges`` (k=1), ``Triangles`` (k=2) and ``Tetrahedra`` (k=3), in file order;
        only the sections present in the file appear.

    Raises
    ------
    MeshParseError
        Unknown layout, unreadable value, a row with the wrong number of values, an index out of
        range or repeated within a cell, a non-simplicial section, data after ``End``; the message
        names the line. A leading UTF-8 byte-order mark and CRLF line ends are accepted.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_medit, example_path
    >>> V, cells = read_medit(example_path("solid-torus.mesh"))
    >>> V.shape, sorted(cells), cells[3].shape
    ((144, 3), [2, 3], (384, 4))
    """
    path = os.fspath(path)
    lines = content_lines(read_text(path))
    dim, V, vlines = 3, None, None
    cells: dict[int, np.ndarray] = {}
    cell_lines: dict[int, list[int]] = {}
    seen: dict[str, int] = {}
    any_line = False
    for line, toks in lines:
        any_line = True
        key = toks[0]
        if key == "End":
            if len(toks) > 1:
                raise MeshParseError(f"unexpected values after End: {' '.join(toks[1:])!r}", path, line)
            extra = next(lines, None)
            if extra is not None:
                raise MeshParseError(
                    f"unexpected data after 'End' (line {line}): {' '.join(extra[1])[:40]!r}; remove it or "
                    "check the declared counts",
                    path,
                    extra[0],
                )
            break
        if not key[0].isalpha() or key.lower() in ("nan", "inf", "infinity"):
            raise MeshParseError(f"expected a keyword such as 'Vertices', found {key!r}", path, line)
        if key in seen:
            raise MeshParseError(f"section '{key}' appears twice (first at line {seen[key]})", path, line)
        seen[key] = line
        if key == "MeshVersionFormatted":
            _value_after(lines, toks, line, path, "a version number")
            continue
        if key == "Dimension":
            at, value = _value_after(lines, toks, line, path, "the dimension")
            if value not in ("2", "3"):
                raise MeshParseError(f"dimension must be 2 or 3, got {value!r}", path, at)
            dim = int(value)
            continue
        at, value = _value_after(lines, toks, line, path, f"the number of {key}")
        count = int(to_array([[value]], [at], np.int64, path, f"count of {key}")[0, 0])
        if count < 0:
            raise MeshParseError(f"negative count of {key}", path, at)
        if key in _NON_SIMPLICIAL and count > 0:
            raise MeshParseError(
                f"the file contains {count} {key}; dhlb handles simplicial meshes only "
                "(split them into triangles / tetrahedra first)",
                path,
                line,
            )
        rows, numbers = [], []
        for i in range(count):
            nxt = next(lines, None)
            if nxt is None:
                raise MeshParseError(f"the file ends after {i} of {count} {key}", path)
            first = nxt[1][0]
            if first[0].isalpha() and first.lower() not in ("nan", "inf", "infinity"):
                raise MeshParseError(
                    f"section '{key}' (line {line}) declares {count} rows, but keyword {first!r} follows "
                    f"after {i}",
                    path,
                    nxt[0],
                )
            numbers.append(nxt[0])
            rows.append(nxt[1])
        if key == "Vertices":
            V = _block(rows, numbers, dim, np.float64, path, "vertex", "coordinates")
            V = np.column_stack([V, np.zeros((count, 3 - dim))]) if dim == 2 else V.reshape(-1, 3)
            vlines = numbers
        elif key in _SIMPLICES:
            k = _SIMPLICES[key]
            cells[k] = _block(rows, numbers, k + 1, np.int64, path, _SINGULAR[k], "vertex indices") - 1
            cells[k] = cells[k].reshape(-1, k + 1)
            cell_lines[k] = numbers
    if not any_line:
        raise MeshParseError("the file is empty", path)
    if V is None:
        raise MeshParseError("the file has no 'Vertices' section; is this a Medit .mesh file?", path)
    check_finite(V, path, vlines, first_number=1)
    for k, T in cells.items():
        check_cells(T, V.shape[0], path, cell_lines[k], first_number=1, what=_SINGULAR[k])
    return V, cells


def _block(rows, numbers, width: int, dtype, path: str, what: str, values: str) -> np.ndarray:
    """Rows of ``width`` values plus an optional trailing reference number (dropped)."""
    lengths = np.fromiter((len(r) for r in rows), dtype=np.int64, count=len(rows))
    bad = np.flatnonzero((lengths != width) & (lengths != width + 1))
    if bad.size:
        i = int(bad[0])
        raise MeshParseError(
            f"a {what} line needs {width} {values} and a reference number, got {lengths[i]} values",
            path,
            numbers[i],
        )
    if np.all(lengths == width + 1):
        table = to_array(rows, numbers, dtype, path, f"{what} value")
        return table[:, :width] if len(rows) else np.zeros((0, width), dtype)
    if np.any(lengths == width + 1):  # refs on some lines only: validate the refs, then drop them
        with_ref = np.flatnonzero(lengths == width + 1)
        to_array([rows[i][width:] for i in with_ref], [numbers[i] for i in with_ref], np.int64, path, "reference")
    return to_array([r[:width] for r in rows], numbers, dtype, path, f"{what} value").reshape(-1, width)


def write_medit(path: str | os.PathLike[str], V: ArrayLike, cells: ArrayLike | Mapping[int, ArrayLike]) -> None:
    """Write vertices and simplices as an ASCII Medit ``.mesh`` file (reference numbers 0).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float
    cells : (m, k+1) int array with k in {1, 2, 3}, or dict {k: array}

    Raises
    ------
    InvalidSimplexError
        A wrong shape, a dimension other than 1, 2, 3, a non-integer cell array, or a cell index out of range.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.
    OutputError
        The file cannot be written (missing folder, no permission, disk full); nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_medit, write_medit
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]); T = np.array([[0, 1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_medit(os.path.join(d, "t.mesh"), V, T)
    ...     V2, cells = read_medit(os.path.join(d, "t.mesh"))
    >>> cells[3].tolist()
    [[0, 1, 2, 3]]
    """
    V, blocks = normalize_cells(V, cells, dims=(1, 2, 3))
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write(f"MeshVersionFormatted 2\nDimension 3\n\nVertices\n{len(V)}\n")
        fh.write(format_number_rows(V, "%r").replace("\n", " 0\n"))
        for k, T in sorted(blocks.items()):
            fh.write(f"\n{_SECTION_OF_DIM[k]}\n{len(T)}\n")
            fh.write(format_number_rows(np.column_stack([T + 1, np.zeros(len(T), np.int64)]), "%d"))
        fh.write("\nEnd\n")
