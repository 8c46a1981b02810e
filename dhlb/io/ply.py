"""Stanford PLY triangle meshes: ASCII, binary little- and big-endian, any extra properties.

Only the ``vertex`` coordinates ``x y z`` and the ``face`` list ``vertex_indices`` (or
``vertex_index``) are returned; every other element and property is parsed and skipped.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import MeshParseError, ShapeError
from dhlb.io._text import (
    check_cells,
    check_finite,
    fan_triangulate,
    format_number_rows,
    no_gc,
    prepare_write,
    to_array,
    to_flat_int,
)

if TYPE_CHECKING:
    from collections.abc import Mapping

    from numpy.typing import ArrayLike

__all__ = ["read_ply", "write_ply"]

_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}  # fmt: skip
_FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}
_FACE_LISTS = ("vertex_indices", "vertex_index")


@dataclass
class _Prop:
    name: str
    dtype: str
    count_dtype: str | None = None  # set for list properties


@dataclass
class _Element:
    name: str
    count: int
    line: int
    props: list[_Prop] = field(default_factory=list)


def _parse_header(data: bytes, path: str):
    """Return (byte order or None for ASCII, elements, byte offset of the body, header line count)."""
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise MeshParseError("not a PLY file: it must start with 'ply' and have an 'end_header' line", path, 1)
    stop = data.find(b"\n", end)
    body = len(data) if stop < 0 else stop + 1
    lines = data[:body].decode("ascii", errors="replace").splitlines()
    order, elements = "missing", []
    for number, text in enumerate(lines, 1):
        toks = text.split()
        if not toks or toks[0] in ("ply", "comment", "obj_info", "end_header"):
            continue
        if toks[0] == "format":
            if len(toks) != 3 or toks[1] not in _FORMATS:
                raise MeshParseError(f"unknown PLY format line {text.strip()!r}", path, number)
            order = _FORMATS[toks[1]]
        elif toks[0] == "element":
            if len(toks) != 3 or not toks[2].isdigit():
                raise MeshParseError(f"expected 'element <name> <count>', got {text.strip()!r}", path, number)
            if toks[1] in [e.name for e in elements]:
                raise MeshParseError(f"element '{toks[1]}' is declared twice", path, number)
            elements.append(_Element(toks[1], int(toks[2]), number))
        elif toks[0] == "property":
            if not elements:
                raise MeshParseError("a property line comes before any element line", path, number)
            if len(toks) == 5 and toks[1] == "list" and toks[2] in _TYPES and toks[3] in _TYPES:
                if _TYPES[toks[2]][0] == "f":
                    raise MeshParseError("a list count must have an integer type", path, number)
                elements[-1].props.append(_Prop(toks[4], _TYPES[toks[3]], _TYPES[toks[2]]))
            elif len(toks) == 3 and toks[1] in _TYPES:
                elements[-1].props.append(_Prop(toks[2], _TYPES[toks[1]]))
            else:
                raise MeshParseError(f"cannot understand the property line {text.strip()!r}", path, number)
            if [p.name for p in elements[-1].props].count(toks[-1]) > 1:
                raise MeshParseError(f"property {toks[-1]!r} is declared twice in element '{elements[-1].name}'",
                                     path, number)  # fmt: skip
        else:
            raise MeshParseError(f"unknown PLY header keyword {toks[0]!r}", path, number)
    if order == "missing":
        raise MeshParseError("the header has no 'format' line", path)
    return order, elements, body, len(lines)


# ---------------------------------------------------------------------------------- ASCII body
def _ascii_element(lines, elem: _Element, path: str) -> dict:
    """Parse one element from an iterator of (line, tokens); return {prop: values or (flat, sizes, lines)}."""
    rows, numbers = [], []
    for i in range(elem.count):
        nxt = next(lines, None)
        if nxt is None:
            raise MeshParseError(f"the file ends after {i} of {elem.count} '{elem.name}' lines", path)
        numbers.append(nxt[0])
        rows.append(nxt[1])
    has_list = any(p.count_dtype for p in elem.props)
    if not rows:
        empty = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64))
        out = {p.name: empty if p.count_dtype else np.zeros(0) for p in elem.props}
        out["__lines__"] = np.zeros(0, np.int64)
        return out
    if not has_list:
        bad = [i for i, r in enumerate(rows) if len(r) != len(elem.props)]
        if bad:
            raise MeshParseError(
                f"'{elem.name}' line has {len(rows[bad[0]])} values, the header declares {len(elem.props)}",
                path, numbers[bad[0]],
            )
        values = to_array(rows, numbers, np.float64, path, f"'{elem.name}' value")
        out = {p.name: values[:, j] for j, p in enumerate(elem.props)}
        out["__lines__"] = np.asarray(numbers)
        return out
    fast = _ascii_fixed_layout(rows, numbers, elem, path)
    if fast is not None:
        return fast
    out: dict = {p.name: ([], []) for p in elem.props}
    for toks, number in zip(rows, numbers):
        pos = 0
        to_array([toks], [number], np.float64, path, f"'{elem.name}' value")
        for p in elem.props:
            if pos >= len(toks):
                raise MeshParseError(f"'{elem.name}' line is too short for its declared properties", path, number)
            if p.count_dtype is None:
                out[p.name][0].append(toks[pos])
                pos += 1
                continue
            count = int(to_array([[toks[pos]]], [number], np.int64, path, "list length")[0, 0])
            if count < 0 or pos + 1 + count > len(toks):
                raise MeshParseError(
                    f"'{elem.name}' list '{p.name}' declares {count} entries but the line has fewer", path, number
                )
            out[p.name][0].append(toks[pos + 1 : pos + 1 + count])
            out[p.name][1].append(count)
            pos += 1 + count
        if pos != len(toks):
            raise MeshParseError(
                f"'{elem.name}' line has {len(toks) - pos} values more than its declared properties", path, number
            )
    result = {"__lines__": np.asarray(numbers)}
    for p in elem.props:
        vals, sizes = out[p.name]
        if p.count_dtype is None:
            result[p.name] = np.array(vals, dtype=np.float64)
        else:
            if p.dtype[0] == "f":
                flat = np.array([float(t) for row in vals for t in row], dtype=np.float64)  # validated above
            else:
                flat = to_flat_int(vals, numbers, path, f"'{p.name}' entry")
            result[p.name] = (flat, np.asarray(sizes, dtype=np.int64), np.asarray(numbers))
    return result


def _ascii_fixed_layout(rows, numbers, elem: _Element, path: str):
    """Fast path: every line has the same length and the same list lengths as the first one.

    Returns the parsed element, or None when the lines differ (the caller then walks them one by one).
    """
    if not rows or any(len(r) != len(rows[0]) for r in rows):
        return None
    table = to_array(rows, numbers, np.float64, path, f"'{elem.name}' value")
    layout, pos = [], 0
    for p in elem.props:
        if pos >= table.shape[1]:
            return None
        if p.count_dtype is None:
            layout.append((p, pos, None))
            pos += 1
            continue
        count = table[0, pos]
        if not np.isfinite(count) or count < 0 or count != int(count):
            return None
        layout.append((p, pos, int(count)))
        pos += 1 + int(count)
    if pos != table.shape[1] or any(c is not None and np.any(table[:, at] != c) for _, at, c in layout):
        return None
    out = {"__lines__": np.asarray(numbers)}
    for p, at, count in layout:
        if count is None:
            out[p.name] = table[:, at]
            continue
        vals = table[:, at + 1 : at + 1 + count]
        if p.dtype[0] != "f":
            frac = np.flatnonzero(np.any((vals != np.round(vals)) | ~np.isfinite(vals), axis=1))
            if frac.size:  # report the token as written
                i = int(frac[0])
                to_array([rows[i][at + 1 : at + 1 + count]], [numbers[i]], np.int64, path, f"'{p.name}' entry")
        out[p.name] = (vals.ravel(), np.full(len(rows), count, dtype=np.int64), np.asarray(numbers))
    return out


# --------------------------------------------------------------------------------- binary body
def _binary_element(data: bytes, pos: int, elem: _Element, order: str, path: str):
    """Parse one binary element at byte ``pos``; return ({prop: values or (flat, sizes, None)}, new pos)."""
    n = elem.count
    if not any(p.count_dtype for p in elem.props):
        dt = np.dtype([(f"p{j}", order + p.dtype) for j, p in enumerate(elem.props)])
        _need(data, pos, n * dt.itemsize, elem, path)
        arr = np.frombuffer(data, dtype=dt, count=n, offset=pos)
        return {p.name: arr[f"p{j}"] for j, p in enumerate(elem.props)}, pos + n * dt.itemsize
    if n == 0:
        return {p.name: (np.zeros(0, np.int64), np.zeros(0, np.int64), None) if p.count_dtype else np.zeros(0)
                for p in elem.props}, pos
    # fast path: every instance has the same list lengths as the first one
    fields, cur = [], pos
    for j, p in enumerate(elem.props):
        if p.count_dtype is None:
            fields.append((f"p{j}", order + p.dtype))
            cur += np.dtype(p.dtype).itemsize
            continue
        _need(data, cur, np.dtype(p.count_dtype).itemsize, elem, path)
        c = int(np.frombuffer(data, order + p.count_dtype, 1, cur)[0])
        if c < 0:
            raise MeshParseError(f"'{elem.name}' 0 has a negative list length {c}", path)
        fields.append((f"n{j}", order + p.count_dtype))
        fields.append((f"p{j}", order + p.dtype, (c,)))
        cur += np.dtype(p.count_dtype).itemsize + c * np.dtype(p.dtype).itemsize
    dt = np.dtype(fields)
    if len(data) - pos >= n * dt.itemsize:
        arr = np.frombuffer(data, dtype=dt, count=n, offset=pos)
        counts = {j: arr[f"n{j}"] for j, p in enumerate(elem.props) if p.count_dtype}
        first = {j: dt[f"p{j}"].shape[0] for j in counts}
        if all(np.all(counts[j] == first[j]) for j in counts):
            out = {}
            for j, p in enumerate(elem.props):
                vals = arr[f"p{j}"]
                out[p.name] = vals if p.count_dtype is None else (
                    vals.reshape(-1), np.full(n, first[j], dtype=np.int64), None)
            return out, pos + n * dt.itemsize
    return _binary_element_slow(data, pos, elem, order, path)


def _binary_element_slow(data: bytes, pos: int, elem: _Element, order: str, path: str):
    """Instance-by-instance walk for lists of varying length (offsets only; values gathered at once)."""
    starts = {j: [] for j in range(len(elem.props))}
    counts = {j: [] for j in range(len(elem.props))}
    sizes = [np.dtype(p.dtype).itemsize for p in elem.props]
    csizes = [np.dtype(p.count_dtype).itemsize if p.count_dtype else 0 for p in elem.props]
    for i in range(elem.count):
        for j, p in enumerate(elem.props):
            if p.count_dtype is None:
                _need(data, pos, sizes[j], elem, path, i)
                starts[j].append(pos)
                pos += sizes[j]
                continue
            _need(data, pos, csizes[j], elem, path, i)
            c = int(np.frombuffer(data, order + p.count_dtype, 1, pos)[0])
            if c < 0:
                raise MeshParseError(f"'{elem.name}' {i} has a negative list length {c}", path)
            pos += csizes[j]
            _need(data, pos, c * sizes[j], elem, path, i)
            starts[j].append(pos)
            counts[j].append(c)
            pos += c * sizes[j]
    raw = np.frombuffer(data, dtype=np.uint8)
    out = {}
    for j, p in enumerate(elem.props):
        st = np.asarray(starts[j], dtype=np.int64)
        c = np.asarray(counts[j], dtype=np.int64) if p.count_dtype else np.ones(len(st), np.int64)
        item_start = np.repeat(st, c) + sizes[j] * (np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c))
        byte_idx = item_start[:, None] + np.arange(sizes[j])[None, :]
        vals = raw[byte_idx.ravel()].view(order + p.dtype) if byte_idx.size else np.zeros(0, p.dtype)
        out[p.name] = vals if p.count_dtype is None else (vals, c, None)
    return out, pos


def _need(data: bytes, pos: int, nbytes: int, elem: _Element, path: str, instance: int | None = None) -> None:
    if pos + nbytes > len(data):
        which = f" (at instance {instance} of {elem.count})" if instance is not None else ""
        raise MeshParseError(
            f"the file is truncated inside element '{elem.name}'{which}: {pos + nbytes - len(data)} bytes missing",
            path,
        )


# ---------------------------------------------------------------------------------- public API
@no_gc
def read_ply(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a PLY triangle mesh (ASCII or binary, either byte order, any extra properties).

    Returns
    -------
    V : (n, 3) float64
        The ``x y z`` properties of the ``vertex`` element.
    F : (m, 3) int64
        The ``face`` element's ``vertex_indices`` lists, fan-triangulated, 0-based.

    Raises
    ------
    MeshParseError
        Bad header, truncated body, unreadable value, missing ``x y z`` or face list, index out
        of range. ASCII errors name the line; binary errors name the element instance.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_ply, write_ply
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]); F = np.array([[0, 1, 2], [1, 3, 2]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_ply(os.path.join(d, "q.ply"), V, F, binary=True, byteorder=">")
    ...     V2, F2 = read_ply(os.path.join(d, "q.ply"))
    >>> F2.tolist()
    [[0, 1, 2], [1, 3, 2]]
    """
    path = os.fspath(path)
    with open(path, "rb") as fh:
        data = fh.read()
    if not data.strip():
        raise MeshParseError("the file is empty", path)
    order, elements, body, n_header = _parse_header(data, path)
    names = [e.name for e in elements]
    for required in ("vertex", "face"):
        if required not in names:
            raise MeshParseError(f"the header declares no '{required}' element", path)
    vert = elements[names.index("vertex")]
    face = elements[names.index("face")]
    missing = [c for c in "xyz" if c not in [p.name for p in vert.props]]
    if missing:
        raise MeshParseError(f"the 'vertex' element has no property {missing[0]!r}", path, vert.line)
    flist = [p for p in face.props if p.name in _FACE_LISTS and p.count_dtype]
    if not flist:
        raise MeshParseError("the 'face' element has no list property 'vertex_indices'", path, face.line)
    if flist[0].dtype[0] == "f":
        raise MeshParseError(f"the face list '{flist[0].name}' must have an integer type", path, face.line)
    parsed = {}
    if order is None:
        text = data[body:].decode("utf-8", errors="replace").splitlines()
        lines = ((k, t.split()) for k, t in enumerate(text, n_header + 1) if t.strip())
        for e in elements:
            parsed[e.name] = _ascii_element(lines, e, path)
        extra = next(lines, None)
        if extra is not None:
            raise MeshParseError("unexpected data after the last declared element", path, extra[0])
    else:
        pos = body
        for e in elements:
            parsed[e.name], pos = _binary_element(data, pos, e, order, path)
    v = parsed["vertex"]
    V = np.column_stack([np.asarray(v[c], dtype=np.float64) for c in "xyz"]).reshape(-1, 3)
    flat, sizes, line_of_face = parsed["face"][flist[0].name]
    flat = np.asarray(flat).astype(np.int64)
    if np.any(sizes < 3):
        i = int(np.flatnonzero(sizes < 3)[0])
        where = (path, int(line_of_face[i])) if line_of_face is not None else (path, None)
        label = "face" if line_of_face is not None else f"face {i}"
        raise MeshParseError(f"{label} has {sizes[i]} vertices; a face needs at least 3", *where)
    vlines = v.get("__lines__")
    check_finite(V, path, vlines)
    F, poly = fan_triangulate(flat, sizes)
    check_cells(F, V.shape[0], path, None if line_of_face is None else line_of_face[poly])
    if F.shape[0] == 0:
        raise MeshParseError("the file has no faces; a surface mesh needs faces", path)
    return V, F


def write_ply(
    path: str | os.PathLike[str],
    V: ArrayLike,
    F: ArrayLike,
    binary: bool = False,
    byteorder: str = "<",
    vertex_properties: Mapping[str, ArrayLike] | None = None,
) -> None:
    """Write a mesh as PLY: ``double x y z`` per vertex, ``list uchar int vertex_indices`` per face.

    Parameters
    ----------
    vertex_properties : dict of name -> (n,) float array, optional
        Extra ``double`` vertex properties (e.g. direction components), written after ``x y z``.
    binary : bool
        Binary body instead of ASCII.
    byteorder : {'<', '>'}
        Little or big endian (binary only).

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_ply, write_ply
    >>> V = np.array([[0.1, 0, 0], [1, 0, 0], [0, 1, 0]]); F = np.array([[0, 1, 2]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_ply(os.path.join(d, "t.ply"), V, F)
    ...     print(open(os.path.join(d, "t.ply")).read().splitlines()[-2:])
    ['0.0 1.0 0.0', '3 0 1 2']
    """
    V, F = prepare_write(V, F, min_corners=3)
    if F.shape[1] > 255:
        raise MeshParseError(f"faces with {F.shape[1]} corners do not fit a uchar list length", os.fspath(path))
    if byteorder not in ("<", ">"):
        raise ValueError(f"byteorder must be '<' or '>', got {byteorder!r}")
    fmt = "ascii" if not binary else ("binary_little_endian" if byteorder == "<" else "binary_big_endian")
    extra = {str(k): np.asarray(a, dtype=np.float64) for k, a in (vertex_properties or {}).items()}
    for k, a in extra.items():
        if a.shape != (len(V),) or not k.isidentifier() or k in ("x", "y", "z"):
            raise ShapeError(f"vertex property {k!r} must be a new identifier with shape ({len(V)},), got {a.shape}")
    V = np.column_stack([V] + list(extra.values()))
    header = (
        f"ply\nformat {fmt} 1.0\ncomment written by dhlb\nelement vertex {len(V)}\n"
        "property double x\nproperty double y\nproperty double z\n"
        + "".join(f"property double {k}\n" for k in extra)
        + f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(os.fspath(path), "wb") as fh:
        fh.write(header.encode("ascii"))
        if not binary:
            fh.write(format_number_rows(V, "%r").encode("ascii"))
            sized = np.column_stack([np.full(len(F), F.shape[1], dtype=np.int64), F])
            fh.write(format_number_rows(sized, "%d").encode("ascii"))
            return
        fh.write(V.astype(byteorder + "f8").tobytes())
        faces = np.zeros(len(F), dtype=[("n", "u1"), ("v", byteorder + "i4", (F.shape[1],))])
        faces["n"] = F.shape[1]
        faces["v"] = F
        fh.write(faces.tobytes())
