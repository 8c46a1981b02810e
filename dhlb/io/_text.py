"""Shared helpers of the mesh readers: reading text, converting tokens, validating arrays.

Every reader keeps the file line of each parsed row so that errors can name it; the helpers
here convert whole blocks at once (numpy) and only fall back to a per-token scan to locate
the offending token when the fast conversion fails.
"""

from __future__ import annotations

import os

import numpy as np

from dhlb.errors import MeshParseError, NonFiniteError

__all__ = [
    "read_text",
    "content_lines",
    "to_array",
    "check_finite",
    "check_cells",
    "fan_triangulate",
    "format_number_rows",
]


def read_text(path) -> str:
    """Return the text of ``path`` (undecodable bytes become U+FFFD, so parsing reports them).

    Raises ``FileNotFoundError`` / ``IsADirectoryError`` / ``PermissionError`` as usual.
    """
    with open(os.fspath(path), "rb") as fh:
        data = fh.read()
    return data.decode("utf-8", errors="replace")


def content_lines(text: str, comment: str | None = "#"):
    """Yield ``(line_number, tokens)`` for the non-blank lines of ``text`` (1-based numbers).

    Everything after ``comment`` on a line is dropped.
    """
    for number, line in enumerate(text.splitlines(), 1):
        if comment is not None and comment in line:
            line = line.split(comment, 1)[0]
        tokens = line.split()
        if tokens:
            yield number, tokens


def _convert_one(token: str, dtype) -> None:
    if np.issubdtype(np.dtype(dtype), np.integer):
        int(token)
    else:
        float(token)


def to_array(rows, lines, dtype, path, what: str) -> np.ndarray:
    """Convert equal-length rows of string tokens to an array, naming the line of a bad token.

    Parameters
    ----------
    rows : list of list of str
        The tokens, one row per entry (all rows have the same length).
    lines : sequence of int
        The file line of each row (used in error messages).
    dtype : numpy dtype
        ``np.float64`` or ``np.int64``.
    path : str
        File name for messages.
    what : str
        What the tokens are ("vertex coordinate", "face index", ...).

    Examples
    --------
    >>> to_array([["1", "2"], ["3", "4"]], [7, 8], np.int64, "f.txt", "index").tolist()
    [[1, 2], [3, 4]]
    >>> to_array([["1", "x"]], [7], np.int64, "f.txt", "index")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: f.txt, line 7: cannot read 'x' as an integer index
    """
    kind = "an integer" if np.issubdtype(np.dtype(dtype), np.integer) else "a number"
    if len(rows) == 0:
        return np.zeros((0, 0), dtype=dtype)
    try:
        return np.array(rows, dtype=dtype)
    except (ValueError, OverflowError, TypeError):
        pass
    for toks, line in zip(rows, lines):
        for tok in toks:
            try:
                _convert_one(tok, dtype)
            except (ValueError, OverflowError):
                raise MeshParseError(f"cannot read {tok!r} as {kind} {what}", path, int(line)) from None
            if kind == "an integer" and abs(int(tok)) >= 2**63:
                raise MeshParseError(f"{what} {tok} is too large", path, int(line))
    raise MeshParseError(f"cannot read the {what}s", path)  # pragma: no cover - defensive


def check_finite(points: np.ndarray, path, lines=None, first_number: int = 0) -> None:
    """Raise :class:`~dhlb.errors.NonFiniteError` naming the first vertex with NaN/inf.

    ``first_number`` is how the file numbers its first vertex (1 for OBJ/Medit, 0 for OFF/PLY).

    Examples
    --------
    >>> check_finite(np.array([[0.0, 1, 2], [np.nan, 0, 0]]), "m.off", [3, 4])
    Traceback (most recent call last):
    ...
    dhlb.errors.NonFiniteError: m.off, line 4: vertex 1 has a non-finite coordinate (nan, 0.0, 0.0); fix or remove it
    """
    if points.size == 0:
        return
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    if bad.size == 0:
        return
    i = int(bad[0])
    where = f"{path}, line {int(lines[i])}" if lines is not None else f"{path}"
    label = f"vertex {i}" if first_number == 0 else f"vertex {i + first_number} (0-based {i})"
    coords = ", ".join(repr(float(c)) for c in points[i])
    more = f" ({bad.size} vertices in total)" if bad.size > 1 else ""
    raise NonFiniteError(f"{where}: {label} has a non-finite coordinate ({coords}){more}; fix or remove it")


def check_cells(cells: np.ndarray, n_points: int, path, lines=None, first_number: int = 0, what: str = "face"):
    """Check 0-based ``cells`` against ``n_points`` and for repeated vertices.

    Raises :class:`~dhlb.errors.MeshParseError` naming the line (or the cell number when
    ``lines`` is None) of the first offending cell. Indices are reported the way the file
    writes them (``first_number`` added).

    Examples
    --------
    >>> check_cells(np.array([[0, 1, 2], [0, 1, 5]]), 4, "m.obj", [10, 11], first_number=1)
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: m.obj, line 11: face refers to vertex 6 but the file has only 4 vertices (numbered from 1)
    """
    if cells.size == 0:
        return
    def where(i):
        return (path, int(lines[i])) if lines is not None else (path, None)

    def label(i):
        return what if lines is not None else f"{what} {i}"

    out = (cells < 0) | (cells >= n_points)
    bad = np.flatnonzero(out.any(axis=1))
    if bad.size:
        i = int(bad[0])
        v = int(cells[i][out[i]][0]) + first_number
        raise MeshParseError(
            f"{label(i)} refers to vertex {v} but the file has only {n_points} vertices "
            f"(numbered from {first_number})",
            *where(i),
        )
    if cells.shape[1] > 1:
        srt = np.sort(cells, axis=1)
        rep = np.flatnonzero(np.any(srt[:, 1:] == srt[:, :-1], axis=1))
        if rep.size:
            i = int(rep[0])
            shown = " ".join(str(int(v) + first_number) for v in cells[i])
            raise MeshParseError(
                f"{label(i)} ({shown}) repeats a vertex (a degenerate cell); remove it from the file",
                *where(i),
            )


def fan_triangulate(flat: np.ndarray, sizes: np.ndarray):
    """Split polygons into triangles ``(p0, p_j, p_{j+1})``, keeping polygon order.

    Parameters
    ----------
    flat : (sum(sizes),) int array
        The polygon corners, concatenated.
    sizes : (m,) int array
        Number of corners of each polygon (each >= 3).

    Returns
    -------
    tris : (sum(sizes - 2), 3) int64
    polygon : (sum(sizes - 2),) int64
        The polygon each triangle comes from.

    Examples
    --------
    >>> tris, poly = fan_triangulate(np.array([0, 1, 2, 3, 4, 5, 6]), np.array([4, 3]))
    >>> tris.tolist(), poly.tolist()
    ([[0, 1, 2], [0, 2, 3], [4, 5, 6]], [0, 0, 1])
    """
    flat = np.asarray(flat, dtype=np.int64)
    sizes = np.asarray(sizes, dtype=np.int64)
    if sizes.size and np.all(sizes == 3):
        return flat.reshape(-1, 3), np.arange(sizes.size, dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    n_tri = sizes - 2
    polygon = np.repeat(np.arange(sizes.size, dtype=np.int64), n_tri)
    tri_start = np.concatenate([[0], np.cumsum(n_tri)[:-1]]).astype(np.int64)
    j = np.arange(polygon.size, dtype=np.int64) - tri_start[polygon] + 1
    s = start[polygon]
    tris = np.stack([flat[s], flat[s + j], flat[s + j + 1]], axis=1)
    return tris, polygon


def format_number_rows(array: np.ndarray, fmt: str) -> str:
    """Format a 2-d array as text, one row per line, every entry with ``fmt`` (``'%.17g'``, ``'%d'``)."""
    array = np.asarray(array)
    if array.shape[0] == 0:
        return ""
    row_fmt = " ".join([fmt] * array.shape[1]) + "\n"
    return "".join(row_fmt % tuple(row) for row in array.tolist())
