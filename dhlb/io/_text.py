"""Shared helpers of the mesh readers: reading text, converting tokens, validating arrays.

Every reader keeps the file line of each parsed row so that errors can name it; the helpers
here convert whole blocks at once (numpy) and only fall back to a per-token scan to locate
the offending token when the fast conversion fails.
"""

from __future__ import annotations

import functools
import gc
import os
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import numpy as np

from dhlb.errors import InvalidSimplexError, MeshParseError, NonFiniteError

__all__ = [
    "no_gc",
    "read_text",
    "decode_text",
    "strip_bom",
    "content_lines",
    "to_array",
    "to_flat_int",
    "check_finite",
    "check_cells",
    "fan_triangulate",
    "format_number_rows",
    "prepare_write",
    "normalize_cells",
    "OUTPUT_EXTENSIONS",
    "output_stem",
    "read_json",
]

_P = ParamSpec("_P")
_R = TypeVar("_R")


def no_gc(func: Callable[_P, _R]) -> Callable[_P, _R]:
    """Decorator: run a parser with the cyclic garbage collector paused.

    Parsing creates hundreds of thousands of small token lists; without this the collector's
    repeated generation scans cost several times the parsing itself. Only acyclic objects are
    created, so pausing it frees nothing late.
    """

    @functools.wraps(func)
    def wrapper(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        was_enabled = gc.isenabled()
        gc.disable()
        try:
            return func(*args, **kwargs)
        finally:
            if was_enabled:
                gc.enable()

    return wrapper


def read_text(path) -> str:
    """Return the text of ``path`` (undecodable bytes become U+FFFD, so parsing reports them).

    A leading UTF-8 byte-order mark is dropped; a UTF-16/32 one raises
    :class:`~dhlb.errors.MeshParseError`.

    Raises ``FileNotFoundError`` / ``IsADirectoryError`` / ``PermissionError`` as usual.
    """
    with open(os.fspath(path), "rb") as fh:
        data = fh.read()
    return decode_text(data, os.fspath(path))


def strip_bom(data: bytes, path: str) -> bytes:
    r"""``data`` without a leading UTF-8 byte-order mark; a UTF-16/32 mark is an error.

    Examples
    --------
    >>> strip_bom(b"\xef\xbb\xbfOFF", "m.off")
    b'OFF'
    >>> strip_bom(b"\xff\xfeO\x00", "m.off")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: m.off, line 1: the file is UTF-16 or UTF-32 encoded (byte-order mark ...
    """
    if data.startswith(b"\xef\xbb\xbf"):
        return data[3:]
    if data.startswith((b"\xff\xfe", b"\xfe\xff", b"\x00\x00\xfe\xff")):
        raise MeshParseError(
            "the file is UTF-16 or UTF-32 encoded (byte-order mark at byte 0); save it as ASCII or UTF-8",
            path, 1,
        )
    return data


def decode_text(data: bytes, path: str) -> str:
    r"""Decode file bytes as UTF-8 after :func:`strip_bom` (undecodable bytes become U+FFFD).

    Examples
    --------
    >>> decode_text(b"\xef\xbb\xbfv 0 0 0\r\n", "m.obj").splitlines()
    ['v 0 0 0']
    """
    return strip_bom(data, path).decode("utf-8", errors="replace")


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


def to_flat_int(rows, lines, path, what: str) -> np.ndarray:
    """Concatenate rows of integer tokens (lengths may differ) into one int64 array.

    Examples
    --------
    >>> to_flat_int([["1", "2", "3"], ["4", "5"]], [1, 2], "f.txt", "index").tolist()
    [1, 2, 3, 4, 5]
    >>> to_flat_int([["1", "2", "3"], ["4", "5.5"]], [1, 2], "f.txt", "index")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: f.txt, line 2: cannot read '5.5' as an integer index
    """
    flat = [t for row in rows for t in row]
    if not flat:
        return np.zeros(0, dtype=np.int64)
    try:
        return np.array(flat, dtype=np.int64)
    except (ValueError, OverflowError, TypeError):
        for row, line in zip(rows, lines):
            to_array([row], [line], np.int64, path, what)
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
    dhlb.errors.MeshParseError: m.obj, line 11: face refers to vertex 6 but the file has only 4 vertices ...
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


def format_number_rows(array: np.ndarray, fmt: str, prefix: str = "") -> str:
    r"""Format a 2-d array as text, one row per line, every entry with ``fmt``.

    ``'%r'`` writes floats exactly (shortest round-trip representation), ``'%d'`` integers.

    Examples
    --------
    >>> format_number_rows(np.array([[0.1, 2.0]]), "%r", prefix="v ")
    'v 0.1 2.0\n'
    """
    array = np.asarray(array)
    if array.shape[0] == 0:
        return ""
    row_fmt = prefix + " ".join([fmt] * array.shape[1]) + "\n"
    return "".join(row_fmt % tuple(row) for row in array.tolist())


def prepare_write(V, F, min_corners: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Validate arrays handed to a writer; return float64 ``(n, 3)`` and int64 ``(m, k)`` arrays.

    Raises :class:`~dhlb.errors.InvalidSimplexError` on a wrong shape, dtype or index range and
    :class:`~dhlb.errors.NonFiniteError` on NaN/inf coordinates, so that nothing unreadable is
    ever written.

    Examples
    --------
    >>> prepare_write([[0, 0, 0], [1, 0, 0]], [[0, 2]])
    Traceback (most recent call last):
    ...
    dhlb.errors.InvalidSimplexError: cell 0 (0, 2) refers to vertex 2, outside the vertex array (rows 0 .. 1)
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    if V.ndim != 2 or V.shape[1] != 3:
        raise InvalidSimplexError(f"vertex array must have shape (n, 3), got {V.shape}")
    check_finite(V, "vertex array")
    if F.ndim != 2 or F.shape[1] < min_corners:
        raise InvalidSimplexError(f"cell array must have shape (m, k) with k >= {min_corners}, got {F.shape}")
    if F.size and not np.issubdtype(F.dtype, np.integer):
        raise InvalidSimplexError(f"cell array must hold integers, got dtype {F.dtype}")
    from dhlb.mesh.arrays import check_cells  # on first write: the readers do not pay for dhlb.mesh

    F = check_cells(F, len(V), F.shape[1], "cell", points="the vertex array")
    return V, F


def normalize_cells(V, cells, dims=(0, 1, 2, 3)) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Validate writer input: ``cells`` is one ``(m, k+1)`` array or a dict ``{k: array}``.

    Examples
    --------
    >>> V, blocks = normalize_cells(np.eye(3), [[0, 1, 2]])
    >>> {k: b.tolist() for k, b in blocks.items()}
    {2: [[0, 1, 2]]}
    """
    if isinstance(cells, dict):
        items = list(cells.items())
    else:
        arr = np.asarray(cells)
        if arr.ndim != 2:
            raise InvalidSimplexError(f"cells must be an (m, k+1) array or a dict {{k: array}}, got shape {arr.shape}")
        items = [(arr.shape[1] - 1, arr)]
    V = np.asarray(V, dtype=np.float64)
    blocks = {}
    for k, T in items:
        T = np.asarray(T)
        if T.size == 0:
            T = T.reshape(0, k + 1).astype(np.int64)
        if int(k) not in dims:
            raise InvalidSimplexError(f"this format stores simplices of dimension {dims}, not {k}")
        if T.ndim != 2 or T.shape[1] != k + 1:
            raise InvalidSimplexError(f"{k}-simplices need an (m, {k + 1}) array, got shape {T.shape}")
        V, blocks[int(k)] = prepare_write(V, T, min_corners=k + 1)
    if not items:
        V, _ = prepare_write(V, np.zeros((0, 1), np.int64))
    return V, blocks


OUTPUT_EXTENSIONS = (".npz", ".ply", ".obj", ".json", ".mesh", ".msh", ".vtk", ".vtu", ".png")
"""Extensions of the files the commands write for an output base (dropped by :func:`output_stem`)."""


def output_stem(path) -> str:
    """``path`` without an extension of :data:`OUTPUT_EXTENSIONS` (an output base stays as it is).

    Examples
    --------
    >>> output_stem("out/spot.npz"), output_stem("out/field-n4-s+0"), output_stem("a.b")
    ('out/spot', 'out/field-n4-s+0', 'a.b')
    """
    out = os.fspath(path)
    stem, ext = os.path.splitext(out)
    return stem if ext.lower() in OUTPUT_EXTENSIONS else out


def read_json(path) -> dict:
    """The JSON object in the file ``path``.

    Raises
    ------
    MeshParseError
        The file is not readable JSON, or holds no JSON object (names the file).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "a.json")
    ...     _ = open(p, "w").write('{"n": 2}')
    ...     read_json(p)
    {'n': 2}
    """
    import json

    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except (OSError, ValueError) as exc:
        raise MeshParseError(f"not readable JSON ({exc})", os.fspath(path)) from None
    if not isinstance(data, dict):
        raise MeshParseError(f"holds a {type(data).__name__}, not a JSON object", os.fspath(path))
    return data
