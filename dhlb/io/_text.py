"""Shared helpers of the mesh readers: reading text, converting tokens, validating arrays.

Every reader keeps the file line of each parsed row so that errors can name it; the helpers
here convert whole blocks at once (numpy) and only fall back to a per-token scan to locate
the offending token when the fast conversion fails.
"""

from __future__ import annotations

import functools
import gc
import os
import tokenize
import zipfile
import zlib
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
    "check_json_type",
    "check_number",
    "check_array",
    "check_repairs",
    "load_npz",
    "npz_keys",
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
                why = ": bytes that are not UTF-8 text" if "\ufffd" in tok else ""
                raise MeshParseError(f"cannot read {tok!r} as {kind} {what}{why}", path, int(line)) from None
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
    r"""The JSON object in the file ``path``.

    Parameters
    ----------
    path : str or path-like
        The file.

    Returns
    -------
    dict
        The object (NaN and infinity, which Python's json writes, are read as floats; the readers of
        the results refuse them where a value must be finite).

    Raises
    ------
    MeshParseError
        The file cannot be read, is empty, is not UTF-8 text, is not readable JSON (the message names
        the line) or holds no JSON object; every message names the file.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "a.json")
    ...     _ = open(p, "w").write('{"n": 2}')
    ...     read_json(p)
    {'n': 2}
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "a.json")
    ...     _ = open(p, "w").write('{"n": 2,\n "m": }')
    ...     read_json(p)
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: .../a.json, line 2: not readable JSON: Expecting value (column 7)
    """
    import json

    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as exc:
        raise MeshParseError(f"cannot be read ({exc.strerror or exc})", path) from None
    if not data.strip():
        raise MeshParseError("the file is empty: not readable JSON", path)
    data = strip_bom(data, path)
    if b"\x00" in data:
        line = data[:data.index(b"\x00")].count(b"\n") + 1
        raise MeshParseError("binary data (a NUL byte): not readable JSON", path, line)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise MeshParseError(f"byte {exc.start} (0x{data[exc.start]:02x}) is not UTF-8 text: not readable JSON",
                             path, line) from None
    try:
        obj = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MeshParseError(f"not readable JSON: {exc.msg} (column {exc.colno})", path, exc.lineno) from None
    except RecursionError:
        raise MeshParseError("not readable JSON: nested too deeply", path) from None
    if not isinstance(obj, dict):
        raise MeshParseError(f"holds a {type(obj).__name__}, not a JSON object", path)
    return obj


# --------------------------------------------------------------------------- checked values of result files
_JSON_TYPES = {dict: "an object", list: "a list", str: "a string", bool: "true or false", int: "an integer",
               float: "a number", type(None): "null"}


def describe(value) -> str:
    """A short description of a value read from a file, for messages.

    Parameters
    ----------
    value : object
        A JSON value or an array of an ``.npz``.

    Returns
    -------
    str

    Examples
    --------
    >>> describe("abc"), describe([1, 2]), describe(None), describe(np.zeros((2, 3)))
    ("the string 'abc'", 'a list of 2 items', 'null', 'a float64 array of shape (2, 3)')
    """
    if value is None:
        return "null"
    if isinstance(value, (bool, np.bool_)):
        return f"{str(bool(value)).lower()} (a boolean)"
    if isinstance(value, str):
        return f"the string {value if len(value) <= 40 else value[:37] + '...'!r}"
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return f"a list of {len(value)} items"
    if isinstance(value, np.ndarray):
        return f"a {value.dtype} array of shape {value.shape}"
    return repr(value)


def check_json_type(value, types, path, field: str):
    """``value`` when it is of one of ``types`` (JSON types: dict, list, str, bool, int, float, None).

    Parameters
    ----------
    value : object
        The value read.
    types : type or tuple of types
        The accepted types (``bool`` is not taken for ``int``).
    path : str
        The file, for the message.
    field : str
        The field, for the message (``"zeros.faces"``).

    Returns
    -------
    object
        ``value``.

    Raises
    ------
    MeshParseError
        ``value`` is of another type; the message names the file and the field.

    Examples
    --------
    >>> check_json_type("3", (list,), "s.json", "zeros.faces")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: s.json: zeros.faces must be a list, got the string '3'
    """
    types = types if isinstance(types, tuple) else (types,)
    ok = isinstance(value, types) and not (isinstance(value, bool) and bool not in types)
    if not ok:
        want = " or ".join(_JSON_TYPES.get(t, t.__name__) for t in types)
        raise MeshParseError(f"{field} must be {want}, got {describe(value)}", os.fspath(path))
    return value


def check_number(value, path, field: str, *, integer: bool = False, finite: bool = True, low=None, high=None,
                 optional: bool = False):
    """A number read from a file (a JSON number or a 0-d array of an ``.npz``), checked.

    Parameters
    ----------
    value : object
        The value read.
    path : str
        The file, for the message.
    field : str
        The field, for the message.
    integer : bool, optional
        An integer is required (a JSON float with an integral value is taken).
    finite : bool, optional
        NaN and infinity are refused.
    low, high : float, optional
        Inclusive bounds.
    optional : bool, optional
        None (JSON null) is accepted and returned.

    Returns
    -------
    int, float or None
        The value as a Python number.

    Raises
    ------
    MeshParseError
        Not a number (a string, a list, a boolean, an array with several values), not an integer,
        not finite or out of range; the message names the file and the field.

    Examples
    --------
    >>> check_number(np.array(3), "f.npz", "n", integer=True, low=1)
    3
    >>> check_number(float("nan"), "v.json", "eigenvalue")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: v.json: eigenvalue must be finite, got nan
    """
    path = os.fspath(path)
    if value is None and optional:
        return None
    x = value
    if isinstance(x, np.ndarray):
        if x.shape != () or x.dtype.kind not in "iuf":
            raise MeshParseError(f"{field} must be a single {'integer' if integer else 'number'}, got {describe(x)}",
                                 path)
        x = x.item()
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise MeshParseError(f"{field} must be {'an integer' if integer else 'a number'}"
                             f"{' or null' if optional else ''}, got {describe(x)}", path)
    if isinstance(x, (int, np.integer)):   # a Python int of JSON may exceed every machine type
        if abs(int(x)) >= 2**63:
            raise MeshParseError(f"{field} is too large, got {x!r}", path)
    elif (finite or integer) and not np.isfinite(x):
        raise MeshParseError(f"{field} must be finite, got {x!r}", path)
    if integer:
        if isinstance(x, (float, np.floating)) and float(x) != np.floor(float(x)):
            raise MeshParseError(f"{field} must be an integer, got {x!r}", path)
        x = int(x)
    elif not isinstance(x, float):
        x = float(x)
    if (low is not None and x < low) or (high is not None and x > high):
        bound = (f"between {low} and {high}" if low is not None and high is not None
                 else f">= {low}" if low is not None else f"<= {high}")
        raise MeshParseError(f"{field} must be {bound}, got {x!r}", path)
    return x


_KINDS = {"f": ("real numbers", "iuf", np.float64), "i": ("integers", "iu", np.int64),
          "c": ("numbers", "iufc", np.complex128), "b": ("booleans", "b", np.bool_)}


def _index_text(index) -> str:
    return "[" + ", ".join(str(int(i)) for i in index) + "]"


def check_array(value, path, field: str, *, kind: str = "f", shape=None, finite: bool = False, bounds=(None, None),
                dims: str | None = None) -> np.ndarray:
    """An array read from a file (an ``.npz`` array or JSON lists), checked; float64, int64, complex128 or bool.

    Parameters
    ----------
    value : array_like
        The value read.
    path : str
        The file, for messages.
    field : str
        The field or key, for messages.
    kind : {"f", "i", "c", "b"}, optional
        Real numbers, integers, real or complex numbers, booleans. JSON numbers with integral values
        are taken as integers; an ``.npz`` array must have an integer dtype.
    shape : tuple of (int or None), optional
        The required shape (None: any length on that axis); by default any.
    finite : bool, optional
        NaN and infinity are refused (the message names the first entry).
    bounds : (low, high) or (low, high, why), optional
        Inclusive bounds (indices: ``(0, n - 1)``; None: unbounded on that side); the message names the first
        entry outside, and ``why``, what the bounds are (``"rows of u, which has 5"``), when given.
    dims : str, optional
        The required shape in words for the message (``"(n_vertices, 3)"``).

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    MeshParseError
        Not a rectangular array of that kind, another shape, a non-finite entry or one out of range;
        the message names the file, the field and the entry.

    Examples
    --------
    >>> check_array([[0, 1], [2, 3]], "s.json", "faces", kind="i", shape=(None, 2), bounds=(0, 2, "3 vertices"))
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: s.json: faces[1, 1] = 3 is outside 0 .. 2 (3 vertices)
    >>> check_array([1.0, float("nan")], "v.json", "u", finite=True)
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: v.json: u[1] is not finite (nan)
    """
    path = os.fspath(path)
    name, kinds, dtype = _KINDS[kind]
    from_json = not isinstance(value, np.ndarray)
    if value is None or (from_json and isinstance(value, (str, bytes, dict, bool))):
        raise MeshParseError(f"{field} must be a list of {name}, got {describe(value)}", path)
    try:
        a = np.asarray(value)
    except (ValueError, TypeError, OverflowError):   # rows of different lengths, nesting too deep
        a = None
    if a is None or a.dtype.kind == "O":
        raise MeshParseError(f"{field} must be a rectangular array of {name} (rows of equal length, no null, "
                             "no number too large)", path)
    if a.size == 0 and a.dtype.kind not in kinds:
        a = a.astype(dtype)                           # [] from JSON is a float array
    if a.dtype.kind not in kinds:
        integral = (from_json and kind == "i" and a.dtype.kind == "f" and bool(np.all(np.isfinite(a)))
                    and bool(np.all(a == np.round(a))) and bool(np.all(np.abs(a) < 2.0**63)))
        if not integral:
            got = "text" if a.dtype.kind in "US" else f"{a.dtype} values"
            raise MeshParseError(f"{field} must hold {name}, got {got}", path)
    if shape is not None:
        ok = a.ndim == len(shape) and all(s is None or s == t for s, t in zip(shape, a.shape))
        if not ok:
            want = dims or "(" + ", ".join("k" if s is None else str(s) for s in shape) + ("," if len(shape) == 1
                                                                                          else "") + ")"
            raise MeshParseError(f"{field} must have shape {want}, got {a.shape}", path)
    a = a.astype(dtype, copy=False)
    if finite and kind in "fc" and a.size:
        bad = ~np.isfinite(a)
        if bad.any():
            idx = np.unravel_index(int(np.argmax(bad)), a.shape)
            raise MeshParseError(f"{field}{_index_text(idx)} is not finite ({a[idx].item()!r})", path)
    low, high, why = (*bounds, "")[:3]
    if (low is not None or high is not None) and a.size:
        with np.errstate(invalid="ignore"):
            bad = ((a < low) if low is not None else False) | ((a > high) if high is not None else False)
        bad = np.asarray(bad)
        if bad.any():
            idx = np.unravel_index(int(np.argmax(bad)), a.shape)
            rng = (f"outside {low} .. {high}" if low is not None and high is not None
                   else f"below {low}" if low is not None else f"above {high}")
            raise MeshParseError(f"{field}{_index_text(idx)} = {a[idx].item()!r} is {rng}"
                                 + (f" ({why})" if why else ""), path)
    return a


def check_repairs(items, path, field: str = "repairs") -> list:
    """The record of the repairs of a mesh (:meth:`dhlb.mesh.repair.MeshRepair.to_json`) read from a file, checked.

    Parameters
    ----------
    items : object
        The parsed JSON value (a list of objects with ``kind``, ``count``, ``message``, ``faces``,
        ``vertices`` and optionally ``value``).
    path : str
        The file, for messages.
    field : str, optional
        The field or key, for messages.

    Returns
    -------
    list of dict
        ``items``.

    Raises
    ------
    MeshParseError
        A wrong type anywhere; the message names the file and the entry.

    Examples
    --------
    >>> check_repairs([{"kind": "split", "count": "1", "message": ""}], "f.npz")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: f.npz: repairs[0].count must be an integer, got the string '1'
    """
    check_json_type(items, list, path, field)
    for k, r in enumerate(items):
        where = f"{field}[{k}]"
        check_json_type(r, dict, path, where)
        for key in ("kind", "count", "message"):
            if key not in r:
                raise MeshParseError(f"{where} has no {key!r}", os.fspath(path))
        check_json_type(r["kind"], str, path, f"{where}.kind")
        check_number(r["count"], path, f"{where}.count", integer=True, low=0)
        check_json_type(r["message"], str, path, f"{where}.message")
        for key in ("faces", "vertices"):
            check_array(r.get(key, []), path, f"{where}.{key}", kind="i", shape=(None,), bounds=(0, None))
        check_number(r.get("value"), path, f"{where}.value", optional=True)
    return items


def _npz_member_header(zf, info, path):
    """Shape and dtype that the header of one ``.npy`` member of an ``.npz`` announces, checked against its size."""
    from numpy.lib import format as npy

    key = info.filename[:-4]
    with zf.open(info) as fh:
        version = npy.read_magic(fh)
        if version == (1, 0):
            shape, _, dtype = npy.read_array_header_1_0(fh)
        elif version == (2, 0):
            shape, _, dtype = npy.read_array_header_2_0(fh)
        else:
            return None
        header = fh.tell()
    if dtype.hasobject:
        raise MeshParseError(f"the array {key!r} holds pickled Python objects; dhlb writes none and does not "
                             "load them (they can run code)", path)
    need = int(np.prod(shape, dtype=object)) * dtype.itemsize
    have = info.file_size - header
    if need != have:
        raise MeshParseError(f"the array {key!r} is damaged: its header announces {need} bytes of data "
                             f"({dtype} {tuple(shape)}), the archive holds {have}", path)
    return shape, dtype


# what zipfile, zlib and numpy.lib.format raise on a damaged archive (an unsupported compression or zip version:
# NotImplementedError; an encrypted member: RuntimeError)
_NPZ_ERRORS = (zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError, KeyError, NotImplementedError,
               RuntimeError, SyntaxError, tokenize.TokenError)   # numpy parses a .npy header as a Python literal


def _open_npz(path):
    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError as exc:
        raise MeshParseError(f"cannot be read ({exc.strerror or exc})", path) from None
    if not head:
        raise MeshParseError("the file is empty (0 bytes): not an .npz archive", path)
    if head.startswith(b"\x93NUMPY"):
        raise MeshParseError("a single .npy array, not an .npz archive of named arrays", path)
    if head.startswith(b"\x80"):
        raise MeshParseError("a pickle of Python objects, not an .npz archive; dhlb does not load pickles", path)
    if not head.startswith(b"PK"):
        raise MeshParseError(f"not an .npz archive (a zip of .npy arrays): it starts with {head[:8]!r}", path)
    try:
        zf = zipfile.ZipFile(path)
    except _NPZ_ERRORS as exc:
        raise MeshParseError(f"a damaged or truncated .npz archive ({type(exc).__name__}: {exc})", path) from None
    return zf


def npz_keys(path) -> set:
    """The names of the arrays in the ``.npz`` archive ``path`` (without reading them).

    Parameters
    ----------
    path : str or path-like
        The archive.

    Returns
    -------
    set of str

    Raises
    ------
    MeshParseError
        Not a readable ``.npz`` archive (empty, truncated, a single ``.npy``, a pickle, ...).
    """
    with _open_npz(path) as zf:
        names = zf.namelist()
    return {n[:-4] for n in names if n.endswith(".npy")}


def load_npz(path) -> dict:
    """The arrays of the ``.npz`` archive ``path``, checked as they are read (never pickled objects).

    Every member must be an ``.npy`` array whose header is readable, whose dtype holds no Python
    objects and whose size matches the data in the archive; then it is read with
    ``allow_pickle=False``.

    Parameters
    ----------
    path : str or path-like
        The archive.

    Returns
    -------
    dict of str to numpy.ndarray

    Raises
    ------
    MeshParseError
        Empty, truncated or damaged, not a zip archive (a single ``.npy``, a pickle, text), a member
        that is not an ``.npy`` array, pickled objects, or an array whose data is cut short; the
        message names the file (and the array).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "a.npz")
    ...     np.savez(p, x=np.arange(3))
    ...     load_npz(p)["x"].tolist()
    [0, 1, 2]
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "a.npz")
    ...     np.savez(p, x=np.array([{}], dtype=object))
    ...     load_npz(p)
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: .../a.npz: the array 'x' holds pickled Python objects; dhlb writes none ...
    """
    from numpy.lib import format as npy

    path = os.fspath(path)
    out = {}
    with _open_npz(path) as zf:
        key = None
        try:
            for info in zf.infolist():
                key = info.filename
                if not key.endswith(".npy"):
                    raise MeshParseError(f"the member {key!r} is not an .npy array: not an .npz of numpy", path)
                key = key[:-4]
                _npz_member_header(zf, info, path)
                with zf.open(info) as fh:
                    out[key] = npy.read_array(fh, allow_pickle=False)
                    if fh.read():       # to the end, where zipfile checks the CRC
                        raise ValueError("data after the array")
        except MeshParseError:
            raise
        except _NPZ_ERRORS as exc:
            what = f"the array {key!r} " if key is not None else ""
            raise MeshParseError(f"{what}cannot be read: a damaged or truncated .npz archive "
                                 f"({type(exc).__name__}: {exc})", path) from None
    return out
