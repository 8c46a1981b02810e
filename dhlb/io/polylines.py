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
        Not such a PLY, or a value cannot be read (names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_polylines_ply(os.path.join(d, "f.ply"), [(np.eye(3), True), (np.ones((2, 3)), False)])
    ...     [(P.shape, c) for P, c in read_polylines_ply(p)]
    [((3, 3), True), ((2, 3), False)]
    """
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    counts, names, k = {}, [], 1
    if not lines or lines[0].strip() != "ply":
        raise MeshParseError("not a PLY file", os.fspath(path))
    while k < len(lines) and lines[k].strip() != "end_header":
        parts = lines[k].split()
        if parts[:1] == ["format"] and parts[1:2] != ["ascii"]:
            raise MeshParseError("a filament PLY of dhlb is ASCII", os.fspath(path), k + 1)
        if parts[:1] == ["element"] and len(parts) == 3:
            names.append(parts[1])
            counts[parts[1]] = int(parts[2])
        k += 1
    if names != ["vertex", "edge"]:
        raise MeshParseError("expected the elements 'vertex' (x y z filament) and 'edge' of dhlb's filament PLY",
                             os.fspath(path))
    nv, ne, body = counts["vertex"], counts["edge"], k + 1
    try:
        X = np.array([[float(t) for t in lines[body + i].split()[:4]] for i in range(nv)]).reshape(-1, 4)
        E = np.array([[int(t) for t in lines[body + nv + i].split()[:2]] for i in range(ne)], np.int64).reshape(-1, 2)
    except (ValueError, IndexError) as exc:
        raise MeshParseError(f"cannot read the vertices and edges ({exc})", os.fspath(path)) from None
    out = []
    fil = X[:, 3].astype(np.int64)
    for f in np.unique(fil):
        rows = np.flatnonzero(fil == f)
        closed = bool(np.any((E[:, 0] == rows[-1]) & (E[:, 1] == rows[0]))) and rows.size > 2
        out.append((X[rows, :3], closed))
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
        self.eigenvalue = float(summary.get("eigenvalue", np.nan))

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


def _domain(name, folder: str):
    """The TetMesh a vortex JSON names (``"box N"`` of ``dhlb vortex --box N`` or a mesh file), or None."""
    from dhlb.io.volume import named_tet_mesh

    return named_tet_mesh(name, folder)


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
        No such file, or one that cannot be read.

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
    summary = read_json(base + ".json") if os.path.isfile(base + ".json") else {}
    if "filaments" in summary:
        try:
            curves = [(np.asarray(f["points"], float).reshape(-1, 3), bool(f["closed"])) for f in summary["filaments"]]
        except (KeyError, TypeError, ValueError) as exc:
            raise MeshParseError(f"cannot read the filaments ({exc})", base + ".json") from None
    else:
        order = (ext,) if ext in (".obj", ".ply") else (".obj", ".ply")
        found = [base + e for e in order if os.path.isfile(base + e)]
        if not found:
            raise MeshParseError(f"no filaments: none of {', '.join(base + e for e in ('.json', '.obj', '.ply'))}",
                                 base)
        if found[0].lower().endswith(".ply"):
            curves = read_polylines_ply(found[0])
        else:
            curves = [(P[:-1], True) if len(P) > 2 and np.array_equal(P[0], P[-1]) else (P, False)
                      for P in read_polylines_obj(found[0])]
    filaments = [Filament(P, closed, None) for P, closed in curves]
    return LoadedVortex(filaments, _domain(summary.get("mesh"), os.path.dirname(os.path.abspath(base))), summary)
