"""Results for ParaView and friends through `meshio <https://github.com/nschloe/meshio>`_ (extra ``dhlb[meshio]``).

Writers (every file is written to a temporary file in its folder and renamed when complete):

* :func:`write_vtu_surface` / :func:`write_vtu_volume`: a triangle or tetrahedral mesh with point
  and cell arrays as VTK XML ``.vtu`` (or any format meshio writes, chosen by the extension).
* :func:`write_vtp_curves`: polylines (vortex filaments, isolines) as VTK XML PolyData ``.vtp``
  (written by dhlb itself: meshio has no ``.vtp`` writer), or with any other extension as a mesh
  of ``line`` cells through meshio.

The layouts of the package's results (which arrays a field, a stripe pattern or a vortex result
carries into ParaView) are in :mod:`dhlb.io.paraview`.

Reader: :func:`read_with_meshio` returns ``(V, F)`` of the triangles of any file meshio reads
(``.vtu``, ``.msh``, ``.vtk``, ``.xdmf``, ``.stl``, ...); dhlb's own strict readers stay the
default for OBJ/OFF/PLY/Medit (line-precise errors).

Complex arrays (ψ, u) are written as two components ``(Re, Im)`` because VTK has no complex type;
booleans as ``uint8``. Without meshio every function raises an ``ImportError`` that names the
extra to install.

Examples
--------
>>> import os, tempfile, numpy as np
>>> from dhlb.io.meshio_bridge import read_with_meshio, write_vtu_surface
>>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]); F = np.array([[0, 1, 2], [1, 3, 2]])
>>> with tempfile.TemporaryDirectory() as d:
...     p = write_vtu_surface(os.path.join(d, "s.vtu"), V, F, point_data={"h": V[:, 0]}, cell_data={"k": [1, -1]})
...     V2, F2 = read_with_meshio(p)
>>> bool(np.array_equal(V2, V)), F2.tolist()
(True, [[0, 1, 2], [1, 3, 2]])
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb._coerce import as_points, curve_list
from dhlb._install import install_hint
from dhlb.errors import MeshParseError, NonFiniteError, OutputError, ShapeError
from dhlb.mesh.arrays import check_cells

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "MESHIO_EXTRA",
    "require_meshio",
    "write_vtu_surface",
    "write_vtu_volume",
    "write_vtp_curves",
    "read_with_meshio",
]

MESHIO_EXTRA = f"meshio is not installed: {install_hint('meshio', 'meshio')}"
"""The message of the ``ImportError`` raised when meshio is missing."""


def require_meshio():
    """The ``meshio`` module, or an ``ImportError`` naming the extra ``dhlb[meshio]``.

    Examples
    --------
    >>> require_meshio().__name__
    'meshio'
    """
    try:
        import meshio
    except ImportError:
        raise ImportError(MESHIO_EXTRA) from None
    return meshio


# ---------------------------------------------------------------------------- checks
def _cells(C, k, n_points, what, path) -> np.ndarray:
    A = np.asarray(C)
    if A.size == 0:
        A = A.reshape(0, k)
    if A.ndim != 2 or A.shape[1] != k:
        raise ShapeError(f"{path}: the {what} must have shape (m, {k}), got {A.shape}")
    if not np.issubdtype(A.dtype, np.integer):
        raise ShapeError(f"{path}: the {what} must be integer vertex rows, got dtype {A.dtype}")
    one = {"faces": "face", "tetrahedra": "tetrahedron"}[what]
    return check_cells(A, n_points, k, f"{path}: {one}", points="the points", error=ShapeError)


def _array(name, value, rows, kind, path) -> np.ndarray:
    """One data array as VTK takes it: real float/int, complex → (…, 2), bool → uint8."""
    A = np.asarray(value)
    if A.dtype == bool:
        A = A.astype(np.uint8)
    elif np.iscomplexobj(A):
        A = np.stack([A.real, A.imag], axis=-1).reshape(len(A), -1) if A.ndim else A
    elif not np.issubdtype(A.dtype, np.number):
        raise ShapeError(f"{path}: {kind} data {name!r} must be numeric, got dtype {A.dtype}")
    if A.ndim == 0 or A.shape[0] != rows:
        raise ShapeError(f"{path}: {kind} data {name!r} needs one row per {kind} ({rows}), got shape {A.shape}")
    if A.ndim > 2:
        A = A.reshape(rows, -1)
    return A


def _data(data, rows, kind, path) -> dict:
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise ShapeError(f"{path}: {kind} data must be a dict {{name: array}}, got {type(data).__name__}")
    return {str(k): _array(k, v, rows, kind, path) for k, v in data.items()}


# ---------------------------------------------------------------------------- writing
def _write_atomic(path, write) -> str:
    """Call ``write(tmp)`` on a temporary path beside ``path`` (:func:`dhlb.io.atomic.atomic_path`).

    meshio's own failures become :class:`~dhlb.errors.OutputError` too.
    """
    from dhlb.io.atomic import atomic_path

    out = os.fspath(path)
    with atomic_path(out) as tmp:
        try:
            write(tmp)
        except OSError:
            raise
        except (ValueError, KeyError, TypeError) as exc:  # meshio's WriteError is a plain Exception subclass
            raise OutputError(out, f"meshio cannot write it ({exc})") from None
        except Exception as exc:
            if type(exc).__module__.startswith("meshio"):
                raise OutputError(out, f"meshio cannot write it ({exc})") from None
            raise
    return out


def _field_data_xml(field_data) -> str:
    """``<FieldData>`` of a VTK XML file (meshio 5.3 reads it but its .vtu writer drops it)."""
    parts = ["<FieldData>"]
    for name, value in field_data.items():
        A = np.atleast_1d(np.asarray(value))
        if not (np.issubdtype(A.dtype, np.number) and not np.iscomplexobj(A)) or A.ndim != 1:
            raise ShapeError(f"field data {name!r} must be a real number or a 1D array of them, got {A!r}")
        isint = np.issubdtype(A.dtype, np.integer)
        text = " ".join(str(int(x)) if isint else f"{float(x):.17g}" for x in A)
        parts.append(f'<DataArray type="{"Int64" if isint else "Float64"}" Name="{name}" '
                     f'NumberOfTuples="{len(A)}" format="ascii">{text}</DataArray>')
    return "\n".join(parts + ["</FieldData>"])


def _write_mesh(path, P, cells, point_data, cell_data, field_data, binary) -> str:
    meshio = require_meshio()
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    field_data = dict(field_data or {})
    fd_xml = _field_data_xml(field_data) if field_data and ext == ".vtu" else None
    mesh = meshio.Mesh(P, cells, point_data=point_data, cell_data={k: [v] for k, v in cell_data.items()},
                       field_data={} if fd_xml else field_data)
    kwargs = {"binary": bool(binary)} if ext in (".vtu", ".vtk") else {}

    def write(tmp):
        meshio.write(tmp, mesh, **kwargs)
        if fd_xml:
            with open(tmp, encoding="utf-8") as fh:
                text = fh.read()
            with open(tmp, "w", encoding="utf-8") as fh:
                fh.write(text.replace("<UnstructuredGrid>", "<UnstructuredGrid>\n" + fd_xml, 1))

    return _write_atomic(path, write)


def write_vtu_surface(
    path: str | os.PathLike[str],
    V: ArrayLike,
    F: ArrayLike,
    *,
    point_data: Mapping[str, ArrayLike] | None = None,
    cell_data: Mapping[str, ArrayLike] | None = None,
    field_data: Mapping[str, ArrayLike] | None = None,
    binary: bool = True,
) -> str:
    """Write a triangle mesh with arrays as ``.vtu`` (or any format meshio writes, by the extension).

    Parameters
    ----------
    path : str or path-like
    V : (N, 3) float
    F : (m, 3) int
        0-based rows of ``V``.
    point_data, cell_data : dict {name: array}, optional
        One row per vertex / per face: scalars ``(N,)``, vectors ``(N, 3)``; complex arrays become
        ``(N, 2)`` (Re, Im), booleans ``uint8``.
    field_data : dict {name: array}, optional
        Whole-mesh numbers (1D real arrays; VTK ``FieldData``, read back as meshio ``field_data``).
    binary : bool
        Binary (zlib-compressed, exact) or ASCII VTK XML (meshio writes 12 significant digits).

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    ShapeError, NonFiniteError
        Bad arrays (named, with the file).
    OutputError
        The file cannot be written (the reason and the path).
    ImportError
        meshio is not installed (names the extra ``dhlb[meshio]``).

    Examples
    --------
    >>> import os, tempfile, meshio
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_vtu_surface(os.path.join(d, "t.vtu"), [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]],
    ...                           point_data={"z": [1j, 2, 3]})
    ...     m = meshio.read(p)
    >>> m.cells_dict["triangle"].tolist(), m.point_data["z"].tolist()
    ([[0, 1, 2]], [[0.0, 1.0], [2.0, 0.0], [3.0, 0.0]])
    """
    where = os.fspath(path)
    P = as_points(V, f"{where}: the points")
    T = _cells(F, 3, len(P), "faces", where)
    return _write_mesh(path, P, [("triangle", T)], _data(point_data, len(P), "point", where),
                       _data(cell_data, len(T), "cell", where), field_data, binary)


def write_vtu_volume(
    path: str | os.PathLike[str],
    P: ArrayLike,
    T: ArrayLike,
    *,
    point_data: Mapping[str, ArrayLike] | None = None,
    cell_data: Mapping[str, ArrayLike] | None = None,
    field_data: Mapping[str, ArrayLike] | None = None,
    binary: bool = True,
) -> str:
    """Write a tetrahedral mesh with arrays as ``.vtu`` (or any format meshio writes).

    Parameters
    ----------
    path : str or path-like
    P : (N, 3) float
    T : (m, 4) int
        0-based rows of ``P``.
    point_data, cell_data, field_data, binary :
        As in :func:`write_vtu_surface` (cell data: one row per tetrahedron).

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    ShapeError, NonFiniteError, OutputError, ImportError
        As in :func:`write_vtu_surface`.

    Examples
    --------
    >>> import os, tempfile, meshio
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(1)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_vtu_volume(os.path.join(d, "b.vtu"), mesh.points, mesh.tets, cell_data={"vol": mesh.volumes})
    ...     m = meshio.read(p)
    >>> m.cells_dict["tetra"].shape, round(float(m.cell_data["vol"][0].sum()), 12)
    ((6, 4), 1.0)
    """
    where = os.fspath(path)
    X = as_points(P, f"{where}: the points")
    C = _cells(T, 4, len(X), "tetrahedra", where)
    return _write_mesh(path, X, [("tetra", C)], _data(point_data, len(X), "point", where),
                       _data(cell_data, len(C), "cell", where), field_data, binary)


def _segments(curves):
    """Stacked points, (s, 2) segments and the curve of each point and segment."""
    pts, seg, pid, sid, base = [], [], [], [], 0
    for k, (X, closed) in enumerate(curves):
        m = len(X)
        nxt = np.arange(1, m + (1 if closed and m > 2 else 0)) % max(m, 1)
        seg.append(np.column_stack([base + np.arange(len(nxt)), base + nxt]))
        pts.append(X)
        pid.append(np.full(m, k, np.int64))
        sid.append(np.full(len(nxt), k, np.int64))
        base += m
    cat = lambda parts, shape: np.concatenate(parts) if parts else np.zeros(shape)  # noqa: E731
    return (cat(pts, (0, 3)), cat(seg, (0, 2)).astype(np.int64), cat(pid, (0,)).astype(np.int64),
            cat(sid, (0,)).astype(np.int64))


def _vtp_text(curves) -> str:
    """VTK XML PolyData: one polyline cell per curve (closed ones repeat their first point index)."""
    X = np.concatenate([c[0] for c in curves]) if curves else np.zeros((0, 3))
    conn, offsets, base = [], [], 0
    for P, closed in curves:
        idx = list(range(base, base + len(P))) + ([base] if closed and len(P) > 2 else [])
        conn += idx
        offsets.append(len(conn))
        base += len(P)
    root = ET.Element("VTKFile", type="PolyData", version="1.0", byte_order="LittleEndian",
                      header_type="UInt64")
    piece = ET.SubElement(ET.SubElement(root, "PolyData"), "Piece", NumberOfPoints=str(len(X)),
                          NumberOfVerts="0", NumberOfLines=str(len(curves)), NumberOfStrips="0",
                          NumberOfPolys="0")

    def array(parent, name, dtype, values, ncomp=1):
        el = ET.SubElement(parent, "DataArray", type=dtype, Name=name, NumberOfComponents=str(ncomp),
                           format="ascii")
        el.text = " ".join(f"{v:.17g}" if dtype.startswith("Float") else str(int(v)) for v in np.ravel(values))

    pd = ET.SubElement(piece, "PointData", Scalars="curve")
    array(pd, "curve", "Int64", np.concatenate([np.full(len(c[0]), k) for k, c in enumerate(curves)])
          if curves else [])
    cd = ET.SubElement(piece, "CellData", Scalars="curve")
    array(cd, "curve", "Int64", np.arange(len(curves)))
    array(cd, "closed", "UInt8", [int(c[1]) for c in curves])
    array(cd, "n_points", "Int64", [len(c[0]) for c in curves])
    array(ET.SubElement(piece, "Points"), "Points", "Float64", X, 3)
    lines = ET.SubElement(piece, "Lines")
    array(lines, "connectivity", "Int64", conn)
    array(lines, "offsets", "Int64", offsets)
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_vtp_curves(path: str | os.PathLike[str], curves: Sequence[Any], *, binary: bool = True) -> str:
    """Write polylines (vortex filaments, isolines) for ParaView.

    With the extension ``.vtp``: VTK XML PolyData (ASCII), one polyline cell per curve (a closed
    curve repeats its first point), cell arrays ``curve`` (number), ``closed`` (0/1), ``n_points``
    and the point array ``curve``. Any other extension (``.vtu``, ``.vtk``, ...): through meshio as
    ``line`` cells (one per segment) with the point and cell array ``curve`` and the cell array
    ``closed``.

    Parameters
    ----------
    path : str or path-like
    curves : sequence
        :class:`dhlb.vortex.Filament` objects (``.points``, ``.closed``), ``(points, closed)``
        pairs, or ``(m, 3)`` arrays (open curves).
    binary : bool
        For the meshio formats: binary or ASCII.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    ShapeError, NonFiniteError
        A curve is not an (m, 3) array of finite numbers (its number is named).
    OutputError, ImportError
        As in :func:`write_vtu_surface` (``.vtp`` needs no meshio).

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> import xml.etree.ElementTree as ET
    >>> ring = (np.array([[1.0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]]), True)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_vtp_curves(os.path.join(d, "f.vtp"), [ring, np.eye(3)])
    ...     piece = ET.parse(p).getroot().find("PolyData/Piece")
    >>> piece.get("NumberOfPoints"), piece.get("NumberOfLines"), piece.find("Lines/DataArray").text.split()
    ('7', '2', ['0', '1', '2', '3', '0', '4', '5', '6'])
    """
    where = os.fspath(path)
    C = curve_list(curves, f"{where}: curves")
    if os.path.splitext(where)[1].lower() == ".vtp":
        text = _vtp_text(C)

        def write(tmp):
            with open(tmp, "w", encoding="utf-8") as fh:
                fh.write(text)

        return _write_atomic(where, write)
    X, S, pid, sid = _segments(C)
    closed = np.array([c[1] for c in C], dtype=np.uint8)[sid] if len(sid) else np.zeros(0, np.uint8)
    return _write_mesh(where, X, [("line", S)], {"curve": pid}, {"curve": sid, "closed": closed}, None, binary)


# ---------------------------------------------------------------------------- reading
def read_with_meshio(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)``: the triangles of any mesh file meshio reads (``.vtu``, ``.msh``, ``.vtk``, ``.stl``, ...).

    Vertex and line cells (e.g. Gmsh's physical points and curves) and, beside triangles, 3D cells
    (a mixed file's tetrahedra) are ignored; quads and other 2D cells are refused, as are files
    without triangles (a tetrahedral mesh: use :func:`dhlb.io.read_volume`). Unreferenced
    vertices are kept.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    V : (N, 3) float64
        2D points get ``z = 0``.
    F : (m, 3) int64
        0-based, in file order (all triangle blocks concatenated).

    Raises
    ------
    FileNotFoundError
        No such file.
    MeshParseError
        meshio cannot read the file (its message, with the path), or it holds no triangles or
        other surface cells than triangles.
    NonFiniteError
        A vertex has a NaN or infinite coordinate (the vertex is named).
    ImportError
        meshio is not installed (names the extra ``dhlb[meshio]``).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_vtu_surface(os.path.join(d, "t.vtu"), [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    ...     V, F = read_with_meshio(p)
    >>> V.shape, F.tolist()
    ((3, 3), [[0, 1, 2]])
    """
    meshio = require_meshio()
    where = os.fspath(path)
    if not os.path.exists(where):
        raise FileNotFoundError(2, "No such file or directory", where)
    if os.path.isdir(where):
        raise IsADirectoryError(21, "Is a directory", where)
    try:
        mesh = meshio.read(where)
    except (MemoryError, KeyboardInterrupt):
        raise
    except Exception as exc:  # meshio raises ReadError, ValueError, KeyError, struct.error ... on bad files
        raise MeshParseError(f"meshio cannot read it ({type(exc).__name__}: {exc})", where) from None
    X = np.asarray(mesh.points, dtype=np.float64)
    if X.ndim != 2 or X.shape[1] not in (2, 3):
        raise MeshParseError(f"the points have shape {X.shape}, expected (N, 2) or (N, 3)", where)
    if X.shape[1] == 2:
        X = np.column_stack([X, np.zeros(len(X))])
    bad = ~np.isfinite(X).all(axis=1)
    if np.any(bad):
        raise NonFiniteError(f"{where}: vertex {int(np.argmax(bad))} has a non-finite coordinate")
    tri, other = [], set()
    for block in mesh.cells:
        if block.type == "triangle":
            tri.append(np.asarray(block.data, dtype=np.int64).reshape(-1, 3))
        elif block.type not in ("vertex", "line", "line3"):
            other.add(block.type)
    if not tri:
        found = ", ".join(sorted({b.type for b in mesh.cells})) or "none"
        raise MeshParseError(f"no triangle cells (cell types: {found})", where,
                             found="volume" if other & {"tetra", "tetra10"} else None)
    surface_other = other - {"tetra", "tetra10", "hexahedron", "wedge", "pyramid"}
    if surface_other:
        raise MeshParseError(f"surface cells other than triangles ({', '.join(sorted(surface_other))}); "
                             "triangulate them first", where)
    F = np.concatenate(tri)
    if F.size and (F.min() < 0 or F.max() >= len(X)):
        r = int(np.argmax(((F < 0) | (F >= len(X))).any(axis=1)))
        raise MeshParseError(f"triangle {r} {F[r].tolist()} refers to a vertex outside 0 .. {len(X) - 1}", where)
    return X, F
