"""Polylines as files: OBJ ``l`` records and PLY edges (vortex filaments, stripe isolines), and OBJ with corner UVs.

One writer per format, for every kind of curve network: :func:`write_lines_obj` takes points and index
polylines (curves that share vertices, like the isolines of a stripe pattern, keep them shared);
:func:`write_polylines_obj` and :func:`write_polylines_ply` take separate curves (vortex filaments).
The readers: :func:`read_polylines_obj`, :func:`read_polylines_ply`, :func:`read_uv_obj` (the
per-corner texture coordinates of a stripe pattern OBJ) and :func:`read_vortex` (the filaments of
``dhlb vortex`` or ``dhlb demo`` as a :class:`LoadedVortex`).

Examples
--------
>>> import os, tempfile
>>> import numpy as np
>>> with tempfile.TemporaryDirectory() as d:
...     p = write_polylines_obj(os.path.join(d, "f.obj"), [(np.eye(3), True)])
...     [c.tolist() for c in read_polylines_obj(p)][0][-1]
[1.0, 0.0, 0.0]
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb._coerce import curve_list
from dhlb._files import atomic_write
from dhlb._result import Result
from dhlb.errors import MeshParseError

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

__all__ = ["LoadedVortex", "read_polylines_obj", "read_polylines_ply", "read_uv_obj", "read_vortex", "write_lines_obj",
           "write_polylines_obj", "write_polylines_ply"]


def write_lines_obj(path: str | os.PathLike[str], points, polylines: Iterable[Sequence[int]], *,
                    comment: str = "dhlb polylines") -> str:
    """Write a curve network as an OBJ: ``v x y z`` lines, then one ``l i j k …`` per polyline (1-based).

    Parameters
    ----------
    path : str or path-like
        The OBJ to write (atomically).
    points : (p, 3) float array
        The vertices.
    polylines : iterable of int sequences
        Each polyline as 0-based indices into ``points`` (a closed curve repeats its first index).
    comment : str
        The first line, after ``#``.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    OutputError
        The file cannot be written.
    """
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    lines = [f"# {comment}", *(f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in P)]
    lines += ["l " + " ".join(str(int(i) + 1) for i in poly) for poly in polylines]
    out = os.fspath(path)
    with atomic_write(out, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    return out


def write_polylines_obj(path: str | os.PathLike[str], polylines, *,
                        comment: str = "dhlb vortex filaments: one 'l' polyline per filament") -> str:
    """Write separate curves as OBJ polylines (closed ones repeat their first vertex at the end).

    Parameters
    ----------
    path : str or path-like
        The OBJ to write (atomically).
    polylines : list
        Curves: objects with ``.points`` (m, 3) and ``.closed`` (a :class:`~dhlb.vortex.Filament`),
        ``(points, closed)`` pairs, or ``(m, 3)`` arrays (open).
    comment : str
        The first line, after ``#``.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    OutputError
        The file cannot be written.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.vortex import Filament
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_polylines_obj(os.path.join(d, "f.obj"), [Filament(np.eye(3), True, None)])
    ...     print(open(p).read().splitlines()[-1])
    l 1 2 3 1
    """
    curves = curve_list(polylines, "polylines")
    points = np.concatenate([P for P, _ in curves]) if curves else np.zeros((0, 3))
    index, base = [], 0
    for P, closed in curves:
        index.append(list(range(base, base + len(P))) + ([base] if closed and len(P) else []))
        base += len(P)
    return write_lines_obj(path, points, index, comment=comment)


def write_polylines_ply(path: str | os.PathLike[str], polylines) -> str:
    """Write separate curves as an ASCII PLY with ``vertex`` (x, y, z, filament) and ``edge`` (vertex1, vertex2).

    Parameters
    ----------
    path : str or path-like
        The PLY to write (atomically).
    polylines : list
        As for :func:`write_polylines_obj`.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    OutputError
        The file cannot be written.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.vortex import Filament
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_polylines_ply(os.path.join(d, "f.ply"), [Filament(np.eye(3), False, None)])
    ...     print(open(p).read().splitlines()[-2:])
    ['0 1', '1 2']
    """
    verts, edges, base = [], [], 0
    for k, (P, closed) in enumerate(curve_list(polylines, "polylines")):
        m = P.shape[0]
        verts += [f"{x:.17g} {y:.17g} {z:.17g} {k}" for x, y, z in P]
        nxt = list(range(1, m)) + ([0] if closed and m > 2 else [])
        edges += [f"{base + i} {base + j}" for i, j in zip(range(m), nxt)]
        base += m
    header = ["ply", "format ascii 1.0", "comment dhlb vortex filaments (edges in filament order)",
              f"element vertex {len(verts)}", "property double x", "property double y", "property double z",
              "property int filament", f"element edge {len(edges)}", "property int vertex1", "property int vertex2",
              "end_header"]
    out = os.fspath(path)
    with atomic_write(out, "w", encoding="utf-8") as fh:
        fh.write("\n".join(header + verts + edges) + "\n")
    return out


# OBJ statements the readers here skip (texture, normals, grouping, materials, free-form geometry, display
# attributes); any other statement is an error: the file is not an OBJ (or not a text file at all).
_OBJ_OTHER = frozenset(
    "vn vp p o g s mg usemtl mtllib usemap maplib lod bevel c_interp d_interp shadow_obj trace_obj ctech stech "
    "cstype deg bmat step curv curv2 surf parm trim hole scrv sp end con".split()
)


def _vertex_record(toks, line: int, path: str, rows: list, lines: list) -> None:
    """Keep the coordinates of an OBJ ``v`` record (and its line); fewer than 3 is an error naming the line."""
    if len(toks) < 4:
        raise MeshParseError(f"a vertex needs 3 coordinates, got {len(toks) - 1}", path, line)
    rows.append(toks[1:4])
    lines.append(line)


def _obj_text(path: str) -> str:
    """The text of an OBJ, undecodable bytes as U+FFFD; a NUL byte (a binary file) is an error naming its line."""
    from dhlb.io._text import read_text

    text = read_text(path)
    nul = text.find("\x00")
    if nul >= 0:
        raise MeshParseError("binary data (a NUL byte): not a text OBJ file", path, text.count("\n", 0, nul) + 1)
    return text


def _unknown_statement(key: str, path: str, line: int):
    if "\ufffd" in key or not key.isprintable():
        raise MeshParseError("bytes that are not UTF-8 text: not a text OBJ file", path, line)
    raise MeshParseError(f"unknown OBJ statement {key!r}; is this an OBJ file?", path, line)


def _obj_indices(tokens, lines, seen, total: int, path: str, what: str, plural: str) -> np.ndarray:
    """0-based indices of OBJ index tokens (1-based, or negative: relative to the ``seen`` so far), checked."""
    from dhlb.io._text import to_flat_int

    sizes = np.array([len(t) for t in tokens], np.int64)
    flat = to_flat_int(tokens, lines, path, f"{what} index")
    line = np.repeat(np.asarray(lines, np.int64), sizes)
    before = np.repeat(np.asarray(seen, np.int64), sizes)
    bad = np.flatnonzero((flat == 0) | ((flat < 0) & (-flat > before)) | (flat > total))
    if bad.size:
        i = int(bad[0])
        v = int(flat[i])
        if v == 0:
            msg = f"{what} index 0 is invalid: OBJ numbers {plural} from 1"
        elif v < 0:
            msg = f"relative {what} index {v} points before the first {what} (only {int(before[i])} so far)"
        else:
            msg = f"refers to {what} {v} but the file has only {total} {plural} (numbered from 1)"
        raise MeshParseError(msg, path, int(line[i]))
    return np.where(flat < 0, flat + before, flat - 1)


def read_uv_obj(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""``(V, F, U)`` of an OBJ with one texture coordinate per face corner (``U`` (m, 3): the ``u`` of ``vt``).

    Parameters
    ----------
    path : str or path-like
        A triangle OBJ whose faces name texture coordinates (``f a/ta b/tb c/tc``; 1-based or negative
        relative indices).

    Returns
    -------
    V : (n, 3) float array
    F : (m, 3) int array
    U : (m, 3) float array
        The first texture coordinate of each face corner.

    Raises
    ------
    MeshParseError
        A binary file, an unknown statement, a record that cannot be read, a face that is not a triangle
        with texture coordinates, an index 0 or past the vertices or texture coordinates, a face that
        repeats a vertex, or no faces; the message names the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "s.obj")
    ...     _ = open(p, "w").write("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0.5 0\nvt 0.25 0\nf 1/1 2/2 3/3\n")
    ...     V, F, U = read_uv_obj(p)
    >>> F.tolist(), U.tolist()
    ([[0, 1, 2]], [[0.0, 0.5, 0.25]])
    """
    from dhlb.io._text import check_cells, check_finite, content_lines, to_array

    path = os.fspath(path)
    vrows, vlines, trows, tlines = [], [], [], []
    fv, ft, flines, seen_v, seen_t = [], [], [], [], []
    for line, toks in content_lines(_obj_text(path)):
        key = toks[0]
        if key == "v":
            _vertex_record(toks, line, path, vrows, vlines)
        elif key == "vt":
            if len(toks) < 2:
                raise MeshParseError("a texture coordinate 'vt' needs a value", path, line)
            trows.append(toks[1:2])
            tlines.append(line)
        elif key == "f":
            corners = [c.split("/") for c in toks[1:]]
            if len(corners) != 3 or any(len(c) < 2 or not c[0] or not c[1] for c in corners):
                raise MeshParseError(f"expected a triangle 'f a/ta b/tb c/tc' (a texture coordinate at each corner), "
                                     f"got {' '.join(toks)!r}", path, line)
            fv.append([c[0] for c in corners])
            ft.append([c[1] for c in corners])
            flines.append(line)
            seen_v.append(len(vrows))
            seen_t.append(len(trows))
        elif key not in _OBJ_OTHER and key != "l":
            _unknown_statement(key, path, line)
    if not fv:
        raise MeshParseError("no faces ('f a/ta b/tb c/tc' lines): not the OBJ of a stripe pattern", path)
    V = to_array(vrows, vlines, np.float64, path, "vertex coordinate").reshape(-1, 3)
    check_finite(V, path, vlines, first_number=1)
    U = to_array(trows, tlines, np.float64, path, "texture coordinate").reshape(-1)
    bad = np.flatnonzero(~np.isfinite(U))
    if bad.size:
        raise MeshParseError(f"texture coordinate {int(bad[0]) + 1} is not finite ({float(U[bad[0]])!r})", path,
                             tlines[int(bad[0])])
    F = _obj_indices(fv, flines, seen_v, len(V), path, "vertex", "vertices").reshape(-1, 3)
    T = _obj_indices(ft, flines, seen_t, len(U), path, "texture coordinate", "texture coordinates").reshape(-1, 3)
    check_cells(F, len(V), path, flines, first_number=1)
    return V, F, U[T]


def _parse_polylines_obj(path: str):
    """``(points, [0-based index arrays], line of each polyline, number of 'f' records)`` of an OBJ."""
    from dhlb.io._text import check_finite, content_lines, to_array

    vrows, vlines, L, llines, seen, n_faces = [], [], [], [], [], 0
    for line, toks in content_lines(_obj_text(path)):
        key = toks[0]
        if key == "v":
            _vertex_record(toks, line, path, vrows, vlines)
        elif key == "l":
            if len(toks) < 2:
                raise MeshParseError("a polyline 'l' needs at least one vertex index", path, line)
            idx = [t.split("/", 1)[0] for t in toks[1:]]
            if not all(idx):
                raise MeshParseError(f"cannot read the polyline {' '.join(toks)!r}", path, line)
            L.append(idx)
            llines.append(line)
            seen.append(len(vrows))
        elif key == "f":
            n_faces += 1
        elif key not in _OBJ_OTHER and key != "vt":
            _unknown_statement(key, path, line)
    X = to_array(vrows, vlines, np.float64, path, "vertex coordinate").reshape(-1, 3)
    check_finite(X, path, vlines, first_number=1)
    flat = _obj_indices(L, llines, seen, len(X), path, "vertex", "vertices") if L else np.zeros(0, np.int64)
    ends = np.cumsum([len(idx) for idx in L])[:-1]
    return X, np.split(flat, ends) if L else [], llines, n_faces


def read_polylines_obj(path: str | os.PathLike[str]) -> list[np.ndarray]:
    r"""The polylines (``l`` records) of an OBJ as a list of ``(m, 3)`` arrays.

    Parameters
    ----------
    path : str or path-like
        An OBJ with ``v`` and ``l`` records (faces, texture coordinates and the other OBJ statements
        are skipped; ``l`` indices are 1-based or negative, relative).

    Returns
    -------
    list of (m, 3) float arrays
        One per ``l`` record (a closed curve repeats its first point).

    Raises
    ------
    MeshParseError
        A binary file, an unknown statement, a record that cannot be read, or a polyline with no index,
        an index 0 or past the vertices; the message names the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "l.obj")
    ...     _ = open(p, "w").write("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3 1\n")
    ...     [c.shape for c in read_polylines_obj(p)]
    [(4, 3)]
    """
    X, L, _, _ = _parse_polylines_obj(os.fspath(path))
    return [X[idx] for idx in L]


def _ply_header(lines: list[str], path: str):
    """The elements ``[(name, count, [property names], line)]`` of an ASCII PLY header and the first body line."""
    if not lines or lines[0].strip() != "ply":
        raise MeshParseError("not a PLY file (the first line is not 'ply')", path, 1)
    elements, k = [], 1
    while k < len(lines) and lines[k].strip() != "end_header":
        parts = lines[k].split()
        if not parts or parts[0] in ("comment", "obj_info"):
            pass
        elif parts[0] == "format":
            if parts[1:2] != ["ascii"]:
                raise MeshParseError("a filament PLY of dhlb is ASCII", path, k + 1)
        elif parts[0] == "element":
            if len(parts) != 3 or not parts[2].isdigit():
                raise MeshParseError(f"expected 'element NAME COUNT', got {lines[k].strip()!r}", path, k + 1)
            elements.append((parts[1], int(parts[2]), [], k + 1))
        elif parts[0] == "property":
            if not elements or len(parts) != 3:
                raise MeshParseError(f"expected 'property TYPE NAME' after an element, got {lines[k].strip()!r}"
                                     + (" (list properties are not in a filament PLY)" if "list" in parts else ""),
                                     path, k + 1)
            elements[-1][2].append(parts[2])
        else:
            raise MeshParseError(f"unknown header line {lines[k].strip()[:40]!r}", path, k + 1)
        k += 1
    if k >= len(lines):
        raise MeshParseError("no 'end_header' line: the header is truncated", path)
    return elements, k + 1


def _ply_columns(rows, lines, props, wanted, path, element):
    from dhlb.io._text import to_array

    missing = [p for p in wanted if p not in props]
    if missing:
        raise MeshParseError(f"the element {element!r} has no property {', '.join(missing)} (it has "
                             f"{', '.join(props) or 'none'})", path)
    for toks, line in zip(rows, lines):
        if len(toks) != len(props):
            raise MeshParseError(f"a {element} needs {len(props)} values ({' '.join(props)}), got {len(toks)}",
                                 path, line)
    A = to_array(rows, lines, np.float64, path, f"{element} value").reshape(-1, len(props))
    return A[:, [props.index(p) for p in wanted]]


def read_polylines_ply(path: str | os.PathLike[str]) -> list[tuple[np.ndarray, bool]]:
    """The curves of a PLY of :func:`write_polylines_ply`: ``(points (m, 3), closed)`` per filament.

    Parameters
    ----------
    path : str or path-like
        An ASCII PLY with ``vertex`` (x, y, z, filament) and ``edge`` (vertex1, vertex2) elements.

    Returns
    -------
    list of (points, closed)
        One per filament number, in order; a curve is closed when an edge returns to its first point.

    Raises
    ------
    MeshParseError
        Not such a PLY (binary, other elements or properties), a truncated file or extra data, a value
        that cannot be read, a non-integer filament number, an edge index out of range, or edges that do
        not join the points of each filament in order; the message names the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_polylines_ply(os.path.join(d, "f.ply"), [(np.eye(3), True), (np.ones((2, 3)), False)])
    ...     [(P.shape, c) for P, c in read_polylines_ply(p)]
    [((3, 3), True), ((2, 3), False)]
    """
    from dhlb.io._text import check_finite, read_text

    path = os.fspath(path)
    lines = read_text(path).splitlines()
    elements, body = _ply_header(lines, path)
    if [e[0] for e in elements] != ["vertex", "edge"]:
        raise MeshParseError("expected the elements 'vertex' (x y z filament) and 'edge' (vertex1 vertex2) of dhlb's "
                             f"filament PLY, got {', '.join(e[0] for e in elements) or 'none'}", path)
    (_, nv, vprops, _), (_, ne, eprops, _) = elements
    data = [(k + 1, ln.split()) for k, ln in enumerate(lines[body:], body) if ln.strip()]
    if len(data) < nv + ne:
        raise MeshParseError(f"truncated: the header announces {nv} vertices and {ne} edges, the file holds "
                             f"{len(data)} lines of values", path)
    if len(data) > nv + ne:
        extra = len(data) - nv - ne
        raise MeshParseError(f"{extra} line{'s' if extra > 1 else ''} of values after the last of the {nv} vertices "
                             f"and {ne} edges the header announces", path, data[nv + ne][0])
    vl, vr = [d[0] for d in data[:nv]], [d[1] for d in data[:nv]]
    el, er = [d[0] for d in data[nv:]], [d[1] for d in data[nv:]]
    X = _ply_columns(vr, vl, vprops, ["x", "y", "z", "filament"], path, "vertex")
    check_finite(X[:, :3], path, vl)
    fil_f = X[:, 3]
    bad = np.flatnonzero(~np.isfinite(fil_f) | (fil_f < 0) | (fil_f != np.round(fil_f)))
    if bad.size:
        raise MeshParseError(f"the filament number {float(fil_f[bad[0]])!r} is not an integer >= 0", path, vl[bad[0]])
    fil = fil_f.astype(np.int64)
    E = _ply_columns(er, el, eprops, ["vertex1", "vertex2"], path, "edge")
    bad = np.flatnonzero(~np.all((E >= 0) & (E < nv) & (E == np.round(E)), axis=1))
    if bad.size:
        raise MeshParseError(f"edge ({' '.join(er[bad[0]])}) refers to a vertex outside 0 .. {nv - 1}", path,
                             el[bad[0]])
    E = E.astype(np.int64)
    return _filament_curves(X[:, :3], fil, E, el, vl, path)


def _filament_curves(X, fil, E, elines, vlines, path):
    """The curves of a filament PLY: the rows of each filament consecutive, its edges joining them in order."""
    out, first, last, size = [], {}, {}, {}
    for f in np.unique(fil):
        rows = np.flatnonzero(fil == f)
        if rows[-1] - rows[0] + 1 != rows.size:
            raise MeshParseError(f"the vertices of filament {int(f)} are not consecutive rows", path,
                                 vlines[int(rows[np.flatnonzero(np.diff(rows) > 1)[0] + 1])])
        first[int(f)], last[int(f)], size[int(f)] = int(rows[0]), int(rows[-1]), rows.size
    a, b = E[:, 0], E[:, 1]
    fa = fil[a]
    nxt = (b == a + 1) & (fil[b] == fa)
    close = np.array([last[int(f)] == i and first[int(f)] == j and size[int(f)] > 2 for f, i, j in zip(fa, a, b)],
                     bool)
    bad = np.flatnonzero(~(nxt | close))
    if bad.size:
        i = int(bad[0])
        raise MeshParseError(f"edge ({int(a[i])}, {int(b[i])}) does not join consecutive points of a filament", path,
                             elines[i])
    count = np.bincount(a[nxt], minlength=len(X))
    has_next = np.ones(len(X), bool)
    has_next[list(last.values())] = False
    bad = np.flatnonzero(count != has_next)
    if bad.size:
        v = int(bad[0])
        what = "twice" if count[v] > 1 else "missing"
        raise MeshParseError(f"the edge ({v}, {v + 1}) of filament {int(fil[v])} is {what}", path,
                             elines[int(np.flatnonzero(nxt & (a == v))[1])] if count[v] > 1 else None)
    closed = set(int(f) for f in fa[close])
    if close.sum() != len(closed):
        raise MeshParseError("a filament is closed twice (its closing edge repeats)", path)
    for f in sorted(first):
        out.append((X[first[f]:last[f] + 1], f in closed))
    return out


class LoadedVortex(Result):
    """Vortex filaments read back by :func:`read_vortex`: the curves, the domain when it is known, the summary.

    It draws as the :class:`~dhlb.vortex.VortexResult` that was written (:func:`dhlb.render.view.scene_of`,
    :func:`dhlb.render.registry.picture`, :meth:`show`).

    Parameters
    ----------
    filaments : list of Filament
        The curves (``.points``, ``.closed``; ``.faces`` is None).
    mesh : TetMesh or None
        The domain (``--box N`` or the mesh file named in the JSON), None when the files do not say.
    summary : dict
        The JSON written beside the curves (empty without one); :meth:`to_json` returns it.

    Attributes
    ----------
    linking_numbers : (c, c) int array
        From the summary (empty without one).
    eigenvalue : float
        From the summary (NaN without one).
    """

    def __init__(self, filaments: list, mesh, summary: dict):
        self.filaments, self.mesh, self.summary = filaments, mesh, summary
        self.linking_numbers = np.asarray(summary.get("linking_numbers", []), np.int64)
        eigenvalue = summary.get("eigenvalue")
        self.eigenvalue = float(np.nan if eigenvalue is None else eigenvalue)

    def to_json(self) -> dict:
        """The summary the filaments were read with (or the filaments alone).

        Returns
        -------
        dict
        """
        return dict(self.summary) or {"filaments": [{"points": f.points.tolist(), "closed": bool(f.closed)}
                                                    for f in self.filaments]}

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs.

        Returns
        -------
        list of (str, object)
        """
        closed = sum(bool(f.closed) for f in self.filaments)
        return [("filaments", f"{len(self.filaments)} ({closed} closed, {len(self.filaments) - closed} open)"),
                ("domain", "unknown" if self.mesh is None else f"{len(self.mesh.points)} vertices")]

    def __repr__(self) -> str:
        return f"LoadedVortex({len(self.filaments)} filaments, domain {'unknown' if self.mesh is None else 'known'})"


def _domain(name, folder: str, path: str | None = None):
    """The TetMesh a vortex JSON names (``"box N"`` of ``dhlb vortex --box N`` or a mesh file), or None.

    A name that does not make a mesh (``"box 0"``, a box too large, a mesh file that cannot be read) is
    a :class:`~dhlb.errors.MeshParseError` naming the JSON ``path`` and its field ``mesh``.
    """
    from dhlb.errors import DhlbError
    from dhlb.io.volume import named_tet_mesh

    try:
        return named_tet_mesh(name, folder)
    except DhlbError as exc:
        if path is None:
            raise
        raise MeshParseError(f"mesh = {name!r} names no usable domain ({exc})", path) from None


def _json_filaments(items, path: str) -> list[tuple[np.ndarray, bool]]:
    """The curves of the ``filaments`` of a vortex JSON, checked: ``[{"points": [[x, y, z], ...], "closed": bool}]``."""
    from dhlb.io._text import check_array, check_json_type

    check_json_type(items, list, path, "filaments")
    curves = []
    for k, f in enumerate(items):
        check_json_type(f, dict, path, f"filaments[{k}]")
        for key in ("points", "closed"):
            if key not in f:
                raise MeshParseError(f"filaments[{k}] has no {key!r}", path)
        P = check_array(f["points"], path, f"filaments[{k}].points", shape=(None, 3), finite=True,
                        dims="(m, 3): a list of [x, y, z]")
        closed = check_json_type(f["closed"], bool, path, f"filaments[{k}].closed")
        if len(P) < (3 if closed else 1):
            raise MeshParseError(f"filaments[{k}] has {len(P)} points, too few for a{' closed' if closed else 'n open'}"
                                 " filament", path)
        curves.append((P, closed))
    return curves


def _check_vortex_summary(summary: dict, path: str, n_curves: int) -> None:
    """The values of a vortex JSON that :class:`LoadedVortex` uses: linking numbers, eigenvalue, the domain's name."""
    from dhlb.io._text import check_array, check_json_type, check_number

    if "linking_numbers" in summary:
        c = n_curves
        L = check_array(summary["linking_numbers"], path, "linking_numbers", kind="i", shape=(c, c) if c else None,
                        dims=f"({c}, {c}): one row and column per filament")
        if not c and L.size:
            raise MeshParseError(f"linking_numbers has shape {L.shape}, but there are no filaments", path)
    if "eigenvalue" in summary:
        check_number(summary["eigenvalue"], path, "eigenvalue", finite=False, optional=True)
    if "mesh" in summary:
        check_json_type(summary["mesh"], (str, type(None)), path, "mesh")


def read_vortex(path: str | os.PathLike[str]) -> LoadedVortex:
    """Read back vortex filaments: ``OUT.json`` of ``dhlb vortex`` or :func:`dhlb.io.results.write`, else the curves.

    The JSON holds the filaments with their ``closed`` flags and names the domain (``"mesh"``: ``box N``
    or a mesh file, looked for as given and beside the JSON); without it, ``OUT.obj`` or ``OUT.ply``
    (the demo writes the OBJ only) give the curves and the domain is unknown.

    Parameters
    ----------
    path : str or path-like
        ``OUT.json``, ``OUT.obj``, ``OUT.ply`` or the output base ``OUT``.

    Returns
    -------
    LoadedVortex

    Raises
    ------
    MeshParseError
        No such file, or one that cannot be read: JSON filaments that are not lists of finite ``[x, y, z]``
        with a boolean ``closed``, linking numbers that are not a square integer matrix of the filaments,
        a domain name that makes no mesh; an OBJ or PLY that :func:`read_polylines_obj` /
        :func:`read_polylines_ply` refuse, an OBJ of faces or with vertices but no polylines (truncated),
        or vertices on no polyline. The message names the file and the field or line.
    NonFiniteError
        A vertex of the OBJ or PLY has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.vortex import Filament
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = write_polylines_obj(os.path.join(d, "v.obj"), [Filament(np.eye(3), True, None)])
    ...     back = read_vortex(os.path.join(d, "v"))
    >>> len(back.filaments), back.filaments[0].closed, back.filaments[0].points.shape, back.mesh
    (1, True, (3, 3), None)
    """
    from dhlb.io._text import output_stem, read_json
    from dhlb.vortex.filaments import Filament

    base = output_stem(path)
    ext = os.path.splitext(os.fspath(path))[1].lower()
    side = base + ".json"
    summary = read_json(side) if os.path.isfile(side) else {}
    if "filaments" in summary:
        curves = _json_filaments(summary["filaments"], side)
    else:
        order = (ext,) if ext in (".obj", ".ply") else (".obj", ".ply")
        found = [base + e for e in order if os.path.isfile(base + e)]
        if not found:
            raise MeshParseError(f"no filaments: none of {', '.join(base + e for e in ('.json', '.obj', '.ply'))}",
                                 base)
        if found[0].lower().endswith(".ply"):
            curves = read_polylines_ply(found[0])
        else:
            curves = _obj_filaments(found[0])
    _check_vortex_summary(summary, side, len(curves))
    filaments = [Filament(P, closed, None) for P, closed in curves]
    domain = _domain(summary.get("mesh"), os.path.dirname(os.path.abspath(base)), side)
    return LoadedVortex(filaments, domain, summary)


def _obj_filaments(path: str) -> list[tuple[np.ndarray, bool]]:
    """The filaments of a vortex OBJ (a closed one repeats its first vertex), checked to be a whole filament OBJ."""
    X, L, _, n_faces = _parse_polylines_obj(path)
    if not L and n_faces:
        raise MeshParseError(f"holds {n_faces} faces and no polylines ('l' records): a surface mesh, not vortex "
                             "filaments", path)
    if not L and len(X):
        raise MeshParseError(f"holds {len(X)} vertices but no polylines ('l' records): the file is truncated, or "
                             "not vortex filaments", path)
    used = np.zeros(len(X), bool)
    for idx in L:
        used[idx] = True
    if not used.all():
        v = int(np.argmin(used))
        raise MeshParseError(f"vertex {v + 1} is on no polyline ('l' record): the file is truncated, or not vortex "
                             "filaments of dhlb", path)
    return [(X[idx[:-1]], True) if len(idx) > 2 and np.array_equal(X[idx[0]], X[idx[-1]]) else (X[idx], False)
            for idx in L]
