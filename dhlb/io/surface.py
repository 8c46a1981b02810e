"""Triangle surface meshes: Wavefront OBJ and OFF readers and writers, and the surface dispatcher.

Polygons are fan-triangulated ``(p0, p_j, p_{j+1})`` in file order; indices are returned 0-based.
PLY lives in :mod:`dhlb.io.ply`; the volume formats (``.mesh``, ``.msh``, ``.vtk``) are read
here as surfaces when they hold triangles but no tetrahedra.
"""

from __future__ import annotations

import os
import re
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import MeshParseError
from dhlb.io._text import (
    check_cells,
    check_finite,
    content_lines,
    fan_triangulate,
    format_number_rows,
    no_gc,
    prepare_write,
    read_text,
    to_array,
    to_flat_int,
)
from dhlb.io.atomic import atomic_write
from dhlb.io.formats import format_of
from dhlb.io.ply import read_ply, write_ply
from dhlb.io.volume import read_cells, write_cells

if TYPE_CHECKING:
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["read_obj", "write_obj", "read_off", "write_off", "read_surface", "write_surface"]

# OBJ statements that carry nothing a triangle mesh needs (texture, normals, grouping, materials,
# free-form geometry, display attributes). Any other statement is an error.
_OBJ_IGNORED = frozenset(
    "vt vn vp l p o g s mg usemtl mtllib usemap maplib lod bevel c_interp d_interp shadow_obj "
    "trace_obj ctech stech cstype deg bmat step curv curv2 surf parm trim hole scrv sp end con".split()
)


@no_gc
def read_obj(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a Wavefront OBJ file as a triangle mesh.

    Supports ``v x y z [w | r g b]``, faces ``f`` with ``i``, ``i/t``, ``i//n`` or ``i/t/n``
    corners, negative (relative) indices and polygons (fan-triangulated in file order).
    Texture coordinates, normals, groups and materials are skipped; ``l`` and ``p`` elements
    are ignored.

    Parameters
    ----------
    path : str or path-like
        The file to read.

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64, 0-based

    Raises
    ------
    MeshParseError
        Unknown statement, unreadable token, face with fewer than 3 corners, index 0 or out of
        range, repeated vertex in a face, or no faces; the message names the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_obj, example_path
    >>> V, F = read_obj(example_path("torus.obj"))
    >>> V.shape, F.shape, F.dtype
    ((288, 3), (576, 3), dtype('int64'))
    """
    path = os.fspath(path)
    text = read_text(path)
    vrows, vlines = [], []
    corners, sizes, flines, n_seen = [], [], [], []
    for line, toks in content_lines(text):
        key = toks[0]
        if key == "v":
            if len(toks) < 4:
                raise MeshParseError(f"a vertex needs 3 coordinates, got {len(toks) - 1}", path, line)
            if len(toks) > 4:  # weight or colour: must still be numbers
                to_array([toks[4:]], [line], np.float64, path, "vertex value")
            vrows.append(toks[1:4])
            vlines.append(line)
        elif key == "f":
            if len(toks) < 4:
                raise MeshParseError(
                    f"a face needs at least 3 vertices, got {len(toks) - 1}; remove or fix this line", path, line
                )
            corners.extend(t.split("/", 1)[0] for t in toks[1:])
            sizes.append(len(toks) - 1)
            flines.append(line)
            n_seen.append(len(vrows))
        elif key not in _OBJ_IGNORED:
            raise MeshParseError(f"unknown OBJ statement {key!r}; is this an OBJ file?", path, line)
    if not vrows and not sizes:
        raise MeshParseError("no vertices and no faces found; is this an OBJ file?", path)
    if not sizes:
        raise MeshParseError("no faces ('f' lines) found; a surface mesh needs faces", path)
    V = to_array(vrows, vlines, np.float64, path, "vertex coordinate").reshape(-1, 3)
    check_finite(V, path, vlines, first_number=1)
    sizes_a = np.asarray(sizes, dtype=np.int64)
    corner_line = np.repeat(np.asarray(flines), sizes_a)
    try:
        flat = np.array(corners, dtype=np.int64)
    except (ValueError, OverflowError):  # locate the bad token for the message
        flat = to_flat_int([[c] for c in corners], corner_line, path, "vertex index")
    zero = np.flatnonzero(flat == 0)
    if zero.size:
        raise MeshParseError("vertex index 0 is invalid: OBJ numbers vertices from 1", path, int(corner_line[zero[0]]))
    seen = np.repeat(np.asarray(n_seen, dtype=np.int64), sizes_a)
    neg = flat < 0
    bad = np.flatnonzero(neg & (-flat > seen))
    if bad.size:
        i = int(bad[0])
        raise MeshParseError(
            f"relative index {flat[i]} points before the first vertex (only {seen[i]} vertices so far)",
            path,
            int(corner_line[i]),
        )
    flat = np.where(neg, flat + seen, flat - 1)
    F, poly = fan_triangulate(flat, sizes_a)
    check_cells(F, V.shape[0], path, np.asarray(flines)[poly], first_number=1)
    return V, F


def write_obj(path: str | os.PathLike[str], V: ArrayLike, F: ArrayLike) -> None:
    """Write a triangle (or polygon) mesh as OBJ, 1-based, coordinates exact (shortest repr).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    F : (m, k) int array
        0-based faces with ``k >= 3`` corners each (triangles: ``k = 3``).

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
    >>> from dhlb.io import read_obj, write_obj
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]); F = np.array([[0, 1, 2]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_obj(os.path.join(d, "t.obj"), V, F)
    ...     V2, F2 = read_obj(os.path.join(d, "t.obj"))
    >>> bool((V2 == V).all() and (F2 == F).all())
    True
    """
    V, F = prepare_write(V, F, min_corners=3)
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write("# written by dhlb\n")
        fh.write(format_number_rows(V, "%r", prefix="v "))
        fh.write(format_number_rows(F + 1, "%d", prefix="f "))


_OFF_HEADER = re.compile(r"^(ST)?(C)?(N)?(4)?(n)?OFF$")


@no_gc
def read_off(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    r"""Read an OFF file (also ``COFF``, ``NOFF``, ``STOFF``... : extra vertex/face values are skipped).

    Faces are ``k i_1 .. i_k [colour]`` with 0-based indices; polygons are fan-triangulated.

    Parameters
    ----------
    path : str or path-like
        The file to read.

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64

    Raises
    ------
    MeshParseError
        Missing header or counts, too few lines, short or unreadable lines, bad indices,
        extra data after the last face; the message names the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_off
    >>> text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "t.off"); _ = open(p, "w").write(text)
    ...     V, F = read_off(p)
    >>> F.tolist()
    [[0, 1, 2]]
    """
    path = os.fspath(path)
    lines = content_lines(read_text(path))
    first = next(lines, None)
    if first is None:
        raise MeshParseError("the file is empty; an OFF file starts with 'OFF'", path)
    line, toks = first
    head = _OFF_HEADER.match(toks[0])
    if head is None:
        raise MeshParseError(f"expected the header 'OFF', found {toks[0]!r}; is this an OFF file?", path, line)
    if head.group(4) or head.group(5):
        raise MeshParseError(f"{toks[0]} (non-3D OFF) is not supported", path, line)
    rest = toks[1:]
    if rest and rest[0].upper() == "BINARY":
        raise MeshParseError("binary OFF is not supported; convert the file to ASCII OFF", path, line)
    if not rest:
        nxt = next(lines, None)
        if nxt is None:
            raise MeshParseError("the file ends after the header; expected 'n_vertices n_faces n_edges'", path)
        line, rest = nxt
    if len(rest) not in (2, 3):
        raise MeshParseError(f"expected 'n_vertices n_faces n_edges', got {' '.join(rest)!r}", path, line)
    nv, nf = (int(x) for x in to_array([rest[:2]], [line], np.int64, path, "count")[0])
    if nv < 0 or nf < 0:
        raise MeshParseError("negative vertex or face count", path, line)
    body = list(lines)
    if len(body) < nv:
        raise MeshParseError(f"the file ends after {len(body)} of {nv} vertices", path)
    if len(body) < nv + nf:
        raise MeshParseError(f"the file ends after {len(body) - nv} of {nf} faces", path)
    if len(body) > nv + nf:
        raise MeshParseError(f"unexpected data after the {nf} declared faces", path, body[nv + nf][0])
    if nf == 0:
        raise MeshParseError("the file declares no faces; a surface mesh needs faces", path)
    vlines = [ln for ln, _ in body[:nv]]
    short = [ln for ln, t in body[:nv] if len(t) < 3]
    if short:
        raise MeshParseError("a vertex needs 3 coordinates", path, short[0])
    vrows = [t[:3] for _, t in body[:nv]]
    faces = body[nv:]
    flines = np.array([ln for ln, _ in faces], dtype=np.int64)
    sizes = to_flat_int([t[:1] for _, t in faces], flines, path, "face size")
    lengths = np.fromiter((len(t) for _, t in faces), dtype=np.int64, count=nf)
    bad = np.flatnonzero((sizes < 3) | (lengths < sizes + 1))
    if bad.size:
        i = int(bad[0])
        msg = (f"a face needs at least 3 vertices, this one declares {sizes[i]}" if sizes[i] < 3
               else f"the face declares {sizes[i]} vertices but lists {lengths[i] - 1}")  # fmt: skip
        raise MeshParseError(msg, path, int(flines[i]))
    if np.all(lengths == sizes + 1):
        corners = [t[1:] for _, t in faces]
    else:  # trailing colour values
        corners = [t[1 : k + 1] for (_, t), k in zip(faces, sizes.tolist())]
    V = to_array(vrows, vlines, np.float64, path, "vertex coordinate").reshape(-1, 3)
    check_finite(V, path, vlines)
    flat = to_flat_int(corners, flines, path, "vertex index")
    F, poly = fan_triangulate(flat, np.asarray(sizes))
    check_cells(F, V.shape[0], path, np.asarray(flines)[poly])
    return V, F


def write_off(path: str | os.PathLike[str], V: ArrayLike, F: ArrayLike) -> None:
    """Write a triangle (or polygon) mesh as ASCII OFF (0-based, exact coordinates).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    F : (m, k) int array
        0-based faces with ``k >= 3`` corners each (triangles: ``k = 3``).

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
    >>> from dhlb.io import read_off, write_off
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_off(os.path.join(d, "t.off"), V, F)
    ...     V2, F2 = read_off(os.path.join(d, "t.off"))
    >>> bool((V2 == V).all() and (F2 == F).all())
    True
    """
    V, F = prepare_write(V, F, min_corners=3)
    sized = np.column_stack([np.full(len(F), F.shape[1], dtype=np.int64), F])
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write(f"OFF\n{len(V)} {len(F)} 0\n")
        fh.write(format_number_rows(V, "%r"))
        fh.write(format_number_rows(sized, "%d"))


def read_surface(path: str | os.PathLike[str], fmt: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a triangle surface mesh, choosing the reader from the extension (or ``fmt``).

    Formats: ``obj``, ``off``, ``ply``; also ``mesh`` / ``msh`` / ``vtk`` files that contain
    triangles and no tetrahedra.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    fmt : str, optional
        The format name (or extension) to use instead of the extension of ``path``
        (:func:`~dhlb.io.format_of`); ``"meshio"`` reads the triangles of any format meshio reads.

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64, 0-based. Unreferenced vertices are kept (see :func:`dhlb.io.compact_mesh`).

    Raises
    ------
    MeshParseError
        Unknown format or one that holds no surfaces, a volume file with tetrahedra, a file without
        triangles, or the errors of the reader of the format (which name the line).
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> len(V) - len({tuple(sorted(e)) for f in F.tolist() for e in zip(f, f[1:] + f[:1])}) + len(F)
    0
    """
    fmt = format_of(path, fmt)
    if fmt == "meshio":  # a format only meshio reads (e.g. .vtu, .stl): its triangles
        from dhlb.io.meshio_bridge import read_with_meshio

        return read_with_meshio(path)
    if fmt == "obj":
        return read_obj(path)
    if fmt == "off":
        return read_off(path)
    if fmt == "ply":
        return read_ply(path)
    if fmt in ("mesh", "msh", "vtk"):
        V, cells = read_cells(path, fmt)
        if 3 in cells:
            raise MeshParseError(f"a volume mesh ({len(cells[3])} tetrahedra), not a surface", os.fspath(path),
                                 found="volume")
        if 2 not in cells:
            raise MeshParseError("the file contains no triangles", os.fspath(path))
        return V, cells[2]
    raise MeshParseError(f"{fmt!r} files are not surface meshes (use obj, off, ply)", os.fspath(path))


def write_surface(
    path: str | os.PathLike[str], V: ArrayLike, F: ArrayLike, fmt: str | None = None, **kwargs: Any
) -> None:
    """Write a triangle mesh; the format comes from the extension (``obj``, ``off``, ``ply``) or ``fmt``.

    Extra keyword arguments go to the writer (e.g. ``binary=True`` for PLY).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    F : (m, 3) int array
        0-based triangles.
    fmt : str, optional
        ``"obj"``, ``"off"``, ``"ply"``, or ``"mesh"``, ``"msh"``, ``"vtk"`` (a surface in a volume format);
        default: from the extension of ``path``.
    **kwargs
        Passed to the writer of the format (:func:`write_obj`, :func:`write_off`, :func:`~dhlb.io.write_ply`,
        :func:`~dhlb.io.write_cells`).

    Returns
    -------
    None
        The writers return nothing.

    Raises
    ------
    MeshParseError
        Unknown format, or one that cannot store a surface.
    InvalidSimplexError, NonFiniteError, OutputError
        As the writer of the format: bad arrays, NaN/inf coordinates, a file that cannot be written.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_surface, write_surface
    >>> V = np.eye(3); F = np.array([[0, 1, 2]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_surface(os.path.join(d, "t.ply"), V, F, binary=True)
    ...     print(read_surface(os.path.join(d, "t.ply"))[1])
    [[0 1 2]]
    """
    fmt = format_of(path, fmt)
    if fmt == "obj":
        return write_obj(path, V, F, **kwargs)
    if fmt == "off":
        return write_off(path, V, F, **kwargs)
    if fmt == "ply":
        return write_ply(path, V, F, **kwargs)
    if fmt in ("mesh", "msh", "vtk"):
        return write_cells(path, V, {2: F}, fmt, **kwargs)
    raise MeshParseError(f"cannot write a surface as {fmt!r} (use obj, off, ply, mesh, msh, vtk)", os.fspath(path))
