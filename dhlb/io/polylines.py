"""Polylines as files: OBJ ``l`` records and PLY edges (vortex filaments, stripe isolines), and OBJ with corner UVs.

One writer per format, for every kind of curve network: :func:`write_lines_obj` takes points and index
polylines (curves that share vertices, like the isolines of a stripe pattern, keep them shared);
:func:`write_polylines_obj` and :func:`write_polylines_ply` take separate curves (vortex filaments).
The readers are those of ``dhlb view``: :func:`read_polylines_obj` and :func:`read_uv_obj` (the
per-corner texture coordinates of a stripe pattern OBJ).

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
from dhlb.errors import MeshParseError

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

__all__ = ["read_polylines_obj", "read_uv_obj", "write_lines_obj", "write_polylines_obj", "write_polylines_ply"]


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


def read_uv_obj(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""``(V, F, U)`` of an OBJ with one texture coordinate per face corner (``U`` (m, 3): the ``u`` of ``vt``).

    Parameters
    ----------
    path : str or path-like
        A triangle OBJ whose faces name texture coordinates (``f a/ta b/tb c/tc``).

    Returns
    -------
    V : (n, 3) float array
    F : (m, 3) int array
    U : (m, 3) float array
        The first texture coordinate of each face corner.

    Raises
    ------
    MeshParseError
        A record cannot be read (names the line), or a face refers to a missing vertex or coordinate.

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
    V, vt, F, T = [], [], [], []
    with open(path, encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            parts = line.split()
            if not parts:
                continue
            try:
                if parts[0] == "v":
                    V.append([float(x) for x in parts[1:4]])
                elif parts[0] == "vt":
                    vt.append(float(parts[1]))
                elif parts[0] == "f":
                    corners = [c.split("/") for c in parts[1:]]
                    if len(corners) != 3 or any(len(c) < 2 or not c[1] for c in corners):
                        raise ValueError("expected a triangle 'f a/ta b/tb c/tc'")
                    F.append([int(c[0]) - 1 for c in corners])
                    T.append([int(c[1]) - 1 for c in corners])
            except (ValueError, IndexError) as exc:
                raise MeshParseError(f"cannot read {parts[0]!r} record ({exc})", path, lineno) from None
    V, F, T, vt = np.array(V, float).reshape(-1, 3), np.array(F, np.int64).reshape(-1, 3), \
        np.array(T, np.int64).reshape(-1, 3), np.array(vt, float)
    if F.size and (F.min() < 0 or F.max() >= len(V) or T.min() < 0 or T.max() >= len(vt)):
        raise MeshParseError("a face refers to a missing vertex or texture coordinate", path)
    return V, F, vt[T] if T.size else np.zeros((0, 3))


def read_polylines_obj(path: str | os.PathLike[str]) -> list[np.ndarray]:
    r"""The polylines (``l`` records) of an OBJ as a list of ``(m, 3)`` arrays.

    Parameters
    ----------
    path : str or path-like
        An OBJ with ``v`` and ``l`` records (other records are ignored).

    Returns
    -------
    list of (m, 3) float arrays
        One per ``l`` record (a closed curve repeats its first point).

    Raises
    ------
    MeshParseError
        A record cannot be read (names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "l.obj")
    ...     _ = open(p, "w").write("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3 1\n")
    ...     [c.shape for c in read_polylines_obj(p)]
    [(4, 3)]
    """
    V, L = [], []
    with open(path, encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            parts = line.split()
            try:
                if parts and parts[0] == "v":
                    V.append([float(x) for x in parts[1:4]])
                elif parts and parts[0] == "l":
                    L.append([int(i) - 1 for i in parts[1:]])
            except ValueError as exc:
                raise MeshParseError(f"cannot read {parts[0]!r} record ({exc})", path, lineno) from None
    X = np.array(V, float).reshape(-1, 3)
    return [X[np.array(idx)] for idx in L if idx and min(idx) >= 0 and max(idx) < len(X)]
