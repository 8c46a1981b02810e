"""Stanford PLY triangle meshes: ASCII, binary little- and big-endian, any extra properties.

Only the ``vertex`` coordinates ``x y z`` and the ``face`` list ``vertex_indices`` (or
``vertex_index``) are returned; every other element and property is parsed and skipped.
The header is parsed here; the body readers (ASCII, binary) are in :mod:`dhlb.io._ply_body`.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidParameterError, MeshParseError, ShapeError
from dhlb.io._ply_body import _Element, _Prop, ascii_element, binary_element
from dhlb.io._text import (
    check_cells,
    check_finite,
    fan_triangulate,
    format_number_rows,
    no_gc,
    prepare_write,
    strip_bom,
)
from dhlb.io.atomic import atomic_write

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


# ---------------------------------------------------------------------------------- public API
@no_gc
def read_ply(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a PLY triangle mesh (ASCII or binary, either byte order, any extra properties).

    Parameters
    ----------
    path : str or path-like
        The file.

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
        of range, data after the declared elements. ASCII errors name the line; binary errors
        name the element instance and the byte offset. A leading UTF-8 byte-order mark is skipped.
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
        data = strip_bom(fh.read(), path)
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
            parsed[e.name] = ascii_element(lines, e, path)
        extra = next(lines, None)
        if extra is not None:
            raise MeshParseError("unexpected data after the last declared element", path, extra[0])
    else:
        pos = body
        for e in elements:
            parsed[e.name], pos = binary_element(data, pos, e, order, path)
        if data[pos:].strip(b" \t\r\n"):
            raise MeshParseError(
                f"{len(data) - pos} bytes of unexpected data after the last declared element "
                f"'{elements[-1].name}' (from byte {pos}); the header declares fewer elements than the file "
                "holds, or the file is corrupt",
                path,
            )
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
    path : str or path-like
        The file (written atomically).
    V : (n, 3) float array
        Vertex positions.
    F : (m, k) int array
        Faces (rows of ``V``), ``3 <= k <= 255`` corners.
    binary : bool
        Binary body instead of ASCII.
    byteorder : {'<', '>'}
        Little or big endian (binary only).
    vertex_properties : dict of name -> (n,) float array, optional
        Extra ``double`` vertex properties (e.g. direction components), written after ``x y z``.

    Raises
    ------
    ShapeError, NonFiniteError, InvalidSimplexError
        Bad ``V`` or ``F`` (see :func:`dhlb.io.write_surface`); a vertex property that is not a new
        identifier with one value per vertex.
    MeshParseError
        Faces of more than 255 corners.
    InvalidParameterError
        ``byteorder`` is not ``'<'`` or ``'>'``.

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
        raise InvalidParameterError(f"byteorder must be '<' or '>', got {byteorder!r}")
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
    with atomic_write(path, "wb") as fh:
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
