"""Tetrahedral (and general simplicial) meshes: dispatch over Medit, Gmsh and VTK files; conformal maps read back."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb._result import Result
from dhlb.errors import InvalidSimplexError, MeshParseError
from dhlb.io.formats import format_of
from dhlb.io.gmsh import read_gmsh, write_gmsh
from dhlb.io.medit import read_medit, write_medit
from dhlb.io.vtk import read_vtk, write_vtk

if TYPE_CHECKING:
    from collections.abc import Mapping
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["read_volume", "write_volume", "read_cells", "write_cells", "LoadedConformal", "read_conformal"]


def read_cells(path: str | os.PathLike[str], fmt: str | None = None) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """Read points and simplices by dimension from a ``.mesh``, ``.msh`` or ``.vtk`` file.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"`` (or the extension) instead of the extension of ``path``.

    Returns
    -------
    V : (n, 3) float64
    cells : dict {k: (m_k, k+1) int64}, 0-based, only the dimensions present in the file.

    Raises
    ------
    MeshParseError
        Unknown format or one that is not a volume format, or the errors of the reader
        (:func:`~dhlb.io.read_medit`, :func:`~dhlb.io.read_gmsh`, :func:`~dhlb.io.read_vtk`), which name the line.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_cells, example_path
    >>> V, cells = read_cells(example_path("solid-torus.mesh"))
    >>> {k: T.shape for k, T in cells.items()}
    {2: (256, 3), 3: (384, 4)}
    """
    fmt = format_of(path, fmt)
    if fmt == "mesh":
        return read_medit(path)
    if fmt == "msh":
        return read_gmsh(path)
    if fmt == "vtk":
        return read_vtk(path)
    if fmt in ("obj", "off", "ply"):
        raise MeshParseError(f"{fmt!r} files hold surfaces, not tetrahedra (volume formats: mesh, msh, vtk)",
                             os.fspath(path), found="surface")
    raise MeshParseError(f"{fmt!r} is not a volume format (use mesh, msh, vtk)", os.fspath(path))


def read_volume(path: str | os.PathLike[str], fmt: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a tetrahedral mesh from a ``.mesh`` (Medit), ``.msh`` (Gmsh) or ``.vtk`` (legacy) file.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"`` (or the extension) instead of the extension of ``path``.

    Returns
    -------
    V : (n, 3) float64
    T : (m, 4) int64, 0-based, in file order. Unreferenced vertices are kept
        (see :func:`dhlb.io.compact_mesh`); lower-dimensional cells in the file are ignored.

    Raises
    ------
    MeshParseError
        Unparsable file, unknown or non-volume format, or a file without tetrahedra.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.

    Examples
    --------
    >>> from dhlb.io import read_volume, example_path
    >>> V, T = read_volume(example_path("solid-torus.mesh"))
    >>> V.shape, T.shape
    ((144, 3), (384, 4))
    """
    V, cells = read_cells(path, fmt)
    if 3 not in cells or len(cells[3]) == 0:
        have = ", ".join(f"{len(c)} {k}-simplices" for k, c in sorted(cells.items())) or "no cells"
        raise MeshParseError(f"the file contains no tetrahedra ({have})", os.fspath(path),
                             found="surface" if 2 in cells and len(cells[2]) else None)
    return V, cells[3]


def write_cells(
    path: str | os.PathLike[str],
    V: ArrayLike,
    cells: ArrayLike | Mapping[int, ArrayLike],
    fmt: str | None = None,
    **kwargs: Any,
) -> None:
    """Write points and simplices to ``.mesh``, ``.msh`` or ``.vtk`` (format from the extension or ``fmt``).

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    cells : (m, k+1) int array or dict {k: (m_k, k+1) int array}
        0-based k-simplices (k = 1..3 for Medit, 0..3 for Gmsh and VTK).
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"``; default: from the extension of ``path``.
    **kwargs
        Passed to the writer (e.g. ``version="4.1"`` for :func:`~dhlb.io.write_gmsh`).

    Returns
    -------
    None
        The writers return nothing.

    Raises
    ------
    MeshParseError
        Unknown format, or one that is not a volume format.
    InvalidSimplexError
        A wrong shape, a dimension the format does not store, a non-integer cell array, or a cell index out of range.
    NonFiniteError
        A vertex has a NaN or infinite coordinate.
    OutputError
        The file cannot be written; nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_cells, write_cells
    >>> V = np.eye(3); cells = {1: np.array([[0, 1]]), 2: np.array([[0, 1, 2]])}
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_cells(os.path.join(d, "t.msh"), V, cells)
    ...     print(sorted(read_cells(os.path.join(d, "t.msh"))[1]))
    [1, 2]
    """
    fmt = format_of(path, fmt)
    if fmt == "mesh":
        return write_medit(path, V, cells, **kwargs)
    if fmt == "msh":
        return write_gmsh(path, V, cells, **kwargs)
    if fmt == "vtk":
        return write_vtk(path, V, cells, **kwargs)
    raise MeshParseError(f"cannot write cells as {fmt!r} (use mesh, msh, vtk)", os.fspath(path))


def write_volume(
    path: str | os.PathLike[str], V: ArrayLike, T: ArrayLike, fmt: str | None = None, **kwargs: Any
) -> None:
    """Write a tetrahedral mesh ``(V, T)`` to ``.mesh``, ``.msh`` or ``.vtk``.

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    V : (n, 3) float array
        Vertex positions.
    T : (m, 4) int array
        0-based tetrahedra.
    fmt : str, optional
        ``"mesh"``, ``"msh"`` or ``"vtk"``; default: from the extension of ``path``.
    **kwargs
        Passed to the writer, as in :func:`write_cells`.

    Raises
    ------
    InvalidSimplexError
        ``T`` is not an ``(m, 4)`` array, or as :func:`write_cells`.
    MeshParseError, NonFiniteError, OutputError
        As :func:`write_cells`.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import read_volume, write_volume
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]); T = np.array([[0, 1, 2, 3]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_volume(os.path.join(d, "t.vtk"), V, T)
    ...     print(read_volume(os.path.join(d, "t.vtk"))[1])
    [[0 1 2 3]]
    """
    T = np.asarray(T)
    if T.ndim != 2 or T.shape[1] != 4:
        raise InvalidSimplexError(f"tetrahedra need an (m, 4) array, got shape {T.shape}")
    write_cells(path, V, {3: T}, fmt, **kwargs)


class LoadedConformal(Result):
    """A close-to-conformal deformation read back by :func:`read_conformal`.

    It draws as the :class:`~dhlb.conformal.ConformalResult` that was written (:func:`dhlb.render.view.scene_of`,
    :func:`dhlb.render.registry.picture`, :meth:`show`).

    Parameters
    ----------
    points : (N, 3) float array
        The deformed vertices.
    mesh : TetMesh
        The input mesh (its points are the vertices before the map); when the files do not say what
        the input was (the ``.json`` of ``result.save``), the deformed mesh, and ``input_known`` is False.
    distortion : (m,) float array or None
        ``σ_max/σ_min`` per tet (None when neither the files hold it nor the input is known).
    summary : dict
        What the JSON or npz held besides the arrays (``eigenvalue``, ``statistics``, ...).
    input_known : bool
        The input points are known.
    """

    def __init__(self, points, mesh, distortion, summary: dict, input_known: bool = True):
        self.points, self.mesh, self.distortion = points, mesh, distortion
        self.summary, self.input_known = summary, bool(input_known)
        eigenvalue = summary.get("eigenvalue")
        self.eigenvalue = float(np.nan if eigenvalue is None else eigenvalue)

    def to_json(self) -> dict:
        """The summary, with the deformed points and the tets.

        Returns
        -------
        dict
        """
        return {**self.summary, "points": self.points.tolist(), "tets": self.mesh.tets.tolist()}

    def summary_rows(self) -> list[tuple[str, object]]:
        """The headline numbers, as ``(label, value)`` pairs.

        Returns
        -------
        list of (str, object)
        """
        d = "unknown" if self.distortion is None else f"{np.mean(self.distortion):.4g}, {np.max(self.distortion):.4g}"
        return [("vertices, tetrahedra", f"{len(self.points)}, {len(self.mesh.tets)}"),
                ("λ₁", f"{self.eigenvalue:.6g}"), ("distortion mean, max", d)]

    def __repr__(self) -> str:
        return f"LoadedConformal({len(self.points)} vertices, {len(self.mesh.tets)} tets, λ₁ = {self.eigenvalue:.4g})"


def named_tet_mesh(name, folder: str = ""):
    """The tet mesh a result's JSON names, or None.

    ``"box N"`` (``dhlb vortex --box N``), ``"ball N"`` (``dhlb conformal --ball N``) or a mesh file,
    looked for as given and in ``folder``.

    Parameters
    ----------
    name : str or None
        The name (``None`` or ``""``: no mesh).
    folder : str, optional
        The folder of the JSON.

    Returns
    -------
    TetMesh or None
        None when the name is no ``box N`` / ``ball N`` and no such file exists.

    Raises
    ------
    InvalidTypeError
        ``name`` is not a string.
    DhlbError
        The errors of :func:`~dhlb.mesh.box_tet_mesh`, :func:`~dhlb.mesh.ball_tet_mesh` (``N`` 0, or too
        large for the memory), :func:`read_volume` and :func:`~dhlb.mesh.check_tet_mesh`.
    """
    from dhlb.errors import InvalidTypeError
    from dhlb.mesh import ball_tet_mesh, box_tet_mesh, check_tet_mesh

    if name is not None and not isinstance(name, str):
        raise InvalidTypeError(f"a mesh name must be a string, got {type(name).__name__} {name!r}")
    name = name or ""
    kind, _, size = name.partition(" ")
    if kind in ("box", "ball") and size.isdigit():
        return box_tet_mesh(int(size), lower=-1.0, upper=1.0) if kind == "box" else ball_tet_mesh(int(size))
    for p in (name, os.path.join(folder, name)):
        if name and os.path.isfile(p):
            return check_tet_mesh(*read_volume(p))
    return None


def _input_mesh(name, folder: str, side: str):
    """The input mesh a ``dhlb conformal`` JSON names (None when it names none that is there), errors naming it."""
    from dhlb.errors import DhlbError
    from dhlb.io._text import check_json_type

    check_json_type(name, (str, type(None)), side, "mesh")
    try:
        return named_tet_mesh(name, folder)
    except DhlbError as exc:
        raise MeshParseError(f"mesh = {name!r} names no usable input mesh ({exc})", side) from None


def _conformal_arrays(data, path: str):
    """``(points, tets, input points or None, distortion or None)`` of an npz or JSON, every array checked."""
    from dhlb.io._text import check_array

    P = check_array(data["points"], path, "points", shape=(None, 3), finite=True)
    N = len(P)
    T = check_array(data["tets"], path, "tets", kind="i", shape=(None, 4), bounds=(0, N - 1,
                    f"rows of points, which has {N}"))
    M = len(T)
    before = distortion = None
    if data.get("input_points") is not None:
        before = check_array(data["input_points"], path, "input_points", shape=(N, 3), finite=True,
                             dims=f"({N}, 3): one per row of points")
    for key in ("phi", "u"):
        if data.get(key) is not None:
            a = check_array(data[key], path, key, finite=True)
            if a.ndim not in (1, 2) or a.shape[0] != N:
                raise MeshParseError(f"{key} must have one row per row of points ({N}), got shape {a.shape}", path)
    for key in ("distortion", "scale_error"):
        if data.get(key) is None:
            continue
        a = check_array(data[key], path, key, shape=(M,), dims=f"({M},): one per row of tets")
        bad = np.flatnonzero(np.isnan(a) | ((a < 1.0 - 1e-9) if key == "distortion" else False))
        if bad.size:
            i = int(bad[0])
            need = "σ_max/σ_min, a number >= 1" if key == "distortion" else "a number"
            raise MeshParseError(f"{key}[{i}] = {float(a[i])!r} is not {need}", path)
        if key == "distortion":
            distortion = a
    return P, T, before, distortion


def _check_conformal_summary(summary: dict, side: str) -> None:
    """The values of a conformal JSON that are used (eigenvalue, statistics, timings), checked."""
    from dhlb.io._text import check_json_type, check_number

    if "eigenvalue" in summary:
        check_number(summary["eigenvalue"], side, "eigenvalue", finite=False, optional=True)
    for key in ("statistics", "timings"):
        if key in summary:
            check_json_type(summary[key], (dict, type(None)), side, key)


def _check_counts(summary: dict, side: str, P, T, source: str) -> None:
    """``statistics.n_vertices`` / ``n_tets`` of the JSON against the deformed mesh of ``source``."""
    from dhlb.io._text import check_number

    stats = summary.get("statistics") or {}
    for key, have, what in (("n_vertices", len(P), "vertices"), ("n_tets", len(T), "tetrahedra")):
        if key in stats and check_number(stats[key], side, f"statistics.{key}", integer=True, low=0) != have:
            raise MeshParseError(f"statistics.{key} = {stats[key]}, but {os.path.basename(source)} has {have} {what}: "
                                 "the files are of different runs", side)


def read_conformal(path: str | os.PathLike[str]) -> LoadedConformal:
    """Read back a conformal deformation: ``OUT.npz`` / ``OUT.json`` of ``result.save``, or ``dhlb conformal``'s files.

    ``dhlb conformal -o OUT.mesh`` writes the deformed tets (``OUT.mesh``, ``OUT.vtk``) and a summary
    ``OUT.json`` that names the input (``"mesh"``: ``ball N`` or the file, looked for as given and
    beside the JSON); the distortion per tet is recomputed from the input and the deformed points
    (:func:`dhlb.conformal.tet_distortion`). ``result.save("OUT.npz")`` holds everything;
    ``result.save("OUT.json")`` (:meth:`~dhlb.conformal.ConformalResult.to_json`) all but the input points.

    Every array is checked before it is used: the points finite, the tets ``(m, 4)`` indices of the
    points, the input points, ``phi``, ``u``, one distortion (``>= 1``) and scale error per tet; the
    counts of the summary must be those of the mesh, and a named input mesh must have the deformed
    mesh's vertices and tetrahedra.

    Parameters
    ----------
    path : str or path-like
        ``OUT.npz``, ``OUT.json``, ``OUT.mesh``, ``OUT.vtk``, ``OUT.msh`` or the output base ``OUT``.

    Returns
    -------
    LoadedConformal

    Raises
    ------
    MeshParseError
        No such file, or files that do not hold a deformation: an unreadable archive or JSON, pickled
        objects, a missing or wrongly shaped array, an index out of range, a non-finite value, values
        that do not fit together (3 distortions for 48 tets), or an input mesh that is not the one
        deformed; the message names the file and the field.
    NonFiniteError
        A vertex of a mesh file has a NaN or infinite coordinate (the message names the line).

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.conformal import conformal_deformation
    >>> from dhlb.mesh import box_tet_mesh
    >>> res = conformal_deformation(box_tet_mesh(2), None, 0.5)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = res.save(os.path.join(d, "c.npz"))
    ...     back = read_conformal(os.path.join(d, "c"))
    >>> bool(np.array_equal(back.points, res.points)), bool(np.array_equal(back.distortion, res.distortion))
    (True, True)
    """
    from dhlb.errors import DhlbError
    from dhlb.io._text import check_number, load_npz, output_stem, read_json
    from dhlb.mesh import check_tet_mesh

    base = output_stem(path)
    ext = os.path.splitext(os.fspath(path))[1].lower()
    folder = os.path.dirname(os.path.abspath(base))
    side = base + ".json"
    summary = read_json(side) if os.path.isfile(side) else {}
    _check_conformal_summary(summary, side)
    if ext in ("", ".npz", ".png") and os.path.isfile(base + ".npz"):
        source = base + ".npz"
        data = load_npz(source)
        missing = [k for k in ("points", "tets") if k not in data]
        if missing:
            raise MeshParseError(f"not a conformal deformation of dhlb: no {', '.join(missing)}", source)
        P, T, before, distortion = _conformal_arrays(data, source)
        if "eigenvalue" in data:
            summary = {**summary, "eigenvalue": check_number(data["eigenvalue"], source, "eigenvalue", finite=False)}
    elif "points" in summary and "tets" in summary:
        source = side
        P, T, before, distortion = _conformal_arrays(summary, side)
        summary = {k: v for k, v in summary.items() if k not in ("points", "tets", "phi", "u", "input_points")}
    else:
        order = (ext,) if ext in (".mesh", ".vtk", ".msh") else (".mesh", ".vtk", ".msh")
        found = [base + e for e in order if os.path.isfile(base + e)]
        if not found:
            raise MeshParseError("no deformed mesh: none of .npz, .json with points, .mesh, .vtk, .msh", base)
        source = found[0]
        P, T = read_volume(source)
        distortion = None
        named = _input_mesh(summary.get("mesh"), folder, side)
        before = None if named is None else named.points
        if named is not None and (named.points.shape != P.shape or not np.array_equal(named.tets, T)):
            raise MeshParseError(f"mesh = {summary.get('mesh')!r} is not the mesh deformed in "
                                 f"{os.path.basename(source)} ({len(named.points)} vertices and "
                                 f"{len(named.tets)} tetrahedra there, {len(P)} and {len(T)} here, or other "
                                 "tetrahedra)", side)
    _check_counts(summary, side, P, T, source)
    try:
        mesh = check_tet_mesh(P if before is None else before, T)  # rows of T keep their order
    except DhlbError as exc:
        what = "points and tets" if before is None else "input_points and tets"
        raise MeshParseError(f"the {what} are not a valid tetrahedral mesh ({exc})", source) from None
    if distortion is None and before is not None:
        from dhlb.conformal import tet_distortion

        sig = tet_distortion(mesh.points, mesh.tets, P)[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            distortion = np.where(sig[:, 2] > 0, sig[:, 0] / np.where(sig[:, 2] > 0, sig[:, 2], 1.0), np.inf)
    return LoadedConformal(P, mesh, None if distortion is None else np.asarray(distortion, float), summary,
                           input_known=before is not None)
